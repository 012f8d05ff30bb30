gpu_struct! {
    mirrors FINE;
    /// The weights of the fine energy and the sizes of one solve (`register::fine_solve`).
    ///
    /// Mirrors `struct FineParams` in `kernels/shared/fine.wgsl`.
    pub struct FineParams {
        pub disp_weight: f64,
        pub edge_weight: f64,
        pub plane_weight: f64,
        pub point_weight: f64,
        /// Conjugate gradients stop once `|r| / |b|` is at most this.
        pub tolerance: f64,
        pub vertices: u32,
        /// Cover pairs.
        pub pairs: u32,
        /// Chunks of [`REDUCE_CHUNK`] vertices, each summed in order by one reduction invocation.
        pub chunks: u32,
        pub max_iterations: u32,
    }
}

gpu_struct! {
    mirrors FINE;
    /// The scalars of one conjugate-gradient solve of the fine stage, which stay on the device
    /// between its kernels; the host reads them back between batches of iterations.
    ///
    /// Mirrors `struct CgState` in `kernels/shared/fine.wgsl`.
    #[derive(Default)]
    pub struct CgState {
        pub b_norm: f64,
        pub rz: f64,
        pub alpha: f64,
        pub beta: f64,
        /// `|r| / |b|` after the last iteration.
        pub residual: f64,
        pub iterations: u32,
        /// Non-zero once the solve has ended; every kernel of an iteration then does nothing.
        pub done: u32,
    }
}

gpu_struct! {
    mirrors FINE;
    /// A vertex's correspondence in the fine stage: target point and unit normal (solver
    /// coordinates); `found` is 0 where the vertex has none.
    ///
    /// Mirrors `struct FineTarget` in `kernels/shared/fine.wgsl`.
    #[derive(Default)]
    pub struct FineTarget {
        pub point: [f64; 3],
        pub normal: [f64; 3],
        pub found: u32,
        pad: u32,
    }
}

impl FineTarget {
    pub fn new(point: [f64; 3], normal: [f64; 3]) -> Self {
        Self {
            point,
            normal,
            found: 1,
            pad: 0,
        }
    }
}

/// Terms one reduction invocation sums in order (`REDUCE_CHUNK` in `kernels/shared/fine.wgsl`).
pub const REDUCE_CHUNK: u32 = 1024;

/// The phases of `kernels/fine_scalars.wgsl` (`PHASE_*` there).
pub const PHASE_NORM: u32 = 0;
pub const PHASE_BEGIN: u32 = 1;
pub const PHASE_ALPHA: u32 = 2;
pub const PHASE_BETA: u32 = 3;
