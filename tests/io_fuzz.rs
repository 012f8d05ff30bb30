//! Readers never panic: good files truncated at every length, with bytes flipped, or with text
//! mangled, give either an error or a mesh whose indices are in range and coordinates finite.

use flate2::Compression;
use flate2::write::GzEncoder;
use glam::Vec3;
use std::io::Write;
use std::path::Path;
use surftrack::io::{
    ObjOptions, PlyEncoding, read_frame, write_bobj_gz, write_obj, write_ply_with,
};
use surftrack::mesh::{Attribute, IndexedMesh};

/// A small closed torus with ids and a colour attribute.
fn torus() -> IndexedMesh {
    let (n, m) = (6u32, 4u32);
    let mut positions = Vec::new();
    for i in 0..n {
        for j in 0..m {
            let (u, v) = (
                std::f32::consts::TAU * i as f32 / n as f32,
                std::f32::consts::TAU * j as f32 / m as f32,
            );
            let r = 1.0 + 0.4 * v.cos();
            positions.push(Vec3::new(r * u.cos(), r * u.sin(), 0.4 * v.sin()));
        }
    }
    let at = |i: u32, j: u32| (i % n) * m + (j % m);
    let mut triangles = Vec::new();
    for i in 0..n {
        for j in 0..m {
            triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    let count = positions.len();
    let mut mesh = IndexedMesh::new(positions, triangles);
    mesh.ids = Some((0..count as u64).collect());
    mesh.attributes.push(Attribute {
        name: "color".into(),
        components: 3,
        values: (0..3 * count).map(|k| k as f32 / 300.0).collect(),
    });
    mesh
}

/// A fixed-seed generator, so every run tries the same inputs.
struct Lcg(u64);

impl Lcg {
    fn below(&mut self, n: usize) -> usize {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 33) % n as u64) as usize
    }
}

/// Reads `bytes` as a file named `name`; any outcome but a panic or an inconsistent mesh is fine.
fn survive(dir: &Path, name: &str, bytes: &[u8]) {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    if let Ok(frame) = read_frame(&path) {
        let mesh = &frame.mesh;
        let n = mesh.positions.len();
        assert!(
            mesh.triangles.iter().flatten().all(|&v| (v as usize) < n),
            "{name}"
        );
        assert!(mesh.positions.iter().all(|p| p.is_finite()), "{name}");
        assert!(mesh.ids.as_ref().is_none_or(|ids| ids.len() == n), "{name}");
        assert!(
            mesh.attributes
                .iter()
                .all(|a| a.values.len() == a.components * n),
            "{name}"
        );
        // Validation must cope with whatever a reader accepts.
        let _ = mesh.validate();
    }
}

fn good_files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mesh = torus();
    let mut files = Vec::new();
    let mut add = |name: &str, write: &dyn Fn(&Path)| {
        let path = dir.join(name);
        write(&path);
        files.push((name.to_string(), std::fs::read(&path).unwrap()));
    };
    add("good.obj", &|p| {
        write_obj(
            p,
            &mesh,
            &ObjOptions {
                uv: false,
                color: true,
            },
        )
        .unwrap()
    });
    add("good_ascii.ply", &|p| {
        write_ply_with(p, &mesh, PlyEncoding::Ascii).unwrap()
    });
    add("good_le.ply", &|p| {
        write_ply_with(p, &mesh, PlyEncoding::BinaryLittleEndian).unwrap()
    });
    add("good_be.ply", &|p| {
        write_ply_with(p, &mesh, PlyEncoding::BinaryBigEndian).unwrap()
    });
    add("good.bobj.gz", &|p| write_bobj_gz(p, &mesh).unwrap());
    files
}

fn gzip(bytes: &[u8]) -> Vec<u8> {
    let mut encoder = GzEncoder::new(Vec::new(), Compression::fast());
    encoder.write_all(bytes).unwrap();
    encoder.finish().unwrap()
}

#[test]
fn truncated_files_never_panic() {
    let dir = tempfile::tempdir().unwrap();
    for (name, bytes) in good_files(dir.path()) {
        let step = (bytes.len() / 300).max(1);
        for len in (0..bytes.len()).step_by(step) {
            survive(dir.path(), &format!("cut_{name}"), &bytes[..len]);
        }
        if name.ends_with(".gz") {
            let payload = flate2::read::GzDecoder::new(bytes.as_slice());
            let payload: Vec<u8> = std::io::Read::bytes(payload).map(Result::unwrap).collect();
            for len in (0..payload.len()).step_by(7) {
                survive(dir.path(), "cut_payload.bobj.gz", &gzip(&payload[..len]));
            }
        }
    }
}

#[test]
fn corrupted_files_never_panic() {
    let dir = tempfile::tempdir().unwrap();
    let mut rng = Lcg(7);
    let text_noise = b"0123456789-+.eE nainf/\n\r\t#vf";
    for (name, bytes) in good_files(dir.path()) {
        let is_text = name.ends_with(".obj") || name.contains("ascii");
        for _ in 0..300 {
            let mut corrupt = bytes.clone();
            for _ in 0..1 + rng.below(4) {
                let at = rng.below(corrupt.len());
                corrupt[at] = if is_text {
                    text_noise[rng.below(text_noise.len())]
                } else {
                    rng.below(256) as u8
                };
            }
            survive(dir.path(), &format!("flip_{name}"), &corrupt);
        }
        if name.ends_with(".gz") {
            let payload = flate2::read::GzDecoder::new(bytes.as_slice());
            let payload: Vec<u8> = std::io::Read::bytes(payload).map(Result::unwrap).collect();
            for _ in 0..300 {
                let mut corrupt = payload.clone();
                let at = rng.below(corrupt.len());
                corrupt[at] = rng.below(256) as u8;
                survive(dir.path(), "flip_payload.bobj.gz", &gzip(&corrupt));
            }
        }
    }
}
