use super::IoError;
use std::path::Path;

/// The frame file formats, told apart by file name extension (case-insensitive).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Format {
    Obj,
    Ply,
    /// Blender/Mantaflow fluid cache: gzip of counts and little-endian arrays.
    BobjGz,
}

impl Format {
    /// Every format, in the order their extensions are tried.
    pub const ALL: [Format; 3] = [Format::BobjGz, Format::Obj, Format::Ply];

    /// The extension including its leading dot, as written after a frame number.
    pub fn extension(self) -> &'static str {
        match self {
            Format::Obj => ".obj",
            Format::Ply => ".ply",
            Format::BobjGz => ".bobj.gz",
        }
    }

    /// The format a file name's extension names, if any.
    pub fn from_name(name: &str) -> Option<Format> {
        let lower = name.to_ascii_lowercase();
        Format::ALL.into_iter().find(|format| {
            lower.len() > format.extension().len() && lower.ends_with(format.extension())
        })
    }

    /// The format of `path`, or `UnsupportedFormat`.
    pub fn from_path(path: &Path) -> Result<Format, IoError> {
        path.file_name()
            .and_then(|name| name.to_str())
            .and_then(Format::from_name)
            .ok_or_else(|| IoError::UnsupportedFormat {
                path: path.to_path_buf(),
            })
    }
}
