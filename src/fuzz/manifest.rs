//! Batch manifests: lists of caches mutated as text, with paths that name no folder, climb out
//! of the root, repeat a line or take the report's name.

use super::mutate::{replace_token, text_any};
use super::{Harness, Input, Rng, Verdict};
use crate::batch::Manifest;
use std::path::Path;

const SEEDS: &[&str] = &[
    "# shots\n\nshotA/cache\n  /data/shotB/fluid_####.bobj.gz  \nshotC/cache/\nshotA-cache\n/data/my shot/frame_0001.ply\n",
    "cache\nx/cache\n../up/cache\n./a/./b\n",
    "/abs/frames_*.ply\nrel/frames_*.ply\n",
];

const PATHS: &[&str] = &[
    "..",
    "/",
    ".",
    "./",
    "a/../..",
    "#",
    "~",
    "C:\\x",
    "\\\\server\\share",
    "frame_####.ply",
    "*.obj",
    "batch.json",
    "a/batch.json",
    "é/ü",
    "a//b",
    "\u{0}",
    "shotA/cache",
    "....",
    "a/.",
    "-",
    "x/.obj",
    ".ply",
];

pub(super) struct ManifestHarness;

impl ManifestHarness {
    pub(super) fn new() -> Self {
        Self
    }
}

impl Harness for ManifestHarness {
    fn generate(&self, rng: &mut Rng) -> Input {
        let mut bytes = rng.pick(SEEDS).as_bytes().to_vec();
        for _ in 0..1 + rng.below(4) {
            if rng.chance(40) {
                let word = if rng.chance(10) {
                    "n".repeat(1 + rng.below(400))
                } else {
                    rng.pick(PATHS).to_string()
                };
                replace_token(rng, &mut bytes, &word);
            } else {
                let donor = rng.pick(SEEDS).as_bytes();
                text_any(rng, &mut bytes, donor);
            }
        }
        Input::one("caches.txt", bytes)
    }

    fn check(&self, scratch: &Path) -> Result<Verdict, String> {
        let Ok(manifest) = Manifest::read(&scratch.join("caches.txt")) else {
            return Ok(Verdict::Refused);
        };
        let names: Vec<&str> = manifest.caches.iter().map(|c| c.name.as_str()).collect();
        for (i, name) in names.iter().enumerate() {
            if name.is_empty()
                || name.trim_matches('.').is_empty()
                || *name == crate::batch::BATCH_FILE
                || !name
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-'))
            {
                return Err(format!("accepted the folder name {name:?}"));
            }
            if names[..i].contains(name) {
                return Err(format!("two caches share the folder {name:?}"));
            }
        }
        if manifest.caches.windows(2).any(|w| w[0].line >= w[1].line) {
            return Err("cache lines out of order".into());
        }
        Ok(Verdict::Accepted)
    }
}
