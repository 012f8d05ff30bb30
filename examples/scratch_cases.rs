#[path = "../tests/topology_scenes.rs"]
mod scenes;
fn main() {}
