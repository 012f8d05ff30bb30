//! Where waves start (paper §5): "we only add wave heights precisely at the locations in space-time
//! where topological changes occur", i.e. at the vertices of the patches a topology change created
//! (§4.4), plus points a user names.

use crate::events::{EventKind, EventList};
use glam::Vec3;
use rustc_hash::FxHashSet;

/// A user's seed: the vertex nearest `point` in frame `frame`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointSeed {
    pub frame: usize,
    pub point: Vec3,
}

/// The ids of the vertices a transition's topology changes created: those of its patch-created
/// events, and those that later events of the same transition (edge and face splits, collapses)
/// made from patch vertices only, so that the re-meshing that follows a patch keeps it whole.
pub fn patch_vertices(events: &EventList) -> FxHashSet<u64> {
    let mut patch = FxHashSet::default();
    for event in &events.events {
        let created = event.outputs.iter().filter(|id| !event.inputs.contains(id));
        let inside = match event.kind {
            EventKind::PatchCreated => true,
            EventKind::SplitEdge
            | EventKind::SplitFace
            | EventKind::Collapse
            | EventKind::Merge => {
                !event.inputs.is_empty() && event.inputs.iter().all(|id| patch.contains(id))
            }
            EventKind::PatchDeleted => false,
        };
        let created: Vec<u64> = created.copied().collect();
        if inside {
            patch.extend(created);
        }
    }
    patch
}

/// The index of the vertex of `positions` nearest `point` (the first of equals), if any.
pub fn nearest_vertex(positions: &[Vec3], point: Vec3) -> Option<usize> {
    positions
        .iter()
        .enumerate()
        .min_by(|(_, a), (_, b)| {
            a.distance_squared(point)
                .total_cmp(&b.distance_squared(point))
        })
        .map(|(i, _)| i)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::events::Event;

    #[test]
    fn splits_inside_a_patch_join_it_and_those_outside_do_not() {
        let mut events = EventList::new();
        events.push(Event::patch_created(10, vec![(1, 0.5), (2, 0.5)]));
        events.push(Event::patch_created(11, vec![(1, 1.0)]));
        events.push(Event::split_edge(10, 11, 12, 0.5));
        events.push(Event::split_edge(10, 3, 13, 0.5));
        events.push(Event::collapse(12, 10, 14));
        let patch = patch_vertices(&events);
        let mut ids: Vec<u64> = patch.into_iter().collect();
        ids.sort_unstable();
        assert_eq!(ids, vec![10, 11, 12, 14]);
    }

    #[test]
    fn the_nearest_vertex_is_found() {
        let positions = [Vec3::ZERO, Vec3::X, Vec3::Y];
        assert_eq!(
            nearest_vertex(&positions, Vec3::new(0.9, 0.2, 0.0)),
            Some(1)
        );
        assert_eq!(nearest_vertex(&[], Vec3::ZERO), None);
    }
}
