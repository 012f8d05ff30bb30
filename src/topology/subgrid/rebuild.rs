//! The surface the plan gives and its record (paper §4.4): the kept tracked triangles, then per
//! input component its copied triangles and the strips joining them to the kept ones; each new
//! vertex takes its data from the nearest vertex it replaces, each deleted one from the nearest
//! vertex of what replaces it.

use rayon::prelude::*;

use super::Surfaces;
use super::decide::Plan;
use super::graft::Corner;
use crate::mesh::{IndexedMesh, Mesh, MeshError, Mutation, Replacement};
use crate::topology::nearest::Survivors;

/// The replacement `plan` stands for; created vertices take ids from `next_id` on. Fails when the
/// assembled surface is not a closed, oriented 2-manifold.
pub(super) fn replacement(
    s: &Surfaces,
    plan: &Plan,
    next_id: u64,
) -> Result<Replacement, MeshError> {
    let (current, target, spacing) = (s.current, s.target, s.spacing);
    let (ours, our_labels) = (&s.ours.list, &s.ours.labels);
    let (theirs, their_triangles) = (&s.theirs.list, &s.theirs.triangles);
    let (delete, insert, grafts, replaces) =
        (&plan.delete, &plan.insert, &plan.grafts, &plan.replaces);
    let mut next_id = next_id;

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
        let sources: Vec<Option<u64>> = copied
            .par_iter()
            .map(|&v| {
                let p = target.positions[v as usize];
                replaced.nearest(p).or_else(|| before.nearest(p)).map(id_of)
            })
            .collect();
        for (v, source) in copied.into_iter().zip(sources) {
            let p = target.positions[v as usize];
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
        let gone: Vec<u32> = ours[c]
            .vertices
            .iter()
            .copied()
            .filter(|&v| !keep[v as usize])
            .collect();
        let sources =
            source_of[c].nearest_each(gone.par_iter().map(|&v| current.positions[v as usize]));
        for (v, source) in gone.into_iter().zip(sources) {
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
    Ok(Replacement {
        surface: Mesh::from_indexed(&surface)?,
        record,
    })
}
