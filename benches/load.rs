//! Loading one 100k-vertex frame with `read_frame` (parse + repair) in each format. The frames are
//! written once to a temporary directory before timing; the `raw` case skips repair, showing what
//! welding and the degenerate-face check cost.

use std::hint::black_box;
use std::path::PathBuf;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec3;
use surftrack::io::{
    ObjOptions, PlyEncoding, ReadOptions, read_frame, read_frame_with, write_bobj_gz, write_obj,
    write_ply_with,
};
use surftrack::mesh::IndexedMesh;

/// A closed torus of `rings × segments` vertices.
fn torus(rings: u32, segments: u32) -> IndexedMesh {
    let mut positions = Vec::with_capacity((rings * segments) as usize);
    for i in 0..rings {
        let u = i as f32 / rings as f32 * std::f32::consts::TAU;
        for j in 0..segments {
            let v = j as f32 / segments as f32 * std::f32::consts::TAU;
            let r = 1.0 + 0.3 * v.cos();
            positions.push(Vec3::new(r * u.cos(), r * u.sin(), 0.3 * v.sin()));
        }
    }
    let at = |i: u32, j: u32| (i % rings) * segments + (j % segments);
    let mut triangles = Vec::with_capacity((2 * rings * segments) as usize);
    for i in 0..rings {
        for j in 0..segments {
            triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    IndexedMesh::new(positions, triangles)
}

fn load(c: &mut Criterion) {
    let mesh = torus(400, 250);
    let dir = std::env::temp_dir().join(format!("surftrack_load_bench_{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temporary directory");
    let files: Vec<(&str, PathBuf)> = vec![
        ("obj", dir.join("frame.obj")),
        ("ply_binary", dir.join("frame.ply")),
        ("ply_ascii", dir.join("frame_ascii.ply")),
        ("bobj_gz", dir.join("frame.bobj.gz")),
    ];
    write_obj(&files[0].1, &mesh, &ObjOptions::default()).expect("write obj");
    write_ply_with(&files[1].1, &mesh, PlyEncoding::BinaryLittleEndian).expect("write ply");
    write_ply_with(&files[2].1, &mesh, PlyEncoding::Ascii).expect("write ascii ply");
    write_bobj_gz(&files[3].1, &mesh).expect("write bobj.gz");

    let mut group = c.benchmark_group("read_frame_100k");
    group.sample_size(10);
    group.throughput(Throughput::Elements(mesh.positions.len() as u64));
    for (name, path) in &files {
        group.bench_with_input(BenchmarkId::new("repaired", name), path, |b, path| {
            b.iter(|| black_box(read_frame(path).expect("read")));
        });
    }
    let raw = ReadOptions {
        repair: false,
        ..ReadOptions::default()
    };
    group.bench_with_input(
        BenchmarkId::new("raw", "ply_binary"),
        &files[1].1,
        |b, path| {
            b.iter(|| black_box(read_frame_with(path, &raw).expect("read")));
        },
    );
    group.finish();
    let _ = std::fs::remove_dir_all(&dir);
}

criterion_group!(benches, load);
criterion_main!(benches);
