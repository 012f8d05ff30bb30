//! Levenberg-Marquardt damping of the coarse stage's Gauss-Newton steps (paper §4.2 solves each
//! step with Gauss-Newton; thesis §3.3.3 damps a step that raises the energy), updated by
//! Nielsen's rule (Madsen, Nielsen & Tingleff 2004, "Methods for Non-linear Least Squares
//! Problems", §3.2): after an accepted step the damping falls by how well the step's energy fall
//! matched the fall its linearization predicted; after a rejected one it rises by a factor that
//! doubles with each rejection in a row.
//!
//! The rule it replaces divided the damping by 10 after every accepted step and multiplied it by
//! 10 after every rejected one. On real fluid frames the next trial then overshot and was rejected
//! iteration after iteration, each rejection costing a solve (docs/performance.md, "Nielsen's
//! damping"); this rule settles at the damping the steps need.

/// Damping relative to the mean diagonal of the matrix on the first rise from none; below it an
/// accepted step's damping falls to none.
const FIRST_DAMPING: f64 = 1e-6;

/// The factor the first rejection after an accepted step raises a nonzero damping by (Nielsen's
/// `ν`).
const FIRST_RAISE: f64 = 2.0;

/// The most an accepted step lowers the damping by (Nielsen's 1/3): a step that fits its
/// linearization perfectly still leaves enough damping that the next one rarely overshoots.
const MOST_LOWERED: f64 = 1.0 / 3.0;

/// The damping `λ` of `(JᵀJ + λ I) δ = −Jᵀr`, and how far the next rejection raises it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Damping {
    lambda: f64,
    raise_by: f64,
}

impl Damping {
    /// No damping: a plain Gauss-Newton step.
    pub(super) fn none() -> Self {
        Self {
            lambda: 0.0,
            raise_by: FIRST_RAISE,
        }
    }

    pub(super) fn lambda(&self) -> f64 {
        self.lambda
    }

    /// After a rejected step (or a non-positive pivot): `scale` (the matrix's mean diagonal) times
    /// [`FIRST_DAMPING`] from none, else the damping times the current factor; either way the
    /// factor then doubles.
    pub(super) fn raise(&mut self, scale: f64) {
        self.lambda = if self.lambda > 0.0 {
            self.lambda * self.raise_by
        } else {
            scale * FIRST_DAMPING
        };
        self.raise_by *= 2.0;
    }

    /// After an accepted step with gain ratio `gain` (actual over predicted energy fall, see
    /// [`gain_ratio`]): the damping times `max(1/3, 1 − (2 gain − 1)³)`, which lowers it by up to
    /// three where the step fit its linearization and raises it where the step barely helped
    /// (`gain` < ½); none once it falls below `scale` × [`FIRST_DAMPING`].
    pub(super) fn lower(&mut self, gain: f64, scale: f64) {
        self.lambda *= MOST_LOWERED.max(1.0 - (2.0 * gain - 1.0).powi(3));
        if self.lambda < scale * FIRST_DAMPING {
            self.lambda = 0.0;
        }
        self.raise_by = FIRST_RAISE;
    }
}

/// Actual over predicted fall of a step `δ` that solves `(JᵀJ + λ I) δ = −Jᵀr`, where `along` is
/// `−Jᵀr · δ` and `length` is `|δ|²`. The energy is a sum of squares `|r|²`, so the predicted fall
/// `|r|² − |r + J δ|² = −2 Jᵀr · δ − δᵀJᵀJ δ` is `−Jᵀr · δ + λ |δ|²`. A step whose prediction is
/// not a fall (a solve far from converged) counts as fitting.
pub(super) fn gain_ratio(actual: f64, along: f64, length: f64, lambda: f64) -> f64 {
    let predicted = along + lambda * length;
    if predicted > 0.0 {
        actual / predicted
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejections_in_a_row_raise_by_doubling_factors() {
        let mut d = Damping::none();
        d.raise(5.0);
        assert_eq!(d.lambda(), 5.0 * FIRST_DAMPING);
        // The rise from none counts as the first: the next rises by 4, then 8.
        d.raise(5.0);
        assert_eq!(d.lambda(), 5.0 * FIRST_DAMPING * 4.0);
        d.raise(5.0);
        assert_eq!(d.lambda(), 5.0 * FIRST_DAMPING * 32.0);
    }

    #[test]
    fn an_accepted_step_lowers_by_its_gain_and_restarts_the_raises() {
        let mut d = Damping::none();
        d.raise(1.0);
        d.raise(1.0);
        d.raise(1.0);
        let lambda = d.lambda();
        // A perfect fit lowers by three.
        d.lower(1.0, 1.0);
        assert!((d.lambda() - lambda / 3.0).abs() <= 1e-15 * lambda);
        // Half the predicted fall keeps the damping; a quarter raises it by 1 + 1/8.
        let lambda = d.lambda();
        d.lower(0.5, 1.0);
        assert_eq!(d.lambda(), lambda);
        d.lower(0.25, 1.0);
        assert!((d.lambda() - lambda * 1.125).abs() <= 1e-15 * lambda);
        // The next rejection raises by the first factor again.
        let lambda = d.lambda();
        d.raise(1.0);
        assert_eq!(d.lambda(), lambda * FIRST_RAISE);
    }

    #[test]
    fn damping_below_the_first_falls_to_none() {
        let mut d = Damping::none();
        d.raise(1.0);
        d.lower(1.0, 1.0);
        assert_eq!(d.lambda(), 0.0);
        d.raise(1.0);
        assert_eq!(d.lambda(), FIRST_DAMPING);
    }

    #[test]
    fn the_gain_ratio_of_an_exact_quadratic_step_is_one() {
        // E(x) = (a x − b)², one unknown: J = a, r = a x − b; the damped step from x = 0 is
        // δ = a b / (a² + λ), and on a quadratic the actual fall is the predicted one.
        let (a, b, lambda) = (2.0_f64, 3.0_f64, 0.5_f64);
        let delta = a * b / (a * a + lambda);
        let actual = b * b - (a * delta - b).powi(2);
        let along = a * b * delta;
        let gain = gain_ratio(actual, along, delta * delta, lambda);
        assert!((gain - 1.0).abs() < 1e-12, "{gain}");
        assert_eq!(gain_ratio(1.0, -1.0, 0.0, 0.0), 1.0);
    }
}
