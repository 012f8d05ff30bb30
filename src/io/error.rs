use std::fmt;
use std::path::PathBuf;
use thiserror::Error;

/// Where in a file something went wrong: a line for text formats, an element for binary ones.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Location {
    /// 1-based line number of a text file.
    Line(usize),
    /// 0-based index of an element (`vertex 17`, `face 3`) of a binary file.
    Element { element: String, index: usize },
    /// A byte offset, for binary data that is not an element (a count).
    Byte(usize),
    /// A part of a file that is neither a line nor an element.
    Section(&'static str),
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::Line(line) => write!(f, "line {line}"),
            Location::Element { element, index } => write!(f, "{element} {index}"),
            Location::Byte(offset) => write!(f, "byte {offset}"),
            Location::Section(section) => f.write_str(section),
        }
    }
}

/// Everything that can go wrong reading, writing or discovering frames.
///
/// Every message starts with the file (or directory) it concerns, then the line or element where
/// possible, then what is wrong, so a user can open the file and find the problem.
#[derive(Debug, Error)]
pub enum IoError {
    #[error("{}: file not found", path.display())]
    NotFound { path: PathBuf },
    #[error("{}: cannot {action}: {source}", path.display())]
    Io {
        path: PathBuf,
        action: &'static str,
        source: std::io::Error,
    },
    #[error("{}: file is empty (no vertices, no faces)", path.display())]
    Empty { path: PathBuf },
    #[error("{}: every face is degenerate ({faces} dropped by repair): no surface is left", path.display())]
    NothingLeft { path: PathBuf, faces: usize },
    #[error("{}: has vertices but no faces: no surface", path.display())]
    NoFaces { path: PathBuf },
    #[error("{}: vertex {vertex} at {position} lies {spread:.1e} median edge lengths from the middle of the frame (more than {limit:.0e}): a garbage coordinate", path.display())]
    Outlier {
        path: PathBuf,
        vertex: usize,
        position: String,
        spread: f64,
        limit: f64,
    },
    #[error("{}: unsupported format (expected .obj, .ply or .bobj.gz)", path.display())]
    UnsupportedFormat { path: PathBuf },
    #[error("{}: not a {format} file: {reason}", path.display())]
    WrongFormat {
        path: PathBuf,
        format: &'static str,
        reason: String,
    },
    #[error("{}: line {line}: bad PLY header: {reason}", path.display())]
    BadHeader {
        path: PathBuf,
        line: usize,
        reason: String,
    },
    #[error("{}: truncated at {at}: expected {expected}", path.display())]
    Truncated {
        path: PathBuf,
        at: Location,
        expected: String,
    },
    #[error("{}: {at}: not a number: {text:?}", path.display())]
    NotANumber {
        path: PathBuf,
        at: Location,
        text: String,
    },
    #[error("{}: {at}: non-finite coordinate {value}", path.display())]
    NonFinite {
        path: PathBuf,
        at: Location,
        value: String,
    },
    #[error("{}: {at}: vertex index {index} out of range (the file has {count} vertices)", path.display())]
    IndexOutOfRange {
        path: PathBuf,
        at: Location,
        index: i64,
        count: usize,
    },
    #[error("{}: {at}: invalid {what} count {count}", path.display())]
    InvalidCount {
        path: PathBuf,
        at: Location,
        what: &'static str,
        count: i64,
    },
    #[error("{}: {at}: {reason}", path.display())]
    Malformed {
        path: PathBuf,
        at: Location,
        reason: String,
    },
    #[error("{}: corrupt gzip stream: {source}", path.display())]
    Gzip {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{}: cannot write this mesh: {reason}", path.display())]
    Unwritable { path: PathBuf, reason: String },
    #[error("{}: output directory is not empty; pass --force to write into it anyway", path.display())]
    OutputNotEmpty { path: PathBuf },
    #[error("{}: exists and is not a directory", path.display())]
    NotADirectory { path: PathBuf },
    #[error("{}: no frame files (.obj, .ply, .bobj.gz) match", input.display())]
    NoFrames { input: PathBuf },
    #[error("{}: holds several frame sequences ({}); name one with a pattern such as fluid_####.obj", dir.display(), patterns.join(", "))]
    MixedSequences { dir: PathBuf, patterns: Vec<String> },
    #[error("frame {frame} appears twice: {} and {}", first.display(), second.display())]
    DuplicateFrame {
        frame: i64,
        first: PathBuf,
        second: PathBuf,
    },
    #[error("{}: bad sequence pattern: {reason}", pattern.display())]
    BadPattern { pattern: PathBuf, reason: String },
    #[error("{}: all {count} frames are empty (no vertices, no faces): no surface to track", first.display())]
    AllEmpty { first: PathBuf, count: usize },
}
