use surftrack::compute::Backend;
use surftrack::grid::GridFrame;
use surftrack::mesh::Mesh;
use surftrack::project::{Bvh, closest_points};
use surftrack::synth::{Scene, SynthOptions, generate};
use surftrack::topology::{Field, TopologyOptions, constrain_topology};
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let scene: Scene = args[1].parse().unwrap();
    let resolution: usize = args[2].parse().unwrap();
    let frames: usize = args[3].parse().unwrap();
    let opts = SynthOptions { resolution, frames };
    let all: Vec<_> = generate(scene, &opts).unwrap().map(|f| f.unwrap()).collect();
    eprintln!("generated");
    let frame = GridFrame::for_mesh(&all[0].mesh, 1.0).unwrap();
    println!("spacing {} vertices {}", frame.spacing(), all[0].mesh.positions.len());
    let first: usize = args.get(4).map_or(1, |a| a.parse().unwrap());
    let last: usize = args.get(5).map_or(frames, |a| a.parse().unwrap());
    for j in first..last {
        let t = &all[j].mesh;
        let base = all[j - 1].mesh.clone();
        let bvh = Bvh::build(t).unwrap();
        let near = closest_points(&Backend::Cpu, &bvh, &base.positions, f32::INFINITY).unwrap();
        let mut m = base.clone();
        for blend in [1.0f32, 0.99, 0.95, 0.9, 0.8] {
            m = base.clone();
            for (p, n) in m.positions.iter_mut().zip(&near) { *p += blend * (n.point - *p); }
            if m.validate().is_ok() { if blend < 1.0 { println!("blend {blend}"); } break; }
        }
        if m.validate().is_err() { println!("frame {j}: projected mesh degenerate, skipped"); continue; }
        let mut mesh = Mesh::from_indexed(&m).unwrap();
        let n0 = mesh.vertex_count();
        let clock = Instant::now();
        let phi_m = Field::signed_distance(&Backend::Cpu, frame, &m).unwrap();
        let t_phi_m = clock.elapsed();
        let r1 = constrain_topology(&mut mesh, &phi_m, &TopologyOptions::default()).unwrap();
        let clock = Instant::now();
        let phi_t = Field::signed_distance(&Backend::Cpu, frame, t).unwrap();
        let t_phi_t = clock.elapsed();
        let r2 = constrain_topology(&mut mesh, &phi_t, &TopologyOptions::default()).unwrap();
        let out = mesh.to_indexed();
        let topo = out.topology();
        println!("frame {j}: n {n0} self {:?} del {} | target {:?} del {} ({:.4}) cut {} patch {} region {} | comps {} (truth {}) genus {} | times phi {:?}/{:?} self {:?} (cls {:?}) target {:?} (cls {:?} rebuild {:?}) {:?}",
            r1.resampling, r1.deleted, r2.resampling, r2.deleted, r2.replaced_fraction(), r2.cut, r2.patch, r2.region_cells,
            topo.components.len(), all[j].truth.components, topo.total_genus(), t_phi_m, t_phi_t, r1.total, r1.classify, r2.total, r2.classify, r2.rebuild, r2.abandoned);
    }
}
