use std::fmt;
use std::str::FromStr;
use std::sync::Arc;

use super::{ComputeError, GpuContext};

/// What the user asked for with `--backend`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum BackendChoice {
    /// A hardware GPU when there is one, else the CPU.
    #[default]
    Auto,
    /// The CPU (rayon); deterministic whatever the thread count.
    Cpu,
    /// Any GPU adapter, software ones such as lavapipe included; an error when there is none.
    Gpu,
}

impl fmt::Display for BackendChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Auto => "auto",
            Self::Cpu => "cpu",
            Self::Gpu => "gpu",
        })
    }
}

impl FromStr for BackendChoice {
    type Err = ComputeError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "auto" => Ok(Self::Auto),
            "cpu" => Ok(Self::Cpu),
            "gpu" => Ok(Self::Gpu),
            _ => Err(ComputeError::UnknownBackend(s.to_owned())),
        }
    }
}

/// Where the data-parallel stages (DESIGN.md, "Where the work runs") execute.
///
/// Cloning is cheap: the GPU context is shared.
#[derive(Debug, Clone)]
pub enum Backend {
    Cpu,
    Gpu(Arc<GpuContext>),
}

impl Backend {
    /// Resolves a [`BackendChoice`], opening a GPU device when one is wanted.
    ///
    /// `auto` skips CPU adapters (lavapipe, llvmpipe, SwiftShader): they run kernels slower than the
    /// rayon twins, so they are worth using only when asked for, as tests do to exercise the GPU
    /// path. When `auto` finds a hardware adapter whose device fails to open, it falls back to the
    /// CPU, which always works.
    pub fn select(choice: BackendChoice) -> Result<Self, ComputeError> {
        match choice {
            BackendChoice::Cpu => Ok(Self::Cpu),
            BackendChoice::Gpu => {
                let adapter = adapters()
                    .into_iter()
                    .next()
                    .ok_or(ComputeError::NoAdapter)?;
                Ok(Self::Gpu(Arc::new(GpuContext::new(&adapter)?)))
            }
            BackendChoice::Auto => Ok(adapters()
                .into_iter()
                .find(|a| a.get_info().device_type != wgpu::DeviceType::Cpu)
                .and_then(|adapter| GpuContext::new(&adapter).ok())
                .map_or(Self::Cpu, |context| Self::Gpu(Arc::new(context)))),
        }
    }

    /// The GPU context, when this backend is a GPU.
    pub fn gpu(&self) -> Option<&Arc<GpuContext>> {
        match self {
            Self::Cpu => None,
            Self::Gpu(context) => Some(context),
        }
    }
}

impl fmt::Display for Backend {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Cpu => write!(f, "cpu ({} threads)", rayon::current_num_threads()),
            Self::Gpu(context) => {
                let info = context.adapter_info();
                write!(
                    f,
                    "gpu ({}, {:?} {:?})",
                    info.name, info.backend, info.device_type
                )?;
                if !context.has_f64() {
                    // The fine stage's kernels compute in f64 (`register::fine_solve`).
                    f.write_str(", fine stage on the CPU: no f64 shaders")?;
                }
                Ok(())
            }
        }
    }
}

/// The adapters of the native GPU APIs (Vulkan, Metal, DX12; `WGPU_BACKEND` overrides), best
/// first: discrete, integrated, virtual, other, then CPU adapters.
fn adapters() -> Vec<wgpu::Adapter> {
    let mut descriptor = wgpu::InstanceDescriptor::new_without_display_handle();
    descriptor.backends = wgpu::Backends::PRIMARY;
    let instance = wgpu::Instance::new(descriptor.with_env());
    let mut adapters = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()));
    adapters.sort_by_key(|a| match a.get_info().device_type {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Other => 3,
        wgpu::DeviceType::Cpu => 4,
    });
    adapters
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn choices_round_trip_through_text() {
        for choice in [BackendChoice::Auto, BackendChoice::Cpu, BackendChoice::Gpu] {
            assert_eq!(choice.to_string().parse::<BackendChoice>(), Ok(choice));
        }
        assert_eq!("GPU".parse::<BackendChoice>(), Ok(BackendChoice::Gpu));
        assert_eq!(
            "cuda".parse::<BackendChoice>(),
            Err(ComputeError::UnknownBackend("cuda".into()))
        );
    }

    #[test]
    fn clap_accepts_the_same_names() {
        use clap::ValueEnum;
        for choice in BackendChoice::value_variants() {
            assert_eq!(
                <BackendChoice as ValueEnum>::from_str(&choice.to_string(), false),
                Ok(*choice)
            );
        }
    }

    #[test]
    fn cpu_needs_no_device() {
        let backend = Backend::select(BackendChoice::Cpu).unwrap();
        assert!(backend.gpu().is_none());
        assert!(backend.to_string().starts_with("cpu"));
    }

    #[test]
    fn auto_never_picks_a_software_adapter() {
        if let Backend::Gpu(context) = Backend::select(BackendChoice::Auto).unwrap() {
            assert_ne!(context.adapter_info().device_type, wgpu::DeviceType::Cpu);
        }
    }
}
