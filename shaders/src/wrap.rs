//! The compute shader around a generated kernel: [`KernelSource`] (a WGSL or GLSL
//! kernel and the arguments it takes), the wrapper per entry (canonical, physical,
//! spot) and the hand-written ABI of [`wrap_kernel`].

use crate::error::GpuError;
use crate::rho_arg;
use crate::{Arg, Entry, Target};
use airlight_shapes::vocab::{ArgType, IndexEntry};

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

    pub(crate) fn shader<'s>(&self, wrapped: &'s str) -> wgpu::ShaderSource<'s> {
        match self.language {
            Target::Glsl => wgpu::ShaderSource::Glsl {
                shader: wrapped.into(),
                stage: wgpu::naga::ShaderStage::Compute,
                defines: &[("AIRLIGHT_SEPARATE_SAMPLERS", "1")],
            },
            _ => wgpu::ShaderSource::Wgsl(wrapped.into()),
        }
    }

    pub(crate) fn args(&self, entry: Entry) -> &'a [Arg] {
        match entry {
            Entry::Canonical => self.params,
            Entry::Radiance => self.radiance_params,
            Entry::Spot => self.spot_params,
        }
    }
}

/// The WGSL/GLSL expression that reads argument `a` of `entry` from the harness's
/// packed inputs `x` (its slot, [`Arg::slot`]).
pub(crate) fn arg_expr(k: &KernelSource, entry: Entry, a: Arg) -> Result<String, GpuError> {
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
pub(crate) fn store_results(outputs: usize) -> String {
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
pub(crate) fn shader_only(k: &KernelSource) -> Result<(), GpuError> {
    if k.language.is_shader() {
        Ok(())
    } else {
        Err(GpuError::Shader(format!("{}: {} is not a shading language", k.prefix, k.language)))
    }
}

/// The compute shader around one of a generated kernel's entry points: one
/// invocation per item, arguments taken by name from the packed inputs.
pub(crate) fn wrap(k: &KernelSource, entry: Entry) -> Result<String, GpuError> {
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
// ---- airlight harness (shaders/src/wrap.rs) ----\n\
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
// ---- airlight harness (shaders/src/wrap.rs) ----\n\
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

/// The compute shader around a kernel: one invocation per point, 2-D dispatch
/// for batches beyond 65,535 workgroups.
pub fn wrap_kernel(kernel: &str, function: &str) -> String {
    format!(
        "{kernel}\n\
// ---- airlight harness (shaders/src/wrap.rs) ----\n\
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

pub(crate) const WORKGROUP: u32 = 64;

pub(crate) const MAX_GROUPS_X: u32 = 65_535;

/// A kernel's result as `A`: kernels saturate at `f32::MAX` where `A` diverges
/// (the ray through the light), which is ∞ here.
pub fn from_kernel(v: f32) -> f64 {
    if v == f32::MAX {
        f64::INFINITY
    } else {
        f64::from(v)
    }
}
