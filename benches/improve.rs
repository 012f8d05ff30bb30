//! Mesh improvement of one raw marching-cubes frame of about 100k vertices (the `morph` scene's first
//! frame at resolution 176), against loading that same frame: improvement should cost no more than a
//! few loads. The improve group's throughput is in operations (splits + collapses + flips), so
//! criterion reports operations per second; the frame, its files and the half-edge mesh are built
//! outside the timed closures, and every timed improvement starts from a fresh copy of the raw mesh.
//! Building the half-edge mesh that improvement works on is timed with the loads, as the last step
//! of loading a frame for tracking.

use criterion::{BatchSize, BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;
use surftrack::improve::{ImproveParams, improve};
use surftrack::io::{ObjOptions, read_frame, write_bobj_gz, write_obj, write_ply};
use surftrack::mesh::{IndexedMesh, Mesh};
use surftrack::synth::{Scene, SynthOptions, extract, plan};

fn frame() -> IndexedMesh {
    let options = SynthOptions {
        resolution: 176,
        frames: 2,
    };
    extract(&plan(Scene::Morph, &options).expect("plan")[0]).expect("extract")
}

fn bench(c: &mut Criterion) {
    let input = frame();
    let params = ImproveParams::new(input.mean_edge_length());
    let mesh = Mesh::from_indexed(&input).expect("marching cubes output is valid");
    let mut once = mesh.clone();
    let report = improve(&mut once, &params).expect("improve");
    eprintln!(
        "frame: {} vertices, {} triangles; improvement: {} splits, {} collapses, {} flips in {} \
         rounds, refused checks {:?}",
        input.positions.len(),
        input.triangles.len(),
        report.splits,
        report.collapses,
        report.flips,
        report.rounds,
        report.refusals
    );

    let mut group = c.benchmark_group("improve_100k");
    group.sample_size(10);
    group.throughput(Throughput::Elements(report.operations() as u64));
    group.bench_function("improve", |b| {
        b.iter_batched(
            || mesh.clone(),
            |mut m| black_box(improve(&mut m, &params).expect("improve")),
            BatchSize::LargeInput,
        );
    });
    group.finish();

    let dir = std::env::temp_dir().join(format!("surftrack_improve_bench_{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temporary directory");
    let files = [
        ("obj", dir.join("frame.obj")),
        ("ply_binary", dir.join("frame.ply")),
        ("bobj_gz", dir.join("frame.bobj.gz")),
    ];
    write_obj(&files[0].1, &input, &ObjOptions::default()).expect("write obj");
    write_ply(&files[1].1, &input).expect("write ply");
    write_bobj_gz(&files[2].1, &input).expect("write bobj.gz");
    let mut group = c.benchmark_group("load_same_frame_100k");
    group.sample_size(10);
    group.throughput(Throughput::Elements(input.positions.len() as u64));
    for (name, path) in &files {
        group.bench_with_input(BenchmarkId::new("read_frame", name), path, |b, path| {
            b.iter(|| black_box(read_frame(path).expect("read")));
        });
    }
    group.bench_function("half_edge_mesh_from_indexed", |b| {
        b.iter(|| black_box(Mesh::from_indexed(&input).expect("valid")));
    });
    group.finish();
    std::fs::remove_dir_all(&dir).ok();
}

criterion_group!(benches, bench);
criterion_main!(benches);
