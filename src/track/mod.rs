//! Algorithm 1 of the paper (§4.5): one tracked mesh `M` carried through the input frames —
//! register to each target (coarse, fine), improve, merge self-intersections
//! (`ConstrainTopology(M, Φ(M))`), take the target's topology (`ConstrainTopology(M, Φ(T_j))`),
//! match what is too small for the grid to see (`topology::subgrid`), improve — while every vertex
//! created or destroyed goes into the frame's event list (§4.4).
//!
//! The tracker holds one frame at a time, so memory follows the frame size, never the sequence
//! length. At the end of every frame the mesh is compacted and its positions rounded as the
//! written frame holds them (world coordinates, see [`anchor`]), so its whole state is what the
//! written frame holds (plus `next_id`): resuming from a written frame continues bit-identically.

mod anchor;
mod churn;
mod droplets;
mod snap;
mod target;

pub use anchor::anchor_of;
pub use churn::{Churn, StageChurn};
pub use target::TargetFrame;

use crate::compute::Backend;
use crate::events::{EventKind, EventList};
use crate::grid::{GridFrame, RasterError};
use crate::improve::{ImproveError, ImproveParams, improve};
use crate::mesh::{IndexedMesh, Mesh, MeshError};
use crate::project::{Bvh, ProjectError, closest_points};
use crate::register::{RegisterError, RegisterOptions, Target, register};
use crate::topology::subgrid::{Fidelity, SubgridCounts, SubgridError, match_and_improve};
use crate::topology::{
    Field, MeshRaster, Moves, ThetaSurface, TopologyError, TopologyOptions, constrain_topology_on,
};
use anchor::localized;
use churn::Marks;
use glam::Vec3;
use rustc_hash::FxHashSet;
use serde::{Deserialize, Serialize};
use std::ops::Range;
use std::time::{Duration, Instant};
use thiserror::Error;

/// Every parameter of the method, with the paper's defaults. Lengths are relative to the target edge
/// length `L` (the first frame's mean edge length unless `edge_length` is given).
#[derive(Debug, Clone, PartialEq)]
pub struct TrackOptions {
    /// Absolute target edge length; `None` takes the first frame's mean edge length.
    pub edge_length: Option<f32>,
    /// Grid spacing Δ of the topology step as a multiple of `L` (paper §4.3: about one edge length).
    pub grid_factor: f32,
    /// Mesh improvement (§4.1); its `edge_length` is replaced by `L`.
    pub improve: ImproveParams,
    pub register: RegisterOptions,
    pub topology: TopologyOptions,
    /// How `M` follows each target before improvement and the topology steps.
    pub motion: Motion,
    /// Farthest, in units of `L`, the tracked surface and the target may lie from each other at
    /// the end of the topology steps: a component that does not come this close (a sheet thinner
    /// than the grid sees) is replaced by the target's own (see [`crate::topology::subgrid`]).
    pub max_distance: f32,
    /// Whether a component the grid leaves unlike the target is replaced by the target's own.
    pub fidelity: Fidelity,
}

/// How the tracked mesh is moved onto each target (Algorithm 1, lines 5–6).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Motion {
    /// The paper's non-rigid registration: deformation graph, then per-vertex fit (§4.2).
    #[default]
    Register,
    /// Every vertex jumps to its closest point on the target: the baseline the paper compares with
    /// (Fig. 9), which drifts tangentially even under a plain translation.
    Project,
}

/// The tracker's per-operation deviation bound of mesh improvement, in units of `L` (see
/// [`ImproveParams::max_deviation`]). A lone improvement keeps a raw frame within a few percent of
/// `L`; inside tracking the registration of the next frame fits the surface to its target again, and
/// the slivers a topology patch leaves on real data (fluid caches) are only removed with more room.
pub const TRACK_MAX_DEVIATION: f32 = 0.1;

/// The default of [`TrackOptions::max_distance`]: the final improvement moves the surface by at most
/// [`TRACK_MAX_DEVIATION`] per operation, and the output must stay within one edge length.
pub const MAX_DISTANCE: f32 = 0.75;

impl Default for TrackOptions {
    fn default() -> Self {
        Self {
            edge_length: None,
            grid_factor: 1.0,
            improve: ImproveParams {
                max_deviation: TRACK_MAX_DEVIATION,
                ..ImproveParams::new(1.0)
            },
            register: RegisterOptions::default(),
            topology: TopologyOptions::default(),
            motion: Motion::Register,
            max_distance: MAX_DISTANCE,
            fidelity: Fidelity::Input,
        }
    }
}

/// Why tracking stopped: the frame, and what its stage reported.
#[derive(Debug, Error)]
pub enum TrackError {
    #[error("frame {frame}: {source}")]
    Stage { frame: usize, source: StageError },
    #[error("the target edge length {0} is not a positive finite number")]
    EdgeLength(f32),
    #[error("frame {frame}: the target was moved to anchor {target}, the tracker's is {tracker}")]
    Anchor {
        frame: usize,
        target: Vec3,
        tracker: Vec3,
    },
}

impl TrackError {
    /// The error `source` of a stage of frame `frame`.
    fn at(frame: usize, source: impl Into<StageError>) -> Self {
        TrackError::Stage {
            frame,
            source: source.into(),
        }
    }
}

/// The error of one stage of Algorithm 1, as the stage reports it.
#[derive(Debug, Error)]
pub enum StageError {
    #[error(transparent)]
    Mesh(#[from] MeshError),
    #[error("registration failed: {0}")]
    Register(#[from] RegisterError),
    #[error("mesh improvement failed: {0}")]
    Improve(#[from] ImproveError),
    #[error("topology step failed: {0}")]
    Topology(#[from] TopologyError),
    #[error(transparent)]
    Project(#[from] ProjectError),
    #[error("matching components below the grid's resolution: {0}")]
    Subgrid(#[from] SubgridError),
    #[error("cannot place the topology grid: {0}")]
    Grid(#[from] RasterError),
}

/// Wall-clock time of each stage of one frame, in milliseconds.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct StageTimes {
    /// Registration, with `Φ(T)` computed alongside it (see [`Tracker::step`]).
    pub register: f64,
    /// Of `register`, the per-vertex (fine) stage.
    #[serde(default)]
    pub register_fine: f64,
    pub improve: f64,
    pub topology_self: f64,
    /// `ConstrainTopology(M, Φ(T))` itself; `Φ(T)` was computed during registration.
    pub topology_target: f64,
    /// The sub-grid match (`topology::subgrid`): what the topology grid cannot see.
    pub reconcile: f64,
    pub residual: f64,
    pub total: f64,
}

/// Events of one frame by kind.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct EventCounts {
    pub split_edge: usize,
    pub split_face: usize,
    pub collapse: usize,
    #[serde(default)]
    pub merge: usize,
    pub patch_created: usize,
    pub patch_deleted: usize,
}

impl EventCounts {
    fn of(list: &EventList) -> Self {
        let mut c = Self::default();
        for e in &list.events {
            *match e.kind {
                EventKind::SplitEdge => &mut c.split_edge,
                EventKind::SplitFace => &mut c.split_face,
                EventKind::Collapse => &mut c.collapse,
                EventKind::Merge => &mut c.merge,
                EventKind::PatchCreated => &mut c.patch_created,
                EventKind::PatchDeleted => &mut c.patch_deleted,
            } += 1;
        }
        c
    }
}

/// What happened in one frame: the per-frame log line and the JSON summary's record.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FrameLog {
    pub frame: usize,
    pub vertices: usize,
    pub faces: usize,
    pub events: EventCounts,
    /// Mean and largest distance of the tracked vertices to the target frame, in units of `L`.
    pub residual_mean: f64,
    pub residual_max: f64,
    pub registration_converged: bool,
    pub topology_changed: bool,
    /// Components below the grid's resolution deleted, copied in or replaced.
    pub reconciled: SubgridCounts,
    /// Share of the frame's vertices carried over from the previous frame (same id); none for
    /// the first frame.
    #[serde(default)]
    pub carried: Option<f64>,
    /// What each stage created and removed, and the vertices of the previous frame it lost.
    #[serde(default)]
    pub churn: StageChurn,
    pub times: StageTimes,
}

/// The state carried from frame to frame.
pub struct Tracker {
    /// The tracked mesh, relative to `anchor`.
    mesh: Mesh,
    options: TrackOptions,
    params: ImproveParams,
    grid: GridFrame,
    /// The world position of the tracker's origin (see [`anchor`]).
    anchor: Vec3,
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

impl Tracker {
    /// Lines 1–2 of Algorithm 1: `M` from the first frame (which must be a closed manifold), then
    /// improved. Returns the tracker and frame 0's log and events.
    pub fn start(
        first: &IndexedMesh,
        backend: &Backend,
        options: &TrackOptions,
    ) -> Result<(Self, EventList, FrameLog), TrackError> {
        let start = Instant::now();
        let anchor = anchor_of(first);
        let mut fresh = localized(first, anchor);
        fresh.ids = None;
        fresh.attributes.clear();
        let mesh = Mesh::from_indexed(&fresh).map_err(|e| TrackError::at(0, e))?;
        let edge_length = options
            .edge_length
            .unwrap_or_else(|| fresh.mean_edge_length());
        let mut tracker = Self::with_mesh(mesh, edge_length, anchor, options)?;
        let t = Instant::now();
        improve(&mut tracker.mesh, &tracker.params).map_err(|e| TrackError::at(0, e))?;
        let improve_time = t.elapsed();
        let events = EventList::drain(&mut tracker.mesh);
        tracker.mesh.compact();
        tracker.settle();
        let mut times = StageTimes {
            improve: ms(improve_time),
            ..StageTimes::default()
        };
        let bvh = Bvh::build(&fresh).map_err(|e| TrackError::at(0, e))?;
        let (mean, max) = tracker.residual(backend, &bvh, 0, &mut times)?;
        times.total = ms(start.elapsed());
        let log = tracker.log(0, &events, (mean, max), true, false, times);
        Ok((tracker, events, log))
    }

    /// A tracker continuing from written frame `frame`: `mesh` (world coordinates) with its
    /// persistent ids, `next_id`, the run's target edge length and anchor as recorded in
    /// `track.json`. An error names `frame`.
    pub fn resume(
        frame: usize,
        mesh: &IndexedMesh,
        next_id: u64,
        (edge_length, anchor): (f32, Vec3),
        options: &TrackOptions,
    ) -> Result<Self, TrackError> {
        let local = localized(mesh, anchor);
        let mut mesh = Mesh::from_indexed(&local).map_err(|e| TrackError::at(frame, e))?;
        mesh.reserve_ids_below(next_id);
        Self::with_mesh(mesh, edge_length, anchor, options)
    }

    /// The tracker over `mesh`, whose journal records from here on: every stage changes the mesh
    /// through its mutations, so each frame's events are what one drain of the journal returns.
    fn with_mesh(
        mut mesh: Mesh,
        edge_length: f32,
        anchor: Vec3,
        options: &TrackOptions,
    ) -> Result<Self, TrackError> {
        mesh.record_mutations();
        if !(edge_length.is_finite() && edge_length > 0.0) {
            return Err(TrackError::EdgeLength(edge_length));
        }
        let grid = GridFrame::new(glam::Vec3::ZERO, options.grid_factor * edge_length)
            .map_err(|e| TrackError::at(0, e))?;
        let params = ImproveParams {
            edge_length,
            ..options.improve.clone()
        };
        Ok(Self {
            mesh,
            options: options.clone(),
            params,
            grid,
            anchor,
        })
    }

    /// The tracked mesh, relative to [`Tracker::anchor`].
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// The tracked mesh in world coordinates, as its frame is written.
    pub fn world_mesh(&self) -> IndexedMesh {
        let mut world = self.mesh.to_indexed();
        if self.anchor != Vec3::ZERO {
            for p in &mut world.positions {
                *p += self.anchor;
            }
        }
        world
    }

    /// The world position of the tracker's origin (see [`anchor_of`]).
    pub fn anchor(&self) -> Vec3 {
        self.anchor
    }

    /// Rounds every position to what the written frame holds, so the state a frame ends in is
    /// the state a resume from its file starts from.
    fn settle(&mut self) {
        if self.anchor == Vec3::ZERO {
            return;
        }
        let vertices: Vec<_> = self.mesh.vertices().collect();
        for v in vertices {
            let p = self.mesh.position(v);
            self.mesh.set_position(v, (p + self.anchor) - self.anchor);
        }
    }

    /// The target edge length `L` every relative parameter is measured in.
    pub fn edge_length(&self) -> f32 {
        self.params.edge_length
    }

    /// Lines 4–12 of Algorithm 1 for frame `frame` with target `target`, made for this tracker's
    /// anchor ([`TargetFrame::new`] with [`Tracker::anchor`]).
    ///
    /// The step runs on a thread of rayon's pool. Its stages make hundreds of small parallel
    /// calls a frame; called from a thread outside the pool, each is handed over to the pool
    /// while the caller blocks until a worker, woken for it, hands the result back. On a worker,
    /// the caller runs one half itself and the other worker takes the other (on the dam break's
    /// splash frames 20–31 this made the two topology steps about 10 ms shorter each).
    pub fn step(
        &mut self,
        backend: &Backend,
        frame: usize,
        target: &TargetFrame,
    ) -> Result<(EventList, FrameLog), TrackError> {
        rayon::scope(|_| self.step_in_pool(backend, frame, target))
    }

    fn step_in_pool(
        &mut self,
        backend: &Backend,
        frame: usize,
        target: &TargetFrame,
    ) -> Result<(EventList, FrameLog), TrackError> {
        let start = Instant::now();
        if target.anchor() != self.anchor {
            return Err(TrackError::Anchor {
                frame,
                target: target.anchor(),
                tracker: self.anchor,
            });
        }
        // The target's tree serves the projection baseline, the sub-grid match and the residual.
        let (target, bvh) = (target.mesh(), target.bvh());
        let mut times = StageTimes::default();
        let before: FxHashSet<u64> = self.mesh.vertices().map(|v| self.mesh.id(v)).collect();
        let mut marks = Marks::default();
        // Vertices from earlier frames may move along the surface rather than go; this frame's own
        // are thinned as before.
        self.params.relax_below = self.mesh.next_id();
        // Lines 5–6: M follows T_j; Φ(T_j) and its isosurface are made meanwhile.
        let (converged, (phi_t, theta_t)) = self.follow(backend, frame, target, bvh, &mut times)?;
        // Line 7: improve.
        marks.improve.push(self.improve(frame, &mut times)?);
        // Lines 8–9: merge M's self-intersections, ConstrainTopology(M, Φ(M)).
        let t = Instant::now();
        // M's raster gives Φ(M) and is where ConstrainTopology cuts M: rasterized once. The cut
        // reads the CPU twin's crossings on either backend (the device's lie within a tolerance
        // of them, not on them), so a device's raster serves Φ(M) alone.
        let raster = MeshRaster::new(backend, self.grid, &self.mesh.to_indexed())
            .map_err(|e| TrackError::at(frame, e))?;
        let phi_m = Field::of_raster(backend, &raster).map_err(|e| TrackError::at(frame, e))?;
        let cut_on = matches!(backend, Backend::Cpu).then_some(raster);
        let (merged, span, continued_self) =
            self.constrain(frame, (&phi_m, &ThetaSurface::of(&phi_m)), cut_on)?;
        marks.topology_self = span;
        times.topology_self = ms(t.elapsed());
        // Lines 10–11: take the target's topology, ConstrainTopology(M, Φ(T_j)).
        let t = Instant::now();
        snap::snap(backend, &mut self.mesh, bvh, self.params.min_angle_degrees)
            .map_err(|e| TrackError::at(frame, e))?;
        let (constrained, span, continued_target) =
            self.constrain(frame, (&phi_t, &theta_t), None)?;
        marks.topology_target = span;
        times.topology_target = ms(t.elapsed());
        // What the grid cannot see, then line 12: improve (with the match's re-check).
        let (t, mark) = (Instant::now(), self.mesh.journal_len());
        let moves = self.moves();
        let matched = match_and_improve(
            backend,
            &mut self.mesh,
            (target, bvh),
            (
                self.grid.spacing(),
                self.options.max_distance * self.params.edge_length,
            ),
            (
                self.options.fidelity,
                self.options.topology.carry,
                self.options.topology.continue_within,
                moves,
            ),
            &self.params,
        )
        .map_err(|e| TrackError::at(frame, e))?;
        times.reconcile = ms(t.elapsed()) - ms(matched.improve);
        // Improvement and the re-sampling leave vertices off the target (a collapse's midpoint, a
        // move along the surface, a patch on Θ's isosurface a fraction of a cell off the input's
        // surface): they go back onto it, by the snap's rules. On the synth morph, where the hole
        // opens, a patch vertex stood 0.66 Δ inside it; now no frame is farther than 0.47 Δ.
        let placed = Instant::now();
        snap::snap(backend, &mut self.mesh, bvh, self.params.min_angle_degrees)
            .map_err(|e| TrackError::at(frame, e))?;
        times.improve += ms(matched.improve + placed.elapsed());
        marks.subgrid = mark..self.mesh.journal_len();
        marks.improve.extend(matched.improve_records);

        // Every stage changed the mesh through its mutations: one drain gives the frame's events.
        let mut churn = marks.churn(self.mesh.journal_since(0), &before);
        let began = |ids: &[u64]| ids.iter().filter(|id| before.contains(id)).count();
        churn.topology_self.continued = began(&continued_self);
        churn.topology_target.continued = began(&continued_target);
        churn.subgrid.continued = began(&matched.continued);
        let events = EventList::drain(&mut self.mesh);
        self.mesh.compact();
        self.settle();
        let residual = self.residual(backend, bvh, frame, &mut times)?;
        times.total = ms(start.elapsed());
        let mut log = self.log(
            frame,
            &events,
            residual,
            converged,
            merged || constrained || matched.counts.changed(),
            times,
        );
        log.reconciled = matched.counts;
        log.carried =
            Some(before.len().saturating_sub(churn.lost()) as f64 / log.vertices.max(1) as f64);
        log.churn = churn;
        Ok((events, log))
    }

    /// Moves the mesh onto `target` (Algorithm 1, lines 5–6) and samples Φ(T) alongside, with the
    /// isosurface its `ConstrainTopology` reads (placed for comparing components too, where the
    /// step keeps shared sheets and so compares them): both depend on the target frame alone,
    /// and registration's sparse factorizations run on one core, so the other would idle.
    /// Returns whether registration converged, and Φ(T) with its isosurface.
    fn follow(
        &mut self,
        backend: &Backend,
        frame: usize,
        target: &IndexedMesh,
        bvh: &Bvh,
        times: &mut StageTimes,
    ) -> Result<(bool, (Field, ThetaSurface)), TrackError> {
        let t = Instant::now();
        let compares = self.keeps_shared_sheets();
        let (mesh, options, grid) = (&mut self.mesh, &self.options, self.grid);
        let (moved, phi_t) = rayon::join(
            || match options.motion {
                Motion::Register => register(backend, mesh, Target::Tree(bvh), &options.register)
                    .map(|report| (report.converged(), ms(report.fine_time)))
                    .map_err(|e| TrackError::at(frame, e)),
                Motion::Project => project_onto(backend, mesh, bvh)
                    .map(|()| (true, 0.0))
                    .map_err(|e| TrackError::at(frame, e)),
            },
            || {
                let phi = Field::signed_distance(backend, grid, target)
                    .map_err(|e| TrackError::at(frame, e))?;
                let surface = if compares {
                    ThetaSurface::compared_of(&phi)
                } else {
                    ThetaSurface::of(&phi)
                };
                Ok((phi, surface))
            },
        );
        let (converged, fine) = moved?;
        let phi_t = phi_t?;
        if self.options.motion == Motion::Register {
            droplets::follow_droplets(backend, &mut self.mesh, (target, bvh), &self.grid)
                .map_err(|e| TrackError::at(frame, e))?;
        }
        times.register = ms(t.elapsed());
        times.register_fine = fine;
        Ok((converged, phi_t))
    }

    /// `ConstrainTopology(M, Θ)` (paper §4.3), with M's raster where Θ is Φ(M); whether it
    /// changed the mesh, where its records lie in the journal, and the ids of the vertices its
    /// patches continued.
    fn constrain(
        &mut self,
        frame: usize,
        theta: (&Field, &ThetaSurface),
        raster: Option<MeshRaster>,
    ) -> Result<(bool, Range<usize>, Vec<u64>), TrackError> {
        let mark = self.mesh.journal_len();
        let options = TopologyOptions {
            keep_shared_sheets: self.keeps_shared_sheets(),
            moves: self.moves(),
            ..self.options.topology
        };
        let report = constrain_topology_on(&mut self.mesh, theta, raster, &options)
            .map_err(|e| TrackError::at(frame, e))?;
        Ok((
            report.changed(),
            mark..self.mesh.journal_len(),
            report.continued,
        ))
    }

    /// Whether the topology steps keep the sheets thinner than a cell that Θ's mesh has too:
    /// where the sub-grid match follows, which would copy them back.
    fn keeps_shared_sheets(&self) -> bool {
        self.options.fidelity != Fidelity::Grid
    }

    /// This frame's moves of new vertices onto the carried ones re-sampling removes: those from
    /// earlier frames, within the longest edge improvement keeps.
    fn moves(&self) -> Moves {
        Moves {
            carried_below: self.params.relax_below,
            longest_edge: self.params.max_edge_length(),
        }
    }

    /// Improves the mesh (paper §4.1), adding its time; where its records lie in the journal.
    fn improve(
        &mut self,
        frame: usize,
        times: &mut StageTimes,
    ) -> Result<Range<usize>, TrackError> {
        let (t, mark) = (Instant::now(), self.mesh.journal_len());
        improve(&mut self.mesh, &self.params).map_err(|e| TrackError::at(frame, e))?;
        times.improve += ms(t.elapsed());
        Ok(mark..self.mesh.journal_len())
    }

    /// Mean and largest distance from the tracked vertices to `target`, in units of `L`.
    fn residual(
        &self,
        backend: &Backend,
        bvh: &Bvh,
        frame: usize,
        times: &mut StageTimes,
    ) -> Result<(f64, f64), TrackError> {
        let t = Instant::now();
        let project = |e: ProjectError| TrackError::at(frame, e);
        let points: Vec<glam::Vec3> = self
            .mesh
            .vertices()
            .map(|v| self.mesh.position(v))
            .collect();
        let nearest = closest_points(backend, bvh, &points, f32::INFINITY).map_err(project)?;
        let l = f64::from(self.params.edge_length);
        let (mut sum, mut max) = (0.0f64, 0.0f64);
        for n in &nearest {
            let d = f64::from(n.distance.abs()) / l;
            sum += d;
            max = max.max(d);
        }
        times.residual = ms(t.elapsed());
        Ok((sum / nearest.len().max(1) as f64, max))
    }

    fn log(
        &self,
        frame: usize,
        events: &EventList,
        (residual_mean, residual_max): (f64, f64),
        registration_converged: bool,
        topology_changed: bool,
        times: StageTimes,
    ) -> FrameLog {
        FrameLog {
            frame,
            vertices: self.mesh.vertex_count(),
            faces: self.mesh.face_count(),
            events: EventCounts::of(events),
            residual_mean,
            residual_max,
            registration_converged,
            topology_changed,
            reconciled: SubgridCounts::default(),
            carried: None,
            churn: StageChurn::default(),
            times,
        }
    }
}

/// Moves every vertex of `mesh` to its closest point on the target whose tree is `bvh`
/// ([`Motion::Project`]).
fn project_onto(backend: &Backend, mesh: &mut Mesh, bvh: &Bvh) -> Result<(), ProjectError> {
    let slots: Vec<_> = mesh.vertices().collect();
    let points: Vec<glam::Vec3> = slots.iter().map(|&v| mesh.position(v)).collect();
    let nearest = closest_points(backend, bvh, &points, f32::INFINITY)?;
    for (&v, hit) in slots.iter().zip(&nearest) {
        if hit.hit_triangle().is_some() {
            mesh.set_position(v, hit.point);
        }
    }
    Ok(())
}
