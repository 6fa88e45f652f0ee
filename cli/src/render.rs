//! `airlight render`: a scene's kernel drawn on the GPU adapter beside the
//! reference (and the Rust kernel), written as PNGs.

use crate::workspace::generated_dir;
use crate::{bad_input, Failure};
use airlight_fit::vocab::CompiledKernel;
use airlight_shaders::{gate, Gpu};
use std::path::{Path, PathBuf};

pub(crate) fn render_scene(
    scene_file: &Path,
    output: Option<&Path>,
    report: bool,
    width: u32,
    height: u32,
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
        airlight_fit::io::write_atomic(&dir.join(format!("{base}.toml")), toml.as_bytes())
            .map_err(|e| Failure(1, format!("{}: {e}", dir.display())))?;
        println!("wrote {}/{base}*; `airlight generate` puts them into REPORT.md", dir.display());
    }
    Ok(())
}
