use surftrack::compute::Backend;
use surftrack::grid::GridFrame;
use surftrack::mesh::{IndexedMesh, Mesh};
use surftrack::project::{Bvh, closest_points};
use surftrack::synth::{Scene, SynthOptions, extract, plan};
use surftrack::topology::{Field, TopologyOptions, constrain_topology};
fn main() {
    let truths = plan(Scene::Merge, &SynthOptions { resolution: 256, frames: 200 }).unwrap();
    let merge = truths.iter().position(|t| t.components == 1).unwrap();
    let prev = extract(&truths[merge - 1]).unwrap();
    let t = extract(&truths[merge]).unwrap();
    let bvh = Bvh::build(&t).unwrap();
    let near = closest_points(&Backend::Cpu, &bvh, &prev.positions, f32::INFINITY).unwrap();
    let mut m: IndexedMesh = prev.clone();
    for (p, n) in m.positions.iter_mut().zip(&near) { *p = n.point; }
    m.validate().unwrap();
    let frame = GridFrame::for_mesh(&t, 1.0).unwrap();
    let theta = Field::signed_distance(&Backend::Cpu, frame, &m).unwrap();
    let mesh = Mesh::from_indexed(&m).unwrap();
    for _ in 0..6 {
        let mut mm = mesh.clone();
        let r = constrain_topology(&mut mm, &theta, &TopologyOptions::default()).unwrap();
        println!("total {:?} classify {:?} rebuild {:?} deleted {}", r.total, r.classify, r.rebuild, r.deleted);
    }
}
