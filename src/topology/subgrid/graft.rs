//! Grafting the input into a component only where the grid cannot tell them apart.
//!
//! Replacing a whole component (see the module above) meets the input's topology and distance,
//! but renumbers every vertex of it: on a fluid cache, whose main body has a thin sheet or a
//! pinched tunnel somewhere in nearly every frame, that costs the coherence the tracker exists
//! for. The difference is almost always local, so the graft copies the input only in a *region*
//! of grid cells around it and keeps the tracked surface everywhere else, like the patches of
//! paper §4.4 but with the input's own triangles as the patch:
//!
//! 1. The region is seeded where the two surfaces differ below the grid ([`seeds`]): the cell
//!    of every sample farther than the distance bound from the other surface, and the clusters
//!    of grid edges crossed differently (a sheet, tunnel or bridge thinner than a cell) whose
//!    replacement changes the Euler characteristic, each grown by one cell in every direction.
//! 2. The tracked triangles with no vertex in the region are kept; the input's triangles with all
//!    their vertices in it are copied, so the two pieces never overlap and a gap of about one
//!    edge separates their boundaries. Pieces of either side too small to stand on their own,
//!    and boundary vertices that are pinched (two boundary edges leaving them), move into the
//!    region until both sides are clean.
//! 3. Each boundary loop of the kept side is paired with the copied side's loop that lies closest
//!    to it (each must be the other's nearest) and the two are zipped with the strip of triangles
//!    of least cost, found by dynamic programming as in optimal contour stitching: thin triangles
//!    and triangles turned against the boundary cost most.
//! 4. The result must be closed, manifold, one component with the input's Euler characteristic,
//!    and within the distance bound of the input both ways.
//!
//! Where step 2 copies nothing (the region is smaller than the input's triangles) or leaves a
//! boundary that is not a simple loop, the region grows by a cell around all of it and step 2
//! runs again; only a region that keeps nothing of the tracked side gives up.
//!
//! Where step 3 leaves a loop without a partner (the two surfaces cross the region's rim
//! differently there), the region grows around the loop's points that stray from the other
//! side's rims (no rim point of the other side in their cell or the 26 around it): a loop of a
//! thousand points that runs beside the other side's rims but for a stretch where they part
//! grows there only, not along its whole length (on the dam break's frame 24 the main body's
//! region then ends at 11.3k cells instead of 15.6k, keeping 26.4k tracked triangles instead of
//! 22.6k). A loop that strays nowhere grows whole, and where growing around strays runs out of
//! tries (the region creeping along a loop that needs more), the graft starts over growing
//! around whole loops. Where step 4 finds samples beyond the bound, the region grows around
//! them; where step 4 finds the result in pieces (the rim cut a bridge of the input), it grows
//! where the smaller pieces come next to the largest; where step 4 finds it not closed and
//! manifold (an edge of the strips that four triangles share), it grows around that element;
//! where step 4 finds another Euler
//! characteristic, the tracked surface kept and the input left out differ in topology outside
//! the region, and the region grows around the rims whose growth alone brings their numbers of
//! handles together ([`mending_rims`]: on the dam break's frame 34 the main body's region
//! then ends at 13.2k cells where growing every rim by a cell gave 22.0k); where none does, the
//! whole clusters that step 1 narrowed to the parts carrying their change join the region, then
//! the region grows by a cell around all of it (or, where that adds more cells, around the far
//! samples described next), then once around those far samples where there are any, then the
//! clusters step 1 left out join it,
//! and if it is still found, the region grows around the samples of either surface farther from
//! the other than half the bound, else a quarter (a hole or handle thinner than a cell that no
//! grid edge meets still holds one surface off the other there); only when there are none does
//! the whole region grow. Where step 1 finds nothing at all although the topology differs, the
//! region is seeded the same way. Steps 2–4 then run again, up to [`GROWTHS`] times; where the
//! region grown from the narrowed clusters runs out of them, the graft starts over from the whole
//! clusters that change χ (DFSPH frame 27 of one run: without it the main body was replaced
//! whole, 0.4% carried, with it 77.1%); after that the caller replaces the whole component.

use glam::Vec3;
use rustc_hash::{FxHashMap, FxHashSet};

use super::SubgridError;
use super::left_out::far_left_out;
use super::matching::{Against, Bounded, InputDistances, TrackedNearest, far_components};
use super::seeds;
use super::stitch::least_cost_steps;
use crate::compute::Backend;
use crate::grid::GridFrame;
use crate::mesh::{IndexedMesh, degenerate_triangle, min_angle_degrees};
use crate::topology::cell;
use crate::topology::classify::dilate;
use crate::topology::keys::Cell;
use rayon::prelude::*;

/// Edge-connected pieces smaller than this many triangles join the region: they are slivers
/// between region cells, not surface worth keeping apart from the rest.
const MIN_PIECE: usize = 64;

/// Most clean-up rounds of step 2; each only grows the region, so they end quickly.
const ROUNDS: usize = 8;

/// Loops compared in full (by mean vertex distance) for each loop, the nearest by centroid.
const CANDIDATES: usize = 4;

/// A vertex of the grafted surface: one of the tracked mesh's or one of the input's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(super) enum Corner {
    Ours(u32),
    Theirs(u32),
}

/// What a graft keeps, copies and adds.
pub(super) struct Graft {
    /// Triangles of the tracked mesh kept (indices into its triangle list).
    pub kept: Vec<u32>,
    /// Triangles of the input copied (indices into its triangle list).
    pub copied: Vec<u32>,
    /// The strips joining the two.
    pub zip: Vec<[Corner; 3]>,
}

/// One side of a graft: a mesh and the triangles (indices) of the component(s) involved.
pub(super) struct Side<'a> {
    pub mesh: &'a IndexedMesh,
    pub triangles: Vec<u32>,
    /// For each of `triangles` and each of its edges (corner k to k+1), the triangle (index into
    /// `triangles`) across it, or [`NONE`]: every mask below is read through it, so the many
    /// rounds of a graft look nothing up by hashing.
    across: Vec<[u32; 3]>,
    /// The selected triangles (indices into `triangles`) around each vertex of `mesh`: those
    /// of vertex `v` are `around[first[v]..first[v + 1]]`, so a clean-up round after the first
    /// looks only where the last one changed the mask.
    first: Vec<u32>,
    around: Vec<u32>,
    /// One triangle of each edge-connected piece of `triangles` smaller than [`MIN_PIECE`]:
    /// a mask that selects all or none of such a piece has no rim there, yet the clean-up
    /// moves it.
    small: Vec<u32>,
}

/// No triangle across an edge.
const NONE: u32 = u32::MAX;

impl<'a> Side<'a> {
    pub fn new(mesh: &'a IndexedMesh, triangles: Vec<u32>) -> Self {
        let mut first = vec![0u32; mesh.positions.len() + 1];
        for &t in &triangles {
            for v in mesh.triangles[t as usize] {
                first[v as usize + 1] += 1;
            }
        }
        for v in 0..mesh.positions.len() {
            first[v + 1] += first[v];
        }
        let mut fill = first.clone();
        let mut around = vec![0u32; 3 * triangles.len()];
        for (i, &t) in triangles.iter().enumerate() {
            for v in mesh.triangles[t as usize] {
                around[fill[v as usize] as usize] = i as u32;
                fill[v as usize] += 1;
            }
        }
        // The triangle across an edge (a, b) is the first around b holding the edge (b, a).
        let holds = |j: u32, (b, a): (u32, u32)| {
            let tri = mesh.triangles[triangles[j as usize] as usize];
            (0..3).any(|m| tri[m] == b && tri[(m + 1) % 3] == a)
        };
        let across: Vec<[u32; 3]> = triangles
            .par_iter()
            .with_min_len(1024)
            .map(|&t| {
                let tri = mesh.triangles[t as usize];
                std::array::from_fn(|k| {
                    let (a, b) = (tri[k], tri[(k + 1) % 3]);
                    let (start, end) = (first[b as usize], first[b as usize + 1]);
                    around[start as usize..end as usize]
                        .iter()
                        .copied()
                        .find(|&j| holds(j, (b, a)))
                        .unwrap_or(NONE)
                })
            })
            .collect();
        let small = small_components(&across);
        Side {
            mesh,
            triangles,
            across,
            first,
            around,
            small,
        }
    }

    /// The selected triangles (indices into `triangles`) with a corner at `v`.
    fn around(&self, v: u32) -> &[u32] {
        &self.around[self.first[v as usize] as usize..self.first[v as usize + 1] as usize]
    }

    /// The corners of the `i`-th triangle.
    fn corners(&self, i: usize) -> [u32; 3] {
        self.mesh.triangles[self.triangles[i] as usize]
    }

    /// Whether the edge from corner `k` of the `i`-th selected triangle is free: no selected
    /// triangle across it.
    fn free(&self, mask: &[bool], i: usize, k: usize) -> bool {
        let j = self.across[i][k];
        j == NONE || !mask[j as usize]
    }
}

/// The bounds a graft must meet.
pub(super) struct Bounds<'a> {
    pub backend: &'a Backend,
    /// The input's tree and the distances to it measured so far, for the result's distance check.
    pub input: &'a InputDistances<'a>,
    pub spacing: f32,
    pub max_distance: f32,
    /// The Euler characteristic of the input's component.
    pub euler: i64,
    /// The tracked triangle nearest each input vertex, as the match measured it (none where no
    /// tracked triangle stays).
    pub nearest: Option<&'a TrackedNearest>,
}

/// Grafts `theirs` into `ours` around the samples `far` (farther than the bound from the other
/// surface) and, unless `shape_only` (`ours` is one component of the input's Euler
/// characteristic), the grid edges the two cross differently; `None` when the result would not
/// meet the bounds (see the module comment), or when there is nothing local to graft.
pub(super) fn graft(
    (ours, theirs): (&Side, &Side),
    far: &[Vec3],
    shape_only: bool,
    bounds: &Bounds,
) -> Result<Option<Graft>, SubgridError> {
    let frame = GridFrame::new(Vec3::ZERO, bounds.spacing)?;
    let (tracked, input) = (
        submesh(ours.mesh, &ours.triangles),
        submesh(theirs.mesh, &theirs.triangles),
    );
    let mut seeds = seeds::seeds(bounds.backend, &frame, (&tracked, &input), far, shape_only)?;
    let cells =
        |points: Vec<Vec3>| -> Vec<Cell> { points.iter().map(|&p| cell(&frame, p)).collect() };
    // Halvings of the bound spent looking for where a wrong topology lies (see `Verdict::Fails`).
    let mut halvings = 0;
    if seeds.all.is_empty() {
        // No sample beyond the bound and no grid edge crossed differently, yet the topology
        // differs: the difference is looked for as a wrong result's is, below the bound.
        let found = suspected(&mut halvings, bounds, |distance| {
            far_apart((&tracked, &input, &tracked), bounds, distance)
        })?;
        if found.is_empty() {
            return Ok(None);
        }
        seeds.all = dilate(&cells(found), 1);
        seeds.changing.clone_from(&seeds.all);
    }
    let mut memo = Memo::new(&frame, ours, theirs);
    // Where the region grown from the narrowed clusters runs out of growths (starting smaller,
    // it spends more of them), the graft starts over from the whole clusters that change χ.
    let mut starts = vec![seeds];
    if starts[0].selected != starts[0].changing {
        let whole = seeds::Seeds {
            selected: starts[0].changing.clone(),
            changing: starts[0].changing.clone(),
            all: starts[0].all.clone(),
        };
        starts.push(whole);
    }
    for seeds in &starts {
        // A loose rim loop grows the region first only where it strays from the other side's
        // rims; where that runs out of growths (the region creeps along a loop that needs
        // more), the graft starts over growing around whole loops.
        let mut strayed = false;
        for reach in [Reach::Strays, Reach::Whole] {
            if reach == Reach::Whole && !strayed {
                break;
            }
            let grown = grow_graft(
                (ours, theirs),
                seeds,
                (reach, &mut strayed, halvings),
                bounds,
                &mut memo,
            )?;
            if grown.is_some() {
                return Ok(grown);
            }
        }
    }
    Ok(None)
}

/// How far a rim loop without a partner grows the region (see [`graft`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Reach {
    /// Around the loop's points with no rim point of the other side in their cell or the 26
    /// around it: where the two surfaces cross the region's rim differently. A loop that runs
    /// along the other side's rims everywhere (it pairs differently there) grows whole.
    Strays,
    /// Around every point of the loop.
    Whole,
}

/// Steps 2–4 of the module comment from `seeds`, growing the region up to [`GROWTHS`] times;
/// `strayed` is set when a loose loop grew only around its strays, `halvings` are those spent
/// before the first try.
fn grow_graft(
    (ours, theirs): (&Side, &Side),
    seeds: &seeds::Seeds,
    (reach, strayed, mut halvings): (Reach, &mut bool, usize),
    bounds: &Bounds,
    memo: &mut Memo,
) -> Result<Option<Graft>, SubgridError> {
    let frame = memo.frame;
    let cells =
        |points: Vec<Vec3>| -> Vec<Cell> { points.iter().map(|&p| cell(&frame, p)).collect() };
    let mut widened = seeds.selected.is_empty();
    let mut unsplit = widened || seeds.changing.len() == seeds.selected.len();
    let mut rimmed = widened;
    // Whether the far samples were looked at before every cluster joins.
    let mut probed = false;
    let mut region = if widened {
        seeds.all.clone()
    } else {
        seeds.selected.clone()
    };
    for _ in 0..GROWTHS {
        let trouble: Vec<[i32; 3]> = match attempt(&region, (ours, theirs), memo, reach) {
            Attempt::Hopeless => return Ok(None),
            Attempt::Lacking => region.clone(),
            Attempt::Unpaired { points, narrowed } => {
                *strayed |= narrowed;
                cells(points)
            }
            Attempt::Joined(graft) => {
                match check(&graft, ours.mesh, theirs, bounds)? {
                    Verdict::Meets => return Ok(Some(graft)),
                    // The kept tracked surface and the input left out differ in topology
                    // beside a rim that growing around that rim alone mends: it grows there.
                    Verdict::Fails => match mending_rims(&region, (ours, theirs), memo) {
                        Some(points) => cells(points),
                        // The narrowed parts missed part of a change: the clusters they came
                        // from join whole.
                        None if !unsplit => {
                            unsplit = true;
                            join(&mut region, &seeds.changing);
                            continue;
                        }
                        // The rim may cut through a selected difference: the region grows by
                        // one around all of them first, which keeps the graft local. Where the
                        // region is a sheet, that growth doubles it (dam-break frame 36: 8,084 →
                        // 18,972 cells, then the whole main body): where growing around the samples
                        // farther than half the bound (see below) adds fewer cells, the region
                        // grows there instead, and the rims later if that does not mend it.
                        None if !rimmed => {
                            let far =
                                cells(far_samples(&graft, (ours, theirs), bounds, &mut halvings)?);
                            let (mut by_far, mut by_rims) = (region.clone(), region.clone());
                            grow(&mut by_far, &far);
                            grow(&mut by_rims, &region);
                            region = if !far.is_empty() && by_far.len() < by_rims.len() {
                                by_far
                            } else {
                                rimmed = true;
                                by_rims
                            };
                            continue;
                        }
                        // The selected clusters are not all the difference. Joining every cluster
                        // can multiply the region (FLIP two columns, frame 49: 2,510 → 11,560
                        // cells, then 25,023 and 68.3% carried), so the region first grows once
                        // around the samples farther from the other surface than half the bound,
                        // else a quarter (see below; 90.5% carried there); where there are none, or
                        // that did not mend it, every cluster joins.
                        None if !widened => {
                            if !probed {
                                probed = true;
                                let found =
                                    far_samples(&graft, (ours, theirs), bounds, &mut halvings)?;
                                if !found.is_empty() {
                                    grow(&mut region, &cells(found));
                                    continue;
                                }
                            }
                            widened = true;
                            join(&mut region, &seeds.all);
                            continue;
                        }
                        // Where the topology went wrong is not known. A hole or handle thinner
                        // than a cell that no grid edge sees still leaves one surface off the
                        // other by a fraction of a cell there (the surface spanning the hole
                        // lies about the hole's radius from its rim), so the region grows first
                        // around the samples farther than half the bound, then a quarter; only
                        // where none are left does the whole region grow.
                        None => {
                            let found = far_samples(&graft, (ours, theirs), bounds, &mut halvings)?;
                            if found.is_empty() {
                                region.clone()
                            } else {
                                cells(found)
                            }
                        }
                    },
                    Verdict::Far(points) | Verdict::Apart(points) | Verdict::Invalid(points) => {
                        cells(points)
                    }
                }
            }
        };
        grow(&mut region, &trouble);
    }
    Ok(None)
}

/// Where a joined result of the wrong Euler characteristic needs its rim moved. The result has
/// χ(K) + χ(C) (the strips are annuli) and the input χ(L) + χ(C) (its copied and left-out parts
/// share circles), with K the kept tracked triangles, C the copied and L the input's left out:
/// so K and L, the surfaces outside the region, differ in topology, as where the rim cuts a
/// tunnel of one surface that the other spans beside it. Growing the whole region by a cell
/// moves every rim at once and re-samples a band along all of them; instead each kept loop's rim
/// is grown alone, and the points of the loops whose growth brings (χ + b)(K) − (χ + b)(L)
/// nearer 0 are returned, b counting boundary loops: χ + b is twice the components less twice
/// the handles, so a grown rim that merely leaves a loop without a partner does not count as a
/// change (dam-break frame 32 frame by frame: 59.05% carried by χ alone, 68.27% by χ + b). None
/// where no loop's growth does (the difference lies away from the rims, or needs several at
/// once), or where K and L agree (the result fails otherwise).
fn mending_rims(region: &[Cell], (ours, theirs): (&Side, &Side), memo: &Memo) -> Option<Vec<Vec3>> {
    let ((kept, our_loops), (copied, their_loops)) = masks(region, (ours, theirs), memo);
    let (our_loops, their_loops) = (our_loops?, their_loops?);
    // χ + b (twice the components less twice the genus) of K against L, whose rims are the
    // copied part's: a grown rim that leaves a loop without a partner changes χ but not the
    // handles, and would otherwise read as a change of topology.
    let differ = |kept: &[bool], copied: &[bool], rims: (usize, usize)| {
        mask_euler(ours, kept, true) + rims.0 as i64
            - mask_euler(theirs, copied, false)
            - rims.1 as i64
    };
    let before = differ(&kept, &copied, (our_loops.len(), their_loops.len()));
    if before == 0 {
        return None;
    }
    let mends: Vec<bool> = our_loops
        .par_iter()
        .map(|l| {
            let mut grown = region.to_vec();
            let around: Vec<Cell> = l
                .iter()
                .map(|&v| cell(&memo.frame, ours.mesh.positions[v as usize]))
                .collect();
            grow(&mut grown, &around);
            match masks(&grown, (ours, theirs), memo) {
                ((kept, Some(ks)), (copied, Some(cs))) => {
                    differ(&kept, &copied, (ks.len(), cs.len())).abs() < before.abs()
                }
                _ => false,
            }
        })
        .collect();
    let points: Vec<Vec3> = our_loops
        .iter()
        .zip(&mends)
        .filter(|(_, m)| **m)
        .flat_map(|(l, _)| l.iter().map(|&v| ours.mesh.positions[v as usize]))
        .collect();
    (!points.is_empty()).then_some(points)
}

/// The Euler characteristic V − E + F of the triangles of `side` whose mask entry is `select`.
fn mask_euler(side: &Side, mask: &[bool], select: bool) -> i64 {
    let chosen: Vec<bool> = mask.iter().map(|&m| m == select).collect();
    let mut used = vec![false; side.mesh.positions.len()];
    let (mut faces, mut free) = (0i64, 0i64);
    for i in (0..chosen.len()).filter(|&i| chosen[i]) {
        faces += 1;
        for (k, v) in side.corners(i).into_iter().enumerate() {
            used[v as usize] = true;
            if side.free(&chosen, i, k) {
                free += 1;
            }
        }
    }
    let vertices = used.iter().filter(|&&u| u).count() as i64;
    vertices - (3 * faces + free) / 2 + faces
}

/// Most times step 3 or 4 may grow the region around where it failed and try again.
const GROWTHS: usize = 24;

/// Halvings of the distance bound below which a wrong topology is looked for (half, a quarter).
const SUSPICIONS: usize = 2;

/// How one try at steps 2 and 3 ended.
enum Attempt {
    /// Nothing of the tracked side is left to keep: no region can graft.
    Hopeless,
    /// Nothing of the input lies wholly inside the region, or a boundary is not a simple loop:
    /// the region grows by a cell around all of it. A seed cluster of 27 cells around a tracked
    /// fold that the input passes beside holds no input triangle whole; giving up there replaced
    /// a dam-break main body whole (frame 7 of a run whose registration solved otherwise: 17.7%
    /// carried, 98.6% with the growth).
    Lacking,
    /// Boundary loops found no partner on the other side: the points the region grows around,
    /// and whether they are fewer than the loops' (see [`Reach::Strays`]).
    Unpaired {
        points: Vec<Vec3>,
        narrowed: bool,
    },
    Joined(Graft),
}

/// A pair of rim loops (kept, copied), by their vertices.
type LoopPair = (Vec<u32>, Vec<u32>);

/// What the tries of one graft share. The sides' vertices do not move between tries, and a
/// growth changes only the rim loops near it: most loops of one try come back unchanged in the
/// next, so their gaps and strips are measured and zipped once.
struct Memo {
    /// The grid the region's cells belong to.
    frame: GridFrame,
    /// Per side, its vertices (without repeats) with the cell of each, in order of cell: a
    /// region (sorted cells) finds the vertices inside it in one pass along both lists.
    ours: Vec<(u32, Cell)>,
    theirs: Vec<(u32, Cell)>,
    /// The gap of a pair of loops (kept, copied), keyed by their vertices.
    gaps: FxHashMap<LoopPair, f32>,
    /// The strip joining a pair of loops, keyed likewise.
    strips: FxHashMap<LoopPair, Vec<[Corner; 3]>>,
}

impl Memo {
    fn new(frame: &GridFrame, ours: &Side, theirs: &Side) -> Self {
        let cells = |side: &Side| -> Vec<(u32, Cell)> {
            // A side's vertices are those with a selected triangle around them.
            let mut placed: Vec<(u32, Cell)> = (0..side.mesh.positions.len() as u32)
                .filter(|&v| !side.around(v).is_empty())
                .map(|v| (v, cell(frame, side.mesh.positions[v as usize])))
                .collect();
            placed.par_sort_unstable_by_key(|&(v, c)| (c, v));
            placed
        };
        let (ours, theirs) = rayon::join(|| cells(ours), || cells(theirs));
        Memo {
            frame: *frame,
            ours,
            theirs,
            gaps: FxHashMap::default(),
            strips: FxHashMap::default(),
        }
    }
}

/// One side's mask over its triangles and its boundary loops (none where one is not simple).
type Masked = (Vec<bool>, Option<Vec<Vec<u32>>>);

/// Step 2 of the module comment for one region: the tracked triangles kept and the input's
/// copied (masks over each side's triangles), and each side's boundary loops (none where one is
/// not a simple loop).
fn masks(region: &[[i32; 3]], (ours, theirs): (&Side, &Side), memo: &Memo) -> (Masked, Masked) {
    let inside = |side: &Side, placed: &[(u32, Cell)]| -> Vec<bool> {
        let mut at = vec![false; side.mesh.positions.len()];
        let mut cells = region.iter().peekable();
        for &(v, c) in placed {
            while cells.next_if(|&&r| r < c).is_some() {}
            at[v as usize] = cells.peek() == Some(&&c);
        }
        at
    };
    // The two sides are cleaned and traced independently, each on its own core.
    rayon::join(
        || {
            let ours_in = inside(ours, &memo.ours);
            let mut kept: Vec<bool> = (0..ours.triangles.len())
                .map(|i| !ours.corners(i).iter().any(|&v| ours_in[v as usize]))
                .collect();
            clean_rounds(ours, &mut kept, Part::Kept);
            let loops = boundary_loops(ours, &kept);
            (kept, loops)
        },
        || {
            let theirs_in = inside(theirs, &memo.theirs);
            let mut copied: Vec<bool> = (0..theirs.triangles.len())
                .map(|i| theirs.corners(i).iter().all(|&v| theirs_in[v as usize]))
                .collect();
            clean_rounds(theirs, &mut copied, Part::Copied);
            let loops = boundary_loops(theirs, &copied);
            (copied, loops)
        },
    )
}

/// Steps 2 and 3 of the module comment for one region.
fn attempt(
    region: &[[i32; 3]],
    (ours, theirs): (&Side, &Side),
    memo: &mut Memo,
    reach: Reach,
) -> Attempt {
    let ((kept, our_loops), (copied, their_loops)) = masks(region, (ours, theirs), memo);
    if !kept.contains(&true) {
        return Attempt::Hopeless;
    }
    let (true, Some(our_loops), Some(their_loops)) =
        (copied.contains(&true), our_loops, their_loops)
    else {
        return Attempt::Lacking;
    };
    let pairs = pair_loops(
        (ours.mesh, &our_loops),
        (theirs.mesh, &their_loops),
        &mut memo.gaps,
    );
    if pairs.len() < our_loops.len().max(their_loops.len()) {
        let (points, narrowed) = loose_points(
            (ours.mesh, &our_loops),
            (theirs.mesh, &their_loops),
            &pairs,
            (&memo.frame, reach),
        );
        return Attempt::Unpaired { points, narrowed };
    }
    let (our_normals, their_normals) =
        rayon::join(|| rim_normals(ours, &kept), || rim_normals(theirs, &copied));
    let keys: Vec<LoopPair> = pairs
        .iter()
        .map(|&(a, c)| (our_loops[a].clone(), their_loops[c].clone()))
        .collect();
    let fresh: Vec<(usize, usize)> = pairs
        .iter()
        .zip(&keys)
        .filter(|(_, key)| !memo.strips.contains_key(*key))
        .map(|(&pair, _)| pair)
        .collect();
    let strips: Vec<Vec<[Corner; 3]>> = fresh
        .par_iter()
        .map(|&(a, c)| {
            zip_loops(
                &Rim {
                    mesh: ours.mesh,
                    points: &our_loops[a],
                    normals: &our_normals,
                },
                &Rim {
                    mesh: theirs.mesh,
                    points: &their_loops[c],
                    normals: &their_normals,
                },
            )
        })
        .collect();
    for (&(a, c), strip) in fresh.iter().zip(strips) {
        memo.strips
            .insert((our_loops[a].clone(), their_loops[c].clone()), strip);
    }
    let zip: Vec<[Corner; 3]> = keys
        .iter()
        .flat_map(|key| memo.strips[key].iter().copied())
        .collect();
    let chosen = |side: &Side, mask: &[bool]| -> Vec<u32> {
        side.triangles
            .iter()
            .zip(mask)
            .filter(|(_, m)| **m)
            .map(|(&t, _)| t)
            .collect()
    };
    Attempt::Joined(Graft {
        kept: chosen(ours, &kept),
        copied: chosen(theirs, &copied),
        zip,
    })
}

/// Adds the cells around `trouble` to `region` (sorted, without repeats): their 26 neighbours,
/// or, where those all lie in the region already (a far sample or a loose piece deep inside it,
/// which growing by one would not reach), the next ring out, up to [`REACH`] cells away.
fn grow(region: &mut Vec<[i32; 3]>, trouble: &[[i32; 3]]) {
    let size = region.len();
    for reach in 1..=REACH {
        join(region, &dilate(trouble, reach));
        if region.len() > size {
            return;
        }
    }
}

/// Adds `cells` to `region`, keeping it sorted and without repeats.
fn join(region: &mut Vec<[i32; 3]>, cells: &[[i32; 3]]) {
    region.extend_from_slice(cells);
    region.sort_unstable();
    region.dedup();
}

/// Farthest, in cells, the region grows around one trouble spot in one growth.
const REACH: u32 = 3;

/// The mesh made of `triangles` of `mesh`, with only the vertices they use (in index order).
pub(super) fn submesh(mesh: &IndexedMesh, triangles: &[u32]) -> IndexedMesh {
    let mut index = vec![u32::MAX; mesh.positions.len()];
    for &t in triangles {
        for v in mesh.triangles[t as usize] {
            index[v as usize] = 0;
        }
    }
    let mut positions = Vec::new();
    for (v, slot) in index.iter_mut().enumerate() {
        if *slot == 0 {
            *slot = positions.len() as u32;
            positions.push(mesh.positions[v]);
        }
    }
    let triangles = triangles
        .iter()
        .map(|&t| mesh.triangles[t as usize].map(|v| index[v as usize]))
        .collect();
    IndexedMesh::new(positions, triangles)
}

/// One triangle (the first) of each edge-connected piece of fewer than [`MIN_PIECE`] triangles,
/// with `across` the triangle across each edge.
fn small_components(across: &[[u32; 3]]) -> Vec<u32> {
    let mut seen = vec![false; across.len()];
    let mut small = Vec::new();
    let mut members = Vec::new();
    for start in 0..across.len() {
        if seen[start] {
            continue;
        }
        seen[start] = true;
        members.clear();
        members.push(start as u32);
        let mut next = 0;
        while next < members.len() {
            let i = members[next] as usize;
            next += 1;
            for &j in &across[i] {
                if j != NONE && !seen[j as usize] {
                    seen[j as usize] = true;
                    members.push(j);
                }
            }
        }
        if members.len() < MIN_PIECE {
            small.push(start as u32);
        }
    }
    small
}

/// The half-edges of the selected triangles with no selected triangle across, in triangle order.
fn free_half_edges(side: &Side, mask: &[bool]) -> Vec<(u32, u32)> {
    (0..mask.len())
        .filter(|&i| mask[i])
        .flat_map(|i| {
            let tri = side.corners(i);
            (0..3)
                .filter(move |&k| side.free(mask, i, k))
                .map(move |k| (tri[k], tri[(k + 1) % 3]))
        })
        .collect()
}

/// Which part of its side a mask selects: the tracked triangles kept, or the input's copied.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Part {
    Kept,
    Copied,
}

/// Step 2's clean-up of one side, up to [`ROUNDS`] rounds or until a round changes nothing. Each
/// round, the kept triangles lose their edge-connected pieces of fewer than [`MIN_PIECE`]
/// triangles, then those at pinched vertices (boundary vertices with more than one free
/// half-edge leaving them); the copied ones gain the small pieces left between them, then the
/// triangles at pinched vertices. Each side's rounds read and change its own mask only, so the
/// two sides are cleaned apart.
///
/// A round only ever moves triangles out of the movable set (the kept ones, or those not
/// copied), so it can only create a small piece or a pinched vertex next to a triangle it
/// moved: the first round starts from the mask's rim and from the side's own small pieces, and
/// each later one only around the triangles the round before it moved (a graft's region is
/// re-masked a few dozen times per frame, and most of each side lies far from its rim).
fn clean_rounds(side: &Side, mask: &mut [bool], part: Part) {
    let mut clean = Cleaning {
        side,
        part,
        large: vec![0; mask.len()],
        visited: vec![0; mask.len()],
        walk: 0,
        vertex_seen: vec![0; side.mesh.positions.len()],
    };
    let mut moved: Option<Vec<u32>> = None;
    for round in 1..=ROUNDS as u32 {
        let now = clean.round(mask, round, moved.as_deref());
        if now.is_empty() {
            break;
        }
        moved = Some(now);
    }
}

/// The scratch state of one side's [`clean_rounds`]: per triangle, the round in which it was
/// found in a large piece and the walk that last reached it; per vertex, the round that last
/// looked at it.
struct Cleaning<'s, 'm> {
    side: &'s Side<'m>,
    part: Part,
    large: Vec<u32>,
    visited: Vec<u32>,
    walk: u32,
    vertex_seen: Vec<u32>,
}

impl Cleaning<'_, '_> {
    /// Whether the mask entry `m` is one a round may flip.
    fn movable(&self, m: bool) -> bool {
        (self.part == Part::Kept) == m
    }

    /// One round: the triangles it moved. `moved` holds those the last round moved (`None` in
    /// the first round, which looks everywhere).
    fn round(&mut self, mask: &mut [bool], round: u32, moved: Option<&[u32]>) -> Vec<u32> {
        let side = self.side;
        // The first round's small pieces hold a triangle on the mask's rim or are pieces of
        // their own; later ones lie next to a triangle the last round moved.
        let (starts, looked): (Vec<u32>, Vec<u32>) = match moved {
            None => {
                let rim: Vec<u32> = (0..mask.len() as u32)
                    .filter(|&i| {
                        side.across[i as usize]
                            .iter()
                            .any(|&j| j == NONE || mask[j as usize] != mask[i as usize])
                    })
                    .collect();
                (rim.iter().chain(&side.small).copied().collect(), rim)
            }
            Some(moved) => (
                moved
                    .iter()
                    .flat_map(|&i| side.across[i as usize])
                    .filter(|&j| j != NONE)
                    .collect(),
                moved.to_vec(),
            ),
        };
        let mut flipped = Vec::new();
        for start in starts {
            self.small_piece(mask, round, start, &mut flipped);
        }
        // A pinched vertex has a free half-edge, so it lies at a triangle on the rim the round
        // began with, or at one moved since: by the last round's pinched step (`looked`), or
        // this round's small pieces.
        let mut candidates: Vec<u32> = looked
            .iter()
            .chain(&flipped)
            .flat_map(|&i| side.corners(i as usize))
            .collect();
        candidates.retain(|&v| {
            let fresh = self.vertex_seen[v as usize] != round;
            self.vertex_seen[v as usize] = round;
            fresh
        });
        let pinched: Vec<u32> = candidates
            .into_iter()
            .filter(|&v| {
                let leaving = side
                    .around(v)
                    .iter()
                    .filter(|&&i| {
                        let i = i as usize;
                        mask[i] && {
                            // `v` is a corner of every triangle around it.
                            let k = side.corners(i).iter().position(|&c| c == v).unwrap_or(0);
                            side.free(mask, i, k)
                        }
                    })
                    .count();
                leaving > 1
            })
            .collect();
        for v in pinched {
            for &i in side.around(v) {
                if self.movable(mask[i as usize]) {
                    mask[i as usize] = !mask[i as usize];
                    flipped.push(i);
                }
            }
        }
        flipped
    }

    /// Walks the movable piece holding `start` (edge-connected); when it has fewer than
    /// [`MIN_PIECE`] triangles it is flipped and appended to `flipped`. A walk stops as soon as
    /// the piece proves large (it reaches that many triangles, or one found large this round),
    /// marking what it reached as large.
    fn small_piece(&mut self, mask: &mut [bool], round: u32, start: u32, flipped: &mut Vec<u32>) {
        let side = self.side;
        if self.large[start as usize] == round || !self.movable(mask[start as usize]) {
            return;
        }
        self.walk += 1;
        let walk = self.walk;
        self.visited[start as usize] = walk;
        let mut members = vec![start];
        let mut next = 0;
        let mut large = false;
        'walk: while next < members.len() {
            let i = members[next] as usize;
            next += 1;
            for &j in &side.across[i] {
                if j == NONE || !self.movable(mask[j as usize]) {
                    continue;
                }
                if self.large[j as usize] == round {
                    large = true;
                    break 'walk;
                }
                if self.visited[j as usize] != walk {
                    self.visited[j as usize] = walk;
                    members.push(j);
                    if members.len() >= MIN_PIECE {
                        large = true;
                        break 'walk;
                    }
                }
            }
        }
        if large {
            for i in members {
                self.large[i as usize] = round;
            }
        } else {
            for &i in &members {
                mask[i as usize] = !mask[i as usize];
            }
            flipped.extend(members);
        }
    }
}

/// The boundary loops of the selected triangles, each running along the missing twins of its
/// free half-edges (so the region left out lies on its left); `None` if a loop is not simple.
fn boundary_loops(side: &Side, mask: &[bool]) -> Option<Vec<Vec<u32>>> {
    let free = free_half_edges(side, mask);
    let next: FxHashMap<u32, u32> = free.iter().map(|&(a, b)| (b, a)).collect();
    if next.len() != free.len() {
        return None;
    }
    let mut seen: FxHashSet<u32> = FxHashSet::default();
    let mut loops = Vec::new();
    for &(_, start) in &free {
        if seen.contains(&start) {
            continue;
        }
        let mut path = Vec::new();
        let mut v = start;
        loop {
            if !seen.insert(v) {
                return None;
            }
            path.push(v);
            let n = *next.get(&v)?;
            if n == start {
                break;
            }
            v = n;
        }
        if path.len() < 3 {
            return None;
        }
        loops.push(path);
    }
    Some(loops)
}

/// Pairs kept and copied loops that are each other's nearest (mean distance from each vertex of
/// either to the nearest vertex of the other, among the few nearest by centroid). `gaps` holds
/// the gaps of pairs measured before (keyed by the loops' vertices), and takes the new ones.
fn pair_loops(
    (ours, our_loops): (&IndexedMesh, &[Vec<u32>]),
    (theirs, their_loops): (&IndexedMesh, &[Vec<u32>]),
    gaps: &mut FxHashMap<LoopPair, f32>,
) -> Vec<(usize, usize)> {
    let points = |mesh: &IndexedMesh, loops: &[Vec<u32>]| -> Vec<Vec<Vec3>> {
        loops
            .iter()
            .map(|l| l.iter().map(|&v| mesh.positions[v as usize]).collect())
            .collect()
    };
    let (a, c) = (points(ours, our_loops), points(theirs, their_loops));
    let centroid = |p: &[Vec3]| p.iter().sum::<Vec3>() / p.len() as f32;
    let (ca, cc): (Vec<Vec3>, Vec<Vec3>) = (
        a.iter().map(|p| centroid(p)).collect(),
        c.iter().map(|p| centroid(p)).collect(),
    );
    // The few loops of `to` nearest to loop `i` of `from` by centroid.
    let candidates = |from: &[Vec3], to: &[Vec3], i: usize| -> Vec<usize> {
        let mut order: Vec<usize> = (0..to.len()).collect();
        order.sort_by(|&x, &y| {
            from[i]
                .distance(to[x])
                .total_cmp(&from[i].distance(to[y]))
                .then(x.cmp(&y))
        });
        order.truncate(CANDIDATES);
        order
    };
    let ours_candidates: Vec<Vec<usize>> = (0..a.len()).map(|i| candidates(&ca, &cc, i)).collect();
    let theirs_candidates: Vec<Vec<usize>> =
        (0..c.len()).map(|j| candidates(&cc, &ca, j)).collect();
    let key = |i: usize, j: usize| (our_loops[i].clone(), their_loops[j].clone());
    let mut wanted: Vec<(usize, usize)> = ours_candidates
        .iter()
        .enumerate()
        .flat_map(|(i, js)| js.iter().map(move |&j| (i, j)))
        .chain(
            theirs_candidates
                .iter()
                .enumerate()
                .flat_map(|(j, is)| is.iter().map(move |&i| (i, j))),
        )
        .collect();
    wanted.sort_unstable();
    wanted.dedup();
    // The gap of every wanted pair, by loop indices: from `gaps` where measured before.
    let mut known: FxHashMap<(usize, usize), f32> = FxHashMap::default();
    wanted.retain(|&(i, j)| match gaps.get(&key(i, j)) {
        Some(&gap) => {
            known.insert((i, j), gap);
            false
        }
        None => true,
    });
    let one_way = |from: &[Vec3], to: &[Vec3]| {
        from.iter()
            .map(|p| {
                to.iter()
                    .map(|q| p.distance(*q))
                    .fold(f32::INFINITY, f32::min)
            })
            .sum::<f32>()
            / from.len() as f32
    };
    let measured: Vec<f32> = wanted
        .par_iter()
        .map(|&(i, j)| one_way(&a[i], &c[j]).max(one_way(&c[j], &a[i])))
        .collect();
    for (&(i, j), gap) in wanted.iter().zip(measured) {
        gaps.insert(key(i, j), gap);
        known.insert((i, j), gap);
    }
    let gap = |i: usize, j: usize| known[&(i, j)];
    let best = |options: &[usize], score: &dyn Fn(usize) -> f32| {
        options
            .iter()
            .copied()
            .min_by(|&x, &y| score(x).total_cmp(&score(y)).then(x.cmp(&y)))
    };
    let ours_best: Vec<Option<usize>> = (0..a.len())
        .map(|i| best(&ours_candidates[i], &|j| gap(i, j)))
        .collect();
    let theirs_best: Vec<Option<usize>> = (0..c.len())
        .map(|j| best(&theirs_candidates[j], &|i| gap(i, j)))
        .collect();
    let pairs: Vec<(usize, usize)> = ours_best
        .iter()
        .enumerate()
        .filter_map(|(i, j)| j.filter(|&j| theirs_best[j] == Some(i)).map(|j| (i, j)))
        .collect();
    pairs
}

/// Whether `cells` holds `c` or one of the 26 cells around it.
fn near_any(c: Cell, cells: &FxHashSet<Cell>) -> bool {
    (-1..=1).any(|x| {
        (-1..=1).any(|y| (-1..=1).any(|z| cells.contains(&[c[0] + x, c[1] + y, c[2] + z])))
    })
}

/// The points the region grows around for the loops `pairs` leaves without a partner, under
/// `reach` (see [`Reach`]), and whether they are fewer than the loops' own.
fn loose_points(
    (ours, our_loops): (&IndexedMesh, &[Vec<u32>]),
    (theirs, their_loops): (&IndexedMesh, &[Vec<u32>]),
    pairs: &[(usize, usize)],
    (frame, reach): (&GridFrame, Reach),
) -> (Vec<Vec3>, bool) {
    let (mut paired_ours, mut paired_theirs) =
        (vec![false; our_loops.len()], vec![false; their_loops.len()]);
    for &(i, j) in pairs {
        paired_ours[i] = true;
        paired_theirs[j] = true;
    }
    let points = |mesh: &IndexedMesh, l: &[u32]| -> Vec<Vec3> {
        l.iter().map(|&v| mesh.positions[v as usize]).collect()
    };
    let rim_cells = |mesh: &IndexedMesh, loops: &[Vec<u32>]| -> FxHashSet<Cell> {
        loops
            .iter()
            .flatten()
            .map(|&v| cell(frame, mesh.positions[v as usize]))
            .collect()
    };
    let (our_cells, their_cells) = match reach {
        Reach::Strays => (rim_cells(ours, our_loops), rim_cells(theirs, their_loops)),
        Reach::Whole => Default::default(),
    };
    let mut narrowed = false;
    let mut loose = |loop_points: Vec<Vec3>, other: &FxHashSet<Cell>| -> Vec<Vec3> {
        if reach == Reach::Whole {
            return loop_points;
        }
        let strays: Vec<Vec3> = loop_points
            .iter()
            .copied()
            .filter(|&p| !near_any(cell(frame, p), other))
            .collect();
        if strays.is_empty() {
            loop_points
        } else {
            narrowed |= strays.len() < loop_points.len();
            strays
        }
    };
    let mut out = Vec::new();
    for (l, _) in our_loops.iter().zip(&paired_ours).filter(|(_, p)| !**p) {
        out.extend(loose(points(ours, l), &their_cells));
    }
    for (l, _) in their_loops.iter().zip(&paired_theirs).filter(|(_, p)| !**p) {
        out.extend(loose(points(theirs, l), &our_cells));
    }
    (out, narrowed)
}

/// One side of a zip: a boundary loop and the normals of the triangles along it.
struct Rim<'a> {
    mesh: &'a IndexedMesh,
    points: &'a [u32],
    /// The normal of the selected triangle holding each free half-edge.
    normals: &'a FxHashMap<(u32, u32), Vec3>,
}

/// Cost of a zip triangle with smallest angle `angle` (degrees): zero for an equilateral one,
/// growing quadratically as it thins, so one sliver costs more than several fair triangles.
fn shape_cost(angle: f32) -> f32 {
    let gap = (60.0 - angle).max(0.0) / 60.0;
    gap * gap
}

/// A zip triangle turned against the boundary triangle it meets costs more than any shape.
const FOLD_COST: f32 = 100.0;

/// Smallest angle, in degrees, at which a zip triangle is known to have an area without the
/// exact test.
const CLEARLY_SOUND: f32 = 1.0;

/// A zip triangle of no area (its corners in a line, or two at one place, where a kept vertex
/// sits on a copied one) would leave the grafted surface invalid: it costs more than any
/// number of folds, so the strip avoids it wherever another exists.
const DEGENERATE_COST: f32 = 1.0e6;

/// Joins the kept loop `a` and the copied loop `c` with a strip of triangles, from their closest
/// pair of vertices round to it again. Among all such strips (each triangle spans one edge of one
/// loop and a vertex of the other) it takes the one of least cost (shape, and turning against the
/// boundary), found by dynamic programming over the two loops like optimal contour stitching.
/// ([`least_cost_steps`] fills only the part of the table that can matter.)
fn zip_loops(a: &Rim, c: &Rim) -> Vec<[Corner; 3]> {
    // The copied loop runs the other way round the gap.
    let rc: Vec<u32> = c.points.iter().rev().copied().collect();
    let (n, m) = (a.points.len(), rc.len());
    let pa = |i: usize| a.mesh.positions[a.points[i % n] as usize];
    let pc = |j: usize| c.mesh.positions[rc[j % m] as usize];
    let mut start = (0, 0, f32::INFINITY);
    for i in 0..n {
        for j in 0..m {
            // Two corners at one place (a kept vertex copied from the input by an earlier
            // graft) cannot start the strip: its first triangle holds both.
            let d = pa(i).distance_squared(pc(j));
            if d > 0.0 && d < start.2 {
                start = (i, j, d);
            }
        }
    }
    let (i0, j0, _) = start;
    let va = |i: usize| a.points[(i0 + i) % n];
    let vc = |j: usize| rc[(j0 + j) % m];
    // Each loop's corners from the start round to it again, and the normal of the boundary
    // triangle on each of its edges, looked up once rather than at every cell of the table.
    let ours: Vec<Vec3> = (0..=n).map(|i| pa(i0 + i)).collect();
    let theirs: Vec<Vec3> = (0..=m).map(|j| pc(j0 + j)).collect();
    let our_normals: Vec<Option<Vec3>> = (0..n)
        .map(|i| a.normals.get(&(va(i + 1), va(i))).copied())
        .collect();
    let their_normals: Vec<Option<Vec3>> = (0..m)
        .map(|j| c.normals.get(&(vc(j), vc(j + 1))).copied())
        .collect();
    let cost = |p: [Vec3; 3], boundary: Option<Vec3>| {
        let normal = (p[1] - p[0]).cross(p[2] - p[0]);
        let folded = boundary.is_some_and(|o| normal.dot(o) < 0.0);
        let angle = min_angle_degrees(p[0], p[1], p[2]);
        // A smallest angle of a degree or more, even as rounded in `f32`, leaves the triangle
        // an area of some 10⁻⁴ of its longest edge squared, far above the exact test's bound:
        // that test (in `f64`) runs only on the others (all three corners at one place give
        // 180°).
        let degenerate =
            !(CLEARLY_SOUND..90.0).contains(&angle) && degenerate_triangle(p[0], p[1], p[2]);
        shape_cost(angle)
            + if folded { FOLD_COST } else { 0.0 }
            + if degenerate { DEGENERATE_COST } else { 0.0 }
    };
    // Advancing along ours adds [a_i, a_i+1, c_j]; its kept neighbour holds (a_i+1, a_i).
    let step_ours = |i: usize, j: usize| cost([ours[i], ours[i + 1], theirs[j]], our_normals[i]);
    // Advancing along theirs adds [c_j, a_i, c_j+1]; its copied neighbour holds (c_j, c_j+1).
    let step_theirs =
        |i: usize, j: usize| cost([theirs[j], ours[i], theirs[j + 1]], their_normals[j]);
    let (mut i, mut j) = (0, 0);
    let mut strip = Vec::with_capacity(n + m);
    for along_ours in least_cost_steps(n, m, step_ours, step_theirs) {
        if along_ours {
            strip.push([
                Corner::Ours(va(i)),
                Corner::Ours(va(i + 1)),
                Corner::Theirs(vc(j)),
            ]);
            i += 1;
        } else {
            strip.push([
                Corner::Theirs(vc(j)),
                Corner::Ours(va(i)),
                Corner::Theirs(vc(j + 1)),
            ]);
            j += 1;
        }
    }
    strip
}

/// The outward normal of the triangle holding each free half-edge of the selected triangles.
fn rim_normals(side: &Side, mask: &[bool]) -> FxHashMap<(u32, u32), Vec3> {
    let mut out = FxHashMap::default();
    for i in (0..mask.len()).filter(|&i| mask[i]) {
        let tri = side.corners(i);
        let p = tri.map(|v| side.mesh.positions[v as usize]);
        let normal = (p[1] - p[0]).cross(p[2] - p[0]);
        for k in (0..3).filter(|&k| side.free(mask, i, k)) {
            out.insert((tri[k], tri[(k + 1) % 3]), normal);
        }
    }
    out
}

/// The triangles `kept` of `ours`, `copied` of `theirs` and the strips `zip` as a mesh of their
/// own, with its vertices in [`Corner`] order: the tracked mesh's in index order, then the
/// input's. Every try's check assembles the whole grafted component twice, so the corners are
/// numbered through one slot per vertex of each mesh rather than by sorting them.
pub(super) fn assemble(
    (kept, copied, zip): (&[u32], &[u32], &[[Corner; 3]]),
    ours: &IndexedMesh,
    theirs: &IndexedMesh,
) -> IndexedMesh {
    let triangles: Vec<[Corner; 3]> = kept
        .iter()
        .map(|&t| ours.triangles[t as usize].map(Corner::Ours))
        .chain(
            copied
                .iter()
                .map(|&t| theirs.triangles[t as usize].map(Corner::Theirs)),
        )
        .chain(zip.iter().copied())
        .collect();
    let (mut our_slots, mut their_slots) = (
        vec![u32::MAX; ours.positions.len()],
        vec![u32::MAX; theirs.positions.len()],
    );
    for &c in triangles.iter().flatten() {
        match c {
            Corner::Ours(v) => our_slots[v as usize] = 0,
            Corner::Theirs(v) => their_slots[v as usize] = 0,
        }
    }
    let mut positions = Vec::new();
    for (slots, mesh) in [(&mut our_slots, ours), (&mut their_slots, theirs)] {
        for (v, slot) in slots.iter_mut().enumerate() {
            if *slot == 0 {
                *slot = positions.len() as u32;
                positions.push(mesh.positions[v]);
            }
        }
    }
    let index = |c: Corner| match c {
        Corner::Ours(v) => our_slots[v as usize],
        Corner::Theirs(v) => their_slots[v as usize],
    };
    IndexedMesh::new(positions, triangles.iter().map(|t| t.map(index)).collect())
}

/// What step 4 found.
enum Verdict {
    Meets,
    /// Not one component of the input's Euler characteristic, or not closed and manifold where
    /// the error names no vertex.
    Fails,
    /// Not closed and manifold: the points of the element that is not (a strip's edge shared by
    /// four triangles, say). Growing the region around them re-zips the loops there; taking it
    /// for a wrong topology grew the dam break's frame 34 from 8,535 to 14,258 cells around
    /// every sample farther than half the bound.
    Invalid(Vec<Vec3>),
    /// These samples (of either surface) lie farther than the bound from the other.
    Far(Vec<Vec3>),
    /// The result falls apart: these are the points of its smaller pieces next to its largest,
    /// where a bridge of the input was cut off by the region's rim.
    Apart(Vec<Vec3>),
}

/// The vertices of the smaller pieces of `part` (labelled by piece in `labels`) that lie in a
/// cell of spacing `spacing` next to one holding a vertex of its largest piece.
fn apart(part: &IndexedMesh, labels: &[u32], spacing: f32) -> Vec<Vec3> {
    let Ok(frame) = GridFrame::new(Vec3::ZERO, spacing) else {
        return Vec::new();
    };
    let mut sizes: FxHashMap<u32, usize> = FxHashMap::default();
    for &l in labels {
        *sizes.entry(l).or_insert(0) += 1;
    }
    let Some(largest) = sizes
        .iter()
        .max_by_key(|&(&l, &n)| (n, std::cmp::Reverse(l)))
        .map(|(&l, _)| l)
    else {
        return Vec::new();
    };
    let main: FxHashSet<[i32; 3]> = part
        .positions
        .iter()
        .zip(labels)
        .filter(|(_, l)| **l == largest)
        .map(|(&p, _)| cell(&frame, p))
        .collect();
    part.positions
        .iter()
        .zip(labels)
        .filter(|(_, l)| **l != largest)
        .map(|(&p, _)| p)
        .filter(|&p| {
            dilate(&[cell(&frame, p)], 1)
                .iter()
                .any(|c| main.contains(c))
        })
        .collect()
}

/// The verdict on the shape of a grafted `part`, where it fails: not closed and manifold, in
/// pieces, or not of the input's Euler characteristic.
fn shape_verdict(part: &IndexedMesh, bounds: &Bounds) -> Option<Verdict> {
    let edges = match part.validated_edges() {
        Ok(edges) => edges,
        Err(error) => {
            let points: Vec<Vec3> = error
                .vertices(&part.triangles)
                .into_iter()
                .filter_map(|v| part.positions.get(v as usize).copied())
                .collect();
            return Some(if points.is_empty() {
                Verdict::Fails
            } else {
                Verdict::Invalid(points)
            });
        }
    };
    let (topology, labels) = part.topology_from_edges(&edges);
    if topology.components.len() > 1 {
        let near = apart(part, &labels, bounds.spacing);
        if !near.is_empty() {
            return Some(Verdict::Apart(near));
        }
    }
    if topology.components.len() != 1 || topology.euler() != bounds.euler {
        return Some(Verdict::Fails);
    }
    None
}

/// The samples of a joined result farther from the other surface than half the bound, else than
/// a quarter (see `suspected`): where a hole or handle thinner than a cell may lie.
fn far_samples(
    graft: &Graft,
    (ours, theirs): (&Side, &Side),
    bounds: &Bounds,
    halvings: &mut usize,
) -> Result<Vec<Vec3>, SubgridError> {
    let (part, joined, (_, left)) = measured(graft, ours.mesh, theirs);
    suspected(halvings, bounds, |distance| {
        far_apart((&joined, &left, &part), bounds, distance)
    })
}

/// The points `look` finds at half the distance bound, else at a quarter, starting at the level
/// `halvings` reached before (updated): none once both are spent.
fn suspected(
    halvings: &mut usize,
    bounds: &Bounds,
    look: impl Fn(f32) -> Result<Vec<Vec3>, SubgridError>,
) -> Result<Vec<Vec3>, SubgridError> {
    while *halvings < SUSPICIONS {
        let found = look(bounds.max_distance / 2f32.powi(*halvings as i32 + 1))?;
        if !found.is_empty() {
            return Ok(found);
        }
        *halvings += 1;
    }
    Ok(Vec::new())
}

/// The samples of `ours` farther than `distance` from the input, and those of `theirs` (input
/// triangles) farther than it from `whole`, the tracked surface `ours` is part of.
fn far_apart(
    (ours, theirs, whole): (&IndexedMesh, &IndexedMesh, &IndexedMesh),
    bounds: &Bounds,
    distance: f32,
) -> Result<Vec<Vec3>, SubgridError> {
    let (from_input, whole) = rayon::join(
        || far_points(bounds.backend, Against::Input(bounds.input), ours, distance),
        || Bounded::new(bounds.backend, whole),
    );
    let mut found = from_input?;
    found.extend(far_points(
        bounds.backend,
        Against::Listed(&whole?),
        theirs,
        distance,
    )?);
    Ok(found)
}

/// The samples of `mesh` farther than `distance` from the surface `against`.
fn far_points(
    backend: &Backend,
    against: Against,
    mesh: &IndexedMesh,
    distance: f32,
) -> Result<Vec<Vec3>, SubgridError> {
    let far = far_components(
        backend,
        against,
        mesh,
        &vec![0; mesh.positions.len()],
        1,
        distance,
    )?;
    Ok(far.into_iter().flatten().collect())
}

/// What step 4 measures of a graft: the result, its kept triangles and strips alone, and the
/// input's triangles it does not copy (with their indices).
fn measured(
    graft: &Graft,
    ours: &IndexedMesh,
    theirs: &Side,
) -> (IndexedMesh, IndexedMesh, (Vec<u32>, IndexedMesh)) {
    // Three surfaces of one graft, each assembled on its own.
    let left_out = || {
        let mut copied = graft.copied.iter().peekable();
        let left: Vec<u32> = theirs
            .triangles
            .iter()
            .copied()
            .filter(|&t| copied.next_if_eq(&&t).is_none())
            .collect();
        let mesh = submesh(theirs.mesh, &left);
        (left, mesh)
    };
    let (part, (joined, left)) = rayon::join(
        || assemble((&graft.kept, &graft.copied, &graft.zip), ours, theirs.mesh),
        || {
            rayon::join(
                || assemble((&graft.kept, &[], &graft.zip), ours, theirs.mesh),
                left_out,
            )
        },
    );
    (part, joined, left)
}

/// Step 4 of the module comment; `theirs` is the input's component grafted in.
fn check(
    graft: &Graft,
    ours: &IndexedMesh,
    theirs: &Side,
    bounds: &Bounds,
) -> Result<Verdict, SubgridError> {
    let (part, joined, (left_triangles, left)) = measured(graft, ours, theirs);
    // The shape is judged while the distances are measured on the other core: a result that
    // fails on shape wastes the measurement, but most results pass. The copied triangles are the
    // input's own, so no sample of theirs lies off either surface: only the kept triangles and
    // the strips are measured against the input, and only the input's triangles left out
    // against the result.
    let (shape, far) = rayon::join(
        || shape_verdict(&part, bounds),
        || match bounds.nearest {
            Some(nearest) => {
                let (from_input, left_out) = rayon::join(
                    || {
                        far_points(
                            bounds.backend,
                            Against::Input(bounds.input),
                            &joined,
                            bounds.max_distance,
                        )
                    },
                    || {
                        far_left_out(
                            bounds.backend,
                            graft,
                            (ours, theirs.mesh),
                            (&left_triangles, &left, &part),
                            nearest,
                            (bounds.max_distance, bounds.spacing),
                        )
                    },
                );
                let mut found = from_input?;
                found.extend(left_out?);
                Ok(found)
            }
            None => far_apart((&joined, &left, &part), bounds, bounds.max_distance),
        },
    );
    if let Some(verdict) = shape {
        return Ok(verdict);
    }
    let far = far?;
    Ok(if far.is_empty() {
        Verdict::Meets
    } else {
        Verdict::Far(far)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::project::Bvh;

    /// A loop of `n` points on a circle of radius `r` around `centre` in the plane z = `z`.
    fn circle(centre: Vec3, r: f32, n: usize) -> Vec<Vec3> {
        (0..n)
            .map(|i| {
                let a = i as f32 / n as f32 * std::f32::consts::TAU;
                centre + Vec3::new(r * a.cos(), r * a.sin(), 0.0)
            })
            .collect()
    }

    /// Loose loops of `points` as a mesh with no triangles, one loop per range.
    fn loops(points: Vec<Vec3>, sizes: &[usize]) -> (IndexedMesh, Vec<Vec<u32>>) {
        let mut out = Vec::new();
        let mut next = 0u32;
        for &n in sizes {
            out.push((next..next + n as u32).collect());
            next += n as u32;
        }
        (IndexedMesh::new(points, Vec::new()), out)
    }

    /// A kept loop that runs beside a copied one but for an arc that bulges away grows the region
    /// around that arc alone; with `Reach::Whole` around all of it.
    #[test]
    fn a_loose_loop_grows_where_it_strays_from_the_other_rims() {
        let frame = GridFrame::new(Vec3::ZERO, 1.0).unwrap();
        let copied = circle(Vec3::splat(0.5), 10.0, 64);
        // The kept loop follows the copied one, 0.3 cells inside it, except for a quarter that
        // bulges 5 cells out.
        let kept: Vec<Vec3> = circle(Vec3::splat(0.5), 9.7, 64)
            .into_iter()
            .enumerate()
            .map(|(i, p)| {
                if i < 16 {
                    let out = (p - Vec3::splat(0.5)).normalize();
                    p + 5.3 * out
                } else {
                    p
                }
            })
            .collect();
        let (ours, our_loops) = loops(kept.clone(), &[64]);
        let (theirs, their_loops) = loops(copied, &[64]);
        let (points, narrowed) = loose_points(
            (&ours, &our_loops),
            (&theirs, &their_loops),
            &[],
            (&frame, Reach::Strays),
        );
        assert!(narrowed);
        // The bulge's points, and not one of those beside the copied loop; the copied loop lies
        // along the kept one but for the bulge, so it strays there too.
        assert!(points.len() < 64 + 32, "{} points", points.len());
        for p in &kept[16..] {
            assert!(!points.contains(p));
        }
        for p in &kept[2..15] {
            assert!(points.contains(p));
        }
        let (whole, narrowed) = loose_points(
            (&ours, &our_loops),
            (&theirs, &their_loops),
            &[],
            (&frame, Reach::Whole),
        );
        assert!(!narrowed);
        assert_eq!(whole.len(), 128);
    }

    /// A joined result that is not manifold names where (the two endpoints of an edge four
    /// triangles share), so the region grows there; a closed result of another Euler
    /// characteristic fails without a place, and one of the input's passes.
    #[test]
    fn a_result_that_is_not_manifold_names_where() {
        let p = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
        let positions = vec![
            p(0.0, 0.0, 0.0),
            p(1.0, 0.0, 0.0),
            p(0.0, 1.0, 0.0),
            p(0.0, 0.0, 1.0),
            p(0.0, -1.0, 0.0),
            p(0.0, 0.0, -1.0),
        ];
        // Two tetrahedra, the second the first turned half a turn about x: both share edge 0–1.
        let triangles = vec![
            [0, 2, 1],
            [0, 1, 3],
            [0, 3, 2],
            [1, 2, 3],
            [0, 4, 1],
            [0, 1, 5],
            [0, 5, 4],
            [1, 4, 5],
        ];
        let pinched = IndexedMesh::new(positions.clone(), triangles);
        let sphere = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 2);
        let bvh = Bvh::build(&sphere).unwrap();
        let input = InputDistances::new(&bvh);
        let bounds = |euler: i64| Bounds {
            backend: &Backend::Cpu,
            input: &input,
            spacing: 0.5,
            max_distance: 0.5,
            euler,
            nearest: None,
        };
        match shape_verdict(&pinched, &bounds(2)) {
            Some(Verdict::Invalid(points)) => {
                assert!(!points.is_empty());
                assert!(
                    points
                        .iter()
                        .all(|q| *q == positions[0] || *q == positions[1])
                );
            }
            _ => panic!("a non-manifold result must name its element"),
        }
        assert!(matches!(
            shape_verdict(&sphere, &bounds(0)),
            Some(Verdict::Fails)
        ));
        assert!(shape_verdict(&sphere, &bounds(2)).is_none());
    }

    /// χ of a mask's triangles: a closed sphere's is 2, the sphere less one triangle a disc's, 1,
    /// and that triangle alone 1; a sphere less a band around its equator, two discs, 2.
    #[test]
    fn euler_characteristic_of_a_mask() {
        let sphere = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 2);
        let side = Side::new(&sphere, (0..sphere.triangles.len() as u32).collect());
        let all = vec![true; sphere.triangles.len()];
        assert_eq!(mask_euler(&side, &all, true), 2);
        let mut holed = all.clone();
        holed[7] = false;
        assert_eq!(mask_euler(&side, &holed, true), 1);
        assert_eq!(mask_euler(&side, &holed, false), 1);
        let band: Vec<bool> = sphere
            .triangles
            .iter()
            .map(|t| {
                t.iter()
                    .any(|&v| sphere.positions[v as usize].z.abs() < 0.3)
            })
            .collect();
        assert_eq!(mask_euler(&side, &band, false), 2);
        assert_eq!(mask_euler(&side, &band, true), 0);
    }

    /// A loop with no rim point of the other side anywhere near grows whole; a paired loop does
    /// not grow at all.
    #[test]
    fn a_loop_far_from_every_rim_grows_whole_and_a_paired_one_not_at_all() {
        let frame = GridFrame::new(Vec3::ZERO, 1.0).unwrap();
        let mut kept = circle(Vec3::ZERO, 3.0, 24);
        kept.extend(circle(Vec3::new(40.0, 0.0, 0.0), 3.0, 24));
        let (ours, our_loops) = loops(kept, &[24, 24]);
        let (theirs, their_loops) = loops(circle(Vec3::ZERO, 3.2, 24), &[24]);
        let (points, narrowed) = loose_points(
            (&ours, &our_loops),
            (&theirs, &their_loops),
            &[(0, 0)],
            (&frame, Reach::Strays),
        );
        assert!(!narrowed);
        assert_eq!(points.len(), 24);
        assert!(points.iter().all(|p| p.x > 30.0));
    }

    /// The clean-up as its rule states it, every round over the whole side: the movable
    /// pieces smaller than [`MIN_PIECE`] flip, then every movable triangle at a pinched vertex.
    /// Returns the rounds that changed the mask.
    fn clean_everywhere(side: &Side, mask: &mut [bool], part: Part) -> usize {
        let movable = |m: bool| (part == Part::Kept) == m;
        for round in 0..ROUNDS {
            let mut changed = false;
            let selected: Vec<bool> = mask.iter().map(|&m| movable(m)).collect();
            let mut seen = vec![false; mask.len()];
            for start in (0..mask.len()).filter(|&i| selected[i]) {
                if seen[start] {
                    continue;
                }
                seen[start] = true;
                let mut piece = vec![start];
                let mut next = 0;
                while next < piece.len() {
                    let i = piece[next];
                    next += 1;
                    for &j in &side.across[i] {
                        if j != NONE && selected[j as usize] && !seen[j as usize] {
                            seen[j as usize] = true;
                            piece.push(j as usize);
                        }
                    }
                }
                if piece.len() < MIN_PIECE {
                    for i in piece {
                        mask[i] = !mask[i];
                    }
                    changed = true;
                }
            }
            let mut leaving = vec![0u32; side.mesh.positions.len()];
            for (a, _) in free_half_edges(side, mask) {
                leaving[a as usize] += 1;
            }
            for (i, m) in mask.iter_mut().enumerate() {
                let touches = side.corners(i).iter().any(|&v| leaving[v as usize] > 1);
                if movable(*m) && touches {
                    *m = !*m;
                    changed = true;
                }
            }
            if !changed {
                return round;
            }
        }
        ROUNDS
    }

    /// The clean-up that looks only around the rim and what it moved ends with the masks that
    /// the whole-side rule gives, on a sphere and a droplet beside it, for regions of scattered
    /// vertices (small pieces, pinches, and pinches that cascade over several rounds), on both
    /// sides.
    #[test]
    fn the_local_clean_up_gives_the_whole_sides_masks() {
        let mesh = IndexedMesh::icosphere(Vec3::ZERO, 4.0, 3).joined(&IndexedMesh::icosphere(
            Vec3::new(6.0, 0.0, 0.0),
            0.5,
            0,
        ));
        let side = Side::new(&mesh, (0..mesh.triangles.len() as u32).collect());
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let (mut flips, mut most_rounds) = (0, 0);
        for trial in 0..120u64 {
            // Each vertex lies in the region with a probability that varies by trial; the
            // droplet's lie out of it in every other trial.
            let share = 1 + trial % 30;
            let inside: Vec<bool> = (0..mesh.positions.len())
                .map(|v| {
                    state ^= state << 13;
                    state ^= state >> 7;
                    state ^= state << 17;
                    state % 32 < share && (trial % 2 == 0 || mesh.positions[v].x < 5.0)
                })
                .collect();
            for part in [Part::Kept, Part::Copied] {
                let start: Vec<bool> = mesh
                    .triangles
                    .iter()
                    .map(|t| match part {
                        Part::Kept => !t.iter().any(|&v| inside[v as usize]),
                        Part::Copied => t.iter().all(|&v| inside[v as usize]),
                    })
                    .collect();
                let (mut local, mut whole) = (start.clone(), start.clone());
                clean_rounds(&side, &mut local, part);
                most_rounds = most_rounds.max(clean_everywhere(&side, &mut whole, part));
                assert_eq!(local, whole, "trial {trial}");
                flips += start.iter().zip(&whole).filter(|(a, b)| a != b).count();
            }
        }
        // The regions exercise the clean-up: it moves triangles, over several rounds.
        assert!(flips > 1000, "{flips}");
        assert!(most_rounds >= 2, "{most_rounds}");
    }
}
