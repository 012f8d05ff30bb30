//! Crash-safe output: a frame file either has its old content or its complete new content, never a
//! prefix, because it is written under a temporary name in the same directory and renamed into place
//! (a rename within one file system is atomic).

use super::IoError;
use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Distinguishes temporary files of concurrent writes from one process.
static NEXT_TEMPORARY: AtomicU64 = AtomicU64::new(0);

/// Writes `path` through `write`, atomically: the data goes to a hidden temporary file beside
/// `path`, is flushed to disk, and only then renamed over `path`. On any error the temporary file
/// is removed and `path` is untouched.
pub fn atomic_write<F>(path: &Path, write: F) -> Result<(), IoError>
where
    F: FnOnce(&mut dyn Write) -> io::Result<()>,
{
    let mut file = AtomicFile::create(path)?;
    write(file.writer()).map_err(|source| file.error("write", source))?;
    file.commit()
}

/// A file written in pieces (a stream of frames, a header patched at the end) that appears at its
/// path only when complete: it is a hidden temporary file beside the path until
/// [`AtomicFile::commit`] renames it into place; dropped before that, it is removed and the path is
/// untouched.
#[derive(Debug)]
pub struct AtomicFile {
    path: PathBuf,
    writer: BufWriter<File>,
    temporary: Temporary,
}

/// Removes the temporary file when dropped, unless it has been renamed into place.
#[derive(Debug)]
struct Temporary {
    path: PathBuf,
    renamed: bool,
}

impl Drop for Temporary {
    fn drop(&mut self) {
        if !self.renamed {
            // The file was created before this guard; if it is already gone there is nothing to do.
            let _ = fs::remove_file(&self.path);
        }
    }
}

impl AtomicFile {
    pub fn create(path: &Path) -> Result<Self, IoError> {
        let temporary = temporary_path(path);
        let file = OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&temporary)
            .map_err(|source| IoError::Io {
                path: path.to_path_buf(),
                action: "create a temporary file beside it",
                source,
            })?;
        Ok(Self {
            path: path.to_path_buf(),
            writer: BufWriter::new(file),
            temporary: Temporary {
                path: temporary,
                renamed: false,
            },
        })
    }

    /// The buffered temporary file; it can seek back (to patch a header).
    pub fn writer(&mut self) -> &mut BufWriter<File> {
        &mut self.writer
    }

    /// An error about the final path.
    pub fn error(&self, action: &'static str, source: io::Error) -> IoError {
        IoError::Io {
            path: self.path.clone(),
            action,
            source,
        }
    }

    /// Flushes the data to disk and renames the temporary file over the path.
    pub fn commit(self) -> Result<(), IoError> {
        let Self {
            path,
            writer,
            mut temporary,
        } = self;
        let failed = |action: &'static str| {
            let path = path.clone();
            move |source: io::Error| IoError::Io {
                path,
                action,
                source,
            }
        };
        let file = writer
            .into_inner()
            .map_err(|e| failed("write")(e.into_error()))?;
        file.sync_all().map_err(failed("flush to disk"))?;
        drop(file);
        fs::rename(&temporary.path, &path).map_err(failed("rename the temporary file onto it"))?;
        temporary.renamed = true;
        Ok(())
    }
}

/// `dir/.name.<pid>.<n>.tmp`: hidden, unique within the process and across processes.
fn temporary_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let n = NEXT_TEMPORARY.fetch_add(1, Ordering::Relaxed);
    path.with_file_name(format!(".{name}.{}.{n}.tmp", std::process::id()))
}

/// Removes from `dir` the temporary files of writes that were cut short (a killed process leaves
/// its `.name.<pid>.<n>.tmp` behind); returns how many. A missing `dir` holds none.
pub fn remove_stale_temporaries(dir: &Path) -> Result<usize, IoError> {
    let failed = |action: &'static str| {
        move |source: io::Error| IoError::Io {
            path: dir.to_path_buf(),
            action,
            source,
        }
    };
    let entries = match fs::read_dir(dir) {
        Ok(entries) => entries,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(0),
        Err(e) => return Err(failed("list the directory")(e)),
    };
    let mut removed = 0;
    for entry in entries {
        let entry = entry.map_err(failed("list the directory"))?;
        if is_temporary(&entry.file_name().to_string_lossy()) {
            fs::remove_file(entry.path()).map_err(failed("remove a stale temporary file in"))?;
            removed += 1;
        }
    }
    Ok(removed)
}

/// `.name.<pid>.<n>.tmp`, as [`temporary_path`] makes them.
fn is_temporary(name: &str) -> bool {
    let Some(inner) = name.strip_prefix('.').and_then(|n| n.strip_suffix(".tmp")) else {
        return false;
    };
    let mut parts = inner.rsplitn(3, '.');
    let numeric = |part: Option<&str>| {
        part.is_some_and(|p| !p.is_empty() && p.bytes().all(|b| b.is_ascii_digit()))
    };
    numeric(parts.next()) && numeric(parts.next()) && parts.next().is_some_and(|n| !n.is_empty())
}

/// Makes `dir` ready to receive output frames: creates it (and its parents) if missing.
///
/// An existing non-empty directory is refused unless `force` is set, so a run never mixes its
/// frames with (or overwrites) files a user already has there. Even with `force` nothing is
/// deleted: files are replaced one by one as new frames are written.
pub fn prepare_output_dir(dir: &Path, force: bool) -> Result<(), IoError> {
    let failed = |action: &'static str| {
        move |source: io::Error| IoError::Io {
            path: dir.to_path_buf(),
            action,
            source,
        }
    };
    match fs::metadata(dir) {
        Ok(meta) if !meta.is_dir() => Err(IoError::NotADirectory {
            path: dir.to_path_buf(),
        }),
        Ok(_) => {
            let mut entries = fs::read_dir(dir).map_err(failed("list the directory"))?;
            if entries.next().is_some() && !force {
                Err(IoError::OutputNotEmpty {
                    path: dir.to_path_buf(),
                })
            } else {
                Ok(())
            }
        }
        Err(e) if e.kind() == io::ErrorKind::NotFound => {
            fs::create_dir_all(dir).map_err(failed("create the directory"))
        }
        Err(e) => Err(failed("inspect the directory")(e)),
    }
}
