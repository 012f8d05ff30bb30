//! The layer as USD text (`.usda`), streamed: a usda file lists each attribute's time samples
//! together, so each attribute's samples are spooled to an anonymous temporary file beside the
//! output as frames arrive and copied into the output at the end. Memory holds one frame.

use super::ExportError;
use super::usd::{PRIM, SUBDIVISION_SCHEME, Sample, StageMetadata, UsdAttribute};
use crate::io::{AtomicFile, IoError};
use std::fs::File;
use std::io::{self, BufWriter, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

/// A `.usda` file being written.
#[derive(Debug)]
pub struct UsdaWriter {
    path: PathBuf,
    attributes: Vec<UsdAttribute>,
    /// One spool per attribute: its `time: value,` lines so far.
    spools: Vec<BufWriter<File>>,
}

impl UsdaWriter {
    pub fn create(path: &Path, attributes: Vec<UsdAttribute>) -> Result<Self, ExportError> {
        let dir = match path.parent() {
            Some(dir) if !dir.as_os_str().is_empty() => dir,
            _ => Path::new("."),
        };
        let spools = attributes
            .iter()
            .map(|_| tempfile::tempfile_in(dir).map(BufWriter::new))
            .collect::<io::Result<Vec<_>>>()
            .map_err(|source| IoError::Io {
                path: path.to_path_buf(),
                action: "create a temporary file beside it",
                source,
            })?;
        Ok(Self {
            path: path.to_path_buf(),
            attributes,
            spools,
        })
    }

    /// Appends one sample per attribute at `time`.
    pub fn push(&mut self, time: f64, samples: &[Sample]) -> Result<(), ExportError> {
        for ((spool, attribute), sample) in
            self.spools.iter_mut().zip(&self.attributes).zip(samples)
        {
            sample_line(spool, time, attribute.tuple, sample).map_err(|source| IoError::Io {
                path: self.path.clone(),
                action: "write a temporary file beside it",
                source,
            })?;
        }
        Ok(())
    }

    /// Writes the file, atomically: the stage metadata, the prim and each attribute's spooled
    /// samples.
    pub fn finish(self, stage: &StageMetadata) -> Result<(), ExportError> {
        let mut file = AtomicFile::create(&self.path)?;
        write_layer(file.writer(), stage, &self.attributes, self.spools)
            .map_err(|source| file.error("write", source))?;
        file.commit()?;
        Ok(())
    }
}

fn write_layer(
    out: &mut impl Write,
    stage: &StageMetadata,
    attributes: &[UsdAttribute],
    spools: Vec<BufWriter<File>>,
) -> io::Result<()> {
    writeln!(out, "#usda 1.0")?;
    writeln!(out, "(")?;
    writeln!(out, "    defaultPrim = \"{PRIM}\"")?;
    writeln!(out, "    timeCodesPerSecond = {}", double(stage.fps))?;
    writeln!(out, "    framesPerSecond = {}", double(stage.fps))?;
    writeln!(out, "    startTimeCode = {}", double(stage.start))?;
    writeln!(out, "    endTimeCode = {}", double(stage.end))?;
    writeln!(out, "    upAxis = \"{}\"", stage.up_axis)?;
    writeln!(out, "    metersPerUnit = {}", double(stage.meters_per_unit))?;
    writeln!(out, ")")?;
    writeln!(out)?;
    writeln!(out, "def Mesh \"{PRIM}\"")?;
    writeln!(out, "{{")?;
    for (attribute, spool) in attributes.iter().zip(spools) {
        let (kind, name) = (attribute.type_name, &attribute.name);
        if attribute.vertex {
            writeln!(out, "    {kind} {name} (")?;
            writeln!(out, "        interpolation = \"vertex\"")?;
            if let Some(size) = attribute.element_size {
                writeln!(out, "        elementSize = {size}")?;
            }
            writeln!(out, "    )")?;
        }
        writeln!(out, "    {kind} {name}.timeSamples = {{")?;
        let mut spool = spool.into_inner().map_err(|e| e.into_error())?;
        spool.seek(SeekFrom::Start(0))?;
        io::copy(&mut spool, out)?;
        writeln!(out, "    }}")?;
    }
    let (name, value) = SUBDIVISION_SCHEME;
    writeln!(out, "    uniform token {name} = \"{value}\"")?;
    writeln!(out, "}}")?;
    Ok(())
}

/// `        time: [v, v, ...],` with `tuple` scalars per element (in parentheses when more than one).
fn sample_line(out: &mut impl Write, time: f64, tuple: usize, sample: &Sample) -> io::Result<()> {
    write!(out, "        {}: [", double(time))?;
    match sample {
        Sample::Ints(values) => {
            for (i, v) in values.iter().enumerate() {
                if i > 0 {
                    out.write_all(b", ")?;
                }
                write!(out, "{v}")?;
            }
        }
        Sample::Floats(values) => {
            for (i, element) in values.chunks(tuple).enumerate() {
                if i > 0 {
                    out.write_all(b", ")?;
                }
                if tuple > 1 {
                    out.write_all(b"(")?;
                }
                for (j, &v) in element.iter().enumerate() {
                    if j > 0 {
                        out.write_all(b", ")?;
                    }
                    out.write_all(double(f64::from(v)).as_bytes())?;
                }
                if tuple > 1 {
                    out.write_all(b")")?;
                }
            }
        }
    }
    writeln!(out, "],")
}

/// A number as usda reads it back exactly: the shortest decimal of the double (a float widened to
/// a double keeps its value, so it reads back as the same float), `inf`, `-inf` or `nan`.
fn double(v: f64) -> String {
    if v.is_nan() {
        "nan".into()
    } else if v.is_infinite() {
        if v > 0.0 { "inf".into() } else { "-inf".into() }
    } else {
        format!("{v:?}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(tuple: usize, sample: &Sample) -> String {
        let mut out = Vec::new();
        sample_line(&mut out, 1.0, tuple, sample).unwrap();
        String::from_utf8(out).unwrap()
    }

    #[test]
    fn samples_are_written_as_usda_arrays_that_read_back_exactly() {
        assert_eq!(
            line(1, &Sample::Ints(vec![3, -1, 7])),
            "        1.0: [3, -1, 7],\n"
        );
        assert_eq!(
            line(2, &Sample::Floats(vec![0.1, -2.0, 1e-20, f32::INFINITY])),
            "        1.0: [(0.10000000149011612, -2.0), (9.999999682655225e-21, inf)],\n"
        );
        // The widened float's shortest decimal reads back as the same float.
        assert_eq!(
            "9.999999682655225e-21".parse::<f64>().unwrap() as f32,
            1e-20f32
        );
        assert_eq!(line(3, &Sample::Floats(Vec::new())), "        1.0: [],\n");
    }
}
