//! The batch manifest: one cache per line (a folder or a frame pattern, as `track` takes), blank
//! lines and `#` comments ignored. Every run reads the whole manifest and names every cache the
//! same way, so farm tasks that each take one line agree on every cache's folder without talking.

use super::BatchError;
use crate::io::Format;
use std::collections::HashMap;
use std::path::{Component, Path, PathBuf};

/// A name no cache may take: the assembled report lives beside the caches' folders.
const RESERVED: [&str; 1] = [super::BATCH_FILE];

/// One cache of the manifest.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Cache {
    /// Its line in the manifest, from 1.
    pub line: usize,
    /// The input as written on the line.
    pub text: String,
    /// The input, relative paths taken from the manifest's folder.
    pub input: PathBuf,
    /// Its folder under the output root: the cache's folder name, made unique.
    pub name: String,
}

/// A parsed manifest.
#[derive(Debug, Clone)]
pub struct Manifest {
    pub path: PathBuf,
    pub caches: Vec<Cache>,
}

impl Manifest {
    pub fn read(path: &Path) -> Result<Self, BatchError> {
        let text = std::fs::read_to_string(path).map_err(|source| BatchError::ReadManifest {
            path: path.to_path_buf(),
            source,
        })?;
        Self::parse(path, &text)
    }

    /// Parses `text`, the contents of `path`; relative inputs are taken from `path`'s folder, so
    /// a manifest means the same caches from whichever folder a farm task starts in.
    pub fn parse(path: &Path, text: &str) -> Result<Self, BatchError> {
        let base = path.parent().unwrap_or(Path::new(""));
        let bad = |line: usize, message: String| BatchError::ManifestLine {
            path: path.to_path_buf(),
            line,
            message,
        };
        let mut found: Vec<(usize, &str, Folder)> = Vec::new();
        let mut first_line: HashMap<PathBuf, usize> = HashMap::new();
        for (i, raw) in text.lines().enumerate() {
            let line = i + 1;
            let entry = raw.trim();
            if entry.is_empty() || entry.starts_with('#') {
                continue;
            }
            let Some(folder) = Folder::of(Path::new(entry)) else {
                return Err(bad(
                    line,
                    format!(
                        "`{entry}` names no folder to call the cache after; write its folder's path"
                    ),
                ));
            };
            let key = normalized(&base.join(entry));
            if let Some(first) = first_line.get(&key) {
                return Err(bad(
                    line,
                    format!("`{entry}` is the cache of line {first} again"),
                ));
            }
            first_line.insert(key, line);
            found.push((line, entry, folder));
        }
        let shared = |name: &str| found.iter().filter(|(_, _, f)| f.name == name).count() > 1;
        let mut taken: Vec<String> = RESERVED.iter().map(|s| s.to_string()).collect();
        let mut caches: Vec<Cache> = Vec::with_capacity(found.len());
        for (line, entry, folder) in &found {
            let wanted = match &folder.parent {
                Some(parent) if shared(&folder.name) => format!("{parent}-{}", folder.name),
                _ => folder.name.clone(),
            };
            let name = unique(&sanitized(&wanted), &taken);
            taken.push(name.clone());
            caches.push(Cache {
                line: *line,
                text: entry.to_string(),
                input: base.join(entry),
                name,
            });
        }
        if caches.is_empty() {
            return Err(BatchError::EmptyManifest {
                path: path.to_path_buf(),
            });
        }
        Ok(Self {
            path: path.to_path_buf(),
            caches,
        })
    }

    /// The cache at `index` (0-based, counting caches, not lines).
    pub fn cache(&self, index: usize) -> Result<&Cache, BatchError> {
        self.caches.get(index).ok_or_else(|| BatchError::Index {
            path: self.path.clone(),
            index,
            count: self.caches.len(),
        })
    }
}

/// The folder a cache is called after: the input itself when it is a folder, the folder holding
/// it when it is a frame file or a pattern (`shot/fluid_####.bobj.gz` → `shot`); and the name of
/// the folder above, which tells apart caches whose folders share a name (`shotA/cache`,
/// `shotB/cache` → `shotA-cache`, `shotB-cache`).
struct Folder {
    name: String,
    parent: Option<String>,
}

impl Folder {
    fn of(entry: &Path) -> Option<Self> {
        let named = normalized(entry);
        let is_frames = named
            .file_name()
            .and_then(|n| n.to_str())
            .is_some_and(|n| n.contains(['#', '*']) || Format::from_name(n).is_some());
        let folder = if is_frames { named.parent()? } else { &named };
        let name_of = |path: &Path| path.file_name().map(|n| n.to_string_lossy().into_owned());
        Some(Self {
            name: name_of(folder)?,
            parent: folder.parent().and_then(name_of),
        })
    }
}

/// `path` with `.` components dropped and `..` applied where it can be, without touching the
/// disk, so `a/./b` and `a/b` are one cache.
fn normalized(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for component in path.components() {
        match component {
            Component::CurDir => {}
            Component::ParentDir => {
                if matches!(out.components().next_back(), Some(Component::Normal(_))) {
                    out.pop();
                } else {
                    out.push(component);
                }
            }
            other => out.push(other),
        }
    }
    out
}

/// A folder name safe on every file system a farm mounts: letters, digits, `.`, `_` and `-`.
fn sanitized(name: &str) -> String {
    let clean: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-') {
                c
            } else {
                '_'
            }
        })
        .collect();
    if clean.trim_matches('.').is_empty() {
        "cache".to_string()
    } else {
        clean
    }
}

/// `name`, or `name-2`, `name-3`, … : the first not in `taken`.
fn unique(name: &str, taken: &[String]) -> String {
    let free = |candidate: &str| !taken.iter().any(|t| t == candidate);
    if free(name) {
        return name.to_string();
    }
    (2..)
        .map(|k| format!("{name}-{k}"))
        .find(|candidate| free(candidate))
        .unwrap_or_else(|| name.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Manifest, BatchError> {
        Manifest::parse(Path::new("/jobs/caches.txt"), text)
    }

    fn names(text: &str) -> Vec<String> {
        parse(text)
            .unwrap()
            .caches
            .into_iter()
            .map(|c| c.name)
            .collect()
    }

    #[test]
    fn caches_are_named_after_their_folders_and_made_unique() {
        let text = "# shots\n\nshotA/cache\n  /data/shotB/fluid_####.bobj.gz  \nshotC/cache/\nshotA-cache\n/data/my shot/frame_0001.ply\n";
        assert_eq!(
            names(text),
            [
                "shotA-cache",
                "shotB",
                "shotC-cache",
                "shotA-cache-2",
                "my_shot"
            ]
        );
        assert_eq!(names("cache\nx/cache\n"), ["cache", "x-cache"]);
        let manifest = parse(text).unwrap();
        assert_eq!(manifest.caches[0].line, 3);
        assert_eq!(manifest.caches[0].input, Path::new("/jobs/shotA/cache"));
        assert_eq!(
            manifest.caches[1].input,
            Path::new("/data/shotB/fluid_####.bobj.gz")
        );
        assert_eq!(names("a/batch.json\n"), ["batch.json-2"]);
    }

    #[test]
    fn bad_lines_name_the_manifest_and_the_line() {
        let repeated = parse("a/cache\n# again\n./a/x/../cache/\n").unwrap_err();
        assert_eq!(
            repeated.to_string(),
            "/jobs/caches.txt:3: `./a/x/../cache/` is the cache of line 1 again"
        );
        let nameless = parse("a\n..\n").unwrap_err().to_string();
        assert!(
            nameless.starts_with("/jobs/caches.txt:2: `..`"),
            "{nameless}"
        );
        let empty = parse("# nothing\n\n").unwrap_err().to_string();
        assert_eq!(empty, "/jobs/caches.txt: lists no cache");
    }

    #[test]
    fn an_index_past_the_last_cache_is_refused() {
        let manifest = parse("a\nb\n").unwrap();
        assert_eq!(manifest.cache(1).unwrap().name, "b");
        assert_eq!(
            manifest.cache(2).unwrap_err().to_string(),
            "/jobs/caches.txt: index 2 is past its last cache (2 caches, indices from 0)"
        );
    }
}
