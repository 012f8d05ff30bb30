use thiserror::Error;

/// How to get a Vulkan adapter on a machine without a GPU driver: Mesa's lavapipe runs compute
/// shaders on the CPU, which is slow but exact enough for every kernel here.
pub const LAVAPIPE_HINT: &str = "install a GPU driver, or the Vulkan software rasterizer lavapipe \
(Debian/Ubuntu: `apt-get install mesa-vulkan-drivers`; Fedora: `dnf install mesa-vulkan-drivers`)";

/// Why a computation could not run on the chosen backend.
///
/// Bad input (an index past the end of the positions) is kept apart from GPU failures so callers can
/// fix the input or fall back to the CPU as fits.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ComputeError {
    #[error("no GPU adapter found (wgpu sees no Vulkan, Metal or DX12 device); {LAVAPIPE_HINT}")]
    NoAdapter,
    #[error("could not open GPU device on adapter {adapter:?}: {message}")]
    Device { adapter: String, message: String },
    #[error("unknown backend {0:?}: expected auto, cpu or gpu")]
    UnknownBackend(String),
    #[error(
        "kernel {kernel:?} takes {expected} buffers (one per binding in the registry), got {got}"
    )]
    BindingCount {
        kernel: &'static str,
        expected: usize,
        got: usize,
    },
    #[error("buffer {label:?} needs {bytes} bytes but the GPU allows at most {limit} per buffer")]
    BufferTooLarge {
        label: &'static str,
        bytes: u64,
        limit: u64,
    },
    #[error("{items} work items need more workgroups than the GPU can dispatch")]
    DispatchTooLarge { items: u64 },
    #[error("triangle {triangle} references vertex {vertex}, but there are only {count} positions")]
    IndexOutOfRange {
        triangle: usize,
        vertex: u32,
        count: usize,
    },
    #[error("GPU error: {0}")]
    Gpu(String),
}
