Fn(() => {
    const pw = float({{pw_dbg}}), h = float({{h_dbg}});
    // screenCoordinate: pixels from the top left, on both backends.
    const pos = screenCoordinate.xy;
    const panel = floor(pos.x.div(pw));
    const u = pos.x.sub(panel.mul(pw)).div(pw).mul(2.0).sub(1.0);
    const v = float(1.0).sub(pos.y.mul(2.0).div(h));
    const t = float({{t_dbg}});
    const d = vec3(u.mul(t.mul(pw.div(h))), v.mul(t), 1.0);
    const dir = d.div(sqrt(dot(d, d)));
    const surface = {{ground}};
    const sigmaT = {{sigma}};
    let sum = float(0.0);
    for (const l of [{{lights}}]) {
        sum = sum.add({{node}}({ {{args}} }));
    }
    const x = max(sum.mul({{exposure_dbg}}), 0.0);
    const c = pow(x.div(x.add(1.0)), 1.0 / 2.2);
    return vec4(c, c, c, 1.0);
})()