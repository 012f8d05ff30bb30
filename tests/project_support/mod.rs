//! What the `project_*` tests share: a deterministic generator, the 100k-triangle synthetic frame,
//! f64 references, and the macro that runs a case on both backends.

#![allow(dead_code)]

use glam::{DVec3, Vec3};
use surftrack::grid::{ScalarGrid, marching_cubes};
use surftrack::mesh::{IndexedMesh, NormalWeighting};

/// SplitMix64: a small deterministic generator, so failures reproduce exactly.
pub struct Rng(pub u64);

impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.unit()
    }

    /// Uniform on the unit sphere.
    pub fn direction(&mut self) -> Vec3 {
        loop {
            let v = Vec3::new(
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            );
            let l = v.length();
            if l > 0.1 && l <= 1.0 {
                return v / l;
            }
        }
    }
}

/// Blended metaballs (three moving, one fixed) extracted by marching cubes on a `cells`³ grid:
/// a closed frame like a fluid cache's. `phase` moves the balls, `shift` the grid origin (in
/// cells), so two calls give two incoherent frames of the same scene.
pub fn metaballs(cells: usize, phase: f32, shift: f32) -> IndexedMesh {
    let balls = [
        (Vec3::new(-0.35 + 0.1 * phase.cos(), 0.05, 0.0), 0.42),
        (Vec3::new(0.35, -0.1 + 0.1 * phase.sin(), 0.1), 0.36),
        (Vec3::new(0.0, 0.4, -0.2 + 0.05 * phase), 0.3),
        (Vec3::new(0.1, -0.45, -0.3), 0.22),
    ];
    let size = 2.4f32;
    let spacing = size / cells as f32;
    let origin = Vec3::splat(-size / 2.0) + Vec3::splat(shift * spacing);
    let dims = [cells + 1; 3];
    let grid = ScalarGrid::from_fn(origin, spacing, dims, |p| {
        let sum: f32 = balls
            .iter()
            .map(|&(c, r)| r * r / (p - c).length_squared().max(1e-12))
            .sum();
        1.0 - sum
    })
    .expect("valid grid");
    marching_cubes(&grid, 0.0)
}

/// The benchmark workload: a 100k-triangle synthetic target frame, and a tracked mesh of the same
/// scene a moment later, meshed independently (about 100k vertices), whose vertices with their
/// normals are the queries: 200k normal rays counting both directions.
pub fn workload() -> (IndexedMesh, Vec<Vec3>, Vec<Vec3>) {
    let target = metaballs(176, 0.0, 0.0);
    let source = metaballs(250, 0.3, 0.37);
    let normals = source.vertex_normals(NormalWeighting::Max);
    (target, source.positions, normals)
}

/// The point of triangle `abc` nearest to `p`, in f64 (Ericson §5.1.5).
pub fn closest_on_triangle_f64(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> DVec3 {
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(ap);
    let d2 = ac.dot(ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let d3 = ab.dot(bp);
    let d4 = ac.dot(bp);
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let d5 = ab.dot(cp);
    let d6 = ac.dot(cp);
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

/// The distance from `p` to the mesh, by brute force in f64.
pub fn distance_f64(mesh: &IndexedMesh, p: Vec3) -> f64 {
    let p = p.as_dvec3();
    mesh.triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| mesh.positions[v as usize].as_dvec3());
            closest_on_triangle_f64(p, a, b, c).distance(p)
        })
        .fold(f64::INFINITY, f64::min)
}

/// Where the line `p + t·d` meets the plane of triangle `tri` of `mesh`, in f64.
pub fn line_plane_f64(mesh: &IndexedMesh, tri: u32, p: Vec3, d: Vec3) -> DVec3 {
    let [a, b, c] = mesh.triangles[tri as usize].map(|v| mesh.positions[v as usize].as_dvec3());
    let n = (b - a).cross(c - a);
    let (p, d) = (p.as_dvec3(), d.as_dvec3());
    p + d * (n.dot(a - p) / n.dot(d))
}

/// `#[test]` wrappers `<case>_cpu` and `<case>_gpu` for each `fn case(&Backend)`; the GPU one is
/// skipped without an adapter unless `SURFTRACK_REQUIRE_GPU=1`.
#[macro_export]
macro_rules! on_both_backends {
    ($($case:ident => $cpu:ident, $gpu:ident;)*) => {$(
        #[test]
        fn $cpu() {
            $case(&surftrack::compute::Backend::Cpu);
        }

        #[test]
        fn $gpu() {
            surftrack::compute::parity::run_on_gpu($case);
        }
    )*};
}
