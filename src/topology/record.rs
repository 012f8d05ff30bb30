//! The record of one topology change (paper §4.4): how every new vertex takes its data and every
//! removed one gives it, handed to the mesh with the new surface (`Mesh::replace`), which carries
//! the attribute channels by the same rules.
//!
//! * A cut point is a vertex inserted on the input surface: on a mesh edge (`split_edge`, linear
//!   in its parameter) or inside a triangle (`split_face`, barycentric).
//! * A new fill vertex takes, going forward, the data of the old surface at its closest point:
//!   the barycentric combination of the corners of the nearest input triangle ([`Transfer`]). No
//!   backward rule. The fill is listed before the deletions, so every corner it reads still
//!   exists when its rule applies.
//! * A deleted vertex takes, going backward, the data of the new patch (the result's triangles
//!   with a cut or fill corner) at its closest point. No forward rule. Undone last first, the
//!   deletions read the fill before the fill itself is undone.
//! * Where there is no such surface to read (an empty input, or no new triangle), the paper's
//!   rule stands in: the average of the neighbours already visited by a breadth-first march from
//!   the patch boundary (the surviving cut points around it), deletions innermost first and the
//!   fill outermost first, so each rule reads only vertices that still exist when it applies.
//!
//! A patch with no boundary (a component appearing or vanishing whole) has nothing to average: each
//! of its vertices copies the nearest vertex that survives the change (the droplet takes the data of
//! the surface it comes from), so every vertex of every frame holds a value and a constant stays
//! constant. Only when nothing survives are the events left without rules.

use std::sync::OnceLock;

use glam::Vec3;
use rayon::prelude::*;

use super::build::Built;
use super::mesh_grid::MeshGrid;
use super::nearest::Survivors;
use super::points::Point;
use super::transfer::{Carry, Transfer};
use crate::mesh::Mutation;
use crate::project::ProjectError;
use rustc_hash::{FxHashMap, FxHashSet};

/// Ids and record of an assembled surface.
#[derive(Debug, Clone)]
pub(crate) struct Recorded {
    pub ids: Vec<u64>,
    pub record: Vec<Mutation>,
    pub cut: usize,
    pub patch: usize,
    pub deleted: usize,
}

/// A neighbour in the breadth-first marches: a vertex of the result or a deleted input vertex.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Near {
    Boundary(u32),
    Patch(u32),
}

pub(crate) fn record(
    grid: &MeshGrid,
    built: &Built,
    splits: &FxHashMap<u32, Vec<(u8, i32)>>,
    (next_id, old, carry): (u64, &Transfer, Carry),
) -> Result<Recorded, ProjectError> {
    let input = grid.mesh;
    let n_in = input.positions.len();
    let input_ids: Vec<u64> = match &input.ids {
        Some(ids) if ids.len() == n_in => ids.clone(),
        _ => (0..n_in as u64).collect(),
    };
    let n_out = built.points.len();
    let mut ids = vec![0u64; n_out];
    let mut output_of = vec![u32::MAX; n_in];
    let mut fresh = next_id;
    for (i, p) in built.points.iter().enumerate() {
        ids[i] = match *p {
            Point::Vertex(v) => {
                output_of[v as usize] = i as u32;
                input_ids[v as usize]
            }
            _ => {
                fresh += 1;
                fresh - 1
            }
        };
    }
    let mut record: Vec<Mutation> = Vec::new();

    // Cut points.
    let mut cut = 0;
    for (i, p) in built.points.iter().enumerate() {
        match *p {
            Point::Pierce { edge, axis, plane } => {
                let s = built
                    .parameters
                    .get(&(edge, axis, plane))
                    .copied()
                    .unwrap_or(0.5) as f32;
                let [a, b] = grid.edges().verts[edge as usize];
                record.push(Mutation::SplitEdge {
                    a: input_ids[a as usize],
                    b: input_ids[b as usize],
                    created: ids[i],
                    t: s,
                });
            }
            Point::Crossing { triangle, .. } => {
                let corners = input.triangles[triangle as usize];
                let w = barycentric(
                    corners.map(|v| input.positions[v as usize]),
                    built.mesh.positions[i],
                );
                record.push(Mutation::SplitFace {
                    corners: corners.map(|v| input_ids[v as usize]),
                    created: ids[i],
                    weights: w,
                });
            }
            Point::Vertex(_) | Point::Level(_) | Point::Centre { .. } => continue,
        }
        cut += 1;
    }

    // Deleted vertices: neighbours along input edges, through the nearest surviving cut point.
    let mut pierce_index: FxHashMap<Point, u32> = FxHashMap::default();
    for (i, p) in built.points.iter().enumerate() {
        if matches!(p, Point::Pierce { .. }) {
            pierce_index.insert(*p, i as u32);
        }
    }
    let deleted: Vec<u32> = (0..n_in as u32)
        .filter(|&v| output_of[v as usize] == u32::MAX)
        .collect();
    let mut around: Vec<Vec<Near>> = vec![Vec::new(); n_in];
    for (e, &[v0, v1]) in grid.edges().verts.iter().enumerate() {
        for (d, x, forward) in [(v0, v1, true), (v1, v0, false)] {
            if output_of[d as usize] != u32::MAX {
                continue;
            }
            let list = splits.get(&(e as u32)).map_or(&[][..], |l| l.as_slice());
            let mut order: Vec<&(u8, i32)> = list.iter().collect();
            if !forward {
                order.reverse();
            }
            let through = order.iter().find_map(|&&(axis, plane)| {
                pierce_index
                    .get(&Point::Pierce {
                        edge: e as u32,
                        axis,
                        plane,
                    })
                    .copied()
            });
            around[d as usize].push(match through {
                Some(i) => Near::Boundary(i),
                None if output_of[x as usize] != u32::MAX => Near::Boundary(output_of[x as usize]),
                None => Near::Patch(x),
            });
        }
    }
    let (order, rules) = march(&deleted, |d| &around[d as usize]);
    let rule_ids = |terms: &[Near]| -> Vec<(u64, f32)> {
        let w = 1.0 / terms.len() as f32;
        terms
            .iter()
            .map(|t| match *t {
                Near::Boundary(i) => (ids[i as usize], w),
                Near::Patch(v) => (input_ids[v as usize], w),
            })
            .collect()
    };
    // The vertices no march reaches (a patch with no boundary) read the nearest survivor whole
    // (none where nothing survives); most patches have a boundary, so the survivors' grid is
    // built only where one does not.
    let survivors = OnceLock::new();
    let nearest_survivors = |points: Vec<Vec3>| -> Vec<Vec<(u64, f32)>> {
        if points.is_empty() {
            return Vec::new();
        }
        let nearest = survivors
            .get_or_init(|| {
                Survivors::new(
                    built
                        .points
                        .iter()
                        .enumerate()
                        .filter(|(_, p)| matches!(p, Point::Vertex(_)))
                        .map(|(i, _)| (i as u32, built.mesh.positions[i])),
                    grid.frame().spacing(),
                )
            })
            .nearest_each(points.into_par_iter());
        nearest
            .into_iter()
            .map(|s| s.map(|i| vec![(ids[i as usize], 1.0)]).unwrap_or_default())
            .collect()
    };
    let fill: Vec<u32> = (0..n_out as u32)
        .filter(|&i| built.points[i as usize].is_fill())
        .collect();
    // Going backward, the deletions; going forward, the fill. Each reads its own surface: the
    // two are found side by side.
    let deletions = || -> Result<Vec<Mutation>, ProjectError> {
        // Going backward, a deleted vertex reads the new patch at its closest point.
        let patch = Transfer::new(
            &built.mesh.positions,
            built
                .mesh
                .triangles
                .iter()
                .filter(|t| {
                    t.iter()
                        .any(|&i| !matches!(built.points[i as usize], Point::Vertex(_)))
                })
                .copied()
                .collect::<Vec<_>>(),
        );
        let on_patch = patch.read(
            &order
                .iter()
                .map(|&d| input.positions[d as usize])
                .collect::<Vec<_>>(),
            carry,
        )?;
        let mut deletions: Vec<Mutation> = Vec::new();
        let unreached = unreached(&deleted, &order);
        let sources = nearest_survivors(
            unreached
                .iter()
                .map(|&d| input.positions[d as usize])
                .collect(),
        );
        for (d, sources) in unreached.into_iter().zip(sources) {
            deletions.push(Mutation::PatchDeleted {
                deleted: input_ids[d as usize],
                sources,
            });
        }
        for ((d, terms), closest) in order.iter().zip(&rules).zip(&on_patch).rev() {
            deletions.push(Mutation::PatchDeleted {
                deleted: input_ids[*d as usize],
                sources: if closest.is_empty() {
                    rule_ids(terms)
                } else {
                    closest.iter().map(|&(i, w)| (ids[i as usize], w)).collect()
                },
            });
        }

        Ok(deletions)
    };
    let creations = || -> Result<Vec<Mutation>, ProjectError> {
        let mut created: Vec<Mutation> = Vec::new();
        // New fill vertices: neighbours along the result's edges.
        let mut adjacent: FxHashMap<u32, Vec<Near>> = FxHashMap::default();
        for tri in &built.mesh.triangles {
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                for (x, y) in [(a, b), (b, a)] {
                    if built.points[x as usize].is_fill() {
                        let near = if built.points[y as usize].is_fill() {
                            Near::Patch(y)
                        } else {
                            Near::Boundary(y)
                        };
                        adjacent.entry(x).or_default().push(near);
                    }
                }
            }
        }
        for list in adjacent.values_mut() {
            list.sort_unstable();
            list.dedup();
        }
        let empty = Vec::new();
        let (order, rules) = march(&fill, |v| adjacent.get(&v).unwrap_or(&empty));
        // Going forward, a fill vertex reads the old surface (`old`, over the input) at its closest
        // point.
        let on_replaced = old.read(
            &order
                .iter()
                .map(|&v| built.mesh.positions[v as usize])
                .collect::<Vec<_>>(),
            carry,
        )?;
        for ((&v, terms), closest) in order.iter().zip(&rules).zip(&on_replaced) {
            let sources = if closest.is_empty() {
                let w = 1.0 / terms.len() as f32;
                terms
                    .iter()
                    .map(|t| match *t {
                        Near::Boundary(i) | Near::Patch(i) => (ids[i as usize], w),
                    })
                    .collect()
            } else {
                closest
                    .iter()
                    .map(|&(u, w)| (input_ids[u as usize], w))
                    .collect()
            };
            created.push(Mutation::PatchCreated {
                created: ids[v as usize],
                sources,
            });
        }
        let unreached = unreached(&fill, &order);
        let sources = nearest_survivors(
            unreached
                .iter()
                .map(|&v| built.mesh.positions[v as usize])
                .collect(),
        );
        for (v, sources) in unreached.into_iter().zip(sources) {
            created.push(Mutation::PatchCreated {
                created: ids[v as usize],
                sources,
            });
        }
        Ok(created)
    };
    let (deletions, created) = rayon::join(deletions, creations);
    record.extend(created?);
    record.extend(deletions?);
    Ok(Recorded {
        ids,
        record,
        cut,
        patch: fill.len(),
        deleted: deleted.len(),
    })
}

/// The vertices of `patch` that a march (visiting `order`) did not reach, in `patch`'s order.
fn unreached(patch: &[u32], order: &[u32]) -> Vec<u32> {
    let reached: FxHashSet<u32> = order.iter().copied().collect();
    patch
        .iter()
        .copied()
        .filter(|v| !reached.contains(v))
        .collect()
}

/// Breadth-first march over `patch` (vertices whose neighbours are listed by `near`: `Output`
/// neighbours are the known boundary, `Deleted` ones other patch vertices) from the boundary
/// inward. Returns the vertices in the order they are visited and, for each, its neighbours visited
/// before it. Vertices no path from the boundary reaches are left out.
fn march<'a, F>(patch: &[u32], near: F) -> (Vec<u32>, Vec<Vec<Near>>)
where
    F: Fn(u32) -> &'a Vec<Near>,
{
    let mut visited: FxHashSet<u32> = FxHashSet::default();
    let mut order: Vec<u32> = Vec::new();
    let mut rules: Vec<Vec<Near>> = Vec::new();
    let mut visit = |v: u32, visited: &mut FxHashSet<u32>, order: &mut Vec<u32>| {
        let terms: Vec<Near> = near(v)
            .iter()
            .copied()
            .filter(|n| match n {
                Near::Boundary(_) => true,
                Near::Patch(u) => visited.contains(u),
            })
            .collect();
        visited.insert(v);
        order.push(v);
        rules.push(terms);
    };
    for &v in patch {
        if near(v).iter().any(|n| matches!(n, Near::Boundary(_))) {
            visit(v, &mut visited, &mut order);
        }
    }
    let mut head = 0;
    while head < order.len() {
        let v = order[head];
        head += 1;
        let mut next: Vec<u32> = near(v)
            .iter()
            .filter_map(|n| match n {
                Near::Patch(u) if !visited.contains(u) => Some(*u),
                _ => None,
            })
            .collect();
        next.sort_unstable();
        next.dedup();
        for u in next {
            if !visited.contains(&u) {
                visit(u, &mut visited, &mut order);
            }
        }
    }
    (order, rules)
}

/// Barycentric weights of the point of triangle `[a, b, c]` nearest to `p`, clamped non-negative.
fn barycentric([a, b, c]: [Vec3; 3], p: Vec3) -> [f32; 3] {
    let (a, b, c, p) = (a.as_dvec3(), b.as_dvec3(), c.as_dvec3(), p.as_dvec3());
    let (v0, v1, v2) = (b - a, c - a, p - a);
    let (d00, d01, d11) = (v0.dot(v0), v0.dot(v1), v1.dot(v1));
    let (d20, d21) = (v2.dot(v0), v2.dot(v1));
    let denom = d00 * d11 - d01 * d01;
    let (v, w) = if denom > 0.0 {
        (
            (d11 * d20 - d01 * d21) / denom,
            (d00 * d21 - d01 * d20) / denom,
        )
    } else {
        (1.0 / 3.0, 1.0 / 3.0)
    };
    let raw = [1.0 - v - w, v, w].map(|x: f64| x.max(0.0));
    let sum: f64 = raw.iter().sum();
    if sum > 0.0 {
        raw.map(|x| (x / sum) as f32)
    } else {
        [1.0 / 3.0; 3]
    }
}
