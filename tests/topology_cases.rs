//! The adversarial cases of the topology design note (§7), each checked against every guarantee:
//! closed, manifold, oriented output with Θ's components and Euler characteristics, untouched
//! vertices outside the region, events that carry constants, fill vertices on Θ's zero set.

#[path = "topology_support/mod.rs"]
pub mod topology_support;

use glam::{Vec2, Vec3};
use surftrack::compute::Backend;
use surftrack::grid::{GridFrame, ScalarGrid, marching_cubes};
use surftrack::mesh::{IndexedMesh, Mesh};
use surftrack::project::{Bvh, closest_points};
use surftrack::topology::{
    Carry, Field, MeshRaster, Moves, ThetaSurface, TopologyOptions, constrain_topology,
    constrain_topology_on,
};
use topology_support::{Case, Kind, Outcome, check, euler_list};

fn frame() -> GridFrame {
    GridFrame::new(Vec3::new(0.013, -0.021, 0.007), 1.0).unwrap()
}

/// Marching cubes of `f` on a grid of spacing `h` offset from the topology grid.
fn surface(f: impl Fn(Vec3) -> f32 + Sync, h: f32) -> IndexedMesh {
    let n = (30.0 / h).ceil() as usize;
    let origin = Vec3::splat(-15.0) + Vec3::new(0.31, 0.17, 0.43) * h;
    let grid = ScalarGrid::from_fn(origin, h, [n; 3], f).unwrap();
    marching_cubes(&grid, 0.0)
}

fn ball(c: Vec3, r: f32) -> impl Fn(Vec3) -> f32 + Sync {
    move |p| (p - c).length() - r
}

fn union(
    a: impl Fn(Vec3) -> f32 + Sync,
    b: impl Fn(Vec3) -> f32 + Sync,
) -> impl Fn(Vec3) -> f32 + Sync {
    move |p| a(p).min(b(p))
}

fn torus(major: f32, minor: f32) -> impl Fn(Vec3) -> f32 + Sync {
    move |p| {
        let q = Vec3::new(p.x, p.y, 0.0).length() - major;
        (q * q + p.z * p.z).sqrt() - minor
    }
}

fn sampled(f: impl Fn(Vec3) -> f32 + Sync) -> Field {
    Field::from_fn(frame(), [-16; 3], [16; 3], f).unwrap()
}

fn phi(mesh: &IndexedMesh) -> Field {
    Field::signed_distance(&Backend::Cpu, frame(), mesh).unwrap()
}

fn checked(kind: Kind, mesh: IndexedMesh, theta: Field) -> Outcome {
    let case = Case { kind, mesh, theta };
    match check(&case) {
        Ok(o) => {
            assert!(
                o.fill_error <= 0.5,
                "fill vertex {} cells from Θ's zero set",
                o.fill_error
            );
            o
        }
        Err(e) => panic!("{e}"),
    }
}

/// The result of one call, to call again on.
fn after(mesh: &IndexedMesh, theta: &Field) -> IndexedMesh {
    after_with(mesh, theta, &TopologyOptions::default())
}

/// [`after`] with `options`.
fn after_with(mesh: &IndexedMesh, theta: &Field, options: &TopologyOptions) -> IndexedMesh {
    let mut m = Mesh::from_indexed(mesh).unwrap();
    constrain_topology(&mut m, theta, options).unwrap();
    m.to_indexed()
}

#[test]
fn clean_sphere_and_torus_are_left_alone_by_their_own_distance() {
    for mesh in [
        surface(ball(Vec3::ZERO, 6.3), 0.9),
        surface(torus(6.0, 2.2), 1.1),
    ] {
        let o = checked(Kind::SelfClean, mesh.clone(), phi(&mesh));
        assert!(!o.changed);
    }
}

/// Two balls a little apart, and a Θ in which they have moved into each other.
fn merging_balls() -> (IndexedMesh, Field) {
    let m = surface(
        union(
            ball(Vec3::new(-4.0, 0.0, 0.0), 3.5),
            ball(Vec3::new(4.2, 0.3, 0.0), 3.5),
        ),
        0.8,
    );
    let target = sampled(union(
        ball(Vec3::new(-3.0, 0.0, 0.0), 3.6),
        ball(Vec3::new(3.2, 0.3, 0.0), 3.6),
    ));
    (m, target)
}

#[test]
fn a_second_call_changes_nothing() {
    let (m, target) = merging_balls();
    let once = after(&m, &target);
    assert_eq!(euler_list(&once), vec![2]);
    let o = checked(Kind::Target, once.clone(), target);
    assert!(!o.changed, "second call with the same Θ re-sampled");
    let o = checked(Kind::SelfClean, once.clone(), phi(&once));
    assert!(!o.changed, "Φ of the result re-sampled it");
}

#[test]
fn patch_vertices_standing_on_the_vertices_they_replace_continue_them() {
    // The patch between the merging balls re-samples both sides of the neck.
    let (m, target) = merging_balls();
    let run = |continue_within: f32| {
        let options = TopologyOptions {
            continue_within,
            ..TopologyOptions::default()
        };
        after_with(&m, &target, &options)
    };
    let (paper, continued) = (run(0.0), run(0.25));
    // The same surface; only the ids differ.
    assert_eq!(paper.positions, continued.positions);
    assert_eq!(paper.triangles, continued.triangles);
    let old = m
        .ids
        .clone()
        .unwrap_or_else(|| (0..m.positions.len() as u64).collect());
    let at: std::collections::HashMap<u64, Vec3> =
        old.into_iter().zip(m.positions.clone()).collect();
    let moved = |out: &IndexedMesh| -> Vec<f32> {
        out.ids
            .as_ref()
            .unwrap()
            .iter()
            .zip(&out.positions)
            .filter_map(|(id, p)| at.get(id).map(|q| q.distance(*p)))
            .filter(|&d| d > 0.0)
            .collect()
    };
    // Without a reach no old vertex moves (paper §4.4); with it, some of the patch's vertices
    // continue the vertex they stand within a quarter cell of.
    assert!(moved(&paper).is_empty());
    let continued = moved(&continued);
    assert!(continued.len() >= 5, "{continued:?}");
    let reach = 0.25 * frame().spacing();
    assert!(continued.iter().all(|&d| d <= reach), "{continued:?}");
}

#[test]
fn patch_vertices_move_onto_the_carried_vertices_they_replace() {
    // Θ joins two balls by a bar the mesh lacks. The patch re-samples the cells around the
    // bar's ends, grown until their front is simple; around the bar the ball's surface is Θ's
    // zero set, and there the patch's new vertices move onto the old ones, which go on.
    let balls = || {
        union(
            ball(Vec3::new(-4.0, 0.0, 0.0), 3.5),
            ball(Vec3::new(4.2, 0.3, 0.0), 3.5),
        )
    };
    let m = surface(balls(), 0.8);
    let bar = |p: Vec3| Vec2::new(p.y - 0.15, p.z).length() - 1.3;
    let theta = sampled(union(balls(), bar));
    let run = |moves: Moves| {
        let options = TopologyOptions {
            moves,
            ..TopologyOptions::default()
        };
        after_with(&m, &theta, &options)
    };
    let every = Moves {
        carried_below: u64::MAX,
        longest_edge: 2.0 * frame().spacing(),
    };
    let (unmoved, moved) = (run(Moves::default()), run(every));
    moved.validate().unwrap();
    assert_eq!(euler_list(&moved), vec![2]);
    assert_eq!(
        moved.triangles, unmoved.triangles,
        "only positions and ids change"
    );
    let old: std::collections::HashMap<u64, Vec3> = m
        .ids
        .clone()
        .unwrap_or_else(|| (0..m.positions.len() as u64).collect())
        .into_iter()
        .zip(m.positions.clone())
        .collect();
    let kept = |out: &IndexedMesh| {
        let ids = out.ids.as_ref().unwrap();
        ids.iter().filter(|id| old.contains_key(id)).count()
    };
    let (lost_unmoved, lost_moved) = (old.len() - kept(&unmoved), old.len() - kept(&moved));
    // Most of those lost lie under the bar, inside Θ; some ten stand beside it.
    assert!(
        lost_moved + 5 <= lost_unmoved,
        "{lost_moved} old vertices lost with moves, {lost_unmoved} without"
    );
    // An old vertex that goes on stands where it stood or within the continue reach of it.
    let reach = 0.25 * frame().spacing();
    for (id, p) in moved.ids.as_ref().unwrap().iter().zip(&moved.positions) {
        if let Some(q) = old.get(id) {
            assert!(q.distance(*p) <= reach, "{id}: {q} to {p}");
        }
    }
}

/// A cube of side `n` cells whose vertices sit on grid corners, edges on grid edges and faces in
/// grid planes, each face split into unit squares.
fn grid_cube(lo: [i32; 3], n: i32) -> IndexedMesh {
    let f = frame();
    let mut positions = Vec::new();
    let mut index = std::collections::HashMap::new();
    let mut triangles = Vec::new();
    let mut vertex = |c: [i32; 3], positions: &mut Vec<Vec3>| -> u32 {
        *index.entry(c).or_insert_with(|| {
            positions.push(f.corner_position(c));
            positions.len() as u32 - 1
        })
    };
    for axis in 0..3 {
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        for side in 0..2 {
            for i in 0..n {
                for j in 0..n {
                    let at = |di: i32, dj: i32| {
                        let mut c = lo;
                        c[axis] += side * n;
                        c[u] += i + di;
                        c[v] += j + dj;
                        c
                    };
                    let q =
                        [at(0, 0), at(1, 0), at(1, 1), at(0, 1)].map(|c| vertex(c, &mut positions));
                    if side == 1 {
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
    let mesh = IndexedMesh::new(positions, triangles);
    mesh.validate().unwrap();
    mesh
}

#[test]
fn a_cube_on_the_grid_lines() {
    let cube = grid_cube([-3, -3, -3], 6);
    checked(Kind::Snapped, cube.clone(), phi(&cube));
    let shifted = sampled(|p| {
        let q = (p - Vec3::new(1.5, 1.5, 1.5)).abs() - Vec3::splat(3.0);
        q.max(Vec3::ZERO).length() + q.max_element().min(0.0)
    });
    let o = checked(Kind::Snapped, cube.clone(), shifted);
    assert!(o.changed);
    let bumped = sampled(union(
        |p: Vec3| {
            let q = p.abs() - Vec3::splat(3.0);
            q.max(Vec3::ZERO).length() + q.max_element().min(0.0)
        },
        ball(Vec3::new(3.0, 0.0, 0.0), 2.0),
    ));
    checked(Kind::Snapped, cube, bumped);
}

#[test]
fn two_spheres_overlapping_touching_and_apart() {
    for gap in [-2.0f32, -0.5, 0.0, 0.5, 1.0, 3.0] {
        let r = 4.0;
        let a = surface(ball(Vec3::new(-r - gap / 2.0, 0.1, 0.0), r), 0.9);
        let b = surface(ball(Vec3::new(r + gap / 2.0, 0.0, 0.2), r), 0.85);
        let both = a.joined(&b);
        if both.validate().is_err() {
            continue;
        }
        checked(Kind::SelfIntersecting, both.clone(), phi(&both));
        let bridge = sampled(union(
            union(
                ball(Vec3::new(-r - gap / 2.0, 0.1, 0.0), r),
                ball(Vec3::new(r + gap / 2.0, 0.0, 0.2), r),
            ),
            |p: Vec3| Vec3::new(0.0, p.y, p.z).length() - 1.5,
        ));
        let o = checked(Kind::Target, both, bridge);
        assert!(o.changed);
    }
}

/// Φ(M)'s own raster handed to the cut (as the tracker does, to rasterize M once) gives the same
/// result as a cut that rasterizes M itself, vertex for vertex; a raster of another grid is not
/// used.
#[test]
fn the_cut_on_phi_ms_raster_is_the_cut_on_its_own() {
    let r = 4.0;
    let a = surface(ball(Vec3::new(-r + 1.0, 0.1, 0.0), r), 0.9);
    let b = surface(ball(Vec3::new(r - 1.0, 0.0, 0.2), r), 0.85);
    let both = a.joined(&b);
    let options = TopologyOptions::default();
    let run = |raster: Option<MeshRaster>, theta: &Field| {
        let mut m = Mesh::from_indexed(&both).unwrap();
        let report =
            constrain_topology_on(&mut m, (theta, &ThetaSurface::of(theta)), raster, &options)
                .unwrap();
        assert!(report.changed(), "the overlapping balls were not merged");
        let out = m.to_indexed();
        (out.positions, out.triangles, out.ids)
    };
    let raster = MeshRaster::new(&Backend::Cpu, frame(), &both).unwrap();
    let theta = Field::of_raster(&Backend::Cpu, &raster).unwrap();
    let own = run(None, &theta);
    assert_eq!(run(Some(raster), &theta), own);
    let elsewhere = GridFrame::new(Vec3::splat(0.3), 1.0).unwrap();
    let other = MeshRaster::new(&Backend::Cpu, elsewhere, &both).unwrap();
    assert_eq!(run(Some(other), &theta), own);
    assert_eq!(euler_list(&IndexedMesh::new(own.0, own.1)), vec![2]);
}

#[test]
fn components_appear_and_vanish() {
    let m = surface(ball(Vec3::new(-5.0, 0.0, 0.0), 4.0), 0.9);
    // A large and a tiny new component.
    for r in [3.0, 0.7] {
        let theta = sampled(union(
            ball(Vec3::new(-5.0, 0.0, 0.0), 4.0),
            ball(Vec3::new(7.0, 1.0, 0.0), r),
        ));
        assert!(checked(Kind::Target, m.clone(), theta).changed);
    }
    // The component is gone from Θ.
    let o = checked(
        Kind::Target,
        m.clone(),
        sampled(ball(Vec3::new(30.0, 0.0, 0.0), 1.0)),
    );
    assert!(o.changed);
    // Θ empty everywhere: the result is empty.
    let o = checked(Kind::Target, m, sampled(|_| 1.0));
    assert!(o.replaced > 0.99);
    // A mesh inside one cell, invisible to every grid edge, vanishes.
    let tiny = surface(ball(Vec3::new(0.5, 0.5, 0.5), 0.3), 0.1);
    let o = checked(Kind::SelfClean, tiny.clone(), phi(&tiny));
    assert!(o.changed && o.replaced > 0.99);
}

#[test]
fn an_empty_mesh_takes_all_of_theta() {
    let mut mesh = Mesh::from_indexed(&surface(ball(Vec3::ZERO, 3.0), 1.0)).unwrap();
    constrain_topology(&mut mesh, &sampled(|_| 1.0), &TopologyOptions::default()).unwrap();
    assert_eq!(mesh.face_count(), 0);
    let report = constrain_topology(
        &mut mesh,
        &sampled(torus(5.0, 2.0)),
        &TopologyOptions::default(),
    )
    .unwrap();
    assert!(report.changed());
    let out = mesh.to_indexed();
    out.validate().unwrap();
    assert_eq!(euler_list(&out), vec![0]);
}

#[test]
fn ambiguous_faces_and_a_checkerboard() {
    let m = surface(ball(Vec3::ZERO, 5.0), 0.9);
    let f = frame();
    let checker = move |p: Vec3| {
        let g = ((p - f.origin()) / f.spacing()).round();
        let inside_ball = p.length() < 5.0;
        let parity = (g.x as i32 + g.y as i32 + g.z as i32).rem_euclid(2) == 0;
        if p.x > 1.0 && p.length() < 6.0 {
            if parity { -0.5 } else { 0.5 }
        } else if inside_ball {
            -1.0
        } else {
            1.0
        }
    };
    checked(Kind::Target, m.clone(), sampled(checker));
    // Diagonal blobs: cells whose corners alternate along a diagonal plane.
    let diagonal = move |p: Vec3| {
        let g = ((p - f.origin()) / f.spacing()).round();
        if p.length() < 5.0 && (g.x as i32 + g.y as i32).rem_euclid(3) == 0 {
            0.5
        } else {
            p.length() - 5.0
        }
    };
    checked(Kind::Target, m, sampled(diagonal));
}

#[test]
fn huge_triangles_slivers_and_near_planes() {
    // An octahedron with triangles spanning about 20 cells.
    let r = 14.0;
    let positions = vec![
        Vec3::new(r, 0.3, 0.1),
        Vec3::new(-r, 0.2, -0.1),
        Vec3::new(0.1, r, 0.2),
        Vec3::new(-0.2, -r, 0.3),
        Vec3::new(0.3, 0.1, r),
        Vec3::new(0.2, -0.3, -r),
    ];
    let triangles = vec![
        [0, 2, 4],
        [2, 1, 4],
        [1, 3, 4],
        [3, 0, 4],
        [2, 0, 5],
        [1, 2, 5],
        [3, 1, 5],
        [0, 3, 5],
    ];
    let octa = IndexedMesh::new(positions, triangles);
    octa.validate().unwrap();
    checked(Kind::SelfClean, octa.clone(), phi(&octa));
    let notched = sampled(move |p: Vec3| {
        let o = p.x.abs() + p.y.abs() + p.z.abs() - r;
        o.max(-((p - Vec3::new(5.0, 5.0, 4.0)).length() - 3.0))
    });
    assert!(checked(Kind::Target, octa.clone(), notched).changed);
    // The same with vertices a float step away from grid planes and corners.
    let f = frame();
    let mut near = octa.clone();
    for p in &mut near.positions {
        for a in 0..3 {
            let plane =
                f.origin()[a] + f.spacing() * ((p[a] - f.origin()[a]) / f.spacing()).round();
            p[a] = if a % 2 == 0 {
                plane.next_up()
            } else {
                plane.next_down()
            };
        }
    }
    near.validate().unwrap();
    checked(Kind::Snapped, near.clone(), phi(&near));
    let bumped = sampled(move |p: Vec3| {
        let o = p.x.abs() + p.y.abs() + p.z.abs() - r;
        o.min((p - Vec3::new(-6.0, 5.0, 4.0)).length() - 3.0)
    });
    checked(Kind::Snapped, near, bumped);
}

#[test]
fn thin_strands_follow_the_deep_rule() {
    for radius in [0.15f32, 0.5, 1.5] {
        let dumbbell = union(
            union(
                ball(Vec3::new(-6.0, 0.0, 0.0), 3.0),
                ball(Vec3::new(6.0, 0.0, 0.0), 3.0),
            ),
            move |p: Vec3| Vec3::new(0.0, p.y - 0.2, p.z - 0.1).length() - radius,
        );
        let m = surface(dumbbell, 0.12_f32.max(radius / 2.0));
        if m.validate().is_err() {
            continue;
        }
        checked(Kind::SelfClean, m.clone(), phi(&m));
    }
}

/// Locality on frames without a topology change: a mesh that matches the target within a cell
/// (another tessellation of the same shapes, moved by up to half a cell) is left alone by both
/// passes, `Φ(M)` and `Φ(T)`.
#[test]
fn a_mesh_within_a_cell_of_its_target_is_left_alone() {
    let mut rng = topology_support::Rng::new(7);
    for shape in 0..4 {
        for _ in 0..5 {
            let shift = rng.vec(0.5 / 3f32.sqrt());
            let (h_t, h_m) = (rng.range(0.6, 1.2), rng.range(0.6, 1.2));
            let (t, m) = match shape {
                0 => (
                    surface(ball(Vec3::ZERO, 6.0), h_t),
                    surface(ball(shift, 6.0), h_m),
                ),
                1 => (
                    surface(torus(6.5, 2.5), h_t),
                    surface(move |p| torus(6.5, 2.5)(p - shift), h_m),
                ),
                2 => {
                    let pair = |s: Vec3| {
                        union(
                            ball(Vec3::new(-6.0, 0.0, 0.0) + s, 3.5),
                            ball(Vec3::new(6.0, 0.0, 0.0) + s, 3.5),
                        )
                    };
                    (surface(pair(Vec3::ZERO), h_t), surface(pair(shift), h_m))
                }
                _ => {
                    let blobs = topology_support::Blobs {
                        centers: vec![Vec3::new(-2.5, 0.0, 0.0), Vec3::new(2.5, 1.0, 0.0)],
                        widths: vec![3.5, 3.0],
                        threshold: 0.4,
                    };
                    let b = blobs.clone();
                    (
                        surface(move |p| 3.0 * blobs.value(p), h_t),
                        surface(move |p| 3.0 * b.value(p - shift), h_m),
                    )
                }
            };
            assert_eq!(euler_list(&m), euler_list(&t), "shape {shape}");
            let o = checked(Kind::SelfClean, m.clone(), phi(&m));
            assert!(!o.changed, "shape {shape}: Φ(M) re-sampled a clean mesh");
            let o = checked(Kind::TargetMesh, m, phi(&t));
            assert!(
                !o.changed,
                "shape {shape}, shift {shift}: Φ(T) re-sampled a mesh within a cell of T"
            );
        }
    }
}

/// A linear field carried through `constrain_topology(mesh, theta)` under `carry`: per vertex the
/// step created, its position, the value it carries, and its distance to the old surface.
fn carried_linear_field(mesh: &IndexedMesh, theta: &Field, carry: Carry) -> Vec<(Vec3, f32, f32)> {
    let mut m = Mesh::from_indexed(mesh).unwrap();
    let channel = m.add_attribute("f", 1, 0.0);
    let slots: Vec<_> = m.vertices().collect();
    for v in slots {
        let value = GRADIENT.dot(m.position(v));
        m.attribute_mut(channel, v)[0] = value;
    }
    let before: std::collections::HashSet<u64> = m.vertices().map(|v| m.id(v)).collect();
    let options = TopologyOptions {
        carry,
        ..TopologyOptions::default()
    };
    constrain_topology(&mut m, theta, &options).unwrap();
    let created: Vec<_> = m
        .vertices()
        .filter(|&v| !before.contains(&m.id(v)))
        .collect();
    assert!(!created.is_empty(), "the step re-sampled nothing");
    let points: Vec<Vec3> = created.iter().map(|&v| m.position(v)).collect();
    let bvh = Bvh::build(mesh).unwrap();
    let old = closest_points(&Backend::Cpu, &bvh, &points, f32::INFINITY).unwrap();
    created
        .iter()
        .zip(&points)
        .zip(&old)
        .map(|((&v, &p), hit)| (p, m.attribute(channel, v)[0], hit.distance.abs()))
        .collect()
}

/// The gradient of the linear field the patch tests carry.
const GRADIENT: Vec3 = Vec3::new(1.0, 2.0, -3.0);

/// The largest amount, over the created vertices, by which the carried value misses the field at
/// the vertex beyond what the field changes over the vertex's distance to the old surface,
/// relative to the field's gradient (a length, in grid steps).
fn linear_field_miss(carried: &[(Vec3, f32, f32)]) -> f32 {
    carried
        .iter()
        .map(|&(p, value, distance)| (value - GRADIENT.dot(p)).abs() / GRADIENT.length() - distance)
        .fold(f32::MIN, f32::max)
}

/// Overlapping spheres merged by their own distance field (Φ(M)), and a hole punched through one
/// of them (Φ(T)): the two re-samplings the patch tests carry a field through, each with the
/// surface replaced.
fn merged_and_punched() -> [(IndexedMesh, Field); 2] {
    let r = 4.0;
    let centres = [Vec3::new(-r + 1.0, 0.1, 0.0), Vec3::new(r - 1.0, 0.0, 0.2)];
    let a = surface(ball(centres[0], r), 0.9);
    let b = surface(ball(centres[1], r), 0.85);
    let both = a.joined(&b);
    let merge = phi(&both);
    let holed = sampled(move |p: Vec3| {
        ball(centres[0], r)(p).max(1.2 - Vec3::new(p.x - centres[0].x, p.y, 0.0).length())
    });
    [(both, merge), (a, holed)]
}

/// With `Carry::Blend`, new patch vertices read the surface the patch replaces at their closest
/// point (barycentric on its triangles), not an average of the patch boundary: a linear field
/// comes through exactly, up to the field's change between the vertex and the old surface.
#[test]
fn a_patch_takes_the_replaced_surface_at_its_closest_points() {
    for (mesh, theta) in merged_and_punched() {
        let miss = linear_field_miss(&carried_linear_field(&mesh, &theta, Carry::Blend));
        println!("linear field missed by {miss} grid steps");
        assert!(miss <= 1e-3, "{miss}");
    }
}

/// With `Carry::Corner` (the default), every new vertex off the old surface (the patch's fill;
/// the cut's points lie on the old edges, and take their ends' blend as a split does) carries
/// the value of one old vertex whole, one no farther from it than its distance to the old
/// surface and an edge: a corner of the triangle holding its closest point, never a blend.
#[test]
fn a_patch_takes_a_corner_of_the_closest_triangle_whole() {
    for (mesh, theta) in merged_and_punched() {
        let longest = mesh
            .triangles
            .iter()
            .flat_map(|t| (0..3).map(move |k| (t[k], t[(k + 1) % 3])))
            .map(|(a, b)| mesh.positions[a as usize].distance(mesh.positions[b as usize]))
            .fold(0.0f32, f32::max);
        let carried = carried_linear_field(&mesh, &theta, Carry::Corner);
        let off: Vec<_> = carried.iter().filter(|c| c.2 > 1e-3).collect();
        assert!(!off.is_empty(), "no new vertex off the old surface");
        for &&(p, value, distance) in &off {
            let whole = mesh.positions.iter().any(|&q| {
                (GRADIENT.dot(q) - value).abs() <= 1e-5 * GRADIENT.length()
                    && q.distance(p) <= distance + longest + 1e-4
            });
            assert!(whole, "{p}: {value} is no nearby old vertex's value");
        }
    }
}

/// A sheet thinner than a cell, lying between two planes of grid corners: no corner is inside it,
/// so Θ, sampled at the corners, cannot hold it, and its isosurface has nothing there.
fn thin_sheet(h: f32, shift: Vec3) -> IndexedMesh {
    let sheet = move |p: Vec3| {
        let q = p - shift - Vec3::new(0.0, 0.0, 0.5);
        let d = q.abs() - Vec3::new(4.0, 4.0, 0.12);
        d.max(Vec3::ZERO).length() + d.max_element().min(0.0)
    };
    let n = (12.0 / h).ceil() as usize;
    let origin = Vec3::new(-6.0, -6.0, -5.5) + Vec3::new(0.31, 0.17, 0.43) * h;
    marching_cubes(&ScalarGrid::from_fn(origin, h, [n; 3], sheet).unwrap(), 0.0)
}

/// With `keep_shared_sheets`, a sheet thinner than a cell that Θ's own mesh has too is no
/// difference: neither pass re-samples it, though Θ's isosurface has no sheet. Without it, or
/// where Θ's mesh has no sheet there, the sheet is a deep difference and goes, as the paper's
/// grid-resolved topology asks.
#[test]
fn shared_sheets_below_the_grid_are_kept_when_asked() {
    let m = thin_sheet(0.1, Vec3::ZERO);
    m.validate().unwrap();
    let other = thin_sheet(0.13, Vec3::new(0.05, -0.04, 0.03));
    let keep = TopologyOptions {
        keep_shared_sheets: true,
        ..TopologyOptions::default()
    };
    for (what, theta) in [("Φ(M)", phi(&m)), ("Φ(T)", phi(&other))] {
        let mut kept = Mesh::from_indexed(&m).unwrap();
        let report = constrain_topology(&mut kept, &theta, &keep).unwrap();
        assert!(!report.changed(), "{what}: the shared sheet was re-sampled");
        assert_eq!(kept.to_indexed().positions, m.positions, "{what}");

        let mut strict = Mesh::from_indexed(&m).unwrap();
        let report = constrain_topology(&mut strict, &theta, &TopologyOptions::default()).unwrap();
        assert!(
            report.changed(),
            "{what}: the sheet was left without the option"
        );
        assert_eq!(strict.vertices().count(), 0, "{what}: Θ holds no sheet");
    }
    // A sheet the target does not have is a difference all the same.
    let elsewhere = thin_sheet(0.1, Vec3::new(0.0, 0.0, 3.0));
    let mut gone = Mesh::from_indexed(&m).unwrap();
    constrain_topology(&mut gone, &phi(&elsewhere), &keep).unwrap();
    assert!(
        gone.vertices()
            .all(|v| (gone.position(v).z - 3.5).abs() < 1.0),
        "a sheet the target lacks was kept"
    );
}

/// A bar 16 cells long (so not a blob the comparison would leave alone), ending in the middle of
/// the cell `[0, 1]³` of `frame()`, with a ring inside that cell, half sunk into the bar's end,
/// where `handle`: a handle that no grid edge, face or corner meets, which Θ cannot see.
fn bar(handle: bool) -> IndexedMesh {
    let centre = Vec3::new(0.513, 0.479, 0.507);
    let f = move |p: Vec3| {
        let lo = Vec3::new(-15.5, -1.3, -1.3);
        let hi = Vec3::new(centre.x, 2.3, 2.3);
        let d = (lo - p).max(p - hi);
        let bar = d.max(Vec3::ZERO).length() + d.max_element().min(0.0);
        if handle {
            bar.min(torus(0.25, 0.1)(p - centre))
        } else {
            bar
        }
    };
    let h = 0.05;
    let origin = Vec3::new(-16.5, -2.3, -2.3) + Vec3::new(0.31, 0.17, 0.43) * h;
    let grid = ScalarGrid::from_fn(origin, h, [360, 112, 112], f).unwrap();
    marching_cubes(&grid, 0.0)
}

/// With `keep_shared_sheets` (a caller that matches the input below the grid follows), a
/// component whose topology differs from Θ's where no grid edge, face or corner can tell, and
/// that re-sampling every difference inside it leaves as wrong as before, is left to that
/// caller: the result keeps the handle and every vertex of the bar, and re-samples only where Θ
/// differs visibly (a blob the mesh lacks). Without the option the guarantee holds: Θ's topology,
/// here only by replacing the whole surface.
#[test]
fn a_difference_the_grid_cannot_mend_is_left_to_a_caller_below_the_grid() {
    let mesh = bar(true);
    assert_eq!(euler_list(&mesh), vec![0], "the bar has its handle");
    let blob = surface(ball(Vec3::new(-8.0, 0.5, 7.0), 1.6), 0.4);
    let target = bar(false).joined(&blob);
    let theta = phi(&target);

    let keep = TopologyOptions {
        keep_shared_sheets: true,
        ..TopologyOptions::default()
    };
    let mut kept = Mesh::from_indexed(&mesh).unwrap();
    let report = constrain_topology(&mut kept, &theta, &keep).unwrap();
    let result = kept.to_indexed();
    result.validate().unwrap();
    assert_eq!(euler_list(&result), vec![0, 2], "{report:?}");
    assert_eq!(report.kept, mesh.positions.len(), "the bar was re-sampled");

    let mut strict = Mesh::from_indexed(&mesh).unwrap();
    constrain_topology(&mut strict, &theta, &TopologyOptions::default()).unwrap();
    assert_eq!(euler_list(&strict.to_indexed()), vec![2, 2]);
}

/// A droplet a third of a cell across, three cells from a ball, that Θ (the ball's alone) does
/// not hold. With `keep_shared_sheets` (a caller that matches the input below the grid follows)
/// the droplet is that caller's: it keeps every vertex. Without the option the step gives Θ's
/// topology and the droplet goes. A droplet touching the ball's cells is not left alone.
#[test]
fn a_droplet_apart_from_the_body_is_left_to_a_caller_below_the_grid() {
    let body = ball(Vec3::ZERO, 3.0);
    let centre = Vec3::new(6.4, 0.3, -0.2);
    let with = |c: Vec3| IndexedMesh::icosphere(c, 0.17, 1);
    let mesh = |c: Vec3| {
        let mut m = surface(&body, 0.25);
        let drop = with(c);
        let base = m.positions.len() as u32;
        m.positions.extend(&drop.positions);
        m.triangles
            .extend(drop.triangles.iter().map(|t| t.map(|v| v + base)));
        m
    };
    let theta = phi(&surface(&body, 0.25));
    let keep = TopologyOptions {
        keep_shared_sheets: true,
        ..TopologyOptions::default()
    };
    let near = |m: &Mesh, c: Vec3| {
        m.vertices()
            .filter(|&v| m.position(v).distance(c) < 0.5)
            .map(|v| m.id(v))
            .collect::<Vec<_>>()
    };
    let mut kept = Mesh::from_indexed(&mesh(centre)).unwrap();
    let before = near(&kept, centre);
    assert_eq!(before.len(), with(centre).positions.len());
    constrain_topology(&mut kept, &theta, &keep).unwrap();
    assert_eq!(near(&kept, centre), before);
    let mut gone = Mesh::from_indexed(&mesh(centre)).unwrap();
    constrain_topology(&mut gone, &theta, &TopologyOptions::default()).unwrap();
    assert!(near(&gone, centre).is_empty());
    // Half a cell off the ball's surface the droplet's cells touch the ball's: no longer apart.
    let touching = Vec3::new(3.5, 0.3, -0.2);
    let mut merged = Mesh::from_indexed(&mesh(touching)).unwrap();
    let before = near(&merged, touching);
    constrain_topology(&mut merged, &theta, &keep).unwrap();
    assert_ne!(near(&merged, touching), before);
}
