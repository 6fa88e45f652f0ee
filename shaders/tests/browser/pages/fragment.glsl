{{kernel}}
// ---- the three.js page (shaders/tests/browser/pages/fragment.glsl) ----
out highp vec4 airlight_color;
const vec4 LIGHTS[{{nl}}] = vec4[{{nl}}]({{lights}});
const float SIGMA_T[{{np}}] = float[{{np}}]({{sigmas}});
void main() {
    float pw = {{pw_dbg}};
    vec2 pos = vec2(gl_FragCoord.x, {{h_dbg}} - gl_FragCoord.y);
    float panel = floor(pos.x / pw);
    float u = 2.0 * (pos.x - panel * pw) / pw - 1.0;
    float v = 1.0 - 2.0 * pos.y / {{h_dbg}};
    float t = tan({{half_dbg}});
    vec3 d = vec3(u * t * (pw / {{h_dbg}}), v * t, 1.0);
    vec3 dir = d / sqrt(dot(d, d));
    float surface = -1.0;
    if ({{ground}} && dir.y < 0.0) {
        surface = {{gy_dbg}} / dir.y;
    }
    float sigma_t = SIGMA_T[int(panel)];
    float sum = 0.0;
    for (int i = 0; i < {{nl}}; i++) {
        sum += {{prefix}}radiance({{args}});
    }
    // render::tone, in f32.
    float x = max(sum * {{exposure_dbg}}, 0.0);
    float c = pow(x / (1.0 + x), 1.0 / 2.2);
    airlight_color = vec4(c, c, c, 1.0);
}
