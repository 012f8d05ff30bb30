#[path = "../tests/topology_support/mod.rs"]
mod topology_support;
use surftrack::mesh::Mesh;
use surftrack::topology::{TopologyOptions, constrain_topology};
use topology_support::*;

fn main() {
    let n: u64 = std::env::args().nth(1).unwrap().parse().unwrap();
    let mut again = 0;
    let mut kinds = std::collections::HashMap::new();
    for seed in 0..n {
        let c = case(seed);
        if c.mesh.triangles.is_empty() { continue; }
        let mut mesh = Mesh::from_indexed(&c.mesh).unwrap();
        constrain_topology(&mut mesh, &c.theta, &TopologyOptions::default()).unwrap();
        if mesh.face_count() == 0 { continue; }
        let r2 = constrain_topology(&mut mesh, &c.theta, &TopologyOptions::default()).unwrap();
        if r2.changed() {
            again += 1;
            *kinds.entry(format!("{:?}", c.kind)).or_insert(0) += 1;
            if again < 6 { println!("seed {seed} {:?}: second call {:?} seeds {} deleted {} abandoned {:?}", c.kind, r2.resampling, r2.seed_cells, r2.deleted, r2.abandoned); }
        }
    }
    println!("{again} of {n} changed on the second call {kinds:?}");
}
