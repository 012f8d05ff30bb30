//! How well a mesh meets the improvement criteria, per triangle: the measure behind the "≥ 99.5% of
//! triangles" bar and the histograms in reports.

use super::ImproveParams;
use super::geometry::{dihedral_degrees, edge_extremes, face_normal, min_angle};
use crate::geometry::{ANGLE_BUCKETS, bucket};
use crate::mesh::IndexedMesh;
use serde::Serialize;

/// Upper ends of the edge-length histogram buckets, relative to the target length `L`.
pub const LENGTH_BUCKETS: [f32; 8] = [0.125, 0.25, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0];

/// Upper ends of the histogram buckets of each triangle's longest : shortest edge ratio; the
/// criterion is the parameters' `edge_ratio` (paper: 4).
pub const RATIO_BUCKETS: [f32; 6] = [1.5, 2.0, 3.0, 4.0, 6.0, 8.0];

/// A triangle that fails the criteria, and by how much (the frame-level quality measure is
/// `eval::TriangleQuality`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FailingTriangle {
    pub triangle: usize,
    pub min_angle: f32,
    /// Shortest and longest edge relative to the target length.
    pub shortest: f32,
    pub longest: f32,
}

/// Counts of triangles (and edges) that break each criterion.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Assessment {
    pub triangles: usize,
    /// Smallest interior angle below the minimum.
    pub small_angle: usize,
    /// An edge outside `[min_edge_length, max_edge_length]`.
    pub edge_out_of_band: usize,
    /// Longest : shortest edge of the triangle above `edge_ratio`.
    pub ratio_exceeded: usize,
    /// Triangles breaking the angle or the edge-ratio criterion.
    pub failing: usize,
    pub edges: usize,
    /// Edges whose faces meet below the minimum dihedral angle.
    pub sharp_edges: usize,
    /// Triangles per bucket of `ANGLE_BUCKETS` (one more for the rest).
    pub min_angle_histogram: Vec<usize>,
    /// Triangles per bucket of `RATIO_BUCKETS` (one more for the rest).
    pub edge_ratio_histogram: Vec<usize>,
    /// Edges per bucket of `LENGTH_BUCKETS` (one more for the rest).
    pub edge_length_histogram: Vec<usize>,
    /// The failing triangles, smallest angle first.
    pub worst: Vec<FailingTriangle>,
}

impl Assessment {
    /// Fraction of triangles meeting both the angle and the edge-ratio criteria.
    pub fn passing_fraction(&self) -> f64 {
        if self.triangles == 0 {
            return 1.0;
        }
        1.0 - self.failing as f64 / self.triangles as f64
    }
}

/// Measures every triangle and edge of `mesh` against `params`.
pub fn assess(mesh: &IndexedMesh, params: &ImproveParams) -> Assessment {
    let (lo, hi, l) = (
        params.min_edge_length(),
        params.max_edge_length(),
        params.edge_length,
    );
    let mut out = Assessment {
        triangles: mesh.triangles.len(),
        small_angle: 0,
        edge_out_of_band: 0,
        ratio_exceeded: 0,
        failing: 0,
        edges: 0,
        sharp_edges: 0,
        min_angle_histogram: vec![0; ANGLE_BUCKETS.len() + 1],
        edge_ratio_histogram: vec![0; RATIO_BUCKETS.len() + 1],
        edge_length_histogram: vec![0; LENGTH_BUCKETS.len() + 1],
        worst: Vec::new(),
    };
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let p = tri.map(|v| mesh.positions[v as usize]);
        let angle = min_angle(p);
        let (shortest, longest) = edge_extremes(p);
        let small = angle < params.min_angle_degrees;
        let ratio = longest > params.edge_ratio * shortest;
        out.small_angle += usize::from(small);
        out.edge_out_of_band += usize::from(shortest < lo || longest > hi);
        out.ratio_exceeded += usize::from(ratio);
        out.min_angle_histogram[bucket(&ANGLE_BUCKETS, angle)] += 1;
        let proportion = if shortest > 0.0 {
            longest / shortest
        } else {
            f32::INFINITY
        };
        out.edge_ratio_histogram[bucket(&RATIO_BUCKETS, proportion)] += 1;
        if small || ratio {
            out.failing += 1;
            out.worst.push(FailingTriangle {
                triangle: t,
                min_angle: angle,
                shortest: shortest / l,
                longest: longest / l,
            });
        }
    }
    out.worst.sort_by(|a, b| {
        a.min_angle
            .total_cmp(&b.min_angle)
            .then(a.triangle.cmp(&b.triangle))
    });
    let edges = mesh.sorted_edges();
    for pair in edges.chunk_by(|x, y| (x.0, x.1) == (y.0, y.1)) {
        let (a, b) = (pair[0].0 as usize, pair[0].1 as usize);
        out.edges += 1;
        let length = mesh.positions[a].distance(mesh.positions[b]);
        out.edge_length_histogram[bucket(&LENGTH_BUCKETS, length / l)] += 1;
        if let [x, y] = pair {
            let n = |t: u32| {
                face_normal(mesh.triangles[t as usize].map(|v| mesh.positions[v as usize]))
            };
            let sharp = dihedral_degrees(n(x.3), n(y.3))
                .is_none_or(|angle| angle < params.min_dihedral_degrees);
            out.sharp_edges += usize::from(sharp);
        }
    }
    out
}
