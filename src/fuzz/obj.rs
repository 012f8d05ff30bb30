//! OBJ frames: the seeds as `write_obj` writes them (with and without colours and uvs), mutated
//! as text.

use super::mutate::text_any;
use super::{Harness, Input, Rng, Verdict, check_frame, seed_meshes, written};
use crate::io::{ObjOptions, write_obj};
use std::path::Path;

pub(super) struct Obj {
    seeds: Vec<Vec<u8>>,
}

impl Obj {
    pub(super) fn new(dir: &Path) -> Result<Self, String> {
        let mut seeds = Vec::new();
        for (m, mesh) in seed_meshes().iter().enumerate() {
            for (o, options) in [
                ObjOptions::default(),
                ObjOptions {
                    uv: true,
                    color: true,
                },
            ]
            .iter()
            .enumerate()
            {
                if o == 1 && mesh.attributes.is_empty() {
                    continue;
                }
                seeds.push(written(dir, &format!("seed_{m}_{o}.obj"), |p| {
                    write_obj(p, mesh, options)
                })?);
            }
        }
        Ok(Self { seeds })
    }
}

impl Harness for Obj {
    fn generate(&self, rng: &mut Rng) -> Input {
        let mut bytes = rng.pick(&self.seeds).clone();
        for _ in 0..1 + rng.below(3) {
            let donor = rng.pick(&self.seeds);
            text_any(rng, &mut bytes, donor);
        }
        Input::one("frame.obj", bytes)
    }

    fn check(&self, scratch: &Path) -> Result<Verdict, String> {
        check_frame(&scratch.join("frame.obj"))
    }
}
