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
//! Like a topology patch with no boundary (§4.4), each vertex of a replaced or grafted component
//! takes its data going backward from the component's result at its closest point, and each
//! vertex of the copy takes, going forward, the data of the component it replaces at its closest
//! point; an inserted droplet reads the whole surface before the change, a deleted one the whole
//! surface after it, each as the caller's [`Carry`] says: the closest triangle's nearest corner
//! whole, or its corners blended. So every vertex of every frame holds a value (unless a whole
//! frame is empty), a constant channel stays constant (up to the rounding of a blend), and
//! colours stay where they were.

mod decide;
mod earlier;
mod graft;
mod left_out;
mod matching;
mod rebuild;
mod seeds;
mod stitch;

use crate::compute::Backend;
use crate::grid::RasterError;
use crate::improve::{ImproveError, ImproveParams, improve};
use crate::mesh::{IndexedMesh, Mesh, MeshError};
use crate::project::{Bvh, ProjectError};
use crate::topology::{Carry, Moves};
use earlier::Earlier;
use matching::{Components, InputDistances};
use serde::{Deserialize, Serialize};
use std::ops::Range;
use std::time::{Duration, Instant};
use thiserror::Error;

/// Components whose bounding-box diagonal is at most this many cells count as small.
pub const SMALL_CELLS: f32 = 4.0;

/// Re-checks of a grafted frame whose graft is improved again (see [`match_and_improve`]).
const RECHECKS: usize = 2;

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

/// What the sub-grid match changed in one frame.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct SubgridCounts {
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

impl SubgridCounts {
    pub fn changed(&self) -> bool {
        self.deleted + self.inserted + self.replaced + self.grafted > 0
    }
}

#[derive(Debug, Error)]
pub enum SubgridError {
    #[error("matching components: {0}")]
    Project(#[from] ProjectError),
    #[error("rebuilding the mesh: {0}")]
    Mesh(#[from] MeshError),
    #[error("comparing the surfaces on the grid: {0}")]
    Raster(#[from] RasterError),
    #[error("improving the matched surface: {0}")]
    Improve(#[from] ImproveError),
}

/// The two surfaces as the steps of the sub-grid match see them.
struct Surfaces<'a> {
    backend: &'a Backend,
    /// The tracked mesh and its components.
    current: &'a IndexedMesh,
    ours: &'a Components,
    /// The input frame, its components, and its tree with the distances to it measured so far.
    target: &'a IndexedMesh,
    theirs: &'a Components,
    input: &'a InputDistances<'a>,
    /// The topology grid's spacing, and the farthest either surface may lie from the other
    /// (world units).
    spacing: f32,
    max_distance: f32,
    /// What an earlier call in this frame measured between the input and the tracked surface.
    earlier: Option<&'a Earlier>,
    /// How the copies and the deleted vertices take their data.
    carry: Carry,
    /// Which removed vertices a copied vertex moves onto (`Moves`).
    moves: Moves,
}

/// Makes `mesh`'s components agree with `target`'s where the grid of spacing `spacing` cannot
/// (see the module comment); `max_distance` (world units) is the farthest either surface may lie
/// from the other. `bvh` is built over `target`. The change goes through `Mesh::replace`, whose
/// record lists creations first, then deletions. Returns what changed; `mesh` is untouched when
/// nothing does. `carry` says how the copies and the deleted vertices take their data; a copied
/// vertex standing within `continue_within` cells of a removed vertex it reads continues it, and
/// `moves` say which removed vertices a copied vertex moves onto first.
pub fn match_below_grid(
    backend: &Backend,
    mesh: &mut Mesh,
    (target, bvh): (&IndexedMesh, &Bvh),
    spacing: f32,
    max_distance: f32,
    policy: (Fidelity, Carry, f32, Moves),
) -> Result<SubgridCounts, SubgridError> {
    let input = InputDistances::new(bvh);
    match_against(
        backend,
        mesh,
        (target, &input),
        (spacing, max_distance),
        policy,
        (&mut None, &mut Vec::new(), &mut None),
    )
}

/// [`match_below_grid`] with the distances to the input measured so far in this frame, and what
/// the last call that measured the input against the tracked surface exactly found (`earlier`,
/// replaced by this call's where it measures exactly). The ids of the vertices a copied vertex
/// continued (see `Replacement::continuing`) go into `continued`. `moves` apply unless the copies
/// must be the input's own (`Fidelity::InputWhole`) or no vertex continues (`continue_within` 0).
/// The input's components are found once per frame: `known` holds them after the first call.
fn match_against(
    backend: &Backend,
    mesh: &mut Mesh,
    (target, input): (&IndexedMesh, &InputDistances),
    (spacing, max_distance): (f32, f32),
    (fidelity, carry, continue_within, moves): (Fidelity, Carry, f32, Moves),
    (earlier, continued, known): (&mut Option<Earlier>, &mut Vec<u64>, &mut Option<Components>),
) -> Result<SubgridCounts, SubgridError> {
    let current = mesh.to_indexed();
    let (ours, theirs) = match known.take() {
        Some(theirs) => (Components::of(&current), theirs),
        None => rayon::join(|| Components::of(&current), || Components::of(target)),
    };
    let surfaces = Surfaces {
        backend,
        current: &current,
        ours: &ours,
        target,
        theirs: &theirs,
        input,
        spacing,
        max_distance,
        earlier: earlier.as_ref(),
        carry,
        moves: match fidelity {
            Fidelity::InputWhole => Moves::default(),
            _ => moves.where_continuing(continue_within),
        },
    };
    let matched = matching::match_components(
        backend,
        &current,
        &ours.list,
        (target, &theirs.labels, theirs.list.len()),
        input.bvh,
        spacing,
    )?;
    let mut plan = decide::decide(&surfaces, &matched, fidelity)?;
    if plan.counts.changed() {
        let replacement = rebuild::replacement(&surfaces, &plan, mesh.next_id())?;
        let (replacement, ids) = replacement.continuing(mesh, continue_within * spacing);
        continued.extend(ids);
        mesh.replace(replacement)?;
    }
    if let Some(nearest) = plan.nearest.take() {
        *earlier = Some(Earlier {
            tracked: current,
            nearest,
        });
    }
    *known = Some(theirs);
    Ok(plan.counts)
}

/// What the sub-grid match of one frame did, how long its improvement passes took, and where in
/// the mesh's journal their records lie (the rest of what it journaled is the match's own).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SubgridReport {
    pub counts: SubgridCounts,
    pub improve: Duration,
    pub improve_records: Vec<Range<usize>>,
    /// Ids of the vertices a copied vertex standing on them continued (see
    /// `Replacement::continuing`): removed by the match, yet their ids go on.
    pub continued: Vec<u64>,
}

/// The sub-grid match of one frame (Algorithm 1 after line 10), with the improvement that follows
/// it (line 12) and its re-check: [`match_below_grid`], then improvement. Improvement reshapes a
/// graft's seam, whose thin triangles it may collapse and flip many times over, each step within
/// its own small bound; the steps can add up to more than `max_distance`. So a grafted frame is
/// matched again: a component that moved out of bounds is grafted again around where it did (a
/// component of the input's topology, only around the samples that strayed), and improved, up to
/// [`RECHECKS`] times; the graft of one more re-check is left as it is, within the bound, its
/// seam improved with the next frame. Replacing a whole body for a few stray samples would cost
/// every vertex of it. A copied droplet or component is matched again too: improvement coarsens
/// a droplet copied with edges shorter than L, and one of 16 vertices about an edge across
/// (the drop pool's frame 33) came out a tetrahedron whose faces lay 1.25 L inside the input's.
pub fn match_and_improve(
    backend: &Backend,
    mesh: &mut Mesh,
    target: (&IndexedMesh, &Bvh),
    (spacing, max_distance): (f32, f32),
    policy: (Fidelity, Carry, f32, Moves),
    params: &ImproveParams,
) -> Result<SubgridReport, SubgridError> {
    let mut report = SubgridReport::default();
    let mut improve_timed = |mesh: &mut Mesh| -> Result<(), SubgridError> {
        let (t, mark) = (Instant::now(), mesh.journal_len());
        improve(mesh, params)?;
        report.improve += t.elapsed();
        report.improve_records.push(mark..mesh.journal_len());
        Ok(())
    };
    // One frame's calls measure the same unmoved vertices against the same input.
    let input = InputDistances::new(target.1);
    let target = (target.0, &input);
    let bounds = (spacing, max_distance);
    let (mut earlier, mut theirs) = (None, None);
    let mut matched = |mesh: &mut Mesh| {
        let memo = (&mut earlier, &mut report.continued, &mut theirs);
        match_against(backend, mesh, target, bounds, policy, memo)
    };
    let mut counts = matched(mesh)?;
    improve_timed(mesh)?;
    let (mut copied, mut grafted) = (copies(&counts), counts.grafted);
    for round in 0..=RECHECKS {
        if copied == 0 {
            break;
        }
        let recheck = matched(mesh)?;
        copied = copies(&recheck);
        if !recheck.changed() {
            break;
        }
        if round < RECHECKS {
            improve_timed(mesh)?;
        }
        // A component the last pass grafted and this one replaces counts as replaced only; a
        // droplet copied in again counts once more.
        counts.grafted = counts.grafted.saturating_sub(recheck.replaced.min(grafted));
        grafted = recheck.grafted;
        counts.replaced += recheck.replaced;
        counts.deleted += recheck.deleted;
        counts.inserted += recheck.inserted;
    }
    report.counts = counts;
    Ok(report)
}

/// Components a match copied in, whole or grafted: those improvement reshaped afterwards.
fn copies(counts: &SubgridCounts) -> usize {
    counts.inserted + counts.replaced + counts.grafted
}
