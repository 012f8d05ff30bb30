//! What one call of the sub-grid match measured, vouching for the next call's bound check in the
//! same frame (the re-checks of [`super::match_and_improve`]).
//!
//! Every call measures each input vertex against the tracked triangles that stay, through a tree
//! built over them ([`far_from_tracked`](super::matching::far_from_tracked)); on the dam break
//! that tree and its queries are most of a re-check that finds nothing to change, which most
//! re-checks are. But between a call and its re-check only the graft's region and the seam that
//! improvement reshaped have changed. So:
//!
//! * an input vertex whose nearest tracked triangle is still there, corner for corner (found by
//!   position), lies at most as far from the surface as it did;
//! * an edge midpoint or centroid of the input lies at most as far as the triangle vouching for
//!   one of its triangle's corners;
//! * what neither vouches for lies near the changed triangles and is measured against a tree over
//!   the staying triangles near it.
//!
//! Every triangle measured against is a staying one, so these distances may exceed the true ones
//! but never fall short of them. When they put every sample of the input within the bound, with
//! the rounding margin the bound check's own shortcut keeps ([`within_bound`]), the exact check
//! would find no far sample either, and only then is it spared: far samples, a graft to make, or
//! a re-check right after a graft (most of the surface re-made) are measured exactly as before.

use glam::Vec3;
use rustc_hash::FxHashMap;

use super::SubgridError;
use super::graft::submesh;
use super::matching::{TrackedNearest, distances, far_given, within_bound};
use crate::compute::Backend;
use crate::geometry::point_triangle_distance;
use crate::mesh::IndexedMesh;
use crate::project::Bvh;
use crate::topology::classify::dilate;

/// The tracked surface an earlier call measured the input against, and what it measured.
pub(super) struct Earlier {
    pub tracked: IndexedMesh,
    pub nearest: TrackedNearest,
}

/// No vertex.
const NONE: u32 = u32::MAX;

/// Most input vertices, as a share of all, that the earlier measurement may leave open: beyond
/// it (the re-check right after a graft, whose region and seam improvement re-made) the trees
/// around them cost about what the exact check costs, which mostly finds far samples there.
const MOST_OPEN: f32 = 0.1;

/// Whether what `earlier` measured, and trees over the staying triangles near what it leaves
/// open, put every sample of `input` (at its vertices, edge midpoints and triangle centroids)
/// within `max_distance` of the triangles `stays` of `current`. False means only that they do
/// not vouch for it: the caller measures exactly.
pub(super) fn all_within(
    backend: &Backend,
    earlier: &Earlier,
    (current, stays): (&IndexedMesh, &[u32]),
    input: &IndexedMesh,
    max_distance: f32,
) -> Result<bool, SubgridError> {
    let bounded = within_bound(max_distance);
    let tracked = &earlier.tracked;
    let around = Incident::new(current, stays);
    let stayed = still_staying(tracked, current, &around);
    // Each input vertex's distance, and the earlier triangle, still staying, that vouches for it.
    let mut distance = vec![f32::INFINITY; input.positions.len()];
    let mut vouching: Vec<Option<u32>> = vec![None; input.positions.len()];
    let mut open = Vec::new();
    for (u, (d, by)) in distance.iter_mut().zip(&mut vouching).enumerate() {
        match earlier.nearest.nearest.get(u).copied().flatten() {
            Some((t, near)) if near <= bounded && stayed(t) => (*d, *by) = (near, Some(t)),
            _ => open.push(u),
        }
    }
    if open.len() as f32 > MOST_OPEN * input.positions.len() as f32 {
        return Ok(false);
    }
    // The staying triangles near the points asked about, as a tree; a distance beyond the margin
    // vouches for nothing: it counts as far, and the caller measures.
    let measure = |points: &[Vec3]| -> Result<Vec<f32>, SubgridError> {
        if points.is_empty() {
            return Ok(Vec::new());
        }
        let near = submesh(current, &around.near(current, points, max_distance));
        if near.triangles.is_empty() {
            return Ok(vec![f32::INFINITY; points.len()]);
        }
        let tree = Bvh::build_unsigned(&near)?;
        let reach = max_distance / tree.mean_edge_length();
        Ok(distances(backend, &tree, points, reach)?
            .into_iter()
            .map(|d| if d <= bounded { d } else { f32::INFINITY })
            .collect())
    };
    let asked: Vec<Vec3> = open.iter().map(|&u| input.positions[u]).collect();
    for (&u, d) in open.iter().zip(measure(&asked)?) {
        if d.is_infinite() {
            return Ok(false);
        }
        distance[u] = d;
    }
    let labels = vec![0; input.positions.len()];
    // A sample lies at most as far as the triangle vouching for one of its triangle's corners;
    // only what those leave open is measured.
    let far = far_given(
        input,
        (&labels, 1),
        max_distance,
        &distance,
        |samples, on| {
            let mut found = vec![f32::INFINITY; samples.len()];
            let mut rest = Vec::new();
            for (k, (&p, &t)) in samples.iter().zip(on).enumerate() {
                let d = input.triangles[t as usize]
                    .iter()
                    .filter_map(|&u| vouching[u as usize])
                    .map(|n| {
                        let [a, b, c] =
                            tracked.triangles[n as usize].map(|v| tracked.positions[v as usize]);
                        point_triangle_distance(p, a, b, c)
                    })
                    .fold(f32::INFINITY, f32::min);
                if d <= bounded {
                    found[k] = d;
                } else {
                    rest.push(k);
                }
            }
            let asked: Vec<Vec3> = rest.iter().map(|&k| samples[k]).collect();
            for (&k, d) in rest.iter().zip(measure(&asked)?) {
                found[k] = d;
            }
            Ok(found)
        },
    )?;
    Ok(far.iter().all(Vec::is_empty))
}

/// Whether a triangle of `tracked` is still one of the staying triangles of `current` (`around`
/// each vertex), corner for corner: its corners are found by position.
fn still_staying<'a>(
    tracked: &'a IndexedMesh,
    current: &'a IndexedMesh,
    around: &'a Incident,
) -> impl Fn(u32) -> bool + 'a {
    let bits = |p: Vec3| p.to_array().map(f32::to_bits);
    let now: FxHashMap<[u32; 3], u32> = current
        .positions
        .iter()
        .enumerate()
        .map(|(v, &p)| (bits(p), v as u32))
        .collect();
    let vertex_now: Vec<u32> = tracked
        .positions
        .iter()
        .map(|&p| now.get(&bits(p)).copied().unwrap_or(NONE))
        .collect();
    move |t: u32| {
        let corners = tracked.triangles[t as usize].map(|v| vertex_now[v as usize]);
        if corners.contains(&NONE) {
            return false;
        }
        let mut wanted = corners;
        wanted.sort_unstable();
        around.of(corners[0]).iter().any(|&n| {
            let mut have = current.triangles[n as usize];
            have.sort_unstable();
            have == wanted
        })
    }
}

/// The staying triangles around each vertex of the tracked mesh.
struct Incident {
    start: Vec<u32>,
    triangles: Vec<u32>,
}

impl Incident {
    fn new(mesh: &IndexedMesh, stays: &[u32]) -> Self {
        let mut start = vec![0u32; mesh.positions.len() + 1];
        for &t in stays {
            for v in mesh.triangles[t as usize] {
                start[v as usize + 1] += 1;
            }
        }
        for v in 0..mesh.positions.len() {
            start[v + 1] += start[v];
        }
        let mut fill = start.clone();
        let mut triangles = vec![0u32; start[mesh.positions.len()] as usize];
        for &t in stays {
            for v in mesh.triangles[t as usize] {
                triangles[fill[v as usize] as usize] = t;
                fill[v as usize] += 1;
            }
        }
        Incident { start, triangles }
    }

    fn of(&self, v: u32) -> &[u32] {
        &self.triangles[self.start[v as usize] as usize..self.start[v as usize + 1] as usize]
    }

    /// The staying triangles with a corner in a cell of side `2 max_distance` next to one
    /// holding a point of `points`: every triangle whose nearest point to one of them lies
    /// within `max_distance`, unless it is longer than a cell.
    fn near(&self, mesh: &IndexedMesh, points: &[Vec3], max_distance: f32) -> Vec<u32> {
        let side = 2.0 * max_distance;
        let cell = |p: Vec3| (p / side).floor().as_ivec3().to_array();
        let cells = dilate(&points.iter().map(|&p| cell(p)).collect::<Vec<_>>(), 1);
        let mut near: Vec<u32> = (0..mesh.positions.len())
            .filter(|&v| cells.binary_search(&cell(mesh.positions[v])).is_ok())
            .flat_map(|v| self.of(v as u32).iter().copied())
            .collect();
        near.sort_unstable();
        near.dedup();
        near
    }
}

#[cfg(test)]
mod tests {
    use super::super::matching::{far_from_tracked, tracked_sphere_and_bumped_input};
    use super::*;

    /// `mesh` with its vertices and triangles in reverse order and each triangle's corners
    /// rotated: the same surface as another call's `to_indexed` may number it.
    fn renumbered(mesh: &IndexedMesh) -> IndexedMesh {
        let n = mesh.positions.len() as u32;
        let positions = mesh.positions.iter().rev().copied().collect();
        let triangles = mesh
            .triangles
            .iter()
            .rev()
            .map(|t| [t[1], t[2], t[0]].map(|v| n - 1 - v))
            .collect();
        IndexedMesh::new(positions, triangles)
    }

    /// The triangles of `mesh` whose centroid lies at `x` at most `cap`, and those of `other`
    /// beyond it moved by `shift` along x, as one mesh.
    fn spliced(mesh: &IndexedMesh, other: Option<(&IndexedMesh, f32)>, cap: f32) -> IndexedMesh {
        let centroid_x = |m: &IndexedMesh, t: &[u32; 3]| {
            t.iter().map(|&v| m.positions[v as usize].x).sum::<f32>() / 3.0
        };
        let mut positions = mesh.positions.clone();
        let mut triangles: Vec<[u32; 3]> = mesh
            .triangles
            .iter()
            .filter(|t| centroid_x(mesh, t) <= cap)
            .copied()
            .collect();
        if let Some((other, shift)) = other {
            let base = positions.len() as u32;
            positions.extend(other.positions.iter().map(|&p| p + Vec3::X * shift));
            triangles.extend(
                other
                    .triangles
                    .iter()
                    .filter(|t| centroid_x(other, t) > cap)
                    .map(|t| t.map(|v| v + base)),
            );
        }
        IndexedMesh::new(positions, triangles)
    }

    /// On a tracked sphere and a bumped input: where the re-checked surface keeps the earlier
    /// one's triangles (renumbered) or takes the input's own in a cap, the earlier measurement
    /// vouches for every sample at a loose bound; it never vouches where the exact check finds a
    /// far sample (a cap removed, or moved off the input, or a tight bound).
    #[test]
    fn it_vouches_only_where_the_exact_check_finds_nothing_far() {
        let backend = Backend::Cpu;
        let (ours, theirs) = tracked_sphere_and_bumped_input();
        // A cap of 7.5% of the sphere: within the share of vertices left open that is vouched for.
        const CAP: f32 = 0.85;
        let labels = vec![0; theirs.positions.len()];
        let every = |mesh: &IndexedMesh| (0..mesh.triangles.len() as u32).collect::<Vec<_>>();
        let variants = [
            ("renumbered", renumbered(&ours)),
            (
                "input in a cap",
                renumbered(&spliced(&ours, Some((&theirs, 0.0)), CAP)),
            ),
            ("cap removed", spliced(&ours, None, CAP)),
            ("cap moved off", spliced(&ours, Some((&theirs, 0.3)), CAP)),
            (
                "input in a larger cap",
                spliced(&ours, Some((&theirs, 0.0)), 0.5),
            ),
        ];
        let mut vouched = Vec::new();
        for max_distance in [0.2, 0.05, 0.005] {
            let (_, nearest) = far_from_tracked(
                &backend,
                (&ours, &every(&ours)),
                &theirs,
                (&labels, 1),
                max_distance,
            )
            .unwrap();
            let earlier = Earlier {
                tracked: ours.clone(),
                nearest,
            };
            for (name, current) in &variants {
                let stays = every(current);
                let vouches =
                    all_within(&backend, &earlier, (current, &stays), &theirs, max_distance)
                        .unwrap();
                let (far, _) = far_from_tracked(
                    &backend,
                    (current, &stays),
                    &theirs,
                    (&labels, 1),
                    max_distance,
                )
                .unwrap();
                let none_far = far.iter().all(Vec::is_empty);
                assert!(!vouches || none_far, "{name} at {max_distance}");
                vouched.push((*name, max_distance, vouches, none_far));
            }
        }
        // A quarter of the sphere re-made is left to the exact check, which finds nothing far.
        let expected = [
            ("renumbered", 0.2, true, true),
            ("input in a cap", 0.2, true, true),
            ("cap removed", 0.2, false, false),
            ("cap moved off", 0.2, false, false),
            ("input in a larger cap", 0.2, false, true),
        ];
        assert_eq!(vouched[..5], expected, "{vouched:?}");
        assert!(
            vouched[10..].iter().all(|v| !v.2 && !v.3),
            "a tight bound leaves samples far: {vouched:?}"
        );
    }
}
