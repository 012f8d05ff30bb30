//! Bar 1 of issue 5: every analytic Jacobian of the coarse energy checked against central finite
//! differences of its residuals, and everything built from them (`Jᵀr`, the assembled `JᵀJ`, the
//! matrix-free product, the graph-pattern bound) checked against the Jacobian; and the
//! single-precision factor that preconditions the coarse solves checked to solve `JᵀJ`.

use glam::{DVec3, Vec3};

use super::assemble::assemble;
use super::cholesky::Cholesky;
use super::energy::{
    CoarseWeights, FitTarget, energy, fit_pulls, gradient, rigid_jacobian, rigid_residuals,
    smooth_psi, smooth_residual,
};
use super::graph::DeformationGraph;
use super::model::{Model, NODE_DOFS, Units};
use super::operator::GaussNewton;
use super::pattern::{Coupling, Pattern};
use crate::mesh::IndexedMesh;

/// A deterministic pseudo-random sequence in [-1, 1).
struct Noise(u64);

impl Noise {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }

    fn vec3(&mut self) -> DVec3 {
        DVec3::new(self.next(), self.next(), self.next())
    }
}

struct Problem {
    model: Model,
    x: Vec<f64>,
    targets: Vec<Option<FitTarget>>,
    w: CoarseWeights,
}

fn problem() -> Problem {
    let mesh = IndexedMesh::icosphere(Vec3::new(0.3, -0.2, 0.1), 1.3, 2);
    let unit = mesh.mean_edge_length();
    let graph = DeformationGraph::build(
        &mesh,
        &super::GraphOptions {
            spacing: 2.5,
            skinning_nodes: 4,
            ..Default::default()
        },
    )
    .unwrap();
    let units = Units::new(&mesh.positions, unit);
    let rest: Vec<DVec3> = mesh.positions.iter().map(|&p| units.to_local(p)).collect();
    let all: Vec<u32> = (0..rest.len() as u32).collect();
    let model = Model::new(&graph, &rest, &all, &units);
    let mut noise = Noise(7);
    let mut x = model.identity();
    for v in &mut x {
        *v += 0.2 * noise.next();
    }
    let targets = rest
        .iter()
        .enumerate()
        .map(|(v, &p)| {
            (v % 5 != 0).then(|| FitTarget {
                point: p + 0.7 * noise.vec3(),
                normal: noise.vec3().normalize(),
            })
        })
        .collect();
    let w = CoarseWeights {
        fit: 0.7,
        plane: 1.0,
        point: 0.1,
        reg: 3.0,
        smooth: 0.1,
    };
    Problem {
        model,
        x,
        targets,
        w,
    }
}

/// Every residual of `E_tot`, scaled by the square root of its weight so `Σ r² = E_tot`.
fn residuals(p: &Problem, x: &[f64]) -> Vec<f64> {
    let w = &p.w;
    let mut r = Vec::new();
    for (v, target) in p.targets.iter().enumerate() {
        if let Some(t) = target {
            let d = p.model.deform_vertex(x, v) - t.point;
            r.push((w.fit * w.plane).sqrt() * t.normal.dot(d));
            r.extend(((w.fit * w.point).sqrt() * d).to_array());
        }
    }
    for i in 0..p.model.node_count() {
        r.extend(rigid_residuals(&x[NODE_DOFS * i..][..NODE_DOFS]).map(|v| w.reg.sqrt() * v));
    }
    for i in 0..p.model.node_count() {
        for &j in p.model.node_neighbours(i) {
            let s = smooth_residual(&p.model, x, i, j as usize);
            r.extend(((w.reg * w.smooth).sqrt() * s).to_array());
        }
    }
    r
}

/// The analytic Jacobian of [`residuals`], row by row, from the model's own pieces.
fn jacobian(p: &Problem) -> Vec<Vec<f64>> {
    let (w, m, n) = (&p.w, &p.model, p.model.unknowns());
    let mut rows = Vec::new();
    for (v, target) in p.targets.iter().enumerate() {
        let Some(t) = target else { continue };
        let mut position = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
        for s in m.skin_range(v) {
            let node = m.skin_nodes[s] as usize;
            for c in 0..4 {
                for (k, row) in position.iter_mut().enumerate() {
                    row[NODE_DOFS * node + 3 * c + k] = m.skin_u[s][c];
                }
            }
        }
        let plane = (w.fit * w.plane).sqrt();
        rows.push(
            (0..n)
                .map(|q| plane * (0..3).map(|k| t.normal[k] * position[k][q]).sum::<f64>())
                .collect(),
        );
        for row in &position {
            rows.push(row.iter().map(|a| (w.fit * w.point).sqrt() * a).collect());
        }
    }
    for i in 0..m.node_count() {
        for jac in rigid_jacobian(&p.x[NODE_DOFS * i..][..NODE_DOFS]) {
            let mut row = vec![0.0; n];
            for (q, a) in jac.iter().enumerate() {
                row[NODE_DOFS * i + q] = w.reg.sqrt() * a;
            }
            rows.push(row);
        }
    }
    let ws = (w.reg * w.smooth).sqrt();
    for i in 0..m.node_count() {
        for &j in m.node_neighbours(i) {
            let psi = smooth_psi(m, i, j as usize);
            for k in 0..3 {
                let mut row = vec![0.0; n];
                for (c, &a) in psi.iter().enumerate() {
                    row[NODE_DOFS * i + 3 * c + k] = ws * a;
                }
                row[NODE_DOFS * j as usize + 9 + k] = -ws;
                rows.push(row);
            }
        }
    }
    rows
}

/// The stored entries `(row, column, value)` of the upper triangle of a matrix in `pattern`.
fn entries<'a>(
    pattern: &'a Pattern,
    values: &'a [f64],
) -> impl Iterator<Item = (usize, usize, f64)> + 'a {
    pattern
        .col_ptr
        .windows(2)
        .enumerate()
        .flat_map(move |(col, range)| {
            (range[0] as usize..range[1] as usize)
                .map(move |k| (pattern.row_idx[k] as usize, col, values[k]))
        })
}

/// The fit term's 3×3 matrix of every sample of `p` (zero without a correspondence).
fn fit_matrices(p: &Problem) -> Vec<[[f64; 3]; 3]> {
    p.targets
        .iter()
        .map(|c| c.map_or([[0.0; 3]; 3], |c| p.w.fit_matrix(c.normal)))
        .collect()
}

/// `JᵀJ` of `p` at its state, assembled on the pattern of `coupling`.
fn assembled(p: &Problem, coupling: Coupling) -> (Pattern, Vec<f64>) {
    let fit = fit_matrices(p);
    let pattern = Pattern::new(&p.model, coupling).unwrap();
    let mut values = vec![0.0; pattern.row_idx.len()];
    assemble(&pattern, &p.model, &p.x, &fit, &p.w, &mut values);
    (pattern, values)
}

fn max_abs(values: impl Iterator<Item = f64>) -> f64 {
    values.fold(0.0, |m, v| m.max(v.abs()))
}

#[test]
fn jacobians_match_finite_differences() {
    let p = problem();
    let analytic = jacobian(&p);
    let h = 1e-6;
    let mut worst = 0.0f64;
    let scale = max_abs(analytic.iter().flatten().copied());
    for q in 0..p.model.unknowns() {
        let mut plus = p.x.clone();
        let mut minus = p.x.clone();
        plus[q] += h;
        minus[q] -= h;
        let (rp, rm) = (residuals(&p, &plus), residuals(&p, &minus));
        for (row, (a, b)) in analytic.iter().zip(rp.iter().zip(&rm)) {
            let numeric = (a - b) / (2.0 * h);
            worst = worst.max((row[q] - numeric).abs());
        }
    }
    let relative = worst / scale;
    println!("Jacobian max relative error vs central differences: {relative:e}");
    assert!(relative < 1e-6, "Jacobian relative error {relative:e}");
}

#[test]
fn energy_is_the_sum_of_squared_residuals() {
    let p = problem();
    let deformed = p.model.deform(&p.x);
    let e = energy(&p.model, &p.x, &deformed, &p.targets, &p.w).total(&p.w);
    let sum: f64 = residuals(&p, &p.x).iter().map(|r| r * r).sum();
    assert!((e - sum).abs() <= 1e-12 * sum, "{e} vs {sum}");
}

#[test]
fn gradient_hessian_and_product_come_from_the_jacobian() {
    let p = problem();
    let (j, r) = (jacobian(&p), residuals(&p, &p.x));
    let n = p.model.unknowns();
    let jtr: Vec<f64> = (0..n)
        .map(|q| j.iter().zip(&r).map(|(row, r)| row[q] * r).sum())
        .collect();
    let deformed = p.model.deform(&p.x);
    let g = gradient(
        &p.model,
        &p.x,
        &fit_pulls(&deformed, &p.targets, &p.w),
        &p.w,
    );
    let scale = max_abs(jtr.iter().copied());
    let error = max_abs(g.iter().zip(&jtr).map(|(a, b)| a - b));
    assert!(
        error < 1e-10 * scale,
        "gradient error {error:e} of {scale:e}"
    );

    let jtj = |a: usize, b: usize| -> f64 { j.iter().map(|row| row[a] * row[b]).sum() };
    let fit = fit_matrices(&p);
    let (pattern, values) = assembled(&p, Coupling::Full);
    let mut dense = vec![vec![0.0; n]; n];
    for (row, col, value) in entries(&pattern, &values) {
        dense[row][col] = value;
        dense[col][row] = value;
    }
    let scale = max_abs((0..n).map(|a| jtj(a, a)));
    let error = max_abs(
        (0..n)
            .flat_map(|a| (0..n).map(move |b| (a, b)))
            .map(|(a, b)| dense[a][b] - jtj(a, b)),
    );
    assert!(error < 1e-10 * scale, "JᵀJ error {error:e} of {scale:e}");

    let mut noise = Noise(11);
    let v: Vec<f64> = (0..n).map(|_| noise.next()).collect();
    let operator = GaussNewton {
        model: &p.model,
        x: &p.x,
        fit: &fit,
        weights: p.w,
        damping: 0.5,
    };
    let mut product = vec![0.0; n];
    operator.apply(&v, &mut product);
    let expected: Vec<f64> = (0..n)
        .map(|a| (0..n).map(|b| dense[a][b] * v[b]).sum::<f64>() + 0.5 * v[a])
        .collect();
    let error = max_abs(product.iter().zip(&expected).map(|(a, b)| a - b));
    assert!(
        error < 1e-10 * max_abs(expected.iter().copied()),
        "product error {error:e}"
    );

    let (bound, bound_values) = assembled(&p, Coupling::Graph);
    let quadratic = |values: &[f64], pattern: &Pattern, v: &[f64]| -> f64 {
        entries(pattern, values)
            .map(|(row, col, value)| {
                let factor = if row == col { 1.0 } else { 2.0 };
                factor * value * v[row] * v[col]
            })
            .sum()
    };
    for trial in 0..20 {
        let v: Vec<f64> = (0..n).map(|_| noise.next()).collect();
        let (exact, upper) = (
            quadratic(&values, &pattern, &v),
            quadratic(&bound_values, &bound, &v),
        );
        assert!(
            upper >= exact * (1.0 - 1e-12),
            "trial {trial}: bound {upper} < {exact}"
        );
    }
}

/// The Jacobi-scaled `f32` factor of the exact `JᵀJ` solves it to single precision times the
/// (scaled) conditioning: it is a preconditioner, so it only has to be close.
#[test]
fn single_precision_factor_solves_the_gauss_newton_matrix() {
    let p = problem();
    let n = p.model.unknowns();
    let (pattern, values) = assembled(&p, Coupling::Full);
    let mut cholesky = Cholesky::analyze(&pattern, faer::Par::Seq).unwrap();
    cholesky.factor(&pattern, &values).unwrap();
    let mut noise = Noise(5);
    let rhs: Vec<f64> = (0..n).map(|_| noise.next()).collect();
    let mut x = rhs.clone();
    cholesky.solve(&mut x).unwrap();
    let mut hx = vec![0.0; n];
    for (row, col, value) in entries(&pattern, &values) {
        hx[row] += value * x[col];
        if row != col {
            hx[col] += value * x[row];
        }
    }
    let error = max_abs(hx.iter().zip(&rhs).map(|(a, b)| a - b));
    assert!(
        error < 1e-3 * max_abs(rhs.iter().copied()),
        "residual {error:e}"
    );
}
