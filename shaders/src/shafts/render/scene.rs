//! The shafts scene: the room, its boxes and ball, the spot light and its shadow
//! map's frame, the camera, the medium, and the scene's shader constants (the
//! shader itself is `scene.wgsl`).

use airlight_truth::shafts::Occluder;

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
pub(crate) const NORMAL_OFFSET: f32 = 0.03;

/// Near and far planes of the light's projection.
pub(crate) const LIGHT_NEAR: f32 = 0.3;

pub(crate) const LIGHT_FAR: f32 = 30.0;

/// An axis-aligned box: min, max, albedo.
pub(crate) type Cuboid = ([f32; 3], [f32; 3], [f32; 3]);

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
pub(crate) const ROOM_ALBEDO: [[f32; 3]; 6] = [
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

pub(crate) fn sub(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(crate) fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(crate) fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

pub(crate) fn unit(a: [f32; 3]) -> [f32; 3] {
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
pub(crate) fn light_frame() -> ([[f32; 3]; 3], f32) {
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

pub(crate) fn v3(v: [f32; 3]) -> String {
    format!("vec3<f32>({:?}, {:?}, {:?})", v[0], v[1], v[2])
}

/// The scene's WGSL: constants, the first surface along a ray (distance and
/// object id), normals, albedos, the light's clip position and the shadow
/// look-up. Both passes include it.
pub(crate) fn scene_wgsl(view: &ShaftsView) -> String {
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
        "// ---- the light-shafts scene (shaders/src/shafts/render/scene.rs, scene.wgsl) ----
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
