//! Components below the grid's resolution. `ConstrainTopology` (paper §4.3) sees the surfaces only
//! through a grid of spacing Δ: a droplet smaller than a cell, or one that vanished inside a cell,
//! leaves no trace in it (notes on the topology step, §6: "sub-cell components inside a simple cell
//! are invisible to every test; pick a policy"). Fluid caches are full of them: marching cubes of a
//! particle field sheds droplets of a handful of vertices every frame. The tracked mesh must still
//! have the input's components, so after the two topology steps every component of `M` is matched
//! with the component of `T` that most of its vertices lie on (within one cell), and:
//!
//! * a component of `M` that lies on no component of `T` (a droplet `T` lost) is deleted;
//! * a component of `T` that no component of `M` lies on (a droplet born below the grid) is copied
//!   in with fresh ids;
//! * a small component of `M` (within [`SMALL_CELLS`] cells) that shares its match with a larger
//!   one is deleted, and one whose Euler characteristic differs from a small match is replaced by a
//!   copy of it.
//!
//! Larger components are left to `ConstrainTopology`, which resolves everything the grid can see.
//! Like a topology patch with no boundary (§4.4), each deleted vertex takes, going backward, and each
//! copied vertex takes, going forward, the data of the nearest surviving vertex, so every vertex of
//! every frame holds a value and a constant channel stays constant.

use crate::compute::Backend;
use crate::events::{Event, EventList};
use crate::mesh::{IndexedMesh, Mesh, MeshError};
use crate::project::{Bvh, ProjectError, closest_points};
use crate::topology::nearest::Survivors;
use glam::Vec3;
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// Components whose bounding-box diagonal is at most this many cells count as small.
pub const SMALL_CELLS: f32 = 4.0;

/// Most vertices of one component that vote on its match.
const VOTERS: usize = 256;

/// What reconciliation changed in one frame.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct ReconcileCounts {
    /// Components of `M` deleted (on no component of `T`, or a small duplicate).
    pub deleted: usize,
    /// Components of `T` copied in (no component of `M` on them).
    pub inserted: usize,
    /// Small components of `M` replaced by their match (Euler characteristic unlike it).
    pub replaced: usize,
}

impl ReconcileCounts {
    pub fn changed(&self) -> bool {
        self.deleted + self.inserted + self.replaced > 0
    }
}

#[derive(Debug, Error)]
pub enum ReconcileError {
    #[error("matching components: {0}")]
    Project(#[from] ProjectError),
    #[error("rebuilding the mesh: {0}")]
    Mesh(#[from] MeshError),
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
/// (see the module comment). `bvh` is built over `target`. Returns the events (deletions first,
/// then insertions) and what changed; `mesh` is untouched when nothing does.
pub fn reconcile_components(
    backend: &Backend,
    mesh: &mut Mesh,
    target: &IndexedMesh,
    bvh: &Bvh,
    spacing: f32,
) -> Result<(EventList, ReconcileCounts), ReconcileError> {
    let current = mesh.to_indexed();
    let (ours, _) = components(&current);
    let (theirs, target_labels) = components(target);
    let small = SMALL_CELLS * spacing;

    // Each of our components votes, vertex by vertex, for the target component within a cell; a
    // large component votes with an evenly strided sample of its vertices.
    let voters: Vec<&[u32]> = ours.iter().map(|c| c.vertices.as_slice()).collect();
    let sample: Vec<Vec<u32>> = voters
        .iter()
        .map(|v| {
            let step = v.len().div_ceil(VOTERS).max(1);
            v.iter().step_by(step).copied().collect()
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
        let mut votes = vec![0usize; theirs.len()];
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

    // Decide, per component of ours, whether it goes; per component of theirs, whether it comes.
    let mut delete = vec![false; ours.len()];
    let mut insert = vec![false; theirs.len()];
    let mut counts = ReconcileCounts::default();
    let mut largest: Vec<Option<usize>> = vec![None; theirs.len()];
    for (c, m) in matched.iter().enumerate() {
        match *m {
            None => {
                delete[c] = true;
                counts.deleted += 1;
            }
            Some(k) => {
                let bigger = |o: usize| ours[o].vertices.len() >= ours[c].vertices.len();
                if largest[k].is_none_or(|o| !bigger(o)) {
                    largest[k] = Some(c);
                }
            }
        }
    }
    for (c, m) in matched.iter().enumerate() {
        let Some(k) = *m else { continue };
        if largest[k] != Some(c) {
            if ours[c].diagonal <= small {
                delete[c] = true;
                counts.deleted += 1;
            }
        } else if ours[c].euler != theirs[k].euler
            && ours[c].diagonal <= small
            && theirs[k].diagonal <= small
        {
            delete[c] = true;
            insert[k] = true;
            counts.replaced += 1;
        }
    }
    for (k, l) in largest.iter().enumerate() {
        if l.is_none() {
            insert[k] = true;
            counts.inserted += 1;
        }
    }
    if !counts.changed() {
        return Ok((EventList::new(), counts));
    }

    // The new surface: our kept components, then copies of the inserted ones.
    let ids = current.ids.as_deref().unwrap_or_default();
    let mut keep = vec![true; current.positions.len()];
    for c in ours
        .iter()
        .zip(&delete)
        .filter(|(_, d)| **d)
        .map(|(c, _)| c)
    {
        for &v in &c.vertices {
            keep[v as usize] = false;
        }
    }
    let mut index = vec![u32::MAX; current.positions.len()];
    let (mut positions, mut new_ids) = (Vec::new(), Vec::new());
    for (v, _) in keep.iter().enumerate().filter(|(_, k)| **k) {
        index[v] = positions.len() as u32;
        positions.push(current.positions[v]);
        new_ids.push(ids.get(v).copied().unwrap_or(v as u64));
    }
    let mut triangles: Vec<[u32; 3]> = current
        .triangles
        .iter()
        .filter(|t| keep[t[0] as usize])
        .map(|t| t.map(|v| index[v as usize]))
        .collect();
    let survivors = Survivors::new(
        positions.iter().enumerate().map(|(i, &p)| (i as u32, p)),
        spacing,
    );
    let kept_ids = new_ids.clone();
    let survivor_id = |p: Vec3| survivors.nearest(p).map(|i| kept_ids[i as usize]);

    let mut events = EventList::new();
    for (v, _) in keep.iter().enumerate().filter(|(_, k)| !**k) {
        let id = ids.get(v).copied().unwrap_or(v as u64);
        let source = survivor_id(current.positions[v]);
        events.push(Event::patch_deleted(
            id,
            source.map(|s| vec![(s, 1.0)]).unwrap_or_default(),
        ));
    }
    let mut next_id = mesh.next_id();
    let mut target_index = vec![u32::MAX; target.positions.len()];
    for k in (0..theirs.len()).filter(|&k| insert[k]) {
        for &v in &theirs[k].vertices {
            let p = target.positions[v as usize];
            let source = survivor_id(p);
            target_index[v as usize] = positions.len() as u32;
            positions.push(p);
            new_ids.push(next_id);
            events.push(Event::patch_created(
                next_id,
                source.map(|s| vec![(s, 1.0)]).unwrap_or_default(),
            ));
            next_id += 1;
        }
    }
    triangles.extend(
        target
            .triangles
            .iter()
            .filter(|t| target_index[t[0] as usize] != u32::MAX)
            .map(|t| t.map(|v| target_index[v as usize])),
    );
    let mut rebuilt = IndexedMesh::new(positions, triangles);
    rebuilt.ids = Some(new_ids);
    let mut replacement = Mesh::from_indexed(&rebuilt)?;
    replacement.reserve_ids_below(next_id);
    *mesh = replacement;
    Ok((events, counts))
}
