//! Forward/backward blends (paper §5, "Morph"): "to obtain a really high quality morph we may
//! additionally blend between the two forward and backward propagated colors". Values given on the
//! first frame are carried forward, values given on the last frame backward, and frame `j` of `n`
//! shows `(1 − w)·forward + w·backward` with `w = j / (n − 1)`: the first frame is exactly what was
//! given on it, the last exactly what was given on the last.

use super::carry::Direction;
use super::displace::{Displace, displace};
use super::run::{PropagateOptions, PropagateSummary, SUMMARY_FILE, propagate};
use super::source::Channel;
use super::{PropagateError, TrackedSequence};
use crate::io::{
    ObjOptions, ReadOptions, atomic_write, prepare_output_dir, read_frame_with, write_obj,
    write_ply,
};
use crate::mesh::IndexedMesh;
use crate::sequence::frame_name;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Sub-folder of a blend's output holding the forward pass.
pub const FORWARD_DIR: &str = "forward";
/// Sub-folder of a blend's output holding the backward pass.
pub const BACKWARD_DIR: &str = "backward";

/// What to paint on each end and what to write.
#[derive(Debug, Clone, PartialEq)]
pub struct BlendOptions {
    /// Painted on the first frame and carried forward.
    pub first: Vec<Channel>,
    /// Painted on the last frame and carried backward; the same names as `first`, in any order.
    pub last: Vec<Channel>,
    pub displace: Option<Displace>,
    pub ply: bool,
    pub obj: bool,
}

/// What a blend did, also written as `propagate.json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BlendSummary {
    pub forward: PropagateSummary,
    pub backward: PropagateSummary,
    /// The backward pass's weight on each frame, frame 0 first.
    pub weights: Vec<f32>,
}

/// Writes the forward pass into `out/forward`, the backward pass into `out/backward` (each as
/// [`propagate`] writes them) and the blend of the two into `out` (`frame_NNNN.ply`/`.obj`), one
/// frame at a time, and the summary last.
pub fn blend(
    tracked: &Path,
    out: &Path,
    options: &BlendOptions,
    force: bool,
) -> Result<BlendSummary, PropagateError> {
    check(options)?;
    let sequence = TrackedSequence::open(tracked)?;
    prepare_output_dir(out, force)?;
    let pass = |direction, channels: &[Channel], dir: &str| {
        let pass_options = PropagateOptions {
            direction,
            channels: channels.to_vec(),
            displace: None,
            ply: true,
            obj: false,
        };
        propagate(tracked, &out.join(dir), &pass_options, force)
    };
    let forward = pass(Direction::Forward, &options.first, FORWARD_DIR)?;
    let backward = pass(Direction::Backward, &options.last, BACKWARD_DIR)?;
    let count = sequence.len();
    let weights: Vec<f32> = (0..count)
        .map(|j| {
            if count > 1 {
                j as f32 / (count - 1) as f32
            } else {
                0.0
            }
        })
        .collect();
    for (frame, &w) in weights.iter().enumerate() {
        let name = frame_name(frame);
        let ahead = read(&out.join(FORWARD_DIR).join(&name))?;
        let behind = read(&out.join(BACKWARD_DIR).join(&name))?;
        let mut mesh = mix(ahead, &behind, w, &out.join(BACKWARD_DIR).join(&name))?;
        if let Some(d) = &options.displace {
            displace(
                &mut mesh,
                &d.channel,
                d.scale * forward.start.mean_edge_length,
            )?;
        }
        if options.ply {
            write_ply(&out.join(&name), &mesh)?;
        }
        if options.obj {
            let obj_options = ObjOptions {
                uv: mesh
                    .attributes
                    .iter()
                    .any(|a| a.name == "uv" && a.components == 2),
                color: mesh
                    .attributes
                    .iter()
                    .any(|a| a.name == "color" && a.components == 3),
            };
            let stem = format!("frame_{frame:04}.obj");
            write_obj(&out.join(stem), &mesh, &obj_options)?;
        }
    }
    let summary = BlendSummary {
        forward,
        backward,
        weights,
    };
    let json = serde_json::to_vec_pretty(&summary)?;
    atomic_write(&out.join(SUMMARY_FILE), |w| w.write_all(&json))?;
    Ok(summary)
}

/// Both ends must carry the same channels, so every frame has something to blend.
fn check(options: &BlendOptions) -> Result<(), PropagateError> {
    let names = |channels: &[Channel]| {
        let mut names: Vec<String> = channels.iter().map(|c| c.name.clone()).collect();
        names.sort();
        names
    };
    let (first, last) = (names(&options.first), names(&options.last));
    if first != last {
        return Err(PropagateError::BlendChannels {
            first: first.join(", "),
            last: last.join(", "),
        });
    }
    Ok(())
}

fn read(path: &Path) -> Result<IndexedMesh, PropagateError> {
    let options = ReadOptions {
        repair: false,
        ..ReadOptions::default()
    };
    Ok(read_frame_with(path, &options)?.mesh)
}

/// `ahead` with each channel replaced by `(1 − w)·ahead + w·behind`; both are the same tracked
/// frame, so their vertices are in the same order.
fn mix(
    mut ahead: IndexedMesh,
    behind: &IndexedMesh,
    w: f32,
    path: &Path,
) -> Result<IndexedMesh, PropagateError> {
    let inconsistent = |what: String| PropagateError::Inconsistent {
        path: PathBuf::from(path),
        what,
    };
    if ahead.ids != behind.ids {
        return Err(inconsistent(
            "its vertices differ from the forward pass's frame".to_string(),
        ));
    }
    for channel in &mut ahead.attributes {
        let other = behind
            .attributes
            .iter()
            .find(|a| a.name == channel.name && a.components == channel.components)
            .ok_or_else(|| inconsistent(format!("no channel '{}'", channel.name)))?;
        for (a, &b) in channel.values.iter_mut().zip(&other.values) {
            *a = if w == 0.0 {
                *a
            } else if w == 1.0 {
                b
            } else {
                (1.0 - w) * *a + w * b
            };
        }
    }
    Ok(ahead)
}
