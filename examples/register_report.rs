//! Prints one registration's report, every Gauss-Newton iteration with its energies and sub-step
//! times, then the fine stage's rounds. With no argument or a number: frames 0 → 1 of `blobs` (1/32
//! of a turn apart, meshed independently) at that resolution (default 260 cells, about 100k
//! vertices; `104` gives about 16k). With two paths: that source frame onto that target frame.
//!
//! `cargo run --release --example register_report -- 104`
//! `cargo run --release --example register_report -- tracked/frames/frame_0001.ply in/f_0002.ply`

use std::path::Path;

use surftrack::compute::Backend;
use surftrack::io::read_frame;
use surftrack::mesh::Mesh;
use surftrack::register::{RegisterOptions, Target, register};
use surftrack::synth::{Scene, SynthOptions, extract, plan};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (source, target) = if let [source, target] = &args[..] {
        (
            read_frame(Path::new(source))?.mesh,
            read_frame(Path::new(target))?.mesh,
        )
    } else {
        let resolution = match args.first() {
            Some(arg) => arg.parse()?,
            None => 260,
        };
        let truths = plan(
            Scene::Blobs,
            &SynthOptions {
                resolution,
                frames: 32,
            },
        )?;
        (extract(&truths[0])?, extract(&truths[1])?)
    };
    let mut mesh = Mesh::from_indexed(&source)?;
    let report = register(
        &Backend::Cpu,
        &mut mesh,
        Target::Mesh(&target),
        &RegisterOptions::default(),
    )?;
    let c = &report.coarse;
    println!(
        "{} vertices, {} nodes, {} samples, {} unknowns; matrix {} nonzeros, factor {}",
        report.vertices, c.nodes, c.samples, c.unknowns, c.matrix_nonzeros, c.factor_nonzeros
    );
    println!(
        "bvh {:?}, setup {:?}, rigid {:?} ({} iterations)",
        report.bvh_time,
        report.setup_time,
        c.rigid_time,
        c.rigid_energies.len()
    );
    for stage in &c.stages {
        println!(
            "stage α_reg {:e}: start {:.4e}, converged {}",
            stage.alpha_reg, stage.energy_start, stage.converged
        );
        for it in &stage.iterations {
            let t = &it.times;
            println!(
                "  {:.4e} → {:.4e}  kept {} pruned {} cg {} fact {} retries {} λ {:.1e}  corr {:.1?} asm {:.1?} fact {:.1?} solve {:.1?} eval {:.1?}",
                it.energy_before,
                it.energy,
                it.kept,
                it.pruned,
                it.cg_iterations,
                it.factorizations,
                it.retries,
                it.damping,
                t.correspondence,
                t.assembly,
                t.factorization,
                t.solve,
                t.evaluation
            );
        }
    }
    for round in &report.fine.rounds {
        println!(
            "fine: kept {} pruned {} cg {} residual {:.2e} corr {:.1?} solve {:.1?}",
            round.kept,
            round.pruned,
            round.cg_iterations,
            round.residual,
            round.correspondence,
            round.solve
        );
    }
    println!(
        "coarse {:?}, fine {:?}, total {:?}",
        report.coarse_time, report.fine_time, report.total_time
    );
    Ok(())
}
