
// ---- the light-shafts pass (shaders/tests/browser/pages/shafts.glsl) ----
uniform highp sampler2DShadow shadowMap;
uniform highp mat4 shadowMatrix;
out highp vec4 airlight_fog;
const vec3 CAMERA = {{camera}};
const vec3 LIGHT = {{light}};
// three.js's shadow: light.shadow.matrix maps the world to [0, 1]^3; outside it, lit.
float visibility(vec3 q) {
    vec4 c = shadowMatrix * vec4(q, 1.0);
    if (c.w <= 0.0) return 1.0;
    vec3 t = c.xyz / c.w;
    if (any(lessThan(t, vec3(0.0))) || any(greaterThan(t, vec3(1.0)))) return 1.0;
    return texture(shadowMap, vec3(t.xy, t.z - 0.0005));
}
float box_entry(vec3 lo, vec3 hi, vec3 d, float end) {
    vec3 a = (lo - CAMERA) / d, b = (hi - CAMERA) / d;
    vec3 n = min(a, b), x = max(a, b);
    float t0 = max(max(n.x, n.y), n.z), t1 = min(min(x.x, x.y), x.z);
    return (t0 < t1 && t0 > 0.0) ? t0 : end;
}
void main() {
    vec2 pos = vec2(gl_FragCoord.x, {{h_dbg}} - gl_FragCoord.y);
    float u = 2.0 * pos.x / {{w_dbg}} - 1.0;
    float v = 1.0 - 2.0 * pos.y / {{h_dbg}};
    float t = {{t_dbg}};
    vec3 d = {{f}} + (u * t * {{aspect_dbg}}) * {{r}} + (v * t) * {{up}};
    vec3 dir = d / sqrt(dot(d, d));
    // The first surface: the room's walls from inside, the beams, pillars and ball.
    vec3 a = ({{room_lo}} - CAMERA) / dir, b = ({{room_hi}} - CAMERA) / dir;
    vec3 x = max(a, b);
    float end = min(min(x.x, x.y), x.z);
{{slabs}}    vec3 w = CAMERA - {{ball_c}};
    float bb = dot(w, dir), disc = bb * bb - (dot(w, w) - {{ball_r2_dbg}});
    float sb = -bb - sqrt(max(disc, 0.0));
    if (disc >= 0.0 && sb > 0.0) end = min(end, sb);
    {{p}}Shafts acc = {{p}}shafts_begin();
    {{p}}shafts_push_spot(acc, 0.0, visibility(CAMERA), {{args}});
    for (int i = 0; i < {{n}}; i++) {
        float s = (float(i) + 0.5) * end / {{nf_dbg}};
        {{p}}shafts_push_spot(acc, s, visibility(CAMERA + s * dir), {{args}});
        for (int k = 0; k < {{refine}} && {{p}}shafts_probe(acc) >= 0.0; k++) {
            {{p}}shafts_refine(acc, visibility(CAMERA + {{p}}shafts_probe(acc) * dir));
        }
    }
    {{p}}shafts_push_spot(acc, end, visibility(CAMERA + end * (1.0 - 1e-4) * dir), {{args}});
    vec3 fog = {{p}}shafts_finish_spot(acc, end, {{args}});
    airlight_fog = vec4(fog, end);
}
