//! Binary PLY frames, both byte orders: the header mutated as text (huge element counts among
//! the mutations), the body as binary data, with garbage counts written over the face lists'
//! count bytes and garbage floats over coordinates.

use super::mutate::{
    GARBAGE_F32, GARBAGE_U32, bytes_any, find, line_edit, ply_element_count, put, replace_token,
};
use super::{Harness, Input, Rng, Verdict, check_frame, seed_meshes, written};
use crate::io::{PlyEncoding, write_ply_with};
use std::path::Path;

/// A seed and where its parts are.
struct Seed {
    bytes: Vec<u8>,
    big_endian: bool,
    /// Offset of the body.
    body: usize,
    vertices: usize,
    /// Bytes per vertex record.
    vertex_size: usize,
}

pub(super) struct PlyBinary {
    seeds: Vec<Seed>,
}

impl PlyBinary {
    pub(super) fn new(dir: &Path) -> Result<Self, String> {
        let mut seeds = Vec::new();
        for (m, mesh) in seed_meshes().iter().enumerate() {
            for (e, encoding) in [
                PlyEncoding::BinaryLittleEndian,
                PlyEncoding::BinaryBigEndian,
            ]
            .into_iter()
            .enumerate()
            {
                let bytes = written(dir, &format!("seed_{m}_{e}.ply"), |p| {
                    write_ply_with(p, mesh, encoding)
                })?;
                let body = find(&bytes, b"end_header\n").ok_or("no end_header")? + 11;
                let header = String::from_utf8_lossy(&bytes[..body]).into_owned();
                seeds.push(Seed {
                    vertex_size: vertex_size(&header),
                    bytes,
                    big_endian: encoding == PlyEncoding::BinaryBigEndian,
                    body,
                    vertices: mesh.positions.len(),
                });
            }
        }
        Ok(Self { seeds })
    }
}

/// Bytes per record of the header's `vertex` element (its scalar properties).
fn vertex_size(header: &str) -> usize {
    let mut in_vertex = false;
    let mut size = 0;
    for line in header.lines() {
        let words: Vec<&str> = line.split_ascii_whitespace().collect();
        match words.as_slice() {
            ["element", name, _] => in_vertex = *name == "vertex",
            ["property", ty, _] if in_vertex => {
                size += match *ty {
                    "char" | "uchar" => 1,
                    "short" | "ushort" => 2,
                    "double" => 8,
                    _ => 4,
                }
            }
            _ => {}
        }
    }
    size
}

impl Harness for PlyBinary {
    fn generate(&self, rng: &mut Rng) -> Input {
        let seed = rng.pick(&self.seeds);
        let mut bytes = seed.bytes.clone();
        for _ in 0..1 + rng.below(3) {
            let faces = seed.body + seed.vertices * seed.vertex_size;
            let word = |value: u32| {
                if seed.big_endian {
                    value.to_be_bytes()
                } else {
                    value.to_le_bytes()
                }
            };
            match rng.below(7) {
                0 => ply_element_count(rng, &mut bytes),
                1 => {
                    let token = *rng.pick(super::mutate::GARBAGE_TOKENS);
                    let mut header = bytes[..seed.body.min(bytes.len())].to_vec();
                    if rng.chance(50) {
                        replace_token(rng, &mut header, token);
                    } else {
                        line_edit(rng, &mut header);
                    }
                    bytes.splice(..seed.body.min(bytes.len()), header);
                }
                2 => {
                    // A face's list count (one byte, then three 4-byte corners).
                    let face = rng.below(64);
                    let count = *rng.pick(&[0u8, 1, 2, 4, 200, 255]);
                    put(&mut bytes, faces + 13 * face, &[count]);
                }
                3 => {
                    let face = rng.below(64);
                    let corner = word(*rng.pick(GARBAGE_U32));
                    put(
                        &mut bytes,
                        faces + 13 * face + 1 + 4 * rng.below(3),
                        &corner,
                    );
                }
                4 => {
                    let vertex = rng.below(seed.vertices.max(1));
                    let value = word(rng.pick(GARBAGE_F32).to_bits());
                    let at = seed.body + vertex * seed.vertex_size + 4 * rng.below(3);
                    put(&mut bytes, at, &value);
                }
                _ => {
                    let donor = &rng.pick(&self.seeds).bytes;
                    bytes_any(rng, &mut bytes, donor);
                }
            }
        }
        Input::one("frame.ply", bytes)
    }

    fn check(&self, scratch: &Path) -> Result<Verdict, String> {
        check_frame(&scratch.join("frame.ply"))
    }
}
