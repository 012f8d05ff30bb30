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
    let temporary = temporary_path(path);
    let result = write_then_rename(path, &temporary, write);
    if result.is_err() {
        // The temporary file may not exist (creation failed); nothing else to do then.
        let _ = fs::remove_file(&temporary);
    }
    result
}

fn write_then_rename<F>(path: &Path, temporary: &Path, write: F) -> Result<(), IoError>
where
    F: FnOnce(&mut dyn Write) -> io::Result<()>,
{
    let failed = |action: &'static str| {
        move |source: io::Error| IoError::Io {
            path: path.to_path_buf(),
            action,
            source,
        }
    };
    let file = OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(temporary)
        .map_err(failed("create a temporary file beside it"))?;
    let mut writer = BufWriter::new(file);
    write(&mut writer).map_err(failed("write"))?;
    let file: File = writer
        .into_inner()
        .map_err(|e| e.into_error())
        .map_err(failed("write"))?;
    file.sync_all().map_err(failed("flush to disk"))?;
    drop(file);
    fs::rename(temporary, path).map_err(failed("rename the temporary file onto it"))
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
