//! Write a test once, run it on both backends (vello's `tests/property.rs`, cubecl's `testgen!`).
//!
//! A test case is a `fn case(backend: &Backend)`; its `_cpu` wrapper calls it with
//! [`Backend::Cpu`], its `_gpu` wrapper hands it to [`run_on_gpu`]. Results are compared through a
//! [`ParityReport`], which lists every disagreeing element rather than stopping at the first, and
//! does nothing until asserted (it is `#[must_use]`), so a comparison cannot be silently dropped.

use std::fmt::{self, Write as _};
use std::sync::OnceLock;

use glam::{DMat3, DVec3, Vec3};

use super::{Backend, BackendChoice, ComputeError};

/// Set to `1` to make a missing GPU adapter fail GPU tests instead of skipping them (CI sets it,
/// so the GPU path can never go untested unnoticed).
pub const REQUIRE_GPU_ENV: &str = "SURFTRACK_REQUIRE_GPU";

/// How many disagreeing elements an assertion message shows; the count is always exact.
const SHOWN: usize = 50;

/// One scalar of a compared value, kept in its own type so floats and integers are compared exactly.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Scalar {
    F32(f32),
    F64(f64),
    U32(u32),
    I32(i32),
}

impl Scalar {
    /// Same kind and same bits: `-0.0` differs from `0.0`, and a NaN equals only itself.
    fn identical(self, other: Self) -> bool {
        match (self, other) {
            (Self::F32(a), Self::F32(b)) => a.to_bits() == b.to_bits(),
            (Self::F64(a), Self::F64(b)) => a.to_bits() == b.to_bits(),
            (Self::U32(a), Self::U32(b)) => a == b,
            (Self::I32(a), Self::I32(b)) => a == b,
            _ => false,
        }
    }

    /// `|a - b|`, infinite when only one side is finite or the kinds differ.
    fn abs_diff(self, other: Self) -> f64 {
        if self.identical(other) {
            return 0.0;
        }
        match (self, other) {
            (Self::F32(a), Self::F32(b)) if a.is_finite() && b.is_finite() => {
                (f64::from(a) - f64::from(b)).abs()
            }
            (Self::F64(a), Self::F64(b)) if a.is_finite() && b.is_finite() => (a - b).abs(),
            (Self::U32(a), Self::U32(b)) => f64::from(a.abs_diff(b)),
            (Self::I32(a), Self::I32(b)) => f64::from(a.abs_diff(b)),
            _ => f64::INFINITY,
        }
    }
}

impl fmt::Display for Scalar {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::F32(x) => write!(f, "{x:?} ({:#010x})", x.to_bits()),
            Self::F64(x) => write!(f, "{x:?} ({:#018x})", x.to_bits()),
            Self::U32(x) => write!(f, "{x}"),
            Self::I32(x) => write!(f, "{x}"),
        }
    }
}

/// A value a kernel produces, seen as named scalar lanes (a box has six: `min.x` … `max.z`).
pub trait ParityValue: Copy {
    /// Lane names, in order; `[""]` for a plain scalar.
    const LANES: &'static [&'static str];
    fn lane(&self, k: usize) -> Scalar;
}

impl ParityValue for f32 {
    const LANES: &'static [&'static str] = &[""];
    fn lane(&self, _: usize) -> Scalar {
        Scalar::F32(*self)
    }
}

impl ParityValue for u32 {
    const LANES: &'static [&'static str] = &[""];
    fn lane(&self, _: usize) -> Scalar {
        Scalar::U32(*self)
    }
}

impl ParityValue for i32 {
    const LANES: &'static [&'static str] = &[""];
    fn lane(&self, _: usize) -> Scalar {
        Scalar::I32(*self)
    }
}

impl ParityValue for f64 {
    const LANES: &'static [&'static str] = &[""];
    fn lane(&self, _: usize) -> Scalar {
        Scalar::F64(*self)
    }
}

impl ParityValue for [f64; 2] {
    const LANES: &'static [&'static str] = &["0", "1"];
    fn lane(&self, k: usize) -> Scalar {
        Scalar::F64(self[k])
    }
}

impl ParityValue for DVec3 {
    const LANES: &'static [&'static str] = &["x", "y", "z"];
    fn lane(&self, k: usize) -> Scalar {
        Scalar::F64(self[k])
    }
}

impl ParityValue for DMat3 {
    const LANES: &'static [&'static str] = &["xx", "xy", "xz", "yx", "yy", "yz", "zx", "zy", "zz"];
    fn lane(&self, k: usize) -> Scalar {
        Scalar::F64(self.col(k / 3)[k % 3])
    }
}

impl ParityValue for Vec3 {
    const LANES: &'static [&'static str] = &["x", "y", "z"];
    fn lane(&self, k: usize) -> Scalar {
        Scalar::F32(self[k])
    }
}

/// One lane of one element where the two sides are not bit-identical.
#[derive(Debug, Clone, PartialEq)]
pub struct Difference {
    pub index: usize,
    pub lane: &'static str,
    pub left: Scalar,
    pub right: Scalar,
    pub abs_diff: f64,
}

/// The outcome of comparing two result arrays element by element.
#[must_use = "a ParityReport checks nothing until one of its assert methods is called"]
#[derive(Debug, Clone)]
pub struct ParityReport {
    what: String,
    left_name: &'static str,
    right_name: &'static str,
    left_len: usize,
    right_len: usize,
    differences: Vec<Difference>,
}

impl ParityReport {
    /// Compares a GPU result with its CPU twin's.
    pub fn gpu_vs_cpu<T: ParityValue>(what: &str, gpu: &[T], cpu: &[T]) -> Self {
        Self::compare(what, ("gpu", gpu), ("cpu", cpu))
    }

    /// Compares any two results, naming each side in messages (`("gpu", …)`, `("expected", …)`).
    pub fn compare<T: ParityValue>(
        what: &str,
        (left_name, left): (&'static str, &[T]),
        (right_name, right): (&'static str, &[T]),
    ) -> Self {
        let mut differences = Vec::new();
        for (index, (l, r)) in left.iter().zip(right).enumerate() {
            for (k, &lane) in T::LANES.iter().enumerate() {
                let (a, b) = (l.lane(k), r.lane(k));
                if !a.identical(b) {
                    differences.push(Difference {
                        index,
                        lane,
                        left: a,
                        right: b,
                        abs_diff: a.abs_diff(b),
                    });
                }
            }
        }
        Self {
            what: what.to_owned(),
            left_name,
            right_name,
            left_len: left.len(),
            right_len: right.len(),
            differences,
        }
    }

    /// Every lane that is not bit-identical, in element order.
    pub fn differences(&self) -> &[Difference] {
        &self.differences
    }

    pub fn lengths_match(&self) -> bool {
        self.left_len == self.right_len
    }

    /// The largest absolute difference over all lanes (0 when identical).
    pub fn max_abs_diff(&self) -> f64 {
        self.differences
            .iter()
            .map(|d| d.abs_diff)
            .fold(0.0, f64::max)
    }

    /// Panics unless both sides have the same length and identical bits everywhere.
    pub fn assert_identical(self) {
        let all: Vec<&Difference> = self.differences.iter().collect();
        self.assert_none(&all, "not bit-identical");
    }

    /// Panics unless both sides have the same length and every lane differs by less than `tol`.
    pub fn assert_max_abs_lt(self, tol: f64) {
        let over: Vec<&Difference> = self
            .differences
            .iter()
            .filter(|d| d.abs_diff.partial_cmp(&tol) != Some(std::cmp::Ordering::Less))
            .collect();
        self.assert_none(&over, &format!("|difference| >= {tol:e}"));
    }

    fn assert_none(&self, failing: &[&Difference], criterion: &str) {
        if failing.is_empty() && self.lengths_match() {
            return;
        }
        let mut message = format!("{}: {} vs {}", self.what, self.left_name, self.right_name);
        if !self.lengths_match() {
            let _ = write!(
                message,
                "\n  lengths differ: {} has {}, {} has {}",
                self.left_name, self.left_len, self.right_name, self.right_len
            );
        }
        if !failing.is_empty() {
            let mut indices: Vec<usize> = failing.iter().map(|d| d.index).collect();
            indices.dedup();
            let _ = write!(
                message,
                "\n  {} lanes in {} elements {criterion} (max |difference| {:e}):",
                failing.len(),
                indices.len(),
                self.max_abs_diff()
            );
            for d in failing.iter().take(SHOWN) {
                let lane = if d.lane.is_empty() {
                    String::new()
                } else {
                    format!(".{}", d.lane)
                };
                let _ = write!(
                    message,
                    "\n  [{}]{lane}: {} {} vs {} {} (|difference| {:e})",
                    d.index, self.left_name, d.left, self.right_name, d.right, d.abs_diff
                );
            }
            if failing.len() > SHOWN {
                let _ = write!(message, "\n  … and {} more", failing.len() - SHOWN);
            }
        }
        panic!("{message}");
    }
}

/// The GPU backend GPU tests run on: one device per test binary, opened on first use.
///
/// `None` (after printing why) when no adapter exists, unless [`REQUIRE_GPU_ENV`] is `1`; then the
/// missing adapter is an error for the caller to fail on.
pub fn test_gpu() -> Result<Option<Backend>, ComputeError> {
    static GPU: OnceLock<Result<Backend, ComputeError>> = OnceLock::new();
    match GPU.get_or_init(|| Backend::select(BackendChoice::Gpu)) {
        Ok(backend) => Ok(Some(backend.clone())),
        Err(error) if std::env::var(REQUIRE_GPU_ENV).is_ok_and(|v| v == "1") => Err(error.clone()),
        Err(error) => {
            eprintln!(
                "skipping GPU test ({error}); set {REQUIRE_GPU_ENV}=1 to make this a failure"
            );
            Ok(None)
        }
    }
}

/// Runs a test case on the GPU backend, or skips it as [`test_gpu`] says; a missing adapter while
/// [`REQUIRE_GPU_ENV`] is `1` fails the test.
pub fn run_on_gpu(case: impl FnOnce(&Backend)) {
    match test_gpu() {
        Ok(Some(backend)) => case(&backend),
        Ok(None) => {}
        Err(error) => panic!("{REQUIRE_GPU_ENV}=1 but no GPU backend is available: {error}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn panic_message(f: impl FnOnce() + std::panic::UnwindSafe) -> String {
        let payload = std::panic::catch_unwind(f).expect_err("the assertion should have failed");
        payload
            .downcast_ref::<String>()
            .cloned()
            .unwrap_or_default()
    }

    #[test]
    fn identical_arrays_pass() {
        let a = [1.0f32, -2.5, 3.25];
        ParityReport::gpu_vs_cpu("same", &a, &a).assert_identical();
        ParityReport::gpu_vs_cpu("same", &a, &a).assert_max_abs_lt(1e-30);
    }

    #[test]
    fn every_difference_is_counted_and_display_is_truncated() {
        let cpu: Vec<u32> = (0..1000).collect();
        let mut gpu = cpu.clone();
        for i in (0..1000).step_by(7) {
            gpu[i] += 1;
        }
        let report = ParityReport::gpu_vs_cpu("counts", &gpu, &cpu);
        assert_eq!(report.differences().len(), 143);
        assert_eq!(report.max_abs_diff(), 1.0);
        let message = panic_message(|| report.assert_identical());
        assert!(message.contains("143 lanes in 143 elements"), "{message}");
        assert!(message.contains("[0]: gpu 1 vs cpu 0"), "{message}");
        assert!(message.contains("[343]"), "{message}");
        assert!(!message.contains("[350]"), "{message}");
        assert!(message.contains("and 93 more"), "{message}");
    }

    #[test]
    fn tolerance_keeps_only_large_differences() {
        let cpu = [Vec3::ZERO, Vec3::ONE, Vec3::splat(2.0)];
        let gpu = [
            Vec3::new(1e-7, 0.0, 0.0),
            Vec3::ONE,
            Vec3::new(2.0, 2.5, 2.0),
        ];
        let report = ParityReport::gpu_vs_cpu("points", &gpu, &cpu);
        assert_eq!(report.differences().len(), 2);
        let message = panic_message(|| report.clone().assert_max_abs_lt(1e-3));
        assert!(message.contains("1 lanes in 1 elements"), "{message}");
        assert!(message.contains("[2].y"), "{message}");
        report.assert_max_abs_lt(0.6);
    }

    #[test]
    fn nan_signed_zero_and_length_mismatch_are_differences() {
        let report = ParityReport::gpu_vs_cpu("nan", &[f32::NAN, -0.0], &[1.0f32, 0.0]);
        assert_eq!(report.differences().len(), 2);
        assert_eq!(report.max_abs_diff(), f64::INFINITY);
        ParityReport::gpu_vs_cpu("nan", &[f32::NAN], &[f32::NAN]).assert_identical();
        ParityReport::gpu_vs_cpu("zero", &[-0.0f32], &[0.0]).assert_max_abs_lt(1e-30);
        let message = panic_message(|| {
            ParityReport::gpu_vs_cpu("zero", &[-0.0f32], &[0.0]).assert_identical()
        });
        assert!(
            message.contains("-0.0 (0x80000000) vs cpu 0.0"),
            "{message}"
        );
        let report = ParityReport::gpu_vs_cpu("short", &[1.0f32], &[1.0f32, 2.0]);
        assert!(report.differences().is_empty());
        let message = panic_message(|| report.assert_max_abs_lt(1.0));
        assert!(message.contains("gpu has 1, cpu has 2"), "{message}");
    }
}
