//! What the `propagate_*` and `eval_*` tests share: tracked sequences written by hand the way
//! `surftrack track` lays them out (docs/output_layout.md), from real mesh mutations and their
//! journal, with a deterministic generator.

#![allow(dead_code)]

use glam::Vec3;
use std::path::Path;
use std::process::{Command, Output, Stdio};
use surftrack::events::EventList;
use surftrack::events::file::encode;
use surftrack::io::write_ply;
use surftrack::mesh::{Attribute, IndexedMesh, Mesh};
use surftrack::propagate::{EVENTS_DIR, FRAMES_DIR, frame_name};

/// SplitMix64: a small deterministic generator, so failures reproduce exactly.
pub struct Rng(pub u64);

impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }

    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
}

/// Which mutations a generated transition may use.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ops {
    /// Edge splits, face splits and flips: nothing is removed.
    Refine,
    /// Splits, flips, collapses and merges.
    All,
}

/// Writes tracked frame `k` (with its persistent ids) into `dir/frames/`.
pub fn write_frame(dir: &Path, k: usize, mesh: &IndexedMesh) {
    std::fs::create_dir_all(dir.join(FRAMES_DIR)).unwrap();
    assert!(mesh.ids.is_some());
    write_ply(&dir.join(FRAMES_DIR).join(frame_name(k)), mesh).unwrap();
}

/// Writes the event list of transition `k − 1 → k` into `dir/events/`.
pub fn write_events(dir: &Path, k: usize, events: &EventList) {
    std::fs::create_dir_all(dir.join(EVENTS_DIR)).unwrap();
    std::fs::write(
        dir.join(EVENTS_DIR).join(format!("{k:04}.events")),
        encode(events),
    )
    .unwrap();
}

/// A sphere of 642 vertices with ids `0..n` and a `truth` channel holding each vertex's initial
/// position: mesh mutations interpolate it exactly as the event rules do.
pub fn start_mesh() -> IndexedMesh {
    let mut mesh = IndexedMesh::icosphere(Vec3::new(0.2, -0.1, 0.3), 1.0, 3);
    mesh.ids = Some((0..mesh.positions.len() as u64).collect());
    mesh.attributes.push(Attribute {
        name: "truth".to_string(),
        components: 3,
        values: mesh.positions.iter().flat_map(|p| p.to_array()).collect(),
    });
    mesh
}

/// Applies `count` random mutations of kind `ops`, moving the surface a little between them, and
/// returns how many vertices were created and removed.
pub fn mutate(mesh: &mut Mesh, rng: &mut Rng, ops: Ops, count: usize) -> (usize, usize) {
    let (mut created, mut removed) = (0, 0);
    let mut done = 0;
    while done < count {
        let edges: Vec<_> = mesh.edges().collect();
        let h = edges[rng.below(edges.len())];
        let choice = rng.below(if ops == Ops::All { 5 } else { 3 });
        let ok = match choice {
            0 => mesh.split_edge(h, 0.2 + 0.6 * rng.unit()).is_some(),
            1 => {
                let faces: Vec<_> = mesh.faces().collect();
                let f = faces[rng.below(faces.len())];
                let a = 0.2 + 0.3 * rng.unit();
                let b = 0.2 + 0.3 * rng.unit();
                mesh.split_face(f, [a, b, 1.0 - a - b]).is_some()
            }
            2 => mesh.flip(h).is_some(),
            3 => {
                let mid = (mesh.position(mesh.origin(h)) + mesh.position(mesh.target(h))) * 0.5;
                let ok = mesh.collapse(h, mid).is_some();
                if ok {
                    removed += 2;
                }
                ok
            }
            _ => {
                let ok = mesh.merge(h).is_some();
                if ok {
                    removed += 1;
                }
                ok
            }
        };
        if ok {
            done += 1;
            created += usize::from(choice != 2 && choice != 4);
        }
    }
    let shift = Vec3::new(0.01, -0.005, 0.002);
    let vertices: Vec<_> = mesh.vertices().collect();
    for v in vertices {
        let p = mesh.position(v);
        mesh.set_position(v, p + shift);
    }
    (created, removed)
}

/// Writes a tracked sequence of `frames` frames into `dir`: frame 0 is [`start_mesh`], each later
/// frame `ops_per_frame` random mutations of the previous one, with the journal as its event list.
/// Returns the frames in memory, each with the `truth` channel the mesh carried itself.
pub fn write_sequence(
    dir: &Path,
    frames: usize,
    ops: Ops,
    ops_per_frame: usize,
    seed: u64,
) -> Vec<IndexedMesh> {
    let mut rng = Rng(seed);
    let first = start_mesh();
    let mut mesh = Mesh::from_indexed(&first).unwrap();
    mesh.record_mutations();
    write_frame(dir, 0, &first);
    let mut out = vec![first];
    for k in 1..frames {
        mutate(&mut mesh, &mut rng, ops, ops_per_frame);
        let events = EventList::drain(&mut mesh);
        write_events(dir, k, &events);
        let indexed = mesh.to_indexed();
        indexed.validate().unwrap();
        write_frame(dir, k, &indexed);
        out.push(indexed);
    }
    out
}

/// The values of channel `name` of `mesh`, per vertex.
pub fn channel<'a>(mesh: &'a IndexedMesh, name: &str) -> (&'a Attribute, Vec<&'a [f32]>) {
    let a = mesh
        .attributes
        .iter()
        .find(|a| a.name == name)
        .unwrap_or_else(|| panic!("no channel {name}"));
    (a, a.values.chunks_exact(a.components).collect())
}

/// Runs the `surftrack` binary with `args` (no input on stdin).
pub fn surftrack(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_surftrack"))
        .args(args)
        .stdin(Stdio::null())
        .output()
        .expect("the surftrack binary runs")
}

/// The standard output of a run that must have succeeded; its output and errors when it did not.
pub fn ok(output: &Output) -> String {
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(
        output.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    stdout
}
