use super::{Event, EventError};
use crate::mesh::{Mesh, Mutation};
use serde::{Deserialize, Serialize};

/// The events of one frame transition, in the order they happened (paper §4.4).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct EventList {
    pub events: Vec<Event>,
}

impl EventList {
    pub fn new() -> Self {
        Self::default()
    }

    /// The events a mesh journal stands for, in journal order (flips re-sample nothing and give none).
    pub fn from_mutations(mutations: &[Mutation]) -> Self {
        Self {
            events: mutations.iter().filter_map(Event::from_mutation).collect(),
        }
    }

    /// Drains the mesh's journal (see `Mesh::record_mutations`) into events: every split and collapse
    /// the mesh performed since the last drain, whoever asked for it.
    pub fn drain(mesh: &mut Mesh) -> Self {
        Self::from_mutations(&mesh.take_journal())
    }

    pub fn push(&mut self, event: Event) {
        self.events.push(event);
    }

    /// Appends the events of a later stage of the same transition.
    pub fn extend(&mut self, later: EventList) {
        self.events.extend(later.events);
    }

    pub fn len(&self) -> usize {
        self.events.len()
    }

    pub fn is_empty(&self) -> bool {
        self.events.is_empty()
    }

    /// Checks every event's rules against its vertex sets (see `Event::check`).
    pub fn check(&self) -> Result<(), EventError> {
        self.events
            .iter()
            .enumerate()
            .try_for_each(|(i, e)| e.check(i))
    }
}
