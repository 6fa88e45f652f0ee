//! The adapter and the dispatch: [`Gpu`] opens a GPU adapter headlessly (a real GPU,
//! or Mesa's lavapipe where there is none), runs a wrapped kernel's compute shader
//! over a packed batch and reads the f32 results back, or times it with timestamp
//! queries.

use crate::error::GpuError;
use crate::rho_arg;
use crate::wrap::{wrap, wrap_kernel, MAX_GROUPS_X, WORKGROUP};
use crate::wrap::{KernelSource, Table};
use crate::{Entry, Ray, SpotRay};
use std::fmt;
use wgpu::util::DeviceExt;

/// The adapter, described for reports: name, backend, driver.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AdapterSummary {
    /// Adapter name, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)" or "NVIDIA H100".
    pub name: String,
    /// Graphics API backend, e.g. "Vulkan".
    pub backend: String,
    /// Driver name and version information.
    pub driver: String,
    /// Device type: discrete, integrated, virtual, CPU.
    pub device_type: String,
}

impl fmt::Display for AdapterSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} ({}, {:?} device, driver {})", self.name, self.backend, self.device_type, self.driver)
    }
}

/// An open device and its queue.
pub struct Gpu {
    device: wgpu::Device,
    queue: wgpu::Queue,
    summary: AdapterSummary,
    /// Harness pipelines compiled so far, by their shader's text: a batch run in
    /// chunks (one shadow map per chunk) compiles once.
    pipelines: std::sync::Mutex<std::collections::HashMap<String, wgpu::ComputePipeline>>,
    /// The first error the device raised outside an error scope (out of memory,
    /// a lost device): wgpu's default handler panics; this one keeps it for
    /// [`Gpu::failed`], so that a GPU failure is an error, never a panic.
    failure: std::sync::Arc<std::sync::Mutex<Option<String>>>,
}

impl Gpu {
    /// Opens the best adapter available on the primary backends (Vulkan, Metal,
    /// DX12; `WGPU_BACKEND=gl` selects OpenGL ES through EGL). A software adapter
    /// is accepted so that CI can run on lavapipe.
    pub fn open() -> Result<Gpu, GpuError> {
        pollster::block_on(Self::open_async())
    }

    async fn open_async() -> Result<Gpu, GpuError> {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
        desc.backends = wgpu::Backends::from_env().unwrap_or(wgpu::Backends::PRIMARY);
        let instance = wgpu::Instance::new(desc);
        let adapter = instance
            .request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                force_fallback_adapter: false,
                compatible_surface: None,
                ..Default::default()
            })
            .await
            .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        let info = adapter.get_info();
        let summary = AdapterSummary {
            name: info.name,
            backend: format!("{:?}", info.backend),
            driver: format!("{} {}", info.driver, info.driver_info).trim().to_string(),
            device_type: format!("{:?}", info.device_type),
        };
        // Timestamps where the adapter has them (the bench's GPU throughput).
        let required_features = adapter.features() & wgpu::Features::TIMESTAMP_QUERY;
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("airlight harness"),
                required_features,
                required_limits: wgpu::Limits::downlevel_defaults().using_resolution(adapter.limits()),
                ..Default::default()
            })
            .await
            .map_err(|e| GpuError::Device(e.to_string()))?;
        let failure: std::sync::Arc<std::sync::Mutex<Option<String>>> = Default::default();
        let slot = failure.clone();
        device.on_uncaptured_error(std::sync::Arc::new(move |e: wgpu::Error| {
            let mut f = slot.lock().unwrap_or_else(|p| p.into_inner());
            if f.is_none() {
                *f = Some(e.to_string().lines().next().unwrap_or("unknown").trim().to_string());
            }
        }));
        Ok(Gpu { device, queue, summary, pipelines: Default::default(), failure })
    }

    /// The adapter in use.
    pub fn adapter(&self) -> &AdapterSummary {
        &self.summary
    }

    /// Evaluates `function` (see the crate's kernel ABI), defined in `kernel`
    /// (WGSL source without an entry point), at every point; `ρ = ∞` is passed as
    /// [`NO_SURFACE`]. Returns one f32 per point, in order.
    pub fn eval(&self, kernel: &str, function: &str, points: &[[f64; 4]]) -> Result<Vec<f32>, GpuError> {
        let source = wrap_kernel(kernel, function);
        self.dispatch(wgpu::ShaderSource::Wgsl(source.into()), function, &pack_points(points), 1, points.len(), 1, None)
    }

    /// Evaluates a generated kernel's canonical entry (`<prefix>airlight`) at every
    /// point `(τ, γ, ρ, g)`, passing the arguments it takes; `ρ = ∞` is passed as
    /// [`NO_SURFACE`]. One f32 per point, in order.
    pub fn airlight(&self, k: &KernelSource, points: &[[f64; 4]]) -> Result<Vec<f32>, GpuError> {
        let source = wrap(k, Entry::Canonical)?;
        self.dispatch(k.shader(&source), k.prefix, &pack_points(points), 1, points.len(), 1, k.table)
    }

    /// Evaluates a generated kernel's physical entry (`<prefix>radiance`) for every
    /// ray. One f32 per ray, in order.
    pub fn radiance(&self, k: &KernelSource, rays: &[Ray]) -> Result<Vec<f32>, GpuError> {
        let source = wrap(k, Entry::Radiance)?;
        let data: Vec<f32> = rays.iter().flat_map(Ray::pack).collect();
        self.dispatch(k.shader(&source), k.prefix, &data, Entry::Radiance.packed_vec4s(), rays.len(), 1, k.table)
    }

    /// Evaluates a generated kernel's spot entry (`<prefix>spot`) for every ray:
    /// RGB per ray, in order.
    pub fn spot(&self, k: &KernelSource, rays: &[SpotRay]) -> Result<Vec<[f32; 3]>, GpuError> {
        let source = wrap(k, Entry::Spot)?;
        let data: Vec<f32> = rays.iter().flat_map(SpotRay::pack).collect();
        let out =
            self.dispatch(k.shader(&source), k.prefix, &data, Entry::Spot.packed_vec4s(), rays.len(), 3, k.table)?;
        Ok(out.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect())
    }

    /// GPU evaluations per second of a kernel's canonical entry over `points`:
    /// the median of `repeats` dispatches, each timed by timestamp queries at the
    /// pass's start and end. `None` where the adapter has no timestamps.
    pub fn throughput(&self, k: &KernelSource, points: &[[f64; 4]], repeats: usize) -> Result<Option<f64>, GpuError> {
        self.timed(k, Entry::Canonical, &pack_points(points), points.len(), repeats)
    }

    /// Rays per second through a kernel's physical entry, as [`Gpu::throughput`].
    pub fn radiance_throughput(&self, k: &KernelSource, rays: &[Ray], repeats: usize) -> Result<Option<f64>, GpuError> {
        let data: Vec<f32> = rays.iter().flat_map(Ray::pack).collect();
        self.timed(k, Entry::Radiance, &data, rays.len(), repeats)
    }

    /// Rays per second (RGB each) through a kernel's spot entry, as [`Gpu::throughput`].
    pub fn spot_throughput(&self, k: &KernelSource, rays: &[SpotRay], repeats: usize) -> Result<Option<f64>, GpuError> {
        let data: Vec<f32> = rays.iter().flat_map(SpotRay::pack).collect();
        self.timed(k, Entry::Spot, &data, rays.len(), repeats)
    }

    /// Items per second of `entry` over `n` packed items: the median of `repeats`
    /// dispatches timed by timestamp queries; `None` without timestamps.
    pub(crate) fn timed(
        &self,
        k: &KernelSource,
        entry: Entry,
        data: &[f32],
        n: usize,
        repeats: usize,
    ) -> Result<Option<f64>, GpuError> {
        self.timed_source(k, &wrap(k, entry)?, entry.outputs(), data, n, repeats)
    }

    /// [`Gpu::timed`] of a harness shader already wrapped around the kernel.
    pub(crate) fn timed_source(
        &self,
        k: &KernelSource,
        source: &str,
        outputs: usize,
        data: &[f32],
        n: usize,
        repeats: usize,
    ) -> Result<Option<f64>, GpuError> {
        self.timed_with(k, source, outputs, data, n, repeats, None)
    }

    /// [`Gpu::timed_source`] with a shadow map's pyramid bound.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn timed_with(
        &self,
        k: &KernelSource,
        source: &str,
        outputs: usize,
        data: &[f32],
        n: usize,
        repeats: usize,
        pyramid: Option<&wgpu::TextureView>,
    ) -> Result<Option<f64>, GpuError> {
        if n == 0 || !self.device.features().contains(wgpu::Features::TIMESTAMP_QUERY) {
            return Ok(None);
        }
        let (gx, gy) = workgroups(n)?;
        let run = self.prepare(k.shader(source), k.prefix, data, n * outputs, k.table, pyramid)?;
        let median = Stamps::median(self, repeats, |enc, stamps| {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: None,
                timestamp_writes: stamps.map(|st| st.compute(true, true)),
            });
            pass.set_pipeline(&run.pipeline);
            pass.set_bind_group(0, &run.bind, &[]);
            pass.dispatch_workgroups(gx, gy, 1);
        })?;
        Ok((median > 0.0).then(|| n as f64 / median))
    }

    /// The bind group of a harness pipeline: inputs (0), results (1) and, for a
    /// table-driven kernel, its table as an r32float texture (2) and, where the
    /// shader declares one (GLSL's separate sampler), a nearest sampler (3).
    pub(crate) fn bind(
        &self,
        pipeline: &wgpu::ComputePipeline,
        input: &wgpu::Buffer,
        output: &wgpu::Buffer,
        table: Option<&Table>,
        pyramid: Option<&wgpu::TextureView>,
    ) -> Result<wgpu::BindGroup, GpuError> {
        let d = &self.device;
        let mut entries = vec![
            wgpu::BindGroupEntry { binding: 0, resource: input.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 1, resource: output.as_entire_binding() },
        ];
        let view;
        let sampler;
        if let Some(t) = table {
            let size = wgpu::Extent3d { width: t.size as u32, height: t.size as u32, depth_or_array_layers: 1 };
            let texture = d.create_texture(&wgpu::TextureDescriptor {
                label: Some("table"),
                size,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::R32Float,
                usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                view_formats: &[],
            });
            self.queue.write_texture(
                wgpu::TexelCopyTextureInfo {
                    texture: &texture,
                    mip_level: 0,
                    origin: wgpu::Origin3d::ZERO,
                    aspect: wgpu::TextureAspect::All,
                },
                bytemuck::cast_slice(&t.texels),
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(4 * t.size as u32),
                    rows_per_image: Some(t.size as u32),
                },
                size,
            );
            view = texture.create_view(&wgpu::TextureViewDescriptor::default());
            entries.push(wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::TextureView(&view) });
            sampler = d.create_sampler(&wgpu::SamplerDescriptor::default());
            entries.push(wgpu::BindGroupEntry { binding: 3, resource: wgpu::BindingResource::Sampler(&sampler) });
        }
        // A shadow map's min-max pyramid (the shadow-map walk): texture 4 and, for
        // GLSL's combined sampler, sampler 5.
        let pyramid_sampler = d.create_sampler(&wgpu::SamplerDescriptor::default());
        if let Some(v) = pyramid {
            entries.push(wgpu::BindGroupEntry { binding: 4, resource: wgpu::BindingResource::TextureView(v) });
            entries
                .push(wgpu::BindGroupEntry { binding: 5, resource: wgpu::BindingResource::Sampler(&pyramid_sampler) });
        }
        let layout = pipeline.get_bind_group_layout(0);
        let attempt = |entries: &[wgpu::BindGroupEntry]| {
            let scope = d.push_error_scope(wgpu::ErrorFilter::Validation);
            let bind = d.create_bind_group(&wgpu::BindGroupDescriptor { label: None, layout: &layout, entries });
            match pollster::block_on(scope.pop()) {
                None => Ok(bind),
                Some(e) => self.failed().and(Err(GpuError::Shader(e.to_string()))),
            }
        };
        match attempt(&entries) {
            // A shader without a sampler (WGSL; GLSL where naga drops an unused one): bind without it.
            Err(_) if entries.iter().any(|e| matches!(e.resource, wgpu::BindingResource::Sampler(_))) => {
                let plain: Vec<_> =
                    entries.into_iter().filter(|e| !matches!(e.resource, wgpu::BindingResource::Sampler(_))).collect();
                attempt(&plain)
            }
            other => other,
        }
    }

    /// Runs a compute shader with entry `main` over `n` items of `stride` vec4s
    /// each (binding 0) into `outputs` f32 per item (binding 1).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn dispatch(
        &self,
        shader: wgpu::ShaderSource,
        label: &str,
        data: &[f32],
        stride: usize,
        n: usize,
        outputs: usize,
        table: Option<&Table>,
    ) -> Result<Vec<f32>, GpuError> {
        self.dispatch_with(shader, label, data, stride, n, outputs, table, None)
    }

    /// [`Gpu::dispatch`] with a shadow map's pyramid bound (texture 4, sampler 5).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn dispatch_with(
        &self,
        shader: wgpu::ShaderSource,
        label: &str,
        data: &[f32],
        stride: usize,
        n: usize,
        outputs: usize,
        table: Option<&Table>,
        pyramid: Option<&wgpu::TextureView>,
    ) -> Result<Vec<f32>, GpuError> {
        if n == 0 {
            return Ok(Vec::new());
        }
        let (gx, gy) = workgroups(n)?;
        debug_assert_eq!(data.len(), n * stride * 4);
        let run = self.prepare(shader, label, data, n * outputs, table, pyramid)?;
        let bytes = (n * outputs * 4) as u64;
        let staging = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("staging"),
            size: bytes,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut enc = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: None, timestamp_writes: None });
            pass.set_pipeline(&run.pipeline);
            pass.set_bind_group(0, &run.bind, &[]);
            pass.dispatch_workgroups(gx, gy, 1);
        }
        enc.copy_buffer_to_buffer(&run.output, 0, &staging, 0, bytes);
        self.queue.submit([enc.finish()]);
        Ok(bytemuck::cast_slice(&self.read_back(&staging)?).to_vec())
    }

    /// Compiles a harness shader (entry `main`) and binds `data` as its inputs, a
    /// results buffer of `n` f32, and the kernel's table if it has one.
    pub(crate) fn prepare(
        &self,
        shader: wgpu::ShaderSource,
        label: &str,
        data: &[f32],
        n: usize,
        table: Option<&Table>,
        pyramid: Option<&wgpu::TextureView>,
    ) -> Result<Prepared, GpuError> {
        let d = &self.device;
        let key = match &shader {
            wgpu::ShaderSource::Wgsl(t) => Some(format!("wgsl\n{t}")),
            wgpu::ShaderSource::Glsl { shader, .. } => Some(format!("glsl\n{shader}")),
            _ => None,
        };
        let cached = key.as_ref().and_then(|k| self.pipelines.lock().ok().and_then(|m| m.get(k).cloned()));
        let scope = d.push_error_scope(wgpu::ErrorFilter::Validation);
        let pipeline = match cached {
            Some(p) => p,
            None => {
                let module =
                    d.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some(label), source: shader });
                d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(label),
                    layout: None,
                    module: &module,
                    entry_point: Some("main"),
                    compilation_options: Default::default(),
                    cache: None,
                })
            }
        };
        if let Some(e) = pollster::block_on(scope.pop()) {
            // An earlier device failure (out of memory) is the cause to report.
            self.failed()?;
            return Err(GpuError::Shader(e.to_string()));
        }
        if let (Some(k), Ok(mut m)) = (key, self.pipelines.lock()) {
            // A few recent pipelines: a batch in chunks reuses its one.
            if m.len() >= 8 {
                m.clear();
            }
            m.insert(k, pipeline.clone());
        }
        let input = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("inputs"),
            contents: bytemuck::cast_slice(data),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let output = d.create_buffer(&wgpu::BufferDescriptor {
            label: Some("results"),
            size: (n * 4) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let bind = self.bind(&pipeline, &input, &output, table, pyramid)?;
        Ok(Prepared { pipeline, bind, output })
    }

    /// The error the device raised since it opened, if any (out of memory, a
    /// lost device): every read-back and pyramid build checks it.
    pub fn failed(&self) -> Result<(), GpuError> {
        match self.failure.lock().unwrap_or_else(|p| p.into_inner()).as_ref() {
            None => Ok(()),
            Some(e) => Err(GpuError::Device(e.clone())),
        }
    }

    /// Maps `staging` after the submitted work, and copies its bytes out.
    pub(crate) fn read_back(&self, staging: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
        self.failed()?;
        let (tx, rx) = std::sync::mpsc::channel();
        staging.map_async(wgpu::MapMode::Read, .., move |r| {
            let _ = tx.send(r);
        });
        self.device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| GpuError::Readback(e.to_string()))?;
        self.failed()?;
        rx.recv().map_err(|e| GpuError::Readback(e.to_string()))?.map_err(|e| GpuError::Readback(e.to_string()))?;
        let view = staging.get_mapped_range(..).map_err(|e| GpuError::Readback(e.to_string()))?;
        let out = view.to_vec();
        drop(view);
        staging.unmap();
        Ok(out)
    }

    /// The device, for passes beyond the harness's (the headless render).
    pub fn device(&self) -> &wgpu::Device {
        &self.device
    }

    /// The queue.
    pub fn queue(&self) -> &wgpu::Queue {
        &self.queue
    }
}

/// A compiled harness pipeline and its bindings (the bind group keeps the input
/// buffer and the table alive).
pub(crate) struct Prepared {
    pipeline: wgpu::ComputePipeline,
    bind: wgpu::BindGroup,
    output: wgpu::Buffer,
}

/// The dispatch for `n` items: one invocation each, in workgroups of
/// [`WORKGROUP`], 2-D beyond 65,535 workgroups.
pub(crate) fn workgroups(n: usize) -> Result<(u32, u32), GpuError> {
    let groups = (n as u64).div_ceil(WORKGROUP as u64);
    if groups > MAX_GROUPS_X as u64 * MAX_GROUPS_X as u64 {
        return Err(GpuError::TooLarge(n));
    }
    Ok(if groups <= MAX_GROUPS_X as u64 {
        (groups as u32, 1)
    } else {
        (MAX_GROUPS_X, groups.div_ceil(MAX_GROUPS_X as u64) as u32)
    })
}

pub(crate) fn pack_points(points: &[[f64; 4]]) -> Vec<f32> {
    points.iter().flat_map(|p| [p[0] as f32, p[1] as f32, rho_arg(p[2]), p[3] as f32]).collect()
}

/// A pair of timestamp queries (0 at a pass's start, 1 at a pass's end), the
/// buffers they are resolved into and read back from: the elapsed GPU time
/// between them.
pub(crate) struct Stamps {
    queries: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    staging: wgpu::Buffer,
    period: f64,
}

impl Stamps {
    /// `None` where the adapter has no timestamps.
    pub(crate) fn new(gpu: &Gpu) -> Option<Stamps> {
        let d = gpu.device();
        if !d.features().contains(wgpu::Features::TIMESTAMP_QUERY) {
            return None;
        }
        let buffer = |label, usage| {
            d.create_buffer(&wgpu::BufferDescriptor { label: Some(label), size: 16, usage, mapped_at_creation: false })
        };
        Some(Stamps {
            queries: d.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: 2,
            }),
            resolve: buffer("timestamps", wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC),
            staging: buffer("timestamps staging", wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST),
            period: f64::from(gpu.queue().get_timestamp_period()),
        })
    }

    /// A compute pass's writes: the start stamp if `start`, the end stamp if `end`.
    pub(crate) fn compute(&self, start: bool, end: bool) -> wgpu::ComputePassTimestampWrites<'_> {
        wgpu::ComputePassTimestampWrites {
            query_set: &self.queries,
            beginning_of_pass_write_index: start.then_some(0),
            end_of_pass_write_index: end.then_some(1),
        }
    }

    /// A render pass's writes: both stamps.
    pub(crate) fn render(&self) -> wgpu::RenderPassTimestampWrites<'_> {
        wgpu::RenderPassTimestampWrites {
            query_set: &self.queries,
            beginning_of_pass_write_index: Some(0),
            end_of_pass_write_index: Some(1),
        }
    }

    /// Records the resolve of both stamps into the staging buffer (after the passes).
    pub(crate) fn resolve(&self, enc: &mut wgpu::CommandEncoder) {
        enc.resolve_query_set(&self.queries, 0..2, &self.resolve, 0);
        enc.copy_buffer_to_buffer(&self.resolve, 0, &self.staging, 0, 16);
    }

    /// Seconds between the stamps (after the encoder with [`Stamps::resolve`] was submitted).
    pub(crate) fn seconds(&self, gpu: &Gpu) -> Result<f64, GpuError> {
        let t: Vec<u64> = bytemuck::cast_slice(&gpu.read_back(&self.staging)?).to_vec();
        Ok(t[1].saturating_sub(t[0]) as f64 * self.period * 1e-9)
    }

    /// The median GPU seconds of `repeats` submissions of what `record` encodes,
    /// after a warm-up submission; `record` places the stamps (it is given none,
    /// and the result is 0, where the adapter has no timestamps). `repeats` 0:
    /// one submission, untimed (the work is wanted, not its time).
    pub(crate) fn median(
        gpu: &Gpu,
        repeats: usize,
        record: impl Fn(&mut wgpu::CommandEncoder, Option<&Stamps>),
    ) -> Result<f64, GpuError> {
        let stamps = if repeats == 0 { None } else { Stamps::new(gpu) };
        let mut times = Vec::new();
        for _ in 0..=repeats {
            let mut enc = gpu.device().create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("timed") });
            record(&mut enc, stamps.as_ref());
            if let Some(st) = &stamps {
                st.resolve(&mut enc);
            }
            gpu.queue().submit([enc.finish()]);
            if let Some(st) = &stamps {
                times.push(st.seconds(gpu)?);
            }
        }
        if times.len() < 2 {
            return Ok(0.0);
        }
        let mut t = times.split_off(1);
        t.sort_by(f64::total_cmp);
        Ok(t[t.len() / 2])
    }
}
