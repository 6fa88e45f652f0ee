//! `airlight render`: a scene's kernel drawn on the GPU adapter beside the
//! reference (and the Rust kernel), written as PNGs.

use crate::workspace::generated_dir;
use crate::{bad_input, Failure};
use airlight_shaders::{gate, Gpu};
use airlight_shapes::vocab::CompiledKernel;
use std::path::{Path, PathBuf};

pub(crate) fn render_scene(
    scene_file: &Path,
    output: Option<&Path>,
    report: bool,
    width: Option<u32>,
    height: Option<u32>,
    root: Option<PathBuf>,
    kernels: &[CompiledKernel],
) -> Result<(), Failure> {
    use airlight_shaders::render;
    let generated = generated_dir(root.clone())?;
    let shown = scene_file.display().to_string();
    // The file as given is planned and its kernel rendered here, so that an
    // edited copy draws its own kernel, not a generated one of the same name.
    let (scene, planned) = crate::plan::plan_file(scene_file, root)?;
    let index = gate::load_index(&generated).map_err(|e| bad_input(e.to_string()))?;
    let k = &planned.index;
    let name = k.name.clone();
    let source = |path: &Option<String>| {
        path.as_ref().and_then(|p| planned.files.iter().find(|o| &o.path == p)).map(|o| o.contents.clone())
    };
    let kernel = source(&k.wgsl)
        .map(|b| String::from_utf8_lossy(&b).into_owned())
        .ok_or_else(|| bad_input(format!("{shown}: the scene has no wgsl target")))?;
    // The linked Rust kernel draws the CPU panel only if it is this plan's: the
    // generated module this binary was built from holds the same source.
    let linked_is_current = match (source(&k.rust), &k.rust) {
        (Some(planned), Some(p)) => std::fs::read(generated.join(p)).ok().as_deref() == Some(&planned[..]),
        _ => false,
    };
    let (width, height) = match scene.shadows {
        true => (width.unwrap_or(640), height.unwrap_or(360)),
        false => (width.unwrap_or(320), height.unwrap_or(240)),
    };
    if width == 0 || height == 0 || width > 4096 || height > 4096 {
        return Err(bad_input("--width and --height must be between 1 and 4096"));
    }
    let (base, dir) = match (output, report) {
        (_, true) => (scene.name.clone(), generated.join("render")),
        (Some(o), false) => (
            o.file_stem().map_or("render".into(), |s| s.to_string_lossy().into_owned()),
            o.parent().map_or(PathBuf::from("."), Path::to_path_buf),
        ),
        (None, false) => return Err(bad_input("name the image with -o OUT.png, or pass --report")),
    };
    if scene.shadows {
        let out = Out { dir, base, report, file: scene.file.clone() };
        return render_shafts(&generated, &index, k, &kernel, &scene, render::ShaftsSize(width, height), &out);
    }
    let gpu = Gpu::open().map_err(|e| Failure(1, e.to_string()))?;
    println!("adapter: {}", gpu.adapter());
    let view = render::View::for_scene(k, scene.sigma_t.1, scene.max_distance, width, height);
    let rk = kernels.iter().find(|rk| rk.name == name && linked_is_current);
    if rk.is_none() {
        println!("no Rust panel: the linked Rust kernels do not hold `{name}` as {shown} plans it (`airlight generate` for a scene of codegen/scenes/, then rebuild)");
    }
    let images = render::Images::draw(&gpu, k, &kernel, &view, scene.spot, rk)
        .map_err(|e| Failure(1, format!("{name}: {e}")))?;
    let w = view.width();
    std::fs::create_dir_all(&dir).map_err(|e| Failure(1, format!("{}: {e}", dir.display())))?;
    let png = |suffix: &str, pixels: &[[u8; 3]]| -> Result<PathBuf, Failure> {
        let path = dir.join(format!("{base}{suffix}.png"));
        render::write_png(&path, w, height, pixels).map_err(|e| Failure(1, e))?;
        Ok(path)
    };
    let gpu_png = png(if report { "-gpu" } else { "" }, &images.gpu)?;
    png("-reference", &images.reference)?;
    png("-diff", &images.diff)?;
    let (gmax, gmean) = images.gpu_err;
    println!("{}: {w}×{height}, σt = {:?}", gpu_png.display(), view.sigma_t);
    println!("GPU (WGSL) vs reference: max relative error {gmax:.2e}, mean {gmean:.2e}");
    let mut summary = vec![
        ("adapter".to_string(), format!("\"{}\"", gpu.adapter().to_string().replace('"', "'"))),
        ("gpu_max_rel".into(), format!("{gmax:e}")),
        ("gpu_mean_rel".into(), format!("{gmean:e}")),
    ];
    if let Some((pixels, (rmax, rmean))) = &images.rust {
        png("-rust", pixels)?;
        println!("Rust kernel (CPU) vs reference: max relative error {rmax:.2e}, mean {rmean:.2e}");
        summary.push(("rust_max_rel".into(), format!("{rmax:e}")));
        summary.push(("rust_mean_rel".into(), format!("{rmean:e}")));
    }
    if report {
        let mut toml = format!(
            "# Written by `airlight render --scene {} --report`; quoted by REPORT.md.\nkernel = \"{name}\"\nwidth = {w}\nheight = {height}\nsigma_t = {:?}\n",
            scene.file, view.sigma_t
        );
        for (k, v) in summary {
            toml.push_str(&format!("{k} = {v}\n"));
        }
        airlight_truth::io::write_atomic(&dir.join(format!("{base}.toml")), toml.as_bytes())
            .map_err(|e| Failure(1, format!("{}: {e}", dir.display())))?;
        println!("wrote {}/{base}*; `airlight generate` puts them into REPORT.md", dir.display());
    }
    Ok(())
}

/// Where a render's files go.
struct Out {
    dir: PathBuf,
    base: String,
    report: bool,
    file: String,
}

/// The light-shafts render of a scene with shadows (shaders/src/shafts/render/):
/// the exact walk's frame, the sampled accumulator's, the marches', each against
/// the reference over the analytic occluders' exact lit intervals.
fn render_shafts(
    generated: &Path,
    index: &airlight_shapes::vocab::Index,
    k: &airlight_shapes::vocab::IndexEntry,
    kernel: &str,
    scene: &airlight_codegen::scene::Scene,
    size: airlight_shaders::render::ShaftsSize,
    out: &Out,
) -> Result<(), Failure> {
    use airlight_shaders::render;
    use airlight_shaders::shafts::render::{self as sr, Method};
    let stage = sr::Stage::named(&scene.name).ok_or_else(|| {
        bad_input(format!(
            "{}: the shafts render draws the stages `window-shafts` and `street-lamp` (shaders/src/shafts/render/scene.rs); `{}` is neither",
            scene.file, scene.name
        ))
    })?;
    let sigma = stage.sigma_t.iter().copied().fold(0.0f32, f32::max);
    if scene.spot != stage.spot.is_some() || f64::from(sigma) > scene.sigma_t.1 || scene.sigma_t.0 > 0.0 {
        return Err(bad_input(format!(
            "{}: the `{}` stage draws a {} light in σt from 0 up to {sigma}: the scene must allow both",
            scene.file,
            stage.name,
            if stage.spot.is_some() { "spot" } else { "point" }
        )));
    }
    if stage.g < k.g[0] as f32 || stage.g > k.g[1] as f32 {
        return Err(bad_input(format!(
            "{}: the stage's g = {} is outside the kernel's {:?}",
            scene.file, stage.g, k.g
        )));
    }
    let march = index.get(sr::march_kernel()).map_err(bad_input)?;
    let march_path = generated.join(march.wgsl.as_deref().unwrap_or_default());
    let march_text = std::fs::read_to_string(&march_path)
        .map_err(|e| Failure(1, format!("{}: cannot read: {e}", march_path.display())))?;
    let texts = airlight_shaders::shafts::WalkTexts::load(generated).map_err(|e| Failure(1, e.to_string()))?;
    let src = texts.sources();
    let walk = sr::WalkWgsl { walk: src.wgsl, pyramid: src.pyramid };
    let gpu = Gpu::open().map_err(|e| Failure(1, e.to_string()))?;
    println!("adapter: {}", gpu.adapter());
    let view = sr::ShaftsView { width: size.0, height: size.1 };
    let fail = |e: airlight_shaders::GpuError| Failure(1, format!("{}: {e}", k.name));
    let mut frames = Vec::new();
    let exact = gpu.shafts_frame(&stage, k, kernel, walk, &view, Method::Exact, sr::REPEATS).map_err(fail)?;
    println!(
        "exact walk of the {0}² shadow map: {1:.1} ms GPU (+ {2:.2} ms for its pyramid)",
        stage.shadow_map,
        exact.gpu_s * 1e3,
        exact.pyramid_s * 1e3
    );
    let walk_only = gpu.shafts_frame(&stage, k, kernel, walk, &view, Method::Walk, sr::REPEATS).map_err(fail)?;
    println!("of which the walk alone (its runs summed, no kernel): {:.1} ms GPU", walk_only.gpu_s * 1e3);
    let counts = sr::WalkCounts::of(&walk_only).ok_or_else(|| Failure(1, "the walk frame has no counts".into()))?;
    println!(
        "the walk over {} rays: {:.1} steps on average (90th percentile {}, max {}), {:.2} lit runs",
        counts.walked, counts.steps_mean, counts.steps_p90, counts.steps_max, counts.runs_mean
    );
    for n in sr::SAMPLED {
        let f = gpu.shafts_frame(&stage, k, kernel, walk, &view, Method::Sampled(n), sr::REPEATS).map_err(fail)?;
        println!(
            "sampled accumulator, {n} look-ups, {} bisection steps per change: {:.1} ms GPU",
            sr::REFINE_STEPS,
            f.gpu_s * 1e3
        );
        frames.push(f);
    }
    let mut marches = Vec::new();
    for n in sr::MARCH_STEPS {
        let f =
            gpu.shafts_frame(&stage, march, &march_text, walk, &view, Method::March(n), sr::REPEATS).map_err(fail)?;
        println!("march, {n} steps: {:.1} ms GPU", f.gpu_s * 1e3);
        marches.push(f);
    }
    println!("reference: exact lit intervals among the analytic occluders, {}×{} pixels …", size.0, size.1);
    let (fog, color) = sr::reference(&stage, &view, &exact);
    let classes = sr::classify(&view, &fog);
    let shown = sr::nearest_in_time(&exact, &marches).ok_or_else(|| Failure(1, "no march frame".into()))?;
    let sampled = frames.last().ok_or_else(|| Failure(1, "no sampled frame".into()))?;
    let exposure = render::exposure(&render::channels(&color));
    let rgb = |f: &sr::Frame| f.color.iter().map(|p| [0, 1, 2].map(|c| f64::from(p[c]))).collect::<Vec<_>>();
    std::fs::create_dir_all(&out.dir).map_err(|e| Failure(1, format!("{}: {e}", out.dir.display())))?;
    let png = |suffix: &str, pixels: &[[u8; 3]]| -> Result<PathBuf, Failure> {
        let path = out.dir.join(format!("{}{suffix}.png", out.base));
        render::write_png(&path, size.0, size.1, pixels).map_err(|e| Failure(1, e))?;
        Ok(path)
    };
    let first = png(if out.report { "-exact" } else { "" }, &render::tone_map_rgb(&rgb(&exact), exposure))?;
    png("-accumulator", &render::tone_map_rgb(&rgb(sampled), exposure))?;
    png("-march", &render::tone_map_rgb(&rgb(shown), exposure))?;
    png("-reference", &render::tone_map_rgb(&color, exposure))?;
    png("-diff-exact", &sr::difference(&exact, &fog, &classes))?;
    png("-diff", &sr::difference(sampled, &fog, &classes))?;
    png("-diff-march", &sr::difference(shown, &fog, &classes))?;
    let lit = classes.iter().filter(|c| **c == Some(false)).count();
    let edges = classes.iter().filter(|c| **c == Some(true)).count();
    println!("{}: {}×{}; {lit} lit pixels off the edges, {edges} on shaft edges", first.display(), size.0, size.1);
    let mut toml = format!(
        "# Written by `airlight render --scene {} --report`; quoted by REPORT.md.\nkind = \"shafts\"\ndescription = \"{}\"\nlight = \"{}\"\nkernel = \"{}\"\nmarch_kernel = \"{}\"\nadapter = \"{}\"\nwidth = {}\nheight = {}\nshadow_map = {}\nfaces = {}\nwalk_bias = {:?}\nend_texels = {:?}\nclip_margin_deg = {:?}\nwalk_ms = {:e}\nwalked_pixels = {}\nwalk_steps_mean = {:e}\nwalk_steps_p90 = {:e}\nwalk_steps_max = {:e}\nwalk_runs_mean = {:e}\nrefine_steps = {}\nlit_pixels = {lit}\nedge_pixels = {edges}\nmarch_shown = {}\nsampled_shown = {}\n",
        out.file,
        stage.description,
        if stage.spot.is_some() { "spot" } else { "point" },
        k.name,
        sr::march_kernel(),
        gpu.adapter().to_string().replace('"', "'"),
        size.0,
        size.1,
        stage.shadow_map,
        stage.faces().len(),
        sr::WALK_BIAS,
        sr::END_TEXELS,
        sr::CLIP_MARGIN_DEG,
        walk_only.gpu_s * 1e3,
        counts.walked,
        counts.steps_mean,
        counts.steps_p90,
        counts.steps_max,
        counts.runs_mean,
        sr::REFINE_STEPS,
        shown.method.steps(),
        sampled.method.steps(),
    );
    for f in std::iter::once(&exact).chain(&frames).chain(&marches) {
        toml.push_str(&format!("\n[[frame]]\n{}", frame_row(f, &fog, &classes)));
    }
    if out.report {
        airlight_truth::io::write_atomic(&out.dir.join(format!("{}.toml", out.base)), toml.as_bytes())
            .map_err(|e| Failure(1, format!("{}: {e}", out.dir.display())))?;
        println!("wrote {}/{}*; `airlight generate` puts them into REPORT.md", out.dir.display(), out.base);
    }
    Ok(())
}

/// A frame's fog errors and leaks against the reference: printed, and its
/// table in the render's TOML record.
fn frame_row(f: &airlight_shaders::shafts::render::Frame, fog: &[[f64; 3]], classes: &[Option<bool>]) -> String {
    use airlight_shaders::shafts::render as sr;
    let e = sr::fog_errors(f, fog, classes);
    let leaks = sr::leak_pixels(f, fog);
    println!(
        "{} {}: {:.1} ms GPU (+ {:.2} ms pyramid); fog error lit max {:.2e} mean {:.2e}, edges max {:.2e} mean {:.2e}; {leaks} leak pixels",
        f.method.name(),
        f.method.steps(),
        f.gpu_s * 1e3,
        f.pyramid_s * 1e3,
        e.lit_max,
        e.lit_mean,
        e.edge_max,
        e.edge_mean
    );
    format!(
        "method = \"{}\"\nsteps = {}\ngpu_ms = {:e}\npyramid_ms = {:e}\nlit_max = {:e}\nlit_mean = {:e}\nedge_max = {:e}\nedge_mean = {:e}\nleak_pixels = {leaks}\n",
        f.method.name(),
        f.method.steps(),
        f.gpu_s * 1e3,
        f.pyramid_s * 1e3,
        e.lit_max,
        e.lit_mean,
        e.edge_max,
        e.edge_mean
    )
}
