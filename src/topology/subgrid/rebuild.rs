//! The surface the plan gives and its record (paper §4.4): the kept tracked triangles, then per
//! input component its copied triangles and the strips joining them to the kept ones. As in a
//! topology patch, each new vertex takes its data from the surface it replaces at its closest
//! point, and each deleted one, going backward, from what replaces it at its own, as the
//! tracker's `Carry` says (`topology::transfer`). On a splash sheet thinner than an edge the
//! vertex nearest in space may lie on the sheet's other side; the closest triangle does not.

use glam::Vec3;

use super::decide::Plan;
use super::graft::Corner;
use super::{SubgridError, Surfaces};
use crate::mesh::{IndexedMesh, Mesh, Mutation, Replacement};
use crate::topology::move_onto::move_onto;
use crate::topology::transfer::{Carry, Transfer};

/// The replacement `plan` stands for; created vertices take ids from `next_id` on. Fails when the
/// assembled surface is not a closed, oriented 2-manifold.
pub(super) fn replacement(
    s: &Surfaces,
    plan: &Plan,
    next_id: u64,
) -> Result<Replacement, SubgridError> {
    let (current, target, spacing, carry) = (s.current, s.target, s.spacing, s.carry);
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
    // The input component whose copy or graft replaces each tracked component, if any.
    let mut group_of: Vec<Option<usize>> = vec![None; ours.len()];
    for (k, group) in replaces.iter().enumerate() {
        for &c in group {
            group_of[c] = Some(k);
        }
    }
    // Per input component, the triangles of its result (new indices): the kept triangles of the
    // tracked components it replaces, then its copied triangles and strips.
    let mut result_of: Vec<Vec<[u32; 3]>> = vec![Vec::new(); theirs.len()];
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    for (t, _) in current
        .triangles
        .iter()
        .zip(&keep_triangle)
        .filter(|(_, k)| **k)
    {
        let kept = t.map(|v| index[v as usize]);
        if let Some(k) = group_of[our_labels[t[0] as usize] as usize] {
            result_of[k].push(kept);
        }
        triangles.push(kept);
    }
    // The input components copied in, whole or grafted, and the input vertices each copies.
    let copying: Vec<usize> = (0..theirs.len())
        .filter(|&k| insert[k] || grafts[k].is_some())
        .collect();
    let copies_of = |k: usize| -> Vec<u32> {
        match &grafts[k] {
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
        }
    };
    let copied: Vec<Vec<u32>> = copying.iter().map(|&k| copies_of(k)).collect();
    let mut target_index = vec![u32::MAX; target.positions.len()];
    let first_created = next_id;
    // Per copy, where its vertices lie among the new surface's (moved ones included).
    let mut copied_range = Vec::with_capacity(copying.len());
    for (&k, copied) in copying.iter().zip(copied.iter()) {
        let first = positions.len() as u32;
        for &v in copied {
            target_index[v as usize] = positions.len() as u32;
            positions.push(target.positions[v as usize]);
            new_ids.push(next_id);
            next_id += 1;
        }
        let corner = |c: Corner| match c {
            Corner::Ours(v) => index[v as usize],
            Corner::Theirs(v) => target_index[v as usize],
        };
        let copies: Vec<[u32; 3]> = match &grafts[k] {
            Some(g) => g
                .copied
                .iter()
                .map(|&t| target.triangles[t as usize].map(|v| target_index[v as usize]))
                .chain(g.zip.iter().map(|t| t.map(corner)))
                .collect(),
            None => their_triangles[k]
                .iter()
                .map(|&t| target.triangles[t as usize].map(|v| target_index[v as usize]))
                .collect(),
        };
        let carried: Vec<Vec3> = replaces[k]
            .iter()
            .flat_map(|&c| &ours[c].vertices)
            .filter(|&&v| !keep[v as usize] && id_of(v) < s.moves.carried_below)
            .map(|&v| current.positions[v as usize])
            .collect();
        let end = positions.len() as u32;
        let movable: Vec<u32> = (first..end).collect();
        let bounds = (spacing, s.moves.longest_edge);
        move_onto(&mut positions, &copies, &movable, &carried, bounds);
        copied_range.push(first as usize..end as usize);
        triangles.extend_from_slice(&copies);
        result_of[k].extend(copies);
    }
    let gone: Vec<(usize, Vec<u32>)> = (0..ours.len())
        .filter(|&c| delete[c])
        .map(|c| {
            let vertices = ours[c].vertices.iter().copied();
            (c, vertices.filter(|&v| !keep[v as usize]).collect())
        })
        .collect();
    let mut surface = IndexedMesh::new(positions, triangles);
    surface.ids = Some(new_ids);
    let copied_at = |i: usize| surface.positions[copied_range[i].clone()].iter().copied();

    // Creations: going forward, every tracked vertex exists when they are applied. A copy reads
    // the tracked components its copy or graft replaces, any other copy the whole tracked
    // surface; the copies reading one surface are asked at once.
    let created = || -> Result<Sources, SubgridError> {
        let mut sources: Sources = vec![Vec::new(); copying.len()];
        let inserted: Vec<usize> = (0..copying.len())
            .filter(|&i| replaces[copying[i]].is_empty())
            .collect();
        read_sources(
            (&current.positions, &current.triangles, spacing, carry),
            &inserted,
            copied_at,
            &mut sources,
        )?;
        for i in (0..copying.len()).filter(|&i| !replaces[copying[i]].is_empty()) {
            let replaced: Vec<[u32; 3]> = replaces[copying[i]]
                .iter()
                .flat_map(|&c| &s.ours.triangles[c])
                .map(|&t| current.triangles[t as usize])
                .collect();
            read_sources(
                (&current.positions, &replaced, spacing, carry),
                &[i],
                copied_at,
                &mut sources,
            )?;
        }
        Ok(sources)
    };
    // Deletions: going backward, every kept vertex and every copy exists when they are undone. A
    // vertex of a replaced or grafted component reads that component's result; any other
    // deleted vertex the whole new surface. The vertices reading one surface are asked at once.
    let deleted = || -> Result<Sources, SubgridError> {
        let mut sources: Sources = vec![Vec::new(); gone.len()];
        let mut readers: Vec<Option<usize>> = gone.iter().map(|(c, _)| group_of[*c]).collect();
        readers.sort_unstable();
        readers.dedup();
        for reader in readers {
            let asking: Vec<usize> = (0..gone.len())
                .filter(|&i| group_of[gone[i].0] == reader)
                .collect();
            let on = match reader {
                Some(k) => &result_of[k],
                None => &surface.triangles,
            };
            read_sources(
                (&surface.positions, on, spacing, carry),
                &asking,
                |i| gone[i].1.iter().map(|&v| current.positions[v as usize]),
                &mut sources,
            )?;
        }
        Ok(sources)
    };
    // The two reads and the new surface's half-edges need only the assembled surface: they are
    // found side by side.
    let ((created, deleted), built) = rayon::join(
        || rayon::join(created, deleted),
        || Mesh::from_indexed(&surface),
    );
    let mut record: Vec<Mutation> = Vec::new();
    for (source, id) in created?.into_iter().flatten().zip(first_created..) {
        record.push(Mutation::PatchCreated {
            created: id,
            sources: source.into_iter().map(|(u, w)| (id_of(u), w)).collect(),
        });
    }
    let new_ids = surface.ids.as_deref().unwrap_or_default();
    for ((_, vertices), found) in gone.iter().zip(deleted?) {
        for (&v, source) in vertices.iter().zip(found) {
            record.push(Mutation::PatchDeleted {
                deleted: id_of(v),
                sources: source
                    .into_iter()
                    .map(|(i, w)| (new_ids[i as usize], w))
                    .collect(),
            });
        }
    }
    Ok(Replacement {
        surface: built?,
        record,
    })
}

/// Per list of points, per point, the (vertex, weight) terms it takes its data from.
type Sources = Vec<Vec<Vec<(u32, f32)>>>;

/// For each list `i` of `asking`, what the points `at(i)` take from `surface` (triangles over
/// `positions`) under `carry` (`Transfer::read`), into `sources[i]`: every list reading one
/// surface is asked at once, through one tree over the triangles around them all
/// (`Transfer::around`, with cells of size `cell`).
fn read_sources<I: Iterator<Item = Vec3>>(
    (positions, surface, cell, carry): (&[Vec3], &[[u32; 3]], f32, Carry),
    asking: &[usize],
    at: impl Fn(usize) -> I,
    sources: &mut [Vec<Vec<(u32, f32)>>],
) -> Result<(), SubgridError> {
    if asking.is_empty() {
        return Ok(());
    }
    let points: Vec<Vec3> = asking.iter().flat_map(|&i| at(i)).collect();
    let mut found = Transfer::around(positions, surface, &points, cell)
        .read(&points, carry)?
        .into_iter();
    for &i in asking {
        sources[i] = found.by_ref().take(at(i).count()).collect();
    }
    Ok(())
}
