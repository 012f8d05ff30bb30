//! New vertices moved onto the carried vertices a re-sampling removes. Where the sub-grid match
//! copies the input's triangles in (a graft's region, a whole replacement), or a topology patch
//! fills a region with Θ's isosurface (paper §4.3), most of the tracked surface removed lay on the
//! new surface already: registration and the snap put it on the input, a graft's region reaches
//! cells beyond a difference a fraction of a cell across, and a patch's region grows past the
//! deep cells until its front is simple. Placed as they come, the new vertices re-sample all of
//! it, and only those that happen to stand within the continue reach of a removed vertex go on
//! as it (`Replacement::continuing`): on the SPH dam break the sub-grid match alone lost
//! 1,000–4,300 carried vertices a frame, each a value re-read from its neighbours.
//!
//! So each removed vertex carried over from an earlier frame takes the new vertex nearest it,
//! within [`MOVE_REACH`] cells, one each, nearest pairs first: the new vertex moves to where the
//! removed one stands, where the move keeps every triangle around it facing its way and the
//! vertex within [`MOVE_LIFT`] of the plane of those triangles, so the new surface stays where it
//! was within a small part of a cell. Standing on the vertex whose data it reads, the moved vertex
//! continues it: the removed vertex goes on, unmoved, with its id and its data. Connectivity is
//! the new surface's; improvement then evens out the moved triangles, keeping the older vertex of
//! a short edge (paper §4.1, as the tracker applies it).

use glam::Vec3;
use rustc_hash::FxHashMap;

use super::nearest::Survivors;

/// Farthest a copied vertex moves onto a removed carried one, in grid spacings: about the
/// distance between neighbouring vertices, so that in a region where both surfaces are sampled
/// alike each removed vertex finds a partner (dam break: 0.5 carried 90.90% a frame, 0.7 91.0%,
/// 1.0 91.0% with a blurrier checker).
const MOVE_REACH: f32 = 0.7;

/// Farthest a move may lift a copied vertex off the plane of the triangles around it, in grid
/// spacings.
const MOVE_LIFT: f32 = 0.1;

/// Least share of its area, projected on its old normal, a triangle keeps when a corner moves.
const MOVE_KEEP: f32 = 0.25;

/// Moves new vertices (`movable`, indices into `positions` and corners of `triangles`, which
/// hold every triangle around them) onto the `removed` points, one each, nearest pairs first,
/// within [`MOVE_REACH`] of `spacing`, where the move keeps the triangles around the vertex as
/// the module comment says, with no edge longer than `longest_edge` (or than the longest around
/// the vertex before). Returns how many moved.
pub(crate) fn move_onto(
    positions: &mut [Vec3],
    triangles: &[[u32; 3]],
    movable: &[u32],
    removed: &[Vec3],
    (spacing, longest_edge): (f32, f32),
) -> usize {
    let reach = MOVE_REACH * spacing;
    if removed.is_empty() || movable.is_empty() || reach <= 0.0 {
        return 0;
    }
    let pairs = nearest_pairs(positions, movable, removed, reach);
    let mut slot: FxHashMap<u32, usize> = FxHashMap::default();
    for (i, &u) in movable.iter().enumerate() {
        slot.insert(u, i);
    }
    let mut star: Vec<Vec<usize>> = vec![Vec::new(); movable.len()];
    for (t, tri) in triangles.iter().enumerate() {
        for v in tri {
            if let Some(&i) = slot.get(v) {
                star[i].push(t);
            }
        }
    }
    let mut taken = vec![false; removed.len()];
    let mut done = vec![false; movable.len()];
    let mut moved = 0;
    for (_, r, u) in pairs {
        let i = slot[&u];
        if taken[r as usize] || done[i] {
            continue;
        }
        let q = removed[r as usize];
        let bounds = (MOVE_LIFT * spacing, longest_edge);
        if fits(positions, (triangles, &star[i]), (u, q), bounds) {
            positions[u as usize] = q;
            taken[r as usize] = true;
            done[i] = true;
            moved += 1;
        }
    }
    moved
}

/// For each of `removed`, the vertex of `movable` nearest it within `reach`, if any (ties to the
/// lower index), as (distance, index into `removed`, vertex), sorted: nearest first, then by
/// index, so the result does not depend on any order but the inputs'.
fn nearest_pairs(
    positions: &[Vec3],
    movable: &[u32],
    removed: &[Vec3],
    reach: f32,
) -> Vec<(f32, u32, u32)> {
    let near = Survivors::new(movable.iter().map(|&u| (u, positions[u as usize])), reach);
    let mut pairs: Vec<(f32, u32, u32)> = removed
        .iter()
        .enumerate()
        .filter_map(|(r, &p)| {
            let u = near.nearest_within(p, reach)?;
            let distance = positions[u as usize].distance(p);
            (distance <= reach).then_some((distance, r as u32, u))
        })
        .collect();
    pairs.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
    pairs
}

/// Whether moving vertex `u` to `q` keeps each triangle of its star (`around`, indices into
/// `triangles`) facing its way with [`MOVE_KEEP`] of its area, no edge of the star longer than
/// `longest_edge` or than its longest was (a longer one improvement would split, blending the
/// data of its ends: on the DFSPH double dam break the carried checker fell from 84% to 79%),
/// and `q` within `lift` of the plane through `u` normal to the star's area-weighted normal.
fn fits(
    positions: &[Vec3],
    (triangles, around): (&[[u32; 3]], &[usize]),
    (u, q): (u32, Vec3),
    (lift, longest_edge): (f32, f32),
) -> bool {
    let p = positions[u as usize];
    let mut normal = Vec3::ZERO;
    let mut longest = longest_edge;
    let mut ends = Vec::with_capacity(2 * around.len());
    for &t in around {
        let tri = triangles[t];
        let Some(k) = tri.iter().position(|&v| v == u) else {
            return false;
        };
        let a = positions[tri[(k + 1) % 3] as usize];
        let b = positions[tri[(k + 2) % 3] as usize];
        let before = (a - p).cross(b - p);
        let after = (a - q).cross(b - q);
        if after.dot(before) < MOVE_KEEP * before.length_squared() {
            return false;
        }
        normal += before;
        longest = longest
            .max(a.distance(p))
            .max(b.distance(p))
            .max(a.distance(b));
        ends.push(a);
    }
    let normal = normal.normalize_or_zero();
    normal != Vec3::ZERO
        && (q - p).dot(normal).abs() <= lift
        && ends.iter().all(|a| a.distance(q) <= longest)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat hexagonal fan in z = 0 around vertex 0 at the origin, ring radius 1, and its
    /// triangles (counter-clockwise seen from +z).
    fn fan() -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let mut positions = vec![Vec3::ZERO];
        for k in 0..6 {
            let a = k as f32 * std::f32::consts::TAU / 6.0;
            positions.push(Vec3::new(a.cos(), a.sin(), 0.0));
        }
        let triangles = (0..6u32).map(|k| [0, 1 + k, 1 + (k + 1) % 6]).collect();
        (positions, triangles)
    }

    #[test]
    fn a_vertex_moves_within_its_star_and_not_off_it() {
        let (positions, copies) = fan();
        let spacing = 1.0;
        let moved_to = |q: Vec3| {
            let mut at = positions.clone();
            let n = move_onto(&mut at, &copies, &[0], &[q], (spacing, 2.0));
            (n, at[0])
        };
        // Within the star, in its plane or lifted less than the bound: the vertex goes there.
        for q in [Vec3::new(0.3, 0.2, 0.0), Vec3::new(-0.2, 0.1, 0.08)] {
            assert_eq!(moved_to(q), (1, q));
        }
        // Lifted farther than the bound, beyond the reach, or so near the ring that a triangle
        // would keep less than a quarter of its area: it stays.
        let towards_edge = Vec3::new(30f32.to_radians().cos(), 30f32.to_radians().sin(), 0.0);
        for q in [
            Vec3::new(0.1, 0.0, 0.2),
            Vec3::new(0.72, 0.0, 0.0),
            0.68 * towards_edge,
        ] {
            assert_eq!(moved_to(q), (0, Vec3::ZERO), "{q}");
        }
    }

    #[test]
    fn the_nearest_removed_vertex_takes_a_copied_vertex_once() {
        let (mut positions, copies) = fan();
        let removed = [Vec3::new(0.1, 0.0, 0.0), Vec3::new(0.05, 0.0, 0.0)];
        assert_eq!(
            nearest_pairs(&positions, &[0], &removed, 0.7),
            vec![(0.05, 1, 0), (0.1, 0, 0)]
        );
        assert_eq!(
            move_onto(&mut positions, &copies, &[0], &removed, (1.0, 2.0)),
            1
        );
        assert_eq!(positions[0], removed[1]);
    }
}
