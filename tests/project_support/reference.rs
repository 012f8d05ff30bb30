//! f64 references for the `project_*` tests: nearest points, distances, line–plane hits.

use glam::{DVec3, Vec3};
use surftrack::mesh::IndexedMesh;

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
