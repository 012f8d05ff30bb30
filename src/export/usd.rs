//! One USD `Mesh` prim sampled per frame: `points`, `faceVertexCounts`, `faceVertexIndices`,
//! `extent`, `velocities`, the persistent `id` primvar and the carried channels' primvars.

use super::ExportError;
use super::primvar::{Primvar, primvar_of};
use crate::apps::VelocityFrame;
use crate::io::atomic_write;
use crate::mesh::Attribute;
use glam::Vec3;
use openusd::gf;
use openusd::sdf::{self, ChildrenKey, FieldKey, SpecType, Specifier, Value, Variability};
use openusd::usda::TextWriter;
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

type Samples = Vec<(f64, Value)>;

/// The time samples of every frame pushed so far.
#[derive(Debug, Default)]
pub struct UsdLayer {
    settings: UsdSettings,
    frames: usize,
    points: Samples,
    counts: Samples,
    indices: Samples,
    extent: Samples,
    velocities: Samples,
    ids: Samples,
    /// The first frame's channels `(name, components)`; every frame must carry the same.
    channels: Vec<(String, usize)>,
    /// Each primvar with the attribute it takes its values from.
    primvars: Vec<(Primvar, String, Samples)>,
}

impl UsdLayer {
    pub fn new(settings: UsdSettings) -> Self {
        Self {
            settings,
            ..Self::default()
        }
    }

    /// Adds one frame's samples; `path` is the file it was read from, named in errors.
    pub fn push(&mut self, frame: &VelocityFrame, path: &Path) -> Result<(), ExportError> {
        let mesh = &frame.mesh;
        let time = self.settings.start + frame.index as f64;
        let channels: Vec<(String, usize)> = mesh
            .attributes
            .iter()
            .map(|a| (a.name.clone(), a.components))
            .collect();
        if self.frames == 0 {
            for attribute in &mesh.attributes {
                let primvars = primvar_of(attribute).ok_or_else(|| ExportError::AttributeName {
                    path: path.to_path_buf(),
                    name: attribute.name.clone(),
                })?;
                self.primvars.extend(
                    primvars
                        .into_iter()
                        .map(|p| (p, attribute.name.clone(), Samples::new())),
                );
            }
            self.channels = channels;
        } else if channels != self.channels {
            let list = |c: &[(String, usize)]| {
                c.iter()
                    .map(|(n, k)| format!("{n} ({k})"))
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            return Err(ExportError::ChannelsChanged {
                path: path.to_path_buf(),
                first: list(&self.channels),
                found: list(&channels),
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
        self.points
            .push((time, Value::Vec3fVec(vec3f(&mesh.positions))));
        self.counts
            .push((time, Value::IntVec(vec![3; mesh.triangles.len()])));
        self.indices.push((time, Value::IntVec(indices)));
        self.extent
            .push((time, Value::Vec3fVec(vec3f(&[low, high]))));
        self.velocities
            .push((time, Value::Vec3fVec(vec3f(&frame.velocities))));
        self.ids.push((time, Value::IntVec(ids)));
        for (primvar, name, samples) in &mut self.primvars {
            if let Some(attribute) = mesh.attributes.iter().find(|a| &a.name == name) {
                samples.push((time, primvar_value(primvar, attribute)));
            }
        }
        self.frames += 1;
        Ok(())
    }

    /// Writes the layer as USD text, atomically.
    pub fn write_usda(self, path: &Path) -> Result<(), ExportError> {
        let data = self.into_data().map_err(|reason| ExportError::Usd {
            path: path.to_path_buf(),
            reason,
        })?;
        atomic_write(path, |mut w| {
            TextWriter::write(&data, &mut w).map_err(|e| std::io::Error::other(e.to_string()))
        })?;
        Ok(())
    }

    /// The layer's specs: the pseudo-root with the stage metadata, the mesh prim, its attributes.
    fn into_data(self) -> Result<sdf::Data, String> {
        let s = self.settings;
        let mut data = sdf::Data::new();
        let root = data.create_spec(sdf::Path::abs_root(), SpecType::PseudoRoot);
        root.add(
            ChildrenKey::PrimChildren,
            Value::TokenVec(vec![PRIM.into()]),
        );
        root.add(FieldKey::DefaultPrim, Value::Token(PRIM.into()));
        root.add(FieldKey::TimeCodesPerSecond, Value::Double(s.fps));
        root.add(FieldKey::FramesPerSecond, Value::Double(s.fps));
        root.add(FieldKey::StartTimeCode, Value::Double(s.start));
        let last = s.start + self.frames.saturating_sub(1) as f64;
        root.add(FieldKey::EndTimeCode, Value::Double(last));
        let axis = match s.up_axis {
            UpAxis::Y => "Y",
            UpAxis::Z => "Z",
        };
        root.add("upAxis", Value::Token(axis.into()));
        root.add("metersPerUnit", Value::Double(s.meters_per_unit));

        let prim = sdf::path(format!("/{PRIM}")).map_err(|e| e.to_string())?;
        let mut attributes: Vec<(String, &str, Option<usize>, Samples)> = vec![
            ("points".into(), "point3f[]", None, self.points),
            ("faceVertexCounts".into(), "int[]", None, self.counts),
            ("faceVertexIndices".into(), "int[]", None, self.indices),
            ("extent".into(), "float3[]", None, self.extent),
            ("velocities".into(), "vector3f[]", None, self.velocities),
            ("primvars:id".into(), "int[]", Some(1), self.ids),
        ];
        for (primvar, _, samples) in self.primvars {
            attributes.push((
                format!("primvars:{}", primvar.name),
                primvar.type_name,
                Some(primvar.components),
                samples,
            ));
        }
        let mut names: Vec<String> = attributes.iter().map(|(n, ..)| n.clone()).collect();
        names.push("subdivisionScheme".into());
        let spec = data.create_spec(prim.clone(), SpecType::Prim);
        spec.add(FieldKey::Specifier, Value::Specifier(Specifier::Def));
        spec.add(FieldKey::TypeName, Value::Token("Mesh".into()));
        spec.add(
            ChildrenKey::PropertyChildren,
            Value::TokenVec(names.into_iter().map(Into::into).collect()),
        );
        for (name, type_name, vertex, samples) in attributes {
            let path = prim
                .append_property(name.as_str())
                .map_err(|e| e.to_string())?;
            let spec = data.create_spec(path, SpecType::Attribute);
            spec.add(FieldKey::TypeName, Value::Token(type_name.into()));
            spec.add(FieldKey::Custom, Value::Bool(false));
            spec.add(
                FieldKey::Variability,
                Value::Variability(Variability::Varying),
            );
            if let Some(components) = vertex {
                spec.add("interpolation", Value::Token("vertex".into()));
                if components > 4 || (components > 1 && type_name == "float[]") {
                    let size = i32::try_from(components).map_err(|e| e.to_string())?;
                    spec.add("elementSize", Value::Int(size));
                }
            }
            spec.add(FieldKey::TimeSamples, Value::TimeSamples(samples));
        }
        // A tracked surface is its triangles; the default Catmull-Clark would round it off.
        let path = prim
            .append_property("subdivisionScheme")
            .map_err(|e| e.to_string())?;
        let scheme = data.create_spec(path, SpecType::Attribute);
        scheme.add(FieldKey::TypeName, Value::Token("token".into()));
        scheme.add(
            FieldKey::Variability,
            Value::Variability(Variability::Uniform),
        );
        scheme.add(FieldKey::Default, Value::Token("none".into()));
        Ok(data)
    }
}

/// The samples of `primvar` from its attribute's values.
fn primvar_value(primvar: &Primvar, attribute: &Attribute) -> Value {
    let k = attribute.components;
    let columns = primvar.first..primvar.first + primvar.components;
    let per_vertex = attribute
        .values
        .chunks_exact(k)
        .map(|v| &v[columns.clone()]);
    match primvar.type_name {
        "color3f[]" | "float3[]" => {
            Value::Vec3fVec(per_vertex.map(|v| gf::vec3f(v[0], v[1], v[2])).collect())
        }
        "texCoord2f[]" | "float2[]" => {
            Value::Vec2fVec(per_vertex.map(|v| gf::vec2f(v[0], v[1])).collect())
        }
        "float4[]" => Value::Vec4fVec(
            per_vertex
                .map(|v| gf::vec4f(v[0], v[1], v[2], v[3]))
                .collect(),
        ),
        _ => Value::FloatVec(per_vertex.flatten().copied().collect()),
    }
}

fn vec3f(points: &[Vec3]) -> Vec<gf::Vec3f> {
    points.iter().map(|p| gf::vec3f(p.x, p.y, p.z)).collect()
}

/// Lowest and highest corner of the points' box (both 0 for no points).
fn bounds(points: &[Vec3]) -> (Vec3, Vec3) {
    if points.is_empty() {
        return (Vec3::ZERO, Vec3::ZERO);
    }
    points.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(low, high), &p| (low.min(p), high.max(p)),
    )
}
