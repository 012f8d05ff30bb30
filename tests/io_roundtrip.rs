//! Writers and readers agree: what is written reads back as the same mesh, bit for bit where the
//! format is binary (and for text too, as floats are written in shortest round-trip form).

use glam::Vec3;
use std::f32::consts::TAU;
use std::path::Path;
use surftrack::io::{
    IoError, ObjOptions, PlyEncoding, read_frame, write_bobj_gz, write_obj, write_ply,
    write_ply_with,
};
use surftrack::mesh::{Attribute, IndexedMesh};

/// A closed torus of `n × m` quads split into triangles, with coordinates that use every bit of
/// an f32.
fn torus(n: u32, m: u32) -> IndexedMesh {
    let mut positions = Vec::new();
    for i in 0..n {
        for j in 0..m {
            let (u, v) = (TAU * i as f32 / n as f32, TAU * j as f32 / m as f32);
            let r = 1.0 + 0.37 * v.cos();
            positions.push(Vec3::new(r * u.cos(), r * u.sin(), 0.37 * v.sin()) * 1.3);
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

/// The torus with ids and one attribute of each naming convention.
fn decorated_torus(id_base: u64) -> IndexedMesh {
    let mut mesh = torus(12, 8);
    let n = mesh.positions.len();
    mesh.ids = Some((0..n as u64).map(|v| id_base + 7 * v).collect());
    let channel = |components: usize, scale: f32| -> Vec<f32> {
        (0..n * components)
            .map(|k| (k as f32 * scale).sin())
            .collect()
    };
    for (name, components, scale) in [
        ("color", 3, 0.11),
        ("uv", 2, 0.23),
        ("normal", 3, 0.37),
        ("temperature", 1, 0.41),
        ("displacement", 4, 0.53),
    ] {
        mesh.attributes.push(Attribute {
            name: name.into(),
            components,
            values: channel(components, scale),
        });
    }
    mesh
}

fn round_trip(path: &Path, mesh: &IndexedMesh) -> IndexedMesh {
    let frame = read_frame(path).unwrap_or_else(|e| panic!("{e}"));
    assert!(frame.repairs.is_clean(), "{:?}", frame.repairs);
    assert_eq!(frame.mesh.triangles, mesh.triangles);
    let bits = |m: &IndexedMesh| -> Vec<[u32; 3]> {
        m.positions
            .iter()
            .map(|p| p.to_array().map(f32::to_bits))
            .collect()
    };
    assert_eq!(bits(&frame.mesh), bits(mesh), "positions differ");
    frame.mesh
}

#[test]
fn obj_round_trips_positions_faces_and_colour() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = decorated_torus(0);
    let path = dir.path().join("torus.obj");
    write_obj(&path, &mesh, &ObjOptions::default()).unwrap();
    let read = round_trip(&path, &mesh);
    assert!(read.attributes.is_empty() && read.ids.is_none());

    write_obj(
        &path,
        &mesh,
        &ObjOptions {
            uv: true,
            color: true,
        },
    )
    .unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert_eq!(
        text.lines().filter(|l| l.starts_with("vt ")).count(),
        mesh.positions.len()
    );
    assert!(text.lines().any(|l| l.starts_with("f ") && l.contains('/')));
    let read = round_trip(&path, &mesh);
    assert_eq!(read.attributes.len(), 1);
    assert_eq!(read.attributes[0], mesh.attributes[0]);
}

#[test]
fn obj_options_need_their_attribute() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("plain.obj");
    let error = write_obj(
        &path,
        &torus(4, 3),
        &ObjOptions {
            uv: true,
            color: false,
        },
    );
    assert!(
        matches!(error, Err(IoError::Unwritable { .. })),
        "{error:?}"
    );
    assert!(!path.exists());
}

#[test]
fn ply_round_trips_everything_in_every_encoding() {
    let dir = tempfile::tempdir().unwrap();
    for id_base in [0, u64::from(u32::MAX) + 1] {
        let mesh = decorated_torus(id_base);
        for encoding in [
            PlyEncoding::Ascii,
            PlyEncoding::BinaryLittleEndian,
            PlyEncoding::BinaryBigEndian,
        ] {
            let path = dir.path().join(format!("torus_{encoding:?}_{id_base}.ply"));
            write_ply_with(&path, &mesh, encoding).unwrap();
            let read = round_trip(&path, &mesh);
            assert_eq!(read, mesh, "{encoding:?}, ids from {id_base}");
        }
    }
}

#[test]
fn ply_header_follows_the_documented_layout() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("torus.ply");
    write_ply(&path, &decorated_torus(0)).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let end = bytes
        .windows(11)
        .position(|w| w == b"end_header\n")
        .unwrap();
    let header = std::str::from_utf8(&bytes[..end]).unwrap();
    let properties: Vec<&str> = header
        .lines()
        .filter_map(|l| l.strip_prefix("property "))
        .collect();
    assert_eq!(
        properties,
        [
            "float x",
            "float y",
            "float z",
            "uint id",
            "float red",
            "float green",
            "float blue",
            "float u",
            "float v",
            "float nx",
            "float ny",
            "float nz",
            "float temperature",
            "float displacement_0",
            "float displacement_1",
            "float displacement_2",
            "float displacement_3",
            "list uchar int vertex_indices",
        ]
    );
    assert!(header.starts_with("ply\nformat binary_little_endian 1.0\n"));

    let mut large = decorated_torus(u64::from(u32::MAX) + 1);
    write_ply(&path, &large).unwrap();
    let header = String::from_utf8_lossy(&std::fs::read(&path).unwrap()[..200]).into_owned();
    assert!(header.contains("property double id\n"), "{header}");
    large.ids.as_mut().unwrap()[3] = (1 << 53) + 1;
    assert!(matches!(
        write_ply(&path, &large),
        Err(IoError::Unwritable { .. })
    ));
}

#[test]
fn ply_refuses_attribute_names_that_would_not_read_back() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.ply");
    let single = |name: &str| Attribute {
        name: name.into(),
        components: 1,
        values: vec![0.5; 12],
    };
    let cases: Vec<Vec<Attribute>> = vec![
        vec![single("x")],
        vec![single("id")],
        vec![single("red"), single("green"), single("blue")],
        vec![single("has space")],
        vec![single("t"), single("t")],
        vec![Attribute {
            name: "short".into(),
            components: 2,
            values: vec![0.0; 3],
        }],
    ];
    for attributes in cases {
        let mut mesh = torus(4, 3);
        mesh.attributes = attributes.clone();
        let result = write_ply(&path, &mesh);
        assert!(
            matches!(result, Err(IoError::Unwritable { .. })),
            "{attributes:?}: {result:?}"
        );
    }
    assert!(!path.exists());
}

#[test]
fn bobj_gz_round_trips_positions_and_faces() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = decorated_torus(0);
    let path = dir.path().join("fluid_0001.bobj.gz");
    write_bobj_gz(&path, &mesh).unwrap();
    let read = round_trip(&path, &mesh);
    assert!(read.ids.is_none() && read.attributes.is_empty());
}

#[test]
fn foreign_ply_conventions_are_read() {
    // Big-endian, double coordinates, uchar colours, an unknown list property on vertices, a
    // `vertex_index` list of uint with a face property before it, an extra element, and a quad.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("foreign.ply");
    let mut bytes = b"ply\r\nformat binary_big_endian 1.0\r\ncomment from elsewhere\r\n\
        element vertex 4\r\nproperty double x\r\nproperty double y\r\nproperty double z\r\n\
        property list uchar short extra\r\nproperty uchar red\r\nproperty uchar green\r\n\
        property uchar blue\r\nproperty short id\r\n\
        element face 2\r\nproperty ushort material\r\nproperty list uchar uint vertex_index\r\n\
        element edge 1\r\nproperty int vertex1\r\nproperty int vertex2\r\nend_header\r\n"
        .to_vec();
    let corners = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.5],
    ];
    for (v, p) in corners.iter().enumerate() {
        for c in p {
            bytes.extend_from_slice(&f64::to_be_bytes(*c));
        }
        bytes.extend_from_slice(&[2, 0, 9, 0, 8]);
        bytes.extend_from_slice(&[255, 51, v as u8]);
        bytes.extend_from_slice(&(10 + v as i16).to_be_bytes());
    }
    bytes.extend_from_slice(&7u16.to_be_bytes());
    bytes.push(4);
    for v in [0u32, 1, 2, 3] {
        bytes.extend_from_slice(&v.to_be_bytes());
    }
    bytes.extend_from_slice(&7u16.to_be_bytes());
    bytes.push(3);
    for v in [0u32, 3, 2] {
        bytes.extend_from_slice(&v.to_be_bytes());
    }
    bytes.extend_from_slice(&[0, 0, 0, 1, 0, 0, 0, 2]);
    std::fs::write(&path, &bytes).unwrap();

    let frame = read_frame(&path).unwrap();
    let mesh = frame.mesh;
    assert_eq!(mesh.triangles, [[0, 1, 2], [0, 2, 3], [0, 3, 2]]);
    assert_eq!(mesh.positions[3], Vec3::new(0.0, 1.0, 0.5));
    assert_eq!(mesh.ids, Some(vec![10, 11, 12, 13]));
    assert_eq!(mesh.attributes.len(), 1);
    let color = &mesh.attributes[0];
    assert_eq!((color.name.as_str(), color.components), ("color", 3));
    assert_eq!(&color.values[..3], &[1.0, 0.2, 0.0]);
}

#[test]
fn obj_statements_beyond_plain_triangles_are_read() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("features.obj");
    std::fs::write(
        &path,
        "mtllib missing.mtl\no first\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nvt 0 0\n\
         usemtl red\ng side\nf 1/1/1 2/1/1 3/1/1 4/1/1\ns off\no second\nv 0 0 2 2\n\
         f -1 4//1 3\nl 1 2\n# f 9 9 9\n",
    )
    .unwrap();
    let mesh = read_frame(&path).unwrap().mesh;
    assert_eq!(mesh.positions[4], Vec3::new(0.0, 0.0, 1.0));
    assert_eq!(mesh.triangles, [[0, 1, 2], [0, 2, 3], [4, 3, 2]]);
}
