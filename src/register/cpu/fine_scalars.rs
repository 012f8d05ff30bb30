//! CPU twin of `kernels/fine_scalars.wgsl`.

use crate::kernels::shared::{CgState, FineParams, PHASE_ALPHA, PHASE_BEGIN, PHASE_NORM};

/// CPU twin of `kernels/fine_scalars.wgsl` (its one invocation): the chunk sums in order, then the
/// step `phase` names.
pub(in crate::register) fn fine_scalars(
    params: &FineParams,
    phase: u32,
    partials: &[[f64; 2]],
    state: &mut CgState,
) {
    let total = |lane: usize| {
        let mut sum = 0.0;
        for partial in partials {
            sum += partial[lane];
        }
        sum
    };
    let running = |state: &CgState| {
        state.residual > params.tolerance && state.iterations < params.max_iterations
    };
    match phase {
        PHASE_NORM => {
            let b_norm = total(0).sqrt();
            *state = CgState {
                b_norm,
                done: u32::from(b_norm == 0.0),
                ..CgState::default()
            };
        }
        PHASE_BEGIN => {
            if state.done == 0 {
                state.rz = total(0);
                state.residual = total(1).sqrt() / state.b_norm;
                state.done = u32::from(!running(state));
            }
        }
        PHASE_ALPHA => {
            if state.done == 0 {
                let pap = total(0);
                if pap > 0.0 && pap <= f64::MAX {
                    state.alpha = state.rz / pap;
                } else {
                    state.done = 1;
                }
            }
        }
        _ => {
            if state.done == 0 {
                let rz_next = total(0);
                state.beta = rz_next / state.rz;
                state.rz = rz_next;
                state.residual = total(1).sqrt() / state.b_norm;
                state.iterations += 1;
                state.done = u32::from(!running(state));
            }
        }
    }
}
