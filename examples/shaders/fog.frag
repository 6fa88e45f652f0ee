// A full-screen fog pass in GLSL 4.50 (Vulkan): the view ray through each pixel
// and the fog around one point light. The kernel is an include
// (generated/glsl/phi-6.glsl; on WebGL 2, prepend its text after the #version
// line instead). tests/tests/examples.rs compiles this file with glslangValidator.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "phi-6.glsl"

layout(set = 0, binding = 0) uniform Fog {
    vec3 eye;
    float intensity;
    vec3 light;
    float sigma_t;
    float sigma_s;
    float g;
};
layout(location = 0) in vec3 view_dir; // the pixel's ray, from the vertex shader
layout(location = 1) in float surface;  // distance to the first surface (negative: none)
layout(location = 0) out vec4 colour;

void main() {
    float l = airlight_phi_6_radiance(eye, normalize(view_dir), surface, light, intensity, sigma_t, sigma_s, g);
    colour = vec4(vec3(l), 1.0);
}
