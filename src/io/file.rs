use super::IoError;
use std::fs;
use std::io;
use std::path::Path;

/// The whole content of `path`; a missing file and a zero-byte file get their own errors.
///
/// Frames are read whole: one frame is small next to memory, and parsing a slice lets every count
/// be checked against the bytes that remain before anything is allocated.
pub(crate) fn read_bytes(path: &Path) -> Result<Vec<u8>, IoError> {
    let bytes = fs::read(path).map_err(|source| match source.kind() {
        io::ErrorKind::NotFound => IoError::NotFound {
            path: path.to_path_buf(),
        },
        _ => IoError::Io {
            path: path.to_path_buf(),
            action: "read",
            source,
        },
    })?;
    if bytes.is_empty() {
        return Err(IoError::Empty {
            path: path.to_path_buf(),
        });
    }
    Ok(bytes)
}
