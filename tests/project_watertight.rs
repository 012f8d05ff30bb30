//! Watertightness: lines aimed exactly at the vertices and edge midpoints of closed meshes, in
//! directions that cross the surface there, always hit it there (no false miss), on both
//! backends and with the single-ray query. Axis-aligned lines pass through a vertex exactly and
//! lie in the planes of box faces, the hardest case for both the triangle and the box tests.

#[path = "project_support/backends.rs"]
mod backends;
#[path = "project_support/metaballs.rs"]
mod metaballs;
#[path = "project_support/rng.rs"]
mod rng;

use std::collections::HashMap;

use glam::{DVec3, Vec3};
use metaballs::metaballs;
use rng::Rng;
use surftrack::compute::Backend;
use surftrack::mesh::IndexedMesh;
use surftrack::project::{Bvh, ProjectOptions, Status, project};

/// A closed cube surface of side 2 about the origin, `n × n` quads per side, welded: its faces
/// lie in coordinate planes, so axis-aligned lines run along box faces.
fn cube(n: usize) -> IndexedMesh {
    let mut index = HashMap::new();
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    let mut vertex = |p: [i64; 3]| -> u32 {
        *index.entry(p).or_insert_with(|| {
            positions
                .push(Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32) * (2.0 / n as f32) - 1.0);
            positions.len() as u32 - 1
        })
    };
    let n = n as i64;
    for axis in 0..3 {
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        for (level, outward) in [(0, false), (n, true)] {
            for i in 0..n {
                for j in 0..n {
                    let corner = |di: i64, dj: i64| {
                        let mut p = [0; 3];
                        p[axis] = level;
                        p[u] = i + di;
                        p[v] = j + dj;
                        p
                    };
                    let q =
                        [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)].map(&mut vertex);
                    if outward {
                        triangles.push([q[0], q[1], q[2]]);
                        triangles.push([q[0], q[2], q[3]]);
                    } else {
                        triangles.push([q[0], q[2], q[1]]);
                        triangles.push([q[0], q[3], q[2]]);
                    }
                }
            }
        }
    }
    IndexedMesh::new(positions, triangles)
}

/// A point on the surface and the unit normals of the triangles that hold it.
struct Target {
    point: Vec3,
    normals: Vec<DVec3>,
}

/// Every vertex and every edge midpoint of `mesh`.
fn targets(mesh: &IndexedMesh) -> Vec<Target> {
    let face_normal = |t: usize| {
        let [a, b, c] = mesh.triangles[t].map(|v| mesh.positions[v as usize].as_dvec3());
        (b - a).cross(c - a).normalize()
    };
    let mut at_vertex: Vec<Vec<DVec3>> = vec![Vec::new(); mesh.positions.len()];
    let mut at_edge: HashMap<(u32, u32), Vec<DVec3>> = HashMap::new();
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let n = face_normal(t);
        for k in 0..3 {
            at_vertex[tri[k] as usize].push(n);
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            at_edge.entry((a.min(b), a.max(b))).or_default().push(n);
        }
    }
    let mut targets: Vec<Target> = mesh
        .positions
        .iter()
        .zip(at_vertex)
        .map(|(&point, normals)| Target { point, normals })
        .collect();
    let mut edges: Vec<_> = at_edge.into_iter().collect();
    edges.sort_by_key(|e| e.0);
    for ((a, b), normals) in edges {
        let (pa, pb) = (mesh.positions[a as usize], mesh.positions[b as usize]);
        targets.push(Target {
            point: pa + (pb - pa) * 0.5,
            normals,
        });
    }
    targets
}

/// Directions that cross the surface at `target`: on the outer side of every triangle there.
/// The first is the coordinate axis most aligned with the normal, when it crosses; then random
/// ones inside the normal cone.
fn crossing_directions(target: &Target, rng: &mut Rng, count: usize) -> Vec<Vec3> {
    let crosses = |d: Vec3| target.normals.iter().all(|n| n.dot(d.as_dvec3()) > 0.05);
    let mean: DVec3 = target.normals.iter().sum::<DVec3>().normalize();
    let mut directions = Vec::new();
    let axis = Vec3::from_array(std::array::from_fn(|k| {
        let strongest = (0..3).max_by(|&i, &j| mean[i].abs().total_cmp(&mean[j].abs()));
        if strongest == Some(k) {
            mean[k].signum() as f32
        } else {
            0.0
        }
    }));
    if crosses(axis) {
        directions.push(axis);
    }
    let mut tries = 0;
    while directions.len() < count && tries < 100 * count {
        tries += 1;
        let d = (mean.as_vec3() + rng.direction() * 0.7).normalize();
        if crosses(d) {
            directions.push(d);
        }
    }
    directions
}

/// Lines from just outside each target, along directions crossing the surface there, through
/// the target: the nearest hit is the target itself, at `t = −offset`.
fn lines_through_vertices_and_edges_never_slip_through(
    backend: &Backend,
    mesh: &IndexedMesh,
    seed: u64,
) {
    let bvh = Bvh::build(mesh).unwrap();
    let offset = 0.25 * bvh.mean_edge_length();
    let mut rng = Rng(seed);
    let mut points = Vec::new();
    let mut normals = Vec::new();
    let mut aimed_at = Vec::new();
    let targets = targets(mesh);
    for target in &targets {
        for d in crossing_directions(target, &mut rng, 3) {
            points.push(target.point + d * offset);
            normals.push(d);
            aimed_at.push(target.point);
        }
    }
    assert!(
        points.len() >= 2 * targets.len(),
        "too few crossing directions"
    );
    let found = project(backend, &bvh, &points, &normals, &ProjectOptions::default()).unwrap();
    let tolerance = 1e-4 * bvh.mean_edge_length();
    let mut slipped = Vec::new();
    for (i, c) in found.iter().enumerate() {
        let on_target = c.status() != Status::Miss
            && c.point.distance(aimed_at[i]) < tolerance
            && (c.distance + offset).abs() < tolerance;
        if !on_target {
            slipped.push(format!(
                "  [{i}] aimed at {} from {} along {}: {:?} t = {} at {}",
                aimed_at[i],
                points[i],
                normals[i],
                c.status(),
                c.distance,
                c.point
            ));
        }
        if backend.gpu().is_none() {
            let ray = bvh.cast_ray(points[i], -normals[i], f32::INFINITY);
            let ray_ok = ray.is_some_and(|r| r.point.distance(aimed_at[i]) < tolerance);
            if !ray_ok {
                slipped.push(format!(
                    "  [{i}] cast_ray aimed at {}: {ray:?}",
                    aimed_at[i]
                ));
            }
        }
    }
    eprintln!(
        "{} lines through {} vertices and edge midpoints ({}): {} slipped through",
        points.len(),
        targets.len(),
        if backend.gpu().is_none() {
            "cpu"
        } else {
            "gpu"
        },
        slipped.len()
    );
    assert!(
        slipped.is_empty(),
        "{} of {} lines slipped through:\n{}",
        slipped.len(),
        points.len(),
        slipped.join("\n")
    );
}

fn sphere(backend: &Backend) {
    lines_through_vertices_and_edges_never_slip_through(
        backend,
        &IndexedMesh::icosphere(Vec3::new(0.1, 0.0, -0.2), 1.0, 3),
        1,
    );
}

fn torus(backend: &Backend) {
    lines_through_vertices_and_edges_never_slip_through(
        backend,
        &IndexedMesh::torus(1.0, 0.4, 48, 16),
        2,
    );
}

fn axis_aligned_cube(backend: &Backend) {
    lines_through_vertices_and_edges_never_slip_through(backend, &cube(8), 3);
}

fn marching_cubes_frame(backend: &Backend) {
    lines_through_vertices_and_edges_never_slip_through(backend, &metaballs(40, 0.5, 0.25), 4);
}

#[test]
fn cube_is_closed_and_manifold() {
    let mesh = cube(8);
    mesh.validate().unwrap();
    assert_eq!(mesh.topology().total_genus(), 0);
    assert!(mesh.signed_volume() > 0.0, "outward winding");
}

on_both_backends! {
    sphere => sphere_cpu, sphere_gpu;
    torus => torus_cpu, torus_gpu;
    axis_aligned_cube => axis_aligned_cube_cpu, axis_aligned_cube_gpu;
    marching_cubes_frame => marching_cubes_frame_cpu, marching_cubes_frame_gpu;
}
