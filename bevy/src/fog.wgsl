// airlight for Bevy 0.19: the fog pass. Every point and spot light's in-scattered
// light along each pixel's ray to the first surface (from the depth prepass),
// composited over the frame: colour · T + fog · exposure, T the medium's
// transmittance to that surface. `AIRLIGHT_MODULE` and `AIRLIGHT_G` are filled in
// by the plugin (bevy/src/lib.rs) with the picked kernel's module and, where the
// kernel takes g at run time, the g argument; `AIRLIGHT_SIGMA_T` with the σt
// argument (the closed form without extinction takes none).

#import bevy_core_pipeline::fullscreen_vertex_shader::FullscreenVertexOutput
#import bevy_render::view::View
#import AIRLIGHT_MODULE::spot

struct Light {
    // World position and the light's range (no in-scattering beyond it).
    position: vec3<f32>,
    range: f32,
    // Colour × luminous intensity (cd): the kernel's intensity per channel.
    intensity: vec3<f32>,
    // A spot's outer cut-off cosine (<= -1: a point light).
    cos_outer: f32,
    // A spot's direction (unit).
    axis: vec3<f32>,
    // A spot's inner cut-off cosine.
    cos_inner: f32,
    // The light's core: a viewer within it sees the ray from where it leaves it
    // (the integral diverges at the source).
    core: f32,
}

struct Fog {
    sigma_t: vec3<f32>,
    g: f32,
    sigma_s: vec3<f32>,
    count: u32,
    // Where in its pixel the depth read lies (pixels from the pixel's corner):
    // the centre, or with MSAA the position of sample 0, whose depth the pass
    // reads (on a floor seen at a grazing angle the distance changes by
    // percents across one pixel).
    sample: vec2<f32>,
    lights: array<Light, MAX_LIGHTS>,
}

@group(0) @binding(0) var screen: texture_2d<f32>;
#ifdef MULTISAMPLED
@group(0) @binding(1) var depth: texture_depth_multisampled_2d;
#else
@group(0) @binding(1) var depth: texture_depth_2d;
#endif
@group(0) @binding(2) var<uniform> view: View;
@group(0) @binding(3) var<uniform> fog: Fog;

// The largest finite f16: the pass clamps the fog to it (a kernel returns f32's
// largest finite value on a ray through a light).
const HALF_MAX: f32 = 65504.0;

@fragment
fn fragment(in: FullscreenVertexOutput) -> @location(0) vec4<f32> {
    let texel = vec2<i32>(floor(in.position.xy));
    let colour = textureLoad(screen, texel, 0);
    let z = textureLoad(depth, texel, 0);
    // Reverse Z: 0 is the far plane at infinity, where the ray meets no surface.
    let uv = (floor(in.position.xy) + fog.sample - view.viewport.xy) / view.viewport.zw;
    let ndc = vec2<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0);
    let far = z <= 0.0;
    var origin = view.world_position;
    var dir: vec3<f32>;
    var dist: f32;
    if view.clip_from_view[3].w == 1.0 {
        // Orthographic: parallel rays along the view's forward, from the near
        // plane (reverse Z: depth 1) through the pixel.
        let n = view.world_from_clip * vec4<f32>(ndc, 1.0, 1.0);
        origin = n.xyz / n.w;
        dir = normalize(-view.world_from_view[2].xyz);
        let p = view.world_from_clip * vec4<f32>(ndc, z, 1.0);
        dist = max(dot(p.xyz / p.w - origin, dir), 0.0);
    } else {
        // Perspective: from the eye through the surface, or the near plane
        // where there is none (its depth is finite however far the far plane).
        let p = view.world_from_clip * vec4<f32>(ndc, select(z, 1.0, far), 1.0);
        let ray = p.xyz / p.w - origin;
        dist = length(ray);
        dir = ray / dist;
    }
    let surface = select(dist, -1.0, far);

    var total = vec3<f32>(0.0);
    for (var i = 0u; i < min(fog.count, MAX_LIGHTS_U); i += 1u) {
        let l = fog.lights[i];
        // The stretch of the ray within the light's range: a sphere.
        let oc = origin - l.position;
        let b = dot(oc, dir);
        let c = dot(oc, oc) - l.range * l.range;
        let disc = b * b - c;
        if !(disc > 0.0) {
            continue;
        }
        let q = sqrt(disc);
        var s0 = max(-b - q, 0.0);
        // A viewer within the light's core: the ray from where it leaves it.
        let cc = dot(oc, oc) - l.core * l.core;
        if cc < 0.0 {
            s0 = max(s0, -b + sqrt(b * b - cc));
        }
        var s1 = -b + q;
        if surface >= 0.0 {
            s1 = min(s1, surface);
        }
        if !(s1 > s0) {
            continue;
        }
        let start = origin + s0 * dir;
        let a = spot(start, dir, s1 - s0, l.position, l.axis, l.cos_outer, l.cos_inner, 1.0,
            AIRLIGHT_SIGMA_T fog.sigma_s AIRLIGHT_G);
        // Clamped before the transmittance, so that f32's largest value (a ray
        // through the light) times an intensity never forms inf · 0.
        total += min(max(a, vec3<f32>(0.0)) * l.intensity, vec3<f32>(3.0e38)) * exp(-fog.sigma_t * s0);
    }
    let t = select(exp(-fog.sigma_t * dist), vec3<f32>(0.0), far);
    let lit = min(total * view.exposure, vec3<f32>(HALF_MAX));
    return vec4<f32>(colour.rgb * t + lit, colour.a);
}
