// The scalars of the fine stage's conjugate gradients (register::fine), on the device so an
// iteration reads nothing back: one invocation sums fine_reduce's chunks in order and, by `phase`,
//   PHASE_NORM:  |b|, and a fresh state (done at once when b = 0);
//   PHASE_BEGIN: rᵀz and the residual of the starting point;
//   PHASE_ALPHA: α = rᵀz / pᵀAp, or the end of the solve when pᵀAp is not a positive number;
//   PHASE_BETA:  β, the residual, one more iteration, and the end once the residual is at most the
//                tolerance or the iterations are spent.
// CPU twin: src/register/cpu/fine_scalars.rs. Prepended: shared/fine.wgsl.

@group(0) @binding(0) var<storage, read> params: FineParams;
@group(0) @binding(1) var<storage, read> phase: array<u32>;
@group(0) @binding(2) var<storage, read> partials: array<f64>;
@group(0) @binding(3) var<storage, read_write> state: CgState;

const WORKGROUP_SIZE: u32 = 64u;

// The largest finite f64: `x <= F64_MAX` is false for infinities and NaN.
const F64_MAX: f64 = 1.7976931348623157e308;

fn total(lane: u32) -> f64 {
    var sum = f64(0.0);
    for (var c = 0u; c < params.chunks; c += 1u) {
        sum += partials[2u * c + lane];
    }
    return sum;
}

// Whether the iteration goes on (the CPU's `residual > tolerance && iterations < max`).
fn running() -> bool {
    return state.residual > params.tolerance && state.iterations < params.max_iterations;
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    if (wg.y * groups.x + wg.x) * WORKGROUP_SIZE + lane != 0u {
        return;
    }
    let zero = f64(0.0);
    switch phase[0] {
        case PHASE_NORM: {
            let b_norm = sqrt(total(0u));
            let empty = b_norm == zero;
            state = CgState(b_norm, zero, zero, zero, zero, 0u, select(0u, 1u, empty));
        }
        case PHASE_BEGIN: {
            if state.done == 0u {
                state.rz = total(0u);
                state.residual = sqrt(total(1u)) / state.b_norm;
                state.done = select(1u, 0u, running());
            }
        }
        case PHASE_ALPHA: {
            if state.done == 0u {
                let pap = total(0u);
                if pap > zero && pap <= F64_MAX {
                    state.alpha = state.rz / pap;
                } else {
                    state.done = 1u;
                }
            }
        }
        default: {
            if state.done == 0u {
                let rz_next = total(0u);
                state.beta = rz_next / state.rz;
                state.rz = rz_next;
                state.residual = sqrt(total(1u)) / state.b_norm;
                state.iterations += 1u;
                state.done = select(1u, 0u, running());
            }
        }
    }
}
