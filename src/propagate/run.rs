//! `propagate`: carried channels written as frames that Blender and Houdini import, plus a summary.

use super::carry::{Direction, carry};
use super::checker::Checker;
use super::displace::{Displace, displace};
use super::source::{Channel, Source, StartFrame, start_values};
use super::{PropagateError, TrackedSequence};
use crate::io::{ObjOptions, atomic_write, prepare_output_dir, write_obj, write_ply};
use crate::mesh::{Attribute, IndexedMesh};
use serde::Serialize;
use std::path::Path;

/// Name of the summary written beside the propagated frames.
pub const SUMMARY_FILE: &str = "propagate.json";

/// What to carry, which way, and what to write.
#[derive(Debug, Clone, PartialEq)]
pub struct PropagateOptions {
    pub direction: Direction,
    /// At least one; names must be distinct.
    pub channels: Vec<Channel>,
    pub displace: Option<Displace>,
    /// Binary PLY with the persistent `id` and every channel as vertex properties.
    pub ply: bool,
    /// OBJ with `vt` from a `uv` channel and vertex colours from a 3-component `color` channel.
    pub obj: bool,
}

/// What a run did, also written as `propagate.json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PropagateSummary {
    pub direction: Direction,
    pub start: StartFrame,
    /// `(name, components)` of each carried channel, in PLY property order.
    pub channels: Vec<(String, usize)>,
    /// The checkerboard painted on the start frame, when a channel is a checker.
    pub checker: Option<Checker>,
    /// Displacement along normals, in world units per unit of the scalar.
    pub displacement: Option<f32>,
    /// Vertex count of each frame, frame 0 first.
    pub vertices: Vec<usize>,
}

/// Carries `options.channels` through the tracked sequence in `tracked` and writes one file per
/// frame and format into `out` (`frame_NNNN.ply`, `frame_NNNN.obj`) and the summary last.
///
/// `out` is created if missing and refused when it holds anything unless `force` is set; every write
/// is atomic.
pub fn propagate(
    tracked: &Path,
    out: &Path,
    options: &PropagateOptions,
    force: bool,
) -> Result<PropagateSummary, PropagateError> {
    check(options)?;
    let sequence = TrackedSequence::open(tracked)?;
    let first = options.direction.start(sequence.len());
    let mesh = sequence.read_frame(first)?;
    let start = StartFrame::of(first, &mesh);
    let channels: Vec<Attribute> = options
        .channels
        .iter()
        .map(|c| start_values(c, &mesh, &start))
        .collect::<Result<_, _>>()?;
    let displacement = options
        .displace
        .as_ref()
        .map(|d| {
            if channels.iter().any(|c| c.name == d.channel) {
                Ok(d.scale * start.mean_edge_length)
            } else {
                Err(PropagateError::NoDisplaceChannel {
                    name: d.channel.clone(),
                })
            }
        })
        .transpose()?;
    prepare_output_dir(out, force)?;
    let obj_options = ObjOptions {
        uv: channels.iter().any(|c| c.name == "uv" && c.components == 2),
        color: channels
            .iter()
            .any(|c| c.name == "color" && c.components == 3),
    };
    let mut vertices = vec![0; sequence.len()];
    carry(
        &sequence,
        options.direction,
        mesh,
        &channels,
        |frame, mut mesh: IndexedMesh| {
            if let (Some(d), Some(distance)) = (&options.displace, displacement) {
                displace(&mut mesh, &d.channel, distance)?;
            }
            vertices[frame] = mesh.positions.len();
            let stem = format!("frame_{frame:04}");
            if options.ply {
                write_ply(&out.join(format!("{stem}.ply")), &mesh)?;
            }
            if options.obj {
                write_obj(&out.join(format!("{stem}.obj")), &mesh, &obj_options)?;
            }
            Ok(())
        },
    )?;
    let summary = PropagateSummary {
        direction: options.direction,
        start,
        channels: channels
            .iter()
            .map(|c| (c.name.clone(), c.components))
            .collect(),
        checker: options.channels.iter().find_map(|c| match c.source {
            Source::Checker { cell } => Some(start.checker(cell)),
            _ => None,
        }),
        displacement,
        vertices,
    };
    let json = serde_json::to_vec_pretty(&summary)?;
    atomic_write(&out.join(SUMMARY_FILE), |w| w.write_all(&json))?;
    Ok(summary)
}

/// Rejects options that cannot give a useful result before anything is read or written.
fn check(options: &PropagateOptions) -> Result<(), PropagateError> {
    for (i, c) in options.channels.iter().enumerate() {
        if options.channels[..i].iter().any(|o| o.name == c.name) {
            return Err(PropagateError::DuplicateChannel {
                name: c.name.clone(),
            });
        }
    }
    if let Some(d) = &options.displace
        && !d.scale.is_finite()
    {
        return Err(PropagateError::Parameter {
            what: "displacement scale",
            value: d.scale,
        });
    }
    Ok(())
}
