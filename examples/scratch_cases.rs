#[path = "../tests/topology_cases.rs"]
mod cases;
fn main() {}
