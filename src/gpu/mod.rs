//! The GPU path: the step's passes as WGSL compute shaders (`shaders/`) through wgpu.
//!
//! `Gpu` owns the device; `Kernel` is one compute pipeline whose bind-group layout is read from
//! its shader (`shader`: every program assembled in one place, parsed by naga) and whose
//! buffers are bound by their WGSL names; `state` holds one storage buffer per field of the
//! CPU's structure-of-arrays state, so every shader has a CPU twin with the same data.
//!
//! Nothing here panics on a missing or limited adapter: every failure is an `Err` naming what
//! is missing (an adapter, a limit, a feature) so the command line can say so.

pub mod batch;
pub mod concrete;
pub mod contact_detect;
pub mod error;
pub mod fem_stress;
pub mod history;
pub mod integrate;
pub mod neighbours;
pub mod params;
pub mod profiler;
pub mod scan;
pub mod shader;
pub mod sph_filter;
pub mod sph_forces;
pub mod sph_rates;
pub mod state;
pub mod step;
pub mod timestep;
pub mod traffic;
pub mod walls;

use std::sync::{Arc, Mutex};

use bytemuck::Pod;

pub use error::GpuError;

/// Threads per workgroup in every shader: `@workgroup_size(WG)`, WG declared from this by the
/// shader prelude (`shader::prelude`).
pub const WORKGROUP: u32 = 64;

/// Items each thread of a reduction folds (`Kernel::dispatch_fold`).
pub const FOLD: u32 = 32;

/// An adapter as `penetrate adapters` lists it.
#[derive(Clone, Debug)]
pub struct AdapterSummary {
    pub name: String,
    pub backend: String,
    pub device_type: String,
    pub driver: String,
    /// Why this adapter cannot run the solver, if it cannot.
    pub unusable: Option<String>,
}

fn instance() -> wgpu::Instance {
    wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env())
}

/// Why an adapter cannot run the solver (a limit below what the passes bind), or None.
fn unusable(adapter: &wgpu::Adapter) -> Option<String> {
    let limits = adapter.limits();
    let needed = shader::storage_buffers_needed();
    if limits.max_storage_buffers_per_shader_stage < needed {
        return Some(format!(
            "max_storage_buffers_per_shader_stage is {}, the solver binds up to {needed}",
            limits.max_storage_buffers_per_shader_stage
        ));
    }
    if !adapter
        .get_downlevel_capabilities()
        .flags
        .contains(wgpu::DownlevelFlags::COMPUTE_SHADERS)
    {
        return Some("no compute shaders".into());
    }
    None
}

/// Every adapter wgpu sees, with the reason it cannot be used where it cannot.
pub fn adapters() -> Vec<AdapterSummary> {
    let instance = instance();
    let list = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()));
    list.iter()
        .map(|a| {
            let info = a.get_info();
            AdapterSummary {
                name: info.name.clone(),
                backend: format!("{:?}", info.backend),
                device_type: format!("{:?}", info.device_type),
                driver: format!("{} {}", info.driver, info.driver_info)
                    .trim()
                    .to_string(),
                unusable: unusable(a),
            }
        })
        .collect()
}

/// Preference of an adapter when none is named: a real GPU first, then lavapipe on Vulkan; the
/// GL backend last (fewer storage buffers, no subgroups: gpu-notes.md).
fn rank(info: &wgpu::AdapterInfo) -> u32 {
    let kind = match info.device_type {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Cpu => 3,
        wgpu::DeviceType::Other => 4,
    };
    let backend = u32::from(info.backend == wgpu::Backend::Gl);
    backend * 10 + kind
}

/// True when the adapter is a real GPU (not a software rasteriser): what `--backend auto` wants.
pub fn is_hardware(info: &wgpu::AdapterInfo) -> bool {
    matches!(
        info.device_type,
        wgpu::DeviceType::DiscreteGpu | wgpu::DeviceType::IntegratedGpu
    )
}

/// The device and queue, with wgpu errors captured instead of panicking.
pub struct Gpu {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub info: wgpu::AdapterInfo,
    pub limits: wgpu::Limits,
    /// Timestamp queries inside compute passes are available (for `bench`).
    pub timestamps: bool,
    errors: Arc<Mutex<Vec<String>>>,
    /// Bytes of buffers created through `buffer`, `zeros` and `uniform`.
    allocated: std::sync::atomic::AtomicU64,
    /// Waits, bytes read back, bytes written and dispatches so far (`traffic`); shared with
    /// the kernels, which count their dispatches.
    pub traffic: Arc<traffic::Counters>,
}

/// How a shader binding is used.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Slot {
    Uniform,
    Read,
    ReadWrite,
}

/// One compute pipeline, its bind-group layout and the shader's bindings it was made from.
pub struct Kernel {
    pub name: String,
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    bindings: Vec<shader::Binding>,
    counters: Arc<traffic::Counters>,
}

impl Gpu {
    /// Open the adapter whose name contains `name` (case-insensitive), or the best one.
    pub fn new(name: Option<&str>) -> Result<Gpu, GpuError> {
        let instance = instance();
        let list = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()));
        if list.is_empty() {
            return Err(GpuError::NoAdapter(
                "no GPU adapter found (on Debian, `apt-get install mesa-vulkan-drivers` \
                 gives the software adapter lavapipe)"
                    .into(),
            ));
        }
        let mut candidates: Vec<&wgpu::Adapter> = match name {
            Some(n) => {
                let n = n.to_lowercase();
                list.iter()
                    .filter(|a| a.get_info().name.to_lowercase().contains(&n))
                    .collect()
            }
            None => list.iter().collect(),
        };
        if candidates.is_empty() {
            let names: Vec<String> = list.iter().map(|a| a.get_info().name).collect();
            return Err(GpuError::NoAdapter(format!(
                "no adapter named like {:?}; adapters: {}",
                name.unwrap_or(""),
                names.join(", ")
            )));
        }
        candidates.sort_by_key(|a| rank(&a.get_info()));
        let usable = candidates.iter().find(|a| unusable(a).is_none());
        let Some(adapter) = usable else {
            let a = candidates[0];
            return Err(GpuError::NoAdapter(format!(
                "adapter {} ({:?}) cannot run the solver: {}",
                a.get_info().name,
                a.get_info().backend,
                unusable(a).unwrap_or_default()
            )));
        };
        let features = adapter.features()
            & (wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES);
        let limits = adapter.limits();
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("penetrate"),
            required_features: features,
            required_limits: limits.clone(),
            ..Default::default()
        }))
        .map_err(|e| GpuError::Open {
            adapter: adapter.get_info().name,
            message: e.to_string(),
        })?;
        let errors = Arc::new(Mutex::new(Vec::new()));
        let sink = errors.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            if let Ok(mut v) = sink.lock() {
                v.push(e.to_string());
            }
        }));
        Ok(Gpu {
            device,
            queue,
            info: adapter.get_info(),
            limits,
            timestamps: features.contains(
                wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES,
            ),
            errors,
            allocated: Default::default(),
            traffic: Default::default(),
        })
    }

    /// Bytes of buffers allocated so far.
    pub fn allocated(&self) -> u64 {
        self.allocated.load(std::sync::atomic::Ordering::Relaxed)
    }

    fn count(&self, bytes: u64) {
        self.allocated
            .fetch_add(bytes, std::sync::atomic::Ordering::Relaxed);
    }

    /// The same device and queue for another run (`batch`): its own counts of allocations and
    /// transfers, the device's errors shared.
    pub fn share(&self) -> Gpu {
        Gpu {
            device: self.device.clone(),
            queue: self.queue.clone(),
            info: self.info.clone(),
            limits: self.limits.clone(),
            timestamps: self.timestamps,
            errors: self.errors.clone(),
            allocated: Default::default(),
            traffic: Default::default(),
        }
    }

    /// "name (backend)" for summaries.
    pub fn adapter_name(&self) -> String {
        format!("{} ({:?})", self.info.name, self.info.backend)
    }

    /// The first wgpu error raised since the last call, if any.
    pub fn take_error(&self) -> Option<String> {
        let mut v = self.errors.lock().ok()?;
        let first = v.first().cloned();
        v.clear();
        first
    }

    /// A scene that exceeds one of this adapter's limits, and how.
    pub fn limit(&self, message: String) -> GpuError {
        GpuError::Limit {
            adapter: self.info.name.clone(),
            message,
        }
    }

    /// Fail if the scene's largest array (bytes) does not fit one binding of this adapter.
    pub fn check_binding_size(&self, what: &str, bytes: u64) -> Result<(), GpuError> {
        let max = self
            .limits
            .max_storage_buffer_binding_size
            .min(self.limits.max_buffer_size);
        if bytes > max {
            return Err(self.limit(format!(
                "{what} take {bytes} bytes in one buffer, above its \
                 max_storage_buffer_binding_size of {max} (fewer particles, or a larger GPU)"
            )));
        }
        Ok(())
    }

    /// A storage buffer holding `data` (at least 16 bytes: bindings may not be empty).
    pub fn buffer<T: Pod>(&self, label: &str, data: &[T]) -> wgpu::Buffer {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        let size = (bytes.len() as u64).max(16).next_multiple_of(4);
        self.count(size);
        let buffer = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_DST
                | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        if !bytes.is_empty() {
            self.queue.write_buffer(&buffer, 0, bytes);
        }
        buffer
    }

    /// A zeroed storage buffer of `count` elements of T.
    pub fn zeros<T: Pod>(&self, label: &str, count: usize) -> wgpu::Buffer {
        let size = ((count * std::mem::size_of::<T>()) as u64)
            .max(16)
            .next_multiple_of(4);
        self.count(size);
        self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_DST
                | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        })
    }

    /// A uniform buffer holding `value`, laid out by encase.
    pub fn uniform<T: encase::ShaderType + encase::internal::WriteInto>(
        &self,
        label: &str,
        value: &T,
    ) -> wgpu::Buffer {
        let mut bytes = encase::UniformBuffer::new(Vec::<u8>::new());
        bytes
            .write(value)
            .expect("encase writes into a growable Vec");
        let bytes = bytes.into_inner();
        let buffer = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: (bytes.len() as u64).max(16).next_multiple_of(16),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        self.queue.write_buffer(&buffer, 0, &bytes);
        buffer
    }

    /// Overwrite a uniform buffer made by `uniform` with a new value of the same type.
    pub fn write_uniform<T: encase::ShaderType + encase::internal::WriteInto>(
        &self,
        buffer: &wgpu::Buffer,
        value: &T,
    ) {
        let mut bytes = encase::UniformBuffer::new(Vec::<u8>::new());
        bytes
            .write(value)
            .expect("encase writes into a growable Vec");
        let bytes = bytes.into_inner();
        self.traffic.written(bytes.len() as u64);
        self.queue.write_buffer(buffer, 0, &bytes);
    }

    /// Overwrite the start of a storage buffer.
    pub fn write<T: Pod>(&self, buffer: &wgpu::Buffer, data: &[T]) {
        self.write_at(buffer, 0, data);
    }

    /// Overwrite a storage buffer's elements from element `first` on.
    pub fn write_at<T: Pod>(&self, buffer: &wgpu::Buffer, first: usize, data: &[T]) {
        if !data.is_empty() {
            let bytes: &[u8] = bytemuck::cast_slice(data);
            self.traffic.written(bytes.len() as u64);
            let at = (first * std::mem::size_of::<T>()) as u64;
            self.queue.write_buffer(buffer, at, bytes);
        }
    }

    /// Read the first `count` elements of a buffer back (blocking). Used for outputs and
    /// tests, not inside the step.
    pub fn read<T: Pod>(&self, buffer: &wgpu::Buffer, count: usize) -> Result<Vec<T>, GpuError> {
        let bytes = (count * std::mem::size_of::<T>()) as u64;
        if bytes == 0 {
            return Ok(Vec::new());
        }
        let staging = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("read-back"),
            size: bytes.next_multiple_of(4),
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        encoder.copy_buffer_to_buffer(buffer, 0, &staging, 0, bytes.next_multiple_of(4));
        self.queue.submit([encoder.finish()]);
        let out = self.map_read(&staging, bytes as usize)?;
        Ok(bytemuck::pod_collect_to_vec(&out))
    }

    /// Block until the GPU has done all that was submitted (one round trip, counted).
    pub fn wait(&self) -> Result<(), GpuError> {
        self.traffic.wait();
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| GpuError::Device(format!("GPU wait failed: {e}")))?;
        Ok(())
    }

    /// Map a MAP_READ buffer, copy out its first `bytes` bytes and unmap it.
    pub fn map_read(&self, staging: &wgpu::Buffer, bytes: usize) -> Result<Vec<u8>, GpuError> {
        let slice = staging.slice(..(bytes as u64).next_multiple_of(4));
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        self.wait()?;
        self.traffic.read(bytes as u64);
        match rx.recv() {
            Ok(Ok(())) => {}
            Ok(Err(e)) => return Err(GpuError::Device(format!("GPU read-back failed: {e}"))),
            Err(_) => return Err(GpuError::Device("GPU read-back was dropped".into())),
        }
        let out = {
            let view = slice
                .get_mapped_range()
                .map_err(|e| GpuError::Device(format!("GPU read-back failed: {e}")))?;
            view[..bytes].to_vec()
        };
        staging.unmap();
        if let Some(e) = self.take_error() {
            return Err(GpuError::Device(format!("GPU error: {e}")));
        }
        Ok(out)
    }

    /// The compute pipeline of `entry` in `program`, with values for its pipeline-overridable
    /// constants (`override`): what a scene does not need is then compiled out, not skipped at
    /// run time.
    pub fn kernel(
        &self,
        program: shader::Program,
        entry: &str,
        constants: &[(&str, f64)],
    ) -> Result<Kernel, GpuError> {
        let name = format!("{}.{entry}", program.name());
        let mut given: Vec<&str> = constants.iter().map(|(c, _)| *c).collect();
        let mut declared = program.overrides().to_vec();
        given.sort_unstable();
        declared.sort_unstable();
        if given != declared {
            return Err(GpuError::Kernel {
                kernel: name,
                message: format!("constants {given:?} given, the program overrides {declared:?}"),
            });
        }
        self.kernel_from(&name, &program.source(), entry, constants)
    }

    /// A compute pipeline from WGSL source (`shader::source`); its bind-group layout is the
    /// shader's own bindings.
    pub fn kernel_from(
        &self,
        name: &str,
        source: &str,
        entry: &str,
        constants: &[(&str, f64)],
    ) -> Result<Kernel, GpuError> {
        let kernel_error = |message: String| GpuError::Kernel {
            kernel: name.to_string(),
            message,
        };
        let bindings = shader::bindings(source)
            .map_err(|e| kernel_error(format!("the shader does not parse: {e}")))?;
        let storage = bindings.iter().filter(|b| b.slot != Slot::Uniform).count() as u32;
        if storage > self.limits.max_storage_buffers_per_shader_stage {
            return Err(GpuError::NoAdapter(format!(
                "adapter {} cannot run {name}: it binds {storage} storage buffers, above the \
                 adapter's max_storage_buffers_per_shader_stage of {}",
                self.info.name, self.limits.max_storage_buffers_per_shader_stage
            )));
        }
        let module = self
            .device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(name),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            });
        let entries: Vec<wgpu::BindGroupLayoutEntry> = bindings
            .iter()
            .map(|b| wgpu::BindGroupLayoutEntry {
                binding: b.index,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty: match b.slot {
                        Slot::Uniform => wgpu::BufferBindingType::Uniform,
                        Slot::Read => wgpu::BufferBindingType::Storage { read_only: true },
                        Slot::ReadWrite => wgpu::BufferBindingType::Storage { read_only: false },
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
                label: Some(name),
                entries: &entries,
            });
        let pipeline_layout = self
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(name),
                bind_group_layouts: &[Some(&layout)],
                immediate_size: 0,
            });
        let pipeline = self
            .device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(name),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(entry),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants,
                    ..Default::default()
                },
                cache: None,
            });
        if let Some(e) = self.take_error() {
            return Err(kernel_error(format!(
                "the shader ({entry}) does not build: {e}"
            )));
        }
        Ok(Kernel {
            name: name.to_string(),
            pipeline,
            layout,
            bindings,
            counters: self.traffic.clone(),
        })
    }
}

impl Kernel {
    /// A bind group with each of the shader's bindings given its buffer by name: every
    /// binding must be named once, and only bindings the shader declares.
    pub fn bind(
        &self,
        gpu: &Gpu,
        buffers: &[(&str, &wgpu::Buffer)],
    ) -> Result<wgpu::BindGroup, GpuError> {
        if let Some((name, _)) = buffers
            .iter()
            .find(|(name, _)| !self.bindings.iter().any(|b| b.name == *name))
        {
            return Err(self.error(format!("no binding {name}")));
        }
        let entries = self
            .bindings
            .iter()
            .map(|b| {
                let mut given = buffers.iter().filter(|(name, _)| *name == b.name);
                match (given.next(), given.next()) {
                    (Some((_, buffer)), None) => Ok(wgpu::BindGroupEntry {
                        binding: b.index,
                        resource: buffer.as_entire_binding(),
                    }),
                    (None, _) => Err(self.error(format!("no buffer for {}", b.name))),
                    (Some(_), Some(_)) => Err(self.error(format!("{} given twice", b.name))),
                }
            })
            .collect::<Result<Vec<_>, GpuError>>()?;
        Ok(gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(&self.name),
            layout: &self.layout,
            entries: &entries,
        }))
    }

    /// A failure of this kernel's contract with its shader.
    fn error(&self, message: String) -> GpuError {
        GpuError::Kernel {
            kernel: self.name.clone(),
            message,
        }
    }

    /// Record one dispatch covering `items` threads (one per item).
    pub fn dispatch(&self, pass: &mut wgpu::ComputePass, bind: &wgpu::BindGroup, items: u32) {
        if items == 0 {
            return;
        }
        self.dispatch_groups(pass, bind, items.div_ceil(WORKGROUP));
    }

    /// Record a reduction over `items`: each thread folds `FOLD` items (strided by the whole
    /// dispatch) before its one atomic, so the shader needs no workgroup barrier (a barrier
    /// swaps every SIMD chunk of the workgroup in and out on lavapipe) and the atomics stay
    /// few.
    pub fn dispatch_fold(&self, pass: &mut wgpu::ComputePass, bind: &wgpu::BindGroup, items: u32) {
        if items == 0 {
            return;
        }
        self.dispatch_groups(pass, bind, items.div_ceil(WORKGROUP * FOLD));
    }

    /// Record a dispatch of exactly `groups` workgroups.
    pub fn dispatch_groups(
        &self,
        pass: &mut wgpu::ComputePass,
        bind: &wgpu::BindGroup,
        groups: u32,
    ) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, bind, &[]);
        pass.dispatch_workgroups(groups, 1, 1);
        self.counters.dispatched();
    }
}

/// Reads of several buffers gathered into one encoder: the copies go into as few staging
/// buffers as the adapter's largest buffer allows, after whatever the encoder already holds,
/// and one submission and one wait bring them all back. A history row or a frame reads some
/// forty buffers; each read alone would be a round trip and a staging buffer.
#[derive(Default)]
pub struct ReadBatch<'a> {
    /// Each part's buffer, the byte it is read from and the bytes read.
    parts: Vec<(&'a wgpu::Buffer, u64, u64)>,
}

/// A part of a [`ReadBatch`], to take its values from the [`Batched`] result.
#[derive(Clone, Copy, Debug)]
pub struct Part(usize);

/// What a [`ReadBatch`] read: each part's bytes.
pub struct Batched {
    parts: Vec<Vec<u8>>,
}

impl Batched {
    /// The values of `part`.
    pub fn take<T: Pod>(&self, part: Part) -> Vec<T> {
        bytemuck::pod_collect_to_vec(&self.parts[part.0])
    }
}

impl<'a> ReadBatch<'a> {
    pub fn new() -> ReadBatch<'a> {
        ReadBatch::default()
    }

    /// Read the first `count` elements of T from `buffer`.
    pub fn add<T: Pod>(&mut self, buffer: &'a wgpu::Buffer, count: usize) -> Part {
        self.add_at::<T>(buffer, 0, count)
    }

    /// Read `count` elements of T from `buffer`, from its element `first` on.
    pub fn add_at<T: Pod>(&mut self, buffer: &'a wgpu::Buffer, first: usize, count: usize) -> Part {
        let size = std::mem::size_of::<T>();
        self.parts
            .push((buffer, (first * size) as u64, (count * size) as u64));
        Part(self.parts.len() - 1)
    }

    /// Record the copies in `encoder` after its commands, submit it, wait once and return
    /// every part.
    pub fn read(self, gpu: &Gpu, mut encoder: wgpu::CommandEncoder) -> Result<Batched, GpuError> {
        // Every part is a whole number of 4-byte words (the buffers hold f32 and u32), so the
        // copies' offsets are aligned as wgpu asks.
        let max = gpu.limits.max_buffer_size;
        let mut placed = Vec::with_capacity(self.parts.len());
        let mut sizes: Vec<u64> = Vec::new();
        for &(_, _, bytes) in &self.parts {
            let last = sizes.len().wrapping_sub(1);
            match sizes.last_mut() {
                Some(size) if *size + bytes <= max => {
                    placed.push((last, *size));
                    *size += bytes;
                }
                _ => {
                    placed.push((sizes.len(), 0));
                    sizes.push(bytes);
                }
            }
        }
        let staging: Vec<wgpu::Buffer> = sizes
            .iter()
            .map(|&size| {
                gpu.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("batched read-back"),
                    size: size.max(4),
                    usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                })
            })
            .collect();
        for (&(buffer, from, bytes), &(k, at)) in self.parts.iter().zip(&placed) {
            if bytes > 0 {
                encoder.copy_buffer_to_buffer(buffer, from, &staging[k], at, bytes);
            }
        }
        gpu.queue.submit([encoder.finish()]);
        let (tx, rx) = std::sync::mpsc::channel();
        for (k, b) in staging.iter().enumerate() {
            let tx = tx.clone();
            b.slice(..).map_async(wgpu::MapMode::Read, move |r| {
                let _ = tx.send((k, r));
            });
        }
        drop(tx);
        gpu.wait()?;
        for _ in 0..staging.len() {
            match rx.recv() {
                Ok((_, Ok(()))) => {}
                Ok((_, Err(e))) => {
                    return Err(GpuError::Device(format!("GPU read-back failed: {e}")))
                }
                Err(_) => return Err(GpuError::Device("GPU read-back was dropped".into())),
            }
        }
        let views = staging
            .iter()
            .map(|b| b.slice(..).get_mapped_range())
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| GpuError::Device(format!("GPU read-back failed: {e}")))?;
        let parts = self
            .parts
            .iter()
            .zip(&placed)
            .map(|(&(_, _, bytes), &(k, at))| views[k][at as usize..(at + bytes) as usize].to_vec())
            .collect();
        drop(views);
        staging.iter().for_each(wgpu::Buffer::unmap);
        gpu.traffic.read(sizes.iter().sum());
        if let Some(e) = gpu.take_error() {
            return Err(GpuError::Device(format!("GPU error: {e}")));
        }
        Ok(Batched { parts })
    }
}

/// Run `record` in one compute pass, submit, and wait (tests and one-off uses).
pub fn run_once(gpu: &Gpu, record: impl FnOnce(&mut wgpu::ComputePass)) -> Result<(), GpuError> {
    let mut encoder = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
    {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor::default());
        record(&mut pass);
    }
    gpu.queue.submit([encoder.finish()]);
    gpu.wait()?;
    match gpu.take_error() {
        Some(e) => Err(GpuError::Device(format!("GPU error: {e}"))),
        None => Ok(()),
    }
}

/// For tests: the adapter, or a failure that says how to get one (GPU tests never pass
/// silently without an adapter).
pub fn test_gpu() -> Gpu {
    match Gpu::new(std::env::var("PENETRATE_ADAPTER").ok().as_deref()) {
        Ok(g) => g,
        Err(e) => panic!(
            "GPU test needs an adapter: {e}. Install Mesa's software Vulkan adapter \
             (Debian: apt-get install mesa-vulkan-drivers) or run `bash scripts/test`, which does."
        ),
    }
}
