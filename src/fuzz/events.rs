//! Event-list files: lists with every kind of event encoded, mutated where the header counts and
//! the events' ranges lie, or anywhere; the checksum is made right again for most inputs, so the
//! checks behind it are reached.

use super::mutate::{GARBAGE_U32, bytes_any, put};
use super::{Harness, Input, Rng, Verdict};
use crate::events::file::{decode, encode};
use crate::events::{Assignment, Event, EventKind, EventList, VertexValues, forward};
use std::path::Path;

pub(super) struct Events {
    seeds: Vec<Vec<u8>>,
}

impl Events {
    pub(super) fn new(_dir: &Path) -> Result<Self, String> {
        let mut lists = vec![EventList::new()];
        let mut list = EventList::new();
        list.push(Event::split_edge(1, 2, 10, 0.25));
        list.push(Event::split_face([3, 4, 5], 11, [0.2, 0.3, 0.5]));
        list.push(Event {
            kind: EventKind::Collapse,
            inputs: vec![10, 2],
            outputs: vec![2],
            forward: vec![Assignment::new(2, vec![(10, 0.5), (2, 0.5)])],
            backward: vec![Assignment::copy(10, 2)],
        });
        list.push(Event {
            kind: EventKind::PatchCreated,
            inputs: vec![],
            outputs: vec![12, 13],
            forward: vec![Assignment::copy(12, 1), Assignment::copy(13, 1)],
            backward: vec![],
        });
        list.push(Event {
            kind: EventKind::PatchDeleted,
            inputs: vec![5],
            outputs: vec![],
            forward: vec![],
            backward: vec![Assignment::copy(5, 4)],
        });
        lists.push(list);
        Ok(Self {
            seeds: lists.iter().map(encode).collect(),
        })
    }
}

/// Makes the CRC-32 trailer match the bytes before it.
fn fix_checksum(bytes: &mut [u8]) {
    if bytes.len() >= 4 {
        let end = bytes.len() - 4;
        let crc = crc32fast::hash(&bytes[..end]);
        bytes[end..].copy_from_slice(&crc.to_le_bytes());
    }
}

impl Harness for Events {
    fn generate(&self, rng: &mut Rng) -> Input {
        let mut bytes = rng.pick(&self.seeds).clone();
        for _ in 0..1 + rng.below(3) {
            match rng.below(4) {
                0 => {
                    let at = 12 + 4 * rng.below(5);
                    put(&mut bytes, at, &rng.pick(GARBAGE_U32).to_le_bytes());
                }
                1 => {
                    let at = 32 + 36 * rng.below(5) + 4 * rng.below(9);
                    put(&mut bytes, at, &rng.pick(GARBAGE_U32).to_le_bytes());
                }
                _ => {
                    let donor = rng.pick(&self.seeds);
                    bytes_any(rng, &mut bytes, donor);
                }
            }
        }
        if rng.chance(80) {
            fix_checksum(&mut bytes);
        }
        Input::one("0001.events", bytes)
    }

    fn check(&self, scratch: &Path) -> Result<Verdict, String> {
        let bytes = std::fs::read(scratch.join("0001.events")).map_err(|e| e.to_string())?;
        let Ok(list) = decode(&bytes) else {
            return Ok(Verdict::Refused);
        };
        if encode(&list) != bytes {
            return Err(
                "accepted a file that is not the encoding of the list it decodes to".into(),
            );
        }
        if list.check().is_err() {
            return Ok(Verdict::Refused);
        }
        // Carrying values through whatever the list says must fail cleanly or succeed.
        let ids: Vec<u64> = (0..16).collect();
        let values: Vec<f32> = ids.iter().map(|&i| i as f32).collect();
        let mut carried = VertexValues::from_parts(1, &ids, &values).map_err(|e| e.to_string())?;
        let _ = forward(&list, &mut carried);
        Ok(Verdict::Accepted)
    }
}
