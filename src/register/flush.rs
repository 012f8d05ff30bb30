//! Runs single-precision factorizations and solves with subnormal numbers flushed to zero.
//!
//! Fill entries of a Cholesky factor decay with their distance in the elimination tree, and at a
//! small `α_reg` (paper §4.2: the last stages of the schedule) the scaled matrix is diagonally
//! dominant enough that many reach the `f32` subnormal range, where every arithmetic operation
//! takes a slow microcode path: on the 100k-vertex `register` bench frame the factorization at
//! `α_reg = 0.1` took 0.86–0.94 s instead of the 0.25–0.3 s of every other stage. The factor only
//! preconditions conjugate gradients run in `f64`, so values below 10⁻³⁸ of the unit diagonal
//! are noise to it; flushing them (x86-64: MXCSR FTZ and DAZ; AArch64: FPCR FZ) changes nothing
//! the solver can see but the time. The mode is per thread and restored on return, and the work
//! inside runs on the calling thread only (`Par::Seq`), so results stay deterministic.

/// Calls `f` with subnormal results and operands of `f32`/`f64` arithmetic treated as zero on this
/// thread, then restores the previous mode.
pub fn flushing_subnormals<R>(f: impl FnOnce() -> R) -> R {
    let saved = mode::enter();
    let result = f();
    mode::restore(saved);
    result
}

#[cfg(target_arch = "x86_64")]
mod mode {
    /// MXCSR flush-to-zero (bit 15) and denormals-are-zero (bit 6).
    const FTZ_DAZ: u32 = 0x8040;

    pub fn enter() -> u32 {
        let mut saved: u32 = 0;
        // SAFETY: stmxcsr stores the 32-bit control register into the local it is given.
        unsafe { std::arch::asm!("stmxcsr [{}]", in(reg) &mut saved, options(nostack)) };
        let flushing = saved | FTZ_DAZ;
        // SAFETY: only the flush bits change; exception masks and rounding stay as they were.
        unsafe { std::arch::asm!("ldmxcsr [{}]", in(reg) &flushing, options(nostack)) };
        saved
    }

    pub fn restore(saved: u32) {
        // SAFETY: restores the value read by `enter` on this thread.
        unsafe { std::arch::asm!("ldmxcsr [{}]", in(reg) &saved, options(nostack)) };
    }
}

#[cfg(target_arch = "aarch64")]
mod mode {
    /// FPCR flush-to-zero (bit 24).
    const FZ: u64 = 1 << 24;

    pub fn enter() -> u64 {
        let saved: u64;
        // SAFETY: reads the floating-point control register.
        unsafe { std::arch::asm!("mrs {}, fpcr", out(reg) saved, options(nomem, nostack)) };
        // SAFETY: only the flush bit changes; rounding and traps stay as they were.
        unsafe { std::arch::asm!("msr fpcr, {}", in(reg) saved | FZ, options(nomem, nostack)) };
        saved
    }

    pub fn restore(saved: u64) {
        // SAFETY: restores the value read by `enter` on this thread.
        unsafe { std::arch::asm!("msr fpcr, {}", in(reg) saved, options(nomem, nostack)) };
    }
}

#[cfg(not(any(target_arch = "x86_64", target_arch = "aarch64")))]
mod mode {
    pub fn enter() {}

    pub fn restore(_: ()) {}
}

#[cfg(test)]
mod tests {
    use super::flushing_subnormals;
    use std::hint::black_box;

    #[test]
    fn subnormals_flush_inside_and_not_after() {
        let tiny = black_box(f32::MIN_POSITIVE);
        let half = black_box(0.5f32);
        if cfg!(any(target_arch = "x86_64", target_arch = "aarch64")) {
            assert_eq!(
                flushing_subnormals(|| black_box(tiny) * black_box(half)),
                0.0
            );
        }
        let after = black_box(tiny) * black_box(half);
        assert!(after > 0.0 && after < f32::MIN_POSITIVE, "mode restored");
    }
}
