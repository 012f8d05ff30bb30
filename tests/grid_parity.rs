//! The GPU kernels against their CPU twins on every frame of every synth scene (default settings):
//! crossings identical as sets (grid edge, triangle, direction; `t` within 1e-5 cell) and winding
//! runs (hence every corner's class and self-intersection flag) identical on every frame;
//! narrow-band distances within 1e-5 cell, on every frame too. On the CPU the same comparison runs
//! against a single thread on every fourth frame: the output must be bit-identical whatever the
//! thread count.

use surftrack::compute::Backend;
use surftrack::compute::parity::{ParityReport, ParityValue, Scalar, run_on_gpu};
use surftrack::grid::{
    GridCrossing, GridFrame, LatticeMesh, NarrowBand, WindingRun, Windings, edge_faces, footprint,
    rasterize, signed_distance, sweep,
};
use surftrack::mesh::IndexedMesh;
use surftrack::synth::{Scene, SynthOptions, extract, plan};

/// Half-width of the compared band, in cells.
const BAND: f32 = 3.0;

#[derive(Clone, Copy)]
struct Crossing(GridCrossing);

impl ParityValue for Crossing {
    const LANES: &'static [&'static str] = &["x", "y", "z", "triangle", "flags", "t"];
    fn lane(&self, k: usize) -> Scalar {
        let c = &self.0;
        match k {
            0..=2 => Scalar::I32(c.corner[k]),
            3 => Scalar::U32(c.triangle),
            4 => Scalar::U32(c.flags),
            _ => Scalar::F32(c.t),
        }
    }
}

#[derive(Clone, Copy)]
struct Run(WindingRun);

impl ParityValue for Run {
    const LANES: &'static [&'static str] = &["start", "winding"];
    fn lane(&self, k: usize) -> Scalar {
        Scalar::I32(if k == 0 { self.0.start } else { self.0.winding })
    }
}

/// Frames compared across thread counts: every fourth of each scene.
const THREADS_EVERY: usize = 4;

struct Outputs {
    crossings: Vec<Crossing>,
    lines: Vec<i32>,
    runs: Vec<Run>,
    windings: Windings,
    band: NarrowBand,
}

fn outputs(backend: &Backend, mesh: &IndexedMesh) -> Outputs {
    let frame = GridFrame::for_mesh(mesh, 1.0).unwrap();
    let lattice = LatticeMesh::new(frame, mesh).unwrap();
    let crossings = rasterize(backend, &lattice).unwrap();
    let windings = sweep(backend, &crossings).unwrap();
    let faces = edge_faces(&lattice);
    let cells = footprint(&lattice, &crossings, &faces);
    let band = signed_distance(backend, &lattice, &cells, &windings, BAND).unwrap();
    // As a set: ordered by grid edge and triangle, not by `t`.
    let mut sorted: Vec<GridCrossing> = crossings.all().to_vec();
    sorted.sort_by_key(|c| (c.axis(), c.corner[2], c.corner[1], c.corner[0], c.triangle));
    Outputs {
        crossings: sorted.into_iter().map(Crossing).collect(),
        lines: windings
            .index()
            .lines()
            .iter()
            .flat_map(|l| [l.axis as i32, l.at[0], l.at[1]])
            .collect(),
        runs: windings.runs().iter().copied().map(Run).collect(),
        windings,
        band,
    }
}

/// Compares `got` with `reference`, floats within `tolerance` cells (0: bit-identical).
fn compare(what: &str, got: &Outputs, reference: &Outputs, tolerance: f64, spacing: f32) {
    let names = ("backend", "reference");
    let c = ParityReport::compare(
        &format!("{what}: crossings"),
        (names.0, &got.crossings),
        (names.1, &reference.crossings),
    );
    if tolerance == 0.0 {
        c.assert_identical();
    } else {
        c.assert_max_abs_lt(tolerance);
    }
    ParityReport::compare(
        &format!("{what}: swept lines"),
        (names.0, &got.lines),
        (names.1, &reference.lines),
    )
    .assert_identical();
    ParityReport::compare(
        &format!("{what}: winding runs"),
        (names.0, &got.runs),
        (names.1, &reference.runs),
    )
    .assert_identical();
    assert!(got.windings.unbalanced_lines().is_empty(), "{what}");
    for x in &got.crossings {
        let corner = x.0.corner;
        let class = got.windings.corner(corner);
        assert!(class.consistent(), "{what}: corner {corner:?} {class:?}");
        assert_eq!(class, reference.windings.corner(corner), "{what}");
    }
    let (a, b) = (&got.band, &reference.band);
    assert!(!a.is_empty(), "{what}");
    let key = |c: &[i32; 3]| [c[2], c[1], c[0]];
    let (mut i, mut j) = (0, 0);
    let limit = f64::from(BAND) - tolerance.max(1e-6);
    let cells = |v: f32| f64::from(v) / f64::from(spacing);
    while i < a.len() || j < b.len() {
        let order = match (a.corners().get(i), b.corners().get(j)) {
            (Some(x), Some(y)) => key(x).cmp(&key(y)),
            (Some(_), None) => std::cmp::Ordering::Less,
            _ => std::cmp::Ordering::Greater,
        };
        match order {
            std::cmp::Ordering::Equal => {
                let d = (cells(a.values()[i]) - cells(b.values()[j])).abs();
                assert!(
                    if tolerance == 0.0 {
                        a.values()[i].to_bits() == b.values()[j].to_bits()
                    } else {
                        d < tolerance
                    },
                    "{what}: corner {:?}: {} vs {}",
                    a.corners()[i],
                    a.values()[i],
                    b.values()[j]
                );
                i += 1;
                j += 1;
            }
            std::cmp::Ordering::Less => {
                assert!(
                    cells(a.values()[i]).abs() > limit,
                    "{what}: only backend has {:?}",
                    a.corners()[i]
                );
                i += 1;
            }
            std::cmp::Ordering::Greater => {
                assert!(
                    cells(b.values()[j]).abs() > limit,
                    "{what}: only reference has {:?}",
                    b.corners()[j]
                );
                j += 1;
            }
        }
    }
}

/// Every frame of every scene on the GPU against the CPU.
#[test]
fn every_synth_frame_gpu() {
    run_on_gpu(|gpu| {
        for scene in Scene::ALL {
            for truth in plan(scene, &SynthOptions::default()).unwrap() {
                let mesh = extract(&truth).unwrap();
                let what = format!("{} frame {}", scene.name(), truth.index);
                let got = outputs(gpu, &mesh);
                let reference = outputs(&Backend::Cpu, &mesh);
                assert!(!got.crossings.is_empty(), "{what}");
                let spacing = GridFrame::for_mesh(&mesh, 1.0).unwrap().spacing();
                compare(&what, &got, &reference, 1e-5, spacing);
            }
        }
    });
}

/// Every fourth frame of every scene on the CPU against the CPU on one thread, bit for bit.
#[test]
fn thread_count_changes_nothing_cpu() {
    let single = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    for scene in Scene::ALL {
        for truth in plan(scene, &SynthOptions::default()).unwrap() {
            if truth.index % THREADS_EVERY != 0 {
                continue;
            }
            let mesh = extract(&truth).unwrap();
            let what = format!("{} frame {}", scene.name(), truth.index);
            let got = outputs(&Backend::Cpu, &mesh);
            let reference = single.install(|| outputs(&Backend::Cpu, &mesh));
            let spacing = GridFrame::for_mesh(&mesh, 1.0).unwrap().spacing();
            compare(&what, &got, &reference, 0.0, spacing);
        }
    }
}
