//! airlight for Bevy 0.19.1: the glow of every `PointLight` and `SpotLight` in fog,
//! as a post-processing pass.
//!
//! ```no_run
//! use bevy::prelude::*;
//! use airlight_bevy::{AirlightFog, AirlightPlugin};
//!
//! App::new()
//!     .add_plugins((DefaultPlugins, AirlightPlugin))
//!     .add_systems(Startup, |mut commands: Commands| {
//!         commands.spawn((Camera3d::default(), AirlightFog::fog(0.05, 0.6)));
//!         commands.spawn((PointLight::default(), Transform::from_xyz(0.0, 3.0, 0.0)));
//!     });
//! ```
//!
//! A camera with [`AirlightFog`] gets, over its frame, the in-scattered light of
//! every visible point and spot light along each pixel's ray to the first surface
//! (read from the depth prepass, which the component requires), and the surfaces
//! behind attenuated by the medium's transmittance: `colour · T + fog · exposure`.
//! The pass runs in [`Core3dSystems::PostProcess`] before tonemapping, on the
//! linear colour. Lights are read every frame: a moved, recoloured, added or
//! removed light shows in the next frame.
//!
//! Units, as Bevy's own lighting has them: a light's `intensity` (lumens) over
//! 4π is its luminous intensity in candela (Bevy divides spot lights by 4π too),
//! times its linear colour: the kernel's intensity `I` per channel; the fog is
//! `σs · I / D · A(τ, γ, ρ; g)` per light (docs/MATH.md), times the view's
//! exposure. A light's `range` bounds its in-scattering: the ray is cut to the
//! sphere of that radius around the light (Bevy's surfaces fade smoothly towards
//! the range, as `(1 − (d/r)⁴)²`; the fog is cut, not faded). A spot's
//! `outer_angle` and `inner_angle` give the kernel's smooth cone: weight 1 within
//! the inner cone, 0 outside the outer, **linear in the cosine** between (Bevy's
//! surfaces square that ramp).
//!
//! With MSAA the pass reads the depth of sample 0, so its rays go through that
//! sample's position in the pixel ([`sample_position`]), not the pixel's centre:
//! the fog is exact for that ray, and the resolved colour is the pixel's mean.
//!
//! Perspective and orthographic cameras: an orthographic camera's rays run
//! parallel from its near plane. The integral diverges at a light: a viewer
//! within a light's core ([`LIGHT_CORE`] or the light's `radius`, the larger —
//! a flashlight at the camera) sees its ray from where it leaves the core, a
//! bright, finite glow (the same rule as airlight-three's). A light whose
//! intensity or colour is NaN, infinite or negative is left out of the fog, and
//! an [`AirlightFog`] whose σt, σs, g or `max_error` cannot be drawn draws no
//! fog; each is logged by entity ([`GpuLight::check`], [`AirlightFog::check`]).
//!
//! What it does not do: no shafts (Bevy's shadow maps are not read: every light
//! glows unshadowed), no directional lights, at most [`MAX_LIGHTS`] lights per
//! view (those that can add the most to the view are kept: [`reach`]; an error
//! is logged whenever the number left out changes).
//!
//! The kernel is the cheapest on airlight's menu whose declared bound meets
//! [`AirlightFog::max_error`] for the medium's g ([`pick`]); the menu, its bounds
//! and measured costs are generated (`generated/bevy-0.19/menu.rs`), and only the
//! picked kernel's module is compiled.

use bevy::core_pipeline::{
    prepass::{DepthPrepass, ViewPrepassTextures},
    schedule::Core3d,
    tonemapping::tonemapping,
    Core3dSystems, FullscreenShader,
};
use bevy::ecs::query::QueryItem;
use bevy::prelude::*;
use bevy::render::{
    extract_component::{ExtractComponent, ExtractComponentPlugin},
    render_resource::{
        binding_types::{texture_2d, texture_depth_2d, texture_depth_2d_multisampled, uniform_buffer},
        BindGroupEntries, BindGroupLayoutDescriptor, BindGroupLayoutEntries, CachedRenderPipelineId, ColorTargetState,
        ColorWrites, DynamicUniformBuffer, FragmentState, Operations, PipelineCache, RenderPassColorAttachment,
        RenderPassDescriptor, RenderPipelineDescriptor, ShaderStages, ShaderType, TextureFormat, TextureSampleType,
    },
    renderer::{RenderContext, RenderDevice, RenderQueue, ViewQuery},
    sync_component::SyncComponent,
    view::{ExtractedView, Msaa, ViewTarget, ViewUniform, ViewUniformOffset, ViewUniforms},
    Extract, ExtractSchedule, Render, RenderApp, RenderStartup, RenderSystems,
};
use bevy::shader::{Shader, ShaderDefVal};
use std::collections::HashMap;

/// One kernel on airlight's menu (generated: `generated/bevy-0.19/menu.rs`).
#[derive(Debug)]
pub struct MenuKernel {
    /// Its name (`phi-4`).
    pub name: &'static str,
    /// Its naga_oil import path (`airlight::phi_4`).
    pub module: &'static str,
    /// Its naga_oil module's source.
    pub source: &'static str,
    /// Its declared bound, as the coefficient file states it.
    pub bound: &'static str,
    /// Its declared max relative error of A on the thin and dense domains (f64 model).
    pub thin: Option<f64>,
    pub dense: Option<f64>,
    /// The g range it serves ((0, 0): isotropic only).
    pub g_range: (f32, f32),
    /// Whether its entry points take g.
    pub g_param: bool,
    /// Its measured cost per evaluation (`airlight bench`): the f32 Rust kernel
    /// on the CPU and the GPU path, in ns (None: not measured).
    pub cpu_ns: Option<f64>,
    pub gpu_ns: Option<f64>,
}

impl MenuKernel {
    /// The larger of its declared bounds.
    pub fn worst(&self) -> f64 {
        self.thin.unwrap_or(f64::INFINITY).max(self.dense.unwrap_or(f64::INFINITY))
    }

    /// Whether its spot entry takes σt (the closed form without extinction does not).
    fn takes_sigma_t(&self) -> bool {
        self.source.contains("cos_inner: f32, intensity: f32, sigma_t: vec3<f32>")
    }

    fn cost(&self) -> f64 {
        self.gpu_ns.or(self.cpu_ns).unwrap_or(f64::INFINITY)
    }
}

mod menu {
    use super::MenuKernel;
    include!("../../generated/bevy-0.19/menu.rs");
}
pub use menu::MENU;

/// The cheapest kernel on the menu whose declared bound on both domains is at
/// most `max_error` and whose g range holds `g`, by measured GPU cost (else
/// CPU); costs within 10% count as equal and the smaller bound wins among them.
/// The same rule as airlight-three's `pick`. None: no kernel meets the budget.
pub fn pick(max_error: f64, g: f32) -> Option<&'static MenuKernel> {
    let fits: Vec<&MenuKernel> =
        MENU.iter().filter(|k| k.g_range.0 <= g && g <= k.g_range.1 && k.worst() <= max_error).collect();
    let cheapest = fits.iter().map(|k| k.cost()).fold(f64::INFINITY, f64::min);
    fits.into_iter().filter(|k| k.cost() <= 1.1 * cheapest).min_by(|a, b| a.worst().total_cmp(&b.worst()))
}

/// The most point and spot lights one view's pass draws.
pub const MAX_LIGHTS: usize = 16;

/// A light's core, in scene units (metres): a viewer closer to the light than
/// this (or than the light's `radius`, if larger) sees its ray's fog from where
/// the ray leaves that sphere. The in-scattering diverges at the source; this
/// keeps a light at the camera bright and finite, about `σs · I / core`.
/// airlight-three uses the same.
pub const LIGHT_CORE: f32 = 0.01;

/// A participating medium over a camera's view: homogeneous, per colour channel.
/// Requires the depth prepass (added with it).
#[derive(Component, Clone, Debug, Reflect)]
#[require(DepthPrepass)]
pub struct AirlightFog {
    /// Extinction σt per metre (per scene unit), per channel (R, G, B).
    pub sigma_t: Vec3,
    /// Scattering σs per metre, per channel (σs ≤ σt).
    pub sigma_s: Vec3,
    /// Henyey–Greenstein asymmetry g, in (−1, 1) (0: isotropic).
    pub g: f32,
    /// The quality: the largest declared relative error of A accepted. The
    /// pass uses the cheapest kernel on the menu within it ([`pick`]).
    pub max_error: f64,
}

impl AirlightFog {
    /// A grey medium: σt = σs = `density` per metre in every channel, HG `g`,
    /// max error 1e-2.
    pub fn fog(density: f32, g: f32) -> Self {
        Self { sigma_t: Vec3::splat(density), sigma_s: Vec3::splat(density), g, max_error: 1e-2 }
    }

    /// The kernel this medium and budget get (None: none on the menu meets them).
    pub fn kernel(&self) -> Option<&'static MenuKernel> {
        pick(self.max_error, self.g)
    }

    /// Whether the pass can draw this medium: σt and σs finite and ≥ 0 in every
    /// channel (σt = 0: no extinction), g finite in (−1, 1), `max_error` > 0.
    /// The same rules as airlight-three's.
    pub fn check(&self) -> Result<(), String> {
        for (name, v) in [("sigma_t", self.sigma_t), ("sigma_s", self.sigma_s)] {
            if !(v.is_finite() && v.min_element() >= 0.0) {
                return Err(format!("{name} = {v} must be finite and >= 0 in every channel"));
            }
        }
        if !(self.g.is_finite() && self.g.abs() < 1.0) {
            return Err(format!("g = {} must be in (-1, 1)", self.g));
        }
        if self.max_error.is_nan() || self.max_error <= 0.0 {
            return Err(format!("max_error = {} must be > 0", self.max_error));
        }
        Ok(())
    }
}

/// One light as the pass reads it.
#[derive(ShaderType, Clone, Copy, Debug, Default, PartialEq)]
pub struct GpuLight {
    /// World position.
    pub position: Vec3,
    /// Range: no in-scattering beyond it.
    pub range: f32,
    /// Linear colour × luminous intensity (cd), per channel.
    pub intensity: Vec3,
    /// A spot's outer cut-off cosine; -2: a point light.
    pub cos_outer: f32,
    /// A spot's direction (unit; (0, 0, 1) for a point light).
    pub axis: Vec3,
    /// A spot's inner cut-off cosine; -1 for a point light.
    pub cos_inner: f32,
    /// Its core: [`LIGHT_CORE`] or its `radius`, the larger.
    pub core: f32,
}

impl GpuLight {
    /// A Bevy point light at `at`, as the kernel takes it.
    pub fn point(light: &PointLight, at: &GlobalTransform) -> Self {
        Self {
            position: at.translation(),
            range: light.range,
            intensity: candela(light.color, light.intensity),
            cos_outer: -2.0,
            axis: Vec3::Z,
            cos_inner: -1.0,
            core: light.radius.max(LIGHT_CORE),
        }
    }

    /// A Bevy spot light at `at` (shining along its forward, −Z), as the kernel takes it.
    pub fn spot(light: &SpotLight, at: &GlobalTransform) -> Self {
        // Bevy keeps the outer angle below π/2 and the inner within it.
        let outer = light.outer_angle.min(std::f32::consts::FRAC_PI_2 - 1e-4);
        let inner = light.inner_angle.min(outer);
        Self {
            position: at.translation(),
            range: light.range,
            intensity: candela(light.color, light.intensity),
            cos_outer: outer.cos(),
            axis: at.forward().as_vec3(),
            cos_inner: inner.cos(),
            core: light.radius.max(LIGHT_CORE),
        }
    }

    /// Whether the pass can draw this light: a finite position, and an
    /// intensity (colour × lumens) finite and ≥ 0 in every channel — NaN would
    /// poison every pixel, a negative one darken the fog. A finite intensity is
    /// drawn as it is (its fog may saturate the frame within its range). The
    /// same rules as airlight-three's.
    pub fn check(&self) -> Result<(), String> {
        if !(self.intensity.is_finite() && self.intensity.min_element() >= 0.0) {
            return Err(format!("intensity x colour = {} cd must be finite and >= 0 in every channel", self.intensity));
        }
        if !(self.position.is_finite() && self.range >= 0.0) {
            return Err(format!("position {} must be finite and range {} >= 0", self.position, self.range));
        }
        Ok(())
    }
}

/// An upper bound on the fog a light can add to any pixel of a view (its
/// intensity times the largest `∫ T/|x − light|² ds` over the view's rays,
/// up to the phase function and σs, which every light shares): the ranking when
/// a view has more than [`MAX_LIGHTS`]. `eye` and `forward` (unit) are the
/// view's; `half_diagonal` the angle from the view's axis to its frustum's
/// corner (perspective), or, with `ortho`, the half-diagonal of its rectangle
/// in scene units. A light in view ranks by `I e^{−σt D}/(D · 1e-3)` (its ray
/// passing a thousandth of its distance from it); one outside by the ray of the
/// view that passes closest to it; a light behind the camera adds little.
pub fn reach(light: &GpuLight, eye: Vec3, forward: Vec3, half_diagonal: f32, ortho: bool, sigma_t: f32) -> f32 {
    let to = light.position - eye;
    let d = to.length().max(1e-6);
    let i = light.intensity.max_element();
    // Every scattering point x has |x − eye| + |light − x| ≥ D: the transmittance
    // of any path is at most e^{−σt D}.
    let t = (-sigma_t.max(0.0) * d).exp();
    let (h, ahead) = if ortho {
        let depth = to.dot(forward);
        let lateral = (to - depth * forward).length();
        ((lateral - half_diagonal).max(0.0), depth)
    } else {
        let angle = (to.dot(forward) / d).clamp(-1.0, 1.0).acos();
        let alpha = (angle - half_diagonal).max(0.0);
        (d * alpha.sin(), d * alpha.cos())
    };
    // ∫ ds/(h² + (s − ahead)²) over s ≥ 0 = (π/2 + atan(ahead/h))/h.
    let h = h.max(1e-3 * d);
    i * t * (std::f32::consts::FRAC_PI_2 + (ahead / h).atan()) / h
}

/// Bevy's luminous power (lumens) and colour as a luminous intensity per linear
/// channel (cd): `colour · lumens / 4π`, as Bevy's own lighting takes it for
/// point and spot lights.
pub fn candela(color: Color, lumens: f32) -> Vec3 {
    let c = color.to_linear();
    Vec3::new(c.red, c.green, c.blue) * (lumens / (4.0 * std::f32::consts::PI))
}

/// What the pass draws for one view.
#[derive(ShaderType, Clone, Copy, Debug)]
struct GpuFog {
    sigma_t: Vec3,
    g: f32,
    sigma_s: Vec3,
    count: u32,
    sample: Vec2,
    lights: [GpuLight; MAX_LIGHTS],
}

/// Where in its pixel sample 0 of `samples` lies (pixels from the pixel's top-left
/// corner): the standard sample positions of Vulkan, Direct3D and Metal (WebGPU's
/// for 4); the pixel's centre without MSAA.
pub fn sample_position(samples: u32) -> Vec2 {
    match samples {
        2 => Vec2::new(0.75, 0.75),
        4 => Vec2::new(0.375, 0.125),
        8 => Vec2::new(0.5625, 0.3125),
        16 => Vec2::new(0.5625, 0.5625),
        _ => Vec2::splat(0.5),
    }
}

/// Adds the fog pass to every camera with [`AirlightFog`].
pub struct AirlightPlugin;

impl Plugin for AirlightPlugin {
    fn build(&self, app: &mut App) {
        app.register_type::<AirlightFog>()
            .init_resource::<KernelShaders>()
            .add_plugins(ExtractComponentPlugin::<AirlightFog>::default())
            .add_systems(PostUpdate, load_kernels);
        let Some(render_app) = app.get_sub_app_mut(RenderApp) else {
            return;
        };
        render_app
            .init_resource::<FogUniforms>()
            .init_resource::<FogLights>()
            .add_systems(RenderStartup, init_pipeline)
            .add_systems(ExtractSchedule, extract_lights)
            .add_systems(
                Render,
                (
                    queue_pipelines.in_set(RenderSystems::Prepare),
                    prepare_uniforms.in_set(RenderSystems::PrepareResources),
                ),
            )
            .add_systems(Core3d, fog_pass.in_set(Core3dSystems::PostProcess).before(tonemapping));
    }
}

/// The fog shader of each kernel picked so far, by its index on the menu (main world).
#[derive(Resource, Default)]
struct KernelShaders {
    fog: HashMap<usize, Handle<Shader>>,
    modules: Vec<Handle<Shader>>,
    /// Cameras told that no kernel meets their budget, until one does again.
    refused: Vec<Entity>,
}

/// The picked kernel of a camera with [`AirlightFog`]: its menu index and fog
/// shader (main world; set by the plugin).
#[derive(Component, Clone, Debug)]
pub struct AirlightKernel {
    index: usize,
    shader: Handle<Shader>,
}

/// The fog pass's source for `kernel`.
fn fog_source(kernel: &MenuKernel) -> String {
    include_str!("fog.wgsl")
        .replace("AIRLIGHT_MODULE", kernel.module)
        .replace("AIRLIGHT_G", if kernel.g_param { ", fog.g" } else { "" })
        .replace("AIRLIGHT_SIGMA_T", if kernel.takes_sigma_t() { "fog.sigma_t, " } else { "" })
        .replace("MAX_LIGHTS_U", &format!("{MAX_LIGHTS}u"))
        .replace("MAX_LIGHTS", &MAX_LIGHTS.to_string())
}

/// Picks each camera's kernel and loads its module and fog shader once.
fn load_kernels(
    mut commands: Commands,
    mut shaders: ResMut<Assets<Shader>>,
    mut loaded: ResMut<KernelShaders>,
    cameras: Query<(Entity, &AirlightFog, Option<&AirlightKernel>), Changed<AirlightFog>>,
) {
    for (entity, fog, current) in &cameras {
        let picked = fog.check().and_then(|()| {
            fog.kernel()
                .ok_or_else(|| format!("no kernel on the menu meets max_error = {} for g = {}", fog.max_error, fog.g))
        });
        let kernel = match picked {
            Ok(k) => k,
            Err(e) => {
                if !loaded.refused.contains(&entity) {
                    error!("airlight: camera {entity}: AirlightFog: {e}; it draws no fog");
                    loaded.refused.push(entity);
                }
                commands.entity(entity).remove::<AirlightKernel>();
                continue;
            }
        };
        // Told again if its budget goes wrong again later.
        loaded.refused.retain(|e| *e != entity);
        let index = MENU.iter().position(|k| std::ptr::eq(k, kernel)).unwrap_or(0);
        if current.is_some_and(|c| c.index == index) {
            continue;
        }
        let shader = match loaded.fog.get(&index) {
            Some(h) => h.clone(),
            None => {
                let module = shaders.add(Shader::from_wgsl(kernel.source, format!("airlight/{}.wgsl", kernel.name)));
                loaded.modules.push(module);
                let h =
                    shaders.add(Shader::from_wgsl(fog_source(kernel), format!("airlight/fog-{}.wgsl", kernel.name)));
                loaded.fog.insert(index, h.clone());
                h
            }
        };
        commands.entity(entity).insert(AirlightKernel { index, shader });
    }
}

/// A camera's medium and kernel (render world).
#[derive(Component, Clone, Debug)]
pub struct ExtractedFog {
    sigma_t: Vec3,
    sigma_s: Vec3,
    g: f32,
    shader: Handle<Shader>,
}

impl SyncComponent for AirlightFog {
    type Target = (ExtractedFog, FogUniformOffset, FogPipelineId);
}

impl ExtractComponent for AirlightFog {
    type QueryData = (&'static AirlightFog, Option<&'static AirlightKernel>);
    type QueryFilter = ();
    type Out = ExtractedFog;

    fn extract_component((fog, kernel): QueryItem<'_, '_, Self::QueryData>) -> Option<ExtractedFog> {
        let kernel = kernel?;
        Some(ExtractedFog { sigma_t: fog.sigma_t, sigma_s: fog.sigma_s, g: fog.g, shader: kernel.shader.clone() })
    }
}

/// The lights of this frame (render world).
#[derive(Resource, Default)]
struct FogLights {
    lights: Vec<GpuLight>,
    /// The lights left out of the fog as bad, told once each until they are good again.
    refused: Vec<Entity>,
    /// The number of lights past [`MAX_LIGHTS`] last logged.
    told_over: usize,
}

fn extract_lights(
    mut out: ResMut<FogLights>,
    points: Extract<Query<(Entity, &PointLight, &GlobalTransform, &InheritedVisibility)>>,
    spots: Extract<Query<(Entity, &SpotLight, &GlobalTransform, &InheritedVisibility)>>,
) {
    out.lights.clear();
    let all = points
        .iter()
        .filter(|p| p.3.get())
        .map(|(e, l, t, _)| (e, GpuLight::point(l, t)))
        .chain(spots.iter().filter(|s| s.3.get()).map(|(e, l, t, _)| (e, GpuLight::spot(l, t))));
    let mut refused = Vec::new();
    for (entity, light) in all {
        match light.check() {
            Ok(()) => out.lights.push(light),
            Err(e) => {
                if !out.refused.contains(&entity) {
                    error!("airlight: light {entity}: {e}; it is left out of the fog");
                }
                refused.push(entity);
            }
        }
    }
    out.refused = refused;
}

#[derive(Resource, Default)]
struct FogUniforms(DynamicUniformBuffer<GpuFog>);

/// The offset of a view's fog uniforms (render world).
#[derive(Component, Clone, Copy)]
pub struct FogUniformOffset(u32);

/// A view's fog pipeline (render world).
#[derive(Component, Clone, Copy)]
pub struct FogPipelineId(CachedRenderPipelineId);

/// Writes each fog view's medium and lights (those that can add the most to
/// the view, [`reach`], when there are more than [`MAX_LIGHTS`]).
fn prepare_uniforms(
    mut commands: Commands,
    device: Res<RenderDevice>,
    queue: Res<RenderQueue>,
    mut uniforms: ResMut<FogUniforms>,
    mut lights: ResMut<FogLights>,
    views: Query<(Entity, &ExtractedView, &ExtractedFog, &Msaa)>,
) {
    uniforms.0.clear();
    let over = lights.lights.len().saturating_sub(MAX_LIGHTS);
    if over != lights.told_over {
        if over > 0 {
            error!(
                "airlight: {} point and spot lights; the fog pass draws at most {MAX_LIGHTS} per view (those that can \
                 add the most to it), {over} left out",
                lights.lights.len()
            );
        }
        lights.told_over = over;
    }
    for (entity, view, fog, msaa) in &views {
        let eye = view.world_from_view.translation();
        let mut chosen = lights.lights.clone();
        if chosen.len() > MAX_LIGHTS {
            let forward = view.world_from_view.forward().as_vec3();
            let p = view.clip_from_view;
            let ortho = p.w_axis.w == 1.0;
            // Perspective: the angle to the frustum's corner; orthographic: the
            // rectangle's half-diagonal.
            let half = if ortho {
                Vec2::new(1.0 / p.x_axis.x, 1.0 / p.y_axis.y).length()
            } else {
                Vec2::new(1.0 / p.x_axis.x, 1.0 / p.y_axis.y).length().atan()
            };
            let sigma_t = fog.sigma_t.min_element();
            let weight = |l: &GpuLight| reach(l, eye, forward, half, ortho, sigma_t);
            chosen.sort_by(|a, b| weight(b).total_cmp(&weight(a)));
            chosen.truncate(MAX_LIGHTS);
        }
        let mut gpu = GpuFog {
            sigma_t: fog.sigma_t,
            g: fog.g,
            sigma_s: fog.sigma_s,
            count: chosen.len() as u32,
            sample: sample_position(msaa.samples()),
            lights: [GpuLight::default(); MAX_LIGHTS],
        };
        gpu.lights[..chosen.len()].copy_from_slice(&chosen);
        let offset = uniforms.0.push(&gpu);
        commands.entity(entity).insert(FogUniformOffset(offset));
    }
    uniforms.0.write_buffer(&device, &queue);
}

/// The pass's bind group layouts (single- and multi-sampled depth) and vertex shader.
#[derive(Resource)]
struct FogPipeline {
    layout: BindGroupLayoutDescriptor,
    layout_msaa: BindGroupLayoutDescriptor,
    vertex: bevy::render::render_resource::VertexState,
    pipelines: HashMap<(AssetId<Shader>, TextureFormat, bool), CachedRenderPipelineId>,
}

fn layout(multisampled: bool) -> BindGroupLayoutDescriptor {
    let depth = if multisampled { texture_depth_2d_multisampled() } else { texture_depth_2d() };
    BindGroupLayoutDescriptor::new(
        if multisampled { "airlight_fog_layout_msaa" } else { "airlight_fog_layout" },
        &BindGroupLayoutEntries::sequential(
            ShaderStages::FRAGMENT,
            (
                texture_2d(TextureSampleType::Float { filterable: false }),
                depth,
                uniform_buffer::<ViewUniform>(true),
                uniform_buffer::<GpuFog>(true),
            ),
        ),
    )
}

fn init_pipeline(mut commands: Commands, fullscreen: Res<FullscreenShader>) {
    commands.insert_resource(FogPipeline {
        layout: layout(false),
        layout_msaa: layout(true),
        vertex: fullscreen.to_vertex_state(),
        pipelines: HashMap::new(),
    });
}

/// Queues (once) the pipeline of each view's kernel, target format and sampling.
fn queue_pipelines(
    mut commands: Commands,
    cache: Res<PipelineCache>,
    mut pipeline: ResMut<FogPipeline>,
    views: Query<(Entity, &ExtractedView, &ExtractedFog, &Msaa)>,
) {
    for (entity, view, fog, msaa) in &views {
        let multisampled = msaa.samples() > 1;
        let key = (fog.shader.id(), view.target_format, multisampled);
        let layout = if multisampled { pipeline.layout_msaa.clone() } else { pipeline.layout.clone() };
        let vertex = pipeline.vertex.clone();
        let id = *pipeline.pipelines.entry(key).or_insert_with(|| {
            cache.queue_render_pipeline(RenderPipelineDescriptor {
                label: Some("airlight_fog".into()),
                layout: vec![layout],
                vertex,
                fragment: Some(FragmentState {
                    shader: fog.shader.clone(),
                    shader_defs: if multisampled { vec![ShaderDefVal::from("MULTISAMPLED")] } else { vec![] },
                    entry_point: Some("fragment".into()),
                    targets: vec![Some(ColorTargetState {
                        format: view.target_format,
                        blend: None,
                        write_mask: ColorWrites::ALL,
                    })],
                }),
                ..default()
            })
        });
        commands.entity(entity).insert(FogPipelineId(id));
    }
}

/// The fog pass: reads the frame and the depth prepass, writes the composite.
fn fog_pass(
    view: ViewQuery<(&ViewTarget, &ViewPrepassTextures, &ViewUniformOffset, &FogUniformOffset, &FogPipelineId, &Msaa)>,
    cache: Res<PipelineCache>,
    pipeline: Res<FogPipeline>,
    view_uniforms: Res<ViewUniforms>,
    fog_uniforms: Res<FogUniforms>,
    mut ctx: RenderContext,
) {
    let (target, prepass, view_offset, fog_offset, id, msaa) = view.into_inner();
    let Some(render_pipeline) = cache.get_render_pipeline(id.0) else {
        return;
    };
    let (Some(depth), Some(view_binding), Some(fog_binding)) =
        (prepass.depth_view(), view_uniforms.uniforms.binding(), fog_uniforms.0.binding())
    else {
        return;
    };
    let layout = if msaa.samples() > 1 { &pipeline.layout_msaa } else { &pipeline.layout };
    let post = target.post_process_write();
    let bind_group = ctx.render_device().create_bind_group(
        "airlight_fog_bind_group",
        &cache.get_bind_group_layout(layout),
        &BindGroupEntries::sequential((post.source, depth, view_binding, fog_binding)),
    );
    let mut pass = ctx.command_encoder().begin_render_pass(&RenderPassDescriptor {
        label: Some("airlight_fog"),
        color_attachments: &[Some(RenderPassColorAttachment {
            view: post.destination,
            depth_slice: None,
            resolve_target: None,
            ops: Operations::default(),
        })],
        depth_stencil_attachment: None,
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    });
    pass.set_pipeline(render_pipeline);
    pass.set_bind_group(0, &bind_group, &[view_offset.offset, fog_offset.0]);
    pass.draw(0..3, 0..1);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_menu_is_picked_by_bound_and_cost() {
        // Every pick meets its budget and the medium's g, and is the cheapest that does
        // (within the 10% tie).
        for max_error in [1e-1, 3e-2, 1e-2, 1e-3, 1e-4, 1e-5, 3e-6] {
            for g in [0.0f32, 0.3, 0.6, -0.5] {
                match pick(max_error, g) {
                    Some(k) => {
                        assert!(k.worst() <= max_error && k.g_range.0 <= g && g <= k.g_range.1, "{}", k.name);
                        for other in
                            MENU.iter().filter(|o| o.worst() <= max_error && o.g_range.0 <= g && g <= o.g_range.1)
                        {
                            assert!(
                                k.cost() <= 1.1 * other.cost(),
                                "{} picked over the cheaper {}",
                                k.name,
                                other.name
                            );
                        }
                    }
                    None => {
                        assert!(!MENU.iter().any(|o| o.worst() <= max_error && o.g_range.0 <= g && g <= o.g_range.1))
                    }
                }
            }
        }
        // A budget tighter than every bound gets nothing.
        assert!(pick(1e-9, 0.0).is_none());
    }

    #[test]
    fn every_menu_kernel_has_the_spot_entry_the_pass_calls() {
        for k in MENU {
            let ident = k.module.trim_start_matches("airlight::");
            assert!(k.source.contains(&format!("#define_import_path airlight::{ident}")), "{}", k.name);
            let g = if k.g_param { ", g: f32" } else { "" };
            let t = if k.takes_sigma_t() { "sigma_t: vec3<f32>, " } else { "" };
            let sig = format!(
                "fn spot(origin: vec3<f32>, dir: vec3<f32>, surface: f32, light: vec3<f32>, axis: vec3<f32>, cos_outer: f32, cos_inner: f32, intensity: f32, {t}sigma_s: vec3<f32>{g}) -> vec3<f32>"
            );
            assert!(k.source.contains(&sig), "{}: no `{sig}`", k.name);
            assert!(!fog_source(k).contains("AIRLIGHT_"), "{}", k.name);
        }
    }

    #[test]
    fn lumens_become_candela_per_channel_as_bevy_takes_them() {
        let i = candela(Color::linear_rgb(1.0, 0.5, 0.0), 4.0 * std::f32::consts::PI * 100.0);
        assert!((i - Vec3::new(100.0, 50.0, 0.0)).abs().max_element() < 1e-3, "{i}");
    }

    fn point_at(position: Vec3, lumens: f32) -> GpuLight {
        GpuLight::point(&PointLight { intensity: lumens, ..default() }, &GlobalTransform::from_translation(position))
    }

    /// Issue 60 (20): the same rules as airlight-three's — a light whose
    /// intensity is NaN, infinite or negative is refused, a finite one drawn;
    /// a medium with a NaN or negative σt, or g out of (−1, 1), is refused.
    #[test]
    fn bad_lights_and_media_are_refused_by_name() {
        for lumens in [f32::NAN, f32::INFINITY, -20.0] {
            let e = point_at(Vec3::ZERO, lumens).check().unwrap_err();
            assert!(e.contains("intensity"), "{lumens}: {e}");
        }
        assert!(point_at(Vec3::ZERO, 1e30).check().is_ok());
        assert!(point_at(Vec3::splat(f32::NAN), 100.0).check().is_err());
        let good = AirlightFog::fog(0.05, 0.6);
        assert!(good.check().is_ok());
        let no_extinction = AirlightFog { sigma_t: Vec3::ZERO, ..good.clone() };
        assert!(no_extinction.check().is_ok());
        for (bad, says) in [
            (AirlightFog { sigma_t: Vec3::splat(f32::NAN), ..good.clone() }, "sigma_t"),
            (AirlightFog { sigma_t: Vec3::new(0.1, -0.1, 0.1), ..good.clone() }, "sigma_t"),
            (AirlightFog { sigma_s: Vec3::splat(f32::INFINITY), ..good.clone() }, "sigma_s"),
            (AirlightFog { g: 1.0, ..good.clone() }, "g ="),
            (AirlightFog { g: f32::NAN, ..good.clone() }, "g ="),
            (AirlightFog { max_error: f64::NAN, ..good.clone() }, "max_error"),
        ] {
            assert!(bad.check().unwrap_err().contains(says), "{bad:?}");
        }
    }

    /// Issue 60 (21): a bright light behind the camera no longer pushes out a
    /// visible one: a light in view outranks one 100x brighter at the same
    /// distance behind, and a light beside the view ranks by how close the
    /// view's rays pass it.
    #[test]
    fn lights_rank_by_what_they_can_add_to_the_view() {
        let (eye, forward) = (Vec3::ZERO, Vec3::NEG_Z);
        let half = (0.5f32.tan().hypot(0.3f32.tan())).atan();
        let ahead = point_at(Vec3::new(0.0, 0.0, -10.0), 1000.0);
        let behind = point_at(Vec3::new(0.0, 0.0, 10.0), 100_000.0);
        let r = |l: &GpuLight| reach(l, eye, forward, half, false, 0.05);
        assert!(r(&ahead) > r(&behind), "{} vs {}", r(&ahead), r(&behind));
        let beside = point_at(Vec3::new(20.0, 0.0, -10.0), 1000.0);
        let farther = point_at(Vec3::new(40.0, 0.0, -10.0), 1000.0);
        assert!(r(&ahead) > r(&beside) && r(&beside) > r(&farther));
        // Fog dims a far light: the same light 100 m off counts less.
        let far = point_at(Vec3::new(0.0, 0.0, -100.0), 1000.0);
        assert!(r(&far) < r(&ahead) * 1e-2);
        // An orthographic view: a light within its rectangle beats one outside.
        let o = |l: &GpuLight| reach(l, eye, forward, 5.0, true, 0.05);
        assert!(o(&ahead) > o(&beside));
    }
}
