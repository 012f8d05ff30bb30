//! A USD file fed frame by frame, in the form its extension names: `.usda` text, `.usdc` or `.usd`
//! the binary crate format (USD's own default for `.usd`).

use super::ExportError;
use super::usd::{FrameSampler, StageMetadata, UsdSettings};
use super::usda::UsdaWriter;
use super::usdc::UsdcWriter;
use crate::apps::VelocityFrame;
use std::path::{Path, PathBuf};

/// The two forms of a USD layer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UsdForm {
    Text,
    Crate,
}

impl UsdForm {
    /// The form `path`'s extension names, if it is a USD one.
    pub fn of(path: &Path) -> Option<Self> {
        match path.extension().and_then(|e| e.to_str()) {
            Some("usda") => Some(Self::Text),
            Some("usdc" | "usd") => Some(Self::Crate),
            _ => None,
        }
    }
}

#[derive(Debug)]
enum Writer {
    Text(UsdaWriter),
    Crate(UsdcWriter),
}

/// A USD file being written: the first frame fixes its attributes, each frame adds a sample to
/// each, and [`UsdFile::finish`] completes it (nothing is at `path` before then).
#[derive(Debug)]
pub struct UsdFile {
    path: PathBuf,
    form: UsdForm,
    settings: UsdSettings,
    /// Set by the first frame.
    open: Option<(FrameSampler, Writer)>,
    frames: usize,
}

impl UsdFile {
    pub fn new(path: &Path, form: UsdForm, settings: UsdSettings) -> Self {
        Self {
            path: path.to_path_buf(),
            form,
            settings,
            open: None,
            frames: 0,
        }
    }

    /// Adds `frame`, read from `source` (named in errors).
    pub fn push(&mut self, frame: &VelocityFrame, source: &Path) -> Result<(), ExportError> {
        let (sampler, writer) = match &mut self.open {
            Some(open) => open,
            None => {
                let sampler = FrameSampler::new(frame, source)?;
                let attributes = sampler.attributes().to_vec();
                let writer = match self.form {
                    UsdForm::Text => Writer::Text(UsdaWriter::create(&self.path, attributes)?),
                    UsdForm::Crate => Writer::Crate(UsdcWriter::create(&self.path, attributes)?),
                };
                self.open.insert((sampler, writer))
            }
        };
        let samples = sampler.samples(frame, source)?;
        let time = self.settings.start + frame.index as f64;
        match writer {
            Writer::Text(w) => w.push(time, &samples)?,
            Writer::Crate(w) => w.push(time, &samples)?,
        }
        self.frames += 1;
        Ok(())
    }

    /// Completes the file and moves it into place.
    pub fn finish(self) -> Result<(), ExportError> {
        let stage = StageMetadata::new(&self.settings, self.frames);
        match self.open {
            Some((_, Writer::Text(w))) => w.finish(&stage),
            Some((_, Writer::Crate(w))) => w.finish(&stage),
            None => Err(ExportError::Usd {
                path: self.path,
                reason: "the tracked sequence has no frames".into(),
            }),
        }
    }
}
