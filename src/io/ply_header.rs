//! The PLY header: encoding, elements and their properties (Turk's PLY format, as written by
//! Blender, Houdini, MeshLab, VTK and others).

use super::IoError;
use std::path::Path;

/// How the body after `end_header` is encoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlyEncoding {
    Ascii,
    BinaryLittleEndian,
    BinaryBigEndian,
}

impl PlyEncoding {
    pub(crate) fn keyword(self) -> &'static str {
        match self {
            PlyEncoding::Ascii => "ascii",
            PlyEncoding::BinaryLittleEndian => "binary_little_endian",
            PlyEncoding::BinaryBigEndian => "binary_big_endian",
        }
    }
}

/// The scalar types of the PLY format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    /// Both the original names (`uchar`) and the sized ones (`uint8`) are accepted.
    fn parse(name: &str) -> Option<Scalar> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    /// The original name, which every PLY reader knows.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Scalar::I8 => "char",
            Scalar::U8 => "uchar",
            Scalar::I16 => "short",
            Scalar::U16 => "ushort",
            Scalar::I32 => "int",
            Scalar::U32 => "uint",
            Scalar::F32 => "float",
            Scalar::F64 => "double",
        }
    }

    pub(crate) fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    pub(crate) fn is_integer(self) -> bool {
        !matches!(self, Scalar::F32 | Scalar::F64)
    }

    /// The inclusive range of an integer type (every value is exact in an f64).
    pub(crate) fn integer_range(self) -> (f64, f64) {
        match self {
            Scalar::I8 => (i8::MIN.into(), i8::MAX.into()),
            Scalar::U8 => (0.0, u8::MAX.into()),
            Scalar::I16 => (i16::MIN.into(), i16::MAX.into()),
            Scalar::U16 => (0.0, u16::MAX.into()),
            Scalar::I32 => (i32::MIN.into(), i32::MAX.into()),
            Scalar::U32 => (0.0, u32::MAX.into()),
            Scalar::F32 | Scalar::F64 => (f64::NEG_INFINITY, f64::INFINITY),
        }
    }

    /// Decodes one value from exactly `self.size()` bytes; every type converts to f64 exactly.
    #[inline(always)]
    pub(crate) fn decode(self, bytes: &[u8], big_endian: bool) -> f64 {
        #[inline(always)]
        fn array<const N: usize>(bytes: &[u8], big_endian: bool) -> [u8; N] {
            let mut a = [0u8; N];
            a.copy_from_slice(&bytes[..N]);
            if big_endian {
                a.reverse();
            }
            a
        }
        match self {
            Scalar::I8 => f64::from(bytes[0] as i8),
            Scalar::U8 => f64::from(bytes[0]),
            Scalar::I16 => f64::from(i16::from_le_bytes(array(bytes, big_endian))),
            Scalar::U16 => f64::from(u16::from_le_bytes(array(bytes, big_endian))),
            Scalar::I32 => f64::from(i32::from_le_bytes(array(bytes, big_endian))),
            Scalar::U32 => f64::from(u32::from_le_bytes(array(bytes, big_endian))),
            Scalar::F32 => f64::from(f32::from_le_bytes(array(bytes, big_endian))),
            Scalar::F64 => f64::from_le_bytes(array(bytes, big_endian)),
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum PropertyKind {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Property {
    pub name: String,
    pub kind: PropertyKind,
    /// The header line declaring it.
    pub line: usize,
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Element {
    pub name: String,
    pub count: usize,
    pub properties: Vec<Property>,
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Header {
    pub encoding: PlyEncoding,
    pub elements: Vec<Element>,
    /// Byte offset of the body (just after the `end_header` line).
    pub body_offset: usize,
    /// Number of header lines, so body line numbers continue from it.
    pub lines: usize,
}

/// Parses the header at the start of `data`.
pub(crate) fn parse_header(path: &Path, data: &[u8]) -> Result<Header, IoError> {
    let bad = |line: usize, reason: String| IoError::BadHeader {
        path: path.to_path_buf(),
        line,
        reason,
    };
    let mut offset = 0;
    let mut line_number = 0;
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    loop {
        if offset >= data.len() {
            return Err(if line_number == 0 {
                not_ply(path)
            } else {
                bad(line_number, "the header has no end_header line".into())
            });
        }
        let len = data[offset..]
            .iter()
            .position(|&b| b == b'\n')
            .unwrap_or(data.len() - offset);
        let raw = &data[offset..offset + len];
        offset = (offset + len + 1).min(data.len());
        line_number += 1;
        let raw = raw.strip_suffix(b"\r").unwrap_or(raw);
        let Ok(line) = std::str::from_utf8(raw) else {
            return Err(if line_number == 1 {
                not_ply(path)
            } else {
                bad(line_number, "not text".into())
            });
        };
        if line_number == 1 {
            if line.trim_end() != "ply" {
                return Err(not_ply(path));
            }
            continue;
        }
        let words: Vec<&str> = line.split_ascii_whitespace().collect();
        match words.as_slice() {
            [] | ["comment", ..] | ["obj_info", ..] => {}
            ["format", name, _version] => {
                encoding = Some(match *name {
                    "ascii" => PlyEncoding::Ascii,
                    "binary_little_endian" => PlyEncoding::BinaryLittleEndian,
                    "binary_big_endian" => PlyEncoding::BinaryBigEndian,
                    other => return Err(bad(line_number, format!("unknown format {other:?}"))),
                });
            }
            ["element", name, count] => {
                let count = count.parse::<usize>().map_err(|_| {
                    bad(
                        line_number,
                        format!("element count {count:?} is not a non-negative integer"),
                    )
                })?;
                if elements.iter().any(|e| e.name == *name) {
                    return Err(bad(line_number, format!("element {name:?} declared twice")));
                }
                elements.push(Element {
                    name: (*name).to_string(),
                    count,
                    properties: Vec::new(),
                });
            }
            ["property", rest @ ..] => {
                let (kind, name) = match rest {
                    ["list", count, item, name] => {
                        let count = scalar(count).map_err(|r| bad(line_number, r))?;
                        let item = scalar(item).map_err(|r| bad(line_number, r))?;
                        if !count.is_integer() {
                            return Err(bad(
                                line_number,
                                format!("list count type {} is not an integer type", count.name()),
                            ));
                        }
                        (PropertyKind::List { count, item }, name)
                    }
                    [ty, name] => (
                        PropertyKind::Scalar(scalar(ty).map_err(|r| bad(line_number, r))?),
                        name,
                    ),
                    _ => {
                        return Err(bad(
                            line_number,
                            format!("malformed property line {line:?}"),
                        ));
                    }
                };
                let Some(element) = elements.last_mut() else {
                    return Err(bad(line_number, "property before any element".into()));
                };
                if element.properties.iter().any(|p| p.name == *name) {
                    return Err(bad(
                        line_number,
                        format!(
                            "property {name:?} declared twice in element {:?}",
                            element.name
                        ),
                    ));
                }
                element.properties.push(Property {
                    name: (*name).to_string(),
                    kind,
                    line: line_number,
                });
            }
            ["end_header"] => break,
            _ => return Err(bad(line_number, format!("unexpected line {line:?}"))),
        }
    }
    let encoding = encoding.ok_or_else(|| bad(line_number, "no format line".into()))?;
    Ok(Header {
        encoding,
        elements,
        body_offset: offset,
        lines: line_number,
    })
}

fn scalar(name: &str) -> Result<Scalar, String> {
    Scalar::parse(name).ok_or_else(|| format!("unknown property type {name:?}"))
}

fn not_ply(path: &Path) -> IoError {
    IoError::WrongFormat {
        path: path.to_path_buf(),
        format: "PLY",
        reason: "it does not start with the line \"ply\"".into(),
    }
}
