//! Output safety: atomic writes leave either the old or the complete new file, and an existing
//! output directory is only written into with `force`.

use std::fs;
use std::io::{self, Seek, SeekFrom, Write};
use surftrack::io::{AtomicFile, IoError, atomic_write, prepare_output_dir};

fn entries(dir: &std::path::Path) -> Vec<String> {
    let mut names: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    names
}

#[test]
fn a_failed_write_leaves_the_old_file_and_no_debris() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("frame_0001.obj");
    atomic_write(&path, |w| w.write_all(b"old")).unwrap();
    assert_eq!(fs::read(&path).unwrap(), b"old");

    let result = atomic_write(&path, |w| {
        w.write_all(&[b'x'; 100_000])?;
        Err(io::Error::other("simulated crash"))
    });
    let error = result.unwrap_err();
    assert!(error.to_string().contains("frame_0001.obj"), "{error}");
    assert!(error.to_string().contains("simulated crash"), "{error}");
    assert_eq!(fs::read(&path).unwrap(), b"old");
    assert_eq!(entries(dir.path()), ["frame_0001.obj"]);

    atomic_write(&path, |w| w.write_all(b"new")).unwrap();
    assert_eq!(fs::read(&path).unwrap(), b"new");
    assert_eq!(entries(dir.path()), ["frame_0001.obj"]);
}

/// A file written in pieces (a streamed export) is not at its path until committed, a patched
/// header is in place, and an abandoned one leaves nothing.
#[test]
fn a_file_written_in_pieces_appears_only_when_committed() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.usdc");
    fs::write(&path, b"old").unwrap();

    let mut file = AtomicFile::create(&path).unwrap();
    file.writer().write_all(b"....body").unwrap();
    assert_eq!(fs::read(&path).unwrap(), b"old");
    file.writer().seek(SeekFrom::Start(0)).unwrap();
    file.writer().write_all(b"HEAD").unwrap();
    file.commit().unwrap();
    assert_eq!(fs::read(&path).unwrap(), b"HEADbody");
    assert_eq!(entries(dir.path()), ["out.usdc"]);

    let mut abandoned = AtomicFile::create(&path).unwrap();
    abandoned.writer().write_all(&[b'x'; 100_000]).unwrap();
    assert_eq!(entries(dir.path()).len(), 2);
    drop(abandoned);
    assert_eq!(fs::read(&path).unwrap(), b"HEADbody");
    assert_eq!(entries(dir.path()), ["out.usdc"]);
}

#[test]
fn writing_into_a_missing_directory_fails_cleanly() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("absent/frame.obj");
    let error = atomic_write(&path, |w| w.write_all(b"data")).unwrap_err();
    assert!(matches!(error, IoError::Io { .. }), "{error}");
}

#[test]
fn output_directories_are_not_reused_without_force() {
    let root = tempfile::tempdir().unwrap();
    let out = root.path().join("a/b/out");
    prepare_output_dir(&out, false).unwrap();
    assert!(out.is_dir());
    prepare_output_dir(&out, false).unwrap();

    fs::write(out.join("keep.txt"), b"user data").unwrap();
    let error = prepare_output_dir(&out, false).unwrap_err();
    assert!(matches!(error, IoError::OutputNotEmpty { .. }), "{error}");
    assert!(error.to_string().contains("--force"), "{error}");
    prepare_output_dir(&out, true).unwrap();
    assert_eq!(fs::read(out.join("keep.txt")).unwrap(), b"user data");

    let file = root.path().join("plain");
    fs::write(&file, b"").unwrap();
    let error = prepare_output_dir(&file, true).unwrap_err();
    assert!(matches!(error, IoError::NotADirectory { .. }), "{error}");
}
