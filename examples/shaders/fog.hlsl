// The same fog pass in HLSL (shader model 5.1; D3D, DXC, FXC): the kernel is an
// include, generated/hlsl/phi-6.hlsl. tests/tests/examples.rs compiles this file
// with glslang's HLSL front end.
#include "phi-6.hlsl"

cbuffer Fog : register(b0) {
    float3 eye;
    float intensity;
    float3 light_pos;
    float sigma_t;
    float sigma_s;
    float g;
};

float4 main(float3 view_dir : TEXCOORD0, float surface : TEXCOORD1) : SV_Target {
    float l = airlight_phi_6_radiance(eye, normalize(view_dir), surface, light_pos, intensity, sigma_t, sigma_s, g);
    return float4(l, l, l, 1.0);
}
