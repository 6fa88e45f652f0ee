//! The shafts scenes ([`Stage`]): a room, its boxes and ball, a light (a spot
//! with one perspective shadow map, or a point light with a cube map), the
//! camera, the medium, and the scene's shader constants (the shader itself is
//! `scene.wgsl`, with the light's look-ups written here). Two stages:
//! `window-shafts` (the constants below: a spot above a pergola) and
//! `street-lamp` ([`Stage::street_lamp`]: a point light behind an iron railing).

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

/// Texels per side of the spot's shadow map.
pub const SHADOW_MAP: u32 = 2048;

/// Look-ups per ray of the sampled accumulator (the three.js page's frame).
pub const LOOK_UPS: u32 = 128;

/// Look-ups per ray of the render's sampled accumulator frames.
pub const SAMPLED: [u32; 2] = [32, 128];

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
pub const REPEATS: usize = 5;

/// Normal offset of a surface's own shadow look-up, metres.
pub(crate) const NORMAL_OFFSET: f32 = 0.03;

/// Near and far planes of the spot's projection.
pub(crate) const LIGHT_NEAR: f32 = 0.3;

pub(crate) const LIGHT_FAR: f32 = 30.0;

/// The exact frame's depth-test bias, metres of the light's face Z (the map's
/// constant raster bias comes on top): thinner than any occluder, so no ray
/// behind an occluder counts as lit. It does light the first `bias` of Z inside
/// an occluder, and a view ray that ends on a shadowed side face near the lit
/// top crosses that band: at 1 cm, 3 of window-shafts' 640×360 pixels leaked
/// so; at 3 mm none of them (measured at 5, 3, 2 and 1 mm: the errors elsewhere
/// move by under 1%).
pub const WALK_BIAS: f32 = 0.003;

/// A view ray that ends on a surface facing away from the light is in that
/// surface's own shadow just before it, which the map cannot resolve within a
/// texel or so of the surface's outline as the light sees it (the texel whose
/// centre ray passes the outline lights the last centimetre of such a ray):
/// every frame's fog ends this many of the map's texels short of such a surface
/// (the texel's width at the surface's distance from the light, over the sine
/// between the view ray and the light's ray there). Measured on window-shafts at
/// 640×360: at 1 texel 1 leak pixel remains (fog 5.9e-4 where the reference is
/// 0, the leak threshold 4.4e-4), at 2 none; the exact frame's lit max and mean
/// unchanged (3.70e-2, 1.89e-3).
pub const END_TEXELS: f32 = 2.0;

/// How far past the spot's outer cone the exact frame still walks its map,
/// degrees: the cone's weight is 0 outside the cone, so the walk starts and ends
/// where the view ray crosses this wider cone (scene.wgsl, `sc_cone_clip`); the
/// margin keeps f32 rounding of that crossing off the lit cone.
pub const CLIP_MARGIN_DEG: f32 = 0.5;

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

/// The cross product `a × b`.
pub fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

/// `a` scaled to unit length.
pub fn unit(a: [f32; 3]) -> [f32; 3] {
    let n = dot(a, a).sqrt();
    a.map(|x| x / n)
}

/// The spot's unit axis.
pub fn axis() -> [f32; 3] {
    unit(sub(AIM, LIGHT))
}

/// `window-shafts`' camera: forward, right and up unit vectors.
pub fn camera_basis() -> [[f32; 3]; 3] {
    pitched_basis(PITCH_DEG)
}

/// A camera looking along +z, pitched up by `pitch_deg`: forward, right, up.
fn pitched_basis(pitch_deg: f32) -> [[f32; 3]; 3] {
    let p = pitch_deg.to_radians();
    let fwd = [0.0, p.sin(), p.cos()];
    let right = [1.0, 0.0, 0.0];
    [fwd, right, cross(fwd, right)]
}

/// A spot light: where it is aimed and its outer and inner half-angles, degrees.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spot {
    /// The point the axis passes through.
    pub aim: [f32; 3],
    /// Outer and inner half-angles, degrees (a smooth edge between).
    pub cone_deg: [f32; 2],
}

/// A shafts scene: everything the frames, the shadow maps and the reference need.
#[derive(Debug, Clone, PartialEq)]
pub struct Stage {
    /// The scene's name (its file `codegen/scenes/<name>.toml`).
    pub name: &'static str,
    /// One line for the report: what is drawn.
    pub description: &'static str,
    /// The room's extent (its walls, floor and ceiling end every view ray).
    pub room: [[f32; 3]; 2],
    /// Albedo of the room's six faces: floor, ceiling, the walls at −x, +x, +z, −z.
    pub room_albedo: [[f32; 3]; 6],
    /// The light's position.
    pub light: [f32; 3],
    /// The spot's aim and cone; `None`: a point light (a cube shadow map).
    pub spot: Option<Spot>,
    /// Radiant intensity, W/sr, and the light's colour (per channel factor).
    pub intensity: f32,
    /// Per-channel factor of the light (a point light's medium is grey, its fog
    /// one channel times this colour).
    pub colour: [f32; 3],
    /// σt per channel, 1/m.
    pub sigma_t: [f32; 3],
    /// σs per channel, 1/m.
    pub sigma_s: [f32; 3],
    /// Henyey–Greenstein g.
    pub g: f32,
    /// The camera's position.
    pub camera: [f32; 3],
    /// Upward pitch of the camera, degrees (it looks along +z).
    pub pitch_deg: f32,
    /// Uniform ambient light on surfaces.
    pub ambient: f32,
    /// Texels per side of the shadow map (of each cube face).
    pub shadow_map: u32,
    /// Near and far planes of the light's projection(s).
    pub near_far: [f32; 2],
    /// The boxes.
    pub boxes: Vec<Cuboid>,
    /// The ball: centre, radius, albedo.
    pub ball: ([f32; 3], f32, [f32; 3]),
}

impl Stage {
    /// The stage drawn for a scene file's name, if there is one.
    pub fn named(name: &str) -> Option<Stage> {
        [Stage::window_shafts(), Stage::street_lamp()].into_iter().find(|s| s.name == name)
    }

    /// `window-shafts`: the spot above a pergola (the constants of this module).
    pub fn window_shafts() -> Stage {
        let (sigma_t, sigma_s) = medium();
        Stage {
            name: "window-shafts",
            description: "a 38°/28° spot light above a pergola shines down through its grid of beams into a smoky room (HG g = 0.5, σt = 0.14/m in red, less in green and blue), past two pillars and a stone ball; one 2048² perspective shadow map",
            room: [[ROOM[0][0], ROOM[1][0], ROOM[2][0]], [ROOM[0][1], ROOM[1][1], ROOM[2][1]]],
            room_albedo: ROOM_ALBEDO,
            light: LIGHT,
            spot: Some(Spot { aim: AIM, cone_deg: CONE_DEG }),
            intensity: INTENSITY,
            colour: [1.0; 3],
            sigma_t,
            sigma_s,
            g: G,
            camera: CAMERA,
            pitch_deg: PITCH_DEG,
            ambient: AMBIENT,
            shadow_map: SHADOW_MAP,
            near_far: [LIGHT_NEAR, LIGHT_FAR],
            boxes: boxes(),
            ball: BALL,
        }
    }

    /// `street-lamp`: a warm point light on a post behind an iron railing of
    /// 3 cm bars (two rails), a bench and a stone ball in front of it, a walled
    /// yard in fog (HG g = 0.6, grey), a 2048² cube shadow map.
    pub fn street_lamp() -> Stage {
        let iron = [0.05, 0.05, 0.055];
        let wood = [0.22, 0.15, 0.09];
        let mut boxes: Vec<Cuboid> = (0..41)
            .map(|i| {
                let x = -5.0 + 0.25 * i as f32;
                ([x - 0.015, 0.0, 6.985], [x + 0.015, 2.1, 7.015], iron)
            })
            .collect();
        boxes.push(([-5.5, 2.1, 6.97], [5.5, 2.16, 7.03], iron));
        boxes.push(([-5.5, 0.12, 6.98], [5.5, 0.16, 7.02], iron));
        // The lamp's post, 0.6 m behind the lamp head, and the arm over it.
        boxes.push(([0.95, 0.0, 9.05], [1.05, 3.45, 9.15], iron));
        boxes.push(([0.97, 3.38, 8.45], [1.03, 3.43, 9.05], iron));
        // The bench: seat, back, two legs at each end.
        boxes.push(([-3.2, 0.42, 4.3], [-1.2, 0.47, 4.75], wood));
        boxes.push(([-3.2, 0.6, 4.75], [-1.2, 0.95, 4.8], wood));
        for x in [-3.1f32, -1.35] {
            boxes.push(([x, 0.0, 4.35], [x + 0.05, 0.42, 4.4], iron));
            boxes.push(([x, 0.0, 4.65], [x + 0.05, 0.95, 4.7], iron));
        }
        let sigma = 0.09;
        let albedo = 0.85;
        Stage {
            name: "street-lamp",
            description: "a warm street lamp (a point light hung from a post's arm, 1.5 m behind an iron railing of 3 cm bars and two rails) shines through the railing into a foggy walled yard (HG g = 0.6, σt = 0.09/m, grey), past a bench and a stone ball; a 2048² cube shadow map (six 90° faces)",
            room: [[-6.0, 0.0, -2.0], [6.0, 9.0, 16.0]],
            room_albedo: [
                [0.20, 0.19, 0.18],
                [0.02, 0.02, 0.03],
                [0.30, 0.26, 0.22],
                [0.30, 0.26, 0.22],
                [0.28, 0.27, 0.26],
                [0.28, 0.27, 0.26],
            ],
            light: [1.0, 3.2, 8.5],
            spot: None,
            intensity: 60.0,
            colour: [1.0, 0.78, 0.5],
            sigma_t: [sigma; 3],
            sigma_s: [albedo * sigma; 3],
            g: 0.6,
            camera: [-0.6, 1.6, -1.2],
            pitch_deg: 6.0,
            ambient: 0.002,
            shadow_map: 2048,
            near_far: [0.05, 30.0],
            boxes,
            ball: ([2.2, 0.55, 4.2], 0.55, [0.38, 0.38, 0.38]),
        }
    }

    /// The occluders in f64 for the reference (the room shadows nothing: the
    /// light is inside it).
    pub fn occluders(&self) -> Vec<Occluder> {
        let f = |v: [f32; 3]| v.map(f64::from);
        let mut out: Vec<Occluder> = self.boxes.iter().map(|b| Occluder::Cuboid { min: f(b.0), max: f(b.1) }).collect();
        out.push(Occluder::Sphere { center: f(self.ball.0), radius: f64::from(self.ball.1) });
        out
    }

    /// The spot's unit axis (`None` for a point light).
    pub fn axis(&self) -> Option<[f32; 3]> {
        self.spot.map(|s| unit(sub(s.aim, self.light)))
    }

    /// The spot's cone for the reference.
    pub fn cone(&self) -> Option<airlight_truth::geometry::Cone> {
        let s = self.spot?;
        Some(airlight_truth::geometry::Cone {
            axis: self.axis()?.map(f64::from),
            cos_outer: f64::from(s.cone_deg[0].to_radians().cos()),
            cos_inner: f64::from(s.cone_deg[1].to_radians().cos()),
        })
    }

    /// The camera's forward, right and up unit vectors.
    pub fn camera_basis(&self) -> [[f32; 3]; 3] {
        pitched_basis(self.pitch_deg)
    }

    /// The faces of the light's map: each face's rows (right, up, forward
    /// scaled so that the face is `[-1, 1]²` in `(X/Z, Y/Z)`, texel row 0 at
    /// `Y/Z = -1`), as the walk reads them. A spot: one face, a little wider
    /// than its cone; a point light: the cube's six, in OpenGL's order.
    pub fn faces(&self) -> Vec<[[f32; 3]; 3]> {
        match self.axis() {
            Some(f) => {
                let r = unit(cross(f, [0.0, 0.0, 1.0]));
                let u = cross(r, f);
                let k = 1.0 / (self.spot.map_or(45.0, |s| s.cone_deg[0]) * 1.15).to_radians().tan();
                // The raster's row 0 is the top (up); the walk's is Y/Z = -1: up flipped.
                vec![[r.map(|x| k * x), u.map(|x| -k * x), f]]
            }
            None => {
                airlight_truth::shafts::CUBE_FACES.iter().map(|face| face.map(|row| row.map(|x| x as f32))).collect()
            }
        }
    }
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
    /// The unit view direction through pixel `(x, y)` (pixel centres) from the
    /// camera whose basis is `basis`: the same f32 arithmetic as the shader's.
    pub fn dir_from(&self, basis: [[f32; 3]; 3], x: u32, y: u32) -> [f32; 3] {
        let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
        let u = 2.0 * px / self.width as f32 - 1.0;
        let v = 1.0 - 2.0 * py / self.height as f32;
        let t = (0.5 * crate::render::FOV_Y).tan();
        let a = self.width as f32 / self.height as f32;
        let [f, r, up] = basis;
        let d: [f32; 3] = std::array::from_fn(|i| f[i] + (u * t * a) * r[i] + (v * t) * up[i]);
        let n = dot(d, d).sqrt();
        d.map(|x| x / n)
    }

    /// [`ShaftsView::dir_from`] for `window-shafts`' camera.
    pub fn dir(&self, x: u32, y: u32) -> [f32; 3] {
        self.dir_from(camera_basis(), x, y)
    }
}

pub(crate) fn v3(v: [f32; 3]) -> String {
    format!("vec3<f32>({:?}, {:?}, {:?})", v[0], v[1], v[2])
}

pub(crate) fn m3(rows: [[f32; 3]; 3]) -> String {
    format!("mat3x3<f32>({}, {}, {})", v3(rows[0]), v3(rows[1]), v3(rows[2]))
}

/// The scene's WGSL: constants, the first surface along a ray (distance and
/// object id), normals, albedos, the light's clip position per face and the
/// shadow look-up. Every pass includes it.
pub(crate) fn scene_wgsl(stage: &Stage, view: &ShaftsView) -> String {
    let b = &stage.boxes;
    let mins: Vec<String> = b.iter().map(|x| v3(x.0)).collect();
    let maxs: Vec<String> = b.iter().map(|x| v3(x.1)).collect();
    let mut albedo: Vec<String> = stage.room_albedo.iter().map(|a| v3(*a)).collect();
    albedo.extend(b.iter().map(|x| v3(x.2)));
    albedo.push(v3(stage.ball.2));
    let [cf, cr, cu] = stage.camera_basis();
    let faces = stage.faces();
    let [near, far] = stage.near_far;
    let a = far / (far - near);
    let (axis, co, ci) = match (stage.axis(), stage.spot) {
        (Some(axis), Some(s)) => (axis, s.cone_deg[0].to_radians().cos(), s.cone_deg[1].to_radians().cos()),
        _ => ([0.0, 0.0, 1.0], -2.0, -1.0),
    };
    let cclip = stage.spot.map_or(-1.0, |s| (s.cone_deg[0] + CLIP_MARGIN_DEG).to_radians().cos());
    let (ball_c, ball_r, _) = stage.ball;
    let constants = format!(
        "// ---- the light-shafts scene `{name}` (shaders/src/shafts/render/scene.rs, scene.wgsl) ----
const SC_ROOM_MIN = {rmin};
const SC_ROOM_MAX = {rmax};
const SC_NB: u32 = {nb}u;
const SC_BOX_MIN = array<vec3<f32>, {nb}>({mins});
const SC_BOX_MAX = array<vec3<f32>, {nb}>({maxs});
const SC_BALL = vec4<f32>({bx:?}, {by:?}, {bz:?}, {br:?});
const SC_ALBEDO = array<vec3<f32>, {na}>({albedo});
const SC_LIGHT = {light};
const SC_COLOUR = {colour};
const SC_SPOT: bool = {spot};
const SC_AXIS = {axis};
const SC_COS_OUTER: f32 = {co:?};
const SC_COS_INNER: f32 = {ci:?};
const SC_COS_CLIP: f32 = {cclip:?};
const SC_INTENSITY: f32 = {intensity:?};
const SC_SIGMA_T = {st};
const SC_SIGMA_S = {ss};
const SC_CAMERA = {cam};
const SC_CAM_F = {cf};
const SC_CAM_R = {cr};
const SC_CAM_U = {cu};
const SC_FACES: u32 = {nf}u;
const SC_FACE_ROWS = array<mat3x3<f32>, {nf}>({rows});
const SC_L_A: f32 = {a:?};
const SC_L_B: f32 = {b_:?};
const SC_AMBIENT: f32 = {ambient:?};
const SC_WIDTH: f32 = {w:?};
const SC_HEIGHT: f32 = {h:?};
const SC_HALF_FOV: f32 = {half:?};
const SC_MAP_RES: f32 = {res:?};
const SC_END_TEXELS: f32 = {end_texels:?};

",
        name = stage.name,
        rmin = v3(stage.room[0]),
        rmax = v3(stage.room[1]),
        nb = b.len(),
        mins = mins.join(", "),
        maxs = maxs.join(", "),
        bx = ball_c[0],
        by = ball_c[1],
        bz = ball_c[2],
        br = ball_r,
        na = albedo.len(),
        albedo = albedo.join(", "),
        light = v3(stage.light),
        colour = v3(stage.colour),
        spot = stage.spot.is_some(),
        axis = v3(axis),
        intensity = stage.intensity,
        st = v3(stage.sigma_t),
        ss = v3(stage.sigma_s),
        cam = v3(stage.camera),
        cf = v3(cf),
        cr = v3(cr),
        cu = v3(cu),
        nf = faces.len(),
        rows = faces.iter().map(|f| m3(*f)).collect::<Vec<_>>().join(", "),
        b_ = a * near,
        ambient = stage.ambient,
        w = view.width as f32,
        h = view.height as f32,
        half = 0.5 * crate::render::FOV_Y,
        res = stage.shadow_map as f32,
        end_texels = END_TEXELS,
    );
    constants + include_str!("scene.wgsl")
}
