//! The exact mode on the GPU adapter: a shadow map's depths uploaded, its min-max
//! pyramid built by the shipped pass (`generated/wgsl/shadowmap_pyramid.wgsl`),
//! and a kernel's shafts accumulator fed the lit runs of the shipped walk
//! (`generated/{wgsl,glsl}/shadowmap.*`) in one compute shader per ray batch
//! ([`Gpu::mapped`], [`Gpu::spot_mapped`]), with the walk's step count per ray.

use crate::error::GpuError;
use crate::gpu::{Gpu, Stamps};
use crate::wrap::{arg_expr, shader_only, KernelSource, WORKGROUP};
use crate::{Arg, Entry, Ray, SpotRay, Target};

/// How the walk reads one map: a cube map or one face (`rows`, the face's
/// `M`), texels per side, and the test's bias.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapSpec {
    /// Six faces (a point light) or one (a spot light, `rows`).
    pub cube: bool,
    /// `M`'s rows of a spot map's face (unused for a cube).
    pub rows: [[f32; 3]; 3],
    /// Texels per side (a power of two).
    pub res: u32,
    /// The depth test's bias.
    pub bias: f32,
    /// The pyramid layer of the map's first face (several maps in one array).
    pub layer: u32,
}

impl MapSpec {
    fn pack(&self) -> [f32; 16] {
        let r = self.rows;
        [
            r[0][0],
            r[0][1],
            r[0][2],
            0.0,
            r[1][0],
            r[1][1],
            r[1][2],
            0.0,
            r[2][0],
            r[2][1],
            r[2][2],
            0.0,
            if self.cube { 1.0 } else { 0.0 },
            self.res as f32,
            self.bias,
            self.layer as f32,
        ]
    }
}

/// The walk's sources, as generated: WGSL and GLSL (`generated/wgsl/shadowmap.wgsl`,
/// `generated/glsl/shadowmap.glsl`) and the pyramid pass (`shadowmap_pyramid.wgsl`).
#[derive(Debug, Clone, Copy)]
pub struct WalkSources<'a> {
    /// The WGSL walk.
    pub wgsl: &'a str,
    /// The GLSL walk.
    pub glsl: &'a str,
    /// The WGSL pyramid pass.
    pub pyramid: &'a str,
}

/// The walk's generated files under `generated/`.
pub const WALK_FILES: [&str; 3] = ["wgsl/shadowmap.wgsl", "glsl/shadowmap.glsl", "wgsl/shadowmap_pyramid.wgsl"];

/// The walk's generated files, read.
#[derive(Debug, Clone)]
pub struct WalkTexts {
    wgsl: String,
    glsl: String,
    pyramid: String,
}

impl WalkTexts {
    /// Reads [`WALK_FILES`] under `generated`.
    pub fn load(generated: &std::path::Path) -> Result<WalkTexts, GpuError> {
        let read = |f: &str| {
            let path = generated.join(f);
            std::fs::read_to_string(&path)
                .map_err(|e| GpuError::Shader(format!("{}: cannot read: {e}", path.display())))
        };
        Ok(WalkTexts { wgsl: read(WALK_FILES[0])?, glsl: read(WALK_FILES[1])?, pyramid: read(WALK_FILES[2])? })
    }

    /// The sources, borrowed.
    pub fn sources(&self) -> WalkSources<'_> {
        WalkSources { wgsl: &self.wgsl, glsl: &self.glsl, pyramid: &self.pyramid }
    }
}

/// A map's pyramid on the adapter, built by the shipped pass.
pub struct PyramidTexture {
    texture: wgpu::Texture,
    view: wgpu::TextureView,
    res: u32,
    faces: u32,
    levels: u32,
}

/// A pyramid's passes, one per level (the first two levels in one, where the
/// map has a level 1): the pipeline, its bind group and the nodes per side of
/// the level it writes (the fused pass: level 1's).
struct PyramidPasses {
    steps: Vec<(wgpu::ComputePipeline, wgpu::BindGroup, u32)>,
    faces: u32,
}

impl PyramidPasses {
    /// Records the passes into `enc`; `stamps` (when given) at the first pass's
    /// start and the last one's end.
    fn record(&self, enc: &mut wgpu::CommandEncoder, stamps: Option<&Stamps>) {
        let last = self.steps.len().saturating_sub(1);
        for (i, (pipeline, bind, n)) in self.steps.iter().enumerate() {
            let timestamp_writes = stamps.filter(|_| i == 0 || i == last).map(|st| st.compute(i == 0, i == last));
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: None, timestamp_writes });
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, bind, &[]);
            pass.dispatch_workgroups(n.div_ceil(8), n.div_ceil(8), self.faces);
        }
    }
}

impl PyramidTexture {
    /// The view the walk binds.
    pub fn view(&self) -> &wgpu::TextureView {
        &self.view
    }
}

/// What a mapped dispatch returns per ray: the shadowed value(s) and the walk's
/// steps (negative: it ran out of steps, the rest counted as shadowed).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mapped<T> {
    /// The shadowed in-scattering.
    pub value: T,
    /// The walk's steps; negative where it was truncated.
    pub steps: f32,
}

impl Gpu {
    /// Uploads `faces × res × res` linear depths and builds their min-max pyramid
    /// with the shipped pass.
    pub fn build_pyramid(&self, pass: &str, depth: &[f32], res: u32, faces: u32) -> Result<PyramidTexture, GpuError> {
        let size = wgpu::Extent3d { width: res, height: res, depth_or_array_layers: faces };
        let source = self.depth_source(size);
        self.queue().write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &source,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            bytemuck::cast_slice(depth),
            wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(4 * res), rows_per_image: Some(res) },
            size,
        );
        let (p, levels) = self.pyramid_levels(pass, &source, res, faces, None)?;
        let mut enc = self.device().create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("pyramid") });
        levels.record(&mut enc, None);
        self.queue().submit([enc.finish()]);
        self.failed()?;
        Ok(p)
    }

    /// Builds the min-max pyramid of a rasterised `Depth32Float` shadow map
    /// (`faces` layers of `res²`, perspective depth in [0, 1] between `near` and
    /// `far`) with the shipped pass, which makes the depth linear; and the GPU
    /// seconds of the pass's dispatches (timestamps, the median of `repeats`
    /// builds after a warm-up; 0 without timestamps, and built once, untimed, for
    /// `repeats` 0). The depth is
    /// first copied into an `R32Float` texture (the harness's step, not timed: a
    /// renderer binds its depth texture to the base pass directly).
    pub fn pyramid_of_depth(
        &self,
        pass: &str,
        depth: &wgpu::Texture,
        res: u32,
        faces: u32,
        near_far: [f32; 2],
        repeats: usize,
    ) -> Result<(PyramidTexture, f64), GpuError> {
        let d = self.device();
        let size = wgpu::Extent3d { width: res, height: res, depth_or_array_layers: faces };
        let source = self.depth_source(size);
        let staging = d.create_buffer(&wgpu::BufferDescriptor {
            label: Some("depth copy"),
            size: u64::from(4 * res * res * faces),
            usage: wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let layout = wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(4 * res), rows_per_image: Some(res) };
        let mut enc = d.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("pyramid of depth") });
        enc.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: depth,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::DepthOnly,
            },
            wgpu::TexelCopyBufferInfo { buffer: &staging, layout },
            size,
        );
        enc.copy_buffer_to_texture(
            wgpu::TexelCopyBufferInfo { buffer: &staging, layout },
            source.as_image_copy(),
            size,
        );
        self.queue().submit([enc.finish()]);
        let (p, levels) = self.pyramid_levels(pass, &source, res, faces, Some(near_far))?;
        // Timed as a renderer runs it, once per frame into the same texture: a
        // warm-up, then the median of `repeats` (the first build also pays for
        // the fresh texture's memory).
        let gpu_s = Stamps::median(self, repeats, |enc, st| levels.record(enc, st))?;
        Ok((p, gpu_s))
    }

    /// An `R32Float` array texture the pyramid's base pass reads.
    fn depth_source(&self, size: wgpu::Extent3d) -> wgpu::Texture {
        self.device().create_texture(&wgpu::TextureDescriptor {
            label: Some("shadow map depths"),
            size,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::R32Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        })
    }

    /// The pyramid's texture and its passes, ready to record: the base level
    /// from `source` (linear Z, or made linear for `near_far`), then each level
    /// from the one below.
    fn pyramid_levels(
        &self,
        pass: &str,
        source: &wgpu::Texture,
        res: u32,
        faces: u32,
        near_far: Option<[f32; 2]>,
    ) -> Result<(PyramidTexture, PyramidPasses), GpuError> {
        let d = self.device();
        let levels = res.max(1).trailing_zeros() + 1;
        let size = wgpu::Extent3d { width: res, height: res, depth_or_array_layers: faces };
        let texture = d.create_texture(&wgpu::TextureDescriptor {
            label: Some("shadow map pyramid"),
            size,
            mip_level_count: levels,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rg32Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::STORAGE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let scope = d.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = d.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("shadowmap_pyramid.wgsl"),
            source: wgpu::ShaderSource::Wgsl(pass.into()),
        });
        let pipe = |entry: &str| {
            d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: None,
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let (base, base2, reduce) =
            (pipe("airlight_pyramid_base"), pipe("airlight_pyramid_base2"), pipe("airlight_pyramid_reduce"));
        let array = |t: &wgpu::Texture, level: u32| {
            t.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                base_mip_level: level,
                mip_level_count: Some(1),
                ..Default::default()
            })
        };
        let mut steps = Vec::new();
        // Levels 0 and 1 in one pass where there is a level 1.
        let fused = levels >= 2;
        for level in (0..levels).filter(|&l| !(fused && l == 1)) {
            let n = res >> (level + u32::from(fused && level == 0));
            let [near, far] = near_far.unwrap_or([0.0, 0.0]);
            let params: [u32; 4] = [near.to_bits(), far.to_bits(), n, u32::from(near_far.is_none())];
            let uniform = wgpu::util::DeviceExt::create_buffer_init(
                d,
                &wgpu::util::BufferInitDescriptor {
                    label: Some("pyramid params"),
                    contents: bytemuck::cast_slice(&params),
                    usage: wgpu::BufferUsages::UNIFORM,
                },
            );
            let (pipeline, below) = match level {
                0 if fused => (&base2, array(source, 0)),
                0 => (&base, array(source, 0)),
                _ => (&reduce, array(&texture, level - 1)),
            };
            let out = array(&texture, level);
            let out1 = (fused && level == 0).then(|| array(&texture, 1));
            let mut entries = vec![
                wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&below) },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&out) },
                wgpu::BindGroupEntry { binding: 2, resource: uniform.as_entire_binding() },
            ];
            if let Some(out1) = &out1 {
                entries.push(wgpu::BindGroupEntry { binding: 3, resource: wgpu::BindingResource::TextureView(out1) });
            }
            let bind = d.create_bind_group(&wgpu::BindGroupDescriptor {
                label: None,
                layout: &pipeline.get_bind_group_layout(0),
                entries: &entries,
            });
            steps.push((pipeline.clone(), bind, n));
        }
        if let Some(e) = pollster::block_on(scope.pop()) {
            // An earlier device failure (out of memory) is the cause to report.
            self.failed()?;
            return Err(GpuError::Shader(format!("shadowmap_pyramid.wgsl: {e}")));
        }
        let view = texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        Ok((PyramidTexture { texture, view, res, faces, levels }, PyramidPasses { steps, faces }))
    }

    /// Reads a pyramid back: `[face][level]` row-major `[min, max]` nodes.
    pub fn read_pyramid(&self, p: &PyramidTexture) -> Result<Vec<Vec<Vec<[f32; 2]>>>, GpuError> {
        let mut out = vec![Vec::new(); p.faces as usize];
        for level in 0..p.levels {
            let n = p.res >> level;
            let row = (8 * n).div_ceil(256) * 256;
            let bytes = u64::from(row * n * p.faces);
            let staging = self.device().create_buffer(&wgpu::BufferDescriptor {
                label: Some("pyramid read-back"),
                size: bytes,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let mut enc = self.device().create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
            enc.copy_texture_to_buffer(
                wgpu::TexelCopyTextureInfo {
                    texture: &p.texture,
                    mip_level: level,
                    origin: wgpu::Origin3d::ZERO,
                    aspect: wgpu::TextureAspect::All,
                },
                wgpu::TexelCopyBufferInfo {
                    buffer: &staging,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(row),
                        rows_per_image: Some(n),
                    },
                },
                wgpu::Extent3d { width: n, height: n, depth_or_array_layers: p.faces },
            );
            self.queue().submit([enc.finish()]);
            let raw = self.read_back(&staging)?;
            for (f, face) in out.iter_mut().enumerate() {
                let mut nodes = Vec::with_capacity((n * n) as usize);
                for y in 0..n {
                    let start = (f as u32 * n + y) * row;
                    let texels: &[f32] = bytemuck::cast_slice(&raw[start as usize..(start + 8 * n) as usize]);
                    nodes.extend(texels.chunks_exact(2).map(|c| [c[0], c[1]]));
                }
                face.push(nodes);
            }
        }
        Ok(out)
    }

    /// A kernel's shafts accumulator over its physical entry, fed the lit runs of
    /// the walk through the pyramid, one ray per invocation, ray `i` through the
    /// map `specs[i]` (its layers in `pyramid`).
    pub fn mapped(
        &self,
        k: &KernelSource,
        walk: &WalkSources,
        rays: &[Ray],
        specs: &[MapSpec],
        pyramid: &PyramidTexture,
    ) -> Result<Vec<Mapped<f32>>, GpuError> {
        let source = wrap_mapped(k, walk, Entry::Radiance)?;
        let data = pack_mapped(rays.iter().map(Ray::pack), specs);
        let stride = Entry::Radiance.packed_vec4s() + 4;
        let out = self.dispatch_with(
            k.shader(&source),
            k.prefix,
            &data,
            stride,
            rays.len(),
            2,
            k.table,
            Some(pyramid.view()),
        )?;
        Ok(out.chunks_exact(2).map(|c| Mapped { value: c[0], steps: c[1] }).collect())
    }

    /// [`Gpu::mapped`] over the spot entry: RGB per ray.
    pub fn spot_mapped(
        &self,
        k: &KernelSource,
        walk: &WalkSources,
        rays: &[SpotRay],
        specs: &[MapSpec],
        pyramid: &PyramidTexture,
    ) -> Result<Vec<Mapped<[f32; 3]>>, GpuError> {
        let source = wrap_mapped(k, walk, Entry::Spot)?;
        let data = pack_mapped(rays.iter().map(SpotRay::pack), specs);
        let stride = Entry::Spot.packed_vec4s() + 4;
        let out = self.dispatch_with(
            k.shader(&source),
            k.prefix,
            &data,
            stride,
            rays.len(),
            4,
            k.table,
            Some(pyramid.view()),
        )?;
        Ok(out.chunks_exact(4).map(|c| Mapped { value: [c[0], c[1], c[2]], steps: c[3] }).collect())
    }

    /// Rays per second through [`Gpu::mapped`] (timestamps; `None` without them).
    pub fn mapped_throughput(
        &self,
        k: &KernelSource,
        walk: &WalkSources,
        rays: &[Ray],
        specs: &[MapSpec],
        pyramid: &PyramidTexture,
        repeats: usize,
    ) -> Result<Option<f64>, GpuError> {
        let source = wrap_mapped(k, walk, Entry::Radiance)?;
        let data = pack_mapped(rays.iter().map(Ray::pack), specs);
        self.timed_with(k, &source, 2, &data, rays.len(), repeats, Some(pyramid.view()))
    }
}

/// Packs each item's entry arguments, then its map's rows and `[cube, res, bias, layer]`.
fn pack_mapped<I, A>(items: I, specs: &[MapSpec]) -> Vec<f32>
where
    I: Iterator<Item = A>,
    A: AsRef<[f32]>,
{
    let mut out = Vec::new();
    for (args, spec) in items.zip(specs) {
        out.extend_from_slice(args.as_ref());
        out.extend_from_slice(&spec.pack());
    }
    out
}

/// The compute shader around a kernel's accumulator fed by the walk: per item,
/// its arguments and map, the walk's runs added in order (flushed when the
/// buffer fills, so exact for any number of runs), finished at its surface;
/// the result(s), then the walk's steps (negative: truncated).
fn wrap_mapped(k: &KernelSource, walk: &WalkSources, entry: Entry) -> Result<String, GpuError> {
    shader_only(k)?;
    let glsl = k.language == Target::Glsl;
    let arg = |a: Arg| arg_expr(k, entry, a);
    let pass = k
        .args(entry)
        .iter()
        .filter(|&&a| a != Arg::Surface)
        .map(|&a| arg(a))
        .collect::<Result<Vec<_>, _>>()?
        .join(", ");
    let (origin, dir, end, light) = (arg(Arg::Origin)?, arg(Arg::Dir)?, arg(Arg::Surface)?, arg(Arg::Light)?);
    let args = entry.packed_vec4s();
    let outputs = entry.outputs();
    let total = outputs + 1;
    let (flush, finish) = match entry {
        Entry::Spot => ("shafts_flush_spot", "shafts_finish_spot"),
        _ => ("shafts_flush", "shafts_finish"),
    };
    let p = k.prefix;
    let lanes = ["x", "y", "z"];
    let store = if outputs == 1 {
        format!("airlight_results[i * {total}u] = r;")
    } else {
        (0..outputs)
            .map(|j| format!("airlight_results[i * {total}u + {j}u] = r.{};", lanes[j]))
            .collect::<Vec<_>>()
            .join(" ")
    };
    Ok(if glsl {
        format!(
            "#version 450\n{src}\n{walk}\n\
// ---- airlight harness (shaders/src/shafts/mapped.rs): the accumulator fed by the shadow-map walk ----\n\
layout(local_size_x = {WORKGROUP}) in;\n\
layout(std430, set = 0, binding = 0) readonly buffer AirlightInputs {{ vec4 airlight_inputs[]; }};\n\
layout(std430, set = 0, binding = 1) buffer AirlightResults {{ float airlight_results[]; }};\n\
layout(set = 0, binding = 4) uniform texture2DArray airlight_pyramid;\n\
layout(set = 0, binding = 5) uniform sampler airlight_pyramid_sampler;\n\
vec2 airlight_smap_node(int face, int level, ivec2 p) {{\n\
    return texelFetch(sampler2DArray(airlight_pyramid, airlight_pyramid_sampler), ivec3(p, face), level).rg;\n\
}}\n\
void main() {{\n\
    uint i = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * {WORKGROUP}u;\n\
    if (i >= uint(airlight_results.length()) / {total}u) {{\n\
        return;\n\
    }}\n\
    uint base = i * {stride}u;\n\
    vec4 x[{args}];\n\
    for (uint j = 0u; j < {args}u; j++) {{\n\
        x[j] = airlight_inputs[base + j];\n\
    }}\n\
    vec4 m = airlight_inputs[base + {args}u + 3u];\n\
    mat3 rows = mat3(airlight_inputs[base + {args}u].xyz, airlight_inputs[base + {args}u + 1u].xyz, airlight_inputs[base + {args}u + 2u].xyz);\n\
    AirlightSmapWalk w = airlight_smap_begin({origin}, {dir}, {end}, {light}, rows, m.x > 0.5, int(m.y), m.z, int(m.w));\n\
    {p}Shafts acc = {p}shafts_begin_runs();\n\
    for (;;) {{\n\
        bool more = true;\n\
        for (;;) {{\n\
            vec2 run = airlight_smap_next(w);\n\
            if (run.x < 0.0) {{\n\
                more = false;\n\
                break;\n\
            }}\n\
            {p}shafts_add_run(acc, run.x, run.y);\n\
            if ({p}shafts_full(acc)) {{\n\
                break;\n\
            }}\n\
        }}\n\
        if (!more) {{\n\
            break;\n\
        }}\n\
        {p}{flush}(acc, {pass});\n\
    }}\n\
    {ty} r = {p}{finish}(acc, {end}, {pass});\n\
    {store}\n\
    airlight_results[i * {total}u + {outputs}u] = w.truncated ? -float(w.steps) : float(w.steps);\n\
}}\n",
            src = k.source,
            walk = walk.glsl,
            stride = args + 4,
            ty = if outputs == 1 { "float" } else { "vec3" }
        )
    } else {
        format!(
            "{src}\n{walk}\n\
// ---- airlight harness (shaders/src/shafts/mapped.rs): the accumulator fed by the shadow-map walk ----\n\
@group(0) @binding(0) var<storage, read> airlight_inputs: array<vec4<f32>>;\n\
@group(0) @binding(1) var<storage, read_write> airlight_results: array<f32>;\n\
@group(0) @binding(4) var airlight_pyramid: texture_2d_array<f32>;\n\
\n\
@compute @workgroup_size({WORKGROUP})\n\
fn main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {{\n\
    let i = id.x + id.y * groups.x * {WORKGROUP}u;\n\
    if (i >= arrayLength(&airlight_results) / {total}u) {{\n\
        return;\n\
    }}\n\
    let base = i * {stride}u;\n\
    var x: array<vec4<f32>, {args}>;\n\
    for (var j = 0u; j < {args}u; j++) {{\n\
        x[j] = airlight_inputs[base + j];\n\
    }}\n\
    let m = airlight_inputs[base + {args}u + 3u];\n\
    let rows = mat3x3<f32>(airlight_inputs[base + {args}u].xyz, airlight_inputs[base + {args}u + 1u].xyz, airlight_inputs[base + {args}u + 2u].xyz);\n\
    var w = airlight_smap_begin({origin}, {dir}, {end}, {light}, rows, m.x > 0.5, u32(m.y), m.z, u32(m.w));\n\
    var acc = {p}shafts_begin_runs();\n\
    loop {{\n\
        var more = true;\n\
        loop {{\n\
            let run = airlight_smap_next(&w, airlight_pyramid);\n\
            if run.x < 0.0 {{\n\
                more = false;\n\
                break;\n\
            }}\n\
            {p}shafts_add_run(&acc, run.x, run.y);\n\
            if {p}shafts_full(acc) {{\n\
                break;\n\
            }}\n\
        }}\n\
        if !more {{\n\
            break;\n\
        }}\n\
        {p}{flush}(&acc, {pass});\n\
    }}\n\
    let r = {p}{finish}(acc, {end}, {pass});\n\
    {store}\n\
    airlight_results[i * {total}u + {outputs}u] = select(f32(w.steps), -f32(w.steps), w.truncated);\n\
}}\n",
            src = k.source,
            walk = walk.wgsl,
            stride = args + 4,
        )
    })
}
