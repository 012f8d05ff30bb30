//! Tracked vertices moved onto the target before its topology is compared.
//!
//! The step on Φ(T) (paper §4.3) compares the mesh with the target cell by cell: where the two lie
//! on different sides of a grid corner, the mesh crosses an edge a different number of times than
//! Θ changes sign along it, and the region to re-sample grows across it. On a splash, registration
//! leaves much of the mesh a fraction of an edge off the target (the fine stage, §4.2, fits it only
//! up to its regularization), and those near misses make most of the step's losses. A vertex within
//! reach of the target moves to its closest point there, unless that would turn one of its
//! triangles over or leave it thinner than the improvement step allows. On the dam break this keeps
//! 89.09% of the vertices per frame against 87.88%, the Φ(T) step re-sampling 17.9k vertices over
//! the run against 26.4k (docs/performance.md).

use glam::Vec3;

use crate::compute::Backend;
use crate::mesh::{Mesh, VertexId, min_angle_degrees};
use crate::project::{Bvh, ProjectError, closest_points};
use rayon::prelude::*;

/// How far a vertex may move, in the target's mean edge lengths.
pub const REACH: f32 = 1.0;

/// A triangle with a corner to move: its corners, and its normal and smallest angle before.
struct Touched {
    corners: [VertexId; 3],
    normal: Vec3,
    angle: f32,
}

/// The (unnormalized) normal of a triangle.
fn normal(p: [Vec3; 3]) -> Vec3 {
    (p[1] - p[0]).cross(p[2] - p[0])
}

/// Moves every vertex within [`REACH`] of the target behind `bvh` onto its closest point there,
/// where its triangles stay facing the same way and no thinner than `min_angle` degrees (the
/// improvement step's limit) unless they were thinner before; returns how many moved.
pub fn snap(
    backend: &Backend,
    mesh: &mut Mesh,
    bvh: &Bvh,
    min_angle: f32,
) -> Result<usize, ProjectError> {
    let vertices: Vec<VertexId> = mesh.vertices().collect();
    let points: Vec<Vec3> = vertices.iter().map(|&v| mesh.position(v)).collect();
    let nearest = closest_points(backend, bvh, &points, REACH)?;
    let slots = vertices.iter().map(|v| v.0 as usize + 1).max().unwrap_or(0);
    let mut moved: Vec<Option<Vec3>> = vec![None; slots];
    for ((v, n), p) in vertices.iter().zip(&nearest).zip(&points) {
        if n.distance.is_finite() && n.point != *p {
            moved[v.0 as usize] = Some(n.point);
        }
    }
    // Only a triangle with a corner moved can be spoiled, and undoing a move moves no other
    // corner: the others are never judged. Each one's shape before the moves is measured once.
    let touched: Vec<Touched> = mesh
        .faces()
        .map(|f| mesh.face_vertices(f))
        .collect::<Vec<_>>()
        .into_par_iter()
        .filter(|c| c.iter().any(|v| moved[v.0 as usize].is_some()))
        .map(|corners| {
            let before = corners.map(|v| mesh.position(v));
            Touched {
                corners,
                normal: normal(before),
                angle: min_angle_degrees(before[0], before[1], before[2]),
            }
        })
        .collect();
    // Whether the moves left spoil the triangle: one with no corner moved is never spoiled.
    let spoiled = |t: &Touched, moved: &[Option<Vec3>]| {
        if t.corners.iter().all(|v| moved[v.0 as usize].is_none()) {
            return false;
        }
        let after = t
            .corners
            .map(|v| moved[v.0 as usize].unwrap_or(mesh.position(v)));
        let angle_after = min_angle_degrees(after[0], after[1], after[2]);
        t.normal.dot(normal(after)) <= 0.0 || angle_after < min_angle.min(t.angle)
    };
    // Undoing a move can spoil a triangle whose other corners moved; every round undoes at least
    // one move until none spoils a triangle (at worst, none is left). The triangles are judged in
    // order, each by the moves left when its turn comes: a round judges at its start, on every
    // core, those with a corner undone in the round before (all of them in the first; the verdict
    // of any other is the one it had then: not spoiled), and judges again in turn only those with
    // a corner undone since.
    let mut undone_at = vec![false; slots];
    let mut judge: Vec<usize> = (0..touched.len()).collect();
    while !judge.is_empty() {
        let mut was = vec![false; touched.len()];
        let verdicts: Vec<bool> = judge
            .par_iter()
            .map(|&i| spoiled(&touched[i], &moved))
            .collect();
        for (&i, verdict) in judge.iter().zip(verdicts) {
            was[i] = verdict;
        }
        undone_at.iter_mut().for_each(|u| *u = false);
        for (t, &was) in touched.iter().zip(&was) {
            let now = if t.corners.iter().any(|v| undone_at[v.0 as usize]) {
                spoiled(t, &moved)
            } else {
                was
            };
            if now {
                for v in t.corners {
                    if moved[v.0 as usize].take().is_some() {
                        undone_at[v.0 as usize] = true;
                    }
                }
            }
        }
        judge = (0..touched.len())
            .filter(|&i| touched[i].corners.iter().any(|v| undone_at[v.0 as usize]))
            .collect();
    }
    // A miss (a vertex beyond reach) reports the point 0, and the rounds judge it as a move
    // there: its triangles are spoiled by it and undo the moves of their corners, which keeps
    // the rest of a part registration left far from the target where it is (docs/performance.md,
    // 2026-12-08: moving them instead did not carry more). The move itself is never made,
    // whatever the rounds left of it: where a move to 0 spoils nothing, the vertex would jump
    // there.
    for (v, n) in vertices.iter().zip(&nearest) {
        if n.hit_triangle().is_none() {
            moved[v.0 as usize] = None;
        }
    }
    let mut count = 0;
    for v in vertices {
        if let Some(p) = moved[v.0 as usize] {
            mesh.set_position(v, p);
            count += 1;
        }
    }
    Ok(count)
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::improve::ImproveParams;
    use crate::mesh::IndexedMesh;
    use glam::Quat;

    /// The improvement step's default limit.
    fn min_angle() -> f32 {
        ImproveParams::new(1.0).min_angle_degrees
    }

    /// A sphere of radius `radius`, triangulated as a turned icosphere so that no vertex of it is
    /// a vertex of the unturned one.
    fn sphere(radius: f32, levels: u32, turned: bool) -> IndexedMesh {
        let mut mesh = IndexedMesh::icosphere(Vec3::ZERO, radius, levels);
        if turned {
            let turn = Quat::from_axis_angle(Vec3::new(1.0, 2.0, 3.0).normalize(), 0.7);
            mesh.positions.iter_mut().for_each(|p| *p = turn * *p);
        }
        mesh
    }

    #[test]
    fn a_mesh_within_reach_lands_on_the_target_and_keeps_its_triangles() {
        let target = sphere(1.0, 4, true);
        let bvh = Bvh::build(&target).unwrap();
        let source = sphere(1.03, 3, false);
        let mut mesh = Mesh::from_indexed(&source).unwrap();
        let moved = snap(&Backend::Cpu, &mut mesh, &bvh, min_angle()).unwrap();
        assert_eq!(moved, source.positions.len());
        let after = mesh.to_indexed();
        let found = closest_points(&Backend::Cpu, &bvh, &after.positions, f32::INFINITY).unwrap();
        assert!(found.iter().all(|c| c.distance.abs() < 1e-5));
        for (old, new) in source.triangles.iter().zip(&after.triangles) {
            let (a, b) = (
                old.map(|v| source.positions[v as usize]),
                new.map(|v| after.positions[v as usize]),
            );
            let normal = |p: [Vec3; 3]| (p[1] - p[0]).cross(p[2] - p[0]);
            assert!(normal(a).dot(normal(b)) > 0.0);
            let (before, now) = (
                min_angle_degrees(a[0], a[1], a[2]),
                min_angle_degrees(b[0], b[1], b[2]),
            );
            assert!(now >= min_angle().min(before));
        }
    }

    #[test]
    fn a_vertex_beyond_reach_never_moves() {
        // A ball whose top vertex stands 0.01 from the origin, where a miss's point lies, and is
        // pulled 0.5 out of it: beyond reach, though a move to the origin would spoil nothing.
        let ball = sphere(1.0, 3, false);
        let top = (0..ball.positions.len())
            .max_by(|&a, &b| ball.positions[a].z.total_cmp(&ball.positions[b].z))
            .unwrap();
        let shift = Vec3::new(0.01, 0.0, 0.0) - ball.positions[top];
        let mut source = ball.clone();
        source.positions.iter_mut().for_each(|p| *p += shift);
        let out = ball.positions[top].normalize() * 0.5;
        source.positions[top] += out;
        let mut target = sphere(1.0, 4, true);
        target.positions.iter_mut().for_each(|p| *p += shift);
        let bvh = Bvh::build(&target).unwrap();
        let mut mesh = Mesh::from_indexed(&source).unwrap();
        snap(&Backend::Cpu, &mut mesh, &bvh, min_angle()).unwrap();
        assert_eq!(mesh.to_indexed().positions[top], source.positions[top]);
    }

    #[test]
    fn a_mesh_beyond_reach_stays() {
        let target = sphere(1.0, 4, true);
        let bvh = Bvh::build(&target).unwrap();
        let source = sphere(1.5, 3, false);
        let mut mesh = Mesh::from_indexed(&source).unwrap();
        assert_eq!(
            snap(&Backend::Cpu, &mut mesh, &bvh, min_angle()).unwrap(),
            0
        );
        assert_eq!(mesh.to_indexed().positions, source.positions);
    }
}
