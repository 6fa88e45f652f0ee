//! A frame on the GPU: the light's depth pass into the shadow map, then the
//! full-screen pass that sums the fog by the accumulator or the march ([`Method`]),
//! timed by timestamp queries.

use super::*;
use crate::gpu::Stamps;
use crate::{Gpu, GpuError};

use airlight_shapes::vocab::{Arg, IndexEntry};

/// How a frame sums its fog.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// The exact mode: the shipped shadow-map walk (`generated/wgsl/shadowmap.wgsl`)
    /// over the min-max pyramid the shipped pass builds from the frame's own
    /// shadow map, each lit run handed to the scene kernel's accumulator.
    Exact,
    /// The exact mode's walk alone, for its cost: the same walk, no kernel
    /// evaluated; the fog it writes is not radiance but, per pixel, its lit runs'
    /// total length, their count and the walk's steps ([`WalkCounts`]).
    Walk,
    /// The scene kernel's shafts accumulator at `n` look-ups, fed the viewer's
    /// and the surface's visibility too, each change placed by
    /// [`REFINE_STEPS`] bisection steps on the shadow map.
    Sampled(u32),
    /// The engines' march (`raymarch-64`'s shafts functions) at `n` steps.
    March(u32),
}

impl Method {
    /// Look-ups (or steps) per ray; 0 for the exact walk.
    pub fn steps(self) -> u32 {
        match self {
            Method::Exact | Method::Walk => 0,
            Method::Sampled(n) | Method::March(n) => n,
        }
    }

    /// Its name in the render's record and the report.
    pub fn name(self) -> &'static str {
        match self {
            Method::Exact => "exact",
            Method::Walk => "walk",
            Method::Sampled(_) => "sampled",
            Method::March(_) => "march",
        }
    }
}

/// The arguments of the kernel entry the stage's light calls (a spot's `spot`
/// entry, a point light's `radiance`) after `(acc, s, v)`, without the surface;
/// and the suffix of its shafts functions (`_spot` or none).
pub(crate) fn push_args(stage: &Stage, k: &IndexEntry) -> (String, &'static str) {
    let spot = stage.spot.is_some();
    let params = if spot { &k.spot_params } else { &k.radiance_params };
    let args = params
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
            Arg::SigmaT => "SC_SIGMA_T.x".into(),
            Arg::SigmaS => "SC_SIGMA_S.x".into(),
            Arg::G => format!("{:?}", stage.g),
            other => unreachable!("{other} is not an argument of a light entry"),
        })
        .collect::<Vec<_>>()
        .join(", ");
    (args, if spot { "_spot" } else { "" })
}

/// The full-screen pass: the kernel `kernel` (index entry `k`) included as a
/// renderer would, the fog by `method` (the walk's source `walk` for the exact
/// mode), the surface lit; two targets: the composite (RGB, object id) and the
/// fog alone (RGB, surface distance).
pub(crate) fn frame_wgsl(
    stage: &Stage,
    k: &IndexEntry,
    kernel: &str,
    walk: &str,
    view: &ShaftsView,
    method: Method,
) -> String {
    let p = &k.prefix;
    let (args, sfx) = push_args(stage, k);
    // A point light's entry is one channel of a grey medium: its colour outside.
    let colour = if stage.spot.is_some() { "" } else { "SC_COLOUR * " };
    let refine = REFINE_STEPS;
    let (walk_src, fog_body) = match method {
        Method::Exact | Method::Walk => (
            walk,
            format!(
                "    let cc = sc_cone_clip(SC_CAMERA, dir, fog_end);
    var acc = {p}shafts_begin_runs();
    if cc.x < cc.y {{
        var w = airlight_smap_begin(SC_CAMERA + cc.x * dir, dir, cc.y - cc.x, SC_LIGHT, SC_WALK_ROWS, SC_FACES == 6u, {res}u, {bias:?}, 0u);
        loop {{
            // The walk's loop holds no kernel: a full buffer leaves it, is
            // flushed, and the walk goes on.
            var more = true;
            loop {{
                let r = airlight_smap_next(&w, sc_pyramid);
                if r.x < 0.0 {{
                    more = false;
                    break;
                }}
                let run = vec2<f32>(cc.x + r.x, select(cc.y, cc.x + r.y, r.y >= 0.0));
{each_run}            }}
            if !more {{
                break;
            }}
            {flush}
        }}
{steps}    }}
",
                steps = if method == Method::Walk { "        acc.sum.z = f32(w.steps);\n" } else { "" },
                flush = if method == Method::Walk { String::new() } else { format!("{p}shafts_flush{sfx}(&acc, {args});") },
                res = stage.shadow_map,
                bias = WALK_BIAS,
                each_run = if method == Method::Walk {
                    "                acc.sum.x += run.y - run.x;\n                acc.sum.y += 1.0;\n".to_string()
                } else {
                    format!(
                        "                {p}shafts_add_run(&acc, run.x, run.y);
                if {p}shafts_full(acc) {{
                    break;
                }}
"
                    )
                },
            ),
        ),
        Method::Sampled(n) => (
            "",
            format!(
                "    let cc = sc_cone_clip(SC_CAMERA, dir, fog_end);
    var acc = {p}shafts_begin();
    if cc.x < cc.y {{
        {p}shafts_push{sfx}(&acc, cc.x, sc_shadow(SC_CAMERA + cc.x * dir), {args});
        for (var i = 0u; i < {n}u; i++) {{
            let s = cc.x + (f32(i) + 0.5) * (cc.y - cc.x) / {nf:?};
            {p}shafts_push{sfx}(&acc, s, sc_shadow(SC_CAMERA + s * dir), {args});
            for (var r = 0u; r < {refine}u && {p}shafts_probe(acc) >= 0.0; r++) {{
                {p}shafts_refine(&acc, sc_shadow(SC_CAMERA + {p}shafts_probe(acc) * dir));
            }}
        }}
        {p}shafts_push{sfx}(&acc, cc.y, select(sc_shadow(SC_CAMERA + cc.y * dir), v_surf, cc.y >= fog_end), {args});
    }}
",
                nf = n as f32
            ),
        ),
        Method::March(n) => (
            "",
            format!(
                "    let cc = sc_cone_clip(SC_CAMERA, dir, fog_end);
    var acc = {p}shafts_begin();
    if cc.x < cc.y {{
        // The march's steps start where the cone does.
        acc.end = cc.x;
        for (var i = 0u; i < {n}u; i++) {{
            let s = cc.x + (f32(i) + 0.5) * (cc.y - cc.x) / {nf:?};
            {p}shafts_push{sfx}(&acc, s, sc_shadow(SC_CAMERA + s * dir), {args});
        }}
    }}
",
                nf = n as f32
            ),
        ),
    };
    let pyramid = if matches!(method, Method::Exact | Method::Walk) {
        format!(
            "@group(0) @binding(2) var sc_pyramid: texture_2d_array<f32>;\nconst SC_WALK_ROWS = {};\n",
            super::scene::m3(stage.faces()[0])
        )
    } else {
        String::new()
    };
    format!(
        "{kernel}
{walk_src}
{scene}
// ---- the frame: fog by {what}, surfaces lit by the light ----
{pyramid}
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
    let fog_end = sc_fog_end(end, p, n, dir);
{fog_body}    let fog = {fog};
    let tl = SC_LIGHT - p;
    let dl = length(tl);
    let l = tl / dl;
    let e = SC_INTENSITY * SC_COLOUR * sc_cone(-tl) * max(dot(n, l), 0.0) / (dl * dl) * exp(-SC_SIGMA_T * dl) * v_surf;
    var albedo = SC_ALBEDO;
    let a = albedo[id];
    let surf = (a * (e / {pi:?}) + SC_AMBIENT * a) * exp(-SC_SIGMA_T * end);
    return ScOut(vec4<f32>(fog + surf, hit.y), vec4<f32>(fog, end));
}}
",
        scene = scene_wgsl(stage, view),
        // The walk alone writes its counts: the runs' length, the runs, the steps.
        fog = if method == Method::Walk {
            "acc.sum".to_string()
        } else {
            format!("{colour}{p}shafts_finish{sfx}(acc, fog_end, {args})")
        },
        what = match method {
            Method::Exact => "the exact shadow-map walk",
            Method::Walk => "the exact shadow-map walk alone (its runs' length, no kernel)",
            Method::Sampled(_) => "the sampled shafts accumulator",
            Method::March(_) => "the march",
        },
        offset = NORMAL_OFFSET,
        pi = std::f32::consts::PI,
    )
}

/// The depth pass's shader for face `face`: the occluders' triangles in the
/// face's clip space.
pub(crate) fn depth_wgsl(stage: &Stage, view: &ShaftsView, face: usize) -> String {
    format!(
        "{}
@vertex
fn vs(@location(0) p: vec3<f32>) -> @builtin(position) vec4<f32> {{
    return sc_face_clip(p, {face}u);
}}
",
        scene_wgsl(stage, view)
    )
}

/// The occluders' triangles (boxes: 12 each; the ball: a 48 × 24 UV sphere).
pub fn mesh(stage: &Stage) -> Vec<[f32; 3]> {
    let mut out = Vec::new();
    for (mn, mx, _) in &stage.boxes {
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
    let (cen, r, _) = stage.ball;
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
    /// GPU seconds of building the min-max pyramid (the exact frame's extra
    /// pass, once per shadow map; 0 for the others).
    pub pyramid_s: f64,
}

/// What the view rays' walks took, from a [`Method::Walk`] frame: over the
/// pixels whose ray was walked (it meets the spot's cone, or any ray for a point
/// light), the steps (mean, 90th percentile, max) and the lit runs per ray.
#[derive(Clone, Debug, PartialEq)]
pub struct WalkCounts {
    /// The pixels whose ray was walked.
    pub walked: usize,
    /// Their walks' steps: mean, 90th percentile and max.
    pub steps_mean: f64,
    /// See `steps_mean`.
    pub steps_p90: f64,
    /// See `steps_mean`.
    pub steps_max: f64,
    /// Lit runs per walked ray.
    pub runs_mean: f64,
}

impl WalkCounts {
    /// The counts of a [`Method::Walk`] frame; `None` for another method's.
    pub fn of(frame: &Frame) -> Option<WalkCounts> {
        if frame.method != Method::Walk {
            return None;
        }
        let walked: Vec<[f32; 4]> = frame.fog.iter().copied().filter(|p| p[2] > 0.0).collect();
        let mut steps: Vec<f64> = walked.iter().map(|p| f64::from(p[2])).collect();
        steps.sort_by(f64::total_cmp);
        let n = steps.len();
        let mean = |v: &mut dyn Iterator<Item = f64>| if n == 0 { 0.0 } else { v.sum::<f64>() / n as f64 };
        Some(WalkCounts {
            walked: n,
            steps_mean: mean(&mut steps.iter().copied()),
            steps_p90: steps.get(n * 9 / 10).copied().unwrap_or(0.0),
            steps_max: steps.last().copied().unwrap_or(0.0),
            runs_mean: mean(&mut walked.iter().map(|p| f64::from(p[1]))),
        })
    }
}

/// The walk's sources a frame needs for [`Method::Exact`]: the WGSL walk and
/// the WGSL pyramid pass (`generated/wgsl/shadowmap.wgsl`, `shadowmap_pyramid.wgsl`).
#[derive(Debug, Clone, Copy)]
pub struct WalkWgsl<'a> {
    /// The walk.
    pub walk: &'a str,
    /// The pyramid pass.
    pub pyramid: &'a str,
}

impl Gpu {
    /// The stage's shadow map: a depth pass from the light per face, into the
    /// layers of one `Depth32Float` array.
    fn shadow_map(&self, stage: &Stage, view: &ShaftsView) -> Result<wgpu::Texture, GpuError> {
        use wgpu::util::DeviceExt;
        let d = self.device();
        let faces = stage.faces().len() as u32;
        let format = wgpu::TextureFormat::Depth32Float;
        let res = stage.shadow_map;
        let vertices = mesh(stage);
        let buffer = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("occluders"),
            contents: bytemuck::cast_slice(&vertices),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let texture = d.create_texture(&wgpu::TextureDescriptor {
            label: Some("shadow map"),
            size: wgpu::Extent3d { width: res, height: res, depth_or_array_layers: faces },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let attributes =
            [wgpu::VertexAttribute { format: wgpu::VertexFormat::Float32x3, offset: 0, shader_location: 0 }];
        let mut enc = d.create_command_encoder(&Default::default());
        let mut keep = Vec::new();
        for face in 0..faces {
            let scope = d.push_error_scope(wgpu::ErrorFilter::Validation);
            let module = d.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("shafts depth"),
                source: wgpu::ShaderSource::Wgsl(depth_wgsl(stage, view, face as usize).into()),
            });
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
                    // A constant bias and no slope term: the map stays the one the
                    // reference casts (a slope-scaled bias of 2 put every occluder
                    // texel of window-shafts' map more than 0.2% deeper: the test
                    // `the_depth_passes_draw_the_map_the_reference_casts`); surfaces
                    // look it up at a normal offset instead, the walk adds its bias.
                    bias: wgpu::DepthBiasState { constant: 2, slope_scale: 0.0, clamp: 0.0 },
                }),
                multisample: Default::default(),
                multiview_mask: None,
                cache: None,
            });
            if let Some(e) = pollster::block_on(scope.pop()) {
                return Err(GpuError::Shader(e.to_string()));
            }
            let layer = texture.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2),
                base_array_layer: face,
                array_layer_count: Some(1),
                ..Default::default()
            });
            {
                let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("shafts depth"),
                    color_attachments: &[],
                    depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                        view: &layer,
                        depth_ops: Some(wgpu::Operations {
                            load: wgpu::LoadOp::Clear(1.0),
                            store: wgpu::StoreOp::Store,
                        }),
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
            keep.push(pipeline);
        }
        self.queue().submit([enc.finish()]);
        Ok(texture)
    }

    /// The stage's shadow map as the exact frame walks it: the depth passes, then
    /// the pyramid built by the shipped pass from them, read back
    /// (`[face][level]` row-major `[min, max]` nodes; level 0 the linear depths).
    pub fn stage_pyramid(
        &self,
        stage: &Stage,
        view: &ShaftsView,
        pass: &str,
    ) -> Result<Vec<Vec<Vec<[f32; 2]>>>, GpuError> {
        let shadow = self.shadow_map(stage, view)?;
        let (p, _) =
            self.pyramid_of_depth(pass, &shadow, stage.shadow_map, stage.faces().len() as u32, stage.near_far, 0)?;
        self.read_pyramid(&p)
    }

    /// Draws the stage with `method`'s fog: the kernel `kernel` (WGSL, index
    /// entry `k`); the full-screen pass timed `repeats` times after a warm-up.
    /// The exact mode builds the pyramid of the frame's own shadow map with the
    /// shipped pass (timed like the frame: a warm-up, the median of `REPEATS`)
    /// and walks it.
    #[allow(clippy::too_many_arguments)]
    pub fn shafts_frame(
        &self,
        stage: &Stage,
        k: &IndexEntry,
        kernel: &str,
        walk: WalkWgsl,
        view: &ShaftsView,
        method: Method,
        repeats: usize,
    ) -> Result<Frame, GpuError> {
        let d = self.device();
        let (pipeline, bind, pyramid_s) = self.frame_pipeline(stage, k, kernel, walk, view, method)?;
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
        let gpu_s = Stamps::median(self, repeats, |enc, stamps| {
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
                timestamp_writes: stamps.map(Stamps::render),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind, &[]);
            pass.draw(0..3, 0..1);
        })?;
        Ok(Frame { method, color: self.read_rgba(&color, w, h)?, fog: self.read_rgba(&fog, w, h)?, gpu_s, pyramid_s })
    }

    /// The frame's render pipeline (its shader: the scene, the kernel and the
    /// method's walk) and its bind group (the light's shadow map, drawn first,
    /// its comparison sampler and, for the exact mode, the map's pyramid), and
    /// the pyramid's GPU seconds.
    fn frame_pipeline(
        &self,
        stage: &Stage,
        k: &IndexEntry,
        kernel: &str,
        walk: WalkWgsl,
        view: &ShaftsView,
        method: Method,
    ) -> Result<(wgpu::RenderPipeline, wgpu::BindGroup, f64), GpuError> {
        let d = self.device();
        let shadow = self.shadow_map(stage, view)?;
        let pyramid = match method {
            Method::Exact | Method::Walk => Some(self.pyramid_of_depth(
                walk.pyramid,
                &shadow,
                stage.shadow_map,
                stage.faces().len() as u32,
                stage.near_far,
                REPEATS,
            )?),
            _ => None,
        };
        let shadow_view = shadow.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        let scope = d.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = d.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("shafts frame"),
            source: wgpu::ShaderSource::Wgsl(frame_wgsl(stage, k, kernel, walk.walk, view, method).into()),
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
        let mut entries = vec![
            wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&shadow_view) },
            wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::Sampler(&sampler) },
        ];
        if let Some((p, _)) = &pyramid {
            entries.push(wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::TextureView(p.view()) });
        }
        let bind = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("shadow map"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(GpuError::Shader(e.to_string()));
        }
        Ok((pipeline, bind, pyramid.map_or(0.0, |p| p.1)))
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
