//! airlight-shaders: the wgpu harness. It opens a GPU adapter headlessly (a real
//! GPU, or Mesa's lavapipe software Vulkan driver where there is none), wraps a
//! generated kernel — WGSL, or a GLSL include as a GLSL 4.50 compute shader
//! through wgpu's GLSL front end — in a compute shader, evaluates its canonical
//! entry on a batch of points `(τ, γ, ρ, g)` or its physical entry on a batch of
//! rays, and reads the f32 results back. Generated kernels are wrapped by the
//! arguments they take ([`KernelSource`]); a hand-written WGSL function can be run
//! with the ABI `fn NAME(tau: f32, gamma: f32, rho: f32, g: f32) -> f32` ([`Gpu::eval`]).
//! `rho = NO_SURFACE` (−1) stands for `ρ = ∞` in the canonical entry; the gate's
//! physical extreme set also passes `+∞` and `f32::MAX` surfaces, which every
//! kernel takes as none.

#![warn(missing_docs)]

pub mod bench;
pub mod browser;
pub mod gate;
pub mod render;
pub mod shafts_render;

pub use airlight_shapes::vocab::{Arg, Entry, Target};
use airlight_shapes::vocab::{ArgType, IndexEntry};
use std::fmt;
use wgpu::util::DeviceExt;

pub use airlight_shapes::vocab::{rho_arg, NO_SURFACE};

/// Environment variable that makes a missing adapter an error instead of a skip.
pub const REQUIRE_GPU_ENV: &str = "AIRLIGHT_REQUIRE_GPU";

/// Whether the environment demands an adapter (`AIRLIGHT_REQUIRE_GPU=1`).
pub fn gpu_required() -> bool {
    std::env::var(REQUIRE_GPU_ENV).is_ok_and(|v| v == "1" || v.eq_ignore_ascii_case("true"))
}

/// What went wrong on the GPU side.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum GpuError {
    /// No adapter could be opened.
    NoAdapter(String),
    /// The adapter refused a device.
    Device(String),
    /// The shader did not compile or validate, or the pipeline failed.
    Shader(String),
    /// Reading results back failed.
    Readback(String),
    /// The batch does not fit one dispatch.
    TooLarge(usize),
}

impl fmt::Display for GpuError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GpuError::NoAdapter(e) => write!(f, "no GPU adapter: {e}"),
            GpuError::Device(e) => write!(f, "the adapter refused a device: {e}"),
            GpuError::Shader(e) => write!(f, "shader error: {e}"),
            GpuError::Readback(e) => write!(f, "reading results back failed: {e}"),
            GpuError::TooLarge(n) => write!(f, "{n} points do not fit one dispatch"),
        }
    }
}

impl std::error::Error for GpuError {}

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
}

const WORKGROUP: u32 = 64;
const MAX_GROUPS_X: u32 = 65_535;

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
        Ok(Gpu { device, queue, summary })
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

    /// Evaluates a generated kernel's shafts accumulator over its physical entry
    /// for every ray: `samples[i]` (`[s, v]`, any number) pushed
    /// in order, then finished at the ray's surface. One f32 per ray, in order.
    pub fn shadowed(&self, k: &KernelSource, rays: &[Ray], samples: &[Vec<[f32; 2]>]) -> Result<Vec<f32>, GpuError> {
        let stride = shadowed_stride(Entry::Radiance, samples);
        let source = wrap_shadowed(k, Entry::Radiance, stride)?;
        let data = pack_shadowed(rays.iter().map(Ray::pack), samples, Entry::Radiance);
        self.dispatch(k.shader(&source), k.prefix, &data, stride, rays.len(), 1, k.table)
    }

    /// [`Gpu::shadowed`] over the spot entry: RGB per ray.
    pub fn spot_shadowed(
        &self,
        k: &KernelSource,
        rays: &[SpotRay],
        samples: &[Vec<[f32; 2]>],
    ) -> Result<Vec<[f32; 3]>, GpuError> {
        let stride = shadowed_stride(Entry::Spot, samples);
        let source = wrap_shadowed(k, Entry::Spot, stride)?;
        let data = pack_shadowed(rays.iter().map(SpotRay::pack), samples, Entry::Spot);
        let out = self.dispatch(k.shader(&source), k.prefix, &data, stride, rays.len(), 3, k.table)?;
        Ok(out.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect())
    }

    /// Rays per second through a kernel's shafts accumulator, as [`Gpu::throughput`].
    pub fn shadowed_throughput(
        &self,
        k: &KernelSource,
        rays: &[Ray],
        samples: &[Vec<[f32; 2]>],
        repeats: usize,
    ) -> Result<Option<f64>, GpuError> {
        let stride = shadowed_stride(Entry::Radiance, samples);
        let data = pack_shadowed(rays.iter().map(Ray::pack), samples, Entry::Radiance);
        self.timed_source(k, &wrap_shadowed(k, Entry::Radiance, stride)?, 1, &data, rays.len(), repeats)
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
    fn timed(
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
    fn timed_source(
        &self,
        k: &KernelSource,
        source: &str,
        outputs: usize,
        data: &[f32],
        n: usize,
        repeats: usize,
    ) -> Result<Option<f64>, GpuError> {
        if !self.device.features().contains(wgpu::Features::TIMESTAMP_QUERY) || n == 0 {
            return Ok(None);
        }
        let (gx, gy) = workgroups(n)?;
        let run = self.prepare(k.shader(source), k.prefix, data, n * outputs, k.table)?;
        let d = &self.device;
        let queries = d.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("bench"),
            ty: wgpu::QueryType::Timestamp,
            count: 2,
        });
        let resolve = d.create_buffer(&wgpu::BufferDescriptor {
            label: Some("timestamps"),
            size: 16,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let staging = d.create_buffer(&wgpu::BufferDescriptor {
            label: Some("timestamps staging"),
            size: 16,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let period = f64::from(self.queue.get_timestamp_period());
        let mut times = Vec::with_capacity(repeats + 1);
        // One warm-up dispatch, then the timed ones.
        for _ in 0..=repeats {
            let mut enc = d.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
            {
                let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: None,
                    timestamp_writes: Some(wgpu::ComputePassTimestampWrites {
                        query_set: &queries,
                        beginning_of_pass_write_index: Some(0),
                        end_of_pass_write_index: Some(1),
                    }),
                });
                pass.set_pipeline(&run.pipeline);
                pass.set_bind_group(0, &run.bind, &[]);
                pass.dispatch_workgroups(gx, gy, 1);
            }
            enc.resolve_query_set(&queries, 0..2, &resolve, 0);
            enc.copy_buffer_to_buffer(&resolve, 0, &staging, 0, 16);
            self.queue.submit([enc.finish()]);
            let t: Vec<u64> = bytemuck::cast_slice(&self.read_back(&staging)?).to_vec();
            times.push(t[1].saturating_sub(t[0]) as f64 * period * 1e-9);
        }
        let mut timed = times.split_off(1);
        timed.sort_by(f64::total_cmp);
        let median = timed[timed.len() / 2];
        Ok((median > 0.0).then(|| n as f64 / median))
    }

    /// The bind group of a harness pipeline: inputs (0), results (1) and, for a
    /// table-driven kernel, its table as an r32float texture (2) and, where the
    /// shader declares one (GLSL's separate sampler), a nearest sampler (3).
    fn bind(
        &self,
        pipeline: &wgpu::ComputePipeline,
        input: &wgpu::Buffer,
        output: &wgpu::Buffer,
        table: Option<&Table>,
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
        let layout = pipeline.get_bind_group_layout(0);
        let attempt = |entries: &[wgpu::BindGroupEntry]| {
            let scope = d.push_error_scope(wgpu::ErrorFilter::Validation);
            let bind = d.create_bind_group(&wgpu::BindGroupDescriptor { label: None, layout: &layout, entries });
            match pollster::block_on(scope.pop()) {
                None => Ok(bind),
                Some(e) => Err(GpuError::Shader(e.to_string())),
            }
        };
        match attempt(&entries) {
            // A shader without the sampler (WGSL; GLSL where naga drops an unused one): bind without it.
            Err(_) if entries.len() == 4 => attempt(&entries[..3]),
            other => other,
        }
    }

    /// Runs a compute shader with entry `main` over `n` items of `stride` vec4s
    /// each (binding 0) into `outputs` f32 per item (binding 1).
    #[allow(clippy::too_many_arguments)]
    fn dispatch(
        &self,
        shader: wgpu::ShaderSource,
        label: &str,
        data: &[f32],
        stride: usize,
        n: usize,
        outputs: usize,
        table: Option<&Table>,
    ) -> Result<Vec<f32>, GpuError> {
        if n == 0 {
            return Ok(Vec::new());
        }
        let (gx, gy) = workgroups(n)?;
        debug_assert_eq!(data.len(), n * stride * 4);
        let run = self.prepare(shader, label, data, n * outputs, table)?;
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
    fn prepare(
        &self,
        shader: wgpu::ShaderSource,
        label: &str,
        data: &[f32],
        n: usize,
        table: Option<&Table>,
    ) -> Result<Prepared, GpuError> {
        let d = &self.device;
        let scope = d.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = d.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some(label), source: shader });
        let pipeline = d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(label),
            layout: None,
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(GpuError::Shader(e.to_string()));
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
        let bind = self.bind(&pipeline, &input, &output, table)?;
        Ok(Prepared { pipeline, bind, output })
    }

    /// Maps `staging` after the submitted work, and copies its bytes out.
    fn read_back(&self, staging: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
        let (tx, rx) = std::sync::mpsc::channel();
        staging.map_async(wgpu::MapMode::Read, .., move |r| {
            let _ = tx.send(r);
        });
        self.device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| GpuError::Readback(e.to_string()))?;
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
struct Prepared {
    pipeline: wgpu::ComputePipeline,
    bind: wgpu::BindGroup,
    output: wgpu::Buffer,
}

/// The dispatch for `n` items: one invocation each, in workgroups of
/// [`WORKGROUP`], 2-D beyond 65,535 workgroups.
fn workgroups(n: usize) -> Result<(u32, u32), GpuError> {
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

fn pack_points(points: &[[f64; 4]]) -> Vec<f32> {
    points.iter().flat_map(|p| [p[0] as f32, p[1] as f32, rho_arg(p[2]), p[3] as f32]).collect()
}

/// A kernel's result as `A`: kernels saturate at `f32::MAX` where `A` diverges
/// (the ray through the light), which is ∞ here.
pub fn from_kernel(v: f32) -> f64 {
    if v == f32::MAX {
        f64::INFINITY
    } else {
        f64::from(v)
    }
}

/// A generated kernel as the harness sees it: its text and the arguments of its
/// two entry points (from `generated/kernels.toml`).
#[derive(Debug, Clone, Copy)]
pub struct KernelSource<'a> {
    /// Language: [`Target::Wgsl`] or [`Target::Glsl`].
    pub language: Target,
    /// The kernel file's text.
    pub source: &'a str,
    /// Prefix of its items, e.g. `airlight_segments_8_`.
    pub prefix: &'a str,
    /// Arguments of `<prefix>airlight`.
    pub params: &'a [Arg],
    /// Arguments of `<prefix>radiance`.
    pub radiance_params: &'a [Arg],
    /// Arguments of `<prefix>spot` (empty: it has none).
    pub spot_params: &'a [Arg],
    /// The table it reads, bound as a texture (binding 2; GLSL: a sampler at 3).
    pub table: Option<&'a Table>,
}

/// A kernel's table: `size × size` f32 texels, row-major.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// Texels per side.
    pub size: usize,
    /// The texels.
    pub texels: Vec<f32>,
}

/// The table `entry` reads (`generated/<path>`), if it has one.
pub fn load_table(generated: &std::path::Path, entry: &IndexEntry) -> Result<Option<Table>, GpuError> {
    let Some(t) = &entry.table else { return Ok(None) };
    let path = generated.join(&t.path);
    let bytes = std::fs::read(&path).map_err(|e| GpuError::Shader(format!("{}: cannot read: {e}", path.display())))?;
    if bytes.len() != 4 * t.size * t.size {
        return Err(GpuError::Shader(format!(
            "{}: {} bytes, but kernels.toml says {}x{} f32 texels",
            path.display(),
            bytes.len(),
            t.size,
            t.size
        )));
    }
    let texels = bytes.chunks_exact(4).map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect();
    Ok(Some(Table { size: t.size, texels }))
}

impl<'a> KernelSource<'a> {
    /// The same kernel with its table.
    pub fn with_table(self, table: Option<&'a Table>) -> KernelSource<'a> {
        KernelSource { table, ..self }
    }

    /// The kernel `entry` of `generated/kernels.toml`, its `language` file's text being `source`.
    pub fn of(entry: &'a IndexEntry, language: Target, source: &'a str) -> KernelSource<'a> {
        KernelSource {
            language,
            source,
            prefix: &entry.prefix,
            params: &entry.params,
            radiance_params: &entry.radiance_params,
            spot_params: &entry.spot_params,
            table: None,
        }
    }

    fn shader<'s>(&self, wrapped: &'s str) -> wgpu::ShaderSource<'s> {
        match self.language {
            Target::Glsl => wgpu::ShaderSource::Glsl {
                shader: wrapped.into(),
                stage: wgpu::naga::ShaderStage::Compute,
                defines: &[("AIRLIGHT_SEPARATE_SAMPLERS", "1")],
            },
            _ => wgpu::ShaderSource::Wgsl(wrapped.into()),
        }
    }

    fn args(&self, entry: Entry) -> &'a [Arg] {
        match entry {
            Entry::Canonical => self.params,
            Entry::Radiance => self.radiance_params,
            Entry::Spot => self.spot_params,
        }
    }
}

/// One view ray and its light and medium, for the physical entry point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray {
    /// Ray origin (the viewer).
    pub origin: [f32; 3],
    /// Ray direction (need not be normalised).
    pub dir: [f32; 3],
    /// Distance to the first surface along the ray; negative: none.
    pub surface: f32,
    /// Light position.
    pub light: [f32; 3],
    /// Radiant intensity.
    pub intensity: f32,
    /// Extinction coefficient.
    pub sigma_t: f32,
    /// Scattering coefficient.
    pub sigma_s: f32,
    /// Henyey–Greenstein asymmetry.
    pub g: f32,
}

impl Ray {
    /// An `eval` CSV row as the physical entry takes it (f32; no surface: −1).
    pub fn from_row(r: &airlight_truth::points_csv::RayRow) -> Ray {
        let f = |v: [f64; 3]| v.map(|x| x as f32);
        Ray {
            origin: f(r.ray.origin),
            dir: f(r.ray.direction),
            surface: r.ray.surface_distance.map_or(-1.0, |s| s as f32),
            light: f(r.ray.light),
            intensity: r.ray.intensity as f32,
            sigma_t: r.ray.sigma_t as f32,
            sigma_s: r.ray.sigma_s as f32,
            g: r.g as f32,
        }
    }

    /// The same ray in f64, for the reference (`surface < 0`: none).
    pub fn physical(&self) -> airlight_truth::geometry::PhysicalRay {
        let f = |v: [f32; 3]| v.map(f64::from);
        airlight_truth::geometry::PhysicalRay {
            origin: f(self.origin),
            direction: f(self.dir),
            surface_distance: (self.surface >= 0.0).then_some(f64::from(self.surface)),
            light: f(self.light),
            intensity: f64::from(self.intensity),
            sigma_t: f64::from(self.sigma_t),
            sigma_s: f64::from(self.sigma_s),
        }
    }

    /// A compiled Rust kernel's physical entry on this ray.
    pub fn radiance_of(&self, k: &airlight_shapes::vocab::CompiledKernel) -> f32 {
        (k.radiance)(
            self.origin,
            self.dir,
            self.surface,
            self.light,
            self.intensity,
            self.sigma_t,
            self.sigma_s,
            self.g,
        )
    }

    /// The arguments in their packing slots ([`Arg::slot`]).
    fn pack(&self) -> [f32; 16] {
        pack_slots(Entry::Radiance, |a| match a {
            Arg::Origin => &self.origin,
            Arg::Dir => &self.dir,
            Arg::Light => &self.light,
            Arg::Surface => std::slice::from_ref(&self.surface),
            Arg::Intensity => std::slice::from_ref(&self.intensity),
            Arg::SigmaT => std::slice::from_ref(&self.sigma_t),
            Arg::SigmaS => std::slice::from_ref(&self.sigma_s),
            Arg::G => std::slice::from_ref(&self.g),
            other => unreachable!("{other} is not an argument of radiance"),
        })
    }
}

/// One view ray with a spot light and an RGB medium, for the spot entry point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpotRay {
    /// Ray origin (the viewer).
    pub origin: [f32; 3],
    /// Ray direction (need not be normalised).
    pub dir: [f32; 3],
    /// Distance to the first surface along the ray; negative: none.
    pub surface: f32,
    /// Light position.
    pub light: [f32; 3],
    /// The cone's axis, from the light.
    pub axis: [f32; 3],
    /// Cosine of the outer half-angle (`<= -1`: a point light).
    pub cos_outer: f32,
    /// Cosine of the inner half-angle (`<= cos_outer`: a hard edge).
    pub cos_inner: f32,
    /// Radiant intensity.
    pub intensity: f32,
    /// Extinction coefficient per channel.
    pub sigma_t: [f32; 3],
    /// Scattering coefficient per channel.
    pub sigma_s: [f32; 3],
    /// Henyey–Greenstein asymmetry.
    pub g: f32,
}

impl SpotRay {
    /// An `eval` CSV row as the spot entry takes it (f32; no surface: −1; a point
    /// light: `cos_outer` −1).
    pub fn from_row(r: &airlight_truth::points_csv::SpotRow) -> SpotRay {
        let f = |v: [f64; 3]| v.map(|x| x as f32);
        let ray = &r.rays[0];
        let (axis, co, ci) = match &r.cone {
            Some(c) => (f(c.axis), c.cos_outer as f32, c.cos_inner as f32),
            None => ([0.0, 0.0, 1.0], -1.0, -1.0),
        };
        SpotRay {
            origin: f(ray.origin),
            dir: f(ray.direction),
            surface: ray.surface_distance.map_or(-1.0, |s| s as f32),
            light: f(ray.light),
            axis,
            cos_outer: co,
            cos_inner: ci,
            intensity: ray.intensity as f32,
            sigma_t: r.rays.each_ref().map(|x| x.sigma_t as f32),
            sigma_s: r.rays.each_ref().map(|x| x.sigma_s as f32),
            g: r.g as f32,
        }
    }

    /// Channel `c` of the ray in f64, as a point-light ray (`surface < 0`: none).
    pub fn physical(&self, c: usize) -> airlight_truth::geometry::PhysicalRay {
        let ray = Ray {
            origin: self.origin,
            dir: self.dir,
            surface: self.surface,
            light: self.light,
            intensity: self.intensity,
            sigma_t: self.sigma_t[c],
            sigma_s: self.sigma_s[c],
            g: self.g,
        };
        ray.physical()
    }

    /// The cone in f64; `None` for a point light (`cos_outer <= -1`).
    pub fn cone(&self) -> Option<airlight_truth::geometry::Cone> {
        (self.cos_outer > -1.0).then(|| airlight_truth::geometry::Cone {
            axis: self.axis.map(f64::from),
            cos_outer: f64::from(self.cos_outer),
            cos_inner: f64::from(self.cos_inner),
        })
    }

    /// The reference radiance of channel `c`, `A` by `a` (the f64 reference or a
    /// model): through the cone's lit stretch, or the whole ray for a point light.
    pub fn reference(
        &self,
        c: usize,
        a: &dyn Fn(airlight_truth::reference::Point) -> f64,
    ) -> Result<f64, airlight_truth::geometry::GeometryError> {
        self.physical(c).light_radiance(self.cone().as_ref(), f64::from(self.g), a)
    }

    /// A compiled Rust kernel's spot entry on this ray, where it has one.
    pub fn spot_of(&self, k: &airlight_shapes::vocab::CompiledKernel) -> Option<[f32; 3]> {
        k.spot.map(|f| {
            f(
                self.origin,
                self.dir,
                self.surface,
                self.light,
                self.axis,
                self.cos_outer,
                self.cos_inner,
                self.intensity,
                self.sigma_t,
                self.sigma_s,
                self.g,
            )
        })
    }

    /// The arguments in their packing slots ([`Arg::slot`]).
    fn pack(&self) -> [f32; 24] {
        pack_slots(Entry::Spot, |a| match a {
            Arg::Origin => &self.origin,
            Arg::Dir => &self.dir,
            Arg::Light => &self.light,
            Arg::Axis => &self.axis,
            Arg::SigmaTRgb => &self.sigma_t,
            Arg::SigmaSRgb => &self.sigma_s,
            Arg::Surface => std::slice::from_ref(&self.surface),
            Arg::CosOuter => std::slice::from_ref(&self.cos_outer),
            Arg::CosInner => std::slice::from_ref(&self.cos_inner),
            Arg::Intensity => std::slice::from_ref(&self.intensity),
            Arg::G => std::slice::from_ref(&self.g),
            other => unreachable!("{other} is not an argument of spot"),
        })
    }
}

/// `entry`'s arguments in their packing slots ([`Arg::slot`]), `N` = 4 ×
/// [`Entry::packed_vec4s`]; `value` gives each argument's lanes.
fn pack_slots<'a, const N: usize>(entry: Entry, value: impl Fn(Arg) -> &'a [f32]) -> [f32; N] {
    debug_assert_eq!(N, 4 * entry.packed_vec4s());
    let mut out = [0.0; N];
    for &a in entry.all_args() {
        let (v, lane) = a.slot(entry).expect("every argument of an entry has a slot");
        let values = value(a);
        out[4 * v + lane..4 * v + lane + values.len()].copy_from_slice(values);
    }
    out
}

/// The WGSL/GLSL expression that reads argument `a` of `entry` from the harness's
/// packed inputs `x` (its slot, [`Arg::slot`]).
fn arg_expr(k: &KernelSource, entry: Entry, a: Arg) -> Result<String, GpuError> {
    let (v, lane) = a
        .slot(entry)
        .ok_or_else(|| GpuError::Shader(format!("{}: '{a}' is not an argument of {}", k.prefix, entry.function())))?;
    let lanes = ["x", "y", "z", "w"];
    Ok(match a.ty() {
        ArgType::Scalar => format!("x[{v}].{}", lanes[lane]),
        ArgType::Vec3 => format!("x[{v}].{}", lanes[lane..lane + 3].concat()),
    })
}

/// The harness's store of the result `r` (`outputs` f32 per item).
fn store_results(outputs: usize) -> String {
    if outputs == 1 {
        return "airlight_results[i] = r;".to_string();
    }
    let lanes = ["x", "y", "z", "w"];
    (0..outputs)
        .map(|j| format!("airlight_results[i * {outputs}u + {j}u] = r.{};", lanes[j]))
        .collect::<Vec<_>>()
        .join(" ")
}

/// A harness needs a shading language.
fn shader_only(k: &KernelSource) -> Result<(), GpuError> {
    if k.language.is_shader() {
        Ok(())
    } else {
        Err(GpuError::Shader(format!("{}: {} is not a shading language", k.prefix, k.language)))
    }
}

/// The compute shader around one of a generated kernel's entry points: one
/// invocation per item, arguments taken by name from the packed inputs.
fn wrap(k: &KernelSource, entry: Entry) -> Result<String, GpuError> {
    let glsl = k.language == Target::Glsl;
    shader_only(k)?;
    let arg = |a: Arg| arg_expr(k, entry, a);
    let stride = entry.packed_vec4s();
    let outputs = entry.outputs();
    let store = store_results(outputs);
    let args = k.args(entry).iter().map(|&p| arg(p)).collect::<Result<Vec<_>, _>>()?.join(", ");
    let call = format!("{}{}({args})", k.prefix, entry.function());
    Ok(if glsl {
        format!(
            "#version 450\n{src}\n\
// ---- airlight harness (shaders/src/lib.rs) ----\n\
layout(local_size_x = {WORKGROUP}) in;\n\
layout(std430, set = 0, binding = 0) readonly buffer AirlightInputs {{ vec4 airlight_inputs[]; }};\n\
layout(std430, set = 0, binding = 1) buffer AirlightResults {{ float airlight_results[]; }};\n\
void main() {{\n\
    uint i = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * {WORKGROUP}u;\n\
    if (i >= uint(airlight_results.length()) / {outputs}u) {{\n\
        return;\n\
    }}\n\
    vec4 x[{stride}];\n\
    for (uint j = 0u; j < {stride}u; j++) {{\n\
        x[j] = airlight_inputs[i * {stride}u + j];\n\
    }}\n\
    {ty} r = {call};\n\
    {store}\n\
}}\n",
            src = k.source,
            ty = if outputs == 1 { "float" } else { "vec3" }
        )
    } else {
        format!(
            "{src}\n\
// ---- airlight harness (shaders/src/lib.rs) ----\n\
@group(0) @binding(0) var<storage, read> airlight_inputs: array<vec4<f32>>;\n\
@group(0) @binding(1) var<storage, read_write> airlight_results: array<f32>;\n\
\n\
@compute @workgroup_size({WORKGROUP})\n\
fn main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {{\n\
    let i = id.x + id.y * groups.x * {WORKGROUP}u;\n\
    if (i >= arrayLength(&airlight_results) / {outputs}u) {{\n\
        return;\n\
    }}\n\
    var x: array<vec4<f32>, {stride}>;\n\
    for (var j = 0u; j < {stride}u; j++) {{\n\
        x[j] = airlight_inputs[i * {stride}u + j];\n\
    }}\n\
    let r = {call};\n\
    {store}\n\
}}\n",
            src = k.source
        )
    })
}

/// `vec4`s per shadowed item of a batch: the entry's arguments, a count, and the
/// samples two by two, as many as the batch's longest item has (no cap: a batch's
/// only limit is the adapter's largest storage buffer, 128 MiB by default, about
/// eight million samples in all).
fn shadowed_stride(entry: Entry, samples: &[Vec<[f32; 2]>]) -> usize {
    entry.packed_vec4s() + 1 + samples.iter().map(Vec::len).max().unwrap_or(0).div_ceil(2)
}

/// Packs shadowed items: each entry's packed arguments, `[count, 0, 0, 0]`, then
/// the `[s, v]` samples two to a `vec4`, zero-padded to [`shadowed_stride`].
fn pack_shadowed<I, A>(items: I, samples: &[Vec<[f32; 2]>], entry: Entry) -> Vec<f32>
where
    I: Iterator<Item = A>,
    A: AsRef<[f32]>,
{
    let stride = shadowed_stride(entry, samples);
    let mut out = Vec::new();
    for (args, sv) in items.zip(samples) {
        let start = out.len();
        out.extend_from_slice(args.as_ref());
        out.extend_from_slice(&[sv.len() as f32, 0.0, 0.0, 0.0]);
        out.extend(sv.iter().flatten());
        out.resize(start + 4 * stride, 0.0);
    }
    out
}

/// The compute shader around a kernel's shafts accumulator over `entry`: per item
/// its arguments, then its samples pushed in order, then finished at its surface.
fn wrap_shadowed(k: &KernelSource, entry: Entry, stride: usize) -> Result<String, GpuError> {
    let glsl = k.language == Target::Glsl;
    shader_only(k)?;
    let arg = |a: Arg| arg_expr(k, entry, a);
    let pass = k
        .args(entry)
        .iter()
        .filter(|&&a| a != Arg::Surface)
        .map(|&a| arg(a))
        .collect::<Result<Vec<_>, _>>()?
        .join(", ");
    let end = arg(Arg::Surface)?;
    let (args, outputs) = (entry.packed_vec4s(), entry.outputs());
    // Every push is followed by a flush of a full buffer: exact for any number of
    // lit runs, as the f64 accumulator is.
    let (push, flush, finish) = match entry {
        Entry::Spot => ("shafts_push_spot", "shafts_flush_spot", "shafts_finish_spot"),
        _ => ("shafts_push", "shafts_flush", "shafts_finish"),
    };
    let p = k.prefix;
    let store = store_results(outputs);
    Ok(if glsl {
        format!(
            "#version 450\n{src}\n\
// ---- airlight harness (shaders/src/lib.rs): the shafts accumulator ----\n\
layout(local_size_x = {WORKGROUP}) in;\n\
layout(std430, set = 0, binding = 0) readonly buffer AirlightInputs {{ vec4 airlight_inputs[]; }};\n\
layout(std430, set = 0, binding = 1) buffer AirlightResults {{ float airlight_results[]; }};\n\
void main() {{\n\
    uint i = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * {WORKGROUP}u;\n\
    if (i >= uint(airlight_results.length()) / {outputs}u) {{\n\
        return;\n\
    }}\n\
    uint base = i * {stride}u;\n\
    vec4 x[{args}];\n\
    for (uint j = 0u; j < {args}u; j++) {{\n\
        x[j] = airlight_inputs[base + j];\n\
    }}\n\
    uint n = uint(airlight_inputs[base + {args}u].x);\n\
    {p}Shafts acc = {p}shafts_begin();\n\
    for (uint j = 0u; j < n; j++) {{\n\
        vec4 q = airlight_inputs[base + {args}u + 1u + j / 2u];\n\
        vec2 sv = (j & 1u) == 1u ? q.zw : q.xy;\n\
        {p}{push}(acc, sv.x, sv.y, {pass});\n\
        if ({p}shafts_full(acc)) {{\n\
            {p}{flush}(acc, {pass});\n\
        }}\n\
    }}\n\
    {ty} r = {p}{finish}(acc, {end}, {pass});\n\
    {store}\n\
}}\n",
            src = k.source,
            ty = if outputs == 1 { "float" } else { "vec3" }
        )
    } else {
        format!(
            "{src}\n\
// ---- airlight harness (shaders/src/lib.rs): the shafts accumulator ----\n\
@group(0) @binding(0) var<storage, read> airlight_inputs: array<vec4<f32>>;\n\
@group(0) @binding(1) var<storage, read_write> airlight_results: array<f32>;\n\
\n\
@compute @workgroup_size({WORKGROUP})\n\
fn main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {{\n\
    let i = id.x + id.y * groups.x * {WORKGROUP}u;\n\
    if (i >= arrayLength(&airlight_results) / {outputs}u) {{\n\
        return;\n\
    }}\n\
    let base = i * {stride}u;\n\
    var x: array<vec4<f32>, {args}>;\n\
    for (var j = 0u; j < {args}u; j++) {{\n\
        x[j] = airlight_inputs[base + j];\n\
    }}\n\
    let n = u32(airlight_inputs[base + {args}u].x);\n\
    var acc = {p}shafts_begin();\n\
    for (var j = 0u; j < n; j++) {{\n\
        let q = airlight_inputs[base + {args}u + 1u + j / 2u];\n\
        let sv = select(q.xy, q.zw, (j & 1u) == 1u);\n\
        {p}{push}(&acc, sv.x, sv.y, {pass});\n\
        if {p}shafts_full(acc) {{\n\
            {p}{flush}(&acc, {pass});\n\
        }}\n\
    }}\n\
    let r = {p}{finish}(acc, {end}, {pass});\n\
    {store}\n\
}}\n",
            src = k.source
        )
    })
}

/// The compute shader around a kernel: one invocation per point, 2-D dispatch
/// for batches beyond 65,535 workgroups.
pub fn wrap_kernel(kernel: &str, function: &str) -> String {
    format!(
        "{kernel}\n\
// ---- airlight harness (shaders/src/lib.rs) ----\n\
@group(0) @binding(0) var<storage, read> airlight_points: array<vec4<f32>>;\n\
@group(0) @binding(1) var<storage, read_write> airlight_results: array<f32>;\n\
\n\
@compute @workgroup_size({WORKGROUP})\n\
fn main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {{\n\
    let i = id.x + id.y * groups.x * {WORKGROUP}u;\n\
    if (i >= arrayLength(&airlight_points)) {{\n\
        return;\n\
    }}\n\
    let p = airlight_points[i];\n\
    airlight_results[i] = {function}(p.x, p.y, p.z, p.w);\n\
}}\n"
    )
}
/// A compiled Rust kernel's canonical entry at `p` (arguments rounded to f32,
/// `ρ = ∞` passed as −1), as f64; the kernel's `HUGE` (the ray through the light) is ∞.
pub fn f32_value(k: &airlight_shapes::vocab::CompiledKernel, p: airlight_truth::reference::Point) -> f64 {
    from_kernel((k.airlight)(p.tau as f32, p.gamma as f32, rho_arg(p.rho), p.g as f32))
}
