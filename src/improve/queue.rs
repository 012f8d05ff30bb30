//! The work list of bad elements, worst first. Entries name vertices by slot *and* persistent id, so an
//! entry whose element was changed by an earlier operation is recognised and skipped; ties break on
//! ids, so the order — and the result — depends only on the mesh.

use crate::mesh::{HalfEdgeId, Mesh, VertexId};
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// What is wrong with an element; the variant order is the processing order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(super) enum Kind {
    SmallAngle,
    ShortEdge,
    SharpDihedral,
}

/// A bad edge (`corners[2]` unused) or face, with the measure that ranks it (smaller is worse).
#[derive(Debug, Clone, Copy)]
pub(super) struct Task {
    pub kind: Kind,
    pub measure: f32,
    pub corners: [(VertexId, u64); 3],
}

impl Task {
    /// The edge of `h`, named from its end with the smaller id so both half-edges give one task.
    pub fn edge(mesh: &Mesh, kind: Kind, measure: f32, h: HalfEdgeId) -> Self {
        let (mut a, mut b) = (mesh.origin(h), mesh.target(h));
        if mesh.id(b) < mesh.id(a) {
            std::mem::swap(&mut a, &mut b);
        }
        Self {
            kind,
            measure,
            corners: [(a, mesh.id(a)), (b, mesh.id(b)), (a, mesh.id(a))],
        }
    }

    pub fn face(mesh: &Mesh, measure: f32, h: HalfEdgeId) -> Self {
        let [a, b, c] = [h, mesh.next(h), mesh.prev(h)].map(|e| mesh.origin(e));
        Self {
            kind: Kind::SmallAngle,
            measure,
            corners: [a, b, c].map(|v| (v, mesh.id(v))),
        }
    }

    /// The half-edge from the first to the second corner when the element still exists; for a face,
    /// the third corner must close it.
    pub fn locate(&self, mesh: &Mesh) -> Option<HalfEdgeId> {
        let live = |(v, id): (VertexId, u64)| mesh.is_live(v) && mesh.id(v) == id;
        if !self.corners.iter().all(|&c| live(c)) {
            return None;
        }
        let h = mesh.find_half_edge(self.corners[0].0, self.corners[1].0)?;
        match self.kind {
            Kind::SmallAngle => (mesh.origin(mesh.prev(h)) == self.corners[2].0).then_some(h),
            Kind::ShortEdge | Kind::SharpDihedral => Some(h),
        }
    }

    fn key(&self) -> (Kind, f32, [u64; 3]) {
        (self.kind, self.measure, self.corners.map(|c| c.1))
    }
}

impl PartialEq for Task {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Task {}

impl PartialOrd for Task {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Task {
    /// Reversed, so the greatest task — popped first — has the smallest (kind, measure, ids).
    fn cmp(&self, other: &Self) -> Ordering {
        let (k0, m0, i0) = self.key();
        let (k1, m1, i1) = other.key();
        k1.cmp(&k0)
            .then(m1.total_cmp(&m0))
            .then_with(|| i1.cmp(&i0))
    }
}

/// The work list: the initial scan sorted once, plus a heap for the tasks operations add, popped
/// together in task order. Sorting the bulk once is much cheaper than heap-popping it.
pub(super) struct Queue {
    /// Sorted so that the next task is last.
    initial: Vec<Task>,
    added: BinaryHeap<Task>,
}

impl Queue {
    pub fn new(mut tasks: Vec<Task>) -> Self {
        tasks.sort_unstable();
        Self {
            initial: tasks,
            added: BinaryHeap::new(),
        }
    }

    pub fn push(&mut self, task: Task) {
        self.added.push(task);
    }

    pub fn pop(&mut self) -> Option<Task> {
        match (self.initial.last(), self.added.peek()) {
            (Some(a), Some(b)) if b > a => self.added.pop(),
            (Some(_), _) => self.initial.pop(),
            (None, _) => self.added.pop(),
        }
    }
}
