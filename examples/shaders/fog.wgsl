// A full-screen fog pass in WGSL: every pixel's view ray through the fog around
// one point light, with and without its shafts. WGSL has no #include: put
// generated/wgsl/phi-6.wgsl (the kernel) and generated/wgsl/shadowmap.wgsl (the
// walk, for shafts) before this file. tests/tests/examples.rs validates the three
// together with naga, as wgpu would.

struct Fog {
    inv_view_proj: mat4x4<f32>,
    eye: vec3<f32>,
    intensity: f32,
    light: vec3<f32>,
    sigma_t: f32,
    sigma_s: f32,
    g: f32,
    bias: f32,
    res: u32,
};

@group(0) @binding(0) var<uniform> u: Fog;
@group(0) @binding(1) var depth: texture_depth_2d;
@group(0) @binding(2) var pyramid: texture_2d_array<f32>; // the light's min-max pyramid (shadowmap_pyramid.wgsl)

// The view ray through a pixel (ndc in [-1, 1]^2) and the distance to the first surface.
fn ray(ndc: vec2<f32>, z: f32) -> vec4<f32> {
    let far = u.inv_view_proj * vec4<f32>(ndc, z, 1.0);
    let p = far.xyz / far.w - u.eye;
    return vec4<f32>(normalize(p), select(length(p), -1.0, z >= 1.0));
}

@fragment
fn fog(@builtin(position) frag: vec4<f32>, @location(0) ndc: vec2<f32>) -> @location(0) vec4<f32> {
    let r = ray(ndc, textureLoad(depth, vec2<i32>(frag.xy), 0));
    let dir = r.xyz;
    let surface = r.w; // negative: the ray meets no surface
    let l = airlight_phi_6_radiance(u.eye, dir, surface, u.light, u.intensity, u.sigma_t, u.sigma_s, u.g);
    return vec4<f32>(vec3<f32>(l), 1.0); // add to the frame's colour times the transmittance
}

@fragment
fn shafts(@builtin(position) frag: vec4<f32>, @location(0) ndc: vec2<f32>) -> @location(0) vec4<f32> {
    let view = ray(ndc, textureLoad(depth, vec2<i32>(frag.xy), 0));
    let origin = u.eye;
    let dir = view.xyz;
    let surface = view.w;
    let light = u.light;
    let intensity = u.intensity;
    let sigma_t = u.sigma_t;
    let sigma_s = u.sigma_s;
    let g = u.g;
    let bias = u.bias;
    let rows = mat3x3<f32>(); // unused for a cube map (a spot light's face: its rows)
    var w = airlight_smap_begin(origin, dir, surface, light, rows, true, u.res, bias, 0u);
    var acc = airlight_phi_6_shafts_begin_runs();
    loop {
        var more = true;
        loop {  // the walk's own loop: no kernel in it
            let r = airlight_smap_next(&w, pyramid);
            if r.x < 0.0 { more = false; break; }
            airlight_phi_6_shafts_add_run(&acc, r.x, r.y);  // r.y < 0: lit to infinity
            if airlight_phi_6_shafts_full(acc) { break; }
        }
        if !more { break; }
        airlight_phi_6_shafts_flush(&acc, origin, dir, light, intensity, sigma_t, sigma_s, g);
    }
    let shafts = airlight_phi_6_shafts_finish(acc, surface, origin, dir, light, intensity, sigma_t, sigma_s, g);
    return vec4<f32>(vec3<f32>(shafts), 1.0);
}

@fragment
fn lamp(@builtin(position) frag: vec4<f32>, @location(0) ndc: vec2<f32>) -> @location(0) vec4<f32> {
    let view = ray(ndc, textureLoad(depth, vec2<i32>(frag.xy), 0));
    let eye = u.eye;
    let dir = view.xyz;
    let surface = view.w;
    let lamp_pos = u.light;
    let intensity = u.intensity;
    // A lamp shining down, 30° outer and 20° inner half-angle, in fog that extinguishes red most.
    let rgb = airlight_phi_6_spot(eye, dir, surface, lamp_pos, vec3<f32>(0.0, -1.0, 0.0),
                                  cos(radians(30.0)), cos(radians(20.0)), intensity,
                                  vec3<f32>(0.06, 0.045, 0.03), vec3<f32>(0.04, 0.035, 0.027), 0.6);
    return vec4<f32>(rgb, 1.0);
}
