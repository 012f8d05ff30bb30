//! Time integration of the wave equation `∂²h/∂t² = c² Δh − d ∂h/∂t` (paper §5, eq. 1, with the
//! optional damping the paper mentions) on one tracked frame.
//!
//! The paper integrates "using symplectic Euler integration with several sub-cycled time steps per
//! input frame". Here the symplectic scheme is its symmetric form, Störmer–Verlet (kick, drift,
//! kick), whose energy error is second order in the step instead of first, and the number of
//! sub-steps is raised until `ω_max · dt ≤ 1`, half the scheme's stability limit of 2, with `ω_max`
//! bounded from the mesh's own operator. Damping multiplies the velocity by `exp(−d·dt)` each step,
//! the exact solution of its part of the equation.

use super::Laplacian;

/// The state carried from frame to frame: height `h` along the normal and its rate `v = ∂h/∂t`, in
/// vertex order.
#[derive(Debug, Clone, PartialEq)]
pub struct WaveState {
    pub height: Vec<f64>,
    pub velocity: Vec<f64>,
}

impl WaveState {
    /// A surface at rest.
    pub fn rest(vertices: usize) -> Self {
        Self {
            height: vec![0.0; vertices],
            velocity: vec![0.0; vertices],
        }
    }

    /// The discrete energy `½ Σ m_i v_i² + ½ c² Σ_edges w_ij (h_i − h_j)²`, which an undamped
    /// exact solution conserves.
    pub fn energy(&self, laplacian: &Laplacian, speed: f64) -> f64 {
        let kinetic: f64 = laplacian
            .mass()
            .iter()
            .zip(&self.velocity)
            .map(|(m, v)| m * v * v)
            .sum::<f64>()
            * 0.5;
        kinetic + speed * speed * laplacian.dirichlet_energy(&self.height)
    }
}

/// Wave speed, damping and the least number of sub-steps, in the caller's units of length and time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WaveParameters {
    pub speed: f64,
    pub damping: f64,
    pub min_substeps: usize,
}

/// The number of sub-steps that makes `duration` stable and accurate on `laplacian`: at least
/// `min_substeps`, and enough that `ω_max · dt ≤ 1`.
pub fn substeps(laplacian: &Laplacian, parameters: &WaveParameters, duration: f64) -> usize {
    let omega_max = parameters.speed * laplacian.max_eigenvalue_bound().sqrt();
    let needed = (omega_max * duration).ceil();
    let needed = if needed.is_finite() && needed > 0.0 {
        needed as usize
    } else {
        1
    };
    needed.max(parameters.min_substeps).max(1)
}

/// Advances `state` by `duration` on the frame whose operator is `laplacian`; returns the number of
/// sub-steps taken.
pub fn advance(
    laplacian: &Laplacian,
    state: &mut WaveState,
    parameters: &WaveParameters,
    duration: f64,
) -> usize {
    let steps = substeps(laplacian, parameters, duration);
    let dt = duration / steps as f64;
    let c2 = parameters.speed * parameters.speed;
    let decay = (-parameters.damping * dt).exp();
    let mut acceleration = vec![0.0; laplacian.len()];
    laplacian.apply_inverse_mass(&state.height, &mut acceleration);
    for _ in 0..steps {
        for (v, a) in state.velocity.iter_mut().zip(&acceleration) {
            *v += 0.5 * dt * c2 * a;
        }
        for (h, v) in state.height.iter_mut().zip(&state.velocity) {
            *h += dt * v;
        }
        laplacian.apply_inverse_mass(&state.height, &mut acceleration);
        for (v, a) in state.velocity.iter_mut().zip(&acceleration) {
            *v = (*v + 0.5 * dt * c2 * a) * decay;
        }
    }
    steps
}
