//! Components below the topology grid's resolution: a droplet only the tracked mesh has is
//! deleted, one only the target has is copied in, and data carried through the events stays
//! consistent (a constant channel stays constant both ways).

pub mod grid_support;

use glam::Vec3;
use grid_support::union;
use surftrack::compute::Backend;
use surftrack::events::{VertexValues, backward, forward};
use surftrack::mesh::{IndexedMesh, Mesh};
use surftrack::project::Bvh;
use surftrack::reconcile::{ReconcileCounts, reconcile_components};

fn constant(ids: &[u64]) -> VertexValues {
    VertexValues::from_parts(1, ids, &vec![0.25; ids.len()]).unwrap()
}

fn assert_constant(values: &VertexValues, ids: &[u64]) {
    assert_eq!(values.len(), ids.len());
    for &id in ids {
        assert_eq!(values.get(id), Some(&[0.25f32][..]), "vertex {id}");
    }
}

fn run(
    ours: &IndexedMesh,
    target: &IndexedMesh,
    spacing: f32,
) -> (Mesh, Mesh, ReconcileCounts, surftrack::events::EventList) {
    let before = Mesh::from_indexed(ours).unwrap();
    let mut mesh = before.clone();
    let bvh = Bvh::build(target).unwrap();
    let (events, counts) =
        reconcile_components(&Backend::Cpu, &mut mesh, target, &bvh, spacing).unwrap();
    (before, mesh, counts, events)
}

#[test]
fn droplets_below_the_grid_follow_the_target() {
    let body = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 3);
    let body_target = IndexedMesh::icosphere(Vec3::splat(0.01), 1.0, 4);
    let lost = IndexedMesh::icosphere(Vec3::new(3.0, 0.0, 0.0), 0.1, 1);
    let born = IndexedMesh::icosphere(Vec3::new(0.0, 3.0, 0.0), 0.1, 1);
    let ours = union(&[body.clone(), lost]);
    let target = union(&[body_target, born.clone()]);
    let (before, mesh, counts, events) = run(&ours, &target, 0.5);
    assert_eq!(
        counts,
        ReconcileCounts {
            deleted: 1,
            inserted: 1,
            replaced: 0
        }
    );
    let out = mesh.to_indexed();
    out.validate().unwrap();
    let topo: Vec<i64> = out.topology().components.iter().map(|c| c.euler).collect();
    assert_eq!(topo, vec![2, 2]);
    // The body is untouched (same ids, same positions) and the new droplet is the target's.
    let ids_before = before.to_indexed().ids.unwrap();
    let ids_after = out.ids.clone().unwrap();
    assert_eq!(
        &ids_after[..body.positions.len()],
        &ids_before[..body.positions.len()]
    );
    assert_eq!(&out.positions[..body.positions.len()], &body.positions[..]);
    assert_eq!(&out.positions[body.positions.len()..], &born.positions[..]);
    assert!(
        ids_after[body.positions.len()..]
            .iter()
            .all(|id| !ids_before.contains(id))
    );

    events.check().unwrap();
    let mut values = constant(&ids_before);
    forward(&events, &mut values).unwrap();
    assert_constant(&values, &ids_after);
    backward(&events, &mut values).unwrap();
    assert_constant(&values, &ids_before);
}

#[test]
fn a_matching_mesh_is_left_alone() {
    let ours = union(&[
        IndexedMesh::icosphere(Vec3::ZERO, 1.0, 3),
        IndexedMesh::icosphere(Vec3::new(2.0, 0.0, 0.0), 0.1, 1),
    ]);
    let target = union(&[
        IndexedMesh::icosphere(Vec3::splat(0.02), 1.0, 4),
        IndexedMesh::icosphere(Vec3::new(2.0, 0.01, 0.0), 0.1, 2),
    ]);
    let (before, mesh, counts, events) = run(&ours, &target, 0.5);
    assert_eq!(counts, ReconcileCounts::default());
    assert!(events.is_empty());
    assert_eq!(mesh.to_indexed(), before.to_indexed());
}

#[test]
fn a_small_component_with_another_topology_is_replaced() {
    let ours = union(&[
        IndexedMesh::icosphere(Vec3::ZERO, 1.0, 3),
        IndexedMesh::icosphere(Vec3::new(4.0, 0.0, 0.0), 0.35, 2),
    ]);
    let ring = IndexedMesh::torus(0.3, 0.1, 24, 8);
    let ring = IndexedMesh {
        positions: ring
            .positions
            .iter()
            .map(|p| *p + Vec3::new(4.0, 0.0, 0.0))
            .collect(),
        ..ring
    };
    let target = union(&[IndexedMesh::icosphere(Vec3::ZERO, 1.0, 4), ring]);
    let (_, mesh, counts, events) = run(&ours, &target, 0.5);
    assert_eq!(counts.replaced, 1);
    let out = mesh.to_indexed();
    out.validate().unwrap();
    let mut euler: Vec<i64> = out.topology().components.iter().map(|c| c.euler).collect();
    euler.sort_unstable();
    assert_eq!(euler, vec![0, 2]);
    events.check().unwrap();
}
