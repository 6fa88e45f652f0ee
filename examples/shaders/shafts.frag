// Light shafts in GLSL 4.50: each lit run of the view ray, exactly as the light's
// shadow map sees it (the shadow-map walk, generated/glsl/shadowmap.glsl), summed
// by the kernel's shafts accumulator (generated/glsl/phi-6.glsl). On WebGL 2,
// prepend the two files' text after the #version line. tests/tests/examples.rs
// compiles this file with glslangValidator.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "phi-6.glsl"
#include "shadowmap.glsl"

layout(set = 0, binding = 0) uniform Fog {
    vec3 eye;
    float intensity;
    vec3 light;
    float sigma_t;
    float sigma_s;
    float g;
    float bias;
};
layout(set = 0, binding = 1) uniform sampler2DArray uPyramid; // RG32F: min, max (shadowmap_pyramid.frag.glsl)
layout(location = 0) in vec3 view_dir;
layout(location = 1) in float surface;
layout(location = 0) out vec4 colour;

vec2 airlight_smap_node(int face, int level, ivec2 p) {
    return texelFetch(uPyramid, ivec3(p, face), level).rg;
}

void main() {
    vec3 origin = eye;
    vec3 dir = normalize(view_dir);
    mat3 rows = mat3(1.0); // unused for a cube map (a spot light's face: its rows)
    AirlightSmapWalk w = airlight_smap_begin(origin, dir, surface, light, rows, true, 2048, bias, 0);
    airlight_phi_6_Shafts acc = airlight_phi_6_shafts_begin_runs();
    for (;;) {
        bool more = true;
        for (;;) {  // the walk's own loop: no kernel in it
            vec2 r = airlight_smap_next(w);
            if (r.x < 0.0) { more = false; break; }
            airlight_phi_6_shafts_add_run(acc, r.x, r.y);
            if (airlight_phi_6_shafts_full(acc)) break;
        }
        if (!more) break;
        airlight_phi_6_shafts_flush(acc, origin, dir, light, intensity, sigma_t, sigma_s, g);
    }
    float shafts = airlight_phi_6_shafts_finish(acc, surface, origin, dir, light, intensity, sigma_t, sigma_s, g);
    colour = vec4(vec3(shafts), 1.0);
}
