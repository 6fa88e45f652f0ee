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
    let generated = generated_dir(root)?;
    let shown = scene_file.display().to_string();
    let text = std::fs::read_to_string(scene_file).map_err(|e| bad_input(format!("{shown}: cannot read: {e}")))?;
    let scene = airlight_codegen::scene::parse(&shown, &text).map_err(bad_input)?;
    let index = gate::load_index(&generated).map_err(|e| bad_input(e.to_string()))?;
    let name = format!("scene-{}", scene.name);
    let k = index.get(&name).map_err(|e| bad_input(format!("{shown}: {e} (run `airlight generate`)")))?;
    let wgsl = k.wgsl.as_ref().ok_or_else(|| bad_input(format!("{shown}: the scene has no wgsl target")))?;
    let kernel = std::fs::read_to_string(generated.join(wgsl))
        .map_err(|e| Failure(1, format!("{}: cannot read: {e}", generated.join(wgsl).display())))?;
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
    let rk = kernels.iter().find(|rk| rk.name == name);
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

/// The light-shafts render of a scene with shadows (shaders/src/shafts/render/).
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
    if !scene.spot || f64::from(sr::SIGMA_T) > scene.sigma_t.1 || scene.sigma_t.0 > 0.0 {
        return Err(bad_input(format!(
            "{}: the shafts render draws a spot light in σt up to {} (and from 0): the scene must allow both",
            scene.file,
            sr::SIGMA_T
        )));
    }
    let march = index.get(sr::march_kernel()).map_err(bad_input)?;
    let march_path = generated.join(march.wgsl.as_deref().unwrap_or_default());
    let march_text = std::fs::read_to_string(&march_path)
        .map_err(|e| Failure(1, format!("{}: cannot read: {e}", march_path.display())))?;
    let gpu = Gpu::open().map_err(|e| Failure(1, e.to_string()))?;
    println!("adapter: {}", gpu.adapter());
    let view = sr::ShaftsView { width: size.0, height: size.1 };
    let fail = |e: airlight_shaders::GpuError| Failure(1, format!("{}: {e}", k.name));
    let acc = gpu.shafts_frame(k, kernel, &view, Method::Accumulator(sr::LOOK_UPS), sr::REPEATS).map_err(fail)?;
    println!(
        "accumulator, {} look-ups and {} bisection steps per change: {:.1} ms GPU",
        sr::LOOK_UPS,
        sr::REFINE_STEPS,
        acc.gpu_s * 1e3
    );
    let mut marches = Vec::new();
    for n in sr::MARCH_STEPS {
        let f = gpu.shafts_frame(march, &march_text, &view, Method::March(n), sr::REPEATS).map_err(fail)?;
        println!("march, {n} steps: {:.1} ms GPU", f.gpu_s * 1e3);
        marches.push(f);
    }
    println!("reference: exact lit intervals, {}×{} pixels …", size.0, size.1);
    let (fog, color) = sr::reference(&view, &acc);
    let classes = sr::classify(&view, &fog);
    let shown = sr::nearest_in_time(&acc, &marches).ok_or_else(|| Failure(1, "no march frame".into()))?;
    let exposure = render::exposure(&render::channels(&color));
    let rgb = |f: &sr::Frame| f.color.iter().map(|p| [0, 1, 2].map(|c| f64::from(p[c]))).collect::<Vec<_>>();
    std::fs::create_dir_all(&out.dir).map_err(|e| Failure(1, format!("{}: {e}", out.dir.display())))?;
    let png = |suffix: &str, pixels: &[[u8; 3]]| -> Result<PathBuf, Failure> {
        let path = out.dir.join(format!("{}{suffix}.png", out.base));
        render::write_png(&path, size.0, size.1, pixels).map_err(|e| Failure(1, e))?;
        Ok(path)
    };
    let first = png(if out.report { "-accumulator" } else { "" }, &render::tone_map_rgb(&rgb(&acc), exposure))?;
    png("-march", &render::tone_map_rgb(&rgb(shown), exposure))?;
    png("-reference", &render::tone_map_rgb(&color, exposure))?;
    png("-diff", &sr::difference(&acc, &fog, &classes))?;
    png("-diff-march", &sr::difference(shown, &fog, &classes))?;
    let lit = classes.iter().filter(|c| **c == Some(false)).count();
    let edges = classes.iter().filter(|c| **c == Some(true)).count();
    println!("{}: {}×{}; {lit} lit pixels off the edges, {edges} on shaft edges", first.display(), size.0, size.1);
    let row = |f: &sr::Frame| frame_row(f, &fog, &classes);
    let mut toml = format!(
        "# Written by `airlight render --scene {} --report`; quoted by REPORT.md.\nkind = \"shafts\"\nkernel = \"{}\"\nmarch_kernel = \"{}\"\nadapter = \"{}\"\nwidth = {}\nheight = {}\nshadow_map = {}\nrefine_steps = {}\nlit_pixels = {lit}\nedge_pixels = {edges}\nmarch_shown = {}\n\n[accumulator]\n{}",
        out.file,
        k.name,
        sr::march_kernel(),
        gpu.adapter().to_string().replace('"', "'"),
        size.0,
        size.1,
        sr::SHADOW_MAP,
        sr::REFINE_STEPS,
        shown.method.steps(),
        row(&acc)
    );
    for f in &marches {
        toml.push_str(&format!("\n[[march]]\n{}", row(f)));
    }
    if out.report {
        airlight_truth::io::write_atomic(&out.dir.join(format!("{}.toml", out.base)), toml.as_bytes())
            .map_err(|e| Failure(1, format!("{}: {e}", out.dir.display())))?;
        println!("wrote {}/{}*; `airlight generate` puts them into REPORT.md", out.dir.display(), out.base);
    }
    Ok(())
}

/// A frame's fog errors against the reference: printed, and its table in the
/// render's TOML record.
fn frame_row(f: &airlight_shaders::shafts::render::Frame, fog: &[[f64; 3]], classes: &[Option<bool>]) -> String {
    let e = airlight_shaders::shafts::render::fog_errors(f, fog, classes);
    println!(
        "{:?}: {:.1} ms GPU; fog error lit max {:.2e} mean {:.2e}, edges max {:.2e} mean {:.2e}",
        f.method,
        f.gpu_s * 1e3,
        e.lit_max,
        e.lit_mean,
        e.edge_max,
        e.edge_mean
    );
    format!(
        "steps = {}\ngpu_ms = {:e}\nlit_max = {:e}\nlit_mean = {:e}\nedge_max = {:e}\nedge_mean = {:e}\n",
        f.method.steps(),
        f.gpu_s * 1e3,
        e.lit_max,
        e.lit_mean,
        e.edge_max,
        e.edge_mean
    )
}
