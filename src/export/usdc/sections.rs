//! The structural sections of a crate file, in their compressed form (file version 0.4.0 on):
//! `TOKENS` (every name and token value), `STRINGS` (none here), `FIELDS` (name and value of each
//! field), `FIELDSETS` (each spec's fields, runs ended by `!0`), `PATHS` (the path tree) and
//! `SPECS` (path, field set and type of each spec). Each is written whole at the end of the file;
//! the table of contents names where.

use super::int_coding;
use super::lz4;
use super::value_rep::ValueRep;
use rustc_hash::FxHashMap;
use std::io;

/// The kinds of spec this layer has, numbered as USD's `SdfSpecType`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpecType {
    Attribute = 1,
    Prim = 6,
    PseudoRoot = 7,
}

/// The token table: each distinct token once, referred to by index.
#[derive(Debug)]
pub struct Tokens {
    names: Vec<String>,
    index: FxHashMap<String, u32>,
}

impl Tokens {
    /// A table whose token 0 is the empty token, the pseudo-root's path element. Property names are
    /// never empty, so none has index 0, whose sign could not mark it as a property in `PATHS`.
    pub fn new() -> Self {
        let mut tokens = Self {
            names: Vec::new(),
            index: FxHashMap::default(),
        };
        tokens.get("");
        tokens
    }

    /// The index of `name`, added if new.
    pub fn get(&mut self, name: &str) -> u32 {
        if let Some(&i) = self.index.get(name) {
            return i;
        }
        let i = self.names.len() as u32;
        self.names.push(name.to_string());
        self.index.insert(name.to_string(), i);
        i
    }

    /// `TOKENS`: the count, then the NUL-terminated names, their size and compressed.
    pub fn section(&self) -> io::Result<Vec<u8>> {
        let mut text = Vec::new();
        for name in &self.names {
            text.extend(name.as_bytes());
            text.push(0);
        }
        let packed = lz4::compress(&text)?;
        let mut out = Vec::new();
        put_u64(&mut out, self.names.len());
        put_u64(&mut out, text.len());
        put_u64(&mut out, packed.len());
        out.extend(packed);
        Ok(out)
    }
}

/// The specs with their fields.
#[derive(Debug, Default)]
pub struct Specs {
    /// Field name token and value.
    fields: Vec<(u32, ValueRep)>,
    /// Field indices of each spec in turn, each run ended by `!0`.
    field_sets: Vec<u32>,
    /// Path index, first field-set entry and type of each spec.
    specs: Vec<(u32, u32, SpecType)>,
}

impl Specs {
    /// Adds the spec of path `path` with `fields` (name token, value).
    pub fn add(&mut self, path: u32, kind: SpecType, fields: &[(u32, ValueRep)]) {
        let set = self.field_sets.len() as u32;
        for &field in fields {
            self.field_sets.push(self.fields.len() as u32);
            self.fields.push(field);
        }
        self.field_sets.push(!0);
        self.specs.push((path, set, kind));
    }

    /// `FIELDS`: the count, the compressed name tokens, the compressed value reps.
    pub fn fields_section(&self) -> io::Result<Vec<u8>> {
        let mut out = Vec::new();
        put_u64(&mut out, self.fields.len());
        let names: Vec<u32> = self.fields.iter().map(|f| f.0).collect();
        put_ints(&mut out, &names)?;
        let reps: Vec<u8> = self
            .fields
            .iter()
            .flat_map(|f| f.1.0.to_le_bytes())
            .collect();
        let packed = lz4::compress(&reps)?;
        put_u64(&mut out, packed.len());
        out.extend(packed);
        Ok(out)
    }

    /// `FIELDSETS`: the count and the compressed field indices.
    pub fn field_sets_section(&self) -> io::Result<Vec<u8>> {
        let mut out = Vec::new();
        put_u64(&mut out, self.field_sets.len());
        put_ints(&mut out, &self.field_sets)?;
        Ok(out)
    }

    /// `SPECS`: the count, then compressed path indices, field-set indices and spec types.
    pub fn specs_section(&self) -> io::Result<Vec<u8>> {
        let mut out = Vec::new();
        put_u64(&mut out, self.specs.len());
        let column = |f: fn(&(u32, u32, SpecType)) -> u32| -> Vec<u32> {
            self.specs.iter().map(f).collect()
        };
        put_ints(&mut out, &column(|s| s.0))?;
        put_ints(&mut out, &column(|s| s.1))?;
        put_ints(&mut out, &column(|s| s.2 as u32))?;
        Ok(out)
    }
}

/// `PATHS` of a layer with one prim under the pseudo-root and properties on that prim: path 0 is
/// `/`, path 1 the prim (`prim` its name token), path `2 + i` property `i`. The tree is stored
/// depth first as three compressed columns: path index, element token (negated for a property)
/// and a jump code (-1: the next entry is the only child, 0: the next is the sibling, -2: a leaf
/// without siblings).
pub fn paths_section(prim: u32, properties: &[u32]) -> io::Result<Vec<u8>> {
    let count = 2 + properties.len();
    let indices: Vec<u32> = (0..count as u32).collect();
    let mut elements = vec![0, prim as i32];
    elements.extend(properties.iter().map(|&p| -(p as i32)));
    let mut jumps = vec![-1, if properties.is_empty() { -2 } else { -1 }];
    jumps.extend((0..properties.len()).map(|i| if i + 1 < properties.len() { 0 } else { -2 }));
    let mut out = Vec::new();
    put_u64(&mut out, count);
    put_u64(&mut out, count);
    put_ints(&mut out, &indices)?;
    put_signed_ints(&mut out, &elements)?;
    put_signed_ints(&mut out, &jumps)?;
    Ok(out)
}

fn put_u64(out: &mut Vec<u8>, n: usize) {
    out.extend((n as u64).to_le_bytes());
}

/// Unsigned indices as USD codes them: the same 32 bits read as signed (`!0` is -1).
fn put_ints(out: &mut Vec<u8>, values: &[u32]) -> io::Result<()> {
    let signed: Vec<i32> = values.iter().map(|&v| v as i32).collect();
    put_signed_ints(out, &signed)
}

/// The compressed size, then the compressed integers.
fn put_signed_ints(out: &mut Vec<u8>, values: &[i32]) -> io::Result<()> {
    let packed = int_coding::compress(values)?;
    put_u64(out, packed.len());
    out.extend(packed);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::export::usdc::value_rep::CrateType;

    #[test]
    fn tokens_are_numbered_once_from_the_empty_token() {
        let mut tokens = Tokens::new();
        assert_eq!(tokens.get("points"), 1);
        assert_eq!(tokens.get("Mesh"), 2);
        assert_eq!(tokens.get("points"), 1);
        let section = tokens.section().unwrap();
        assert_eq!(section[..8], 3u64.to_le_bytes());
        assert_eq!(section[8..16], 13u64.to_le_bytes());
        let text = lz4_flex::block::decompress(&section[25..], 13).unwrap();
        assert_eq!(text, b"\0points\0Mesh\0");
    }

    #[test]
    fn field_sets_are_runs_ended_by_all_ones() {
        let mut specs = Specs::default();
        let rep = ValueRep::inlined(CrateType::Int, 1);
        specs.add(0, SpecType::PseudoRoot, &[(1, rep), (2, rep)]);
        specs.add(1, SpecType::Prim, &[(3, rep)]);
        assert_eq!(specs.field_sets, [0, 1, !0, 2, !0]);
        assert_eq!(
            specs.specs,
            [(0, 0, SpecType::PseudoRoot), (1, 3, SpecType::Prim)]
        );
    }
}
