//! The broken-input corpus under tests/data/broken: every file fails with its own error, from the
//! reader (`IoError`) or from validation of what was read (`MeshError`), and never panics.

use std::collections::HashSet;
use std::mem::discriminant;
use std::path::{Path, PathBuf};
use surftrack::io::{IoError, Location, read_frame};
use surftrack::mesh::MeshError;

fn corpus(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/broken")
        .join(name)
}

fn io_error(name: &str) -> IoError {
    match read_frame(&corpus(name)) {
        Err(e) => e,
        Ok(frame) => panic!("{name} read without error: {:?}", frame.mesh),
    }
}

fn mesh_error(name: &str) -> MeshError {
    let frame = read_frame(&corpus(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
    assert!(frame.repairs.is_clean(), "{name}: {:?}", frame.repairs);
    frame
        .mesh
        .validate()
        .expect_err(&format!("{name} validated"))
}

#[test]
fn reader_errors_name_the_file_and_what_is_wrong() {
    let cases: Vec<(&str, IoError, &[&str])> = vec![
        (
            "empty.obj",
            io_error("empty.obj"),
            &["empty.obj", "file is empty"],
        ),
        (
            "nan.obj",
            io_error("nan.obj"),
            &["nan.obj", "line 4", "non-finite"],
        ),
        (
            "not_a_number.obj",
            io_error("not_a_number.obj"),
            &["not_a_number.obj", "line 4", "not a number", "1,5"],
        ),
        (
            "index_out_of_range.obj",
            io_error("index_out_of_range.obj"),
            &["line 9", "vertex index 5", "4 vertices"],
        ),
        (
            "truncated.ply",
            io_error("truncated.ply"),
            &["truncated.ply", "truncated at face 2", "4 face records"],
        ),
        (
            "garbage.ply",
            io_error("garbage.ply"),
            &["garbage.ply", "not a PLY file"],
        ),
        (
            "garbage.bobj.gz",
            io_error("garbage.bobj.gz"),
            &["garbage.bobj.gz", "gzip"],
        ),
        (
            "bad_header.ply",
            io_error("bad_header.ply"),
            &["line 2", "bad PLY header", "binary_middle_endian"],
        ),
        (
            "extra_values.ply",
            io_error("extra_values.ply"),
            &["line 12", "more values than the header declares"],
        ),
        (
            "negative_count.bobj.gz",
            io_error("negative_count.bobj.gz"),
            &["byte 0", "invalid vertex count -5"],
        ),
        (
            "unsupported.stl",
            io_error("unsupported.stl"),
            &["unsupported format"],
        ),
        (
            "missing.obj",
            io_error("missing.obj"),
            &["missing.obj", "not found"],
        ),
    ];
    for (name, error, fragments) in &cases {
        let message = error.to_string();
        for fragment in *fragments {
            assert!(
                message.contains(fragment),
                "{name}: {message:?} lacks {fragment:?}"
            );
        }
    }
    let kinds: HashSet<_> = cases.iter().map(|(_, e, _)| discriminant(e)).collect();
    assert_eq!(
        kinds.len(),
        cases.len(),
        "two corpus files share an error kind"
    );

    assert!(matches!(
        io_error("nan.obj"),
        IoError::NonFinite {
            at: Location::Line(4),
            ..
        }
    ));
    assert!(matches!(
        io_error("index_out_of_range.obj"),
        IoError::IndexOutOfRange {
            at: Location::Line(9),
            index: 5,
            count: 4,
            ..
        }
    ));
    assert!(matches!(
        io_error("truncated.ply"),
        IoError::Truncated {
            at: Location::Element { index: 2, .. },
            ..
        }
    ));
}

#[test]
fn topology_errors_come_from_validation() {
    assert!(matches!(
        mesh_error("open.obj"),
        MeshError::OpenBoundary { .. }
    ));
    assert!(matches!(
        mesh_error("nonmanifold_edge.obj"),
        MeshError::NonManifoldEdge {
            a: 0,
            b: 1,
            count: 4
        }
    ));
    assert!(matches!(
        mesh_error("flipped.obj"),
        MeshError::InconsistentOrientation { .. }
    ));
}

#[test]
fn ascii_ply_errors_name_their_line() {
    let dir = tempfile::tempdir().unwrap();
    let header = "ply\r\nformat ascii 1.0\r\nelement vertex 3\r\nproperty float x\r\n\
                  property float y\r\nproperty float z\r\nelement face 1\r\n\
                  property list uchar int vertex_index\r\nend_header\r\n";
    let cases = [
        ("0 0 0\r\n1 0 inf\r\n0 1 0\r\n3 0 1 2\r\n", 11, "non-finite"),
        (
            "0 0 0\r\n\r\n1 0 0\r\n0 1 x\r\n3 0 1 2\r\n",
            13,
            "not a number",
        ),
        (
            "0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1 3\r\n",
            13,
            "vertex index 3",
        ),
        (
            "0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1\r\n",
            13,
            "ends before all its values",
        ),
    ];
    for (body, line, fragment) in cases {
        let path = dir.path().join("case.ply");
        std::fs::write(&path, format!("{header}{body}")).unwrap();
        let message = read_frame(&path).unwrap_err().to_string();
        assert!(message.contains(&format!("line {line}:")), "{message}");
        assert!(message.contains(fragment), "{message}");
    }
}
