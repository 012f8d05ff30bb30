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
