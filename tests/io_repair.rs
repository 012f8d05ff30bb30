//! Repairs on reading: welding relative to the mean edge length, dropping exactly-degenerate
//! faces, splitting parts that touch at a vertex or an edge, removing unreferenced vertices, and
//! leaving clean meshes alone.

use glam::Vec3;
use std::f32::consts::TAU;
use std::path::Path;
use surftrack::io::{ReadOptions, read_frame, read_frame_with, write_ply};
use surftrack::mesh::{Attribute, IndexedMesh};

/// A closed torus of `n × m` quads split into triangles.
fn torus(n: u32, m: u32) -> IndexedMesh {
    let mut positions = Vec::new();
    for i in 0..n {
        for j in 0..m {
            let (u, v) = (TAU * i as f32 / n as f32, TAU * j as f32 / m as f32);
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
    IndexedMesh::new(positions, triangles)
}

/// One vertex per triangle corner, each moved by `jitter(corner)`, carrying its corner number as
/// an id and attribute; as exporters write "triangle soup".
fn soup(mesh: &IndexedMesh, jitter: impl Fn(usize) -> Vec3) -> IndexedMesh {
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    for tri in &mesh.triangles {
        let base = positions.len() as u32;
        for &v in tri {
            positions.push(mesh.positions[v as usize] + jitter(positions.len()));
        }
        triangles.push([base, base + 1, base + 2]);
    }
    let n = positions.len();
    let mut soup = IndexedMesh::new(positions, triangles);
    soup.ids = Some((0..n as u64).collect());
    soup.attributes.push(Attribute {
        name: "corner".into(),
        components: 1,
        values: (0..n).map(|c| c as f32).collect(),
    });
    soup
}

fn scaled(mesh: &IndexedMesh, scale: f32) -> IndexedMesh {
    let mut mesh = mesh.clone();
    for p in &mut mesh.positions {
        *p *= scale;
    }
    mesh
}

/// `path` read as it is, without repairs.
fn read_unrepaired(path: &Path) -> surftrack::io::Frame {
    read_frame_with(
        path,
        &ReadOptions {
            repair: false,
            ..ReadOptions::default()
        },
    )
    .unwrap()
}

fn write_and_read(path: &Path, mesh: &IndexedMesh) -> surftrack::io::Frame {
    write_ply(path, mesh).unwrap();
    read_frame(path).unwrap()
}

#[test]
fn triangle_soup_welds_back_into_the_closed_torus() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("soup.ply");
    let torus = torus(16, 10);
    let mean_edge = torus.mean_edge_length();
    for scale in [1e-6, 1.0, 1e6] {
        // Copies jittered well within the tolerance (1e-6 × mean edge length) weld.
        let tiny = 2e-8 * mean_edge * scale;
        let input = soup(&scaled(&torus, scale), |c| {
            Vec3::new(1.0, -1.0, 0.5) * tiny * ((c % 3) as f32)
        });
        let frame = write_and_read(&path, &input);
        let corners = 3 * torus.triangles.len();
        assert_eq!(
            frame.repairs.welded_vertices,
            corners - torus.positions.len(),
            "scale {scale}"
        );
        assert_eq!(frame.repairs.degenerate_faces, 0);
        assert_eq!(frame.repairs.unreferenced_vertices, 0);
        let mesh = &frame.mesh;
        mesh.validate().unwrap();
        assert_eq!(mesh.topology().total_genus(), 1);
        assert_eq!(mesh.positions.len(), torus.positions.len());
        // Kept vertices are the first corner of each group, with its id and attribute.
        let ids = mesh.ids.as_ref().unwrap();
        for (v, &id) in ids.iter().enumerate() {
            assert_eq!(mesh.attributes[0].values[v], id as f32);
            assert_eq!(mesh.positions[v], input.positions[id as usize]);
        }
        assert!(
            ids.windows(2).all(|w| w[0] < w[1]),
            "kept vertices keep input order"
        );
    }
}

#[test]
fn copies_farther_apart_than_the_tolerance_stay_apart() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("apart.ply");
    let torus = torus(16, 10);
    let step = 1e-4 * torus.mean_edge_length();
    // Every copy at its own offset (distinct for the 960 corners), all within 0.002 edge lengths.
    let input = soup(&torus, |c| {
        Vec3::new((c % 10) as f32, (c / 10 % 10) as f32, (c / 100) as f32) * step
    });
    let frame = write_and_read(&path, &input);
    assert!(frame.repairs.is_clean(), "{:?}", frame.repairs);
    assert_eq!(frame.mesh, input);

    let options = ReadOptions {
        weld_tolerance: 1e-2,
        ..ReadOptions::default()
    };
    let welded = read_frame_with(&path, &options).unwrap();
    assert_eq!(welded.mesh.positions.len(), torus.positions.len());
    welded.mesh.validate().unwrap();
}

#[test]
fn degenerate_faces_and_unreferenced_vertices_are_removed() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("dirty.ply");
    let torus = torus(8, 6);
    let mut input = torus.clone();
    let n = input.positions.len() as u32;
    // An unused vertex, a repeated-corner face, and a zero-area face on three collinear new
    // vertices (which then become unreferenced).
    input.positions.push(Vec3::splat(9.0));
    input
        .positions
        .extend([Vec3::ZERO, Vec3::ONE, Vec3::splat(2.0)]);
    input.triangles.insert(3, [0, 1, 1]);
    input.triangles.push([n + 1, n + 2, n + 3]);
    input.ids = Some((100..100 + input.positions.len() as u64).collect());
    let frame = write_and_read(&path, &input);
    assert_eq!(frame.repairs.welded_vertices, 0);
    assert_eq!(frame.repairs.degenerate_faces, 2);
    assert_eq!(frame.repairs.unreferenced_vertices, 4);
    let mut expected = torus;
    expected.ids = Some((100..100 + n as u64).collect());
    assert_eq!(frame.mesh, expected);

    let raw = read_unrepaired(&path);
    assert!(raw.repairs.is_clean());
    assert_eq!(raw.mesh, input);
}

#[test]
fn polygons_with_fewer_than_three_corners_count_as_degenerate() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("short.obj");
    std::fs::write(&path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2\nf 3\n").unwrap();
    let frame = read_frame(&path).unwrap();
    assert_eq!(frame.repairs.degenerate_faces, 2);
    assert_eq!(frame.mesh.triangles, [[0, 1, 2]]);
}

/// The parts of `tests/data/touching/NAME`, read: each touching part becomes a component of its own,
/// every point stays where the file put it, and the mesh is a closed 2-manifold.
fn touching(name: &str) -> (IndexedMesh, surftrack::io::RepairReport) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/touching")
        .join(name);
    let raw = read_unrepaired(&path);
    let frame = read_frame(&path).unwrap();
    frame.mesh.validate().unwrap();
    assert_eq!(frame.mesh.triangles.len(), raw.mesh.triangles.len());
    for (read, file) in frame.mesh.triangles.iter().zip(&raw.mesh.triangles) {
        for k in 0..3 {
            assert_eq!(
                frame.mesh.positions[read[k] as usize],
                raw.mesh.positions[file[k] as usize]
            );
        }
    }
    (frame.mesh, frame.repairs)
}

#[test]
fn parts_touching_at_a_vertex_or_an_edge_are_split_apart_in_place() {
    let (mesh, repairs) = touching("tetrahedra_at_a_vertex.obj");
    assert_eq!((repairs.split_vertices, repairs.split_edges), (1, 0));
    assert_eq!(mesh.positions.len(), 8);
    assert_eq!(mesh.topology().components.len(), 2);

    let (mesh, repairs) = touching("tetrahedra_on_an_edge.obj");
    assert_eq!((repairs.split_vertices, repairs.split_edges), (2, 1));
    assert_eq!(mesh.positions.len(), 8);
    assert_eq!(mesh.topology().components.len(), 2);
}
