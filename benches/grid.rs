//! Grid stages on a 100k-triangle metaball surface in a 128³ box (2.1 M corners), CPU and GPU in
//! one group each so the report shows the ratio. References measured on the project's 2-core
//! machine on such a mesh: inside/outside of all 2.1 M corners takes Open3D 0.20 s (2 threads) to
//! 0.40 s (1 thread); signed distance at the 0.27 M corners within 3 cells takes libigl 0.50 s,
//! Open3D 0.65 s, pysdf 0.83 s. Setup (mesh, snapping, pipeline compilation) stays outside the
//! timed closures; without a GPU adapter only the CPU is measured.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use surftrack::compute::{Backend, BackendChoice};
use surftrack::grid::{LatticeMesh, edge_faces, footprint, rasterize, signed_distance, sweep};

#[path = "support/metaballs.rs"]
mod metaballs;

use metaballs::{N, metaballs};

fn bench(c: &mut Criterion) {
    let gpu = match Backend::select(BackendChoice::Gpu) {
        Ok(backend) => Some(backend),
        Err(error) => {
            eprintln!("GPU variants skipped: {error}");
            None
        }
    };
    let (mesh, frame) = metaballs();
    let lattice = LatticeMesh::new(frame, &mesh).expect("benchmark mesh snaps");
    eprintln!(
        "metaballs: {} triangles, grid {N}³ cells, spacing {} ({:.2} mean edge lengths)",
        mesh.triangles.len(),
        frame.spacing(),
        frame.spacing() / mesh.mean_edge_length()
    );
    let mut backends = vec![("cpu", Backend::Cpu)];
    backends.extend(gpu.iter().map(|g| ("gpu", g.clone())));
    // Compiles every pipeline before timing.
    for (_, backend) in &backends {
        let crossings = rasterize(backend, &lattice).expect("rasterize");
        let windings = sweep(backend, &crossings).expect("sweep");
        let cells = footprint(&lattice, &crossings, &edge_faces(&lattice));
        signed_distance(backend, &lattice, &cells, &windings, 3.0).expect("distance");
    }

    let mut group = c.benchmark_group("grid_rasterize");
    group.sample_size(20);
    for (name, backend) in &backends {
        group.bench_function(*name, |b| {
            b.iter(|| rasterize(backend, black_box(&lattice)))
        });
    }
    group.bench_function("cpu_cells", |b| {
        b.iter(|| {
            let crossings = rasterize(&Backend::Cpu, &lattice).expect("rasterize");
            footprint(&lattice, &crossings, &edge_faces(&lattice))
        })
    });
    group.finish();

    // Inside/outside of every corner of the box: rasterize, sweep, and the winding of all 129³
    // corners written out densely (what the references produce).
    let mut group = c.benchmark_group("grid_inside_outside");
    group.sample_size(20);
    for (name, backend) in &backends {
        group.bench_function(*name, |b| {
            b.iter(|| {
                let crossings = rasterize(backend, black_box(&lattice)).expect("rasterize");
                let windings = sweep(backend, &crossings).expect("sweep");
                windings.fill_box([0; 3], [N + 1; 3])
            })
        });
    }
    group.finish();

    let crossings = rasterize(&Backend::Cpu, &lattice).expect("rasterize");
    let windings = sweep(&Backend::Cpu, &crossings).expect("sweep");
    let cells = footprint(&lattice, &crossings, &edge_faces(&lattice));
    let band = signed_distance(&Backend::Cpu, &lattice, &cells, &windings, 3.0).expect("band");
    eprintln!("narrow band: {} corners within 3 cells", band.len());
    let mut group = c.benchmark_group("grid_narrow_band");
    group.sample_size(10);
    for (name, backend) in &backends {
        group.bench_function(*name, |b| {
            b.iter(|| signed_distance(backend, black_box(&lattice), &cells, &windings, 3.0))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
