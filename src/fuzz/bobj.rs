//! `.bobj.gz` frames: the decompressed payload mutated where its counts, coordinates and corners
//! lie, then compressed again; or the compressed stream itself cut, flipped or followed by
//! another member; or a small file that inflates to megabytes of zeros.

use super::mutate::{GARBAGE_F32, GARBAGE_U32, bytes_any, put};
use super::{Harness, Input, Rng, Verdict, check_frame, seed_meshes, written};
use crate::io::write_bobj_gz;
use flate2::Compression;
use flate2::read::MultiGzDecoder;
use flate2::write::GzEncoder;
use std::io::{Read, Write};
use std::path::Path;

struct Seed {
    compressed: Vec<u8>,
    payload: Vec<u8>,
    vertices: usize,
}

pub(super) struct Bobj {
    seeds: Vec<Seed>,
}

impl Bobj {
    pub(super) fn new(dir: &Path) -> Result<Self, String> {
        let mut seeds = Vec::new();
        for (m, mesh) in seed_meshes().iter().enumerate() {
            let compressed = written(dir, &format!("seed_{m}.bobj.gz"), |p| {
                write_bobj_gz(p, mesh)
            })?;
            let mut payload = Vec::new();
            MultiGzDecoder::new(compressed.as_slice())
                .read_to_end(&mut payload)
                .map_err(|e| e.to_string())?;
            seeds.push(Seed {
                compressed,
                payload,
                vertices: mesh.positions.len(),
            });
        }
        Ok(Self { seeds })
    }
}

fn gzip(payload: &[u8]) -> Vec<u8> {
    let mut encoder = GzEncoder::new(Vec::new(), Compression::fast());
    // Writing into a Vec cannot fail.
    let _ = encoder.write_all(payload);
    encoder.finish().unwrap_or_default()
}

impl Harness for Bobj {
    fn generate(&self, rng: &mut Rng) -> Input {
        let seed = rng.pick(&self.seeds);
        let bytes = match rng.below(100) {
            0 => {
                // Valid empty counts, then up to 8 MiB of zeros: about 8 KiB compressed.
                let mut payload = vec![0u8; 12];
                payload.resize(12 + rng.below(8 << 20), 0);
                gzip(&payload)
            }
            1..=20 => {
                let mut compressed = seed.compressed.clone();
                match rng.below(3) {
                    0 => compressed.extend_from_slice(&rng.pick(&self.seeds).compressed),
                    _ => bytes_any(rng, &mut compressed, &seed.compressed),
                }
                compressed
            }
            _ => {
                let mut payload = seed.payload.clone();
                let v = seed.vertices;
                let counts = [0, 4 + 12 * v, 8 + 24 * v];
                for _ in 0..1 + rng.below(3) {
                    match rng.below(5) {
                        0 => {
                            let at = *rng.pick(&counts);
                            let count = *rng.pick(&[
                                u32::MAX,
                                i32::MIN as u32,
                                i32::MAX as u32,
                                (v + 1) as u32,
                                1 << 28,
                                0,
                            ]);
                            put(&mut payload, at, &count.to_le_bytes());
                        }
                        1 => {
                            let at = 4 + 12 * rng.below(v) + 4 * rng.below(3);
                            put(&mut payload, at, &rng.pick(GARBAGE_F32).to_le_bytes());
                        }
                        2 => {
                            let at = counts[2] + 4 + 4 * rng.below(64);
                            put(&mut payload, at, &rng.pick(GARBAGE_U32).to_le_bytes());
                        }
                        _ => {
                            let donor = &rng.pick(&self.seeds).payload;
                            bytes_any(rng, &mut payload, donor);
                        }
                    }
                }
                gzip(&payload)
            }
        };
        Input::one("frame.bobj.gz", bytes)
    }

    fn check(&self, scratch: &Path) -> Result<Verdict, String> {
        check_frame(&scratch.join("frame.bobj.gz"))
    }
}
