//! Components below the topology grid's resolution: a droplet only the tracked mesh has is
//! deleted, one only the target has is copied in, and data carried through the events stays
//! consistent (a constant channel stays constant both ways).

pub mod grid_support;

use glam::{Vec2, Vec3};
use grid_support::union;
use surftrack::compute::Backend;
use surftrack::events::{VertexValues, backward, forward};
use surftrack::geometry::point_triangle::point_triangle_distance;
use surftrack::grid::{ScalarGrid, marching_cubes};
use surftrack::mesh::{IndexedMesh, Mesh};
use surftrack::project::Bvh;
use surftrack::topology::subgrid::{Fidelity, SubgridCounts, match_below_grid};
use surftrack::topology::{Carry, Moves};

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
) -> (Mesh, Mesh, SubgridCounts, surftrack::events::EventList) {
    run_with(ours, target, spacing, spacing, Fidelity::Input)
}

fn run_with(
    ours: &IndexedMesh,
    target: &IndexedMesh,
    spacing: f32,
    max_distance: f32,
    fidelity: Fidelity,
) -> (Mesh, Mesh, SubgridCounts, surftrack::events::EventList) {
    run_carrying(
        ours,
        target,
        (spacing, max_distance),
        (fidelity, Carry::Corner, 0.0, Moves::default()),
    )
}

/// Moves onto every removed vertex, as if all were carried from an earlier frame, with edges up
/// to two cells long.
fn every_carried(spacing: f32) -> Moves {
    Moves {
        carried_below: u64::MAX,
        longest_edge: 2.0 * spacing,
    }
}

fn run_carrying(
    ours: &IndexedMesh,
    target: &IndexedMesh,
    (spacing, max_distance): (f32, f32),
    policy: (Fidelity, Carry, f32, Moves),
) -> (Mesh, Mesh, SubgridCounts, surftrack::events::EventList) {
    let before = Mesh::from_indexed(ours).unwrap();
    let mut mesh = before.clone();
    mesh.record_mutations();
    let bvh = Bvh::build(target).unwrap();
    let counts = match_below_grid(
        &Backend::Cpu,
        &mut mesh,
        (target, &bvh),
        spacing,
        max_distance,
        policy,
    )
    .unwrap();
    let events = surftrack::events::EventList::drain(&mut mesh);
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
        SubgridCounts {
            deleted: 1,
            inserted: 1,
            replaced: 0,
            grafted: 0,
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
    assert_eq!(counts, SubgridCounts::default());
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

/// Each vertex's x coordinate as a one-channel value.
fn x_values(mesh: &Mesh) -> (Vec<u64>, VertexValues) {
    let out = mesh.to_indexed();
    let ids = out.ids.clone().unwrap();
    let xs: Vec<f32> = out.positions.iter().map(|p| p.x).collect();
    let values = VertexValues::from_parts(1, &ids, &xs).unwrap();
    (ids, values)
}

/// The distance from `p` to the triangle `t` of `mesh`.
fn triangle_distance(mesh: &IndexedMesh, t: &[u32; 3], p: Vec3) -> f32 {
    let [a, b, c] = t.map(|v| mesh.positions[v as usize]);
    point_triangle_distance(p, a, b, c)
}

/// The distance from `p` to the surface of `mesh`.
fn surface_distance(mesh: &IndexedMesh, p: Vec3) -> f32 {
    mesh.triangles
        .iter()
        .map(|t| triangle_distance(mesh, t, p))
        .fold(f32::INFINITY, f32::min)
}

/// Carries each vertex's x coordinate through `events` forward from `before` to `after`, then
/// each of `after`'s back, and checks each direction with `check` (the vertices, their source,
/// the values, the direction); returns `before`'s ids.
fn check_x_both_ways(
    (before, after): (&Mesh, &Mesh),
    events: &surftrack::events::EventList,
    check: fn(&Mesh, &Mesh, &VertexValues, &str),
) -> Vec<u64> {
    let (ids_before, mut values) = x_values(before);
    forward(events, &mut values).unwrap();
    check(after, before, &values, "forward");
    let (_, mut values) = x_values(after);
    backward(events, &mut values).unwrap();
    check(before, after, &values, "backward");
    ids_before
}

/// Checks that every vertex of `mesh` carries the x coordinate of a corner of the triangle of
/// `source` closest to it (of one of them, where several lie within rounding of the closest):
/// data is read on the surface at the closest point, not from whichever vertex lies nearest in
/// space, which may belong to a triangle farther away.
fn assert_closest_corner_x(mesh: &Mesh, source: &Mesh, values: &VertexValues, what: &str) {
    let (out, from) = (mesh.to_indexed(), source.to_indexed());
    let ids = out.ids.unwrap();
    assert_eq!(values.len(), ids.len(), "{what}");
    for (&id, p) in ids.iter().zip(&out.positions) {
        let closest = surface_distance(&from, *p);
        let value = values.get(id).unwrap()[0];
        let on_closest = from
            .triangles
            .iter()
            .filter(|t| triangle_distance(&from, t, *p) <= closest + 1e-5)
            .flatten()
            .any(|&v| from.positions[v as usize].x == value);
        assert!(
            on_closest || value == p.x,
            "{what}: vertex {id}: {value} is no corner's of the closest triangle"
        );
    }
}

#[test]
fn a_large_component_with_another_topology_is_replaced_and_keeps_its_data() {
    // A sphere the grid could not open into the input's ring: far larger than a small component.
    let ours = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 3);
    let target = IndexedMesh::torus(0.8, 0.3, 48, 16);

    let (_, kept, counts, events) = run_with(&ours, &target, 0.25, 0.25, Fidelity::Grid);
    assert_eq!(counts, SubgridCounts::default(), "grid fidelity keeps it");
    assert!(events.is_empty());
    assert_eq!(
        kept.to_indexed(),
        Mesh::from_indexed(&ours).unwrap().to_indexed()
    );

    let (before, mesh, counts, events) = run(&ours, &target, 0.25);
    assert_eq!(
        counts,
        SubgridCounts {
            deleted: 0,
            inserted: 0,
            replaced: 1,
            grafted: 0,
        }
    );
    let out = mesh.to_indexed();
    out.validate().unwrap();
    assert_eq!(out.positions, target.positions);
    assert_eq!(out.topology().components[0].euler, 0);
    events.check().unwrap();

    // Data follows the replacement: each copied vertex takes the value of the replaced surface's
    // closest triangle, at its corner nearest the closest point, and back.
    let ids_before = check_x_both_ways((&before, &mesh), &events, assert_closest_corner_x);
    let mut values = constant(&ids_before);
    forward(&events, &mut values).unwrap();
    assert_constant(&values, out.ids.as_deref().unwrap());
}

#[test]
fn a_replaced_component_blends_its_data_when_asked() {
    let ours = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 3);
    let target = IndexedMesh::torus(0.8, 0.3, 48, 16);
    let policy = (Fidelity::Input, Carry::Blend, 0.0, Moves::default());
    let (before, mesh, counts, events) = run_carrying(&ours, &target, (0.25, 0.25), policy);
    assert_eq!(counts.replaced, 1);
    events.check().unwrap();
    // x is linear on a triangle: the blend at the closest point gives that point's x, within
    // the distance to the surface read. Taking a corner whole misses by up to the distance to
    // that corner, which this bound catches.
    let ids_before = check_x_both_ways((&before, &mesh), &events, assert_blended_x);
    // A constant stays constant, up to the rounding of the blend.
    let mut values = constant(&ids_before);
    forward(&events, &mut values).unwrap();
    let ids = mesh.to_indexed().ids.unwrap();
    assert_eq!(values.len(), ids.len());
    for id in ids {
        let value = values.get(id).map(|v| v[0]);
        assert!(
            value.is_some_and(|v| (v - 0.25).abs() <= 1e-6),
            "{id}: {value:?}"
        );
    }
}

#[test]
fn a_copied_vertex_standing_on_the_vertex_it_reads_continues_it() {
    let ours = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 3);
    let target = IndexedMesh::torus(0.8, 0.3, 48, 16);
    let (spacing, reach) = (0.25, 0.25);
    let policy = (
        Fidelity::Input,
        Carry::Corner,
        reach,
        every_carried(spacing),
    );
    let (before, mesh, counts, events) = run_carrying(&ours, &target, (spacing, spacing), policy);
    assert_eq!(counts.replaced, 1);
    events.check().unwrap();
    let out = mesh.to_indexed();
    out.validate().unwrap();
    assert_eq!(
        out.triangles, target.triangles,
        "the copy's connectivity is the input's"
    );
    // Some copied vertices stand within a quarter cell of the sphere vertex they read, or were
    // moved onto one: those vertices go on there, each at most that far from where it stood.
    let old = before.to_indexed();
    let was: std::collections::HashMap<u64, Vec3> =
        old.ids.unwrap().into_iter().zip(old.positions).collect();
    let moved: Vec<f32> = out
        .ids
        .as_ref()
        .unwrap()
        .iter()
        .zip(&out.positions)
        .filter_map(|(id, p)| was.get(id).map(|q| q.distance(*p)))
        .collect();
    assert!(moved.len() >= 10, "{} continued", moved.len());
    assert!(moved.len() < was.len());
    assert!(
        moved.iter().all(|&d| d <= reach * spacing + 1e-6),
        "{moved:?}"
    );
    // Every other vertex stands where the input's does; a moved one stands on the sphere vertex
    // it continues, within a tenth of a cell of the input's surface.
    for ((id, p), q) in out
        .ids
        .as_ref()
        .unwrap()
        .iter()
        .zip(&out.positions)
        .zip(&target.positions)
    {
        if p != q {
            assert_eq!(
                was.get(id),
                Some(p),
                "{id} moved, yet not onto a vertex it continues"
            );
            assert!(
                surface_distance(&target, *p) <= 0.1 * spacing + 1e-6,
                "{id} at {p}"
            );
        }
    }
    // They keep their values, which are what the copy would have read: a corner of the closest
    // triangle, both ways.
    let ids_before = check_x_both_ways((&before, &mesh), &events, assert_closest_corner_x);
    let mut values = constant(&ids_before);
    forward(&events, &mut values).unwrap();
    assert_constant(&values, out.ids.as_deref().unwrap());
    // Without a reach every vertex of the copy is new, and stands where the input's does.
    let policy = (Fidelity::Input, Carry::Corner, 0.0, every_carried(spacing));
    let (_, mesh, _, _) = run_carrying(&ours, &target, (spacing, spacing), policy);
    let out = mesh.to_indexed();
    assert!(out.ids.unwrap().iter().all(|id| !was.contains_key(id)));
    assert_eq!(out.positions, target.positions);
}

/// Checks that every vertex of `mesh` carries the x coordinate of the point of `source` closest
/// to it, within its distance to `source`'s surface.
fn assert_blended_x(mesh: &Mesh, source: &Mesh, values: &VertexValues, what: &str) {
    let (out, from) = (mesh.to_indexed(), source.to_indexed());
    let ids = out.ids.unwrap();
    assert_eq!(values.len(), ids.len(), "{what}");
    for (&id, p) in ids.iter().zip(&out.positions) {
        let closest = surface_distance(&from, *p);
        let error = (values.get(id).unwrap()[0] - p.x).abs();
        assert!(
            error <= closest + 1e-5,
            "{what}: vertex {id}: {error} > {closest}"
        );
    }
}

#[test]
fn a_component_farther_than_the_bound_is_replaced() {
    let ours = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 3);
    let target = IndexedMesh::icosphere(Vec3::ZERO, 1.3, 3);
    let (_, _, counts, _) = run_with(&ours, &target, 0.5, 0.4, Fidelity::Input);
    assert_eq!(counts, SubgridCounts::default(), "0.3 apart, bound 0.4");
    let (_, mesh, counts, events) = run_with(&ours, &target, 0.5, 0.2, Fidelity::Input);
    assert_eq!(counts.replaced, 1, "0.3 apart, bound 0.2");
    assert_eq!(mesh.to_indexed().positions, target.positions);
    events.check().unwrap();
    let (_, _, counts, _) = run_with(&ours, &target, 0.5, 0.2, Fidelity::Grid);
    assert_eq!(
        counts,
        SubgridCounts::default(),
        "grid fidelity ignores the bound"
    );
}

/// The tracked unit sphere, and the input: the same sphere with a smooth bump 0.4 high within 25°
/// of +z, farther than the bound of 0.15 used with it.
/// What a match that grafts one component and touches nothing else reports.
const GRAFTED_ONCE: SubgridCounts = SubgridCounts {
    deleted: 0,
    inserted: 0,
    replaced: 0,
    grafted: 1,
};

fn sphere_and_bump() -> (IndexedMesh, IndexedMesh) {
    let sphere = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 4);
    let (height, edge) = (0.4, 25f32.to_radians().cos());
    let bumped = IndexedMesh {
        positions: sphere
            .positions
            .iter()
            .map(|p| {
                let t = ((p.normalize().z - edge) / (1.0 - edge)).max(0.0);
                *p * (1.0 + height * t * t)
            })
            .collect(),
        ..sphere.clone()
    };
    (sphere, bumped)
}

#[test]
fn a_local_difference_is_grafted_and_the_rest_keeps_its_vertices() {
    // The input has a bump the tracked sphere lacks, farther than the bound: only the cells
    // around it take the input's triangles.
    let (ours, target) = sphere_and_bump();
    let (before, mesh, counts, events) = run_with(&ours, &target, 0.25, 0.15, Fidelity::Input);
    assert_eq!(counts, GRAFTED_ONCE);
    let out = mesh.to_indexed();
    out.validate().unwrap();
    let topology = out.topology();
    assert_eq!(topology.components.len(), 1);
    assert_eq!(topology.euler(), 2);

    // Most of the sphere keeps its vertices, ids and positions.
    let ids_before = before.to_indexed().ids.unwrap();
    let ids_after = out.ids.clone().unwrap();
    let kept = ids_before
        .iter()
        .filter(|id| ids_after.contains(id))
        .count();
    assert!(
        kept * 10 > ids_before.len() * 8,
        "{kept} of {} vertices kept",
        ids_before.len()
    );
    for (id, p) in ids_after.iter().zip(&out.positions) {
        if let Some(v) = ids_before.iter().position(|b| b == id) {
            assert_eq!(*p, ours.positions[v]);
        }
    }

    // Within the bound of the input both ways, at every vertex.
    let near = |from: &IndexedMesh, to: &IndexedMesh| {
        let bvh = Bvh::build(to).unwrap();
        surftrack::project::closest_points(&Backend::Cpu, &bvh, &from.positions, f32::INFINITY)
            .unwrap()
            .iter()
            .map(|hit| hit.distance.abs())
            .fold(0.0f32, f32::max)
    };
    assert!(near(&out, &target) <= 0.15, "{}", near(&out, &target));
    assert!(near(&target, &out) <= 0.15, "{}", near(&target, &out));

    events.check().unwrap();
    let mut values = constant(&ids_before);
    forward(&events, &mut values).unwrap();
    assert_constant(&values, &ids_after);
    backward(&events, &mut values).unwrap();
    assert_constant(&values, &ids_before);
    let (_, mut values) = x_values(&before);
    forward(&events, &mut values).unwrap();
    assert_closest_corner_x(&mesh, &before, &values, "forward");
}

#[test]
fn a_graft_moves_copied_vertices_onto_the_tracked_ones_it_removes() {
    // The input is the tracked sphere sampled otherwise (turned), with a bump farther than the
    // bound. The graft's region reaches cells beyond the bump, where the tracked vertices lie
    // on the input: there the copied vertices nearest them move onto them and continue them,
    // though few stand within the continue reach (a tenth of a cell) of one.
    let (ours, bumped) = sphere_and_bump();
    let turn = glam::Quat::from_rotation_z(0.05) * glam::Quat::from_rotation_x(0.03);
    let target = IndexedMesh {
        positions: bumped.positions.iter().map(|&p| turn * p).collect(),
        ..bumped
    };
    let spacing = 0.25;
    let graft = |reach: f32| {
        let policy = (
            Fidelity::Input,
            Carry::Corner,
            reach,
            every_carried(spacing),
        );
        run_carrying(&ours, &target, (spacing, 0.15), policy)
    };
    let (before, unmoved, counts, _) = graft(0.0);
    assert_eq!(counts, GRAFTED_ONCE);
    let (_, moved, counts, events) = graft(0.1);
    assert_eq!(counts, GRAFTED_ONCE);
    let out = moved.to_indexed();
    out.validate().unwrap();
    assert_eq!(out.topology().euler(), 2);
    events.check().unwrap();
    let (lost_unmoved, lost_moved) = (
        1.0 - kept_share(&before, &unmoved),
        1.0 - kept_share(&before, &moved),
    );
    assert!(
        lost_moved < 0.5 * lost_unmoved,
        "lost {lost_moved} of the vertices, {lost_unmoved} without moving or continuing"
    );
    // A vertex that goes on stands where it stood, or within the continue reach of it, and
    // every vertex lies within the bound of the input.
    let old = before.to_indexed();
    let was: std::collections::HashMap<u64, Vec3> =
        old.ids.unwrap().into_iter().zip(old.positions).collect();
    for (id, p) in out.ids.as_ref().unwrap().iter().zip(&out.positions) {
        if let Some(q) = was.get(id) {
            assert!(q.distance(*p) <= 0.1 * spacing + 1e-6, "{id}: {q} to {p}");
        }
        assert!(surface_distance(&target, *p) <= 0.15, "{id} at {p}");
    }
    let ids_before = check_x_both_ways((&before, &moved), &events, assert_closest_corner_x);
    let mut values = constant(&ids_before);
    forward(&events, &mut values).unwrap();
    assert_constant(&values, out.ids.as_deref().unwrap());
}

#[test]
fn a_difference_smaller_than_the_inputs_triangles_is_grafted() {
    // The input is a coarse polyhedron; the tracked surface is the same polyhedron sampled 64
    // times finer, with one vertex pulled out into a spike farther than the bound. The cells
    // around the spike hold no whole input triangle: the region grows until they do, and the
    // spike is grafted away instead of the whole body being replaced.
    let target = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 1);
    let mut ours = target.split_flat(3);
    let tip = ours
        .positions
        .iter()
        .position(|p| p.z > 0.0 && (p.x.abs() + p.y.abs()) > 0.2)
        .unwrap();
    ours.positions[tip] *= 1.25;
    let (before, mesh, counts, _) = run_with(&ours, &target, 0.25, 0.15, Fidelity::Input);
    assert_eq!(counts, GRAFTED_ONCE);
    let out = mesh.to_indexed();
    out.validate().unwrap();
    assert_eq!(out.topology().euler(), 2);
    assert!(!out.positions.contains(&ours.positions[tip]));
    assert!(
        kept_share(&before, &mesh) > 0.5,
        "{}",
        kept_share(&before, &mesh)
    );
}

#[test]
fn whole_input_fidelity_replaces_instead_of_grafting() {
    let (ours, target) = sphere_and_bump();
    let (_, mesh, counts, events) = run_with(&ours, &target, 0.25, 0.15, Fidelity::InputWhole);
    assert_eq!(
        counts,
        SubgridCounts {
            deleted: 0,
            inserted: 0,
            replaced: 1,
            grafted: 0,
        }
    );
    assert_eq!(mesh.to_indexed().positions, target.positions);
    events.check().unwrap();
}

/// The surface of `field` (negative inside) sampled on a grid of `spacing` from `origin` over
/// `cells` cells per side.
fn surface_of(
    field: impl Fn(Vec3) -> f32 + Sync,
    origin: Vec3,
    spacing: f32,
    cells: usize,
) -> IndexedMesh {
    let grid = ScalarGrid::from_fn(origin, spacing, [cells + 1; 3], field).unwrap();
    marching_cubes(&grid, 0.0)
}

/// Share of the vertices of `before` whose id is still in `after`.
fn kept_share(before: &Mesh, after: &Mesh) -> f64 {
    let ids_before = before.to_indexed().ids.unwrap();
    let ids_after: std::collections::HashSet<u64> =
        after.to_indexed().ids.unwrap().into_iter().collect();
    let kept = ids_before
        .iter()
        .filter(|id| ids_after.contains(id))
        .count();
    kept as f64 / ids_before.len() as f64
}

#[test]
fn ripples_within_the_bound_do_not_grow_a_graft() {
    // The input is the bumped sphere with ripples everywhere, a few hundredths high: the grid
    // edges the ripples graze are crossed differently by the two surfaces, but replacing the
    // tracked surface there changes no topology, so only the bump is grafted.
    let (ours, bumped) = sphere_and_bump();
    let rippled = IndexedMesh {
        positions: bumped
            .positions
            .iter()
            .map(|p| {
                let n = p.normalize();
                *p + n * 0.03 * (17.0 * n.x).sin() * (19.0 * n.y).sin() * (13.0 * n.z).cos()
            })
            .collect(),
        ..bumped
    };
    let (before, mesh, counts, _) = run_with(&ours, &rippled, 0.25, 0.15, Fidelity::Input);
    assert_eq!(counts.grafted, 1, "{counts:?}");
    assert_eq!(counts.replaced, 0, "{counts:?}");
    let out = mesh.to_indexed();
    out.validate().unwrap();
    assert_eq!(out.topology().euler(), 2);
    let kept = kept_share(&before, &mesh);
    assert!(kept > 0.8, "{:.1}% of the vertices kept", 100.0 * kept);
}

/// A sheet 0.12 thick (about half a topology cell of 0.25) over the unit square, its rim rounded,
/// with a hole of radius `hole` through its middle (none when 0), meshed on a grid shifted by
/// `shift` so that two sheets never share a triangulation.
fn sheet(hole: f32, shift: f32) -> IndexedMesh {
    sheet_at(hole, Vec2::ZERO, 0.0, Vec3::splat(-1.25 + shift))
}

/// The sheet of [`sheet`] centred at height `z`, its hole centred at `centre`, meshed from
/// `origin`.
fn sheet_at(hole: f32, centre: Vec2, z: f32, origin: Vec3) -> IndexedMesh {
    let field = move |p: Vec3| {
        let q = Vec3::new(p.x.abs() - 1.0, p.y.abs() - 1.0, (p.z - z).abs() - 0.06);
        let slab = q.max(Vec3::ZERO).length() + q.max_element().min(0.0);
        let tube = hole - (Vec2::new(p.x, p.y) - centre).length();
        if hole > 0.0 { slab.max(tube) } else { slab }
    };
    surface_of(field, origin, 0.04, 63)
}

#[test]
fn a_tunnel_through_a_sheet_thinner_than_a_cell_is_grafted() {
    // The input's sheet has a hole narrower than a topology cell that the tracked sheet lacks;
    // every sample of either lies within the bound of the other, so only the topology tells
    // them apart. The graft punches the hole and keeps part of the sheet: the sheet's two sides
    // lie within one cell, so the region grows over much of it before the rims pair up.
    let ours = sheet(0.0, 0.013);
    let target = sheet(0.16, 0.0);
    assert_eq!(ours.topology().euler(), 2);
    assert_eq!(target.topology().euler(), 0);
    assert_grafted_into_one_body(&ours, &target, 0.1);
}

/// A sheet as in [`sheet`] but lying between the topology grid's planes z = 0 and z = 0.25, with
/// a hole of radius `hole` (none when 0) centred in the column of the cell at the origin, away
/// from every grid edge.
fn sheet_between_planes(hole: f32, shift: f32) -> IndexedMesh {
    sheet_at(
        hole,
        Vec2::splat(0.125),
        0.125,
        Vec3::new(-1.25, -1.25, -1.125) + shift,
    )
}

#[test]
fn a_hole_no_grid_edge_meets_is_found_below_the_bound() {
    // The input's sheet has a hole of radius 0.12 that the tracked sheet lacks. No grid edge of
    // the topology grid (0.25) passes through the hole, and the sheet lies between two grid
    // planes, so both sheets cross every grid edge alike; every sample of either lies within the
    // bound (0.25) of the other. Only the tracked sheet's samples over the hole, up to 0.12 from
    // its rim, tell where the difference is: the graft looks for them below the bound and keeps
    // most of the sheet instead of replacing it.
    let ours = sheet_between_planes(0.0, 0.013);
    let target = sheet_between_planes(0.12, 0.0);
    assert_eq!(ours.topology().euler(), 2);
    assert_eq!(target.topology().euler(), 0);
    assert_grafted_into_one_body(&ours, &target, 0.5);
}

#[test]
fn a_bridge_thinner_than_a_cell_is_grafted_between_two_bodies() {
    // The input joins two balls by a strand 0.1 wide, below the topology cell of 0.25; the
    // tracked balls are apart. Both tracked components lie on the one input component, so the
    // graft takes the strand and its ends from the input and joins the two balls into one body
    // of the input's Euler characteristic, keeping most of their vertices.
    let balls = |p: Vec3| {
        let a = (p - Vec3::new(-0.55, 0.0, 0.0)).length() - 0.45;
        let b = (p - Vec3::new(0.55, 0.0, 0.0)).length() - 0.45;
        a.min(b)
    };
    let strand = move |p: Vec3| {
        let tube = Vec2::new(p.y, p.z).length() - 0.05;
        balls(p).min(tube.max(p.x.abs() - 0.6))
    };
    let ours = surface_of(balls, Vec3::new(-1.25, -0.75, -0.75), 0.04, 63);
    let target = surface_of(strand, Vec3::new(-1.237, -0.763, -0.741), 0.04, 63);
    assert_eq!(ours.topology().components.len(), 2);
    assert_eq!(target.topology().components.len(), 1);
    assert_grafted_into_one_body(&ours, &target, 0.5);
}

/// Matches `ours` to `target` (one component) on a grid of 0.25 with a bound of 0.25, and checks
/// that one graft, no replacement, gives one valid body of the target's Euler characteristic that
/// keeps more than `kept` of the vertices, with valid events.
fn assert_grafted_into_one_body(ours: &IndexedMesh, target: &IndexedMesh, kept: f64) {
    let (before, mesh, counts, events) = run_with(ours, target, 0.25, 0.25, Fidelity::Input);
    assert_eq!(counts.grafted, 1, "{counts:?}");
    assert_eq!(counts.replaced, 0, "{counts:?}");
    let out = mesh.to_indexed();
    out.validate().unwrap();
    let topology = out.topology();
    assert_eq!(topology.components.len(), 1);
    assert_eq!(topology.euler(), target.topology().euler());
    let share = kept_share(&before, &mesh);
    assert!(share > kept, "{:.1}% of the vertices kept", 100.0 * share);
    events.check().unwrap();
}
