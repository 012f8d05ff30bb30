//! The event-list file: one per frame transition, a versioned little-endian binary with a CRC-32
//! trailer, laid out as flat record arrays so it reads with a few `numpy.frombuffer` calls
//! (`docs/event_format.md`, `docs/read_events.py`).
//!
//! ```text
//! header   magic "SURFEVT\0", version u32, event_count u32, id_count u32,
//!          assignment_count u32, term_count u32, reserved u32 (0)            32 bytes
//! events   event_count × 9 u32: kind, inputs (start, count), outputs (start, count),
//!          forward assignments (start, count), backward assignments (start, count)
//! ids      id_count × u64: every event's inputs then outputs, concatenated
//! assigns  assignment_count × (target u64, term start u32, term count u32)
//! terms    term_count × (source u64, weight f32, reserved u32 (0))
//! trailer  CRC-32 (IEEE) of every preceding byte, u32
//! ```

use super::{Assignment, Event, EventKind, EventList};
use rustc_hash::FxHashMap;
use thiserror::Error;

pub const MAGIC: &[u8; 8] = b"SURFEVT\0";
pub const VERSION: u32 = 1;
const HEADER_BYTES: usize = 32;
const EVENT_BYTES: usize = 36;
const ASSIGNMENT_BYTES: usize = 16;
const TERM_BYTES: usize = 16;

/// Why bytes are not a valid event-list file; the caller adds the file name.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum EventFileError {
    #[error("not an event-list file (bad magic)")]
    Magic,
    #[error("event-list version {0} is not supported (this build reads version {VERSION})")]
    Version(u32),
    #[error("truncated: {expected} bytes expected, {found} present")]
    Truncated { expected: usize, found: usize },
    #[error("checksum mismatch: stored {stored:#010x}, computed {computed:#010x}")]
    Checksum { stored: u32, computed: u32 },
    #[error("event {event}: {what} range {start}+{count} lies outside its table of {len}")]
    Range {
        event: usize,
        what: &'static str,
        start: usize,
        count: usize,
        len: usize,
    },
    #[error("event {event}: unknown kind {kind}")]
    Kind { event: usize, kind: u32 },
    #[error(
        "event {event}: {what} range starts at {start}, where the previous one ended at {expected}"
    )]
    Order {
        event: usize,
        what: &'static str,
        start: usize,
        expected: usize,
    },
    #[error("{what} table: {used} of its {len} entries belong to an event")]
    Unused {
        what: &'static str,
        used: usize,
        len: usize,
    },
    #[error("reserved field at byte {0} is not zero")]
    Reserved(usize),
}

fn kind_code(kind: EventKind) -> u32 {
    match kind {
        EventKind::SplitEdge => 0,
        EventKind::SplitFace => 1,
        EventKind::Collapse => 2,
        EventKind::PatchCreated => 3,
        EventKind::PatchDeleted => 4,
        EventKind::Merge => 5,
    }
}

fn kind_from(code: u32) -> Option<EventKind> {
    Some(match code {
        0 => EventKind::SplitEdge,
        1 => EventKind::SplitFace,
        2 => EventKind::Collapse,
        3 => EventKind::PatchCreated,
        4 => EventKind::PatchDeleted,
        5 => EventKind::Merge,
        _ => return None,
    })
}

/// Serializes an event list (deterministic: the same list gives the same bytes).
pub fn encode(list: &EventList) -> Vec<u8> {
    let mut events = Vec::new();
    let mut ids: Vec<u64> = Vec::new();
    let mut assigns: Vec<(u64, u32, u32)> = Vec::new();
    let mut terms: Vec<(u64, f32)> = Vec::new();
    let mut push_assignments = |list: &[Assignment], assigns: &mut Vec<(u64, u32, u32)>| {
        let start = assigns.len() as u32;
        for a in list {
            assigns.push((a.target, terms.len() as u32, a.terms.len() as u32));
            terms.extend(a.terms.iter().copied());
        }
        (start, list.len() as u32)
    };
    for e in &list.events {
        let inputs = (ids.len() as u32, e.inputs.len() as u32);
        ids.extend(&e.inputs);
        let outputs = (ids.len() as u32, e.outputs.len() as u32);
        ids.extend(&e.outputs);
        let forward = push_assignments(&e.forward, &mut assigns);
        let backward = push_assignments(&e.backward, &mut assigns);
        events.push([
            kind_code(e.kind),
            inputs.0,
            inputs.1,
            outputs.0,
            outputs.1,
            forward.0,
            forward.1,
            backward.0,
            backward.1,
        ]);
    }
    let mut out = Vec::with_capacity(
        HEADER_BYTES
            + events.len() * EVENT_BYTES
            + ids.len() * 8
            + assigns.len() * ASSIGNMENT_BYTES
            + terms.len() * TERM_BYTES
            + 4,
    );
    out.extend_from_slice(MAGIC);
    for v in [
        VERSION,
        events.len() as u32,
        ids.len() as u32,
        assigns.len() as u32,
        terms.len() as u32,
        0,
    ] {
        out.extend_from_slice(&v.to_le_bytes());
    }
    for e in &events {
        for v in e {
            out.extend_from_slice(&v.to_le_bytes());
        }
    }
    for id in &ids {
        out.extend_from_slice(&id.to_le_bytes());
    }
    for (target, start, count) in &assigns {
        out.extend_from_slice(&target.to_le_bytes());
        out.extend_from_slice(&start.to_le_bytes());
        out.extend_from_slice(&count.to_le_bytes());
    }
    for (source, weight) in &terms {
        out.extend_from_slice(&source.to_le_bytes());
        out.extend_from_slice(&weight.to_le_bytes());
        out.extend_from_slice(&0u32.to_le_bytes());
    }
    let crc = crc32fast::hash(&out);
    out.extend_from_slice(&crc.to_le_bytes());
    out
}

/// The range `start..start + count` of a table of `len` entries, which must begin where the
/// previous range of that table ended (`used`), and then ends there.
fn take(
    event: usize,
    what: &'static str,
    start: u32,
    count: u32,
    len: usize,
    used: &mut usize,
) -> Result<std::ops::Range<usize>, EventFileError> {
    let (start, count) = (start as usize, count as usize);
    if start != *used {
        return Err(EventFileError::Order {
            event,
            what,
            start,
            expected: *used,
        });
    }
    if start.checked_add(count).is_none_or(|end| end > len) {
        return Err(EventFileError::Range {
            event,
            what,
            start,
            count,
            len,
        });
    }
    *used = start + count;
    Ok(start..start + count)
}

/// Little-endian cursor over a byte slice whose length was checked up front.
struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl Reader<'_> {
    fn u32(&mut self) -> u32 {
        let v = u32::from_le_bytes([
            self.bytes[self.at],
            self.bytes[self.at + 1],
            self.bytes[self.at + 2],
            self.bytes[self.at + 3],
        ]);
        self.at += 4;
        v
    }

    fn u64(&mut self) -> u64 {
        let lo = u64::from(self.u32());
        let hi = u64::from(self.u32());
        lo | (hi << 32)
    }

    fn f32(&mut self) -> f32 {
        f32::from_bits(self.u32())
    }
}

/// Checks that `bytes` are one whole event file — magic, version, the length its counts give
/// and the checksum — without decoding it; returns the counts of events, ids, assignments and
/// terms. A reader that only needs to know a file is present and whole (before writing anything)
/// pays for a checksum, not for building the list.
pub fn verify(bytes: &[u8]) -> Result<[usize; 4], EventFileError> {
    if bytes.len() < HEADER_BYTES + 4 {
        return Err(if bytes.len() >= 8 && &bytes[..8] != MAGIC {
            EventFileError::Magic
        } else {
            EventFileError::Truncated {
                expected: HEADER_BYTES + 4,
                found: bytes.len(),
            }
        });
    }
    if &bytes[..8] != MAGIC {
        return Err(EventFileError::Magic);
    }
    let mut r = Reader { bytes, at: 8 };
    let version = r.u32();
    if version != VERSION {
        return Err(EventFileError::Version(version));
    }
    let counts = [r.u32(), r.u32(), r.u32(), r.u32()].map(|c| c as usize);
    let [n_events, n_ids, n_assigns, n_terms] = counts;
    let expected = (HEADER_BYTES + 4)
        .saturating_add(n_events.saturating_mul(EVENT_BYTES))
        .saturating_add(n_ids.saturating_mul(8))
        .saturating_add(n_assigns.saturating_mul(ASSIGNMENT_BYTES))
        .saturating_add(n_terms.saturating_mul(TERM_BYTES));
    if bytes.len() != expected {
        return Err(EventFileError::Truncated {
            expected,
            found: bytes.len(),
        });
    }
    let body = &bytes[..expected - 4];
    let stored = u32::from_le_bytes([
        bytes[expected - 4],
        bytes[expected - 3],
        bytes[expected - 2],
        bytes[expected - 1],
    ]);
    let computed = crc32fast::hash(body);
    if stored != computed {
        return Err(EventFileError::Checksum { stored, computed });
    }
    Ok(counts)
}

/// Every vertex a whole event file (see [`verify`]) touches, sorted, with whether the list leaves
/// it alive: an event destroys its inputs and leaves its outputs alive, in the list's order (an
/// input an event also outputs, as an edge split keeps its ends, stays alive). Reads only the
/// event records and the id table, not the rules, so a reader checking a list against its frame's
/// ids pays little for it.
pub fn touched(bytes: &[u8]) -> Result<Vec<(u64, bool)>, EventFileError> {
    let [n_events, n_ids, _, _] = verify(bytes)?;
    let mut r = Reader {
        bytes,
        at: HEADER_BYTES,
    };
    let records: Vec<[u32; 9]> = (0..n_events)
        .map(|_| std::array::from_fn(|_| r.u32()))
        .collect();
    let ids: Vec<u64> = (0..n_ids).map(|_| r.u64()).collect();
    let mut used = 0;
    let mut alive: FxHashMap<u64, bool> = FxHashMap::default();
    for (i, rec) in records.iter().enumerate() {
        let inputs = take(i, "input", rec[1], rec[2], ids.len(), &mut used)?;
        let outputs = take(i, "output", rec[3], rec[4], ids.len(), &mut used)?;
        for &id in &ids[inputs] {
            alive.insert(id, false);
        }
        for &id in &ids[outputs] {
            alive.insert(id, true);
        }
    }
    let mut touched: Vec<(u64, bool)> = alive.into_iter().collect();
    touched.sort_unstable();
    Ok(touched)
}

/// Parses and checks an event-list file: magic, version, sizes, checksum, and every index range.
///
/// The ranges must tile their tables in order, as [`encode`] writes them (each event's inputs
/// right after the previous event's outputs, and so on), and reserved fields must be zero: so
/// every accepted file is the encoding of the list it decodes to, and the list is never larger
/// than the file (overlapping ranges could make a small file name the same ids millions of times).
pub fn decode(bytes: &[u8]) -> Result<EventList, EventFileError> {
    let [n_events, n_ids, n_assigns, n_terms] = verify(bytes)?;
    let mut r = Reader {
        bytes,
        at: HEADER_BYTES,
    };
    let expected = bytes.len();
    let records: Vec<[u32; 9]> = (0..n_events)
        .map(|_| std::array::from_fn(|_| r.u32()))
        .collect();
    let ids: Vec<u64> = (0..n_ids).map(|_| r.u64()).collect();
    let assigns: Vec<(u64, u32, u32)> = (0..n_assigns)
        .map(|_| (r.u64(), r.u32(), r.u32()))
        .collect();
    let terms: Vec<(u64, f32)> = (0..n_terms)
        .map(|_| {
            let t = (r.u64(), r.f32());
            r.u32();
            t
        })
        .collect();
    let reserved = u32::from_le_bytes([bytes[28], bytes[29], bytes[30], bytes[31]]);
    if reserved != 0 {
        return Err(EventFileError::Reserved(28));
    }
    let terms_at = expected - 4 - n_terms * TERM_BYTES;
    for t in 0..n_terms {
        let at = terms_at + t * TERM_BYTES + 12;
        if bytes[at..at + 4] != [0; 4] {
            return Err(EventFileError::Reserved(at));
        }
    }
    let mut ids_used = 0;
    let mut assigns_used = 0;
    let mut terms_used = 0;
    let mut list = EventList::new();
    for (i, rec) in records.iter().enumerate() {
        let kind = kind_from(rec[0]).ok_or(EventFileError::Kind {
            event: i,
            kind: rec[0],
        })?;
        let inputs = take(i, "input", rec[1], rec[2], ids.len(), &mut ids_used)?;
        let outputs = take(i, "output", rec[3], rec[4], ids.len(), &mut ids_used)?;
        let mut assignments = |start: u32, count: u32| -> Result<Vec<Assignment>, EventFileError> {
            take(
                i,
                "assignment",
                start,
                count,
                assigns.len(),
                &mut assigns_used,
            )?
            .map(|a| {
                let (target, ts, tc) = assigns[a];
                let range = take(i, "term", ts, tc, terms.len(), &mut terms_used)?;
                Ok(Assignment::new(target, terms[range].to_vec()))
            })
            .collect()
        };
        let forward = assignments(rec[5], rec[6])?;
        let backward = assignments(rec[7], rec[8])?;
        list.push(Event {
            kind,
            inputs: ids[inputs].to_vec(),
            outputs: ids[outputs].to_vec(),
            forward,
            backward,
        });
    }
    for (what, used, len) in [
        ("id", ids_used, ids.len()),
        ("assignment", assigns_used, assigns.len()),
        ("term", terms_used, terms.len()),
    ] {
        if used != len {
            return Err(EventFileError::Unused { what, used, len });
        }
    }
    Ok(list)
}
