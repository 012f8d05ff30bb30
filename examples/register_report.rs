//! Prints one registration's report: frames 0 → 1 of `blobs` (1/32 of a turn apart, meshed
//! independently) at the resolution given (default 260 cells, about 100k vertices), every
//! Gauss-Newton iteration with its energies and sub-step times, then the fine stage's rounds.
//! `cargo run --release --example register_report -- 104` for about 16k vertices.

use surftrack::compute::Backend;
use surftrack::mesh::Mesh;
use surftrack::register::{RegisterOptions, register};
use surftrack::synth::{Scene, SynthOptions, extract, plan};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let resolution = match std::env::args().nth(1) {
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
    let source = extract(&truths[0])?;
    let target = extract(&truths[1])?;
    let mut mesh = Mesh::from_indexed(&source)?;
    let report = register(
        &Backend::Cpu,
        &mut mesh,
        &target,
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
                "  {:.4e} → {:.4e}  kept {} pruned {} cg {} fact {}  corr {:.1?} asm {:.1?} fact {:.1?} solve {:.1?} eval {:.1?}",
                it.energy_before,
                it.energy,
                it.kept,
                it.pruned,
                it.cg_iterations,
                it.factorizations,
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
