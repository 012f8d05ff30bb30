//! One USD `Mesh` prim sampled per frame: `points`, `faceVertexCounts`, `faceVertexIndices`,
//! `extent`, `velocities`, the persistent `id` primvar and the carried channels' primvars. This is
//! the layer both file forms hold ([`super::usda`], [`super::usdc`]); a frame becomes one sample
//! of each attribute here, and the writers stream the samples out.

use super::ExportError;
use super::primvar::{Primvar, primvar_of};
use crate::apps::VelocityFrame;
use crate::geometry::bounds;
use crate::mesh::Attribute;
use glam::Vec3;
use std::path::Path;

/// Name of the one prim the layer holds (its default prim).
pub const PRIM: &str = "Surface";

/// `upAxis` of the stage.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UpAxis {
    Y,
    Z,
}

/// How frames become time codes, and the stage's units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UsdSettings {
    /// Frames (time codes) per second; velocities are in units per second at this rate.
    pub fps: f64,
    /// Time code of tracked frame 0; frame `k` is at `start + k`.
    pub start: f64,
    pub up_axis: UpAxis,
    pub meters_per_unit: f64,
}

impl Default for UsdSettings {
    /// 24 frames per second from time code 1 (where Blender's and Houdini's timelines begin), Y up
    /// (USD's default), one metre per unit (simulation caches are in SI units).
    fn default() -> Self {
        Self {
            fps: 24.0,
            start: 1.0,
            up_axis: UpAxis::Y,
            meters_per_unit: 1.0,
        }
    }
}

/// The stage metadata of the layer (the pseudo-root's fields besides `primChildren`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StageMetadata {
    pub fps: f64,
    pub start: f64,
    pub end: f64,
    pub up_axis: &'static str,
    pub meters_per_unit: f64,
}

impl StageMetadata {
    /// The metadata of a layer holding `frames` frames (time codes `start..=start + frames - 1`).
    pub fn new(settings: &UsdSettings, frames: usize) -> Self {
        Self {
            fps: settings.fps,
            start: settings.start,
            end: settings.start + frames.saturating_sub(1) as f64,
            up_axis: match settings.up_axis {
                UpAxis::Y => "Y",
                UpAxis::Z => "Z",
            },
            meters_per_unit: settings.meters_per_unit,
        }
    }
}

/// One time-sampled attribute of the prim.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UsdAttribute {
    /// Full property name (`points`, `primvars:st`).
    pub name: String,
    /// USD value type name (`point3f[]`, `int[]`, `texCoord2f[]`, ...).
    pub type_name: &'static str,
    /// Scalars per array element: 1 (`int`, `float`), 2, 3 or 4 (`float2`...`float4` and their
    /// roles).
    pub tuple: usize,
    /// A primvar of `vertex` interpolation.
    pub vertex: bool,
    /// `elementSize` of a primvar whose vertices have several array elements.
    pub element_size: Option<i32>,
}

/// The prim's one non-sampled attribute: a tracked surface is its triangles; the default
/// Catmull-Clark would round it off.
pub const SUBDIVISION_SCHEME: (&str, &str) = ("subdivisionScheme", "none");

/// One attribute's value at one frame, its scalars in order (`tuple` per array element).
#[derive(Debug, Clone, PartialEq)]
pub enum Sample {
    Ints(Vec<i32>),
    Floats(Vec<f32>),
}

/// Turns frames into samples: the attributes are fixed by the first frame's channels, and every
/// later frame must carry the same channels.
#[derive(Debug)]
pub struct FrameSampler {
    /// The first frame's channels `(name, components)`.
    channels: Vec<(String, usize)>,
    /// Each primvar with the attribute it takes its values from.
    primvars: Vec<(Primvar, String)>,
    /// The sampled attributes: the mesh's, then the primvars'.
    attributes: Vec<UsdAttribute>,
}

impl FrameSampler {
    /// The sampler for a sequence whose first frame is `first`, read from `path` (named in errors).
    pub fn new(first: &VelocityFrame, path: &Path) -> Result<Self, ExportError> {
        let plain = |name: &str, type_name, tuple| UsdAttribute {
            name: name.into(),
            type_name,
            tuple,
            vertex: false,
            element_size: None,
        };
        let mut attributes = vec![
            plain("points", "point3f[]", 3),
            plain("faceVertexCounts", "int[]", 1),
            plain("faceVertexIndices", "int[]", 1),
            plain("extent", "float3[]", 3),
            plain("velocities", "vector3f[]", 3),
            UsdAttribute {
                vertex: true,
                ..plain("primvars:id", "int[]", 1)
            },
        ];
        let mut primvars = Vec::new();
        for attribute in &first.mesh.attributes {
            let of = primvar_of(attribute).ok_or_else(|| ExportError::AttributeName {
                path: path.to_path_buf(),
                name: attribute.name.clone(),
            })?;
            for primvar in of {
                let tuple = match primvar.type_name {
                    "float[]" => 1,
                    "texCoord2f[]" | "float2[]" => 2,
                    "float4[]" => 4,
                    _ => 3,
                };
                let element_size = if tuple == 1 && primvar.components > 1 {
                    let size = i32::try_from(primvar.components).map_err(|_| ExportError::Usd {
                        path: path.to_path_buf(),
                        reason: format!("attribute '{}' has too many components", attribute.name),
                    })?;
                    Some(size)
                } else {
                    None
                };
                attributes.push(UsdAttribute {
                    vertex: true,
                    element_size,
                    ..plain(
                        &format!("primvars:{}", primvar.name),
                        primvar.type_name,
                        tuple,
                    )
                });
                primvars.push((primvar, attribute.name.clone()));
            }
        }
        Ok(Self {
            channels: channels(first),
            primvars,
            attributes,
        })
    }

    /// The attributes, in the order [`FrameSampler::samples`] gives their samples.
    pub fn attributes(&self) -> &[UsdAttribute] {
        &self.attributes
    }

    /// One sample per attribute of `frame`, read from `path` (named in errors).
    pub fn samples(&self, frame: &VelocityFrame, path: &Path) -> Result<Vec<Sample>, ExportError> {
        let mesh = &frame.mesh;
        let found = channels(frame);
        if found != self.channels {
            let list = |c: &[(String, usize)]| {
                c.iter()
                    .map(|(n, k)| format!("{n} ({k})"))
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            return Err(ExportError::ChannelsChanged {
                path: path.to_path_buf(),
                first: list(&self.channels),
                found: list(&found),
            });
        }
        let ids = mesh
            .ids
            .as_deref()
            .unwrap_or_default()
            .iter()
            .map(|&id| {
                i32::try_from(id).map_err(|_| ExportError::IdRange {
                    path: path.to_path_buf(),
                    id,
                })
            })
            .collect::<Result<Vec<i32>, _>>()?;
        let indices = mesh
            .triangles
            .iter()
            .flatten()
            .map(|&v| {
                i32::try_from(v).map_err(|_| ExportError::Usd {
                    path: path.to_path_buf(),
                    reason: "more vertices than an int index holds".into(),
                })
            })
            .collect::<Result<Vec<i32>, _>>()?;
        let (low, high) = bounds(&mesh.positions);
        let mut samples = vec![
            Sample::Floats(scalars(&mesh.positions)),
            Sample::Ints(vec![3; mesh.triangles.len()]),
            Sample::Ints(indices),
            Sample::Floats(scalars(&[low, high])),
            Sample::Floats(scalars(&frame.velocities)),
            Sample::Ints(ids),
        ];
        for (primvar, name) in &self.primvars {
            let values = mesh
                .attributes
                .iter()
                .find(|a| &a.name == name)
                .map(|attribute| primvar_values(primvar, attribute))
                .unwrap_or_default();
            samples.push(Sample::Floats(values));
        }
        Ok(samples)
    }
}

/// The `(name, components)` of a frame's channels.
fn channels(frame: &VelocityFrame) -> Vec<(String, usize)> {
    frame
        .mesh
        .attributes
        .iter()
        .map(|a| (a.name.clone(), a.components))
        .collect()
}

/// The scalars of `primvar` from its attribute's values, vertex by vertex.
fn primvar_values(primvar: &Primvar, attribute: &Attribute) -> Vec<f32> {
    let columns = primvar.first..primvar.first + primvar.components;
    attribute
        .values
        .chunks_exact(attribute.components)
        .flat_map(|v| v[columns.clone()].iter().copied())
        .collect()
}

fn scalars(points: &[Vec3]) -> Vec<f32> {
    points.iter().flat_map(|p| p.to_array()).collect()
}
