//! The shafts accumulator on the GPU adapter: a kernel's accumulator over its
//! physical or spot entry, fed each ray's `[s, v]` visibility samples in order and
//! finished at its surface ([`Gpu::shadowed`], [`Gpu::spot_shadowed`]), and its
//! throughput.

use crate::error::GpuError;
use crate::gpu::Gpu;
use crate::wrap::KernelSource;
use crate::wrap::WORKGROUP;
use crate::wrap::{arg_expr, shader_only, store_results};
use crate::{Arg, Entry, Ray, SpotRay, Target};

impl Gpu {
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
}

/// `vec4`s per shadowed item of a batch: the entry's arguments, a count, and the
/// samples two by two, as many as the batch's longest item has (no cap: a batch's
/// only limit is the adapter's largest storage buffer, 128 MiB by default, about
/// eight million samples in all).
pub(crate) fn shadowed_stride(entry: Entry, samples: &[Vec<[f32; 2]>]) -> usize {
    entry.packed_vec4s() + 1 + samples.iter().map(Vec::len).max().unwrap_or(0).div_ceil(2)
}

/// Packs shadowed items: each entry's packed arguments, `[count, 0, 0, 0]`, then
/// the `[s, v]` samples two to a `vec4`, zero-padded to [`shadowed_stride`].
pub(crate) fn pack_shadowed<I, A>(items: I, samples: &[Vec<[f32; 2]>], entry: Entry) -> Vec<f32>
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
pub(crate) fn wrap_shadowed(k: &KernelSource, entry: Entry, stride: usize) -> Result<String, GpuError> {
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
// ---- airlight harness (shaders/src/shafts/harness.rs): the shafts accumulator ----\n\
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
// ---- airlight harness (shaders/src/shafts/harness.rs): the shafts accumulator ----\n\
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
