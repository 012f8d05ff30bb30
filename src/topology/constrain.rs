//! `ConstrainTopology(M, Θ)` (paper §4.3): classify, grow, cut, fill, stitch, verify — and never
//! fail.
//!
//! Each attempt builds the whole result and checks it exactly: closed, manifold, consistently
//! oriented and non-degenerate (the validation `Mesh::from_indexed` runs), with the components and
//! per-component Euler characteristics of Θ's isosurface. An attempt that falls short teaches the
//! next one: a local failure (a triangle that could not be split or triangulated, an invalid
//! element) adds the cells around it to the seeds and tries the same classification again, a few
//! times; a topology left different by a shallow difference makes the classification stricter:
//! every difference deep, first only in the components whose topology came out wrong
//! (`mismatch`), and there first only where replacing changes the Euler characteristic
//! (`narrow`), then everywhere, then every face the cut could not run along, then wider margins.
//! When every local attempt fails the whole surface is replaced by Θ's isosurface, which is closed
//! and manifold by construction — that last step is the guarantee, the local attempts are what
//! keep re-sampling small.
//!
//! With `keep_shared_sheets` (for a caller that matches the input's own topology below the grid
//! afterwards) a sheet thinner than a cell that Θ's mesh has too is no difference, and a result
//! is accepted where its topology differs from Θ's only in components holding such a sheet, or in
//! droplets (`mismatch`), or in components that an attempt focused on them left as wrong as
//! before: the grid cannot mend those, and the caller matches them below it.

use std::rc::Rc;
use std::time::Instant;

use rustc_hash::{FxHashMap, FxHashSet};

use super::build::{Built, build};
use super::classify::{Strictness, dilate, seeds, shared_sheet_cells};
use super::cut::cut;
use super::face_arcs::Arc;
use super::field::Field;
use super::fill::fill;
use super::isosurface::{place_isosurface, signature};
use super::keys::{Cell, GridFace, cell_face, cell_neighbour};
use super::mesh_grid::{MeshGrid, MeshRaster};
use super::mismatch::mismatched;
use super::move_onto::move_onto;
use super::narrow::changing;
use super::points::Point;
use super::record::record;
use super::region::{Checks, grow};
use super::theta_surface::ThetaSurface;
use super::transfer::{Carry, Transfer};
use super::{Abandoned, Resampling, TopologyError, TopologyOptions, TopologyReport};
use super::{cell, droplets};
use crate::mesh::{IndexedMesh, Mesh, Replacement};
use glam::Vec3;

/// Constrains the topology of `mesh` to that of Θ's isosurface (paper §4.3): where the two differ
/// deeply, the mesh's triangles are replaced by Θ's isosurface, cut and stitched along the boundary
/// of the region of complex cells; elsewhere the mesh is untouched (same vertex ids, same
/// positions). Called as `constrain_topology(M, Φ(M))` it merges self-intersections; as
/// `constrain_topology(M, Φ(T))` it gives M the topology of the target frame.
///
/// The result is closed, 2-manifold and consistently oriented, with the same components and
/// per-component Euler characteristic as Θ's isosurface; its new vertices lie on Θ's zero set or on
/// the cut. New vertices get fresh ids; the record of where every created and removed vertex came
/// from and went (paper §4.4) goes with the new surface into `Mesh::replace`, which journals it and
/// carries attribute channels by the same rules.
/// Triangle quality is not this step's concern: the caller improves the mesh afterwards
/// (Algorithm 1, line 12).
pub fn constrain_topology(
    mesh: &mut Mesh,
    theta: &Field,
    options: &TopologyOptions,
) -> Result<TopologyReport, TopologyError> {
    constrain_topology_on(mesh, (theta, &ThetaSurface::of(theta)), None, options)
}

/// [`constrain_topology`] with Θ's isosurface extracted beforehand (`ThetaSurface::of(theta)`),
/// as the tracker does for Φ(T) while registration runs, and, where Θ is Φ(M), the raster it
/// was measured from, which the cut reads too: `MeshRaster::new` of `mesh.to_indexed()` on Θ's
/// grid, on the CPU (a device's crossings agree with the twin's within a tolerance, and the cut
/// must see the same ones on either backend). A raster of another mesh or grid is not used.
pub fn constrain_topology_on(
    mesh: &mut Mesh,
    (theta, iso): (&Field, &ThetaSurface),
    raster: Option<MeshRaster>,
    options: &TopologyOptions,
) -> Result<TopologyReport, TopologyError> {
    let (mut report, replacement) = resample(mesh, (theta, iso), raster, options)?;
    if let Some(replacement) = replacement {
        let reach = options.continue_within * theta.frame().spacing();
        let (replacement, continued) = replacement.continuing(mesh, reach);
        report.continued = continued;
        mesh.replace(replacement)?;
    }
    Ok(report)
}

/// The attempts of [`constrain_topology`]; the new surface and its record, unless nothing changes.
fn resample(
    mesh: &Mesh,
    (theta, theta_surface): (&Field, &ThetaSurface),
    raster: Option<MeshRaster>,
    options: &TopologyOptions,
) -> Result<(TopologyReport, Option<Replacement>), TopologyError> {
    let start = Instant::now();
    let input = mesh.to_indexed();
    let (surface, iso, target) = (
        &theta_surface.cells,
        &theta_surface.mesh,
        &theta_surface.signature,
    );
    let grid = match raster {
        Some(raster) if raster.fits(theta.frame(), input.positions.len()) => {
            MeshGrid::rastered(&input, mesh, raster)
        }
        _ => MeshGrid::new(&input, mesh, *theta.frame())?,
    };
    let mut checks = Checks::new(&grid, theta);
    let mut report = TopologyReport::default();
    let mut extra: Vec<Cell> = Vec::new();
    // The surface every attempt's new vertices read.
    let old = Transfer::new(&input.positions, &input.triangles[..]);

    let steps = ladder(options);
    let every = Strictness {
        depth: 0,
        faces: false,
        dilate: 0,
        keep_shared: options.keep_shared_sheets,
    };
    // Built on the first comparison: most steps never compare components.
    let compared = || theta_surface.compared(theta);
    let mut explained = if options.keep_shared_sheets {
        shared_sheet_cells(&grid, theta)
    } else {
        FxHashSet::default()
    };
    // Droplets apart from the body are the caller's too: no seed lies in their cells or next to
    // them, and a result that still differs from Θ there is accepted. Re-sampled, a droplet
    // thinner than the grid is deleted (Θ does not hold it) and the caller copies the input's
    // back with fresh ids: on the dam break's frame 28, 274 of its droplets' 276 vertices went.
    let apart: FxHashSet<Cell> = if options.keep_shared_sheets {
        let frame = theta.frame();
        let cells: Vec<Cell> = droplets(frame, &input, true)
            .iter()
            .flatten()
            .map(|&v| cell(frame, input.positions[v as usize]))
            .collect();
        dilate(&cells, 1).into_iter().collect()
    } else {
        FxHashSet::default()
    };
    explained.extend(apart.iter().copied());
    // Whether a surface's topology is what this step must give: Θ's, or, keeping shared sheets,
    // Θ's but where such a sheet makes the difference. Where it is not, the cells of the
    // components that differ if they were compared, which a failed attempt reuses.
    let accepted = |mesh: &IndexedMesh| -> Result<(), Option<Vec<Cell>>> {
        if signature(mesh) == *target {
            return Ok(());
        }
        if !options.keep_shared_sheets {
            return Err(None);
        }
        let wrong = mismatched(theta.frame(), mesh, compared(), &explained);
        if wrong.is_empty() {
            Ok(())
        } else {
            Err(Some(wrong))
        }
    };
    // The components whose topology the previous attempt got wrong, its seeds, and whether only
    // the shallow differences there that change χ are taken (`narrow`).
    let mut focus: Option<(Vec<Cell>, Vec<Cell>, bool)> = None;
    // The wrong components and seeds again, to take all their shallow differences should the
    // narrowed attempt fail.
    let mut fallback: Option<(Vec<Cell>, Vec<Cell>)> = None;
    let (mut step, mut attempt) = (0, 0);
    // Whether the last attempt failed locally (its cells are in `extra`), and how often the
    // current step was tried again for it.
    let (mut local, mut retries) = (false, 0);
    // The cells a focused attempt works on (the wrong components' cells, grown by one): one whose
    // result is wrong only there found nothing there that the grid can mend.
    let mut focus_area: Vec<Cell> = Vec::new();
    loop {
        let again = local && retries < LOCAL_RETRIES && focus.is_none() && fallback.is_none();
        if step >= steps.len() && !again {
            break;
        }
        let clock = Instant::now();
        if let Some((wrong, before)) = fallback.take() {
            focus = Some((wrong, before, false));
        }
        let focused = focus.is_some();
        let mut cells = match focus.take() {
            Some((wrong, before, narrowed)) => {
                let mut cells = seeds(&grid, theta, &every);
                cells.retain(|c| wrong.binary_search(c).is_ok());
                if narrowed {
                    let changing = changing(&grid, (surface, iso), &cells);
                    if changing.len() < cells.len() {
                        fallback = Some((wrong, before.clone()));
                        cells = changing;
                    }
                }
                cells.extend(before);
                cells
            }
            None => {
                // A local failure tries the same step again around where it failed; anything
                // else makes the classification stricter.
                if again {
                    retries += 1;
                } else {
                    step += 1;
                    retries = 0;
                }
                seeds(&grid, theta, &steps[step - 1])
            }
        };
        // Seeds only around droplets apart from the body leave the mesh as it is, unless it is
        // wrong elsewhere too: then they are taken, as without droplets set apart.
        let unset: Vec<Cell> = cells
            .iter()
            .copied()
            .filter(|c| !apart.contains(c))
            .collect();
        if !unset.is_empty() || cells.is_empty() || accepted(&input).is_ok() {
            cells = unset;
        }
        local = false;
        attempt += 1;
        let tried = cells.clone();
        cells.extend_from_slice(&extra);
        cells.sort_unstable();
        cells.dedup();
        let region = grow(&cells, &mut checks);
        report.seed_cells = cells.len();
        report.region_cells = region.len();
        report.classify += clock.elapsed();
        if region.is_empty() {
            if accepted(&input).is_ok() {
                report.kept = input.positions.len();
                report.euler = signature(&input);
                report.total = start.elapsed();
                return Ok((report, None));
            }
            report.abandoned.push(Abandoned::NoDeepDifference);
            continue;
        }
        let clock = Instant::now();
        // The first attempt's record reads the input's tree: built meanwhile.
        let attempted = old.prepare_while(|| attempt_region(&grid, theta, &region, &mut checks));
        let outcome = match attempted {
            Ok((mut built, splits)) => {
                move_fill(&mut built, &input, (theta.frame().spacing(), options));
                let recorded = record(
                    &grid,
                    &built,
                    &splits,
                    (mesh.next_id(), &old, options.carry),
                )?;
                // The result's topology and its validity are judged on both cores at once; the
                // half-edge mesh is wasted only where the topology is wrong.
                let (judged, valid) = rayon::join(
                    || accepted(&built.mesh),
                    || validated(&built.mesh, &recorded),
                );
                // Every difference inside the components that came out wrong was re-sampled,
                // and the result is wrong there again, and nowhere else: what makes them differ
                // from Θ's lies below the grid. Keeping shared sheets, the caller matches the
                // input there, and the result is taken; the ladder's next step would re-sample
                // every shallow difference of the whole surface instead (DFSPH frame 30: 13,392
                // cells rather than 5,887, for three small components against Θ's two).
                let below = options.keep_shared_sheets
                    && focused
                    && fallback.is_none()
                    && matches!(&judged, Err(Some(wrong))
                        if wrong.iter().all(|c| focus_area.binary_search(c).is_ok()));
                let verdict = verify(valid, judged.is_ok() || below);
                Ok((built, recorded, verdict, judged))
            }
            Err(points) => Err(points),
        };
        report.rebuild += clock.elapsed();
        match outcome {
            Err(points) => {
                let cells: Vec<Cell> = points.iter().flat_map(|p| point_cells(&grid, p)).collect();
                report.abandoned.push(Abandoned::CutOrFill {
                    cells: cells.clone(),
                });
                extra.extend(cells);
                local = true;
            }
            Ok((built, recorded, verdict, judged)) => match verdict {
                Ok(surface) => {
                    report.resampling = Resampling::Local {
                        attempt: attempt - 1,
                    };
                    report.region = region.iter().copied().collect();
                    report.region.sort_unstable();
                    report.euler = signature(&built.mesh);
                    let replacement = summarize(surface, recorded, &mut report);
                    report.total = start.elapsed();
                    return Ok((report, Some(replacement)));
                }
                Err(Failure::Topology) => {
                    report.abandoned.push(Abandoned::Topology);
                    if !focused && steps[step - 1].depth > 0 {
                        let wrong = match judged {
                            Err(Some(wrong)) => wrong,
                            _ => mismatched(theta.frame(), &built.mesh, compared(), &explained),
                        };
                        let wrong = dilate(&wrong, 1);
                        if !wrong.is_empty() {
                            focus_area.clone_from(&wrong);
                            focus = Some((wrong, tried, true));
                        }
                    }
                }
                Err(Failure::Element(vertices)) => {
                    let cells: Vec<Cell> = vertices
                        .iter()
                        .filter_map(|&v| built.points.get(v as usize))
                        .flat_map(|p| point_cells(&grid, p))
                        .collect();
                    report.abandoned.push(Abandoned::InvalidElement {
                        cells: cells.clone(),
                    });
                    extra.extend(cells);
                    local = true;
                }
            },
        }
        extra = widen(&extra);
    }
    report.region_cells = surface.len();
    let replacement = replace_whole(
        (mesh, &old, options.carry),
        &grid,
        (theta, theta_surface),
        &mut report,
    )?;
    report.total = start.elapsed();
    Ok((report, Some(replacement)))
}

/// Most times one step of the ladder is tried again after a local failure (a cut or fill that
/// failed, an invalid element), each time with the cells around every failure so far.
const LOCAL_RETRIES: usize = 2;

/// The attempts, from the configured depth to the strictest classification with wide margins.
fn ladder(options: &TopologyOptions) -> Vec<Strictness> {
    let mut steps = vec![Strictness {
        depth: options.depth,
        faces: false,
        dilate: 0,
        keep_shared: options.keep_shared_sheets,
    }];
    if options.depth > 0 {
        steps.push(Strictness {
            depth: 0,
            faces: false,
            dilate: 0,
            keep_shared: options.keep_shared_sheets,
        });
    }
    for dilate in [0, 1, 3] {
        steps.push(Strictness {
            depth: 0,
            faces: true,
            dilate,
            keep_shared: options.keep_shared_sheets,
        });
    }
    steps
}

/// The planes at which each split mesh edge is cut, in order from its first vertex.
type Splits = FxHashMap<u32, Vec<(u8, i32)>>;

/// Cut, fill and assemble for one region.
fn attempt_region(
    grid: &MeshGrid,
    theta: &Field,
    region: &FxHashSet<Cell>,
    checks: &mut Checks,
) -> Result<(Built, Splits), Vec<Point>> {
    let mut cells: Vec<Cell> = region.iter().copied().collect();
    cells.sort_unstable();
    let mut fronts: Vec<(GridFace, Rc<Vec<Arc>>)> = Vec::new();
    for &cell in &cells {
        for f in 0..6 {
            if region.contains(&cell_neighbour(cell, f)) {
                continue;
            }
            let face = cell_face(cell, f);
            let arcs = checks
                .face(face)
                .ok_or_else(|| vec![Point::Centre { cell, index: 0 }])?;
            fronts.push((face, arcs));
        }
    }
    let kept = cut(grid, region, &fronts)
        .map_err(|t| grid.mesh.triangles[t as usize].map(Point::Vertex).to_vec())?;
    let filled = fill(grid, theta, region, &cells, checks)
        .map_err(|cell| vec![Point::Centre { cell, index: 0 }])?;
    let built = build(grid, theta, &kept, &filled)?;
    Ok((built, kept.splits))
}

enum Failure {
    /// Not closed, manifold or non-degenerate around these output vertices.
    Element(Vec<u32>),
    /// Valid, but with a topology other than Θ's.
    Topology,
}

/// The half-edge mesh of a result, with its ids, where it is closed, manifold, oriented and
/// non-degenerate (checked by `Mesh::from_indexed`, once) or empty.
fn validated(mesh: &IndexedMesh, recorded: &super::record::Recorded) -> Result<Mesh, Failure> {
    if mesh.triangles.is_empty() {
        return Ok(Mesh::empty());
    }
    let mut output = mesh.clone();
    output.ids = Some(recorded.ids.clone());
    output.attributes.clear();
    Mesh::from_indexed(&output).map_err(|e| Failure::Element(e.vertices(&mesh.triangles)))
}

/// A [`validated`] result, where it has the topology the step must give (`topology_accepted`).
fn verify(valid: Result<Mesh, Failure>, topology_accepted: bool) -> Result<Mesh, Failure> {
    if !topology_accepted {
        return Err(Failure::Topology);
    }
    valid
}

/// Moves new vertices of the fill onto the carried input vertices the patch removes
/// (`move_onto`), where the options ask for it; cut points stay on the cut.
fn move_fill(built: &mut Built, input: &IndexedMesh, (spacing, options): (f32, &TopologyOptions)) {
    let moves = options.moves.where_continuing(options.continue_within);
    if moves.carried_below == 0 {
        return;
    }
    let mut kept = vec![false; input.positions.len()];
    let mut fill = Vec::new();
    for (i, p) in built.points.iter().enumerate() {
        match *p {
            Point::Vertex(v) => kept[v as usize] = true,
            _ if p.is_fill() => fill.push(i as u32),
            _ => {}
        }
    }
    let ids = input.ids.as_deref().unwrap_or_default();
    let removed: Vec<Vec3> = (0..input.positions.len())
        .filter(|&v| !kept[v] && ids.get(v).is_some_and(|&id| id < moves.carried_below))
        .map(|v| input.positions[v])
        .collect();
    let mesh = &mut built.mesh;
    let bounds = (spacing, moves.longest_edge);
    move_onto(
        &mut mesh.positions,
        &mesh.triangles,
        &fill,
        &removed,
        bounds,
    );
}

/// Cells a point lies in or on.
fn point_cells(grid: &MeshGrid, p: &Point) -> Vec<Cell> {
    match *p {
        Point::Vertex(v) => vec![grid.vertex_cell(v)],
        Point::Pierce { edge, axis, plane } => {
            let cell = grid.segment(edge).face(usize::from(axis), plane);
            GridFace::new(cell, usize::from(axis)).cells().to_vec()
        }
        Point::Crossing { edge, .. } | Point::Level(edge) => edge.cells().to_vec(),
        Point::Centre { cell, .. } => vec![cell],
    }
}

/// Cells around the given ones (one cell in every direction), sorted.
fn widen(cells: &[Cell]) -> Vec<Cell> {
    let mut out: Vec<Cell> = cells
        .iter()
        .flat_map(|&c| {
            (-1..=1).flat_map(move |x| {
                (-1..=1).flat_map(move |y| (-1..=1).map(move |z| [c[0] + x, c[1] + y, c[2] + z]))
            })
        })
        .collect();
    out.sort_unstable();
    out.dedup();
    out
}

/// What the recorded surgery did, into the report; the replacement it stands for.
fn summarize(
    surface: Mesh,
    recorded: super::record::Recorded,
    report: &mut TopologyReport,
) -> Replacement {
    report.kept = recorded.ids.len() - recorded.cut - recorded.patch;
    report.deleted = recorded.deleted;
    report.cut = recorded.cut;
    report.patch = recorded.patch;
    Replacement {
        surface,
        record: recorded.record,
    }
}

/// The last resort: every input vertex is removed and Θ's isosurface takes the mesh's place.
fn replace_whole(
    (mesh, old, carry): (&Mesh, &Transfer, Carry),
    grid: &MeshGrid,
    (theta, theta_surface): (&Field, &ThetaSurface),
    report: &mut TopologyReport,
) -> Result<Replacement, TopologyError> {
    let clock = Instant::now();
    let (mut iso, edges) = (theta_surface.mesh.clone(), &theta_surface.edges);
    let target = &theta_surface.signature;
    place_isosurface(theta, &mut iso, edges);
    let built = Built {
        points: edges.iter().copied().map(Point::Level).collect(),
        mesh: iso,
        parameters: Default::default(),
    };
    let recorded = record(
        grid,
        &built,
        &Default::default(),
        (mesh.next_id(), old, carry),
    )?;
    let (topology, valid) = rayon::join(
        || signature(&built.mesh) == *target,
        || validated(&built.mesh, &recorded),
    );
    let surface = verify(valid, topology).map_err(|_| TopologyError::Unresolved {
        abandoned: report.abandoned.clone(),
    })?;
    report.resampling = Resampling::Whole;
    let replacement = summarize(surface, recorded, report);
    report.euler = target.to_vec();
    report.rebuild += clock.elapsed();
    Ok(replacement)
}
