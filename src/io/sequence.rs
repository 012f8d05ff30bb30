//! Finding the frames of a sequence on disk: every file of one name pattern with a frame number,
//! in numeric order (9 before 10), with gaps reported. A cache written every Nth frame (numbers
//! 0, 3, 6, …) has its numbers on a stride of N, and only numbers missing on that stride are gaps.

use super::{Format, IoError, ReadOptions, read_frame_with};
use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};

/// The frames of one sequence, ordered by frame number.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Sequence {
    /// The file name pattern, `#` per digit when every frame number has the same width
    /// (`fluid_####.obj`), else `*` for any number of digits (`frame_*.ply`).
    pub pattern: String,
    pub frames: Vec<(i64, PathBuf)>,
    /// The step between frame numbers: the greatest common divisor of the differences between
    /// consecutive ones (1 for a single frame).
    pub stride: i64,
    /// Frame numbers missing on the stride, as inclusive ranges `(first, last)`: from the number
    /// a stride after a frame to the one a stride before the next.
    pub gaps: Vec<(i64, i64)>,
}

/// Frames without any surface at the ends of a sequence, as inclusive frame-number ranges.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct EmptyEnds {
    /// Before the first frame with a surface: a simulation with an inflow writes these until its
    /// fluid appears.
    pub leading: Option<(i64, i64)>,
    /// After the last frame with a surface: the fluid has drained away.
    pub trailing: Option<(i64, i64)>,
}

impl Sequence {
    /// Each gap as a user reads it: `from..=to`, with the stride where it is not 1.
    pub fn gap_ranges(&self) -> Vec<String> {
        self.gaps
            .iter()
            .map(|(from, to)| match self.stride {
                1 => format!("{from}..={to}"),
                stride => format!("{from}..={to} (numbered every {stride})"),
            })
            .collect()
    }

    /// The sequence without the empty frames (an empty file, or no vertices and no faces) at its
    /// start and its end, and which those were. Frames are read from each end until one is not
    /// empty; one that fails otherwise stops the scan and is left for the tracker to report. Empty
    /// frames between two with a surface stay (the tracker stops there, naming the file).
    pub fn without_empty_ends(mut self) -> Result<(Sequence, EmptyEnds), IoError> {
        // Every reader finds an empty file itself, before any repair: the first frame with a
        // surface is not repaired here only to be read again by the tracker.
        let unrepaired = ReadOptions {
            repair: false,
            ..ReadOptions::default()
        };
        let is_empty = |path: &Path| {
            matches!(
                read_frame_with(path, &unrepaired),
                Err(IoError::Empty { .. })
            )
        };
        let leading = self.frames.iter().take_while(|(_, p)| is_empty(p)).count();
        if leading == self.frames.len() {
            return Err(IoError::AllEmpty {
                first: self.frames[0].1.clone(),
                count: leading,
            });
        }
        let trailing = self.frames[leading..]
            .iter()
            .rev()
            .take_while(|(_, p)| is_empty(p))
            .count();
        let range = |frames: &[(i64, PathBuf)]| Some((frames.first()?.0, frames.last()?.0));
        let ends = EmptyEnds {
            leading: range(&self.frames[..leading]),
            trailing: range(&self.frames[self.frames.len() - trailing..]),
        };
        self.frames.truncate(self.frames.len() - trailing);
        self.frames.drain(..leading);
        if let (Some((first, _)), Some((last, _))) = (self.frames.first(), self.frames.last()) {
            self.gaps.retain(|&(from, to)| from > *first && to < *last);
        }
        Ok((self, ends))
    }
}

/// Finds a sequence from `input`:
/// - a directory: all its `.obj`, `.ply` and `.bobj.gz` files (hidden files aside), which must
///   share one name pattern with a number (the last run of digits before the extension);
/// - a pattern such as `dir/fluid_####.obj` (`#` per zero-padded digit; a longer number without a
///   leading zero also matches, as `10000` for `####`) or `dir/frame_*.ply` (`*` for one or more
///   digits);
/// - a single frame file: a sequence of one.
pub fn discover_sequence(input: &Path) -> Result<Sequence, IoError> {
    let name = input
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or_default();
    if input.is_dir() {
        from_directory(input)
    } else if name.contains(['#', '*']) {
        from_pattern(input, name)
    } else if input.is_file() {
        Format::from_path(input)?;
        let number = split_number(name).and_then(|(_, digits, _)| digits.parse().ok());
        Ok(Sequence {
            pattern: name.to_string(),
            frames: vec![(number.unwrap_or(0), input.to_path_buf())],
            stride: 1,
            gaps: Vec::new(),
        })
    } else {
        Err(IoError::NotFound {
            path: input.to_path_buf(),
        })
    }
}

/// `stem = prefix + digits + suffix`, with the last run of digits of the name before its frame
/// extension; `None` when the name has no frame extension or no digits.
fn split_number(name: &str) -> Option<(&str, &str, &str)> {
    let format = Format::from_name(name)?;
    let stem = &name[..name.len() - format.extension().len()];
    let end = stem.rfind(|c: char| c.is_ascii_digit())? + 1;
    let start = stem[..end]
        .rfind(|c: char| !c.is_ascii_digit())
        .map_or(0, |i| i + 1);
    Some((&name[..start], &name[start..end], &name[end..]))
}

fn from_directory(dir: &Path) -> Result<Sequence, IoError> {
    // Pattern key (prefix, suffix) -> frames.
    let mut groups: BTreeMap<(String, String), Vec<(i64, String)>> = BTreeMap::new();
    for name in list(dir)? {
        if name.starts_with('.') || Format::from_name(&name).is_none() {
            continue;
        }
        match split_number(&name).and_then(|(p, d, s)| Some((p, d.parse::<i64>().ok()?, s))) {
            Some((prefix, number, suffix)) => groups
                .entry((prefix.to_string(), suffix.to_string()))
                .or_default()
                .push((number, name.clone())),
            None => {
                groups.insert((name.clone(), String::new()), Vec::new());
            }
        }
    }
    match groups.len() {
        0 => Err(IoError::NoFrames {
            input: dir.to_path_buf(),
        }),
        1 => {
            let ((prefix, suffix), names) = groups.into_iter().next().unwrap_or_default();
            if names.is_empty() {
                return Err(IoError::NoFrames {
                    input: dir.to_path_buf(),
                });
            }
            assemble(dir, &prefix, &suffix, names)
        }
        _ => Err(IoError::MixedSequences {
            dir: dir.to_path_buf(),
            patterns: groups
                .iter()
                .map(|((prefix, suffix), names)| {
                    if names.is_empty() {
                        prefix.clone()
                    } else {
                        format!("{prefix}*{suffix}")
                    }
                })
                .collect(),
        }),
    }
}

fn from_pattern(input: &Path, pattern: &str) -> Result<Sequence, IoError> {
    let bad = |reason: &str| IoError::BadPattern {
        pattern: input.to_path_buf(),
        reason: reason.into(),
    };
    let start = pattern.find(['#', '*']).unwrap_or(0);
    let end = start
        + if pattern[start..].starts_with('*') {
            1
        } else {
            pattern[start..]
                .find(|c| c != '#')
                .unwrap_or(pattern.len() - start)
        };
    let (prefix, placeholder, suffix) = (&pattern[..start], &pattern[start..end], &pattern[end..]);
    if suffix.contains(['#', '*']) {
        return Err(bad(
            "only one run of # or one * may stand for the frame number",
        ));
    }
    let lower = suffix.to_ascii_lowercase();
    if !Format::ALL.iter().any(|f| lower.ends_with(f.extension())) {
        return Err(bad("the pattern must end in .obj, .ply or .bobj.gz"));
    }
    let width = (placeholder != "*").then_some(placeholder.len());
    let dir = match input.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    };
    if !dir.is_dir() {
        return Err(IoError::NotFound {
            path: dir.to_path_buf(),
        });
    }
    let mut names = Vec::new();
    for name in list(dir)? {
        let Some(digits) = name
            .strip_prefix(prefix)
            .and_then(|rest| rest.strip_suffix(suffix))
        else {
            continue;
        };
        let digits_only = !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit());
        let width_matches = width
            .is_none_or(|w| digits.len() == w || (digits.len() > w && !digits.starts_with('0')));
        if digits_only
            && width_matches
            && let Ok(number) = digits.parse::<i64>()
        {
            names.push((number, name));
        }
    }
    if names.is_empty() {
        return Err(IoError::NoFrames {
            input: input.to_path_buf(),
        });
    }
    assemble(dir, prefix, suffix, names)
}

/// Names of the entries of `dir` that are valid UTF-8 (frame names are).
fn list(dir: &Path) -> Result<Vec<String>, IoError> {
    let failed = |source| IoError::Io {
        path: dir.to_path_buf(),
        action: "list the directory",
        source,
    };
    let mut names = Vec::new();
    for entry in fs::read_dir(dir).map_err(failed)? {
        let entry = entry.map_err(failed)?;
        if let Ok(name) = entry.file_name().into_string() {
            names.push(name);
        }
    }
    Ok(names)
}

/// Orders frames by number, rejects duplicates and finds gaps.
fn assemble(
    dir: &Path,
    prefix: &str,
    suffix: &str,
    mut names: Vec<(i64, String)>,
) -> Result<Sequence, IoError> {
    names.sort();
    if let Some(pair) = names.windows(2).find(|pair| pair[0].0 == pair[1].0) {
        return Err(IoError::DuplicateFrame {
            frame: pair[0].0,
            first: dir.join(&pair[0].1),
            second: dir.join(&pair[1].1),
        });
    }
    let widths: Vec<usize> = names
        .iter()
        .map(|(_, name)| name.len() - prefix.len() - suffix.len())
        .collect();
    let placeholder = match widths.split_first() {
        Some((&w, rest)) if rest.iter().all(|&x| x == w) => "#".repeat(w),
        _ => "*".to_string(),
    };
    let stride = names
        .windows(2)
        .map(|pair| pair[1].0 - pair[0].0)
        .reduce(gcd)
        .unwrap_or(1);
    let gaps = names
        .windows(2)
        .filter(|pair| pair[1].0 - pair[0].0 > stride)
        .map(|pair| (pair[0].0 + stride, pair[1].0 - stride))
        .collect();
    Ok(Sequence {
        pattern: format!("{prefix}{placeholder}{suffix}"),
        frames: names
            .into_iter()
            .map(|(number, name)| (number, dir.join(name)))
            .collect(),
        stride,
        gaps,
    })
}

/// The greatest common divisor of two positive numbers.
fn gcd(a: i64, b: i64) -> i64 {
    if b == 0 { a } else { gcd(b, a % b) }
}
