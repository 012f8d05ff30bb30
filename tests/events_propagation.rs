//! Event lists against the mutations they record (paper §4.4, §4.6): for random sequences of splits,
//! face splits, collapses and flips, `forward` on positions reproduces the positions the mutations
//! created, constant channels stay constant both ways, `backward(forward(x))` returns `x` on every
//! vertex that survived, and the mesh's own attribute interpolation agrees with the event rules.

use glam::Vec3;
use proptest::prelude::*;
use std::collections::HashSet;
use surftrack::events::{
    Assignment, Event, EventError, EventKind, EventList, VertexValues, backward, forward,
};
use surftrack::mesh::{HalfEdgeId, IndexedMesh, Mesh};

/// One mutation drawn by proptest: which one, where (a face and a corner, reduced modulo the live
/// counts at the time), and its parameters.
#[derive(Debug, Clone)]
struct Step {
    kind: u8,
    face: usize,
    corner: u32,
    t: f32,
    weights: (f32, f32),
}

fn step() -> impl Strategy<Value = Step> {
    (
        0u8..4,
        any::<usize>(),
        0u32..3,
        0.05f32..0.95,
        (0.1f32..0.45, 0.1f32..0.45),
    )
        .prop_map(|(kind, face, corner, t, weights)| Step {
            kind,
            face,
            corner,
            t,
            weights,
        })
}

/// A sphere whose vertices are pushed in and out, so positions are not symmetric and every rule is
/// exercised on distinct values.
fn start_mesh() -> Mesh {
    let mut input = IndexedMesh::icosphere(Vec3::new(0.3, -0.2, 0.1), 1.5, 2);
    for (i, p) in input.positions.iter_mut().enumerate() {
        *p *= 1.0 + 0.05 * ((i * 37 % 11) as f32 / 11.0);
    }
    Mesh::from_indexed(&input).expect("valid start mesh")
}

/// Applies the steps that the mesh accepts; returns how many were applied.
fn apply(mesh: &mut Mesh, steps: &[Step]) -> usize {
    let mut applied = 0;
    for s in steps {
        let faces: Vec<_> = mesh.faces().collect();
        let f = faces[s.face % faces.len()];
        let h = HalfEdgeId(mesh.face_half_edge(f).0 + s.corner);
        let done = match s.kind {
            0 => mesh.split_edge(h, s.t).is_some(),
            1 => {
                let (a, b) = s.weights;
                mesh.split_face(f, [a, b, 1.0 - a - b]).is_some()
            }
            2 => {
                let mid = (mesh.position(mesh.origin(h)) + mesh.position(mesh.target(h))) * 0.5;
                mesh.collapse(h, mid).is_some()
            }
            _ => mesh.flip(h).is_some(),
        };
        applied += usize::from(done);
    }
    applied
}

fn positions(mesh: &Mesh) -> VertexValues {
    let ids: Vec<u64> = mesh.vertices().map(|v| mesh.id(v)).collect();
    let values: Vec<f32> = mesh
        .vertices()
        .flat_map(|v| mesh.position(v).to_array())
        .collect();
    VertexValues::from_parts(3, &ids, &values).expect("one value per vertex")
}

fn constant(ids: &[u64], value: &[f32]) -> VertexValues {
    let values: Vec<f32> = ids.iter().flat_map(|_| value.iter().copied()).collect();
    VertexValues::from_parts(value.len(), ids, &values).expect("one value per vertex")
}

fn sorted(ids: &[u64]) -> Vec<u64> {
    let mut ids = ids.to_vec();
    ids.sort_unstable();
    ids
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn events_reproduce_the_mutations(steps in prop::collection::vec(step(), 1..250)) {
        let mut mesh = start_mesh();
        mesh.add_attribute("position", 3, 0.0);
        for v in mesh.vertices().collect::<Vec<_>>() {
            let p = mesh.position(v).to_array();
            mesh.attribute_mut(0, v).copy_from_slice(&p);
        }
        let before = positions(&mesh);
        let initial: Vec<u64> = sorted(before.ids());
        mesh.record_mutations();
        apply(&mut mesh, &steps);
        mesh.validate().expect("mutations keep the mesh valid");
        let events = EventList::drain(&mut mesh);
        events.check().expect("every recorded event is well formed");
        let after = positions(&mesh);
        let last: Vec<u64> = sorted(after.ids());

        // Forward on positions gives every vertex of the last frame, where the mutations put it,
        // and agrees with the channel the mesh interpolated itself.
        let mut carried = before.clone();
        forward(&events, &mut carried).expect("forward");
        prop_assert_eq!(sorted(carried.ids()), last.clone());
        for v in mesh.vertices() {
            let id = mesh.id(v);
            let p = Vec3::from_slice(carried.get(id).expect("carried"));
            let scale = 1.0 + mesh.position(v).abs().max_element();
            prop_assert!(p.distance(mesh.position(v)) <= 1e-5 * scale, "vertex {}: {} vs {}", id, p, mesh.position(v));
            let own = Vec3::from_slice(mesh.attribute(0, v));
            prop_assert!(p.distance(own) <= 1e-5 * scale, "vertex {}: events {} vs mesh {}", id, p, own);
        }

        // Backward brings values back to exactly the first frame's vertices; survivors unchanged.
        let mut back = carried.clone();
        backward(&events, &mut back).expect("backward");
        prop_assert_eq!(sorted(back.ids()), initial.clone());
        let alive: HashSet<u64> = last.iter().copied().collect();
        for &id in &initial {
            if alive.contains(&id) {
                prop_assert_eq!(back.get(id), before.get(id), "survivor {} changed", id);
            }
        }

        // Constants stay constant, both ways (weights sum to one up to rounding).
        let c = [3.5f32, -1.25];
        let mut forth = constant(&initial, &c);
        forward(&events, &mut forth).expect("forward constant");
        for &id in &last {
            let v = forth.get(id).expect("every vertex has a value");
            prop_assert!((v[0] - c[0]).abs() <= 1e-5 && (v[1] - c[1]).abs() <= 1e-5, "{}: {:?}", id, v);
        }
        let mut back = constant(&last, &c);
        backward(&events, &mut back).expect("backward constant");
        prop_assert_eq!(sorted(back.ids()), initial);
        for id in back.ids() {
            let v = back.get(*id).expect("value");
            prop_assert!((v[0] - c[0]).abs() <= 1e-5 && (v[1] - c[1]).abs() <= 1e-5, "{}: {:?}", id, v);
        }
    }
}

#[test]
fn every_mutation_but_a_flip_becomes_one_event_of_its_kind() {
    let mut mesh = start_mesh();
    mesh.record_mutations();
    let h = HalfEdgeId(0);
    let split = mesh.split_edge(h, 0.25).expect("split");
    let f = mesh.faces().next().expect("a face");
    mesh.split_face(f, [0.2, 0.3, 0.5]).expect("face split");
    let e = mesh.outgoing(split).next().expect("an edge");
    let flipped = mesh.flip(e).is_some();
    let e = mesh.outgoing(split).nth(1).expect("an edge");
    let mid = (mesh.position(mesh.origin(e)) + mesh.position(mesh.target(e))) * 0.5;
    mesh.collapse(e, mid).expect("collapse");
    let events = EventList::drain(&mut mesh);
    let kinds: Vec<EventKind> = events.events.iter().map(|e| e.kind).collect();
    assert!(flipped, "the test flip was refused");
    assert_eq!(
        kinds,
        [
            EventKind::SplitEdge,
            EventKind::SplitFace,
            EventKind::Collapse
        ]
    );
    assert_eq!(events.events[0].forward[0].terms[1].1, 0.25);
    let collapse = &events.events[2];
    assert_eq!(collapse.outputs.len(), 1);
    assert_eq!(collapse.backward.len(), 2, "a := b := new");
    assert!(
        EventList::drain(&mut mesh).is_empty(),
        "the journal was drained"
    );
}

#[test]
fn topology_patches_average_their_boundary_and_vanish_the_other_way() {
    let mut events = EventList::new();
    events.push(Event::patch_created(10, vec![(1, 0.25), (2, 0.75)]));
    events.push(Event::patch_deleted(2, vec![(1, 0.5), (10, 0.5)]));
    events.check().expect("well formed");
    let mut values = VertexValues::from_parts(1, &[1, 2], &[4.0, 8.0]).unwrap();
    forward(&events, &mut values).unwrap();
    assert_eq!(sorted(values.ids()), [1, 10]);
    assert_eq!(values.get(10), Some(&[7.0][..]));
    values.insert(10, &[2.0]).unwrap();
    backward(&events, &mut values).unwrap();
    assert_eq!(sorted(values.ids()), [1, 2]);
    assert_eq!(
        values.get(2),
        Some(&[3.0][..]),
        "deleted vertex := (1 + 10)/2"
    );
    assert_eq!(values.get(1), Some(&[4.0][..]));
}

#[test]
fn missing_sources_and_malformed_rules_are_errors() {
    let events = EventList {
        events: vec![Event::collapse(1, 2, 3)],
    };
    let mut values = VertexValues::from_parts(1, &[1], &[1.0]).unwrap();
    assert_eq!(
        forward(&events, &mut values),
        Err(EventError::MissingVertex { event: 0, id: 2 })
    );
    assert!(matches!(
        VertexValues::from_parts(2, &[1, 2], &[1.0, 2.0, 3.0]),
        Err(EventError::ComponentMismatch { .. })
    ));
    assert_eq!(
        VertexValues::from_parts(1, &[5, 5], &[1.0, 2.0]),
        Err(EventError::DuplicateVertex { id: 5 })
    );
    let mut bad = Event::split_edge(1, 2, 3, 0.5);
    bad.forward.push(Assignment::copy(4, 1));
    assert!(matches!(
        bad.check(7),
        Err(EventError::Malformed { event: 7, .. })
    ));
    let mut bad = Event::collapse(1, 2, 3);
    bad.backward[0].terms[0].0 = 1;
    assert!(matches!(bad.check(0), Err(EventError::Malformed { .. })));
}

#[test]
fn event_lists_survive_a_serde_round_trip() {
    let mut mesh = start_mesh();
    mesh.record_mutations();
    apply(
        &mut mesh,
        &(0..40)
            .map(|i| Step {
                kind: (i % 3) as u8,
                face: i * 7,
                corner: (i % 3) as u32,
                t: 0.3,
                weights: (0.2, 0.3),
            })
            .collect::<Vec<_>>(),
    );
    let events = EventList::drain(&mut mesh);
    assert!(!events.is_empty());
    let json = serde_json::to_string(&events).unwrap();
    let back: EventList = serde_json::from_str(&json).unwrap();
    assert_eq!(back, events);
}
