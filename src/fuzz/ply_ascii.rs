//! ASCII PLY frames: the seeds as `write_ply_with` writes them, mutated as text, with element
//! counts far beyond what the file holds.

use super::mutate::{ply_element_count, text_any};
use super::{Harness, Input, Rng, Verdict, check_frame, seed_meshes, written};
use crate::io::{PlyEncoding, write_ply_with};
use std::path::Path;

pub(super) struct PlyAscii {
    seeds: Vec<Vec<u8>>,
}

impl PlyAscii {
    pub(super) fn new(dir: &Path) -> Result<Self, String> {
        let seeds = seed_meshes()
            .iter()
            .enumerate()
            .map(|(m, mesh)| {
                written(dir, &format!("seed_{m}.ply"), |p| {
                    write_ply_with(p, mesh, PlyEncoding::Ascii)
                })
            })
            .collect::<Result<_, _>>()?;
        Ok(Self { seeds })
    }
}

impl Harness for PlyAscii {
    fn generate(&self, rng: &mut Rng) -> Input {
        let mut bytes = rng.pick(&self.seeds).clone();
        for _ in 0..1 + rng.below(3) {
            if rng.chance(20) {
                ply_element_count(rng, &mut bytes);
            } else {
                let donor = rng.pick(&self.seeds);
                text_any(rng, &mut bytes, donor);
            }
        }
        Input::one("frame.ply", bytes)
    }

    fn check(&self, scratch: &Path) -> Result<Verdict, String> {
        check_frame(&scratch.join("frame.ply"))
    }
}
