//! airlight-shaders: the wgpu harness. It opens a GPU adapter headlessly (a real
//! GPU, or Mesa's lavapipe software Vulkan driver where there is none), wraps a
//! WGSL kernel function in a compute shader, evaluates it on a batch of
//! canonical points `(τ, γ, ρ, g)` and reads the f32 results back.
//!
//! Kernel ABI: `fn NAME(tau: f32, gamma: f32, rho: f32, g: f32) -> f32`, with
//! `rho = NO_SURFACE` (−1) standing for `ρ = ∞`: WGSL implementations may assume
//! no infinities, so none is ever passed to a shader.

#![warn(missing_docs)]

use std::fmt;
use wgpu::util::DeviceExt;

/// The value of `rho` that means "no surface" (`ρ = ∞`) in every kernel.
pub const NO_SURFACE: f32 = -1.0;

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
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("airlight harness"),
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
        if points.is_empty() {
            return Ok(Vec::new());
        }
        let n = points.len();
        let groups = (n as u64).div_ceil(WORKGROUP as u64);
        if groups > MAX_GROUPS_X as u64 * MAX_GROUPS_X as u64 {
            return Err(GpuError::TooLarge(n));
        }
        let (gx, gy) = if groups <= MAX_GROUPS_X as u64 {
            (groups as u32, 1)
        } else {
            (MAX_GROUPS_X, groups.div_ceil(MAX_GROUPS_X as u64) as u32)
        };
        let source = wrap_kernel(kernel, function);
        let data: Vec<f32> = points
            .iter()
            .flat_map(|p| {
                let rho = if p[2].is_infinite() { NO_SURFACE } else { p[2] as f32 };
                [p[0] as f32, p[1] as f32, rho, p[3] as f32]
            })
            .collect();
        let d = &self.device;
        let scope = d.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = d.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(function),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let pipeline = d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(function),
            layout: None,
            module: &module,
            entry_point: Some("airlight_harness_main"),
            compilation_options: Default::default(),
            cache: None,
        });
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(GpuError::Shader(e.to_string()));
        }
        let input = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("points"),
            contents: bytemuck::cast_slice(&data),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let bytes = (n * 4) as u64;
        let output = d.create_buffer(&wgpu::BufferDescriptor {
            label: Some("results"),
            size: bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let staging = d.create_buffer(&wgpu::BufferDescriptor {
            label: Some("staging"),
            size: bytes,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: input.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: output.as_entire_binding() },
            ],
        });
        let mut enc = d.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: None, timestamp_writes: None });
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind, &[]);
            pass.dispatch_workgroups(gx, gy, 1);
        }
        enc.copy_buffer_to_buffer(&output, 0, &staging, 0, bytes);
        self.queue.submit([enc.finish()]);
        let (tx, rx) = std::sync::mpsc::channel();
        staging.map_async(wgpu::MapMode::Read, .., move |r| {
            let _ = tx.send(r);
        });
        d.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| GpuError::Readback(e.to_string()))?;
        rx.recv().map_err(|e| GpuError::Readback(e.to_string()))?.map_err(|e| GpuError::Readback(e.to_string()))?;
        let view = staging.get_mapped_range(..).map_err(|e| GpuError::Readback(e.to_string()))?;
        let out: Vec<f32> = bytemuck::cast_slice(&view).to_vec();
        drop(view);
        staging.unmap();
        Ok(out)
    }
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
fn airlight_harness_main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {{\n\
    let i = id.x + id.y * groups.x * {WORKGROUP}u;\n\
    if (i >= arrayLength(&airlight_points)) {{\n\
        return;\n\
    }}\n\
    let p = airlight_points[i];\n\
    airlight_results[i] = {function}(p.x, p.y, p.z, p.w);\n\
}}\n"
    )
}
