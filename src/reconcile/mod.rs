//! Components the grid cannot resolve. `ConstrainTopology` (paper §4.3) sees the surfaces only
//! through a grid of spacing Δ: a droplet smaller than a cell, or one that vanished inside a cell,
//! leaves no trace in it, and neither does a sheet thinner than a cell, a tunnel through one or a
//! bridge narrower than one (notes on the topology step, §6: "sub-cell components inside a simple
//! cell are invisible to every test; pick a policy"). Fluid caches are full of them: marching cubes
//! of a particle field sheds droplets of a handful of vertices every frame and leaves splash sheets
//! a tenth of an edge thick, pierced by holes. Refining the grid does not converge on such input
//! (its features reach every scale), so the tracked mesh takes the input's own geometry where the
//! grid fails: after the two topology steps every component of `M` is matched with the component
//! of `T` that most of its vertices lie on (within one cell), and:
//!
//! * a component of `M` that lies on no component of `T` (a droplet `T` lost) is deleted;
//! * a component of `T` that no component of `M` lies on (a droplet born below the grid) is copied
//!   in with fresh ids;
//! * a small component of `M` (within [`SMALL_CELLS`] cells) that shares its match with a larger
//!   one is deleted;
//! * a component whose match it does not reproduce — another Euler characteristic, another large
//!   component on the same match (a bridge below the grid), or a sample of either surface farther
//!   than `max_distance` from the other (a sheet below the grid) — takes its match's triangles
//!   only in the cells around the difference ([`graft`]), keeping its own vertices elsewhere, or,
//!   where no graft meets the bounds, is replaced by a whole copy of its match.
//!
//! Everything the grid resolves was already resolved by `ConstrainTopology`, so replacement is the
//! exception on clean input and the guarantee on real data: afterwards `M` has the input's
//! components and Euler characteristics, and lies within `max_distance` of it.
//!
//! Like a topology patch with no boundary (§4.4), each vertex of a replaced component takes its data
//! from the nearest vertex of the copy going backward, and each vertex of the copy takes, going
//! forward, the data of the nearest vertex of the component it replaces; an inserted droplet takes
//! the data of the nearest vertex before the change, a deleted one that of the nearest vertex after
//! it. So every vertex of every frame holds a value (unless a whole frame is empty), a constant
//! channel stays constant, and colours stay near where they were.

mod graft;

use crate::compute::Backend;
use crate::grid::RasterError;
use crate::mesh::{IndexedMesh, Mesh, MeshError, Mutation, Replacement};
use crate::project::{Bvh, ProjectError, closest_points};
use crate::topology::nearest::Survivors;
use glam::Vec3;
use graft::{Bounds, Corner, Graft, Side};
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// Components whose bounding-box diagonal is at most this many cells count as small.
pub const SMALL_CELLS: f32 = 4.0;

/// Most vertices of one component that vote on its match.
const VOTERS: usize = 256;

/// How closely the tracked mesh must follow the input where the grid cannot see.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Fidelity {
    /// The input's components and Euler characteristics, within `max_distance`, on every frame:
    /// a component of any size the grid leaves different is replaced.
    #[default]
    Input,
    /// As `Input`, but a component that differs is always replaced whole, never grafted: where
    /// the input differs the surface is the input's own, with no seam for improvement to reshape.
    InputWhole,
    /// The topology the grid resolves (paper §4.3), plus the components below
    /// [`SMALL_CELLS`]: larger components keep their vertices (and their coherence) even where
    /// the input has a sheet, tunnel or bridge thinner than a cell.
    Grid,
}

/// What reconciliation changed in one frame.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct ReconcileCounts {
    /// Components of `M` deleted (on no component of `T`, or a small duplicate).
    pub deleted: usize,
    /// Components of `T` copied in (no component of `M` on them).
    pub inserted: usize,
    /// Components of `M` replaced whole by a copy of their match.
    pub replaced: usize,
    /// Components of `M` that took their match's triangles only where the two differ.
    #[serde(default)]
    pub grafted: usize,
}

impl ReconcileCounts {
    pub fn changed(&self) -> bool {
        self.deleted + self.inserted + self.replaced + self.grafted > 0
    }
}

#[derive(Debug, Error)]
pub enum ReconcileError {
    #[error("matching components: {0}")]
    Project(#[from] ProjectError),
    #[error("rebuilding the mesh: {0}")]
    Mesh(#[from] MeshError),
    #[error("comparing the surfaces on the grid: {0}")]
    Raster(#[from] RasterError),
}

/// One component of a mesh: its vertices (indices), Euler characteristic and extent.
struct Component {
    vertices: Vec<u32>,
    euler: i64,
    diagonal: f32,
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

/// Makes `mesh`'s components agree with `target`'s where the grid of spacing `spacing` cannot
/// (see the module comment); `max_distance` (world units) is the farthest either surface may lie
/// from the other. `bvh` is built over `target`. The change goes through `Mesh::replace`, whose
/// record lists creations first, then deletions. Returns what changed; `mesh` is untouched when
/// nothing does.
pub fn reconcile_components(
    backend: &Backend,
    mesh: &mut Mesh,
    target: &IndexedMesh,
    bvh: &Bvh,
    spacing: f32,
    max_distance: f32,
    fidelity: Fidelity,
) -> Result<ReconcileCounts, ReconcileError> {
    let current = mesh.to_indexed();
    let (ours, our_labels) = components(&current);
    let (theirs, target_labels) = components(target);
    let small = SMALL_CELLS * spacing;
    let matched = match_components(
        backend,
        &current,
        &ours,
        (target, &target_labels, theirs.len()),
        bvh,
        spacing,
    )?;
    let our_triangles = triangles_by_component(&current, &our_labels, ours.len());
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); theirs.len()];
    for (c, m) in matched.iter().enumerate() {
        if let Some(k) = *m {
            members[k].push(c);
        }
    }
    let largest: Vec<Option<usize>> = members
        .iter()
        .map(|group| {
            group
                .iter()
                .copied()
                .max_by_key(|&c| (ours[c].vertices.len(), std::cmp::Reverse(c)))
        })
        .collect();
    let (our_far, their_far) = match fidelity {
        Fidelity::Input | Fidelity::InputWhole if !current.triangles.is_empty() => {
            // The input is measured against what stays if every group is faithful: without the
            // unmatched components and the small duplicates, which are deleted then.
            let ours = &ours;
            let stays: Vec<u32> = members
                .iter()
                .zip(&largest)
                .flat_map(|(group, &l)| {
                    group
                        .iter()
                        .copied()
                        .filter(move |&c| Some(c) == l || ours[c].diagonal > small)
                })
                .flat_map(|c| our_triangles[c].iter().copied())
                .collect();
            let staying = graft::submesh(&current, &stays);
            (
                far_components(
                    backend,
                    bvh,
                    &current,
                    &our_labels,
                    ours.len(),
                    max_distance,
                )?,
                if staying.triangles.is_empty() {
                    theirs
                        .iter()
                        .map(|c| {
                            c.vertices
                                .iter()
                                .map(|&v| target.positions[v as usize])
                                .collect()
                        })
                        .collect()
                } else {
                    far_components(
                        backend,
                        &Bvh::build(&staying)?,
                        target,
                        &target_labels,
                        theirs.len(),
                        max_distance,
                    )?
                },
            )
        }
        _ => (vec![Vec::new(); ours.len()], vec![Vec::new(); theirs.len()]),
    };
    let their_triangles = triangles_by_component(target, &target_labels, theirs.len());

    // Decide, per component of theirs, which of ours stay on it, or whether a copy replaces them,
    // whole or grafted.
    let mut delete = vec![false; ours.len()];
    let mut insert = vec![false; theirs.len()];
    let mut grafts: Vec<Option<Graft>> = (0..theirs.len()).map(|_| None).collect();
    let mut replaces: Vec<Vec<usize>> = vec![Vec::new(); theirs.len()];
    let mut counts = ReconcileCounts::default();
    for (c, _) in matched.iter().enumerate().filter(|(_, m)| m.is_none()) {
        delete[c] = true;
        counts.deleted += 1;
    }
    for (k, group) in members.iter().enumerate() {
        let Some(largest) = largest[k] else {
            insert[k] = true;
            counts.inserted += 1;
            continue;
        };
        let others = group.iter().copied().filter(|&c| c != largest);
        let faithful = match fidelity {
            Fidelity::Input | Fidelity::InputWhole => {
                ours[largest].euler == theirs[k].euler
                    && our_far[largest].is_empty()
                    && their_far[k].is_empty()
                    && others.clone().all(|c| ours[c].diagonal <= small)
            }
            Fidelity::Grid => {
                ours[largest].euler == theirs[k].euler
                    || ours[largest].diagonal > small
                    || theirs[k].diagonal > small
            }
        };
        if faithful {
            for c in others.filter(|&c| ours[c].diagonal <= small) {
                delete[c] = true;
                counts.deleted += 1;
            }
            continue;
        }
        let grafted = match fidelity {
            Fidelity::Input => {
                let far: Vec<Vec3> = group
                    .iter()
                    .flat_map(|&c| &our_far[c])
                    .chain(&their_far[k])
                    .copied()
                    .collect();
                graft::graft(
                    &Side::new(
                        &current,
                        group
                            .iter()
                            .flat_map(|&c| &our_triangles[c])
                            .copied()
                            .collect(),
                    ),
                    &Side::new(target, their_triangles[k].clone()),
                    &far,
                    &Bounds {
                        backend,
                        target_bvh: bvh,
                        spacing,
                        max_distance,
                        euler: theirs[k].euler,
                    },
                )?
            }
            Fidelity::InputWhole | Fidelity::Grid => None,
        };
        for &c in group {
            delete[c] = true;
        }
        replaces[k] = group.clone();
        if grafted.is_some() {
            counts.grafted += 1;
        } else {
            insert[k] = true;
            counts.replaced += 1;
        }
        grafts[k] = grafted;
    }
    if !counts.changed() {
        return Ok(counts);
    }

    // The new surface: our kept triangles, then per component of theirs its copied triangles and
    // the strips joining them to ours.
    let ids = current.ids.as_deref().unwrap_or_default();
    let id_of = |v: u32| ids.get(v as usize).copied().unwrap_or(u64::from(v));
    let mut keep_triangle: Vec<bool> = current
        .triangles
        .iter()
        .map(|t| !delete[our_labels[t[0] as usize] as usize])
        .collect();
    for g in grafts.iter().flatten() {
        for &t in &g.kept {
            keep_triangle[t as usize] = true;
        }
    }
    let mut keep = vec![false; current.positions.len()];
    for (tri, _) in current
        .triangles
        .iter()
        .zip(&keep_triangle)
        .filter(|(_, k)| **k)
    {
        for &v in tri {
            keep[v as usize] = true;
        }
    }
    let mut index = vec![u32::MAX; current.positions.len()];
    let (mut positions, mut new_ids) = (Vec::new(), Vec::new());
    for (v, _) in keep.iter().enumerate().filter(|(_, k)| **k) {
        index[v] = positions.len() as u32;
        positions.push(current.positions[v]);
        new_ids.push(id_of(v as u32));
    }
    let mut triangles: Vec<[u32; 3]> = current
        .triangles
        .iter()
        .zip(&keep_triangle)
        .filter(|(_, k)| **k)
        .map(|(t, _)| t.map(|v| index[v as usize]))
        .collect();
    // Every vertex exists when the creations are applied going forward; every kept vertex and
    // every copy when the deletions are undone going backward.
    let before = Survivors::new(
        current
            .positions
            .iter()
            .enumerate()
            .map(|(v, &p)| (v as u32, p)),
        spacing,
    );

    // Creations: a copied vertex takes its data from the component it replaces or is grafted
    // into, any other copy from the nearest vertex.
    let mut record: Vec<Mutation> = Vec::new();
    let mut next_id = mesh.next_id();
    let mut target_index = vec![u32::MAX; target.positions.len()];
    let mut survivors_of: Vec<Vec<u32>> = vec![Vec::new(); theirs.len()];
    for k in (0..theirs.len()).filter(|&k| insert[k] || grafts[k].is_some()) {
        let copied: Vec<u32> = match &grafts[k] {
            Some(g) => {
                let mut used: Vec<u32> = g
                    .copied
                    .iter()
                    .flat_map(|&t| target.triangles[t as usize])
                    .chain(g.zip.iter().flatten().filter_map(|c| match *c {
                        Corner::Theirs(v) => Some(v),
                        Corner::Ours(_) => None,
                    }))
                    .collect();
                used.sort_unstable();
                used.dedup();
                used
            }
            None => theirs[k].vertices.clone(),
        };
        let group_vertices = || replaces[k].iter().flat_map(|&c| &ours[c].vertices);
        let replaced = Survivors::new(
            group_vertices().map(|&v| (v, current.positions[v as usize])),
            spacing,
        );
        for v in copied {
            let p = target.positions[v as usize];
            let source = replaced.nearest(p).or_else(|| before.nearest(p)).map(id_of);
            target_index[v as usize] = positions.len() as u32;
            survivors_of[k].push(positions.len() as u32);
            positions.push(p);
            new_ids.push(next_id);
            record.push(Mutation::PatchCreated {
                created: next_id,
                sources: source.map(|s| vec![(s, 1.0)]).unwrap_or_default(),
            });
            next_id += 1;
        }
        let corner = |c: Corner| match c {
            Corner::Ours(v) => index[v as usize],
            Corner::Theirs(v) => target_index[v as usize],
        };
        match &grafts[k] {
            Some(g) => {
                triangles.extend(
                    g.copied
                        .iter()
                        .map(|&t| target.triangles[t as usize].map(|v| target_index[v as usize])),
                );
                triangles.extend(g.zip.iter().map(|t| t.map(corner)));
                survivors_of[k].extend(
                    group_vertices()
                        .filter(|&&v| keep[v as usize])
                        .map(|&v| index[v as usize]),
                );
            }
            None => triangles.extend(
                their_triangles[k]
                    .iter()
                    .map(|&t| target.triangles[t as usize].map(|v| target_index[v as usize])),
            ),
        }
    }

    // Deletions: a vertex of a replaced or grafted component takes its data from that component's
    // result going backward; any other deleted vertex from the nearest kept or copied vertex.
    let after = Survivors::new(
        positions.iter().enumerate().map(|(i, &p)| (i as u32, p)),
        spacing,
    );
    let results: Vec<Survivors> = replaces
        .iter()
        .zip(&survivors_of)
        .filter(|(group, _)| !group.is_empty())
        .map(|(_, s)| Survivors::new(s.iter().map(|&i| (i, positions[i as usize])), spacing))
        .collect();
    let mut source_of: Vec<&Survivors> = vec![&after; ours.len()];
    for (group, survivors) in replaces.iter().filter(|g| !g.is_empty()).zip(&results) {
        for &c in group {
            source_of[c] = survivors;
        }
    }
    for c in (0..ours.len()).filter(|&c| delete[c]) {
        for &v in ours[c].vertices.iter().filter(|&&v| !keep[v as usize]) {
            let source = source_of[c].nearest(current.positions[v as usize]);
            record.push(Mutation::PatchDeleted {
                deleted: id_of(v),
                sources: source
                    .map(|i| vec![(new_ids[i as usize], 1.0)])
                    .unwrap_or_default(),
            });
        }
    }
    let mut surface = IndexedMesh::new(positions, triangles);
    surface.ids = Some(new_ids);
    mesh.replace(Replacement { surface, record })?;
    Ok(counts)
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
fn match_components(
    backend: &Backend,
    current: &IndexedMesh,
    ours: &[Component],
    (target, target_labels, theirs): (&IndexedMesh, &[u32], usize),
    bvh: &Bvh,
    spacing: f32,
) -> Result<Vec<Option<usize>>, ReconcileError> {
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

/// The samples of each component of `mesh` (vertex labels `labels`, `count` components) farther
/// than `max_distance` (world units) from the surface in `bvh`, measured where `eval` measures: at every
/// vertex, edge midpoint and triangle centroid.
///
/// Only vertices are queried first: distance to a surface is 1-Lipschitz, so a midpoint or
/// centroid lies within `max_distance` when one of its triangle's vertices lies within
/// `max_distance` minus its offset from that vertex. Only the samples this leaves open are
/// queried, which on a tracked frame are almost none, so the check costs about one query per
/// vertex instead of four.
fn far_components(
    backend: &Backend,
    bvh: &Bvh,
    mesh: &IndexedMesh,
    labels: &[u32],
    count: usize,
    max_distance: f32,
) -> Result<Vec<Vec<Vec3>>, ReconcileError> {
    let reach = max_distance / bvh.mean_edge_length();
    let distance: Vec<f32> = closest_points(backend, bvh, &mesh.positions, reach)?
        .iter()
        .map(|hit| match hit.hit_triangle() {
            Some(_) => hit.distance.abs(),
            None => f32::INFINITY,
        })
        .collect();
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
    // A margin for rounding, so a bound never admits a sample the query would reject.
    let bounded = max_distance * (1.0 - 1e-4);
    let within = |p: Vec3, corners: &[u32]| {
        corners
            .iter()
            .any(|&v| distance[v as usize] + (p - mesh.positions[v as usize]).length() <= bounded)
    };
    let (mut open, mut owners) = (Vec::new(), Vec::new());
    for tri in &mesh.triangles {
        let p = tri.map(|v| mesh.positions[v as usize]);
        let centroid = (p[0] + p[1] + p[2]) / 3.0;
        let midpoints = (0..3)
            .filter(|&k| tri[k] < tri[(k + 1) % 3])
            .map(|k| (p[k] + p[(k + 1) % 3]) * 0.5);
        for s in std::iter::once(centroid).chain(midpoints) {
            if !within(s, tri) {
                open.push(s);
                owners.push(labels.get(tri[0] as usize).copied().unwrap_or(u32::MAX));
            }
        }
    }
    if open.is_empty() {
        return Ok(far);
    }
    let found = closest_points(backend, bvh, &open, reach)?;
    for ((hit, owner), &p) in found.iter().zip(&owners).zip(&open) {
        if hit.hit_triangle().is_none() {
            mark(Some(owner), p);
        }
    }
    Ok(far)
}
