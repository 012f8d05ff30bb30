//! Fuzzing kept in the project: one harness per reader of outside data (the frame readers for OBJ,
//! ASCII PLY, binary PLY and `.bobj.gz`, the event-file reader, the resume state of a tracked
//! folder, the batch manifest), each feeding its reader structure-aware mutations of valid files
//! from a seeded generator, and checking that every input is either refused with an error or
//! accepted as something consistent.
//!
//! The same harnesses run with a small fixed budget inside `cargo test` (`tests/fuzz.rs`) and for
//! as long as wanted from `examples/fuzz.rs`, which saves every failing input for reproduction.
//! Stable Rust has no coverage-guided fuzzer, so the mutations are chosen by what each format
//! holds: counts that claim more than the file, non-finite and overflowing numbers, cuts at every
//! length, splices of one valid file into another.

mod bobj;
mod events;
mod manifest;
mod mutate;
mod obj;
mod ply_ascii;
mod ply_binary;
mod resume;
mod rng;

pub use rng::Rng;

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};
use thiserror::Error;

/// What a fuzz run reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    Obj,
    PlyAscii,
    PlyBinary,
    Bobj,
    Events,
    Resume,
    Manifest,
}

impl Target {
    pub const ALL: [Target; 7] = [
        Target::Obj,
        Target::PlyAscii,
        Target::PlyBinary,
        Target::Bobj,
        Target::Events,
        Target::Resume,
        Target::Manifest,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Target::Obj => "obj",
            Target::PlyAscii => "ply-ascii",
            Target::PlyBinary => "ply-binary",
            Target::Bobj => "bobj",
            Target::Events => "events",
            Target::Resume => "resume",
            Target::Manifest => "manifest",
        }
    }

    pub fn from_name(name: &str) -> Option<Target> {
        Target::ALL.into_iter().find(|t| t.name() == name)
    }
}

/// Why a fuzz run could not run (not a finding: findings are in the [`Report`]).
#[derive(Debug, Error)]
pub enum FuzzError {
    #[error("{}: {source}", path.display())]
    Scratch {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("cannot build the {target} seeds: {reason}")]
    Seeds {
        target: &'static str,
        reason: String,
    },
}

/// One generated input: files relative to the scratch folder, each with its bytes or `None` for
/// a file left out (the folder is emptied before each input).
#[derive(Debug, Clone, Default)]
pub struct Input {
    pub files: Vec<(String, Option<Vec<u8>>)>,
}

impl Input {
    fn one(name: &str, bytes: Vec<u8>) -> Self {
        Self {
            files: vec![(name.to_string(), Some(bytes))],
        }
    }
}

/// How the target took an input.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    Accepted,
    Refused,
}

/// One fuzz target: valid seeds, their mutations, and the check of what the reader made of one.
trait Harness {
    /// A mutated input: `rng` is the input's own generator.
    fn generate(&self, rng: &mut Rng) -> Input;
    /// Feeds the input (already written under `scratch`) to the reader. An accepted input that
    /// breaks an invariant is an `Err` naming it.
    fn check(&self, scratch: &Path) -> Result<Verdict, String>;
}

/// What to run.
#[derive(Debug, Clone)]
pub struct Options {
    pub inputs: u64,
    pub seed: u64,
    /// Where inputs are written for the reader (emptied of the previous input's files first).
    pub scratch: PathBuf,
    /// Where failing inputs are copied, one folder per input; none: not kept.
    pub saved: Option<PathBuf>,
}

/// One input that panicked or broke an invariant.
#[derive(Debug, Clone)]
pub struct Failure {
    pub index: u64,
    pub message: String,
    /// The folder holding its files, when failures are saved.
    pub saved: Option<PathBuf>,
}

/// What a fuzz run found.
#[derive(Debug, Clone)]
pub struct Report {
    pub target: Target,
    pub inputs: u64,
    pub accepted: u64,
    pub refused: u64,
    pub failures: Vec<Failure>,
    /// The slowest input and its time.
    pub slowest: (u64, Duration),
    pub over_one_second: u64,
    pub total: Duration,
}

/// Runs `options.inputs` inputs of `target`.
pub fn run(target: Target, options: &Options) -> Result<Report, FuzzError> {
    let scratch = |path: &Path| {
        let path = path.to_path_buf();
        move |source| FuzzError::Scratch { path, source }
    };
    let seeds_dir = options.scratch.join("seeds");
    let input_dir = options.scratch.join("input");
    std::fs::create_dir_all(&seeds_dir).map_err(scratch(&seeds_dir))?;
    let harness = harness(target, &seeds_dir)?;
    let mut report = Report {
        target,
        inputs: 0,
        accepted: 0,
        refused: 0,
        failures: Vec::new(),
        slowest: (0, Duration::ZERO),
        over_one_second: 0,
        total: Duration::ZERO,
    };
    let started = Instant::now();
    for index in 0..options.inputs {
        let input = harness.generate(&mut Rng::for_input(options.seed, index));
        reset(&input_dir).map_err(scratch(&input_dir))?;
        write(&input_dir, &input).map_err(scratch(&input_dir))?;
        let clock = Instant::now();
        let outcome = catch_unwind(AssertUnwindSafe(|| harness.check(&input_dir)));
        let time = clock.elapsed();
        report.inputs += 1;
        if time > report.slowest.1 {
            report.slowest = (index, time);
        }
        if time > Duration::from_secs(1) {
            report.over_one_second += 1;
        }
        let message = match outcome {
            Ok(Ok(Verdict::Accepted)) => {
                report.accepted += 1;
                continue;
            }
            Ok(Ok(Verdict::Refused)) => {
                report.refused += 1;
                continue;
            }
            Ok(Err(broken)) => broken,
            Err(panic) => format!("panic: {}", panic_message(&*panic)),
        };
        let saved = match &options.saved {
            Some(dir) => {
                let folder = dir.join(format!("{}-{}-{index}", target.name(), options.seed));
                reset(&folder).map_err(scratch(&folder))?;
                write(&folder, &input).map_err(scratch(&folder))?;
                Some(folder)
            }
            None => None,
        };
        report.failures.push(Failure {
            index,
            message,
            saved,
        });
    }
    report.total = started.elapsed();
    Ok(report)
}

fn harness(target: Target, seeds: &Path) -> Result<Box<dyn Harness>, FuzzError> {
    let failed = |reason: String| FuzzError::Seeds {
        target: target.name(),
        reason,
    };
    Ok(match target {
        Target::Obj => Box::new(obj::Obj::new(seeds).map_err(failed)?),
        Target::PlyAscii => Box::new(ply_ascii::PlyAscii::new(seeds).map_err(failed)?),
        Target::PlyBinary => Box::new(ply_binary::PlyBinary::new(seeds).map_err(failed)?),
        Target::Bobj => Box::new(bobj::Bobj::new(seeds).map_err(failed)?),
        Target::Events => Box::new(events::Events::new(seeds).map_err(failed)?),
        Target::Resume => Box::new(resume::Resume::new(seeds).map_err(failed)?),
        Target::Manifest => Box::new(manifest::ManifestHarness::new()),
    })
}

fn reset(dir: &Path) -> std::io::Result<()> {
    match std::fs::remove_dir_all(dir) {
        Ok(()) => {}
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
        Err(e) => return Err(e),
    }
    std::fs::create_dir_all(dir)
}

fn write(dir: &Path, input: &Input) -> std::io::Result<()> {
    for (name, bytes) in &input.files {
        let path = dir.join(name);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent)?;
        }
        if let Some(bytes) = bytes {
            std::fs::write(&path, bytes)?;
        }
    }
    Ok(())
}

fn panic_message(panic: &(dyn std::any::Any + Send)) -> String {
    panic
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| panic.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".to_string())
}

/// The invariants of a frame a reader accepted: indices in range, coordinates finite, one id and
/// one value per component for every vertex; validation copes with it.
fn check_frame(path: &Path) -> Result<Verdict, String> {
    let Ok(frame) = crate::io::read_frame(path) else {
        return Ok(Verdict::Refused);
    };
    let mesh = &frame.mesh;
    let n = mesh.positions.len();
    if mesh.triangles.iter().flatten().any(|&v| v as usize >= n) {
        return Err("accepted a triangle index out of range".into());
    }
    if mesh.positions.iter().any(|p| !p.is_finite()) {
        return Err("accepted a non-finite coordinate".into());
    }
    if mesh.ids.as_ref().is_some_and(|ids| ids.len() != n) {
        return Err("accepted a different number of ids and vertices".into());
    }
    if mesh
        .attributes
        .iter()
        .any(|a| a.values.len() != a.components * n)
    {
        return Err("accepted an attribute of the wrong length".into());
    }
    let _ = mesh.validate();
    Ok(Verdict::Accepted)
}

/// Seed files made by the project's own writers, read back as bytes.
fn written(
    dir: &Path,
    name: &str,
    write: impl FnOnce(&Path) -> Result<(), crate::io::IoError>,
) -> Result<Vec<u8>, String> {
    let path = dir.join(name);
    write(&path).map_err(|e| e.to_string())?;
    std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))
}

/// The meshes every frame reader's seeds are made of: a closed torus with ids, colours and uvs,
/// and a small sphere without attributes.
fn seed_meshes() -> Vec<crate::mesh::IndexedMesh> {
    use crate::mesh::{Attribute, IndexedMesh};
    let mut torus = IndexedMesh::torus(1.0, 0.4, 6, 4);
    let n = torus.positions.len();
    torus.ids = Some((0..n as u64).map(|i| 3 * i + 1).collect());
    torus.attributes.push(Attribute {
        name: "color".into(),
        components: 3,
        values: (0..3 * n).map(|k| k as f32 / (3 * n) as f32).collect(),
    });
    torus.attributes.push(Attribute {
        name: "uv".into(),
        components: 2,
        values: (0..2 * n).map(|k| k as f32 / (2 * n) as f32).collect(),
    });
    let sphere = IndexedMesh::icosphere(glam::Vec3::new(0.5, -0.25, 2.0), 0.75, 1);
    vec![torus, sphere]
}
