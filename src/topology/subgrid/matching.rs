//! Where each component lies: the component of the other surface each one is on (by a vote of
//! its vertices), and the samples of each farther than the distance bound from the other.

use std::sync::Mutex;

use glam::Vec3;
use rustc_hash::FxHashMap;

use super::{SubgridError, VOTERS};
use crate::compute::Backend;
use crate::mesh::IndexedMesh;
use crate::project::{Bvh, Cells, closest_points};

/// One component of a mesh: its vertices (indices), Euler characteristic and extent.
pub(super) struct Component {
    pub vertices: Vec<u32>,
    pub euler: i64,
    pub diagonal: f32,
}

/// The components of `mesh` and the component of each of its vertices.
fn components(mesh: &IndexedMesh) -> (Vec<Component>, Vec<u32>) {
    let (topology, labels) = mesh.topology_with_labels();
    let mut out: Vec<Component> = topology
        .components
        .iter()
        .map(|c| Component {
            vertices: Vec::with_capacity(c.vertices),
            euler: c.euler,
            diagonal: 0.0,
        })
        .collect();
    let mut bounds = vec![(Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)); out.len()];
    for (v, &label) in labels.iter().enumerate() {
        if let Some(c) = out.get_mut(label as usize) {
            c.vertices.push(v as u32);
            let p = mesh.positions[v];
            let b = &mut bounds[label as usize];
            *b = (b.0.min(p), b.1.max(p));
        }
    }
    for (c, (lo, hi)) in out.iter_mut().zip(bounds) {
        c.diagonal = (hi - lo).length();
    }
    (out, labels)
}

/// The components of one surface, the component of each vertex and the triangles of each.
pub(super) struct Components {
    pub list: Vec<Component>,
    pub labels: Vec<u32>,
    pub triangles: Vec<Vec<u32>>,
}

impl Components {
    pub fn of(mesh: &IndexedMesh) -> Self {
        let (list, labels) = components(mesh);
        let triangles = triangles_by_component(mesh, &labels, list.len());
        Self {
            list,
            labels,
            triangles,
        }
    }
}

/// The triangles (indices) of each of `count` components, by the label of their first vertex.
fn triangles_by_component(mesh: &IndexedMesh, labels: &[u32], count: usize) -> Vec<Vec<u32>> {
    let mut out = vec![Vec::new(); count];
    for (t, tri) in mesh.triangles.iter().enumerate() {
        if let Some(list) = labels
            .get(tri[0] as usize)
            .and_then(|&k| out.get_mut(k as usize))
        {
            list.push(t as u32);
        }
    }
    out
}

/// The component of `target` (vertex labels `target_labels`, `theirs` components) each of `ours`
/// lies on: each votes, vertex by vertex, for the target component within a cell; a large
/// component votes with an evenly strided sample of its vertices. `None` where no component has
/// a majority.
pub(super) fn match_components(
    backend: &Backend,
    current: &IndexedMesh,
    ours: &[Component],
    (target, target_labels, theirs): (&IndexedMesh, &[u32], usize),
    bvh: &Bvh,
    spacing: f32,
) -> Result<Vec<Option<usize>>, SubgridError> {
    let sample: Vec<Vec<u32>> = ours
        .iter()
        .map(|c| {
            let step = c.vertices.len().div_ceil(VOTERS).max(1);
            c.vertices.iter().step_by(step).copied().collect()
        })
        .collect();
    let points: Vec<Vec3> = sample
        .iter()
        .flatten()
        .map(|&v| current.positions[v as usize])
        .collect();
    let reach = spacing / bvh.mean_edge_length();
    let nearest = closest_points(backend, bvh, &points, reach)?;
    let mut matched: Vec<Option<usize>> = Vec::with_capacity(ours.len());
    let mut hits = nearest.iter();
    for s in &sample {
        let mut votes = vec![0usize; theirs];
        for hit in hits.by_ref().take(s.len()) {
            if let Some(t) = hit.hit_triangle()
                && let Some(&[a, _, _]) = target.triangles.get(t as usize)
                && let Some(k) = target_labels.get(a as usize)
                && let Some(count) = votes.get_mut(*k as usize)
            {
                *count += 1;
            }
        }
        let best = (0..votes.len()).max_by_key(|&k| (votes[k], std::cmp::Reverse(k)));
        matched.push(best.filter(|&k| 2 * votes[k] > s.len()));
    }
    Ok(matched)
}

/// Distances to the input frame's surface measured so far in one frame's sub-grid match, by query
/// point and reach. The match, its re-checks and every graft try's check measure the tracked
/// vertices against the input again, and most of those vertices have not moved since the last
/// time; a query's answer depends only on the point, the reach and the tree, so a remembered one
/// is the answer a new query would give, bit for bit.
pub(super) struct InputDistances<'a> {
    pub bvh: &'a Bvh,
    seen: Mutex<FxHashMap<(u32, [u32; 3]), f32>>,
}

impl<'a> InputDistances<'a> {
    pub fn new(bvh: &'a Bvh) -> Self {
        Self {
            bvh,
            seen: Mutex::new(FxHashMap::default()),
        }
    }

    /// [`distances`] to the input's surface, querying only points not measured before at `reach`.
    fn distances(
        &self,
        backend: &Backend,
        points: &[Vec3],
        reach: f32,
    ) -> Result<Vec<f32>, SubgridError> {
        let key = |p: &Vec3| (reach.to_bits(), p.to_array().map(f32::to_bits));
        let mut out = vec![0.0; points.len()];
        let mut missing = Vec::new();
        {
            let seen = self.seen.lock().unwrap_or_else(|e| e.into_inner());
            for (i, p) in points.iter().enumerate() {
                match seen.get(&key(p)) {
                    Some(&d) => out[i] = d,
                    None => missing.push(i),
                }
            }
        }
        let asked: Vec<Vec3> = missing.iter().map(|&i| points[i]).collect();
        let found = distances(backend, self.bvh, &asked, reach)?;
        let mut seen = self.seen.lock().unwrap_or_else(|e| e.into_inner());
        for (&i, d) in missing.iter().zip(found) {
            out[i] = d;
            seen.insert(key(&points[i]), d);
        }
        Ok(out)
    }
}

/// The surface `far_components` measures against: any surface listed for it, or the input's
/// through what was measured before.
#[derive(Clone, Copy)]
pub(super) enum Against<'a> {
    Listed(&'a Bounded),
    Input(&'a InputDistances<'a>),
}

impl Against<'_> {
    /// The distance from each point, infinite beyond `max_distance` (world units).
    fn distances(
        &self,
        backend: &Backend,
        points: &[Vec3],
        max_distance: f32,
    ) -> Result<Vec<f32>, SubgridError> {
        match self {
            Self::Listed(surface) => surface.distances(backend, points, max_distance),
            Self::Input(input) => {
                input.distances(backend, points, max_distance / input.bvh.mean_edge_length())
            }
        }
    }
}

/// The unsigned distance from each point to the surface in `bvh`, infinite beyond `reach` (mean
/// edge lengths).
pub(super) fn distances(
    backend: &Backend,
    bvh: &Bvh,
    points: &[Vec3],
    reach: f32,
) -> Result<Vec<f32>, SubgridError> {
    if points.is_empty() {
        return Ok(Vec::new());
    }
    Ok(closest_points(backend, bvh, points, reach)?
        .iter()
        .map(|hit| match hit.hit_triangle() {
            Some(_) => hit.distance.abs(),
            None => f32::INFINITY,
        })
        .collect())
}

/// The samples of each component of `mesh` (vertex labels `labels`, `count` components) farther
/// than `max_distance` (world units) from the surface `against`, measured where `eval` measures:
/// at every vertex, edge midpoint and triangle centroid.
///
/// Only vertices are queried first: distance to a surface is 1-Lipschitz, so a midpoint or
/// centroid lies within `max_distance` when one of its triangle's vertices lies within
/// `max_distance` minus its offset from that vertex. Only the samples this leaves open are
/// queried, which on a tracked frame are almost none, so the check costs about one query per
/// vertex instead of four.
pub(super) fn far_components(
    backend: &Backend,
    against: Against,
    mesh: &IndexedMesh,
    labels: &[u32],
    count: usize,
    max_distance: f32,
) -> Result<Vec<Vec<Vec3>>, SubgridError> {
    let distance = against.distances(backend, &mesh.positions, max_distance)?;
    far_given(mesh, (labels, count), max_distance, &distance, |open, _| {
        against.distances(backend, open, max_distance)
    })
}

/// [`far_components`] from the distances `distance` of `mesh`'s vertices (infinite beyond
/// `max_distance`), with `measure` giving those of the samples the vertices leave open, given
/// with the triangle of `mesh` each lies on (only whether each distance is infinite is read). A vertex distance may exceed the true one, never fall
/// short of it: a sample it no longer vouches for is measured instead.
pub(super) fn far_given(
    mesh: &IndexedMesh,
    (labels, count): (&[u32], usize),
    max_distance: f32,
    distance: &[f32],
    measure: impl FnOnce(&[Vec3], &[u32]) -> Result<Vec<f32>, SubgridError>,
) -> Result<Vec<Vec<Vec3>>, SubgridError> {
    let mut far: Vec<Vec<Vec3>> = vec![Vec::new(); count];
    let mut mark = |label: Option<&u32>, p: Vec3| {
        if let Some(f) = label.and_then(|&k| far.get_mut(k as usize)) {
            f.push(p);
        }
    };
    for (v, d) in distance.iter().enumerate() {
        if d.is_infinite() {
            mark(labels.get(v), mesh.positions[v]);
        }
    }
    let bounded = within_bound(max_distance);
    let within = |p: Vec3, corners: &[u32]| {
        corners
            .iter()
            .any(|&v| distance[v as usize] + (p - mesh.positions[v as usize]).length() <= bounded)
    };
    let (mut open, mut owners, mut on) = (Vec::new(), Vec::new(), Vec::new());
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let p = tri.map(|v| mesh.positions[v as usize]);
        let centroid = (p[0] + p[1] + p[2]) / 3.0;
        let midpoints = (0..3)
            .filter(|&k| tri[k] < tri[(k + 1) % 3])
            .map(|k| (p[k] + p[(k + 1) % 3]) * 0.5);
        for s in std::iter::once(centroid).chain(midpoints) {
            if !within(s, tri) {
                open.push(s);
                owners.push(labels.get(tri[0] as usize).copied().unwrap_or(u32::MAX));
                on.push(t as u32);
            }
        }
    }
    if open.is_empty() {
        return Ok(far);
    }
    let found = measure(&open, &on)?;
    for ((d, owner), &p) in found.iter().zip(&owners).zip(&open) {
        if d.is_infinite() {
            mark(Some(owner), p);
        }
    }
    Ok(far)
}

/// The distance up to which a measured distance vouches for a point within `max_distance`: a
/// margin for rounding, so a bound never admits a sample the query would reject.
pub(super) fn within_bound(max_distance: f32) -> f32 {
    max_distance * (1.0 - 1e-4)
}

/// A surface measured against only within a bound: listed by cells on the CPU, where a tree
/// took three times as long to build as its queries took to run (`project::Cells`; the staying
/// tracked triangles of a dam-break frame, 33.5k), and in a tree on a GPU, whose kernels read one.
/// Both find the same nearest triangles at the same distances.
pub(super) enum Bounded {
    Cells(Cells),
    Tree(Bvh),
}

impl Bounded {
    pub fn new(backend: &Backend, mesh: &IndexedMesh) -> Result<Self, SubgridError> {
        Ok(match backend {
            Backend::Cpu => Self::Cells(Cells::new(mesh)?),
            Backend::Gpu(_) => Self::Tree(Bvh::build_unsigned(mesh)?),
        })
    }

    /// The nearest triangle of each point within `max_distance` (world units) and its
    /// distance.
    pub fn nearest(
        &self,
        backend: &Backend,
        points: &[Vec3],
        max_distance: f32,
    ) -> Result<Vec<Option<(u32, f32)>>, SubgridError> {
        if points.is_empty() {
            return Ok(Vec::new());
        }
        Ok(match self {
            Self::Cells(cells) => cells.nearest(points, max_distance / cells.mean_edge_length())?,
            Self::Tree(bvh) => {
                closest_points(backend, bvh, points, max_distance / bvh.mean_edge_length())?
                    .iter()
                    .map(|hit| hit.hit_triangle().map(|t| (t, hit.distance.abs())))
                    .collect()
            }
        })
    }

    /// The distance from each point to the surface, infinite beyond `max_distance`.
    pub fn distances(
        &self,
        backend: &Backend,
        points: &[Vec3],
        max_distance: f32,
    ) -> Result<Vec<f32>, SubgridError> {
        Ok(self
            .nearest(backend, points, max_distance)?
            .iter()
            .map(|hit| hit.map_or(f32::INFINITY, |(_, d)| d))
            .collect())
    }
}

/// The tracked surface the input was measured against in the sub-grid match's bound check, kept
/// for the graft's checks (see `left_out`): the staying triangles, the tracked mesh's index of
/// each of them, and for each vertex of the input the tracked triangle nearest to it (by that
/// index) and its distance, where one lies within the distance bound.
pub(super) struct TrackedNearest {
    pub staying: Bounded,
    pub triangles: Vec<u32>,
    pub nearest: Vec<Option<(u32, f32)>>,
}

/// The input's samples farther than `max_distance` from `staying` (the tracked triangles
/// `stays`, as a mesh of their own), by component of the input (`labels`, `count`), and the
/// tracked triangle nearest each input vertex: [`far_components`] against `staying`, which
/// keeps what it measured at the vertices.
pub(super) fn far_from_tracked(
    backend: &Backend,
    (staying, stays): (&IndexedMesh, &[u32]),
    input: &IndexedMesh,
    (labels, count): (&[u32], usize),
    max_distance: f32,
) -> Result<(Vec<Vec<Vec3>>, TrackedNearest), SubgridError> {
    let staying = Bounded::new(backend, staying)?;
    let nearest: Vec<Option<(u32, f32)>> = staying
        .nearest(backend, &input.positions, max_distance)?
        .into_iter()
        .map(|hit| hit.map(|(t, d)| (stays[t as usize], d)))
        .collect();
    let distance: Vec<f32> = nearest
        .iter()
        .map(|n| n.map_or(f32::INFINITY, |(_, d)| d))
        .collect();
    let far = far_given(
        input,
        (labels, count),
        max_distance,
        &distance,
        |open, _| staying.distances(backend, open, max_distance),
    )?;
    Ok((
        far,
        TrackedNearest {
            staying,
            triangles: stays.to_vec(),
            nearest,
        },
    ))
}

/// A tracked unit sphere and an input sphere shifted a little and bumped outward by up to 8% of
/// its radius over part of it: the two surfaces the bound checks' tests measure.
#[cfg(test)]
pub(super) fn tracked_sphere_and_bumped_input() -> (IndexedMesh, IndexedMesh) {
    let ours = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 3);
    let mut theirs = IndexedMesh::icosphere(Vec3::new(0.01, -0.02, 0.015), 1.0, 3);
    for p in &mut theirs.positions {
        let bump = (4.0 * p.y).sin() * (3.0 * p.z).cos();
        *p *= 1.0 + 0.08 * bump.max(0.0);
    }
    (ours, theirs)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Remembered distances are the ones a new query gives, for points seen before and not, at
    /// each reach, and a sample out of reach stays out of reach.
    #[test]
    fn remembered_distances_are_fresh_ones() {
        let target = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 3);
        let bvh = Bvh::build_unsigned(&target).unwrap();
        let input = InputDistances::new(&bvh);
        let backend = Backend::Cpu;
        let points = |scale: f32| -> Vec<Vec3> {
            IndexedMesh::icosphere(Vec3::new(0.05, -0.02, 0.01), scale, 2).positions
        };
        let (near, far) = (points(1.02), points(1.6));
        let reach = 0.5 / bvh.mean_edge_length();
        for (batch, reach) in [
            (&near, reach),
            (&far, reach),
            (&near, reach),
            (&far, 2.0 * reach),
        ] {
            let fresh = distances(&backend, &bvh, batch, reach).unwrap();
            let remembered = input.distances(&backend, batch, reach).unwrap();
            assert_eq!(fresh, remembered);
        }
        let twice = input.distances(&backend, &far, reach).unwrap();
        assert!(twice.iter().all(|d| d.is_infinite()));
        let mixed: Vec<Vec3> = near.iter().chain(&far).copied().collect();
        assert_eq!(
            input.distances(&backend, &mixed, reach).unwrap(),
            distances(&backend, &bvh, &mixed, reach).unwrap()
        );
    }
}
