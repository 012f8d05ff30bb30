use surftrack::compute::Backend;
use surftrack::mesh::Mesh;
use surftrack::register::{RegisterOptions, register};
use surftrack::synth::{Scene, SynthOptions, extract, plan};

#[test]
#[ignore]
fn timing() {
    let res: usize = std::env::var("RES").ok().and_then(|v| v.parse().ok()).unwrap_or(104);
    let truths = plan(Scene::Blobs, &SynthOptions { resolution: res, frames: 32 }).unwrap();
    let (source, target) = (extract(&truths[0]).unwrap(), extract(&truths[1]).unwrap());
    let t = std::time::Instant::now();
    let g = surftrack::register::DeformationGraph::build(&source, &Default::default()).unwrap();
    println!("graph build {:?} nodes {}", t.elapsed(), g.node_count());
    let t = std::time::Instant::now();
    let _ = source.mean_edge_length();
    println!("mean edge {:?}", t.elapsed());
    if std::env::var("GRAPHONLY").is_ok() { return; }
    let mut mesh = Mesh::from_indexed(&source).unwrap();
    let mut options = RegisterOptions::default();
    if let Some(t) = std::env::var("TOL").ok().and_then(|v| v.parse().ok()) { options.coarse.cg_tolerance = t; }
    if std::env::var("EXACT").is_ok() { options.coarse.solver = surftrack::register::LinearSolver::Cholesky; }
    let r = register(&Backend::Cpu, &mut mesh, &target, &options).unwrap();
    println!("V {} nodes {} samples {} nnz {} Lnnz {}", r.vertices, r.coarse.nodes, r.coarse.samples, r.coarse.matrix_nonzeros, r.coarse.factor_nonzeros);
    for s in &r.coarse.stages {
        let it: Vec<String> = s.iterations.iter().map(|i| format!("{}f/{}cg", i.factorizations, i.cg_iterations)).collect();
        println!("  α {} iterations {} [{}]", s.alpha_reg, s.iterations.len(), it.join(" "));
    }
    println!("  times {:?}", r.coarse.times);
    for f in &r.fine.rounds { println!("  fine cg {} corr {:?} solve {:?}", f.cg_iterations, f.correspondence, f.solve); }
    println!("bvh {:?} setup {:?} (coarse setup {:?}) coarse {:?} fine {:?} total {:?}", r.bvh_time, r.setup_time, r.coarse.setup, r.coarse_time, r.fine_time, r.total_time);
}
