//! Reading PLY frames: one walk over the elements declared in the header, for ASCII and both
//! binary byte orders. Unknown elements and properties are read past (their sizes are known from
//! the header), polygons are fan-triangulated.

use super::IoError;
use super::error::Location;
use super::file::read_bytes;
use super::ply_header::{Element, PlyEncoding, PropertyKind, parse_header};
use super::ply_layout::{Layout, Role};
use super::ply_values::{Ascii, Binary, Fault, Values};
use crate::mesh::{Attribute, IndexedMesh};
use glam::Vec3;
use std::path::Path;

/// Largest id a `double` property holds exactly.
const MAX_EXACT_ID: f64 = (1u64 << 53) as f64;

/// Reads a PLY frame without repairing it.
pub(crate) fn read_ply(path: &Path) -> Result<IndexedMesh, IoError> {
    let data = read_bytes(path)?;
    let header = parse_header(path, &data)?;
    let layout = Layout::new(path, &header)?;
    let body = &data[header.body_offset..];
    let mesh = match header.encoding {
        PlyEncoding::Ascii => walk(
            path,
            &header.elements,
            &layout,
            &mut Ascii::new(body, header.lines + 1),
        ),
        PlyEncoding::BinaryLittleEndian => walk(
            path,
            &header.elements,
            &layout,
            &mut Binary::<false>::new(body),
        ),
        PlyEncoding::BinaryBigEndian => walk(
            path,
            &header.elements,
            &layout,
            &mut Binary::<true>::new(body),
        ),
    }?;
    if mesh.positions.is_empty() && mesh.triangles.is_empty() {
        return Err(IoError::Empty {
            path: path.to_path_buf(),
        });
    }
    Ok(mesh)
}

/// What is wrong with one record, before the file and location are known.
enum Problem {
    Fault(Fault),
    IndexOutOfRange(f64),
    NonFinite([f64; 3]),
    BadId(f64),
    NegativeCount(f64),
}

impl From<Fault> for Problem {
    fn from(fault: Fault) -> Self {
        Problem::Fault(fault)
    }
}

/// Everything read so far.
struct Sink {
    positions: Vec<Vec3>,
    ids: Vec<u64>,
    /// Vertex-major channel values, `layout.channels` per vertex.
    channels: Vec<f32>,
    triangles: Vec<[u32; 3]>,
    /// Scratch for the current record.
    record: Vec<f32>,
    corners: Vec<u32>,
}

fn walk<V: Values>(
    path: &Path,
    elements: &[Element],
    layout: &Layout,
    values: &mut V,
) -> Result<IndexedMesh, IoError> {
    let mut sink = Sink {
        positions: Vec::new(),
        ids: Vec::new(),
        channels: Vec::new(),
        triangles: Vec::new(),
        record: vec![0.0; layout.channels],
        corners: Vec::new(),
    };
    for (e, element) in elements.iter().enumerate() {
        if element.properties.is_empty() {
            continue;
        }
        let roles = &layout.roles[e];
        let is_vertex = e == layout.vertex_element;
        let is_face = roles.contains(&Role::Corners);
        // Every value takes at least one byte, which bounds the records the file can hold.
        let capacity = element
            .count
            .min(values.max_records(element.properties.len()));
        if is_vertex {
            sink.positions.reserve(capacity);
            if layout.has_id {
                sink.ids.reserve(capacity);
            }
            sink.channels.reserve(capacity * layout.channels);
        }
        if is_face {
            sink.triangles.reserve(capacity);
        }
        for index in 0..element.count {
            let result =
                read_record(values, element, roles, layout, &mut sink).and_then(|(xyz, id)| {
                    if is_vertex {
                        commit_vertex(&mut sink, layout, xyz, id)
                    } else {
                        Ok(())
                    }
                });
            if let Err(problem) = result {
                return Err(describe(
                    path,
                    values.location(&element.name, index),
                    element,
                    layout,
                    problem,
                ));
            }
            if is_face {
                fan(&sink.corners, &mut sink.triangles);
            }
        }
    }
    let mut mesh = IndexedMesh::new(sink.positions, sink.triangles);
    mesh.ids = layout.has_id.then_some(sink.ids);
    let mut offset = 0;
    for (name, components) in &layout.attributes {
        let values = sink
            .channels
            .chunks_exact(layout.channels)
            .flat_map(|record| &record[offset..offset + components])
            .copied()
            .collect();
        mesh.attributes.push(Attribute {
            name: name.clone(),
            components: *components,
            values,
        });
        offset += components;
    }
    Ok(mesh)
}

/// Reads one record: returns its coordinates and id (zero where absent), and leaves its channel
/// values in `sink.record` and its face corners in `sink.corners`.
fn read_record<V: Values>(
    values: &mut V,
    element: &Element,
    roles: &[Role],
    layout: &Layout,
    sink: &mut Sink,
) -> Result<([f64; 3], f64), Problem> {
    values.begin()?;
    sink.corners.clear();
    let mut xyz = [0.0f64; 3];
    let mut id = 0.0f64;
    for (property, role) in element.properties.iter().zip(roles) {
        match property.kind {
            PropertyKind::Scalar(ty) => {
                let v = values.value(ty)?;
                match *role {
                    Role::Coordinate(axis) => xyz[axis] = v,
                    Role::Id => id = v,
                    Role::Channel { slot, divisor } => sink.record[slot] = (v / divisor) as f32,
                    Role::Ignore | Role::Corners => {}
                }
            }
            PropertyKind::List { count, item } => {
                let n = values.value(count)?;
                if n < 0.0 {
                    return Err(Problem::NegativeCount(n));
                }
                // An integer type's value, exact in f64 and below 2^32.
                let n = n as usize;
                values.check_list(n, item)?;
                for _ in 0..n {
                    let v = values.value(item)?;
                    if *role == Role::Corners {
                        if !(0.0..layout.vertex_count as f64).contains(&v) {
                            return Err(Problem::IndexOutOfRange(v));
                        }
                        sink.corners.push(v as u32);
                    }
                }
            }
        }
    }
    values.end()?;
    Ok((xyz, id))
}

/// Appends the vertex just read; coordinates must be finite in single precision, ids whole.
fn commit_vertex(sink: &mut Sink, layout: &Layout, xyz: [f64; 3], id: f64) -> Result<(), Problem> {
    let position = Vec3::from_array(xyz.map(|c| c as f32));
    if !position.is_finite() {
        return Err(Problem::NonFinite(xyz));
    }
    if layout.has_id {
        if !(0.0..=MAX_EXACT_ID).contains(&id) || id.fract() != 0.0 {
            return Err(Problem::BadId(id));
        }
        sink.ids.push(id as u64);
    }
    sink.positions.push(position);
    sink.channels.extend_from_slice(&sink.record);
    Ok(())
}

/// Fan-triangulates a polygon. A polygon with one or two corners becomes one degenerate triangle,
/// so that repair counts it among the degenerate faces it drops.
fn fan(corners: &[u32], triangles: &mut Vec<[u32; 3]>) {
    match *corners {
        [] => {}
        [a] => triangles.push([a, a, a]),
        [a, b] => triangles.push([a, b, b]),
        [a, ref rest @ ..] => {
            for pair in rest.windows(2) {
                triangles.push([a, pair[0], pair[1]]);
            }
        }
    }
}

fn describe(
    path: &Path,
    at: Location,
    element: &Element,
    layout: &Layout,
    problem: Problem,
) -> IoError {
    let path = path.to_path_buf();
    let name = &element.name;
    let malformed = |path, at, reason| IoError::Malformed { path, at, reason };
    match problem {
        Problem::Fault(Fault::Truncated) => IoError::Truncated {
            path,
            at,
            expected: format!("{} {name} records", element.count),
        },
        Problem::Fault(Fault::NotANumber(text)) => IoError::NotANumber { path, at, text },
        Problem::Fault(Fault::OutOfRange(text, ty)) => malformed(
            path,
            at,
            format!("{text} does not fit the declared type {}", ty.name()),
        ),
        Problem::Fault(Fault::MissingValue) => malformed(
            path,
            at,
            format!("the {name} record ends before all its values"),
        ),
        Problem::Fault(Fault::ExtraValues) => malformed(
            path,
            at,
            format!("the {name} record has more values than the header declares"),
        ),
        Problem::IndexOutOfRange(index) => IoError::IndexOutOfRange {
            path,
            at,
            index: index as i64,
            count: layout.vertex_count,
        },
        Problem::NonFinite([x, y, z]) => IoError::NonFinite {
            path,
            at,
            value: format!("({x}, {y}, {z})"),
        },
        Problem::BadId(id) => malformed(
            path,
            at,
            format!("vertex id {id} is not a non-negative integer"),
        ),
        Problem::NegativeCount(count) => IoError::InvalidCount {
            path,
            at,
            what: "list",
            count: count as i64,
        },
    }
}
