//! Rigid pre-alignment: point-to-plane ICP (Chen & Medioni 1992) with the coarse stage's own fit
//! term, `Σ α_plane (n·(x − c))² + α_point |x − c|²` over the fit samples, before any graph stage.
//!
//! The first stage (`α_reg = 1000`) is nearly rigid, and non-rigid ICP spends most of its
//! iterations there walking the correspondences towards the rigid alignment, each iteration paying
//! for a sparse solve. A 6-unknown rigid ICP gets there with projections alone; the graph stages
//! then start from it (every node transformed by the same rigid motion).

use glam::{DMat3, DQuat, DVec3, Vec3};

use super::energy::FitTarget;

/// Stop when a step turns by less than this (radians)…
const MIN_TURN: f64 = 1e-6;
/// …and moves by less than this (mean edge lengths).
const MIN_MOVE: f64 = 1e-4;

/// A rigid motion `x ↦ R x + t` in solver coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rigid {
    pub rotation: DQuat,
    pub translation: DVec3,
}

impl Rigid {
    pub const IDENTITY: Rigid = Rigid {
        rotation: DQuat::IDENTITY,
        translation: DVec3::ZERO,
    };

    pub fn apply(&self, p: DVec3) -> DVec3 {
        self.rotation * p + self.translation
    }
}

/// The fit energy of rigidly moved samples against their targets.
fn fit_energy(points: &[DVec3], targets: &[Option<FitTarget>], plane: f64, point: f64) -> f64 {
    points
        .iter()
        .zip(targets)
        .filter_map(|(&x, t)| {
            t.map(|t| {
                let r = x - t.point;
                plane * t.normal.dot(r).powi(2) + point * r.length_squared()
            })
        })
        .sum()
}

/// One Gauss-Newton step of the rigid fit: the rotation vector `ω` and translation `τ` minimizing
/// the linearized energy of `x + ω × (x − x̄) + τ`, or `None` when fewer than six independent
/// constraints exist.
fn step(
    points: &[DVec3],
    targets: &[Option<FitTarget>],
    plane: f64,
    point: f64,
) -> Option<(DVec3, DVec3, DVec3)> {
    let matched: Vec<(DVec3, FitTarget)> = points
        .iter()
        .zip(targets)
        .filter_map(|(&x, t)| t.map(|t| (x, t)))
        .collect();
    if matched.len() < 6 {
        return None;
    }
    let centre = matched.iter().fold(DVec3::ZERO, |a, (x, _)| a + *x) / matched.len() as f64;
    let mut h = [[0.0f64; 6]; 6];
    let mut g = [0.0f64; 6];
    let mut add = |row: [f64; 6], residual: f64, weight: f64| {
        for a in 0..6 {
            g[a] += weight * row[a] * residual;
            for b in 0..6 {
                h[a][b] += weight * row[a] * row[b];
            }
        }
    };
    for (x, t) in &matched {
        let q = *x - centre;
        let r = *x - t.point;
        let n = t.normal;
        let qn = q.cross(n);
        add([qn.x, qn.y, qn.z, n.x, n.y, n.z], n.dot(r), plane);
        for k in 0..3 {
            let mut e = DVec3::ZERO;
            e[k] = 1.0;
            let qe = q.cross(e);
            let mut row = [qe.x, qe.y, qe.z, 0.0, 0.0, 0.0];
            row[3 + k] = 1.0;
            add(row, r[k], point);
        }
    }
    let delta = solve6(h, g.map(|v| -v))?;
    Some((
        DVec3::new(delta[0], delta[1], delta[2]),
        DVec3::new(delta[3], delta[4], delta[5]),
        centre,
    ))
}

/// Solves the symmetric positive definite 6×6 system `h x = g` (Cholesky); `None` if singular.
fn solve6(h: [[f64; 6]; 6], g: [f64; 6]) -> Option<[f64; 6]> {
    let scale = (0..6).map(|k| h[k][k]).fold(0.0, f64::max);
    let mut l = [[0.0f64; 6]; 6];
    for i in 0..6 {
        for j in 0..=i {
            let s: f64 = h[i][j] - (0..j).map(|k| l[i][k] * l[j][k]).sum::<f64>();
            if i == j {
                if s <= 1e-12 * scale {
                    return None;
                }
                l[i][i] = s.sqrt();
            } else {
                l[i][j] = s / l[j][j];
            }
        }
    }
    let mut y = [0.0f64; 6];
    for i in 0..6 {
        y[i] = (g[i] - (0..i).map(|k| l[i][k] * y[k]).sum::<f64>()) / l[i][i];
    }
    let mut x = [0.0f64; 6];
    for i in (0..6).rev() {
        x[i] = (y[i] - (i + 1..6).map(|k| l[k][i] * x[k]).sum::<f64>()) / l[i][i];
    }
    Some(x)
}

/// What the pre-alignment did.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Prealignment {
    /// Fit energy of each accepted pose with its fresh correspondences, the start included; it only
    /// falls (a pose that would raise it ends the iteration and is discarded).
    pub energies: Vec<f64>,
}

/// Rigid ICP of the samples `rest` (solver coordinates) with unit normals `normals`:
/// `project(points, normals)` gives their correspondences at a pose. Stops once a negligible step
/// has been taken (and its pose evaluated), when the energy stops falling, or after
/// `max_iterations`; returns the best pose.
pub fn prealign<E>(
    rest: &[DVec3],
    normals: &[Vec3],
    plane: f64,
    point: f64,
    max_iterations: usize,
    mut project: impl FnMut(&[DVec3], &[Vec3]) -> Result<Vec<Option<FitTarget>>, E>,
) -> Result<(Rigid, Prealignment), E> {
    let mut pose = Rigid::IDENTITY;
    let mut report = Prealignment::default();
    let mut best = (f64::INFINITY, pose);
    let mut settled = false;
    for _ in 0..=max_iterations {
        let points: Vec<DVec3> = rest.iter().map(|&p| pose.apply(p)).collect();
        let turned: Vec<Vec3> = normals
            .iter()
            .map(|&n| (pose.rotation * n.as_dvec3()).as_vec3())
            .collect();
        let targets = project(&points, &turned)?;
        let e = fit_energy(&points, &targets, plane, point);
        if e >= best.0 {
            break;
        }
        report.energies.push(e);
        best = (e, pose);
        if settled {
            break;
        }
        let Some((omega, tau, centre)) = step(&points, &targets, plane, point) else {
            break;
        };
        let turn = DQuat::from_scaled_axis(omega);
        pose = Rigid {
            rotation: (turn * pose.rotation).normalize(),
            translation: turn * (pose.translation - centre) + centre + tau,
        };
        settled = omega.length() < MIN_TURN && tau.length() < MIN_MOVE;
    }
    Ok((best.1, report))
}

/// The node unknowns that move every vertex by `pose`: `A_i = R`, `b_i = R g_i + t − g_i`.
pub fn node_unknowns(pose: &Rigid, nodes: &[DVec3]) -> Vec<f64> {
    let r = DMat3::from_quat(pose.rotation);
    nodes
        .iter()
        .flat_map(|&g| {
            let b = pose.apply(g) - g;
            let c = r.to_cols_array();
            [
                c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], c[8], b.x, b.y, b.z,
            ]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_a_rigid_motion_of_a_point_set() {
        // Points on an ellipsoid; their targets are the moved points with moved normals.
        let truth = Rigid {
            rotation: DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 0.5).normalize(), 0.3),
            translation: DVec3::new(0.5, -0.2, 0.3),
        };
        let mut rest = Vec::new();
        let mut normals = Vec::new();
        for i in 0..20 {
            for j in 0..40 {
                let (u, v) = (
                    std::f64::consts::PI * (i as f64 + 0.5) / 20.0,
                    std::f64::consts::TAU * j as f64 / 40.0,
                );
                let d = DVec3::new(u.sin() * v.cos(), u.sin() * v.sin(), u.cos());
                rest.push(DVec3::new(3.0 * d.x, 2.0 * d.y, 1.5 * d.z));
                normals.push(
                    DVec3::new(d.x / 3.0, d.y / 2.0, d.z / 1.5)
                        .normalize()
                        .as_vec3(),
                );
            }
        }
        let moved: Vec<DVec3> = rest.iter().map(|&p| truth.apply(p)).collect();
        let moved_normals: Vec<DVec3> = normals
            .iter()
            .map(|n| truth.rotation * n.as_dvec3())
            .collect();
        // Correspondence: the nearest moved point (brute force), as a tiny stand-in for projection.
        let project = |points: &[DVec3], _: &[Vec3]| -> Result<Vec<Option<FitTarget>>, ()> {
            Ok(points
                .iter()
                .map(|p| {
                    let k = (0..moved.len())
                        .min_by(|&a, &b| {
                            p.distance_squared(moved[a])
                                .total_cmp(&p.distance_squared(moved[b]))
                        })
                        .unwrap_or(0);
                    Some(FitTarget {
                        point: moved[k],
                        normal: moved_normals[k],
                    })
                })
                .collect())
        };
        let (pose, report) = prealign(&rest, &normals, 1.0, 0.1, 50, project).unwrap();
        let error = rest
            .iter()
            .map(|&p| pose.apply(p).distance(truth.apply(p)))
            .fold(0.0, f64::max);
        assert!(
            error < 1e-6,
            "error {error}, energies {:?}",
            report.energies
        );
        assert!(report.energies.windows(2).all(|w| w[1] <= w[0]));
    }
}
