//! The event-list file format: round trip, rejection of every kind of damage, and the documented
//! numpy reader (`docs/read_events.py`) agreeing with the Rust decoder.

use std::process::Command;
use surftrack::events::file::{EventFileError, decode, encode};
use surftrack::events::{Assignment, Event, EventKind, EventList};

fn sample() -> EventList {
    let mut list = EventList::new();
    list.push(Event::split_edge(3, 9, 40, 0.5));
    list.push(Event::split_face([1, 2, 3], 41, [0.2, 0.3, 0.5]));
    list.push(Event::collapse(40, 7, 42));
    list.push(Event::patch_created(43, vec![(1, 0.25), (2, 0.75)]));
    list.push(Event::patch_deleted(5, vec![(43, 1.0)]));
    list.push(Event::merge(42, 8));
    list.push(Event {
        kind: EventKind::PatchCreated,
        inputs: vec![],
        outputs: vec![u64::MAX - 1],
        forward: vec![Assignment::new(u64::MAX - 1, vec![])],
        backward: vec![],
    });
    list
}

#[test]
fn event_lists_round_trip_bit_exactly() {
    let list = sample();
    let bytes = encode(&list);
    assert_eq!(decode(&bytes), Ok(list.clone()));
    assert_eq!(encode(&decode(&bytes).unwrap()), bytes);
    assert_eq!(decode(&encode(&EventList::new())), Ok(EventList::new()));
}

#[test]
fn damaged_files_are_rejected_with_the_reason() {
    let bytes = encode(&sample());
    assert_eq!(
        decode(b"hello world, not events at all....."),
        Err(EventFileError::Magic)
    );
    assert!(matches!(
        decode(&bytes[..bytes.len() - 1]),
        Err(EventFileError::Truncated { .. })
    ));
    assert!(matches!(
        decode(&bytes[..10]),
        Err(EventFileError::Truncated { .. })
    ));
    let mut flipped = bytes.clone();
    flipped[40] ^= 0x10;
    assert!(matches!(
        decode(&flipped),
        Err(EventFileError::Checksum { .. })
    ));
    let mut version = bytes.clone();
    version[8] = 9;
    assert_eq!(decode(&version), Err(EventFileError::Version(9)));
    for cut in 0..bytes.len() {
        assert!(
            decode(&bytes[..cut]).is_err(),
            "prefix of {cut} bytes accepted"
        );
    }
}

#[test]
fn the_documented_python_reader_agrees() {
    let numpy = Command::new("python3")
        .args(["-c", "import numpy"])
        .status();
    if !numpy.is_ok_and(|s| s.success()) {
        assert!(
            std::env::var_os("SURFTRACK_REQUIRE_NUMPY").is_none(),
            "SURFTRACK_REQUIRE_NUMPY is set but python3 with numpy is not available"
        );
        eprintln!("skipping: python3 with numpy is not available");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("0001.events");
    std::fs::write(&path, encode(&sample())).unwrap();
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/docs/read_events.py");
    let out = Command::new("python3")
        .args([script, path.to_str().unwrap(), "--json"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let events = json.as_array().unwrap();
    let list = sample();
    assert_eq!(events.len(), list.events.len());
    let kinds = [
        "split_edge",
        "split_face",
        "collapse",
        "patch_created",
        "patch_deleted",
        "merge",
    ];
    for (py, rs) in events.iter().zip(&list.events) {
        let kind = match rs.kind {
            EventKind::SplitEdge => 0,
            EventKind::SplitFace => 1,
            EventKind::Collapse => 2,
            EventKind::PatchCreated => 3,
            EventKind::PatchDeleted => 4,
            EventKind::Merge => 5,
        };
        assert_eq!(py["kind"], kinds[kind]);
        let ids = |v: &serde_json::Value| -> Vec<u64> {
            v.as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_u64().unwrap())
                .collect()
        };
        assert_eq!(ids(&py["inputs"]), rs.inputs);
        assert_eq!(ids(&py["outputs"]), rs.outputs);
        for (rule, expected) in [
            (&py["forward"], &rs.forward),
            (&py["backward"], &rs.backward),
        ] {
            let rule = rule.as_array().unwrap();
            assert_eq!(rule.len(), expected.len());
            for (a, e) in rule.iter().zip(expected) {
                assert_eq!(a["target"].as_u64(), Some(e.target));
                let terms: Vec<(u64, f32)> = a["terms"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|t| (t[0].as_u64().unwrap(), t[1].as_f64().unwrap() as f32))
                    .collect();
                assert_eq!(terms, e.terms);
            }
        }
    }
}
