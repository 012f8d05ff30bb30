//! The layer as a binary USD crate file (`.usdc`), streamed: each frame's arrays are written into
//! the file as the frame arrives and only their 8-byte references stay in memory; at the end come
//! the time samples (the shared times and each attribute's references), the specs' other values,
//! the structural sections and the table of contents, and the header is patched to point at it.
//!
//! Layout: an 88-byte header (`PXR-USDC`, the version, the table of contents' offset, reserved
//! zeros), the values, the sections `TOKENS`, `STRINGS`, `FIELDS`, `FIELDSETS`, `PATHS`, `SPECS`,
//! and the table of contents (a count, then per section a NUL-padded 16-byte name, its offset and
//! size). Everything is little-endian, as in USD's `crateFile.cpp`.
//!
//! The file is version 0.8.0: every USD release since 19.03 reads it, and USD wrote new files in
//! it by default from 20.11 until 24.03, when 0.9.0 (time-code values, which this layer does not
//! have) took over; so the DCCs and renderers in use read it. It has what this layer needs:
//! compressed structural sections (0.4.0), compressed int arrays (0.5.0) and 64-bit array sizes
//! (0.7.0). Float arrays are written uncompressed, which every version reads (USD compresses
//! only float arrays of whole numbers or few distinct values, which points are not).

mod int_coding;
mod lz4;
mod sections;
mod value_rep;

use super::ExportError;
use super::usd::{PRIM, SUBDIVISION_SCHEME, Sample, StageMetadata, UsdAttribute};
use crate::io::AtomicFile;
use sections::{SpecType, Specs, Tokens, paths_section};
use std::io::{self, Seek, SeekFrom, Write};
use std::path::Path;
use value_rep::{CrateType, ValueRep};

/// File format version written in the header: major, minor, patch.
const VERSION: [u8; 3] = [0, 8, 0];
/// Size of the header: identifier, version, table of contents offset, 8 reserved `i64`.
const HEADER: usize = 88;
/// Int arrays shorter than this are written plainly, as USD does (and expects).
const MIN_COMPRESSED_INTS: usize = 16;
/// `SdfSpecifierDef`.
const DEF: u32 = 0;
/// `SdfVariabilityVarying`, `SdfVariabilityUniform`.
const VARYING: u32 = 0;
const UNIFORM: u32 = 1;

/// A `.usdc` file being written.
#[derive(Debug)]
pub struct UsdcWriter {
    file: AtomicFile,
    /// Bytes written so far: the offset of the next value.
    at: u64,
    attributes: Vec<UsdAttribute>,
    /// Per attribute, the reference of each frame's sample.
    samples: Vec<Vec<ValueRep>>,
    times: Vec<f64>,
}

impl UsdcWriter {
    /// Starts the file (as a temporary file beside `path`) with a header to be completed.
    pub fn create(path: &Path, attributes: Vec<UsdAttribute>) -> Result<Self, ExportError> {
        let mut writer = Self {
            file: AtomicFile::create(path)?,
            at: 0,
            samples: vec![Vec::new(); attributes.len()],
            attributes,
            times: Vec::new(),
        };
        writer
            .put(&[0; HEADER])
            .map_err(|source| writer.file.error("write", source))?;
        Ok(writer)
    }

    /// Writes one sample per attribute at `time`.
    pub fn push(&mut self, time: f64, samples: &[Sample]) -> Result<(), ExportError> {
        let tuples: Vec<usize> = self.attributes.iter().map(|a| a.tuple).collect();
        let mut reps = Vec::with_capacity(samples.len());
        for (sample, tuple) in samples.iter().zip(tuples) {
            let rep = match sample {
                Sample::Ints(values) => self.ints(values),
                Sample::Floats(values) => self.floats(tuple, values),
            };
            reps.push(rep.map_err(|source| self.file.error("write", source))?);
        }
        for (list, rep) in self.samples.iter_mut().zip(reps) {
            list.push(rep);
        }
        self.times.push(time);
        Ok(())
    }

    /// Writes the specs, the structural sections and the table of contents, then renames the file
    /// into place.
    pub fn finish(mut self, stage: &StageMetadata) -> Result<(), ExportError> {
        self.close(stage)
            .map_err(|source| self.file.error("write", source))?;
        self.file.commit()?;
        Ok(())
    }

    fn close(&mut self, stage: &StageMetadata) -> io::Result<()> {
        let mut tokens = Tokens::new();
        let (specs, properties) = self.specs(&mut tokens, stage)?;
        let toc = self.sections(&mut tokens, &specs, &properties)?;
        self.header(toc)
    }

    /// Writes the values of the specs' fields (the stage metadata, the prim's property list, each
    /// attribute's time samples) and gives the specs and the property name tokens.
    fn specs(
        &mut self,
        tokens: &mut Tokens,
        stage: &StageMetadata,
    ) -> io::Result<(Specs, Vec<u32>)> {
        let attributes = std::mem::take(&mut self.attributes);
        let samples = std::mem::take(&mut self.samples);
        let mut specs = Specs::default();
        let token =
            |tokens: &mut Tokens, name: &str| ValueRep::inlined(CrateType::Token, tokens.get(name));

        let children = self.token_vector(tokens, &[PRIM])?;
        let root = [
            (tokens.get("primChildren"), children),
            (tokens.get("defaultPrim"), token(tokens, PRIM)),
            (tokens.get("timeCodesPerSecond"), self.double(stage.fps)?),
            (tokens.get("framesPerSecond"), self.double(stage.fps)?),
            (tokens.get("startTimeCode"), self.double(stage.start)?),
            (tokens.get("endTimeCode"), self.double(stage.end)?),
            (tokens.get("upAxis"), token(tokens, stage.up_axis)),
            (
                tokens.get("metersPerUnit"),
                self.double(stage.meters_per_unit)?,
            ),
        ];
        specs.add(0, SpecType::PseudoRoot, &root);

        let (scheme, scheme_value) = SUBDIVISION_SCHEME;
        let mut names: Vec<&str> = attributes.iter().map(|a| a.name.as_str()).collect();
        names.push(scheme);
        let properties = self.token_vector(tokens, &names)?;
        let mesh = [
            (
                tokens.get("specifier"),
                ValueRep::inlined(CrateType::Specifier, DEF),
            ),
            (tokens.get("typeName"), token(tokens, "Mesh")),
            (tokens.get("properties"), properties),
        ];
        specs.add(1, SpecType::Prim, &mesh);

        let times = self.times()?;
        let mut path = 2;
        for (attribute, reps) in attributes.iter().zip(&samples) {
            let mut fields = vec![
                (tokens.get("typeName"), token(tokens, attribute.type_name)),
                (
                    tokens.get("variability"),
                    ValueRep::inlined(CrateType::Variability, VARYING),
                ),
            ];
            if attribute.vertex {
                fields.push((tokens.get("interpolation"), token(tokens, "vertex")));
            }
            if let Some(size) = attribute.element_size {
                fields.push((
                    tokens.get("elementSize"),
                    ValueRep::inlined(CrateType::Int, size as u32),
                ));
            }
            fields.push((tokens.get("timeSamples"), self.time_samples(times, reps)?));
            specs.add(path, SpecType::Attribute, &fields);
            path += 1;
        }
        let fields = [
            (tokens.get("typeName"), token(tokens, "token")),
            (
                tokens.get("variability"),
                ValueRep::inlined(CrateType::Variability, UNIFORM),
            ),
            (tokens.get("default"), token(tokens, scheme_value)),
        ];
        specs.add(path, SpecType::Attribute, &fields);

        let properties = names.iter().map(|n| tokens.get(n)).collect();
        Ok((specs, properties))
    }

    /// Writes the structural sections and the table of contents; gives the table's offset.
    fn sections(
        &mut self,
        tokens: &mut Tokens,
        specs: &Specs,
        properties: &[u32],
    ) -> io::Result<u64> {
        let prim = tokens.get(PRIM);
        let paths = paths_section(prim, properties)?;
        let no_strings = 0u64.to_le_bytes().to_vec();
        let mut toc = Vec::new();
        for (name, bytes) in [
            ("TOKENS", tokens.section()?),
            ("STRINGS", no_strings),
            ("FIELDS", specs.fields_section()?),
            ("FIELDSETS", specs.field_sets_section()?),
            ("PATHS", paths),
            ("SPECS", specs.specs_section()?),
        ] {
            toc.push((name, self.at, bytes.len() as u64));
            self.put(&bytes)?;
        }
        let toc_offset = self.at;
        let mut table = (toc.len() as u64).to_le_bytes().to_vec();
        for (name, start, size) in toc {
            let mut padded = [0u8; 16];
            padded[..name.len()].copy_from_slice(name.as_bytes());
            table.extend(padded);
            table.extend(start.to_le_bytes());
            table.extend(size.to_le_bytes());
        }
        self.put(&table)?;
        Ok(toc_offset)
    }

    /// Completes the header: identifier, version and the offset of the table of contents.
    fn header(&mut self, toc_offset: u64) -> io::Result<()> {
        let mut header = Vec::with_capacity(HEADER);
        header.extend(b"PXR-USDC");
        header.extend(VERSION);
        header.extend([0; 5]);
        header.extend(toc_offset.to_le_bytes());
        header.resize(HEADER, 0);
        let out = self.file.writer();
        out.seek(SeekFrom::Start(0))?;
        out.write_all(&header)?;
        Ok(())
    }

    fn put(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.file.writer().write_all(bytes)?;
        self.at += bytes.len() as u64;
        Ok(())
    }

    /// Pads to a multiple of 8 bytes, so that readers can map arrays in place.
    fn align(&mut self) -> io::Result<()> {
        let pad = self.at.next_multiple_of(8) - self.at;
        self.put(&[0; 8][..pad as usize])
    }

    /// An array of floats, `tuple` per element: its element count, then the floats.
    fn floats(&mut self, tuple: usize, values: &[f32]) -> io::Result<ValueRep> {
        let kind = CrateType::floats(tuple);
        if values.is_empty() {
            return Ok(ValueRep::array(kind, 0));
        }
        self.align()?;
        let rep = ValueRep::array(kind, self.at);
        let mut bytes = Vec::with_capacity(8 + 4 * values.len());
        bytes.extend(((values.len() / tuple) as u64).to_le_bytes());
        bytes.extend(values.iter().flat_map(|v| v.to_le_bytes()));
        self.put(&bytes)?;
        Ok(rep)
    }

    /// An array of ints: its count, then the ints, compressed (with their compressed size) from
    /// [`MIN_COMPRESSED_INTS`] on.
    fn ints(&mut self, values: &[i32]) -> io::Result<ValueRep> {
        if values.is_empty() {
            return Ok(ValueRep::array(CrateType::Int, 0));
        }
        self.align()?;
        let rep = ValueRep::array(CrateType::Int, self.at);
        let mut bytes = (values.len() as u64).to_le_bytes().to_vec();
        if values.len() < MIN_COMPRESSED_INTS {
            bytes.extend(values.iter().flat_map(|v| v.to_le_bytes()));
            self.put(&bytes)?;
            return Ok(rep);
        }
        let packed = int_coding::compress(values)?;
        bytes.extend((packed.len() as u64).to_le_bytes());
        bytes.extend(packed);
        self.put(&bytes)?;
        Ok(rep.compressed())
    }

    /// A double: inlined as a float when that is exact, else written out.
    fn double(&mut self, v: f64) -> io::Result<ValueRep> {
        let narrow = v as f32;
        if f64::from(narrow) == v {
            return Ok(ValueRep::inlined(CrateType::Double, narrow.to_bits()));
        }
        let rep = ValueRep::at(CrateType::Double, self.at);
        self.put(&v.to_le_bytes())?;
        Ok(rep)
    }

    /// A list of tokens: its length, then the token indices.
    fn token_vector(&mut self, tokens: &mut Tokens, names: &[&str]) -> io::Result<ValueRep> {
        let rep = ValueRep::at(CrateType::TokenVector, self.at);
        let mut bytes = (names.len() as u64).to_le_bytes().to_vec();
        bytes.extend(names.iter().flat_map(|n| tokens.get(n).to_le_bytes()));
        self.put(&bytes)?;
        Ok(rep)
    }

    /// The sample times, written once and shared by every attribute's time samples.
    fn times(&mut self) -> io::Result<ValueRep> {
        let rep = ValueRep::at(CrateType::DoubleVector, self.at);
        let mut bytes = (self.times.len() as u64).to_le_bytes().to_vec();
        bytes.extend(self.times.iter().flat_map(|t| t.to_le_bytes()));
        self.put(&bytes)?;
        Ok(rep)
    }

    /// One attribute's time samples: a jump of 8 (to the next word), the times' reference, a jump
    /// of 8, the sample count and each sample's reference. (USD writes nested values between a
    /// jump and what it skips to; here they are all written before.)
    fn time_samples(&mut self, times: ValueRep, reps: &[ValueRep]) -> io::Result<ValueRep> {
        let rep = ValueRep::at(CrateType::TimeSamples, self.at);
        let mut bytes = Vec::with_capacity(32 + 8 * reps.len());
        bytes.extend(8i64.to_le_bytes());
        bytes.extend(times.0.to_le_bytes());
        bytes.extend(8i64.to_le_bytes());
        bytes.extend((reps.len() as u64).to_le_bytes());
        bytes.extend(reps.iter().flat_map(|r| r.0.to_le_bytes()));
        self.put(&bytes)?;
        Ok(rep)
    }
}
