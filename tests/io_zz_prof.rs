use std::time::Instant;
use surftrack::io::*;
#[test]
fn prof() {
    let dir = tempfile::tempdir().unwrap();
    let (rings, segments) = (400u32, 250u32);
    let mut positions = Vec::new();
    for i in 0..rings {
        let u = i as f32 / rings as f32 * std::f32::consts::TAU;
        for j in 0..segments {
            let v = j as f32 / segments as f32 * std::f32::consts::TAU;
            let r = 1.0 + 0.3 * v.cos();
            positions.push(glam::Vec3::new(r * u.cos(), r * u.sin(), 0.3 * v.sin()));
        }
    }
    let at = |i: u32, j: u32| (i % rings) * segments + (j % segments);
    let mut triangles = Vec::new();
    for i in 0..rings {
        for j in 0..segments {
            triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    let mesh = surftrack::mesh::IndexedMesh::new(positions, triangles);
    let p = dir.path().join("a.bobj.gz");
    write_bobj_gz(&p, &mesh).unwrap();
    let raw = ReadOptions {
        repair: false,
        ..Default::default()
    };
    for _ in 0..10 {
        let t = Instant::now();
        let f = read_frame_with(&p, &raw).unwrap();
        let a = t.elapsed();
        let t = Instant::now();
        let g = read_frame(&p).unwrap();
        let b = t.elapsed();
        println!("raw {a:?} repaired {b:?} {}", f.mesh == g.mesh);
    }
}
