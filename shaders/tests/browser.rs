//! The generated GLSL ES 3.00 include in a real browser: headless Chromium
//! (Debian's `chromium`, WebGL2 on SwiftShader) runs a three.js page that draws
//! the harbour-fog scene through the include; every pixel must match the f64
//! reference render, tone-mapped the same way, within the kernel's declared
//! bound (plus the f32 allowance) and 8-bit quantisation. Skipped loudly without
//! a browser, unless `AIRLIGHT_REQUIRE_GPU=1` (CI) or `AIRLIGHT_REQUIRE_BROWSER=1`.

use airlight_fit::vocab::f32_limit;
use airlight_shaders::{browser, gate, render};
use std::path::Path;

fn required() -> bool {
    ["AIRLIGHT_REQUIRE_GPU", "AIRLIGHT_REQUIRE_BROWSER"].iter().any(|v| std::env::var(v).is_ok_and(|x| x == "1"))
}

#[test]
fn harbour_fog_in_three_js_matches_the_reference_render() {
    let Some(chrome) = browser::chromium() else {
        assert!(!required(), "AIRLIGHT_REQUIRE_GPU/BROWSER=1 but no chromium: install Debian's chromium (see README)");
        eprintln!("SKIPPED harbour_fog_in_three_js: no chromium (install Debian's chromium; AIRLIGHT_REQUIRE_BROWSER=1 makes this a failure)");
        return;
    };
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let generated = root.join("generated");
    let index = gate::load_index(&generated).unwrap();
    let k = index.get("scene-harbour-fog").unwrap();
    let models = airlight_fit::catalog::load(&generated.join("coefficients")).unwrap();
    let bound = f32_limit(gate::declared_max(k, &models).unwrap());
    let glsl = std::fs::read_to_string(generated.join(k.glsl.as_ref().unwrap())).unwrap();
    // codegen/scenes/harbour-fog.toml: σt up to 0.03 /m, lights up to 400 m.
    let view = render::View::for_scene(k, 0.03, 400.0, 48, 40);
    let (w, h) = (view.width(), view.height);
    let reference = render::render_reference(k, &view);
    let exposure = render::exposure(&reference);
    let page = browser::page(&browser::fragment_shader(k, &glsl, &view, exposure), w, h);
    let vendor = root.join(format!("tests/browser/vendor/three-{}", browser::THREE_VERSION));
    let drawn = browser::draw(&chrome, browser::page_files(&vendor, page).unwrap(), w, h)
        .unwrap_or_else(|e| panic!("the three.js page: {e}"));
    eprintln!("harbour_fog_in_three_js: {}", drawn.adapter);
    assert!(drawn.adapter.contains("WebGL 2"), "{}", drawn.adapter);
    let mut worst = (0.0f64, 0usize);
    let mut lit = 0;
    for (i, (&got, &r)) in drawn.pixels.iter().zip(&reference).enumerate() {
        let want = 255.0 * render::tone(r, exposure);
        let lo = 255.0 * render::tone(r * (1.0 - bound), exposure) - 1.0;
        let hi = 255.0 * render::tone(r * (1.0 + bound), exposure) + 1.0;
        let g = f64::from(got);
        assert!(
            (lo..=hi).contains(&g),
            "pixel ({}, {}): {got}, the reference {want:.2} (allowed {lo:.2}..{hi:.2} for the bound {bound:.2e})",
            i as u32 % w,
            i as u32 / w
        );
        if (g - want).abs() > worst.0 {
            worst = ((g - want).abs(), i);
        }
        lit += usize::from(got > 64);
    }
    eprintln!(
        "harbour_fog_in_three_js: {} pixels, worst {:.2} levels off the reference at ({}, {}), {lit} above 64",
        w * h,
        worst.0,
        worst.1 as u32 % w,
        worst.1 as u32 / w
    );
    assert!(lit > 20, "the glow is drawn ({lit} pixels above 64 of 255)");
}
