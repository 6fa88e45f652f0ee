//! The light-shafts render (issue 24; docs/MATH.md §8): a spot light above a
//! pergola shines down through its grid of beams into a smoky courtyard room,
//! past two pillars and a stone ball. As an engine would draw it:
//!
//! 1. a depth pass from the light (a perspective shadow map of the occluders'
//!    triangles, slope-scaled depth bias);
//! 2. a full-screen pass that finds each pixel's first surface (walls, floor,
//!    ceiling, beams, pillars, ball), walks the view ray to it in `N` equal steps,
//!    looks the shadow map up at each step's midpoint (a comparison sampler with
//!    linear filtering: 2×2 PCF, so visibility is fractional at edges) and sums the
//!    fog either with the scene kernel's shafts accumulator (fed the viewer's and
//!    the surface's visibility too) or with `raymarch-64`'s march functions (the
//!    engines' march, any step count); the surface is lit by the spot's direct
//!    light, attenuated by the medium and shadowed by the same map.
//!
//! The reference frame takes each pixel's ray to the same surface (the GPU
//! frame's distance) and sums the reference in-scattering (airlight_truth::reference, per
//! channel) over the ray's exact lit intervals among the analytic occluders
//! (airlight_truth::shafts); its surfaces are lit with exact visibility.

use crate::{Gpu, GpuError};
use airlight_shapes::vocab::{Arg, IndexEntry};
use airlight_truth::geometry::{Cone, PhysicalRay};
use airlight_truth::shafts::{self, Occluder};

/// The room's extent, metres: x, y, z ranges.
pub const ROOM: [[f32; 2]; 3] = [[-5.0, 5.0], [0.0, 8.0], [-2.0, 16.0]];
/// The spot light's position.
pub const LIGHT: [f32; 3] = [4.2, 7.5, 3.5];
/// Where the spot light is aimed.
pub const AIM: [f32; 3] = [-2.0, 0.0, 11.0];
/// The cone's outer and inner half-angles, degrees (a smooth edge between).
pub const CONE_DEG: [f32; 2] = [38.0, 28.0];
/// Radiant intensity, W/sr.
pub const INTENSITY: f32 = 300.0;
/// σt of the most extinguished (red) channel, 1/m; the others by
/// [`crate::render::RGB_EXTINCTION`], albedo [`crate::render::RGB_ALBEDO`].
pub const SIGMA_T: f32 = 0.14;
/// Henyey–Greenstein g (the scene's).
pub const G: f32 = 0.5;
/// The camera and its upward pitch, degrees.
pub const CAMERA: [f32; 3] = [0.0, 1.8, -1.5];
/// Upward pitch of the camera, degrees.
pub const PITCH_DEG: f32 = 12.0;
/// Uniform ambient light on surfaces (radiance per unit albedo), so that what
/// the spot does not reach still reads as a place.
pub const AMBIENT: f32 = 0.003;
/// Texels per side of the shadow map.
pub const SHADOW_MAP: u32 = 2048;
/// Look-ups per ray for the accumulator's frame.
pub const LOOK_UPS: u32 = 128;
/// Bisection steps on the shadow map that place each change the accumulator's
/// look-ups see (each a further look-up).
pub const REFINE_STEPS: u32 = 5;
/// Step counts tried for the march's frame; the one whose GPU time is nearest
/// the accumulator's is shown.
pub const MARCH_STEPS: [u32; 5] = [32, 64, 128, 256, 512];
/// The kernel whose march functions draw the march's frame (its shafts march
/// takes any number of steps): `[shafts] render_march` in `fit/src/roles.toml`.
pub fn march_kernel() -> &'static str {
    &airlight_fit::roles::roles().shafts.render_march
}
/// Timed repeats of each frame's full-screen pass (after a warm-up).
pub const REPEATS: usize = 3;
/// Normal offset of a surface's own shadow look-up, metres.
const NORMAL_OFFSET: f32 = 0.03;
/// Near and far planes of the light's projection.
const LIGHT_NEAR: f32 = 0.3;
const LIGHT_FAR: f32 = 30.0;

/// An axis-aligned box: min, max, albedo.
type Cuboid = ([f32; 3], [f32; 3], [f32; 3]);

/// The boxes: eleven beams across the room and two girders along it (the
/// pergola), and two pillars.
pub fn boxes() -> Vec<Cuboid> {
    let wood = [0.20, 0.14, 0.09];
    let stone = [0.30, 0.29, 0.27];
    let mut out: Vec<Cuboid> = (0..11)
        .map(|i| {
            let z = 2.5 + 1.2 * i as f32;
            ([-5.0, 5.0, z], [5.0, 5.3, z + 0.5], wood)
        })
        .collect();
    for x in [-2.6f32, 2.6] {
        out.push(([x - 0.15, 5.3, 2.0], [x + 0.15, 5.6, 15.5], wood));
    }
    out.push(([-4.6, 0.0, 5.6], [-4.0, 5.0, 6.2], stone));
    out.push(([3.4, 0.0, 11.6], [4.0, 5.0, 12.2], stone));
    out
}

/// The stone ball: centre, radius, albedo.
pub const BALL: ([f32; 3], f32, [f32; 3]) = ([-1.0, 1.1, 9.0], 1.1, [0.38, 0.38, 0.38]);

/// Albedo of the room's six faces: floor, ceiling, the walls at −x, +x, +z, −z.
const ROOM_ALBEDO: [[f32; 3]; 6] = [
    [0.28, 0.25, 0.21],
    [0.15, 0.15, 0.15],
    [0.31, 0.30, 0.29],
    [0.31, 0.30, 0.29],
    [0.31, 0.30, 0.29],
    [0.31, 0.30, 0.29],
];

/// The occluders in f64 for the reference (the room itself shadows nothing: the
/// light is inside it).
pub fn occluders() -> Vec<Occluder> {
    let f = |v: [f32; 3]| v.map(f64::from);
    let mut out: Vec<Occluder> = boxes().iter().map(|b| Occluder::Cuboid { min: f(b.0), max: f(b.1) }).collect();
    out.push(Occluder::Sphere { center: f(BALL.0), radius: f64::from(BALL.1) });
    out
}

/// The medium per channel: (σt, σs).
pub fn medium() -> ([f32; 3], [f32; 3]) {
    let e = crate::render::RGB_EXTINCTION;
    let a = crate::render::RGB_ALBEDO;
    (e.map(|x| x * SIGMA_T), [0, 1, 2].map(|c| a[c] * e[c] * SIGMA_T))
}

fn sub(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}
fn unit(a: [f32; 3]) -> [f32; 3] {
    let n = dot(a, a).sqrt();
    a.map(|x| x / n)
}

/// The spot's unit axis.
pub fn axis() -> [f32; 3] {
    unit(sub(AIM, LIGHT))
}

/// The camera's forward, right and up unit vectors.
pub fn camera_basis() -> [[f32; 3]; 3] {
    let p = PITCH_DEG.to_radians();
    let fwd = [0.0, p.sin(), p.cos()];
    let right = [1.0, 0.0, 0.0];
    [fwd, right, cross(fwd, right)]
}

/// The light's frame: forward (the axis), right, up, and the projection's
/// `1/tan(fov/2)` (the fov a little wider than the cone).
fn light_frame() -> ([[f32; 3]; 3], f32) {
    let f = axis();
    let r = unit(cross(f, [0.0, 0.0, 1.0]));
    let u = cross(r, f);
    let half = (CONE_DEG[0] * 1.15).to_radians();
    ([f, r, u], 1.0 / half.tan())
}

/// The frame drawn: size and look-ups.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShaftsView {
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
}

impl ShaftsView {
    /// The unit view direction through pixel `(x, y)` (pixel centres): the same
    /// f32 arithmetic as the shader's.
    pub fn dir(&self, x: u32, y: u32) -> [f32; 3] {
        let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
        let u = 2.0 * px / self.width as f32 - 1.0;
        let v = 1.0 - 2.0 * py / self.height as f32;
        let t = (0.5 * crate::render::FOV_Y).tan();
        let a = self.width as f32 / self.height as f32;
        let [f, r, up] = camera_basis();
        let d: [f32; 3] = std::array::from_fn(|i| f[i] + (u * t * a) * r[i] + (v * t) * up[i]);
        let n = dot(d, d).sqrt();
        d.map(|x| x / n)
    }
}

fn v3(v: [f32; 3]) -> String {
    format!("vec3<f32>({:?}, {:?}, {:?})", v[0], v[1], v[2])
}

/// The scene's WGSL: constants, the first surface along a ray (distance and
/// object id), normals, albedos, the light's clip position and the shadow
/// look-up. Both passes include it.
fn scene_wgsl(view: &ShaftsView) -> String {
    let b = boxes();
    let mins: Vec<String> = b.iter().map(|x| v3(x.0)).collect();
    let maxs: Vec<String> = b.iter().map(|x| v3(x.1)).collect();
    let mut albedo: Vec<String> = ROOM_ALBEDO.iter().map(|a| v3(*a)).collect();
    albedo.extend(b.iter().map(|x| v3(x.2)));
    albedo.push(v3(BALL.2));
    let ([lf, lr, lu], k) = light_frame();
    let [cf, cr, cu] = camera_basis();
    let (st, ss) = medium();
    let a = LIGHT_FAR / (LIGHT_FAR - LIGHT_NEAR);
    let constants = format!(
        "// ---- the light-shafts scene (shaders/src/shafts/render.rs, scene.wgsl) ----
const SC_ROOM_MIN = {rmin};
const SC_ROOM_MAX = {rmax};
const SC_NB: u32 = {nb}u;
const SC_BOX_MIN = array<vec3<f32>, {nb}>({mins});
const SC_BOX_MAX = array<vec3<f32>, {nb}>({maxs});
const SC_BALL = vec4<f32>({bx:?}, {by:?}, {bz:?}, {br:?});
const SC_ALBEDO = array<vec3<f32>, {na}>({albedo});
const SC_LIGHT = {light};
const SC_AXIS = {axis};
const SC_COS_OUTER: f32 = {co:?};
const SC_COS_INNER: f32 = {ci:?};
const SC_INTENSITY: f32 = {intensity:?};
const SC_SIGMA_T = {st};
const SC_SIGMA_S = {ss};
const SC_CAMERA = {cam};
const SC_CAM_F = {cf};
const SC_CAM_R = {cr};
const SC_CAM_U = {cu};
const SC_L_F = {lf};
const SC_L_R = {lr};
const SC_L_U = {lu};
const SC_L_K: f32 = {k:?};
const SC_L_A: f32 = {a:?};
const SC_L_B: f32 = {b_:?};
const SC_AMBIENT: f32 = {ambient:?};
const SC_WIDTH: f32 = {w:?};
const SC_HEIGHT: f32 = {h:?};
const SC_HALF_FOV: f32 = {half:?};

",
        rmin = v3([ROOM[0][0], ROOM[1][0], ROOM[2][0]]),
        rmax = v3([ROOM[0][1], ROOM[1][1], ROOM[2][1]]),
        nb = b.len(),
        mins = mins.join(", "),
        maxs = maxs.join(", "),
        bx = BALL.0[0],
        by = BALL.0[1],
        bz = BALL.0[2],
        br = BALL.1,
        na = albedo.len(),
        albedo = albedo.join(", "),
        light = v3(LIGHT),
        axis = v3(axis()),
        co = CONE_DEG[0].to_radians().cos(),
        ci = CONE_DEG[1].to_radians().cos(),
        intensity = INTENSITY,
        st = v3(st),
        ss = v3(ss),
        cam = v3(CAMERA),
        cf = v3(cf),
        cr = v3(cr),
        cu = v3(cu),
        lf = v3(lf),
        lr = v3(lr),
        lu = v3(lu),
        b_ = a * LIGHT_NEAR,
        ambient = AMBIENT,
        w = view.width as f32,
        h = view.height as f32,
        half = 0.5 * crate::render::FOV_Y,
    );
    constants + include_str!("scene.wgsl")
}

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
fn push_args(k: &IndexEntry) -> String {
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
fn frame_wgsl(k: &IndexEntry, kernel: &str, view: &ShaftsView, method: Method) -> String {
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
fn depth_wgsl(view: &ShaftsView) -> String {
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

/// The outward normal of object `id` at `p` (f64; the shader's `sc_normal`).
fn normal(id: usize, p: [f64; 3]) -> [f64; 3] {
    match id {
        0 => [0.0, 1.0, 0.0],
        1 => [0.0, -1.0, 0.0],
        2 => [1.0, 0.0, 0.0],
        3 => [-1.0, 0.0, 0.0],
        4 => [0.0, 0.0, -1.0],
        5 => [0.0, 0.0, 1.0],
        _ => {
            let b = boxes();
            if id >= 6 + b.len() {
                let c = BALL.0.map(f64::from);
                let v = [p[0] - c[0], p[1] - c[1], p[2] - c[2]];
                let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                return v.map(|x| x / n);
            }
            let (mn, mx, _) = b[id - 6];
            let mut best = (f64::INFINITY, [0.0; 3]);
            for a in 0..3 {
                for (dist, sign) in [((p[a] - f64::from(mn[a])).abs(), -1.0), ((f64::from(mx[a]) - p[a]).abs(), 1.0)] {
                    if dist < best.0 {
                        let mut n = [0.0; 3];
                        n[a] = sign;
                        best = (dist, n);
                    }
                }
            }
            best.1
        }
    }
}

fn albedo(id: usize) -> [f64; 3] {
    let b = boxes();
    let a = match id {
        0..=5 => ROOM_ALBEDO[id],
        i if i < 6 + b.len() => b[i - 6].2,
        _ => BALL.2,
    };
    a.map(f64::from)
}

/// The distance from the camera along the unit `dir` to the first surface:
/// the room's walls from inside, or an occluder (f64).
pub fn first_surface(dir: [f64; 3]) -> f64 {
    let cam = CAMERA.map(f64::from);
    let exit = (0..3)
        .filter(|&a| dir[a] != 0.0)
        .map(|a| {
            let [lo, hi] = ROOM[a].map(f64::from);
            ((lo - cam[a]) / dir[a]).max((hi - cam[a]) / dir[a])
        })
        .fold(f64::INFINITY, f64::min);
    occluders().iter().filter_map(|o| o.enters(cam, dir)).fold(exit, f64::min)
}

/// The reference fog of each pixel of `view`, its ray ending at `ends[i]`: the
/// reference in-scattering (per channel) over the ray's exact lit intervals
/// among the analytic occluders, for the spot's cone.
pub fn reference_fog(view: &ShaftsView, ends: &[f64]) -> Vec<[f64; 3]> {
    let occ = occluders();
    let (st, ss) = medium();
    let cone = Cone {
        axis: axis().map(f64::from),
        cos_outer: f64::from(CONE_DEG[0].to_radians().cos()),
        cos_inner: f64::from(CONE_DEG[1].to_radians().cos()),
    };
    let (light, cam) = (LIGHT.map(f64::from), CAMERA.map(f64::from));
    let pixels: Vec<u32> = (0..view.width * view.height).collect();
    let a = |q: airlight_truth::reference::Point| airlight_truth::reference::airlight(q).unwrap_or(f64::INFINITY);
    airlight_truth::parallel::map(
        &pixels,
        |&i| {
            let dir = view.dir(i % view.width, i / view.width).map(f64::from);
            let ray = |c: usize| PhysicalRay {
                origin: cam,
                direction: dir,
                surface_distance: Some(ends[i as usize]),
                light,
                intensity: f64::from(INTENSITY),
                sigma_t: f64::from(st[c]),
                sigma_s: f64::from(ss[c]),
            };
            let lit = shafts::lit_intervals(&ray(0), &occ);
            std::array::from_fn(|c| {
                shafts::shadowed_radiance(&ray(c), Some(&cone), f64::from(G), &lit, &a).unwrap_or(f64::NAN)
            })
        },
        &|_, _| {},
    )
}

/// The reference frame for the GPU frame `gpu` (its surface distances and
/// object ids): the fog by the reference over the exact lit intervals, and the
/// composite with surfaces lit under exact visibility. Per pixel RGB (f64).
pub fn reference(view: &ShaftsView, gpu: &Frame) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    let occ = occluders();
    let (st, ss) = medium();
    let cone = Cone {
        axis: axis().map(f64::from),
        cos_outer: f64::from(CONE_DEG[0].to_radians().cos()),
        cos_inner: f64::from(CONE_DEG[1].to_radians().cos()),
    };
    let light = LIGHT.map(f64::from);
    let cam = CAMERA.map(f64::from);
    let pixels: Vec<u32> = (0..view.width * view.height).collect();
    let a = |q: airlight_truth::reference::Point| airlight_truth::reference::airlight(q).unwrap_or(f64::INFINITY);
    let out = airlight_truth::parallel::map(
        &pixels,
        |&i| {
            let dir = view.dir(i % view.width, i / view.width).map(f64::from);
            let end = f64::from(gpu.fog[i as usize][3]);
            let id = gpu.color[i as usize][3] as usize;
            let ray = |c: usize| PhysicalRay {
                origin: cam,
                direction: dir,
                surface_distance: Some(end),
                light,
                intensity: f64::from(INTENSITY),
                sigma_t: f64::from(st[c]),
                sigma_s: f64::from(ss[c]),
            };
            let lit = shafts::lit_intervals(&ray(0), &occ);
            let fog: [f64; 3] = std::array::from_fn(|c| {
                shafts::shadowed_radiance(&ray(c), Some(&cone), f64::from(G), &lit, &a).unwrap_or(f64::NAN)
            });
            let p: [f64; 3] = std::array::from_fn(|q| cam[q] + end * dir[q]);
            let n = normal(id, p);
            let off: [f64; 3] = std::array::from_fn(|q| p[q] + 1e-3 * n[q]);
            let v = if occ.iter().any(|o| o.blocks(off, light)) { 0.0 } else { 1.0 };
            let tl: [f64; 3] = std::array::from_fn(|q| light[q] - p[q]);
            let dl = (tl[0] * tl[0] + tl[1] * tl[1] + tl[2] * tl[2]).sqrt();
            let cos = (n[0] * tl[0] + n[1] * tl[1] + n[2] * tl[2]) / dl;
            let w = cone.weight(tl.map(|x| -x));
            let alb = albedo(id);
            let color: [f64; 3] = std::array::from_fn(|c| {
                let e = f64::from(INTENSITY) * w * cos.max(0.0) / (dl * dl) * (-f64::from(st[c]) * dl).exp() * v;
                let surf =
                    (alb[c] * e / std::f64::consts::PI + f64::from(AMBIENT) * alb[c]) * (-f64::from(st[c]) * end).exp();
                fog[c] + surf
            });
            (fog, color)
        },
        &|_, _| {},
    );
    out.into_iter().unzip()
}

/// Errors of a frame's fog against the reference's, relative per pixel (the
/// largest channel's): max and mean over the lit pixels off the shafts' edges,
/// and over the edge pixels.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FogErrors {
    /// Max relative error, lit pixels off the edges.
    pub lit_max: f64,
    /// Mean relative error, lit pixels off the edges.
    pub lit_mean: f64,
    /// Max relative error, shaft-edge pixels.
    pub edge_max: f64,
    /// Mean relative error, shaft-edge pixels.
    pub edge_mean: f64,
}

/// Which pixels are lit (reference fog luminance at least 1% of its 99th
/// percentile) and which of those lie on a shaft's edge (a neighbour's reference
/// fog differs from the pixel's by more than [`EDGE_STEP`] of the larger).
pub fn classify(view: &ShaftsView, fog: &[[f64; 3]]) -> Vec<Option<bool>> {
    let lum: Vec<f64> = fog.iter().map(|p| (p[0] + p[1] + p[2]) / 3.0).collect();
    let mut sorted: Vec<f64> = lum.iter().copied().filter(|x| x.is_finite()).collect();
    sorted.sort_by(f64::total_cmp);
    let p99 = sorted.get((sorted.len() as f64 * 0.99) as usize).copied().unwrap_or(0.0);
    let (w, h) = (view.width as i64, view.height as i64);
    (0..w * h)
        .map(|i| {
            let l = lum[i as usize];
            if l.is_nan() || l < 0.01 * p99 {
                return None;
            }
            let (x, y) = (i % w, i / w);
            let mut edge = false;
            for (dx, dy) in [(-1, 0), (1, 0), (0, -1), (0, 1)] {
                let (u, v) = (x + dx, y + dy);
                if u >= 0 && u < w && v >= 0 && v < h {
                    let m = lum[(v * w + u) as usize];
                    edge |= (m - l).abs() > EDGE_STEP * m.max(l);
                }
            }
            Some(edge)
        })
        .collect()
}

/// A neighbouring pixel's fog differs by more than this fraction on a shaft's edge.
pub const EDGE_STEP: f64 = 0.1;

/// The fog errors of `frame` against the reference `fog`, by `classes` ([`classify`]).
pub fn fog_errors(frame: &Frame, fog: &[[f64; 3]], classes: &[Option<bool>]) -> FogErrors {
    let (mut lit, mut edge) = (Vec::new(), Vec::new());
    for ((g, r), class) in frame.fog.iter().zip(fog).zip(classes) {
        let Some(on_edge) = class else { continue };
        let e = (0..3)
            .map(|c| if r[c] > 0.0 { (f64::from(g[c]) - r[c]).abs() / r[c] } else { f64::from(g[c]).abs() })
            .fold(0.0, f64::max);
        if *on_edge {
            edge.push(e);
        } else {
            lit.push(e);
        }
    }
    let max = |e: &[f64]| e.iter().copied().fold(0.0, f64::max);
    let mean = |e: &[f64]| e.iter().sum::<f64>() / e.len().max(1) as f64;
    FogErrors { lit_max: max(&lit), lit_mean: mean(&lit), edge_max: max(&edge), edge_mean: mean(&edge) }
}

/// A relative-difference image of a frame's fog: log10 of the largest
/// channel's relative error from 1e-3 (black) through 3e-2 (orange) to 1
/// (white); pixels off the lit set dark blue.
pub fn difference(frame: &Frame, fog: &[[f64; 3]], classes: &[Option<bool>]) -> Vec<[u8; 3]> {
    frame
        .fog
        .iter()
        .zip(fog)
        .zip(classes)
        .map(|((g, r), class)| {
            if class.is_none() {
                return [10, 14, 40];
            }
            let e = (0..3).map(|c| (f64::from(g[c]) - r[c]).abs() / r[c].max(1e-300)).fold(0.0, f64::max);
            let s = ((e.max(1e-3).log10() + 3.0) / 3.0).clamp(0.0, 1.0);
            let c = |a: f64| (255.0 * a.clamp(0.0, 1.0)).round() as u8;
            [c(2.0 * s), c(2.0 * s - 0.6), c(2.0 * s - 1.2)]
        })
        .collect()
}

/// The march frame whose GPU time is nearest the accumulator's (by ratio).
pub fn nearest_in_time<'f>(acc: &Frame, marches: &'f [Frame]) -> Option<&'f Frame> {
    marches.iter().min_by(|a, b| {
        let d = |f: &Frame| (f.gpu_s.max(1e-12) / acc.gpu_s.max(1e-12)).ln().abs();
        d(a).total_cmp(&d(b))
    })
}
