//! How far the input's triangles that a graft try leaves out lie from the try's result, for its
//! bound check (step 4 of the graft, [`super::graft`]).
//!
//! The check measures every sample of those triangles against the grafted component; a tree over
//! the whole component, built for each try, was most of a check's time. But the sub-grid match
//! has already measured every input vertex against the tracked surface, and keeps that surface's
//! tree ([`TrackedNearest`]); the result keeps most of that surface, so a point whose nearest
//! tracked triangle is kept lies at most that far from the result. The rest lie near the region,
//! where the copied triangles and strips are, and a tree over those alone is small. Only what
//! neither vouches for within the bound is measured against the whole result. A vertex distance
//! found this way may exceed the true one but never falls short of it, so the samples it vouches
//! for are a subset of those the true one vouches for, and every sample it does not is measured:
//! the far samples are the ones a tree over the whole result gives, in the same order.

use glam::Vec3;

use super::SubgridError;
use super::graft::{Graft, assemble};
use super::matching::{Bounded, TrackedNearest, far_given, within_bound};
use crate::compute::Backend;
use crate::mesh::IndexedMesh;
use crate::topology::transfer::triangles_around;

/// The samples of `left` (the input triangles `left_triangles` of `theirs`, as a mesh of their
/// own) farther than `max_distance` from `part`, the result of `graft` of `theirs` into `ours`,
/// with `nearest` measured between `ours` and `theirs`.
pub(super) fn far_left_out(
    backend: &Backend,
    graft: &Graft,
    (ours, theirs): (&IndexedMesh, &IndexedMesh),
    (left_triangles, left, part): (&[u32], &IndexedMesh, &IndexedMesh),
    nearest: &TrackedNearest,
    (max_distance, cell): (f32, f32),
) -> Result<Vec<Vec3>, SubgridError> {
    let bounded = within_bound(max_distance);
    // The input vertex of each vertex of `left`, which numbers them in that order.
    let mut input_vertex: Vec<u32> = left_triangles
        .iter()
        .flat_map(|&t| theirs.triangles[t as usize])
        .collect();
    input_vertex.sort_unstable();
    input_vertex.dedup();
    let mut kept = vec![false; ours.triangles.len()];
    for &t in &graft.kept {
        kept[t as usize] = true;
    }
    let mut distance = vec![f32::INFINITY; input_vertex.len()];
    let mut open = Vec::new();
    for (k, &u) in input_vertex.iter().enumerate() {
        match nearest.nearest.get(u as usize).copied().flatten() {
            Some((t, d)) if kept[t as usize] && d <= bounded => distance[k] = d,
            _ => open.push(k),
        }
    }
    let fresh = assemble((&[], &graft.copied, &graft.zip), ours, theirs);
    let mut trees = Trees {
        tracked: (nearest, &kept),
        fresh: (&fresh, None),
        whole: (part, cell),
    };
    let asked: Vec<Vec3> = open.iter().map(|&k| left.positions[k]).collect();
    let found = trees.measure(backend, &asked, max_distance)?;
    for (&k, d) in open.iter().zip(found) {
        distance[k] = d;
    }
    let labels = vec![0; left.positions.len()];
    let far = far_given(left, (&labels, 1), max_distance, &distance, |samples, _| {
        trees.measure(backend, samples, max_distance)
    })?;
    Ok(far.into_iter().flatten().collect())
}

/// What a point's distance to the result is measured against: the tracked surface with the
/// triangles the result keeps, the result's new triangles (copied and strips, listed once
/// asked), and the whole result, with the cell size of the lists of its triangles around the few
/// points left (`triangles_around`: a tree over the whole result, for a handful of points, was
/// most of a check's time).
struct Trees<'a> {
    tracked: (&'a TrackedNearest, &'a [bool]),
    fresh: (&'a IndexedMesh, Option<Bounded>),
    whole: (&'a IndexedMesh, f32),
}

/// `mesh` listed for measuring against, on first use.
fn listed<'t>(
    backend: &Backend,
    slot: &'t mut (&IndexedMesh, Option<Bounded>),
) -> Result<&'t Bounded, SubgridError> {
    if slot.1.is_none() {
        slot.1 = Some(Bounded::new(backend, slot.0)?);
    }
    Ok(slot.1.as_ref().expect("the surface was just listed"))
}

/// The distances from `points[i]`, for each `i` of `which`, to `surface`, infinite beyond
/// `max_distance` (world units).
fn distances_at(
    backend: &Backend,
    surface: &Bounded,
    points: &[Vec3],
    which: &[usize],
    max_distance: f32,
) -> Result<Vec<f32>, SubgridError> {
    let asked: Vec<Vec3> = which.iter().map(|&i| points[i]).collect();
    surface.distances(backend, &asked, max_distance)
}

impl Trees<'_> {
    /// A distance from each point to the result: within the bound from a kept tracked triangle
    /// or from the new triangles, else the exact one from the whole result (infinite beyond
    /// `max_distance`).
    fn measure(
        &mut self,
        backend: &Backend,
        points: &[Vec3],
        max_distance: f32,
    ) -> Result<Vec<f32>, SubgridError> {
        let bounded = within_bound(max_distance);
        let mut out = vec![f32::INFINITY; points.len()];
        let mut rest: Vec<usize> = (0..points.len()).collect();
        if !points.is_empty() {
            let (tracked, kept) = self.tracked;
            let hits = tracked.staying.nearest(backend, points, max_distance)?;
            rest.retain(|&i| {
                let kept_near = hits[i].and_then(|(t, d)| {
                    (kept[tracked.triangles[t as usize] as usize] && d <= bounded).then_some(d)
                });
                if let Some(d) = kept_near {
                    out[i] = d;
                }
                kept_near.is_none()
            });
        }
        if !rest.is_empty() && !self.fresh.0.triangles.is_empty() {
            let fresh = listed(backend, &mut self.fresh)?;
            let found = distances_at(backend, fresh, points, &rest, max_distance)?;
            let mut still = Vec::new();
            for (&i, d) in rest.iter().zip(found) {
                if d <= bounded {
                    out[i] = d;
                } else {
                    still.push(i);
                }
            }
            rest = still;
        }
        if rest.is_empty() {
            return Ok(out);
        }
        let (whole, cell) = self.whole;
        let asked: Vec<Vec3> = rest.iter().map(|&i| points[i]).collect();
        let near = triangles_around(
            (&whole.positions, &whole.triangles),
            &asked,
            cell,
            max_distance,
        );
        // No triangle near any of them: every one lies beyond the bound.
        if !near.is_empty() {
            let around = IndexedMesh::new(whole.positions.clone(), near);
            let found = distances_at(
                backend,
                &Bounded::new(backend, &around)?,
                points,
                &rest,
                max_distance,
            )?;
            for (&i, d) in rest.iter().zip(found) {
                out[i] = d;
            }
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::super::graft::submesh;
    use super::super::matching::{
        Against, far_components, far_from_tracked, tracked_sphere_and_bumped_input,
    };
    use super::*;
    use crate::project::Bvh;

    /// On a tracked sphere and a bumped input, for kept, copied and left-out triangles on
    /// either side of a gap, the far samples are those a tree over the whole result gives, in
    /// the same order, at bounds where none, some and many samples are far.
    #[test]
    fn far_samples_are_those_of_a_tree_over_the_whole_result() {
        let backend = Backend::Cpu;
        let (ours, theirs) = tracked_sphere_and_bumped_input();
        let centroid_x = |mesh: &IndexedMesh, t: &[u32; 3]| {
            t.iter().map(|&v| mesh.positions[v as usize].x).sum::<f32>() / 3.0
        };
        let pick = |mesh: &IndexedMesh, keep: &dyn Fn(f32) -> bool| -> Vec<u32> {
            (0..mesh.triangles.len() as u32)
                .filter(|&t| keep(centroid_x(mesh, &mesh.triangles[t as usize])))
                .collect()
        };
        let graft = Graft {
            kept: pick(&ours, &|x| x < 0.2),
            copied: pick(&theirs, &|x| x > 0.5),
            zip: Vec::new(),
        };
        let left_triangles = pick(&theirs, &|x| x <= 0.5);
        let left = submesh(&theirs, &left_triangles);
        let part = assemble((&graft.kept, &graft.copied, &graft.zip), &ours, &theirs);
        let stays: Vec<u32> = (0..ours.triangles.len() as u32).collect();
        let input_labels = vec![0; theirs.positions.len()];
        let left_labels = vec![0; left.positions.len()];
        let mut counts = Vec::new();
        for max_distance in [0.2, 0.05, 0.02, 0.005] {
            let (_, nearest) = far_from_tracked(
                &backend,
                (&ours, &stays),
                &theirs,
                (&input_labels, 1),
                max_distance,
            )
            .unwrap();
            let found = far_left_out(
                &backend,
                &graft,
                (&ours, &theirs),
                (&left_triangles, &left, &part),
                &nearest,
                (max_distance, 0.1),
            )
            .unwrap();
            let whole = Bounded::Tree(Bvh::build_unsigned(&part).unwrap());
            let expected: Vec<Vec3> = far_components(
                &backend,
                Against::Listed(&whole),
                &left,
                &left_labels,
                1,
                max_distance,
            )
            .unwrap()
            .into_iter()
            .flatten()
            .collect();
            assert_eq!(found, expected, "bound {max_distance}");
            counts.push(found.len());
        }
        assert_eq!(counts[0], 0, "{counts:?}");
        assert!(counts[3] > counts[1] && counts[1] > 0, "{counts:?}");
    }
}
