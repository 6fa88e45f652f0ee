//! A Bevy 0.19.1 app with no window draws the example's street (a lamp post's
//! point light and a wall-mounted spot light in HG fog) through `AirlightPlugin`
//! into an `Rgba16Float` image on the machine's adapter (lavapipe in CI), reads
//! it back, and compares it with the reference computed here in f64 for the same
//! camera, lights and medium: the composite `colour · T + fog · exposure` per
//! pixel, `colour` being the same frame drawn before the camera had fog.
//!
//! Then the lamp's intensity is doubled and the spot despawned: the next frames
//! must show exactly that (lights are read every frame).
//!
//! Without an adapter the test says so and passes, unless
//! `AIRLIGHT_REQUIRE_GPU=1` (as `.ci/run` sets).

use airlight_bevy::{AirlightFog, AirlightPlugin};
use airlight_bevy_example::{Lamp, Spot, Street};
use airlight_truth::geometry::{Cone, PhysicalRay};
use airlight_truth::shafts::Occluder;
use bevy::camera::{Exposure, Hdr, RenderTarget};
use bevy::core_pipeline::tonemapping::Tonemapping;
use bevy::prelude::*;
use bevy::render::gpu_readback::{Readback, ReadbackComplete};
use bevy::render::render_resource::{TextureFormat, TextureUsages};
use bevy::window::{ExitCondition, WindowPlugin};

/// The image: 320 × 192 (rows of 320 · 8 bytes are a multiple of 256, so the
/// read-back has no row padding).
const W: u32 = 320;
const H: u32 = 192;

#[derive(Resource, Default)]
struct Frames(Vec<Vec<u8>>);

fn required() -> bool {
    std::env::var("AIRLIGHT_REQUIRE_GPU").is_ok_and(|v| v == "1")
}

fn f16_to_f32(h: u16) -> f32 {
    let sign = if h & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exp = i32::from((h >> 10) & 0x1f);
    let man = f32::from(h & 0x3ff);
    match exp {
        0 => sign * man * 2f32.powi(-24),
        31 if man == 0.0 => sign * f32::INFINITY,
        31 => f32::NAN,
        e => sign * (1.0 + man / 1024.0) * 2f32.powi(e - 15),
    }
}

fn decode(bytes: &[u8]) -> Vec<[f32; 3]> {
    assert_eq!(bytes.len(), (W * H * 8) as usize, "read-back size");
    bytes
        .chunks_exact(8)
        .map(|p| std::array::from_fn(|c| f16_to_f32(u16::from_le_bytes([p[2 * c], p[2 * c + 1]]))))
        .collect()
}

/// Runs frames until the read-back is the same twice in a row, not black, and
/// differs from `before` (the pass's pipeline compiles over the first frames);
/// returns it and how many updates that took.
fn settle(app: &mut App, before: Option<&Vec<[f32; 3]>>, what: &str) -> (Vec<[f32; 3]>, usize) {
    let mut last: Option<Vec<[f32; 3]>> = None;
    for n in 1..=600 {
        app.update();
        let frames = std::mem::take(&mut app.world_mut().resource_mut::<Frames>().0);
        for f in frames {
            let px = decode(&f);
            // The first frames are black (the meshes and pipelines are still
            // being prepared): a frame counts once it is not.
            let new = before.is_none_or(|b| *b != px) && px.iter().any(|p| p.iter().any(|&v| v != 0.0));
            if new && last.as_ref() == Some(&px) {
                return (px, n);
            }
            last = Some(px);
        }
    }
    panic!("{what}: the frame did not settle in 600 updates");
}

fn app(street: &Street) -> Option<App> {
    app_with(street, Projection::Perspective(PerspectiveProjection { fov: street.fov, near: 0.05, ..default() }))
}

fn app_with(street: &Street, projection: Projection) -> Option<App> {
    // Bevy panics where it finds no adapter: ask wgpu first.
    if let Err(e) = airlight_shaders::Gpu::open() {
        eprintln!("no GPU adapter ({e})");
        return None;
    }
    let mut app = App::new();
    app.add_plugins(DefaultPlugins.set(WindowPlugin {
        primary_window: None,
        exit_condition: ExitCondition::DontExit,
        close_when_requested: false,
        ..default()
    }))
    .add_plugins(AirlightPlugin)
    .init_resource::<Frames>();
    app.finish();
    app.cleanup();
    let mut image = Image::new_target_texture(W, H, TextureFormat::Rgba16Float, None);
    image.texture_descriptor.usage |= TextureUsages::COPY_SRC;
    let target = app.world_mut().resource_mut::<Assets<Image>>().add(image);
    let s = street.clone();
    app.add_systems(
        Startup,
        move |mut commands: Commands, mut meshes: ResMut<Assets<Mesh>>, mut mats: ResMut<Assets<StandardMaterial>>| {
            s.spawn(&mut commands, &mut meshes, &mut mats);
            commands.spawn((
                Camera3d::default(),
                Camera { clear_color: ClearColorConfig::Custom(Color::BLACK), ..default() },
                RenderTarget::Image(target.clone().into()),
                Hdr,
                Tonemapping::None,
                Msaa::Sample4,
                projection.clone(),
                Exposure { ev100: s.ev100 },
                s.camera_transform(),
                bevy::core_pipeline::prepass::DepthPrepass,
            ));
            commands
                .spawn(Readback::texture(target.clone()))
                .observe(|ev: On<ReadbackComplete>, mut frames: ResMut<Frames>| frames.0.push(ev.event().data.clone()));
        },
    );
    Some(app)
}

/// The camera's MSAA: Bevy's default, 4 samples. The pass reads sample 0's
/// depth and casts its rays through that sample's position in the pixel.
const SAMPLES: u32 = 4;

/// Pixel `(i, j)`'s unit ray direction (f64), as Bevy's perspective projection
/// has it, through the position in the pixel of the sample the pass reads
/// (`i`, `j` may lie outside the image).
fn ray(street: &Street, i: i32, j: i32) -> [f64; 3] {
    let at = airlight_bevy::sample_position(SAMPLES).as_dvec2();
    let t = (f64::from(street.fov) * 0.5).tan();
    let aspect = f64::from(W) / f64::from(H);
    let x = (2.0 * (f64::from(i) + at.x) / f64::from(W) - 1.0) * t * aspect;
    let y = (1.0 - 2.0 * (f64::from(j) + at.y) / f64::from(H)) * t;
    let r = street.camera_transform().rotation.as_dquat();
    let d = r * bevy::math::DVec3::new(x, y, -1.0);
    let d = d.normalize();
    [d.x, d.y, d.z]
}

/// One light as the reference takes it: position, range, intensity per channel,
/// core (the plugin's `GpuLight`), and a spot's cone.
type RefLight<'a> = (&'a airlight_bevy::GpuLight, Option<&'a Cone>);

/// The reference fog of one light along the ray from `eye` along `dir` (per
/// channel, before exposure): the ray cut to the light's range sphere and to the
/// surface, and started where it leaves the light's core if the viewer is
/// within it, its in-scattering by the f64 reference.
fn light_fog(street: &Street, eye: [f64; 3], dir: [f64; 3], surface: Option<f64>, light: RefLight) -> [f64; 3] {
    let (g, cone) = light;
    let (at, range, intensity) = (g.position, g.range, g.intensity);
    let eye = bevy::math::DVec3::from(eye);
    let l = at.as_dvec3();
    let d = bevy::math::DVec3::from(dir);
    let oc = eye - l;
    let b = oc.dot(d);
    let c = oc.length_squared() - f64::from(range).powi(2);
    let disc = b * b - c;
    if disc <= 0.0 {
        return [0.0; 3];
    }
    let mut s0 = (-b - disc.sqrt()).max(0.0);
    let cc = oc.length_squared() - f64::from(g.core).powi(2);
    if cc < 0.0 {
        s0 = s0.max(-b + (b * b - cc).sqrt());
    }
    let s1 = (-b + disc.sqrt()).min(surface.unwrap_or(f64::INFINITY));
    if s1 <= s0 {
        return [0.0; 3];
    }
    let a = |q| airlight_truth::reference::airlight(q).unwrap_or(f64::INFINITY);
    std::array::from_fn(|ch| {
        let r = PhysicalRay {
            origin: [eye.x, eye.y, eye.z],
            direction: dir,
            surface_distance: Some(s1),
            light: [l.x, l.y, l.z],
            intensity: f64::from(intensity[ch]),
            sigma_t: f64::from(street.fog.sigma_t[ch]),
            sigma_s: f64::from(street.fog.sigma_s[ch]),
        };
        let (part, t) = r.stretch(s0, s1);
        t * part.light_radiance(cone, f64::from(street.fog.g), &a).expect("reference")
    })
}

struct Reference {
    /// Per pixel: the surface distance and block (None: the ray meets none), the
    /// lamp's and the spot's fog (before exposure), and whether it is on a silhouette.
    surface: Vec<Option<(f64, usize)>>,
    lamp: Vec<[f64; 3]>,
    spot: Vec<[f64; 3]>,
    edge: Vec<bool>,
}

/// The distance along the unit `dir` from `origin` to the first block and that
/// block's index, or None: the blocks as the reference's own occluders.
fn first_surface(street: &Street, origin: [f64; 3], dir: [f64; 3]) -> Option<(f64, usize)> {
    let corner = |v: Vec3| [f64::from(v.x), f64::from(v.y), f64::from(v.z)];
    street
        .blocks
        .iter()
        .enumerate()
        .filter_map(|(id, b)| {
            Occluder::Cuboid { min: corner(b.min), max: corner(b.max) }.enters(origin, dir).map(|t| (t, id))
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))
}

/// The camera's exposure, as Bevy applies it.
fn exposure(street: &Street) -> f64 {
    f64::from(Exposure { ev100: street.ev100 }.exposure())
}

/// The medium's transmittance to pixel `k`'s surface in channel `c` (0: no surface).
fn transmittance(street: &Street, r: &Reference, k: usize, c: usize) -> f64 {
    r.surface[k].map_or(0.0, |s| (-f64::from(street.fog.sigma_t[c]) * s.0).exp())
}

fn reference(street: &Street) -> Reference {
    let eye = street.eye.as_dvec3();
    reference_of(street, &|i, j| ([eye.x, eye.y, eye.z], ray(street, i, j)), &street_lights(street))
}

/// The street's lamp and spot as the reference takes them.
fn street_lights(street: &Street) -> [(airlight_bevy::GpuLight, Option<Cone>); 2] {
    let lamp = airlight_bevy::GpuLight::point(&street.lamp.0, &GlobalTransform::from_translation(street.lamp.1));
    let (spot_light, spot_at, spot_aim) = &street.spot;
    let spot = airlight_bevy::GpuLight::spot(
        spot_light,
        &GlobalTransform::from(Transform::from_translation(*spot_at).looking_at(*spot_aim, Vec3::Y)),
    );
    let axis = (*spot_aim - *spot_at).normalize().as_dvec3();
    let cone = Cone {
        axis: [axis.x, axis.y, axis.z],
        cos_outer: f64::from(spot_light.outer_angle).cos(),
        cos_inner: f64::from(spot_light.inner_angle).cos(),
    };
    [(lamp, None), (spot, Some(cone))]
}

/// The reference of the rays `ray_of(i, j)` (origin, unit direction) of every
/// pixel for the two `lights` (their fogs in `Reference::lamp` and `spot`).
fn reference_of(
    street: &Street,
    ray_of: &(dyn Fn(i32, i32) -> ([f64; 3], [f64; 3]) + Sync),
    lights: &[(airlight_bevy::GpuLight, Option<Cone>); 2],
) -> Reference {
    let px: Vec<(u32, u32)> = (0..H).flat_map(|j| (0..W).map(move |i| (i, j))).collect();
    let surface: Vec<Option<(f64, usize)>> = px
        .iter()
        .map(|&(i, j)| {
            let (o, d) = ray_of(i as i32, j as i32);
            first_surface(street, o, d)
        })
        .collect();
    let fogs = airlight_truth::parallel::map(
        &(0..px.len()).collect::<Vec<_>>(),
        |&k| {
            let (i, j) = px[k];
            let (o, d) = ray_of(i as i32, j as i32);
            let s = surface[k].map(|s| s.0);
            (
                light_fog(street, o, d, s, (&lights[0].0, lights[0].1.as_ref())),
                light_fog(street, o, d, s, (&lights[1].0, lights[1].1.as_ref())),
            )
        },
        &|_, _| {},
    );
    // Silhouettes: where a neighbour's ray (inside the image or not) meets
    // another block or none. There a pixel's multisampled colour blends both
    // sides, while the pass reads the depth of one sample.
    let edge = (0..px.len())
        .map(|k| {
            let (i, j) = ((k as u32 % W) as i32, (k as u32 / W) as i32);
            let me = surface[k];
            [(-1i32, 0i32), (1, 0), (0, -1), (0, 1)].iter().any(|&(di, dj)| {
                let (x, y) = (i + di, j + dj);
                let o = if x < 0 || y < 0 || x >= W as i32 || y >= H as i32 {
                    let (o, d) = ray_of(x, y);
                    first_surface(street, o, d)
                } else {
                    surface[(y as u32 * W + x as u32) as usize]
                };
                me.map(|m| m.1) != o.map(|o| o.1)
            })
        })
        .collect();
    Reference { surface, lamp: fogs.iter().map(|f| f.0).collect(), spot: fogs.iter().map(|f| f.1).collect(), edge }
}

/// Figures of one frame against `colour · T + fog · exposure`.
#[derive(Debug)]
struct Figures {
    /// Pixels compared (off the silhouettes), of which lit (fog ≥ 1e-3 of the frame's largest).
    compared: usize,
    lit: usize,
    /// Max and mean relative error of the fog over lit pixels.
    max: f64,
    mean: f64,
    /// Pixels past the allowance: the kernel's bound on the fog plus one f16 ulp
    /// of the frame (and 1e-6 for the f32 geometry and transmittance).
    over: usize,
    worst_at: (u32, u32),
    /// The least and largest signed error of the fog over lit pixels, in ulps of
    /// the f16 the frame holds the pixel in.
    ulps: (f64, f64),
    non_finite: usize,
}

fn figures(
    street: &Street,
    r: &Reference,
    colour: &[[f32; 3]],
    frame: &[[f32; 3]],
    lamp_scale: f64,
    spot_scale: f64,
    bound: f64,
) -> Figures {
    let exposure = exposure(street);
    let fog = |k: usize, c: usize| exposure * (lamp_scale * r.lamp[k][c] + spot_scale * r.spot[k][c]);
    let top = (0..frame.len()).flat_map(|k| (0..3).map(move |c| (k, c))).map(|(k, c)| fog(k, c)).fold(0.0, f64::max);
    // One unit in the last place of the f16 the frame holds `v` in: lavapipe
    // rounds towards zero when it stores f16 (measured: every error of the fog
    // against the reference within [-1, 0] ulp, with the kernel of bound 7e-6),
    // so a whole ulp, not a half.
    let ulp = |v: f64| 2f64.powi(v.abs().max(2f64.powi(-14)).log2().floor() as i32 - 10);
    let mut f = Figures {
        compared: 0,
        lit: 0,
        max: 0.0,
        mean: 0.0,
        over: 0,
        worst_at: (0, 0),
        ulps: (0.0, 0.0),
        non_finite: 0,
    };
    let mut sum = 0.0;
    for k in 0..frame.len() {
        if frame[k].iter().any(|v| !v.is_finite()) {
            f.non_finite += 1;
            continue;
        }
        if r.edge[k] {
            continue;
        }
        f.compared += 1;
        let mut lit = false;
        for c in 0..3 {
            let under = f64::from(colour[k][c]) * transmittance(street, r, k, c);
            let got = f64::from(frame[k][c]);
            let want = fog(k, c);
            let allowed = bound * want + ulp(got) + 1e-6 * want + 1e-7 * top;
            if (got - under - want).abs() > allowed {
                f.over += 1;
            }
            if want >= 1e-3 * top {
                lit = true;
                let u = (got - under - want) / ulp(got);
                f.ulps = (f.ulps.0.min(u), f.ulps.1.max(u));
                let e = (got - under - want).abs() / want;
                sum += e;
                if e > f.max {
                    f.max = e;
                    f.worst_at = (k as u32 % W, k as u32 / W);
                }
            }
        }
        if lit {
            f.lit += 1;
        }
    }
    f.mean = sum / (3 * f.lit.max(1)) as f64;
    f
}

/// The composite the reference gives: `colour · T + fog · exposure`.
fn reference_frame(street: &Street, r: &Reference, colour: &[[f32; 3]]) -> Vec<[f64; 3]> {
    let exposure = exposure(street);
    (0..colour.len())
        .map(|k| {
            std::array::from_fn(|c| {
                f64::from(colour[k][c]) * transmittance(street, r, k, c) + exposure * (r.lamp[k][c] + r.spot[k][c])
            })
        })
        .collect()
}

/// Writes the frame and the reference's composite as PNG (`bevy-street-frame.png`,
/// `bevy-street-reference.png`), tone-mapped alike.
fn pictures(dir: &std::path::Path, street: &Street, r: &Reference, colour: &[[f32; 3]], frame: &[[f32; 3]]) {
    use airlight_shaders::render;
    let want = reference_frame(street, r, colour);
    let exposure = render::exposure(&render::channels(&want));
    let got: Vec<[f64; 3]> = frame.iter().map(|p| p.map(f64::from)).collect();
    render::write_png(&dir.join("bevy-street-frame.png"), W, H, &render::tone_map_rgb(&got, exposure)).unwrap();
    render::write_png(&dir.join("bevy-street-reference.png"), W, H, &render::tone_map_rgb(&want, exposure)).unwrap();
}

#[test]
fn a_bevy_app_draws_the_street_in_fog_against_the_reference() {
    let street = Street::default();
    let Some(mut app) = app(&street) else {
        assert!(!required(), "AIRLIGHT_REQUIRE_GPU=1 but Bevy found no adapter");
        eprintln!("no GPU adapter: skipped");
        return;
    };
    let kernel = street.fog.kernel().expect("the street's budget has a kernel");
    let bound = kernel.worst();
    eprintln!("kernel {} (declared {})", kernel.name, kernel.bound);

    // The frame without fog: each surface's colour.
    let (colour, n0) = settle(&mut app, None, "the frame without fog");
    let camera = app.world_mut().query_filtered::<Entity, With<Camera3d>>().single(app.world()).unwrap();
    app.world_mut().entity_mut(camera).insert(street.fog.clone());
    let (fogged, n1) = settle(&mut app, Some(&colour), "the frame with fog");
    eprintln!("settled after {n0} and {n1} updates");

    let start = std::time::Instant::now();
    let r = reference(&street);
    eprintln!("reference: {} pixels in {:.1} s", r.lamp.len(), start.elapsed().as_secs_f64());
    let f = figures(&street, &r, &colour, &fogged, 1.0, 1.0, bound);
    eprintln!("street, lamp and spot: {f:?}");
    // The time of one update (main world and render world, read-back included),
    // median of 15, the frame settled.
    let mut times: Vec<f64> = (0..15)
        .map(|_| {
            let t = std::time::Instant::now();
            app.update();
            t.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    times.sort_by(f64::total_cmp);
    let update_ms = times[times.len() / 2];
    app.world_mut().resource_mut::<Frames>().0.clear();
    let adapter = app
        .world()
        .get_resource::<bevy::render::renderer::RenderAdapterInfo>()
        .map_or(String::from("unknown"), |a| format!("{} ({:?}, {})", a.name, a.backend, a.driver_info));
    eprintln!("adapter {adapter}; {update_ms:.1} ms per update (median of 15)");
    if std::env::var("AIRLIGHT_RECORD_EXAMPLE").is_ok_and(|v| v == "1") {
        let out = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../generated/render");
        pictures(&out, &street, &r, &colour, &fogged);
        let toml = format!(
            "# Written by the Bevy example's headless test (examples/bevy/tests/headless.rs, AIRLIGHT_RECORD_EXAMPLE=1); quoted by REPORT.md.\nkind = \"bevy-example\"\nbevy = \"0.19.1\"\nadapter = {adapter:?}\nprofile = \"{}\"\nkernel = \"{}\"\nbound = {bound:e}\nwidth = {W}\nheight = {H}\nmsaa = {SAMPLES}\ncompared_pixels = {}\nlit_pixels = {}\nlit_max = {:e}\nlit_mean = {:e}\nulps_min = {:e}\nulps_max = {:e}\nover = {}\nbad_pixels = {}\nupdate_ms = {update_ms:e}\n",
            if cfg!(debug_assertions) { "debug" } else { "release" },
            kernel.name,
            f.compared,
            f.lit,
            f.max,
            f.mean,
            f.ulps.0,
            f.ulps.1,
            f.over,
            f.non_finite
        );
        airlight_truth::io::write_atomic(&out.join("bevy-street.toml"), toml.as_bytes()).unwrap();
    }
    assert_eq!(f.non_finite, 0, "NaN or infinite pixels");
    assert!(f.lit > 2000, "too few lit pixels: {f:?}");
    assert_eq!(f.over, 0, "pixels past the kernel's bound plus one f16 ulp: {f:?}");

    // The lamp twice as bright: the next settled frame has twice its fog.
    let lamp = app.world_mut().query_filtered::<Entity, With<Lamp>>().single(app.world()).unwrap();
    app.world_mut().get_mut::<PointLight>(lamp).unwrap().intensity *= 2.0;
    let (brighter, n2) = settle(&mut app, Some(&fogged), "the frame with the lamp doubled");
    let f = figures(&street, &r, &colour, &brighter, 2.0, 1.0, bound);
    eprintln!("lamp doubled (shown after {n2} updates): {f:?}");
    assert_eq!((f.over, f.non_finite), (0, 0), "{f:?}");

    // The spot removed.
    let spot = app.world_mut().query_filtered::<Entity, With<Spot>>().single(app.world()).unwrap();
    app.world_mut().despawn(spot);
    let (no_spot, n3) = settle(&mut app, Some(&brighter), "the frame without the spot");
    let f = figures(&street, &r, &colour, &no_spot, 2.0, 0.0, bound);
    eprintln!("spot removed (shown after {n3} updates): {f:?}");
    assert_eq!((f.over, f.non_finite), (0, 0), "{f:?}");

    // Issue 60 (20): lights with intensity NaN, ∞ and −20 beside the lamp are
    // left out (logged by entity): the frame is the one without them.
    let bad: Vec<Entity> = [f32::NAN, f32::INFINITY, -20.0]
        .iter()
        .map(|&i| {
            app.world_mut().spawn((PointLight { intensity: i, ..default() }, Transform::from_xyz(0.0, 2.0, 0.0))).id()
        })
        .collect();
    let with_bad = after(&mut app, 8);
    assert!(with_bad == no_spot, "bad lights changed the frame");
    for e in bad {
        app.world_mut().despawn(e);
    }
    // A medium that cannot be drawn draws no fog: the frame without fog.
    app.world_mut().entity_mut(camera).insert(AirlightFog { sigma_t: Vec3::splat(f32::NAN), ..street.fog.clone() });
    let (plain, _) = settle(&mut app, Some(&no_spot), "the frame with a NaN sigma_t");
    assert!(plain == colour, "a NaN sigma_t drew something other than the frame without fog");
    app.world_mut().entity_mut(camera).insert(street.fog.clone());
    let (back, _) = settle(&mut app, Some(&plain), "the frame with the fog again");
    assert!(back == no_spot, "the good medium again did not give the frame back");

    // Issues 60 (19): a point light at the eye (a flashlight): every pixel
    // finite, none clamped, and the fog that of the ray from where it leaves
    // the light's core, as the reference gives it.
    let flash = PointLight { intensity: 20_000.0, range: 30.0, ..default() };
    let flash_id = app.world_mut().spawn((flash, Transform::from_translation(street.eye))).id();
    let (lit, _) = settle(&mut app, Some(&back), "the frame with a light at the eye");
    let eye = street.eye.as_dvec3();
    let flash_light = airlight_bevy::GpuLight::point(&flash, &GlobalTransform::from_translation(street.eye));
    let lights = [street_lights(&street)[0], (flash_light, None)];
    let rf = reference_of(&street, &|i, j| ([eye.x, eye.y, eye.z], ray(&street, i, j)), &lights);
    let f = figures(&street, &rf, &colour, &lit, 2.0, 1.0, bound);
    let top = lit.iter().flat_map(|p| p.iter()).fold(0.0f32, |a, &b| a.max(b));
    eprintln!("a light at the eye: {f:?}, brightest pixel {top}");
    assert_eq!((f.over, f.non_finite), (0, 0), "{f:?}");
    assert!(top < 65504.0, "a pixel clamped to f16's largest");
    app.world_mut().despawn(flash_id);

    // Issue 60 (18): an orthographic camera — parallel rays from its near
    // plane — against the reference over the same rays.
    let half = 1.5f64;
    app.world_mut().entity_mut(camera).remove::<AirlightFog>().insert(Projection::Orthographic(
        OrthographicProjection {
            scaling_mode: bevy::camera::ScalingMode::FixedVertical { viewport_height: 2.0 * half as f32 },
            ..OrthographicProjection::default_3d()
        },
    ));
    let (ortho_colour, _) = settle(&mut app, Some(&lit), "the orthographic frame without fog");
    app.world_mut().entity_mut(camera).insert(street.fog.clone());
    let (ortho, _) = settle(&mut app, Some(&ortho_colour), "the orthographic frame with fog");
    let rot = street.camera_transform().rotation.as_dquat();
    let at = airlight_bevy::sample_position(SAMPLES).as_dvec2();
    let aspect = f64::from(W) / f64::from(H);
    let forward = rot * bevy::math::DVec3::NEG_Z;
    let ortho_ray = |i: i32, j: i32| {
        let x = (2.0 * (f64::from(i) + at.x) / f64::from(W) - 1.0) * half * aspect;
        let y = (1.0 - 2.0 * (f64::from(j) + at.y) / f64::from(H)) * half;
        let o = eye + rot * bevy::math::DVec3::new(x, y, 0.0);
        ([o.x, o.y, o.z], [forward.x, forward.y, forward.z])
    };
    let ro = reference_of(&street, &ortho_ray, &street_lights(&street));
    let f = figures(&street, &ro, &ortho_colour, &ortho, 2.0, 0.0, bound);
    eprintln!("orthographic: {f:?}");
    assert_eq!((f.over, f.non_finite), (0, 0), "{f:?}");
    assert!(f.lit > 2000, "too few lit pixels: {f:?}");
}

/// Runs `n` updates and returns the last frame read back.
fn after(app: &mut App, n: usize) -> Vec<[f32; 3]> {
    let mut last = None;
    for _ in 0..n {
        app.update();
        for f in std::mem::take(&mut app.world_mut().resource_mut::<Frames>().0) {
            last = Some(decode(&f));
        }
    }
    last.expect("a frame was read back")
}
