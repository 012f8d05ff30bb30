//! Marching cubes: closed, manifold, oriented output for any input; geometric accuracy on a sphere;
//! topology matching the digital topology of the inside corners; determinism across thread counts;
//! agreement with a direct per-cell reference extraction.

use glam::Vec3;
use std::collections::HashMap;
use surftrack::grid::cases::cell_case;
use surftrack::grid::cube::EDGE_CORNERS;
use surftrack::grid::{ScalarGrid, T_MIN, marching_cubes};
use surftrack::mesh::IndexedMesh;

/// splitmix64: a deterministic stream of pseudo-random numbers for test fields.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    fn uniform(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }
}

fn noise_grid(dims: [usize; 3], seed: u64, inside_fraction: f32) -> ScalarGrid {
    let mut rng = Rng(seed);
    let n = dims.iter().product();
    let values = (0..n).map(|_| rng.uniform() - inside_fraction).collect();
    ScalarGrid::new(Vec3::new(-1.0, 0.5, 2.0), 0.25, dims, values).unwrap()
}

fn signed_volume(mesh: &IndexedMesh) -> f64 {
    mesh.triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| mesh.positions[v as usize].as_dvec3());
            a.dot(b.cross(c)) / 6.0
        })
        .sum()
}

/// Checks closed, manifold, consistently oriented with the mesh module's validation, and that no
/// vertex is unused or duplicated.
fn assert_valid(mesh: &IndexedMesh, what: &str) {
    mesh.validate().unwrap_or_else(|e| panic!("{what}: {e}"));
    let mut seen = HashMap::new();
    for (v, p) in mesh.positions.iter().enumerate() {
        let key = p.to_array().map(f32::to_bits);
        assert!(
            seen.insert(key, v).is_none(),
            "{what}: vertex {v} duplicated"
        );
    }
}

#[test]
fn noise_gives_closed_oriented_manifolds() {
    let shapes = [
        [12, 12, 12],
        [17, 9, 23],
        [64, 5, 6],
        [65, 4, 7],
        [130, 6, 5],
        [3, 3, 3],
    ];
    for (s, dims) in shapes.into_iter().enumerate() {
        for (f, fraction) in [0.2f32, 0.5, 0.8].into_iter().enumerate() {
            let seed = (s * 10 + f) as u64;
            let mesh = marching_cubes(&noise_grid(dims, seed, fraction), 0.0);
            if dims == [3, 3, 3] && mesh.triangles.is_empty() {
                continue;
            }
            assert_valid(&mesh, &format!("noise {dims:?} seed {seed}"));
            assert!(signed_volume(&mesh) > 0.0, "inside has positive volume");
        }
    }
}

#[test]
fn ties_and_non_finite_values_still_give_valid_meshes() {
    let dims = [20, 21, 22];
    let mut rng = Rng(7);
    let specials = [
        0.0,
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        -1.0,
        1.0,
        1e30,
        -1e30,
    ];
    let values = (0..dims.iter().product::<usize>())
        .map(|_| specials[(rng.next() % specials.len() as u64) as usize])
        .collect();
    let grid = ScalarGrid::new(Vec3::ZERO, 1.0, dims, values).unwrap();
    let mesh = marching_cubes(&grid, 0.0);
    assert!(!mesh.triangles.is_empty());
    assert!(mesh.positions.iter().all(|p| p.is_finite()));
    assert_valid(&mesh, "specials");
}

#[test]
fn checkerboards_give_closed_oriented_manifolds() {
    for period in 1..=3usize {
        let dims = [14, 15, 16];
        let grid = ScalarGrid::from_fn(Vec3::ZERO, 1.0, dims, |p| {
            let [i, j, k] = p.to_array().map(|c| c.round() as usize / period);
            if (i + j + k) % 2 == 0 { -1.0 } else { 1.0 }
        })
        .unwrap();
        for iso in [0.0, -1.0, 1.0, 2.0] {
            let mesh = marching_cubes(&grid, iso);
            if iso <= -1.0 {
                assert!(mesh.triangles.is_empty(), "value == iso is outside");
                continue;
            }
            assert_valid(&mesh, &format!("checkerboard period {period} iso {iso}"));
        }
    }
}

#[test]
fn everything_inside_gives_one_box_on_the_border() {
    let grid = ScalarGrid::new(Vec3::ZERO, 1.0, [5, 6, 7], vec![-1.0; 210]).unwrap();
    let mesh = marching_cubes(&grid, 0.0);
    assert_valid(&mesh, "all inside");
    let topology = mesh.topology();
    assert_eq!(topology.components.len(), 1);
    assert_eq!(topology.total_genus(), 0);
    // Boundary corners are read as lying on the surface, so the box hugs the grid's border.
    let lo = mesh.positions.iter().fold(Vec3::MAX, |m, p| m.min(*p));
    let hi = mesh.positions.iter().fold(Vec3::MIN, |m, p| m.max(*p));
    assert!((lo - Vec3::splat(T_MIN)).abs().max_element() < 1e-6, "{lo}");
    assert!(
        (hi - Vec3::new(4.0, 5.0, 6.0) + T_MIN).abs().max_element() < 1e-6,
        "{hi}"
    );
}

#[test]
fn too_small_or_empty_grids_give_empty_meshes() {
    for dims in [[2, 9, 9], [9, 2, 9], [9, 9, 2], [0, 0, 0]] {
        let n = dims.iter().product();
        let grid = ScalarGrid::new(Vec3::ZERO, 1.0, dims, vec![-1.0; n]).unwrap();
        assert_eq!(marching_cubes(&grid, 0.0), IndexedMesh::default());
    }
}

#[test]
fn sphere_vertices_lie_on_the_sphere_and_face_outward() {
    let h = 0.1f32;
    let radius = 1.0f32;
    let center = Vec3::new(0.013, -0.021, 0.034);
    let origin = Vec3::splat(-1.4);
    let grid =
        ScalarGrid::from_fn(origin, h, [29, 29, 29], |p| (p - center).length() - radius).unwrap();
    let mesh = marching_cubes(&grid, 0.0);
    assert_valid(&mesh, "sphere");
    let topology = mesh.topology();
    assert_eq!(topology.components.len(), 1);
    assert_eq!(topology.total_genus(), 0);
    // Linear interpolation of a distance field along a grid edge that cuts a sphere of radius
    // R at an angle errs by O(h²/R); here R = 10 cells.
    let worst = mesh
        .positions
        .iter()
        .map(|p| ((*p - center).length() - radius).abs())
        .fold(0.0f32, f32::max);
    assert!(worst < 0.02 * h, "a vertex is {worst} off the sphere");
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|v| mesh.positions[v as usize]);
        let normal = (b - a).cross(c - a);
        assert!(
            normal.dot((a + b + c) / 3.0 - center) > 0.0,
            "triangle {t:?} faces inward"
        );
    }
    let exact = 4.0 / 3.0 * std::f64::consts::PI * f64::from(radius).powi(3);
    let relative = (signed_volume(&mesh) - exact).abs() / exact;
    assert!(relative < 0.01, "volume off by {relative}");
}

#[test]
fn torus_has_genus_one_and_separate_spheres_are_separate_components() {
    let torus = ScalarGrid::from_fn(Vec3::splat(-1.5), 0.1, [31, 31, 31], |p| {
        let ring = (p.x * p.x + p.y * p.y).sqrt() - 0.9;
        (ring * ring + p.z * p.z).sqrt() - 0.35
    })
    .unwrap();
    let mesh = marching_cubes(&torus, 0.0);
    assert_valid(&mesh, "torus");
    let topology = mesh.topology();
    assert_eq!((topology.components.len(), topology.total_genus()), (1, 1));

    let spheres = ScalarGrid::from_fn(Vec3::splat(-1.5), 0.1, [31, 31, 31], |p| {
        let a = (p - Vec3::new(-0.7, 0.0, 0.0)).length() - 0.5;
        let b = (p - Vec3::new(0.7, 0.0, 0.0)).length() - 0.5;
        a.min(b)
    })
    .unwrap();
    let topology = marching_cubes(&spheres, 0.0).topology();
    assert_eq!((topology.components.len(), topology.total_genus()), (2, 0));
}

/// Union-find over grid corners.
fn find(parent: &mut [usize], mut x: usize) -> usize {
    while parent[x] != x {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    x
}

/// Components of inside corners under face adjacency (6-connectivity) and of outside corners under
/// face and face-diagonal adjacency (18-connectivity); boundary corners count as outside.
fn digital_components(grid: &ScalarGrid, iso: f32) -> (usize, usize) {
    let [nx, ny, nz] = grid.dims();
    let id = |i: usize, j: usize, k: usize| i + nx * (j + ny * k);
    let inside = |i: usize, j: usize, k: usize| {
        let border = i == 0 || j == 0 || k == 0 || i + 1 == nx || j + 1 == ny || k + 1 == nz;
        !border && grid.value(i, j, k).unwrap() < iso
    };
    let mut parent: Vec<usize> = (0..nx * ny * nz).collect();
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                for (di, dj, dk) in [
                    (1, 0, 0),
                    (0, 1, 0),
                    (0, 0, 1),
                    (1, 1, 0),
                    (1, -1, 0),
                    (1, 0, 1),
                    (1, 0, -1),
                    (0, 1, 1),
                    (0, 1, -1),
                ] {
                    let (x, y, z) = (i as isize + di, j as isize + dj, k as isize + dk);
                    if x < 0 || y < 0 || z < 0 {
                        continue;
                    }
                    let (x, y, z) = (x as usize, y as usize, z as usize);
                    if x >= nx || y >= ny || z >= nz {
                        continue;
                    }
                    let a = inside(i, j, k);
                    if a != inside(x, y, z) {
                        continue;
                    }
                    let diagonal = (di != 0) as u8 + (dj != 0) as u8 + (dk != 0) as u8 > 1;
                    if a && diagonal {
                        continue;
                    }
                    let (ra, rb) = (
                        find(&mut parent, id(i, j, k)),
                        find(&mut parent, id(x, y, z)),
                    );
                    parent[ra.max(rb)] = ra.min(rb);
                }
            }
        }
    }
    let (mut inside_count, mut outside_count) = (0, 0);
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                if find(&mut parent, id(i, j, k)) == id(i, j, k) {
                    if inside(i, j, k) {
                        inside_count += 1;
                    } else {
                        outside_count += 1;
                    }
                }
            }
        }
    }
    (inside_count, outside_count)
}

/// With inside corners separated on every ambiguous face, the inside of the surface is the
/// 6-connected inside corners and its outside the 18-connected outside corners; the surface's
/// components are the borders between them, which form a tree in space: inside + outside − 1.
#[test]
fn surface_components_match_digital_topology_of_the_corners() {
    for (seed, fraction) in [(1u64, 0.15f32), (2, 0.3), (3, 0.45), (4, 0.6), (5, 0.75)] {
        let grid = noise_grid([14, 13, 12], seed, fraction);
        let mesh = marching_cubes(&grid, 0.0);
        let (inside, outside) = digital_components(&grid, 0.0);
        assert_eq!(
            mesh.topology().components.len(),
            inside + outside - 1,
            "seed {seed}: {inside} inside and {outside} outside components"
        );
    }
}

#[test]
fn output_is_identical_for_one_and_two_threads() {
    let grid = noise_grid([70, 33, 41], 99, 0.5);
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| marching_cubes(&grid, 0.0))
    };
    let one = run(1);
    let two = run(2);
    let bits = |m: &IndexedMesh| -> Vec<[u32; 3]> {
        m.positions
            .iter()
            .map(|p| p.to_array().map(f32::to_bits))
            .collect()
    };
    assert_eq!(bits(&one), bits(&two));
    assert_eq!(one.triangles, two.triangles);
}

/// A direct extraction, cell by cell with a hash map from grid edge to vertex, for comparison: same
/// triangles, same positions, so the packed-bit numbering loses and invents nothing.
fn reference(grid: &ScalarGrid, iso: f32) -> Vec<[[u32; 3]; 3]> {
    let [nx, ny, nz] = grid.dims();
    let inside = |c: [usize; 3]| {
        let border = c[0] == 0 || c[1] == 0 || c[2] == 0;
        let border = border || c[0] + 1 == nx || c[1] + 1 == ny || c[2] + 1 == nz;
        !border && grid.value(c[0], c[1], c[2]).unwrap() < iso
    };
    let mut out = Vec::new();
    for k in 0..nz - 1 {
        for j in 0..ny - 1 {
            for i in 0..nx - 1 {
                let corner = |c: usize| [i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1)];
                let config = (0..8).fold(0u8, |m, c| m | (u8::from(inside(corner(c))) << c));
                for t in &cell_case(config).triangles {
                    out.push(t.map(|e| {
                        let [a, b] = EDGE_CORNERS[usize::from(e)].map(corner);
                        let (va, vb) = (
                            grid.value(a[0], a[1], a[2]).unwrap(),
                            grid.value(b[0], b[1], b[2]).unwrap(),
                        );
                        let (va, vb) = if inside(a) {
                            (va, vb.max(iso))
                        } else {
                            (va.max(iso), vb)
                        };
                        let t = ((iso - va) / (vb - va)).clamp(T_MIN, 1.0 - T_MIN);
                        let mut p = a.map(|x| x as f32);
                        p[usize::from(e) / 4] += t;
                        (grid.origin() + grid.spacing() * Vec3::from(p))
                            .to_array()
                            .map(f32::to_bits)
                    }));
                }
            }
        }
    }
    out
}

#[test]
fn agrees_with_a_direct_per_cell_extraction() {
    for (dims, seed) in [
        ([130, 7, 6], 5u64),
        ([64, 9, 8], 6),
        ([63, 8, 9], 7),
        ([11, 40, 12], 8),
    ] {
        let grid = noise_grid(dims, seed, 0.5);
        let mesh = marching_cubes(&grid, 0.0);
        let ours: Vec<[[u32; 3]; 3]> = mesh
            .triangles
            .iter()
            .map(|t| t.map(|v| mesh.positions[v as usize].to_array().map(f32::to_bits)))
            .collect();
        assert_eq!(ours, reference(&grid, 0.0), "dims {dims:?}");
    }
}

/// The synthetic droplets rely on this: a ball of radius one cell, wherever it sits, holds grid
/// corners and comes out as a single sphere.
#[test]
fn balls_of_one_cell_radius_are_always_single_spheres() {
    let mut rng = Rng(11);
    for _ in 0..3000 {
        let center = Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) + Vec3::splat(3.0);
        let grid = ScalarGrid::from_fn(Vec3::ZERO, 1.0, [8, 8, 8], |p| (p - center).length() - 1.0)
            .unwrap();
        let topology = marching_cubes(&grid, 0.0).topology();
        assert_eq!(
            (topology.components.len(), topology.total_genus()),
            (1, 0),
            "ball at {center}"
        );
    }
}
