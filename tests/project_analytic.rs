//! Projection and closest points against analytic answers, on both backends: concentric spheres,
//! a plane, a torus; misses; pruning by angle and distance on either side of the thresholds.

#[path = "project_support/backends.rs"]
mod backends;
#[path = "project_support/reference.rs"]
mod reference;
#[path = "project_support/rng.rs"]
mod rng;

use glam::Vec3;
use reference::{closest_on_triangle_f64, distance_f64, line_plane_f64};
use rng::Rng;
use surftrack::compute::Backend;
use surftrack::mesh::IndexedMesh;
use surftrack::project::{Bvh, Correspondence, ProjectOptions, Status, closest_points, project};

fn run(
    backend: &Backend,
    bvh: &Bvh,
    points: &[Vec3],
    normals: &[Vec3],
    options: &ProjectOptions,
) -> Vec<Correspondence> {
    project(backend, bvh, points, normals, options)
        .unwrap_or_else(|e| panic!("project on {backend}: {e}"))
}

/// The hit point lies on its triangle: the barycentric blend of the corners, weights in [0, 1].
fn assert_on_triangle(mesh: &IndexedMesh, c: &Correspondence, tol: f32, what: &str) {
    let tri = mesh.triangles[c.triangle as usize].map(|v| mesh.positions[v as usize]);
    let w = c.barycentric;
    assert!(
        w.min_element() >= 0.0 && (w.element_sum() - 1.0).abs() < 1e-5,
        "{what}: weights {w}"
    );
    let blend = tri[0] * w.x + tri[1] * w.y + tri[2] * w.z;
    assert!(
        blend.distance(c.point) < tol,
        "{what}: point {} but weights give {blend}",
        c.point
    );
}

/// Points on spheres of radius 0.5 and 2 about the centre of a unit icosphere, with radial
/// normals, land on the radial line through them, on the plane of the hit triangle (f64
/// reference); points on the target's vertex directions land exactly on those vertices.
fn concentric_spheres_land_on_the_radial_point(backend: &Backend) {
    let center = Vec3::new(0.3, -0.2, 0.1);
    let mesh = IndexedMesh::icosphere(center, 1.0, 4);
    let bvh = Bvh::build(&mesh).unwrap();
    let mut rng = Rng(7);
    let mut directions: Vec<Vec3> = (0..2000).map(|_| rng.direction()).collect();
    let vertex_directions: Vec<Vec3> = mesh
        .positions
        .iter()
        .map(|&p| (p - center).normalize())
        .collect();
    directions.extend(&vertex_directions);
    for (radius, expected_t) in [(0.5f32, 0.5f32), (2.0, -1.0)] {
        let points: Vec<Vec3> = directions.iter().map(|&d| center + d * radius).collect();
        let found = run(
            backend,
            &bvh,
            &points,
            &directions,
            &ProjectOptions::default(),
        );
        for (i, (c, (&p, &d))) in found.iter().zip(points.iter().zip(&directions)).enumerate() {
            let what = format!("radius {radius}, query {i}");
            assert_eq!(c.status(), Status::Accepted, "{what}: {c:?}");
            let exact = line_plane_f64(&mesh, c.triangle, p, d);
            let error = exact.distance(c.point.as_dvec3());
            assert!(
                error < 1e-5,
                "{what}: {} is {error:e} from the radial point {exact}",
                c.point
            );
            assert!(
                (c.distance - expected_t).abs() < 0.01,
                "{what}: t = {} (expected about {expected_t})",
                c.distance
            );
            assert!(
                c.point.distance(p + d * c.distance) < 1e-6,
                "{what}: point is not p + t·n"
            );
            assert!(
                c.normal.dot(d) > 0.999,
                "{what}: normal {} vs radial {d}",
                c.normal
            );
            assert_on_triangle(&mesh, c, 1e-5, &what);
            if i >= 2000 {
                let v = mesh.positions[i - 2000];
                assert!(
                    c.point.distance(v) < 1e-5,
                    "{what}: vertex {v}, hit {}",
                    c.point
                );
                assert!(
                    c.normal.dot(d) > 1.0 - 1e-6,
                    "{what}: normal at a vertex is radial"
                );
            }
        }
    }
}

/// A flat grid at z = 0.5: vertical rays land at (x, y, 0.5) with t = 0.5 − z; tilted rays at
/// t = (0.5 − z) / cos θ; the angle threshold splits 59.9° from 60.1°.
fn plane_hits_and_angle_threshold(backend: &Backend) {
    let n = 20;
    let mut positions = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            positions.push(Vec3::new(
                -1.0 + 2.0 * i as f32 / n as f32,
                -1.0 + 2.0 * j as f32 / n as f32,
                0.5,
            ));
        }
    }
    let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut triangles = Vec::new();
    for j in 0..n {
        for i in 0..n {
            triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let mesh = IndexedMesh::new(positions, triangles);
    let bvh = Bvh::build(&mesh).unwrap();
    let mut rng = Rng(11);
    let points: Vec<Vec3> = (0..1000)
        .map(|_| {
            Vec3::new(
                rng.range(-0.5, 0.5),
                rng.range(-0.5, 0.5),
                rng.range(-1.0, 2.0),
            )
        })
        .collect();
    let up = vec![Vec3::Z; points.len()];
    let found = run(backend, &bvh, &points, &up, &ProjectOptions::default());
    for (c, &p) in found.iter().zip(&points) {
        assert_eq!(c.status(), Status::Accepted);
        assert!(
            (c.point - Vec3::new(p.x, p.y, 0.5)).abs().max_element() < 1e-6,
            "{p}: {c:?}"
        );
        assert!(
            (c.distance - (0.5 - p.z)).abs() < 1e-6,
            "{p}: t = {}",
            c.distance
        );
        assert_eq!(c.normal, Vec3::Z);
        assert_on_triangle(&mesh, c, 1e-6, "plane");
    }
    let down = vec![-Vec3::Z; points.len()];
    let found = run(backend, &bvh, &points, &down, &ProjectOptions::default());
    for (c, &p) in found.iter().zip(&points) {
        assert_eq!(
            c.status(),
            Status::NormalMismatch,
            "a normal opposite the plane's"
        );
        assert!((c.distance - (p.z - 0.5)).abs() < 1e-6);
    }
    for (degrees, expected) in [
        (0.0f32, Status::Accepted),
        (30.0, Status::Accepted),
        (59.9, Status::Accepted),
        (60.1, Status::NormalMismatch),
        (75.0, Status::NormalMismatch),
    ] {
        let theta = degrees.to_radians();
        for phi in [0.0f32, 1.0, 2.5, 4.0] {
            let d = Vec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            );
            let p = Vec3::new(0.1, -0.2, 0.3);
            let c = run(backend, &bvh, &[p], &[d], &ProjectOptions::default())[0];
            assert_eq!(c.status(), expected, "{degrees}° tilt");
            let t = 0.2 / theta.cos();
            assert!(
                (c.distance - t).abs() < 1e-5 * t.max(1.0),
                "{degrees}°: t = {}",
                c.distance
            );
            let strict = ProjectOptions {
                max_angle_degrees: 20.0,
                ..Default::default()
            };
            let c = run(backend, &bvh, &[p], &[d], &strict)[0];
            let expected = if degrees < 20.0 {
                Status::Accepted
            } else {
                Status::NormalMismatch
            };
            assert_eq!(c.status(), expected, "{degrees}° tilt, 20° limit");
        }
    }
}

/// Hits beyond `max_distance` mean edge lengths are not found; hits just inside are. Queries
/// straddle the threshold by 0.1% on both sides of the plane.
fn distance_threshold(backend: &Backend) {
    let mesh = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 3);
    let bvh = Bvh::build(&mesh).unwrap();
    let unit = bvh.mean_edge_length();
    let k = 2.0;
    let options = ProjectOptions {
        max_distance: k,
        ..Default::default()
    };
    let mut points = Vec::new();
    let mut normals = Vec::new();
    let mut inside_limit = Vec::new();
    // Vertex directions, so the surface point along the normal is the vertex at radius 1.
    for v in mesh.positions.iter().take(200) {
        let d = v.normalize();
        for (offset, inside) in [(0.999f32, true), (1.001, false)] {
            for side in [1.0f32, -1.0] {
                points.push(*v + d * (side * k * unit * offset));
                normals.push(d);
                inside_limit.push(inside);
            }
        }
    }
    let found = run(backend, &bvh, &points, &normals, &options);
    for (i, c) in found.iter().enumerate() {
        if inside_limit[i] {
            assert_eq!(
                c.status(),
                Status::Accepted,
                "query {i} within the limit: {c:?}"
            );
            assert!(c.distance.abs() <= k * unit);
        } else {
            assert_eq!(
                c.status(),
                Status::Miss,
                "query {i} beyond the limit: {c:?}"
            );
        }
    }
    let unlimited = run(backend, &bvh, &points, &normals, &ProjectOptions::default());
    assert!(unlimited.iter().all(Correspondence::is_accepted));
    let zero = ProjectOptions {
        max_distance: 0.0,
        ..Default::default()
    };
    let on_surface = run(
        backend,
        &bvh,
        &mesh.positions,
        &mesh.vertex_normals(surftrack::mesh::NormalWeighting::Max),
        &zero,
    );
    assert!(
        on_surface
            .iter()
            .all(|c| c.is_accepted() && c.distance == 0.0),
        "a vertex projects onto itself at t = 0"
    );
}

/// Points on a tube of radius 0.15 and 0.45 around the core circle of a torus (R = 1, r = 0.3),
/// with the tube's normal, land on the line through them on the hit triangle's plane, about
/// |0.3 − tube| away; along the mesh's own vertex directions they land on the vertices.
fn torus_tube_projects_along_the_tube_normal(backend: &Backend) {
    let (big, small, nu, nv) = (1.0f32, 0.3f32, 64, 24);
    let mesh = IndexedMesh::torus(big, small, nu, nv);
    let bvh = Bvh::build(&mesh).unwrap();
    let mut rng = Rng(5);
    let mut frames: Vec<(f32, f32)> = (0..1500)
        .map(|_| {
            (
                rng.range(0.0, std::f32::consts::TAU),
                rng.range(0.0, std::f32::consts::TAU),
            )
        })
        .collect();
    let grid = frames.len();
    for i in 0..nu {
        for j in 0..nv {
            frames.push((
                i as f32 / nu as f32 * std::f32::consts::TAU,
                j as f32 / nv as f32 * std::f32::consts::TAU,
            ));
        }
    }
    for tube in [0.15f32, 0.45] {
        let (points, normals): (Vec<Vec3>, Vec<Vec3>) = frames
            .iter()
            .map(|&(u, v)| {
                let m = Vec3::new(v.cos() * u.cos(), v.cos() * u.sin(), v.sin());
                let r = big + tube * v.cos();
                (Vec3::new(r * u.cos(), r * u.sin(), tube * v.sin()), m)
            })
            .unzip();
        let found = run(backend, &bvh, &points, &normals, &ProjectOptions::default());
        for (i, c) in found.iter().enumerate() {
            let what = format!("tube {tube}, query {i}");
            assert_eq!(c.status(), Status::Accepted, "{what}: {c:?}");
            let exact = line_plane_f64(&mesh, c.triangle, points[i], normals[i]);
            assert!(
                exact.distance(c.point.as_dvec3()) < 1e-5,
                "{what}: off the line/plane"
            );
            let expected = small - tube;
            assert!(
                (c.distance - expected).abs() < 0.01,
                "{what}: t = {}, expected about {expected}",
                c.distance
            );
            assert_on_triangle(&mesh, c, 1e-5, &what);
            if i >= grid {
                let v = mesh.positions[i - grid];
                assert!(
                    c.point.distance(v) < 1e-5 * big,
                    "{what}: vertex {v}, hit {}",
                    c.point
                );
            }
        }
    }
}

/// Lines that pass beside the mesh, unusable normals and points, and nothing within a tight
/// distance limit: all misses with the documented empty record.
fn misses_are_reported_as_misses(backend: &Backend) {
    let mesh = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 3);
    let bvh = Bvh::build(&mesh).unwrap();
    let points = [
        Vec3::new(3.0, 0.0, 0.0),
        Vec3::new(0.0, 1.5, 1.5),
        Vec3::new(0.5, 0.0, 0.0),
        Vec3::new(f32::NAN, 0.0, 0.0),
        Vec3::new(0.0, f32::INFINITY, 0.0),
    ];
    let normals = [Vec3::Y, Vec3::X, Vec3::ZERO, Vec3::X, Vec3::Z];
    let found = run(backend, &bvh, &points, &normals, &ProjectOptions::default());
    for (i, c) in found.iter().enumerate() {
        assert_eq!(*c, Correspondence::MISS, "query {i}");
        assert_eq!(c.hit_triangle(), None);
    }
    let far = [Vec3::new(0.0, 0.0, 5.0)];
    let tight = ProjectOptions {
        max_distance: 10.0,
        ..Default::default()
    };
    let unit = bvh.mean_edge_length();
    assert!(
        10.0 * unit < 4.0,
        "the limit must be shorter than the 4 units to the sphere"
    );
    assert_eq!(
        run(backend, &bvh, &far, &[Vec3::Z], &tight)[0],
        Correspondence::MISS
    );
    assert!(run(backend, &bvh, &far, &[Vec3::Z], &ProjectOptions::default())[0].is_accepted());
    assert!(run(backend, &bvh, &[], &[], &ProjectOptions::default()).is_empty());
}

/// Closest points on an icosphere against an f64 brute force: the same distance, the sign of
/// the side (negative inside), the nearest point on the reported triangle.
fn closest_points_match_brute_force(backend: &Backend) {
    let mesh = IndexedMesh::icosphere(Vec3::new(0.1, 0.2, -0.3), 1.0, 3);
    let bvh = Bvh::build(&mesh).unwrap();
    let mut rng = Rng(3);
    let mut points: Vec<Vec3> = (0..600)
        .map(|_| Vec3::new(0.1, 0.2, -0.3) + rng.direction() * rng.range(0.0, 2.5))
        .collect();
    // Exactly on vertices, and just off them along and against the normal: the corner and edge
    // pseudo-normals decide the sign there.
    for v in mesh.positions.iter().take(40) {
        let n = (*v - Vec3::new(0.1, 0.2, -0.3)).normalize();
        points.extend([*v, *v + n * 1e-3, *v - n * 1e-3]);
    }
    let found = closest_points(backend, &bvh, &points, f32::INFINITY).unwrap();
    for (i, (c, &p)) in found.iter().zip(&points).enumerate() {
        let what = format!("query {i} at {p}");
        assert!(c.is_accepted(), "{what}");
        let expected = distance_f64(&mesh, p);
        assert!(
            (f64::from(c.distance.abs()) - expected).abs() < 1e-5,
            "{what}: |distance| {} vs brute force {expected}",
            c.distance
        );
        let [a, b, cc] =
            mesh.triangles[c.triangle as usize].map(|v| mesh.positions[v as usize].as_dvec3());
        let on_triangle = closest_on_triangle_f64(p.as_dvec3(), a, b, cc);
        assert!(
            on_triangle.distance(c.point.as_dvec3()) < 1e-5,
            "{what}: point"
        );
        assert_on_triangle(&mesh, c, 1e-5, &what);
        if expected > 1e-4 {
            let inside = (p - Vec3::new(0.1, 0.2, -0.3)).length() < 0.95;
            let outside = (p - Vec3::new(0.1, 0.2, -0.3)).length() > 1.0;
            if inside || outside {
                assert_eq!(c.distance < 0.0, inside, "{what}: sign of {}", c.distance);
            }
        }
    }
    for (k, v) in mesh.positions.iter().take(40).enumerate() {
        let base = 600 + 3 * k;
        assert_eq!(found[base].distance, 0.0, "vertex {v} is on the surface");
        assert!(found[base + 1].distance > 0.0, "just outside vertex {v}");
        assert!(found[base + 2].distance < 0.0, "just inside vertex {v}");
    }
    let limited = closest_points(backend, &bvh, &points[..600], 1.0).unwrap();
    let unit = f64::from(bvh.mean_edge_length());
    for (i, (c, &p)) in limited.iter().zip(&points).enumerate() {
        let expected = distance_f64(&mesh, p);
        if expected < unit * 0.999 {
            assert!(c.is_accepted(), "query {i} within one edge length");
        } else if expected > unit * 1.001 {
            assert_eq!(*c, Correspondence::MISS, "query {i} beyond one edge length");
        }
    }
    let odd = closest_points(backend, &bvh, &[Vec3::NAN, Vec3::INFINITY], f32::INFINITY).unwrap();
    assert!(odd.iter().all(|c| *c == Correspondence::MISS));
}

/// Closest points on a torus: signed distance is |distance to the core circle| − r up to the
/// mesh's chord error, negative inside the tube.
fn closest_points_on_a_torus_sign_the_tube(backend: &Backend) {
    let (big, small) = (1.0f32, 0.3f32);
    let mesh = IndexedMesh::torus(big, small, 96, 32);
    let bvh = Bvh::build(&mesh).unwrap();
    let mut rng = Rng(9);
    let points: Vec<Vec3> = (0..2000)
        .map(|_| {
            Vec3::new(
                rng.range(-1.6, 1.6),
                rng.range(-1.6, 1.6),
                rng.range(-0.6, 0.6),
            )
        })
        .collect();
    let found = closest_points(backend, &bvh, &points, f32::INFINITY).unwrap();
    let sagitta = small * (1.0 - (std::f32::consts::PI / 32.0).cos()) + 0.01;
    for (c, &p) in found.iter().zip(&points) {
        let ring = Vec3::new(p.x, p.y, 0.0).normalize_or_zero() * big;
        let analytic = p.distance(ring) - small;
        if analytic.abs() > sagitta {
            assert_eq!(
                c.distance < 0.0,
                analytic < 0.0,
                "{p}: {} vs {analytic}",
                c.distance
            );
        }
        assert!(
            (c.distance - analytic).abs() < sagitta,
            "{p}: {} vs {analytic}",
            c.distance
        );
    }
}

/// `cast_ray` finds the first hit at t ≥ 0 only, in units of |direction|.
#[test]
fn cast_ray_is_one_sided() {
    let mesh = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 4);
    let bvh = Bvh::build(&mesh).unwrap();
    let inward = bvh.cast_ray(
        Vec3::new(0.0, 0.0, 3.0),
        Vec3::new(0.0, 0.0, -2.0),
        f32::INFINITY,
    );
    let hit = inward.unwrap();
    assert!(
        (hit.distance - 1.0).abs() < 1e-6,
        "t = {} in units of |d| = 2",
        hit.distance
    );
    assert!((hit.point.z - 1.0).abs() < 1e-6);
    assert!(
        bvh.cast_ray(Vec3::new(0.0, 0.0, 3.0), Vec3::Z, f32::INFINITY)
            .is_none()
    );
    assert!(
        bvh.cast_ray(Vec3::new(0.0, 0.0, 3.0), -Vec3::Z, 1.9)
            .is_none()
    );
    let inside = bvh.cast_ray(Vec3::ZERO, Vec3::X, f32::INFINITY).unwrap();
    assert!((inside.point.x - 1.0).abs() < 1e-6 && inside.distance > 0.0);
    assert!(bvh.cast_ray(Vec3::ZERO, Vec3::ZERO, 1.0).is_none());
    assert!(bvh.cast_ray(Vec3::NAN, Vec3::X, 1.0).is_none());
}

on_both_backends! {
    concentric_spheres_land_on_the_radial_point => concentric_spheres_land_on_the_radial_point_cpu, concentric_spheres_land_on_the_radial_point_gpu;
    plane_hits_and_angle_threshold => plane_hits_and_angle_threshold_cpu, plane_hits_and_angle_threshold_gpu;
    distance_threshold => distance_threshold_cpu, distance_threshold_gpu;
    torus_tube_projects_along_the_tube_normal => torus_tube_projects_along_the_tube_normal_cpu, torus_tube_projects_along_the_tube_normal_gpu;
    misses_are_reported_as_misses => misses_are_reported_as_misses_cpu, misses_are_reported_as_misses_gpu;
    closest_points_match_brute_force => closest_points_match_brute_force_cpu, closest_points_match_brute_force_gpu;
    closest_points_on_a_torus_sign_the_tube => closest_points_on_a_torus_sign_the_tube_cpu, closest_points_on_a_torus_sign_the_tube_gpu;
}
