//! Drift of tracked material points from where a known rigid motion takes them (paper §6, Fig. 10:
//! the tracked blobs are "virtually identical to the analytical solution").

use crate::mesh::IndexedMesh;
use crate::propagate::Bounds;
use crate::synth::RigidTransform;
use glam::Vec3;
use serde::Serialize;

/// How far the surviving frame-0 vertices are from their ground-truth positions in one frame.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Drift {
    /// Mean distance, in percent of the frame-0 bounding-box diagonal.
    pub mean_percent: f32,
    /// Largest distance, in percent of the frame-0 bounding-box diagonal.
    pub max_percent: f32,
    /// Fraction of frame-0 vertices still present (same persistent id).
    pub survivors: f64,
}

/// The frame-0 vertices of a tracked sequence, each a material point whose ground-truth position
/// in frame `j` is `T_j · T_0⁻¹ · p`.
#[derive(Debug, Clone, PartialEq)]
pub struct MaterialPoints {
    /// `(id, frame-0 position)` sorted by id.
    points: Vec<(u64, Vec3)>,
    start: RigidTransform,
    diagonal: f32,
}

impl MaterialPoints {
    /// The material points of tracked frame 0, whose ground-truth motion is `start`; `None` when the
    /// frame has no ids or no extent.
    pub fn new(frame0: &IndexedMesh, start: RigidTransform) -> Option<Self> {
        let ids = frame0.ids.as_ref()?;
        let diagonal = Bounds::of(&frame0.positions)?.diagonal();
        if diagonal <= 0.0 {
            return None;
        }
        let mut points: Vec<(u64, Vec3)> = ids
            .iter()
            .copied()
            .zip(frame0.positions.iter().copied())
            .collect();
        points.sort_unstable_by_key(|&(id, _)| id);
        Some(Self {
            points,
            start,
            diagonal,
        })
    }

    /// Drift of the material points in a tracked frame whose ground-truth motion is `transform`.
    pub fn drift(&self, frame: &IndexedMesh, transform: &RigidTransform) -> Drift {
        let ids = frame.ids.as_deref().unwrap_or_default();
        let (mut sum, mut max, mut found) = (0.0f64, 0.0f32, 0usize);
        for (id, p) in ids.iter().zip(&frame.positions) {
            let Ok(slot) = self.points.binary_search_by_key(id, |&(i, _)| i) else {
                continue;
            };
            let truth = transform.apply(self.start.inverse_apply(self.points[slot].1));
            let d = p.distance(truth);
            sum += f64::from(d);
            max = max.max(d);
            found += 1;
        }
        let percent = |d: f64| (100.0 * d / f64::from(self.diagonal)) as f32;
        Drift {
            mean_percent: if found == 0 {
                0.0
            } else {
                percent(sum / found as f64)
            },
            max_percent: percent(f64::from(max)),
            survivors: found as f64 / self.points.len().max(1) as f64,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Quat;

    #[test]
    fn a_perfect_track_has_no_drift_and_an_offset_shows_in_percent() {
        let mut frame0 = IndexedMesh::icosphere(Vec3::new(1.0, 0.0, 0.0), 1.0, 2);
        frame0.ids = Some((0..frame0.positions.len() as u64).map(|i| 3 * i).collect());
        let t0 = RigidTransform::new(Quat::from_rotation_y(0.3), Vec3::new(0.5, 0.0, 0.0));
        let t1 = RigidTransform::new(Quat::from_rotation_y(1.7), Vec3::new(-0.5, 0.2, 0.0));
        let points = MaterialPoints::new(&frame0, t0).unwrap();
        let mut frame1 = frame0.clone();
        for p in &mut frame1.positions {
            *p = t1.apply(t0.inverse_apply(*p));
        }
        let d = points.drift(&frame1, &t1);
        assert!(d.max_percent < 1e-4, "{d:?}");
        assert_eq!(d.survivors, 1.0);
        let diagonal = Bounds::of(&frame0.positions).unwrap().diagonal();
        for p in &mut frame1.positions {
            *p += Vec3::new(0.0, 0.0, 0.01 * diagonal);
        }
        frame1.ids.as_mut().unwrap().truncate(10);
        let d = points.drift(&frame1, &t1);
        assert!(
            (d.max_percent - 1.0).abs() < 1e-3 && (d.mean_percent - 1.0).abs() < 1e-3,
            "{d:?}"
        );
        assert!((d.survivors - 10.0 / frame0.positions.len() as f64).abs() < 1e-12);
    }
}
