//! The BVH's structure (every triangle in exactly one leaf, boxes nested, depth within the
//! traversal stacks even for adversarial inputs), the constants the kernels share with Rust, and
//! the errors for bad targets and queries.

#[path = "project_support/metaballs.rs"]
mod metaballs;

use glam::Vec3;
use metaballs::metaballs;
use naga::{Expression, Literal};
use surftrack::compute::Backend;
use surftrack::compute::ComputeError;
use surftrack::compute::SharedWgsl;
use surftrack::mesh::{IndexedMesh, MeshError};
use surftrack::project::{
    Bvh, BvhChild, BvhNode, Correspondence, ProjectError, ProjectOptions, Status, closest_points,
    project,
};

fn contains(outer: ([f32; 3], [f32; 3]), min: Vec3, max: Vec3) -> bool {
    Vec3::from_array(outer.0).cmple(min).all() && max.cmple(Vec3::from_array(outer.1)).all()
}

/// Walks the tree from the root, checking every node, every box and every slot.
fn check_structure(mesh: &IndexedMesh, bvh: &Bvh) {
    let nodes = bvh.nodes();
    let triangles = bvh.triangles();
    assert_eq!(triangles.len(), mesh.triangles.len());
    let mut slot_seen = vec![0u32; triangles.len()];
    let mut visited = 0usize;
    let mut pending = vec![0usize];
    while let Some(n) = pending.pop() {
        visited += 1;
        let node = &nodes[n];
        let children: Vec<_> = node.children().collect();
        assert!(!children.is_empty(), "node {n} has no children");
        assert!(
            n == 0 || children.len() >= 2,
            "interior node {n} has one child"
        );
        for (k, child) in children {
            let bounds = node.bounds(k);
            match child {
                BvhChild::Leaf { first, count } => {
                    assert!(
                        count as usize <= Bvh::MAX_LEAF_TRIANGLES,
                        "node {n}/{k}: {count}"
                    );
                    for slot in first..first + count {
                        slot_seen[slot as usize] += 1;
                        let corners = triangles[slot as usize].corners();
                        let min = corners[0].min(corners[1]).min(corners[2]);
                        let max = corners[0].max(corners[1]).max(corners[2]);
                        assert!(
                            contains(bounds, min, max),
                            "node {n}/{k} misses slot {slot}"
                        );
                    }
                }
                BvhChild::Node { index } => {
                    let index = index as usize;
                    assert!(index > n && index < nodes.len(), "node {n}/{k} -> {index}");
                    for (j, _) in nodes[index].children() {
                        let (min, max) = nodes[index].bounds(j);
                        let (min, max) = (Vec3::from_array(min), Vec3::from_array(max));
                        assert!(contains(bounds, min, max), "node {n}/{k} ⊉ {index}/{j}");
                    }
                    pending.push(index);
                }
            }
        }
    }
    assert_eq!(visited, nodes.len(), "every node is reachable exactly once");
    assert!(
        slot_seen.iter().all(|&k| k == 1),
        "every slot in exactly one leaf"
    );
    let mut ids: Vec<u32> = triangles.iter().map(|t| t.id).collect();
    ids.sort_unstable();
    assert!(
        ids.iter().enumerate().all(|(i, &id)| id == i as u32),
        "every triangle once"
    );
    for tri in triangles {
        let expected = mesh.triangles[tri.id as usize].map(|v| mesh.positions[v as usize]);
        assert_eq!(
            tri.corners(),
            expected,
            "slot of triangle {} keeps its corners",
            tri.id
        );
    }
    assert!(
        3 * (bvh.depth() + 1) <= Bvh::STACK_SIZE,
        "depth {}",
        bvh.depth()
    );
    assert_eq!(bvh.normals().len(), triangles.len());
    assert_eq!(bvh.pseudo_normals().len(), triangles.len());
}

#[test]
fn synthetic_frame_tree_is_well_formed() {
    let mesh = metaballs(60, 0.2, 0.1);
    let bvh = Bvh::build(&mesh).unwrap();
    check_structure(&mesh, &bvh);
    assert!(
        bvh.depth() < 30,
        "SAH depth {} on a 10k-triangle frame",
        bvh.depth()
    );
    let reference = mesh.mean_edge_length();
    assert!((bvh.mean_edge_length() - reference).abs() <= 1e-6 * reference);
}

/// A tree built without normals answers what the full one answers but signs and normals: the
/// same nearest triangles, points and weights, the same distances up to sign, the same scale.
#[test]
fn unsigned_tree_finds_what_the_full_one_finds() {
    let mesh = metaballs(40, 0.7, 0.3);
    let (full, unsigned) = (
        Bvh::build(&mesh).unwrap(),
        Bvh::build_unsigned(&mesh).unwrap(),
    );
    check_structure(&mesh, &unsigned);
    assert_eq!(unsigned.mean_edge_length(), full.mean_edge_length());
    let queries = metaballs(24, 1.9, 0.55).positions;
    let a = closest_points(&Backend::Cpu, &full, &queries, 3.0).unwrap();
    let b = closest_points(&Backend::Cpu, &unsigned, &queries, 3.0).unwrap();
    let mut hits = 0;
    for (a, b) in a.iter().zip(&b) {
        assert_eq!(a.hit_triangle(), b.hit_triangle());
        assert_eq!((a.point, a.barycentric), (b.point, b.barycentric));
        assert_eq!(a.distance.abs(), b.distance.abs());
        assert_eq!(b.normal, Vec3::ZERO);
        hits += usize::from(a.hit_triangle().is_some());
    }
    assert!(hits > queries.len() / 2, "{hits} of {} hit", queries.len());
}

#[test]
fn tiny_targets_work() {
    let positions = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z];
    for triangles in [vec![[0, 1, 2]], vec![[0, 1, 2], [0, 1, 3]]] {
        let mesh = IndexedMesh::new(positions.clone(), triangles);
        let bvh = Bvh::build(&mesh).unwrap();
        check_structure(&mesh, &bvh);
        assert_eq!(bvh.nodes().len(), 1, "one node holds up to four leaves");
        let found = project(
            &Backend::Cpu,
            &bvh,
            &[Vec3::new(0.2, 0.2, 1.0)],
            &[Vec3::Z],
            &ProjectOptions::default(),
        )
        .unwrap();
        assert_eq!(found[0].status(), Status::Accepted);
        assert_eq!(found[0].triangle, 0);
        assert!((found[0].distance + 1.0).abs() < 1e-6);
    }
}

/// Coincident centroids (no plane separates them) and sizes in geometric progression (which
/// drive SAH towards a list) still give a tree within the stack size.
#[test]
fn adversarial_inputs_stay_within_the_stack() {
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    for k in 0..3000u32 {
        let s = 1.0 + k as f32 * 1e-3;
        positions.extend([
            Vec3::new(-s, -s, 0.0),
            Vec3::new(s, -s, 0.0),
            Vec3::new(0.0, 2.0 * s, 0.0),
        ]);
        triangles.push([3 * k, 3 * k + 1, 3 * k + 2]);
    }
    let stacked = IndexedMesh::new(positions, triangles);
    let bvh = Bvh::build(&stacked).unwrap();
    check_structure(&stacked, &bvh);

    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    for k in 0..120u32 {
        let x = 0.8f32.powi(k as i32);
        positions.extend([
            Vec3::new(x, 0.0, 0.0),
            Vec3::new(x, 1.0, 0.0),
            Vec3::new(x, 0.0, 1.0),
        ]);
        triangles.push([3 * k, 3 * k + 1, 3 * k + 2]);
    }
    let geometric = IndexedMesh::new(positions, triangles);
    let bvh = Bvh::build(&geometric).unwrap();
    check_structure(&geometric, &bvh);
    let found = project(
        &Backend::Cpu,
        &bvh,
        &[Vec3::new(2.0, 0.2, 0.2)],
        &[Vec3::X],
        &ProjectOptions::default(),
    )
    .unwrap();
    assert_eq!(
        found[0].triangle, 0,
        "the plane at x = 1 is nearest to x = 2"
    );
}

fn wgsl_u32_constant(shared: &SharedWgsl, name: &str) -> u32 {
    let module = naga::front::wgsl::parse_str(shared.source).unwrap();
    let (_, constant) = module
        .constants
        .iter()
        .find(|(_, c)| c.name.as_deref() == Some(name))
        .unwrap_or_else(|| panic!("{}: no constant {name}", shared.path));
    match module.global_expressions[constant.init] {
        Expression::Literal(Literal::U32(value)) => value,
        ref other => panic!("{}: {name} is {other:?}", shared.path),
    }
}

#[test]
fn kernel_constants_match_rust() {
    let shared = SharedWgsl::BVH;
    assert_eq!(
        wgsl_u32_constant(&shared, "STACK_SIZE") as usize,
        Bvh::STACK_SIZE
    );
    assert_eq!(
        wgsl_u32_constant(&shared, "STATUS_MISS"),
        Status::Miss.code()
    );
    assert_eq!(
        wgsl_u32_constant(&shared, "STATUS_ACCEPTED"),
        Status::Accepted.code()
    );
    assert_eq!(
        wgsl_u32_constant(&shared, "STATUS_NORMAL_MISMATCH"),
        Status::NormalMismatch.code()
    );
    assert_eq!(
        wgsl_u32_constant(&shared, "NO_TRIANGLE"),
        Correspondence::NO_TRIANGLE
    );
    assert_eq!(wgsl_u32_constant(&shared, "EMPTY_CHILD"), BvhNode::EMPTY);
}

#[test]
fn bad_targets_are_named_errors() {
    let empty = IndexedMesh::new(vec![Vec3::ZERO], vec![]);
    assert_eq!(
        Bvh::build(&empty).unwrap_err(),
        ProjectError::Target(MeshError::Empty)
    );
    let nan = IndexedMesh::new(
        vec![Vec3::ZERO, Vec3::X, Vec3::new(0.0, f32::NAN, 0.0)],
        vec![[0, 1, 2]],
    );
    assert!(matches!(
        Bvh::build(&nan),
        Err(ProjectError::Target(MeshError::NonFiniteCoordinate {
            vertex: 2,
            ..
        }))
    ));
    let out_of_range = IndexedMesh::new(
        vec![Vec3::ZERO, Vec3::X, Vec3::Y],
        vec![[0, 1, 2], [0, 1, 5]],
    );
    assert_eq!(
        Bvh::build(&out_of_range).unwrap_err(),
        ProjectError::Target(MeshError::IndexOutOfRange {
            triangle: 1,
            vertex: 5,
            count: 3
        })
    );
}

#[test]
fn bad_queries_are_named_errors() {
    let bvh = Bvh::build(&IndexedMesh::icosphere(Vec3::ZERO, 1.0, 1)).unwrap();
    assert_eq!(
        project(
            &Backend::Cpu,
            &bvh,
            &[Vec3::ZERO; 3],
            &[Vec3::X; 2],
            &ProjectOptions::default()
        ),
        Err(ProjectError::LengthMismatch {
            points: 3,
            normals: 2
        })
    );
    let bad = ProjectOptions {
        max_angle_degrees: f32::NAN,
        ..Default::default()
    };
    assert!(matches!(
        project(&Backend::Cpu, &bvh, &[Vec3::ZERO], &[Vec3::X], &bad),
        Err(ProjectError::InvalidOption {
            name: "max_angle_degrees",
            ..
        })
    ));
    assert!(matches!(
        closest_points(&Backend::Cpu, &bvh, &[Vec3::ZERO], -1.0),
        Err(ProjectError::InvalidOption {
            name: "max_distance",
            ..
        })
    ));
    let message = ProjectError::Compute(ComputeError::NoAdapter).to_string();
    assert!(message.contains("no GPU adapter"), "{message}");
}
