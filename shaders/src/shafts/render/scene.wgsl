// The light-shafts scene's shader (shaders/src/shafts/render/scene.rs puts the scene's
// constants, SC_*, before it): a room of boxes and a ball lit by a spot light (one
// perspective shadow map) or a point light (a cube map: six 90-degree faces, one
// layer each); the first surface along a view ray, its normal, the light's clip
// position per face and shadow-map visibility, the cone's weight, the camera's rays.

@group(0) @binding(0) var sc_shadow_map: texture_depth_2d_array;
@group(0) @binding(1) var sc_shadow_cmp: sampler_comparison;

fn sc_safe(d: vec3<f32>) -> vec3<f32> {
    return select(d, vec3<f32>(1e-30), abs(d) < vec3<f32>(1e-30));
}

// The first surface along o + t d (d unit, o inside the room): (t, object id).
fn sc_hit(o: vec3<f32>, d: vec3<f32>) -> vec2<f32> {
    let inv = 1.0 / sc_safe(d);
    // The room's faces from inside: floor 0, ceiling 1, walls -x 2, +x 3, +z 4, -z 5.
    let t0 = (SC_ROOM_MIN - o) * inv;
    let t1 = (SC_ROOM_MAX - o) * inv;
    let far = max(t0, t1);
    var best = far.y;
    var id = select(0.0, 1.0, d.y > 0.0);
    if far.x < best { best = far.x; id = select(2.0, 3.0, d.x > 0.0); }
    if far.z < best { best = far.z; id = select(5.0, 4.0, d.z > 0.0); }
    var mins = SC_BOX_MIN;
    var maxs = SC_BOX_MAX;
    for (var i = 0u; i < SC_NB; i++) {
        let a = (mins[i] - o) * inv;
        let b = (maxs[i] - o) * inv;
        let lo = min(a, b);
        let hi = max(a, b);
        let tn = max(max(lo.x, lo.y), lo.z);
        let tf = min(min(hi.x, hi.y), hi.z);
        if tn <= tf && tn > 0.0 && tn < best { best = tn; id = 6.0 + f32(i); }
    }
    let oc = o - SC_BALL.xyz;
    let bq = dot(oc, d);
    let cq = dot(oc, oc) - SC_BALL.w * SC_BALL.w;
    let disc = bq * bq - cq;
    if disc >= 0.0 {
        let t = -bq - sqrt(disc);
        if t > 0.0 && t < best { best = t; id = 6.0 + f32(SC_NB); }
    }
    return vec2<f32>(best, id);
}

// The outward normal of object `id` at its surface point p.
fn sc_normal(id: u32, p: vec3<f32>) -> vec3<f32> {
    switch id {
        case 0u: { return vec3<f32>(0.0, 1.0, 0.0); }
        case 1u: { return vec3<f32>(0.0, -1.0, 0.0); }
        case 2u: { return vec3<f32>(1.0, 0.0, 0.0); }
        case 3u: { return vec3<f32>(-1.0, 0.0, 0.0); }
        case 4u: { return vec3<f32>(0.0, 0.0, -1.0); }
        case 5u: { return vec3<f32>(0.0, 0.0, 1.0); }
        default: {}
    }
    if id == 6u + SC_NB {
        return normalize(p - SC_BALL.xyz);
    }
    var mins = SC_BOX_MIN;
    var maxs = SC_BOX_MAX;
    let lo = abs(p - mins[id - 6u]);
    let hi = abs(maxs[id - 6u] - p);
    var n = vec3<f32>(-1.0, 0.0, 0.0);
    var m = lo.x;
    if hi.x < m { m = hi.x; n = vec3<f32>(1.0, 0.0, 0.0); }
    if lo.y < m { m = lo.y; n = vec3<f32>(0.0, -1.0, 0.0); }
    if hi.y < m { m = hi.y; n = vec3<f32>(0.0, 1.0, 0.0); }
    if lo.z < m { m = lo.z; n = vec3<f32>(0.0, 0.0, -1.0); }
    if hi.z < m { m = hi.z; n = vec3<f32>(0.0, 0.0, 1.0); }
    return n;
}

// The face of the light's map that sees the offset q from the light (a spot: its
// one face; a cube: the major axis, faces +X, -X, +Y, -Y, +Z, -Z).
fn sc_face(q: vec3<f32>) -> u32 {
    if SC_FACES == 1u {
        return 0u;
    }
    let a = abs(q);
    if a.x >= a.y && a.x >= a.z {
        return select(1u, 0u, q.x > 0.0);
    }
    if a.y >= a.z {
        return select(3u, 2u, q.y > 0.0);
    }
    return select(5u, 4u, q.z > 0.0);
}

// The clip position of p on face f: (X, -Y, depth, Z) for the face's rows
// (X, Y, Z) = M (p - light), so that texel row 0 is Y/Z = -1 as the walk reads
// it; depth 0 ... 1 from the near to the far plane.
fn sc_face_clip(p: vec3<f32>, f: u32) -> vec4<f32> {
    var rows = SC_FACE_ROWS;
    let m = rows[f];
    let q = p - SC_LIGHT;
    let z = dot(m[2], q);
    return vec4<f32>(dot(m[0], q), -dot(m[1], q), SC_L_A * z - SC_L_B, z);
}

// The light's visibility at p from the shadow map (2x2 PCF by the comparison
// sampler); 1 outside the map (outside the cone too).
fn sc_shadow(p: vec3<f32>) -> f32 {
    let f = sc_face(p - SC_LIGHT);
    let c = sc_face_clip(p, f);
    if c.w <= 0.0 {
        return 1.0;
    }
    let n = c.xyz / c.w;
    let uv = vec2<f32>(0.5 * n.x + 0.5, 0.5 - 0.5 * n.y);
    if any(uv < vec2<f32>(0.0)) || any(uv > vec2<f32>(1.0)) || n.z > 1.0 {
        return 1.0;
    }
    return textureSampleCompareLevel(sc_shadow_map, sc_shadow_cmp, uv, i32(f), n.z);
}

// The smooth cone's weight (linear in the cosine between the two cut-offs); 1 for
// a point light.
fn sc_cone(to_point: vec3<f32>) -> f32 {
    if !SC_SPOT {
        return 1.0;
    }
    let c = dot(normalize(to_point), SC_AXIS);
    return clamp((c - SC_COS_OUTER) / (SC_COS_INNER - SC_COS_OUTER), 0.0, 1.0);
}

// The stretch [a, b] of the view ray o + t d (|d| = 1), t in [0, end], inside the
// spot's outer cone widened by SC_CLIP_MARGIN (the cone's weight is 0 outside
// it, so the exact walk need not look there); a > b: none. A point light, or a
// ray the quadric cannot decide in f32 (nearly parallel to the cone's side),
// keeps the whole [0, end]. The cone is convex, so one stretch.
fn sc_cone_clip(o: vec3<f32>, d: vec3<f32>, end: f32) -> vec2<f32> {
    let all = vec2<f32>(0.0, end);
    if !SC_SPOT {
        return all;
    }
    let w = o - SC_LIGHT;
    let c2 = SC_COS_CLIP * SC_COS_CLIP;
    let da = dot(d, SC_AXIS);
    let wa = dot(w, SC_AXIS);
    let qa = da * da - c2;
    let qb = da * wa - c2 * dot(d, w);
    let qc = wa * wa - c2 * dot(w, w);
    if abs(qa) < 1e-4 {
        return all;
    }
    let disc = qb * qb - qa * qc;
    if disc < 0.0 {
        // No real crossing: inside everywhere (qa > 0, only by rounding) or nowhere.
        return select(vec2<f32>(1.0, 0.0), all, qa > 0.0);
    }
    let q = -(qb + select(-1.0, 1.0, qb >= 0.0) * sqrt(disc));
    let ra = q / qa;
    let rb = select(qc / q, ra, q == 0.0);
    let r1 = min(ra, rb);
    let r2 = max(ra, rb);
    var lo: f32;
    var hi: f32;
    if qa < 0.0 {
        // Inside between the roots: the light's nappe if its middle faces the axis.
        if wa + 0.5 * (r1 + r2) * da < 0.0 {
            return vec2<f32>(1.0, 0.0);
        }
        lo = r1;
        hi = r2;
    } else if da > 0.0 {
        lo = r2;
        hi = 3.4e38;
    } else {
        lo = -3.4e38;
        hi = r1;
    }
    return vec2<f32>(max(lo, 0.0), min(hi, end));
}

// Where a view ray's fog ends, for its surface at `end` (point p, normal n): the
// surface, or, where it faces away from the light, SC_END_TEXELS of the map's
// texels short of it (scene.rs, END_TEXELS): the ray is in the surface's own
// shadow there, which the map cannot resolve near the surface's outline.
fn sc_fog_end(end: f32, p: vec3<f32>, n: vec3<f32>, dir: vec3<f32>) -> f32 {
    let tl = SC_LIGHT - p;
    let dl = length(tl);
    if !(dot(n, tl) < 0.0) || !(dl > 0.0) {
        return end;
    }
    let foot = SC_END_TEXELS * 2.0 * dl / SC_MAP_RES;
    return max(end - foot / max(length(cross(dir, tl / dl)), 0.05), 0.0);
}

fn sc_dir(pos: vec2<f32>) -> vec3<f32> {
    let u = 2.0 * pos.x / SC_WIDTH - 1.0;
    let v = 1.0 - 2.0 * pos.y / SC_HEIGHT;
    let t = tan(SC_HALF_FOV);
    let a = SC_WIDTH / SC_HEIGHT;
    let d = SC_CAM_F + (u * t * a) * SC_CAM_R + (v * t) * SC_CAM_U;
    return d / sqrt(dot(d, d));
}
