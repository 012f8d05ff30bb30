//! Patch replacement: the mesh takes a new surface (a valid `Mesh`, so an open one cannot be
//! offered) only with a record that accounts for every vertex it gains and loses, journals that
//! record as events, and carries attributes by its rules.

use glam::Vec3;
use surftrack::events::{EventKind, EventList};
use surftrack::mesh::{IndexedMesh, Mesh, MeshError, Mutation, Replacement, ReplacementError};

/// A sphere whose vertex 0 is replaced by a new vertex at the same place (a one-vertex patch).
fn swapped(mesh: &Mesh) -> (IndexedMesh, u64, u64) {
    let mut surface = mesh.to_indexed();
    let ids = surface.ids.as_mut().expect("a mesh has ids");
    let old = ids[0];
    let new = mesh.next_id();
    ids[0] = new;
    (surface, old, new)
}

fn sphere() -> Mesh {
    let mut mesh = Mesh::from_indexed(&IndexedMesh::icosphere(Vec3::ZERO, 1.0, 2)).unwrap();
    mesh.add_attribute("x", 1, 0.0);
    for v in mesh.vertices().collect::<Vec<_>>() {
        let x = mesh.position(v).x;
        mesh.attribute_mut(0, v)[0] = x;
    }
    mesh.record_mutations();
    mesh
}

#[test]
fn a_recorded_replacement_is_journaled_and_carries_attributes() {
    let mut mesh = sphere();
    let (surface, old, new) = swapped(&mesh);
    let neighbour = surface.ids.as_ref().unwrap()[1];
    let record = vec![
        Mutation::PatchCreated {
            created: new,
            sources: vec![(old, 0.25), (neighbour, 0.75)],
        },
        Mutation::PatchDeleted {
            deleted: old,
            sources: vec![(new, 1.0)],
        },
    ];
    let expected = 0.25 * surface.positions[0].x + 0.75 * surface.positions[1].x;
    let surface = Mesh::from_indexed(&surface).unwrap();
    mesh.replace(Replacement { surface, record }).unwrap();
    mesh.validate().unwrap();
    assert_eq!(mesh.next_id(), new + 1);
    let out = mesh.to_indexed();
    let at = out.ids.as_ref().unwrap().iter().position(|&i| i == new);
    let value = out.attributes[0].values[at.expect("the new vertex is in the mesh")];
    assert!((value - expected).abs() < 1e-6, "{value} vs {expected}");
    let events = EventList::drain(&mut mesh);
    let kinds: Vec<EventKind> = events.events.iter().map(|e| e.kind).collect();
    assert_eq!(kinds, [EventKind::PatchCreated, EventKind::PatchDeleted]);
    events.check().unwrap();
}

#[test]
fn a_replacement_without_its_record_is_refused_and_changes_nothing() {
    let mut mesh = sphere();
    let before = mesh.to_indexed();
    let (surface, old, new) = swapped(&mesh);
    let refuse = |mesh: &mut Mesh, record: Vec<Mutation>| {
        let err = mesh
            .replace(Replacement {
                surface: Mesh::from_indexed(&surface).unwrap(),
                record,
            })
            .unwrap_err();
        match err {
            MeshError::Replacement(e) => e,
            other => panic!("not a replacement error: {other}"),
        }
    };
    assert_eq!(
        refuse(&mut mesh, Vec::new()),
        ReplacementError::Unrecorded { id: new }
    );
    let created = Mutation::PatchCreated {
        created: new,
        sources: Vec::new(),
    };
    assert_eq!(
        refuse(&mut mesh, vec![created.clone()]),
        ReplacementError::Vanished { id: old }
    );
    let reused = Mutation::PatchCreated {
        created: old,
        sources: Vec::new(),
    };
    assert_eq!(
        refuse(&mut mesh, vec![reused]),
        ReplacementError::Reused { id: old }
    );
    let twice = Mutation::PatchDeleted {
        deleted: old,
        sources: Vec::new(),
    };
    assert_eq!(
        refuse(&mut mesh, vec![created, twice.clone(), twice]),
        ReplacementError::NotRemovable { id: old }
    );
    let after = mesh.to_indexed();
    assert_eq!(after.positions, before.positions);
    assert_eq!(after.ids, before.ids);
    assert!(EventList::drain(&mut mesh).is_empty());
}

#[test]
fn an_invalid_surface_cannot_be_a_replacement() {
    let mesh = sphere();
    let (mut surface, _, _) = swapped(&mesh);
    surface.triangles.pop();
    let err = Mesh::from_indexed(&surface).unwrap_err();
    assert!(matches!(err, MeshError::OpenBoundary { .. }), "{err}");
}

/// Vertices 0, 1 and 2 of a sphere re-sampled: 0 by a new vertex 0.01 from it that reads it, 1 by
/// one 0.1 from it that reads it, 2 by one on it that reads a kept neighbour above all.
fn resampled(mesh: &Mesh) -> (Replacement, [u64; 3], [u64; 3]) {
    let mut surface = mesh.to_indexed();
    let first = mesh.next_id();
    let ids = surface.ids.as_mut().expect("a mesh has ids");
    let old = [ids[0], ids[1], ids[2]];
    let new = [first, first + 1, first + 2];
    let kept = ids[3];
    ids[..3].copy_from_slice(&new);
    for (v, shift) in [(0, 0.01), (1, 0.1)] {
        let p = surface.positions[v];
        surface.positions[v] = p * (1.0 + shift / p.length());
    }
    let record = vec![
        Mutation::PatchCreated {
            created: new[0],
            sources: vec![(kept, 0.25), (old[0], 0.75)],
        },
        Mutation::PatchCreated {
            created: new[1],
            sources: vec![(old[1], 1.0)],
        },
        Mutation::PatchCreated {
            created: new[2],
            sources: vec![(old[2], 0.4), (kept, 0.6)],
        },
        Mutation::PatchDeleted {
            deleted: old[0],
            sources: vec![(new[0], 1.0)],
        },
        Mutation::PatchDeleted {
            deleted: old[1],
            sources: vec![(new[1], 0.5), (new[0], 0.5)],
        },
        Mutation::PatchDeleted {
            deleted: old[2],
            sources: vec![(new[2], 1.0)],
        },
    ];
    let surface = Mesh::from_indexed(&surface).unwrap();
    (Replacement { surface, record }, old, new)
}

#[test]
fn a_new_vertex_standing_on_the_removed_vertex_it_reads_continues_it() {
    let mut mesh = sphere();
    let x0 = mesh.to_indexed().attributes[0].values[0];
    let (replacement, old, new) = resampled(&mesh);
    let (continued, ids) = replacement.continuing(&mesh, 0.05);
    assert_eq!(ids, [old[0]]);
    mesh.replace(continued).unwrap();
    mesh.validate().unwrap();
    let out = mesh.to_indexed();
    let ids = out.ids.as_ref().unwrap();
    let at = |id: u64| ids.iter().position(|&i| i == id);
    // Vertex 0 stood 0.01 from its new vertex and was read above all: it continues there, with
    // its value; 1 stood too far, 2 was not what its new vertex read most.
    let kept = at(old[0]).expect("the old vertex continues");
    assert!((out.positions[kept].length() - 1.01).abs() < 1e-5);
    assert_eq!(out.attributes[0].values[kept], x0);
    assert_eq!(at(new[0]), None);
    assert!(at(old[1]).is_none() && at(old[2]).is_none());
    assert!(at(new[1]).is_some() && at(new[2]).is_some());
    let events = EventList::drain(&mut mesh);
    events.check().unwrap();
    let kinds: Vec<EventKind> = events.events.iter().map(|e| e.kind).collect();
    use EventKind::{PatchCreated, PatchDeleted};
    assert_eq!(
        kinds,
        [PatchCreated, PatchCreated, PatchDeleted, PatchDeleted]
    );
    // The removal of 1 read the new vertex 0 going backward: it reads the old id now.
    let undone = events
        .events
        .iter()
        .find(|e| e.kind == PatchDeleted)
        .unwrap();
    assert_eq!(undone.backward[0].target, old[1]);
    assert_eq!(undone.backward[0].terms, [(new[1], 0.5), (old[0], 0.5)]);
}

#[test]
fn without_a_reach_every_resampled_vertex_is_new() {
    let mesh = sphere();
    let (replacement, _, _) = resampled(&mesh);
    let record = replacement.record.clone();
    let (same, count) = replacement.continuing(&mesh, 0.0);
    assert_eq!(same.record, record);
    assert!(count.is_empty());
}

#[test]
fn which_vertices_continue_does_not_depend_on_the_records_order() {
    // Every vertex of a sphere re-sampled by a new vertex nudged outward by 0.01; new vertex v
    // reads old vertex v − v mod 2 above all, so two new vertices compete for each even old
    // vertex, and with a reach of a whole radius both stand within it: the nearer (its own) wins.
    let mesh = sphere();
    let mut surface = mesh.to_indexed();
    let first = mesh.next_id();
    let ids = surface.ids.as_mut().expect("a mesh has ids");
    let old = ids.clone();
    let n = old.len();
    for (v, id) in ids.iter_mut().enumerate() {
        *id = first + v as u64;
    }
    for p in &mut surface.positions {
        *p *= 1.01;
    }
    let created: Vec<Mutation> = (0..n)
        .map(|v| Mutation::PatchCreated {
            created: first + v as u64,
            sources: vec![(old[v - v % 2], 0.6), (old[(v + 1) % n], 0.4)],
        })
        .collect();
    let deleted: Vec<Mutation> = (0..n)
        .map(|v| Mutation::PatchDeleted {
            deleted: old[v],
            sources: vec![(first + v as u64, 1.0)],
        })
        .collect();
    let surface = Mesh::from_indexed(&surface).unwrap();
    let run = |reverse: bool| {
        let mut record: Vec<Mutation> = created.iter().chain(&deleted).cloned().collect();
        if reverse {
            record.reverse();
        }
        let replacement = Replacement {
            surface: surface.clone(),
            record,
        };
        let (continued, ids) = replacement.continuing(&mesh, 1.0);
        (
            continued.surface.to_indexed().ids.unwrap(),
            continued.record,
            ids,
        )
    };
    let (forward, backward) = (run(false), run(true));
    assert_eq!(forward.0, backward.0);
    assert_eq!(forward.2, backward.2);
    let expected: Vec<u64> = (0..n)
        .map(|v| if v % 2 == 0 { old[v] } else { first + v as u64 })
        .collect();
    assert_eq!(forward.0, expected);
    assert_eq!(forward.2.len(), n.div_ceil(2));
    // The odd new vertices stay new, and the odd old vertices are removed: 2 records each.
    assert_eq!(forward.1.len(), 2 * (n / 2));
    let mut mesh = mesh;
    let (replacement, _) = Replacement {
        surface,
        record: created.iter().chain(&deleted).cloned().collect(),
    }
    .continuing(&mesh.clone(), 1.0);
    mesh.replace(replacement).unwrap();
    EventList::drain(&mut mesh).check().unwrap();
}
