//! A frame on the GPU: the light's depth pass into the shadow map, then the
//! full-screen pass that sums the fog by the accumulator or the march ([`Method`]),
//! timed by timestamp queries.

use super::*;
use crate::{Gpu, GpuError};
use airlight_shapes::vocab::{Arg, IndexEntry};

/// How a frame sums its fog.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// The scene kernel's shafts accumulator at `n` look-ups, fed the viewer's
    /// and the surface's visibility too, each change placed by
    /// [`REFINE_STEPS`] bisection steps on the shadow map.
    Accumulator(u32),
    /// The engines' march (`raymarch-64`'s shafts functions) at `n` steps.
    March(u32),
}

impl Method {
    /// Look-ups (or steps) per ray.
    pub fn steps(self) -> u32 {
        match self {
            Method::Accumulator(n) | Method::March(n) => n,
        }
    }
}

/// The arguments of a kernel's `shafts_push_spot` after `(acc, s, v)` (its spot
/// entry's, without the surface).
pub(crate) fn push_args(k: &IndexEntry) -> String {
    k.spot_params
        .iter()
        .filter(|p| **p != Arg::Surface)
        .map(|p| match p {
            Arg::Origin => "SC_CAMERA".to_string(),
            Arg::Dir => "dir".into(),
            Arg::Light => "SC_LIGHT".into(),
            Arg::Axis => "SC_AXIS".into(),
            Arg::CosOuter => "SC_COS_OUTER".into(),
            Arg::CosInner => "SC_COS_INNER".into(),
            Arg::Intensity => "SC_INTENSITY".into(),
            Arg::SigmaTRgb => "SC_SIGMA_T".into(),
            Arg::SigmaSRgb => "SC_SIGMA_S".into(),
            Arg::G => format!("{G:?}"),
            other => unreachable!("{other} is not an argument of spot"),
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// The full-screen pass: the kernel `kernel` (index entry `k`) included as a
/// renderer would, the fog by `method`, the surface lit; two targets: the
/// composite (RGB, object id) and the fog alone (RGB, surface distance).
pub(crate) fn frame_wgsl(k: &IndexEntry, kernel: &str, view: &ShaftsView, method: Method) -> String {
    let p = &k.prefix;
    let args = push_args(k);
    let n = method.steps();
    let ends = matches!(method, Method::Accumulator(_));
    let (first, last) = if ends {
        (
            format!("    {p}shafts_push_spot(&acc, 0.0, sc_shadow(SC_CAMERA), {args});\n"),
            format!("    {p}shafts_push_spot(&acc, end, v_surf, {args});\n"),
        )
    } else {
        (String::new(), String::new())
    };
    let refine = REFINE_STEPS;
    let body = if ends {
        format!("{p}shafts_push_spot(&acc, s, sc_shadow(SC_CAMERA + s * dir), {args});\n        for (var r = 0u; r < {refine}u && {p}shafts_probe(acc) >= 0.0; r++) {{\n            {p}shafts_refine(&acc, sc_shadow(SC_CAMERA + {p}shafts_probe(acc) * dir));\n        }}")
    } else {
        format!("{p}shafts_push_spot(&acc, s, sc_shadow(SC_CAMERA + s * dir), {args});")
    };
    let fin = format!("{p}shafts_finish_spot(acc, end, {args})");
    format!(
        "{kernel}
{scene}
// ---- the frame: fog by {what}, surfaces lit by the spot ----
struct ScOut {{
    @location(0) color: vec4<f32>,
    @location(1) fog: vec4<f32>,
}}

@vertex
fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {{
    let xy = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(xy * 2.0 - 1.0, 0.0, 1.0);
}}

@fragment
fn fs(@builtin(position) pos: vec4<f32>) -> ScOut {{
    let dir = sc_dir(pos.xy);
    let hit = sc_hit(SC_CAMERA, dir);
    let end = hit.x;
    let id = u32(hit.y);
    let p = SC_CAMERA + end * dir;
    let n = sc_normal(id, p);
    let v_surf = sc_shadow(p + {offset:?} * n);
    var acc = {p}shafts_begin();
{first}    for (var i = 0u; i < {n}u; i++) {{
        let s = (f32(i) + 0.5) * end / {nf:?};
        {body}
    }}
{last}    let fog = {fin};
    let tl = SC_LIGHT - p;
    let dl = length(tl);
    let l = tl / dl;
    let e = SC_INTENSITY * sc_cone(-tl) * max(dot(n, l), 0.0) / (dl * dl) * exp(-SC_SIGMA_T * dl) * v_surf;
    var albedo = SC_ALBEDO;
    let a = albedo[id];
    let surf = (a * (e / {pi:?}) + SC_AMBIENT * a) * exp(-SC_SIGMA_T * end);
    return ScOut(vec4<f32>(fog + surf, hit.y), vec4<f32>(fog, end));
}}
",
        scene = scene_wgsl(view),
        what = if ends { "the shafts accumulator" } else { "the march" },
        offset = NORMAL_OFFSET,
        nf = n as f32,
        pi = std::f32::consts::PI,
    )
}

/// The depth pass's shader: the occluders' triangles in the light's clip space.
pub(crate) fn depth_wgsl(view: &ShaftsView) -> String {
    format!(
        "{}
@vertex
fn vs(@location(0) p: vec3<f32>) -> @builtin(position) vec4<f32> {{
    return sc_light_clip(p);
}}
",
        scene_wgsl(view)
    )
}

/// The occluders' triangles (boxes: 12 each; the ball: a 48 × 24 UV sphere).
pub fn mesh() -> Vec<[f32; 3]> {
    let mut out = Vec::new();
    for (mn, mx, _) in boxes() {
        let c = |i: usize| {
            [
                if i & 1 == 0 { mn[0] } else { mx[0] },
                if i & 2 == 0 { mn[1] } else { mx[1] },
                if i & 4 == 0 { mn[2] } else { mx[2] },
            ]
        };
        for q in [[0, 1, 3, 2], [4, 5, 7, 6], [0, 1, 5, 4], [2, 3, 7, 6], [0, 2, 6, 4], [1, 3, 7, 5]] {
            out.extend([c(q[0]), c(q[1]), c(q[2]), c(q[0]), c(q[2]), c(q[3])]);
        }
    }
    let (cen, r, _) = BALL;
    let (nu, nv) = (48, 24);
    let at = |i: usize, j: usize| {
        let (th, ph) = (std::f32::consts::TAU * i as f32 / nu as f32, std::f32::consts::PI * j as f32 / nv as f32);
        [cen[0] + r * ph.sin() * th.cos(), cen[1] + r * ph.cos(), cen[2] + r * ph.sin() * th.sin()]
    };
    for i in 0..nu {
        for j in 0..nv {
            out.extend([at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    out
}

/// One GPU frame: the composite (RGB, object id) and the fog alone (RGB,
/// surface distance), row by row, and the full-screen pass's GPU time (median
/// of the timed repeats, seconds; 0 without timestamps).
#[derive(Debug, Clone)]
pub struct Frame {
    /// How its fog was summed.
    pub method: Method,
    /// Composite radiance and the object id per pixel.
    pub color: Vec<[f32; 4]>,
    /// Fog radiance and the surface distance per pixel.
    pub fog: Vec<[f32; 4]>,
    /// GPU seconds of the full-screen pass.
    pub gpu_s: f64,
}

impl Gpu {
    /// The shadow map of the scene: a depth pass from the light.
    fn shadow_map(&self, view: &ShaftsView) -> Result<wgpu::TextureView, GpuError> {
        use wgpu::util::DeviceExt;
        let d = self.device();
        let scope = d.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = d.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("shafts depth"),
            source: wgpu::ShaderSource::Wgsl(depth_wgsl(view).into()),
        });
        let format = wgpu::TextureFormat::Depth32Float;
        let attributes =
            [wgpu::VertexAttribute { format: wgpu::VertexFormat::Float32x3, offset: 0, shader_location: 0 }];
        let pipeline = d.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("shafts depth"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: 12,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &attributes,
                })],
            },
            fragment: None,
            primitive: Default::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: wgpu::DepthBiasState { constant: 2, slope_scale: 2.0, clamp: 0.0 },
            }),
            multisample: Default::default(),
            multiview_mask: None,
            cache: None,
        });
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(GpuError::Shader(e.to_string()));
        }
        let vertices = mesh();
        let buffer = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("occluders"),
            contents: bytemuck::cast_slice(&vertices),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let texture = d.create_texture(&wgpu::TextureDescriptor {
            label: Some("shadow map"),
            size: wgpu::Extent3d { width: SHADOW_MAP, height: SHADOW_MAP, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let tview = texture.create_view(&Default::default());
        let mut enc = d.create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("shafts depth"),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &tview,
                    depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&pipeline);
            pass.set_vertex_buffer(0, buffer.slice(..));
            pass.draw(0..vertices.len() as u32, 0..1);
        }
        self.queue().submit([enc.finish()]);
        Ok(tview)
    }

    /// Draws the scene with `method`'s fog: the kernel `kernel` (WGSL, index
    /// entry `k`); the full-screen pass timed `repeats` times after a warm-up.
    pub fn shafts_frame(
        &self,
        k: &IndexEntry,
        kernel: &str,
        view: &ShaftsView,
        method: Method,
        repeats: usize,
    ) -> Result<Frame, GpuError> {
        let d = self.device();
        let (pipeline, bind) = self.frame_pipeline(k, kernel, view, method)?;
        let format = wgpu::TextureFormat::Rgba32Float;
        let (w, h) = (view.width, view.height);
        let make = |label| {
            d.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            })
        };
        let (color, fog) = (make("color"), make("fog"));
        let (cv, fv) = (color.create_view(&Default::default()), fog.create_view(&Default::default()));
        let timed = d.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        let queries = timed.then(|| {
            d.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("frame"),
                ty: wgpu::QueryType::Timestamp,
                count: 2,
            })
        });
        let resolve = d.create_buffer(&wgpu::BufferDescriptor {
            label: Some("timestamps"),
            size: 16,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let stamps = d.create_buffer(&wgpu::BufferDescriptor {
            label: Some("timestamps staging"),
            size: 16,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let period = f64::from(self.queue().get_timestamp_period());
        let mut times = Vec::new();
        for _ in 0..=repeats.max(1) {
            let mut enc = d.create_command_encoder(&Default::default());
            {
                let attach = |v| {
                    Some(wgpu::RenderPassColorAttachment {
                        view: v,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                            store: wgpu::StoreOp::Store,
                        },
                    })
                };
                let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("shafts frame"),
                    color_attachments: &[attach(&cv), attach(&fv)],
                    depth_stencil_attachment: None,
                    timestamp_writes: queries.as_ref().map(|q| wgpu::RenderPassTimestampWrites {
                        query_set: q,
                        beginning_of_pass_write_index: Some(0),
                        end_of_pass_write_index: Some(1),
                    }),
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
                pass.set_pipeline(&pipeline);
                pass.set_bind_group(0, &bind, &[]);
                pass.draw(0..3, 0..1);
            }
            if let Some(q) = &queries {
                enc.resolve_query_set(q, 0..2, &resolve, 0);
                enc.copy_buffer_to_buffer(&resolve, 0, &stamps, 0, 16);
            }
            self.queue().submit([enc.finish()]);
            if timed {
                let t: Vec<u64> = bytemuck::cast_slice(&self.read_back(&stamps)?).to_vec();
                times.push(t[1].saturating_sub(t[0]) as f64 * period * 1e-9);
            }
        }
        let gpu_s = if times.len() > 1 {
            let mut t = times.split_off(1);
            t.sort_by(f64::total_cmp);
            t[t.len() / 2]
        } else {
            0.0
        };
        Ok(Frame { method, color: self.read_rgba(&color, w, h)?, fog: self.read_rgba(&fog, w, h)?, gpu_s })
    }

    /// The frame's render pipeline (its shader: the scene, the kernel and the
    /// method's walk) and its bind group (the light's shadow map, drawn first, and
    /// its comparison sampler).
    fn frame_pipeline(
        &self,
        k: &IndexEntry,
        kernel: &str,
        view: &ShaftsView,
        method: Method,
    ) -> Result<(wgpu::RenderPipeline, wgpu::BindGroup), GpuError> {
        let d = self.device();
        let shadow = self.shadow_map(view)?;
        let scope = d.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = d.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("shafts frame"),
            source: wgpu::ShaderSource::Wgsl(frame_wgsl(k, kernel, view, method).into()),
        });
        let format = wgpu::TextureFormat::Rgba32Float;
        let target = Some(wgpu::ColorTargetState { format, blend: None, write_mask: wgpu::ColorWrites::ALL });
        let pipeline = d.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("shafts frame"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs"),
                compilation_options: Default::default(),
                targets: &[target.clone(), target],
            }),
            primitive: Default::default(),
            depth_stencil: None,
            multisample: Default::default(),
            multiview_mask: None,
            cache: None,
        });
        let sampler = d.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("shadow compare"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            compare: Some(wgpu::CompareFunction::LessEqual),
            ..Default::default()
        });
        let bind = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("shadow map"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&shadow) },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::Sampler(&sampler) },
            ],
        });
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(GpuError::Shader(e.to_string()));
        }
        Ok((pipeline, bind))
    }

    /// An Rgba32Float texture's texels, row by row.
    fn read_rgba(&self, texture: &wgpu::Texture, w: u32, h: u32) -> Result<Vec<[f32; 4]>, GpuError> {
        let d = self.device();
        let row = (w * 16).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let staging = d.create_buffer(&wgpu::BufferDescriptor {
            label: Some("frame staging"),
            size: u64::from(row * h),
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut enc = d.create_command_encoder(&Default::default());
        enc.copy_texture_to_buffer(
            texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &staging,
                layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(row), rows_per_image: Some(h) },
            },
            wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
        );
        self.queue().submit([enc.finish()]);
        let bytes = self.read_back(&staging)?;
        let mut out = Vec::with_capacity((w * h) as usize);
        for y in 0..h {
            let start = (y * row) as usize;
            let texels: &[[f32; 4]] = bytemuck::cast_slice(&bytes[start..start + (w * 16) as usize]);
            out.extend_from_slice(texels);
        }
        Ok(out)
    }
}
