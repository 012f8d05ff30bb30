use std::borrow::Cow;
use std::collections::HashMap;
use std::fmt;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, mpsc};

use bytemuck::Pod;
use wgpu::util::DeviceExt;

use super::ComputeError;
use super::dispatch::workgroup_grid;
use super::kernel::{Access, KernelInfo};

/// A compiled kernel: its pipeline and the layout its bind groups must follow.
#[derive(Debug, Clone)]
struct Compiled {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
}

/// An open GPU device with what every kernel needs: buffer upload and readback, and pipelines
/// compiled once per kernel and cached by name.
///
/// Opening a device is slow (hundreds of milliseconds, more under lavapipe), so one context is
/// meant to be created per process and shared through [`super::Backend::Gpu`].
pub struct GpuContext {
    info: wgpu::AdapterInfo,
    device: wgpu::Device,
    queue: wgpu::Queue,
    limits: wgpu::Limits,
    pipelines: Mutex<HashMap<&'static str, Compiled>>,
    /// Bytes uploaded to and read back from the device so far (see [`GpuContext::transferred`]).
    uploaded: AtomicU64,
    read_back: AtomicU64,
}

impl fmt::Debug for GpuContext {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("GpuContext")
            .field("adapter", &self.info.name)
            .field("backend", &self.info.backend)
            .field("device_type", &self.info.device_type)
            .finish_non_exhaustive()
    }
}

impl GpuContext {
    /// Opens a device on `adapter` with the adapter's full limits, so buffers as large as the
    /// hardware allows can be bound (the WebGPU defaults stop at 128 MiB per storage buffer), and
    /// with f64 shader arithmetic where the adapter has it (the fine stage's kernels need it).
    pub fn new(adapter: &wgpu::Adapter) -> Result<Self, ComputeError> {
        let info = adapter.get_info();
        let limits = adapter.limits();
        let descriptor = wgpu::DeviceDescriptor {
            label: Some("surftrack"),
            required_features: adapter.features() & wgpu::Features::SHADER_F64,
            required_limits: limits.clone(),
            ..Default::default()
        };
        let (device, queue) =
            pollster::block_on(adapter.request_device(&descriptor)).map_err(|e| {
                ComputeError::Device {
                    adapter: info.name.clone(),
                    message: e.to_string(),
                }
            })?;
        Ok(Self {
            info,
            device,
            queue,
            limits,
            pipelines: Mutex::new(HashMap::new()),
            uploaded: AtomicU64::new(0),
            read_back: AtomicU64::new(0),
        })
    }

    pub fn adapter_info(&self) -> &wgpu::AdapterInfo {
        &self.info
    }

    /// Whether kernels may compute in f64 (`wgpu::Features::SHADER_F64`).
    pub fn has_f64(&self) -> bool {
        self.device.features().contains(wgpu::Features::SHADER_F64)
    }

    pub fn device(&self) -> &wgpu::Device {
        &self.device
    }

    pub fn queue(&self) -> &wgpu::Queue {
        &self.queue
    }

    /// Bytes moved host → device and device → host through this context so far: every upload and
    /// read-back (buffers a kernel writes and another reads stay on the device and are not counted).
    pub fn transferred(&self) -> [u64; 2] {
        [
            self.uploaded.load(Ordering::Relaxed),
            self.read_back.load(Ordering::Relaxed),
        ]
    }

    pub fn limits(&self) -> &wgpu::Limits {
        &self.limits
    }

    /// The most elements of `T` one storage buffer binding may hold (at least 1). Kernels over
    /// longer arrays run in chunks of this length.
    pub fn max_binding_len<T>(&self) -> usize {
        let bytes = self.binding_limit() / size_of::<T>().max(1) as u64;
        usize::try_from(bytes).unwrap_or(usize::MAX).max(1)
    }

    /// A storage buffer holding `data`, readable by kernels.
    pub fn upload<T: Pod>(
        &self,
        label: &'static str,
        data: &[T],
    ) -> Result<wgpu::Buffer, ComputeError> {
        let contents: &[u8] = bytemuck::cast_slice(data);
        self.check_size(label, contents.len() as u64)?;
        self.uploaded
            .fetch_add(contents.len() as u64, Ordering::Relaxed);
        self.scoped(|| {
            self.device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(label),
                    contents,
                    usage: BUFFER_USAGES,
                })
        })
    }

    /// An uninitialised storage buffer of `len` elements of `T` for a kernel to write.
    pub fn output<T: Pod>(
        &self,
        label: &'static str,
        len: usize,
    ) -> Result<wgpu::Buffer, ComputeError> {
        let bytes = byte_len::<T>(label, len)? as u64;
        self.check_size(label, bytes)?;
        self.scoped(|| {
            self.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: padded(bytes),
                usage: BUFFER_USAGES,
                mapped_at_creation: false,
            })
        })
    }

    /// Overwrites the start of `buffer` with `data` (made by [`Self::upload`] or [`Self::output`],
    /// at least as long); the write lands before any work submitted after it.
    pub fn write<T: Pod>(&self, buffer: &wgpu::Buffer, data: &[T]) -> Result<(), ComputeError> {
        let contents: &[u8] = bytemuck::cast_slice(data);
        if contents.is_empty() {
            return Ok(());
        }
        if contents.len() as u64 > buffer.size()
            || !(contents.len() as u64).is_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT)
        {
            return Err(ComputeError::Gpu(format!(
                "write of {} bytes into a buffer of {} bytes",
                contents.len(),
                buffer.size()
            )));
        }
        self.uploaded
            .fetch_add(contents.len() as u64, Ordering::Relaxed);
        self.scoped(|| self.queue.write_buffer(buffer, 0, contents))
    }

    /// Copies the first `len` elements of `buffer` back to the host, waiting for all work
    /// submitted before.
    pub fn read_back<T: Pod>(
        &self,
        buffer: &wgpu::Buffer,
        len: usize,
    ) -> Result<Vec<T>, ComputeError> {
        let used = byte_len::<T>("read_back", len)?;
        let bytes = used as u64;
        if bytes == 0 {
            return Ok(Vec::new());
        }
        self.read_back.fetch_add(bytes, Ordering::Relaxed);
        if padded(bytes) > buffer.size() {
            return Err(ComputeError::Gpu(format!(
                "read_back of {bytes} bytes from a buffer of {} bytes",
                buffer.size()
            )));
        }
        let staging = self.scoped(|| {
            let staging = self.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("read_back"),
                size: padded(bytes),
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let mut encoder = self.device.create_command_encoder(&Default::default());
            encoder.copy_buffer_to_buffer(buffer, 0, &staging, 0, padded(bytes));
            self.queue.submit([encoder.finish()]);
            staging
        })?;
        let (sender, receiver) = mpsc::channel();
        staging.map_async(wgpu::MapMode::Read, .., move |result| {
            // Sending fails only when the receiver is gone, that is when `read_back` has already
            // returned an error; the result is then of no use to anyone.
            let _ = sender.send(result);
        });
        self.wait()?;
        receiver
            .recv()
            .map_err(|e| ComputeError::Gpu(format!("buffer mapping never completed: {e}")))?
            .map_err(|e| ComputeError::Gpu(format!("buffer mapping failed: {e}")))?;
        let data = {
            let view = staging
                .get_mapped_range(..)
                .map_err(|e| ComputeError::Gpu(format!("mapped range unavailable: {e}")))?;
            bytemuck::pod_collect_to_vec(&view[..used])
        };
        staging.unmap();
        Ok(data)
    }

    /// Runs `info` over `items` work items with `buffers` bound in its bindings' order, splitting the
    /// grid into rows when it exceeds `max_compute_workgroups_per_dimension`. Returns once the work
    /// is submitted; [`Self::read_back`] or [`Self::wait`] waits for it.
    pub fn dispatch(
        &self,
        info: &'static KernelInfo,
        buffers: &[&wgpu::Buffer],
        items: u64,
    ) -> Result<(), ComputeError> {
        let mut batch = self.batch();
        batch.dispatch(info, buffers, items)?;
        batch.submit()
    }

    /// `info` with `buffers` bound in its bindings' order, for dispatching many times
    /// ([`Batch::dispatch_bound`]): a solver's iterations bind their kernels once, not per dispatch.
    pub fn bind(
        &self,
        info: &'static KernelInfo,
        buffers: &[&wgpu::Buffer],
    ) -> Result<Bound, ComputeError> {
        check_binding_count(info, buffers)?;
        let compiled = self.compiled(info)?;
        let bind_group = self.scoped(|| {
            let entries: Vec<wgpu::BindGroupEntry> = buffers
                .iter()
                .enumerate()
                .map(|(i, buffer)| wgpu::BindGroupEntry {
                    binding: i as u32,
                    resource: buffer.as_entire_binding(),
                })
                .collect();
            self.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(info.name),
                layout: &compiled.layout,
                entries: &entries,
            })
        })?;
        Ok(Bound {
            info,
            compiled,
            bind_group,
        })
    }

    /// An empty [`Batch`] of dispatches.
    pub fn batch(&self) -> Batch<'_> {
        Batch {
            context: self,
            encoder: self.device.create_command_encoder(&Default::default()),
        }
    }

    /// Blocks until all submitted work has finished.
    pub fn wait(&self) -> Result<(), ComputeError> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| ComputeError::Gpu(format!("waiting for the GPU failed: {e}")))
    }

    /// The cached pipeline of `info`, compiling it on first use.
    fn compiled(&self, info: &'static KernelInfo) -> Result<Compiled, ComputeError> {
        let mut cache = self
            .pipelines
            .lock()
            .map_err(|_| ComputeError::Gpu("pipeline cache poisoned".into()))?;
        if let Some(compiled) = cache.get(info.name) {
            return Ok(compiled.clone());
        }
        let compiled = self.scoped(|| self.compile(info))?;
        cache.insert(info.name, compiled.clone());
        Ok(compiled)
    }

    fn compile(&self, info: &KernelInfo) -> Compiled {
        let module = self
            .device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(info.path),
                source: wgpu::ShaderSource::Wgsl(Cow::Owned(info.full_source())),
            });
        let entries: Vec<wgpu::BindGroupLayoutEntry> = info
            .bindings
            .iter()
            .enumerate()
            .map(|(i, binding)| wgpu::BindGroupLayoutEntry {
                binding: i as u32,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage {
                        read_only: binding.access == Access::Read,
                    },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            })
            .collect();
        let layout = self
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(info.name),
                entries: &entries,
            });
        let pipeline_layout = self
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(info.name),
                bind_group_layouts: &[Some(&layout)],
                immediate_size: 0,
            });
        let pipeline = self
            .device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(info.name),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(info.entry_point),
                compilation_options: Default::default(),
                cache: None,
            });
        Compiled { pipeline, layout }
    }

    fn binding_limit(&self) -> u64 {
        self.limits
            .max_storage_buffer_binding_size
            .min(self.limits.max_buffer_size)
    }

    fn check_size(&self, label: &'static str, bytes: u64) -> Result<(), ComputeError> {
        let limit = self.binding_limit();
        if bytes > limit {
            return Err(ComputeError::BufferTooLarge {
                label,
                bytes,
                limit,
            });
        }
        Ok(())
    }

    /// Runs `f` with wgpu's errors captured and returned instead of reaching the device's default
    /// handler, which panics.
    fn scoped<R>(&self, f: impl FnOnce() -> R) -> Result<R, ComputeError> {
        let out_of_memory = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let internal = self.device.push_error_scope(wgpu::ErrorFilter::Internal);
        let result = f();
        let errors = [
            pollster::block_on(internal.pop()),
            pollster::block_on(validation.pop()),
            pollster::block_on(out_of_memory.pop()),
        ];
        match errors.into_iter().flatten().next() {
            Some(error) => Err(ComputeError::Gpu(error.to_string())),
            None => Ok(result),
        }
    }
}

/// Dispatches recorded into one command buffer and submitted together: a sequence of kernels that
/// read each other's outputs costs one submission, not one each. Each dispatch has its own compute
/// pass, so each sees everything the ones before it wrote.
pub struct Batch<'a> {
    context: &'a GpuContext,
    encoder: wgpu::CommandEncoder,
}

impl Batch<'_> {
    /// Records `info` over `items` work items with `buffers` bound in its bindings' order (see
    /// [`GpuContext::dispatch`]).
    pub fn dispatch(
        &mut self,
        info: &'static KernelInfo,
        buffers: &[&wgpu::Buffer],
        items: u64,
    ) -> Result<(), ComputeError> {
        if items == 0 {
            return check_binding_count(info, buffers);
        }
        let bound = self.context.bind(info, buffers)?;
        self.dispatch_bound(&bound, items)
    }

    /// Records `bound` over `items` work items.
    pub fn dispatch_bound(&mut self, bound: &Bound, items: u64) -> Result<(), ComputeError> {
        if items == 0 {
            return Ok(());
        }
        let context = self.context;
        let info = bound.info;
        let grid = workgroup_grid(
            items,
            info.workgroup_size,
            context.limits.max_compute_workgroups_per_dimension,
        )?;
        let encoder = &mut self.encoder;
        context.scoped(|| {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(info.name),
                timestamp_writes: None,
            });
            pass.set_pipeline(&bound.compiled.pipeline);
            pass.set_bind_group(0, &bound.bind_group, &[]);
            pass.dispatch_workgroups(grid[0], grid[1], grid[2]);
        })
    }

    /// Submits everything recorded; [`GpuContext::read_back`] or [`GpuContext::wait`] waits for it.
    pub fn submit(self) -> Result<(), ComputeError> {
        let Self { context, encoder } = self;
        context.scoped(|| {
            context.queue.submit([encoder.finish()]);
        })
    }
}

/// A kernel bound to its buffers ([`GpuContext::bind`]).
#[derive(Debug)]
pub struct Bound {
    info: &'static KernelInfo,
    compiled: Compiled,
    bind_group: wgpu::BindGroup,
}

/// An error unless `buffers` has one buffer per binding of `info`.
fn check_binding_count(
    info: &'static KernelInfo,
    buffers: &[&wgpu::Buffer],
) -> Result<(), ComputeError> {
    if buffers.len() == info.bindings.len() {
        Ok(())
    } else {
        Err(ComputeError::BindingCount {
            kernel: info.name,
            expected: info.bindings.len(),
            got: buffers.len(),
        })
    }
}

/// How every storage buffer may be used: bound to kernels, copied out for reading back, written
/// in place ([`GpuContext::write`]).
const BUFFER_USAGES: wgpu::BufferUsages = wgpu::BufferUsages::STORAGE
    .union(wgpu::BufferUsages::COPY_SRC)
    .union(wgpu::BufferUsages::COPY_DST);

/// Byte length of `len` elements of `T`.
fn byte_len<T>(label: &'static str, len: usize) -> Result<usize, ComputeError> {
    len.checked_mul(size_of::<T>())
        .ok_or(ComputeError::BufferTooLarge {
            label,
            bytes: u64::MAX,
            limit: 0,
        })
}

/// `bytes` rounded up to wgpu's copy alignment, at least one word (buffers of size 0 cannot be
/// mapped or copied).
fn padded(bytes: u64) -> u64 {
    bytes.div_ceil(wgpu::COPY_BUFFER_ALIGNMENT).max(1) * wgpu::COPY_BUFFER_ALIGNMENT
}
