//! Preconditioned conjugate gradients on flat `f64` vectors, with dot products summed in a fixed
//! order so the iterates do not depend on the thread count.

use rayon::prelude::*;

use super::model::ordered_sum;

/// How a solve ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Solve {
    pub iterations: usize,
    /// `|b − A x| / |b|` at the end.
    pub residual: f64,
    pub converged: bool,
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    ordered_sum(a.len(), |i| a[i] * b[i])
}

/// Solves `A x = b` from the `x` given, for symmetric positive (semi)definite `A` applied by
/// `apply(v, out)` and a preconditioner applied by `precondition(r, z)`; stops when the residual
/// falls below `tolerance · |b|` or after `max_iterations`.
pub fn pcg(
    apply: impl Fn(&[f64], &mut [f64]),
    mut precondition: impl FnMut(&[f64], &mut [f64]),
    b: &[f64],
    x: &mut [f64],
    tolerance: f64,
    max_iterations: usize,
) -> Solve {
    let n = b.len();
    let b_norm = dot(b, b).sqrt();
    if b_norm == 0.0 {
        x.iter_mut().for_each(|v| *v = 0.0);
        return Solve {
            iterations: 0,
            residual: 0.0,
            converged: true,
        };
    }
    let mut ax = vec![0.0; n];
    apply(x, &mut ax);
    let mut r: Vec<f64> = b.iter().zip(&ax).map(|(b, a)| b - a).collect();
    let mut residual = dot(&r, &r).sqrt() / b_norm;
    // A start that already meets the tolerance (the coarse stage's direct solve from a fresh
    // factor) needs no preconditioned residual.
    if residual <= tolerance || max_iterations == 0 {
        return Solve {
            iterations: 0,
            residual,
            converged: residual <= tolerance,
        };
    }
    let mut z = vec![0.0; n];
    precondition(&r, &mut z);
    let mut p = z.clone();
    let mut rz = dot(&r, &z);
    let mut iterations = 0;
    while residual > tolerance && iterations < max_iterations {
        if iterations > 0 {
            // The next direction, only once the residual has been found short of the tolerance:
            // the preconditioner (a pair of triangular solves in the coarse stage) is the
            // iteration's main cost, and the last iteration needs none.
            precondition(&r, &mut z);
            let rz_next = dot(&r, &z);
            let beta = rz_next / rz;
            rz = rz_next;
            p.par_iter_mut()
                .zip(&z)
                .for_each(|(p, z)| *p = z + beta * *p);
        }
        apply(&p, &mut ax);
        let pap = dot(&p, &ax);
        if !(pap > 0.0 && pap.is_finite()) {
            break;
        }
        let alpha = rz / pap;
        x.par_iter_mut().zip(&p).for_each(|(x, p)| *x += alpha * p);
        r.par_iter_mut().zip(&ax).for_each(|(r, a)| *r -= alpha * a);
        residual = dot(&r, &r).sqrt() / b_norm;
        iterations += 1;
    }
    Solve {
        iterations,
        residual,
        converged: residual <= tolerance,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::Cell;

    /// `A = diag(d)` applied to `v`.
    fn diagonal(d: &[f64]) -> impl Fn(&[f64], &mut [f64]) + '_ {
        move |v, out| {
            for ((o, v), d) in out.iter_mut().zip(v).zip(d) {
                *o = v * d;
            }
        }
    }

    fn identity(r: &[f64], z: &mut [f64]) {
        z.copy_from_slice(r);
    }

    /// A start that already solves the system is returned as it is, without a preconditioned
    /// residual (the coarse stage's direct solve from a fresh factor usually is one).
    #[test]
    fn a_start_within_the_tolerance_needs_no_preconditioner() {
        let d: Vec<f64> = (1..=50).map(|i| i as f64).collect();
        let b: Vec<f64> = d.iter().map(|d| 2.0 * d).collect();
        let mut x = vec![2.0; 50];
        let calls = Cell::new(0);
        let solve = pcg(
            diagonal(&d),
            |r, z| {
                calls.set(calls.get() + 1);
                identity(r, z)
            },
            &b,
            &mut x,
            1e-6,
            100,
        );
        assert_eq!(solve.iterations, 0);
        assert!(solve.converged);
        assert_eq!(calls.get(), 0);
        assert_eq!(x, vec![2.0; 50]);
    }
}
