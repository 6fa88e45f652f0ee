//! `airlight eval`: points, rays or spot rays from a CSV through an f64 model,
//! a compiled f32 kernel, or a shader kernel on the GPU adapter.

use crate::workspace::{generated_dir, registry};
use crate::{bad_input, EvalEntry, Failure};
use airlight_shaders::{gate, Gpu, KernelSource, Ray, SpotRay};
use airlight_shapes::vocab::{CompiledKernel, Target};
use airlight_truth::points_csv;
use std::path::{Path, PathBuf};

/// `eval` on the CPU: the f64 model, or the compiled Rust kernel of that name
/// when `kernels` are given.
pub(crate) fn eval(
    model: &str,
    input: &Path,
    output: Option<&Path>,
    kernels: Option<&[CompiledKernel]>,
    entry_kind: EvalEntry,
    root: Option<PathBuf>,
) -> Result<(), Failure> {
    match kernels {
        None => eval_model(model, input, output, entry_kind, root),
        Some(ks) => eval_compiled(compiled(ks, model)?, input, output, entry_kind, root),
    }
}

/// `eval --precision f32`: a compiled Rust kernel, which checks the input
/// against what it takes (its index entry).
fn eval_compiled(
    k: &CompiledKernel,
    input: &Path,
    output: Option<&Path>,
    entry_kind: EvalEntry,
    root: Option<PathBuf>,
) -> Result<(), Failure> {
    let index = gate::load_index(&generated_dir(root)?).map_err(|e| bad_input(e.to_string()))?;
    let entry = index.get(k.name).map_err(bad_input)?;
    match entry_kind {
        EvalEntry::Shadowed => Err(bad_input("--entry shadowed goes through eval_shadowed")),
        EvalEntry::Spot => {
            if k.spot.is_none() {
                return Err(bad_input(format!("kernel '{}' has no spot entry", k.name)));
            }
            let rows = read_spots(input, &|r, g| entry.check_ray(r, g))?;
            points_csv::check_axes_f32(&input.display().to_string(), &rows).map_err(bad_input)?;
            let values: Vec<[f64; 3]> =
                rows.iter().map(|r| SpotRay::from_row(r).spot_of(k).unwrap_or([f32::NAN; 3]).map(f64::from)).collect();
            write_csv(output, &points_csv::render_spots(&rows, &values))
        }
        EvalEntry::Radiance => {
            let rows = read_rays(input, &|r, g| entry.check_ray(r, g))?;
            let values: Vec<f64> = rows.iter().map(|r| f64::from(Ray::from_row(r).radiance_of(k))).collect();
            write_csv(output, &points_csv::render_rays(&rows, &values))
        }
        EvalEntry::Airlight => {
            let rows = read_points(input, &|p| entry.check(p))?;
            points_csv::check_gamma_f32(&input.display().to_string(), &rows).map_err(bad_input)?;
            let values: Vec<f64> = rows.iter().map(|r| airlight_shaders::f32_value(k, r.point)).collect();
            write_csv(output, &points_csv::render(&rows, &values))
        }
    }
}

/// A model the registry does not know. Outside the repository only the
/// reference is known: the message says why first (every entry says it alike).
pub(crate) fn unknown_model(model: &str, e: impl std::fmt::Display, root: &Option<PathBuf>) -> Failure {
    let found = root.clone().or_else(|| crate::workspace::find_root().ok());
    match found {
        None if model != "reference" => bad_input(format!(
            "no generated/coefficients found above the current directory (run inside the repository or pass --root), so {e}"
        )),
        _ => bad_input(e),
    }
}

/// `eval` through an f64 model (or the reference), which checks the input
/// against its `g` range and domain.
fn eval_model(
    model: &str,
    input: &Path,
    output: Option<&Path>,
    entry_kind: EvalEntry,
    root: Option<PathBuf>,
) -> Result<(), Failure> {
    let (reg, _) = registry(root.clone())?;
    let m = reg.get(model).map_err(|e| unknown_model(model, e, &root))?;
    let g_ok = |_: &airlight_truth::geometry::PhysicalRay, g: f64| {
        m.check(&airlight_truth::reference::Point { tau: 0.0, gamma: 1.0, rho: f64::INFINITY, g })
            .map_err(|e| ("g", e.to_string()))
    };
    match entry_kind {
        EvalEntry::Shadowed => Err(bad_input("--entry shadowed goes through eval_shadowed")),
        EvalEntry::Spot => {
            let rows = read_spots(input, &g_ok)?;
            let values = airlight_truth::parallel::map(&rows, |r| r.radiance(&|p| m.eval_unchecked(p)), &|_, _| {});
            let mut out = Vec::with_capacity(rows.len());
            for (r, v) in rows.iter().zip(values) {
                out.push(v.map_err(|e| bad_input(format!("{}:{}: {e}", input.display(), r.line)))?);
            }
            write_csv(output, &points_csv::render_spots(&rows, &out))
        }
        EvalEntry::Radiance => {
            // The f64 model's g range, on the ray's g.
            let rows = read_rays(input, &g_ok)?;
            let values = airlight_truth::parallel::map(
                &rows,
                |r| r.ray.radiance(r.g, &|p| m.eval_unchecked(p)).unwrap_or(f64::NAN),
                &|_, _| {},
            );
            if let Some((r, _)) = rows.iter().zip(&values).find(|(_, v)| v.is_nan()) {
                let e = r.ray.radiance(r.g, &|_| 0.0).err().map(|e| e.to_string()).unwrap_or_default();
                return Err(bad_input(format!("{}:{}: {e}", input.display(), r.line)));
            }
            write_csv(output, &points_csv::render_rays(&rows, &values))
        }
        EvalEntry::Airlight => {
            // The f64 model checks the points (its g range).
            let rows = read_points(input, &|p| m.check(p))?;
            let values = airlight_truth::parallel::map(&rows, |r| m.eval_unchecked(r.point), &|_, _| {});
            write_csv(output, &points_csv::render(&rows, &values))
        }
    }
}

/// The points of an `eval` CSV, each checked by `check` (the f64 model's domain,
/// or what a generated kernel takes).
pub(crate) fn read_points(
    input: &Path,
    check: &dyn Fn(&airlight_truth::reference::Point) -> Result<(), airlight_truth::ParamError>,
) -> Result<Vec<points_csv::Row>, Failure> {
    let name = input.display().to_string();
    let text = read_text(input)?;
    points_csv::parse(&name, &text, check).map_err(bad_input)
}

/// The rays of an `eval --entry radiance` CSV, each checked by `check`.
pub(crate) fn read_rays(input: &Path, check: &points_csv::RayCheck) -> Result<Vec<points_csv::RayRow>, Failure> {
    let name = input.display().to_string();
    let text = read_text(input)?;
    points_csv::parse_rays(&name, &text, check).map_err(bad_input)
}

/// The text of an `eval` input: UTF-8, or an error naming the line of the first
/// byte that is not.
pub(crate) fn read_text(input: &Path) -> Result<String, Failure> {
    let name = input.display().to_string();
    let bytes = std::fs::read(input).map_err(|e| bad_input(format!("{name}: cannot read: {e}")))?;
    points_csv::decode(&name, bytes).map_err(bad_input)
}

/// Whether the header of `input` names the spot entry's cone (`cos_outer`): such
/// a file given to `--entry radiance` goes to the spot entry.
pub(crate) fn names_spot_columns(input: &Path) -> bool {
    std::fs::read_to_string(input).is_ok_and(|t| points_csv::names_spot_columns(&t))
}

/// The rays of an `eval --entry spot` CSV, each channel checked by `check`.
pub(crate) fn read_spots(input: &Path, check: &points_csv::RayCheck) -> Result<Vec<points_csv::SpotRow>, Failure> {
    let name = input.display().to_string();
    let text = read_text(input)?;
    points_csv::parse_spots(&name, &text, check).map_err(bad_input)
}

/// `eval --target wgsl|glsl`: the generated shader kernel on the GPU adapter.
pub(crate) fn eval_gpu(
    name: &str,
    input: &Path,
    output: Option<&Path>,
    language: Target,
    entry_kind: EvalEntry,
    root: Option<PathBuf>,
) -> Result<(), Failure> {
    let rays = entry_kind == EvalEntry::Radiance;
    let index = gate::load_index(&generated_dir(root.clone())?).map_err(|e| bad_input(e.to_string()))?;
    let k = index.get(name).map_err(bad_input)?;
    let (source, table, path) = shader_source(root, k, language)?;
    let src = KernelSource::of(k, language, &source).with_table(table.as_ref());
    if entry_kind == EvalEntry::Spot {
        if !k.has(airlight_shapes::vocab::Entry::Spot) {
            return Err(bad_input(format!("kernel '{name}' has no spot entry")));
        }
        let rows = read_spots(input, &|r, g| k.check_ray(r, g))?;
        points_csv::check_axes_f32(&input.display().to_string(), &rows).map_err(bad_input)?;
        let gpu = Gpu::open().map_err(|e| Failure(1, format!("{e}")))?;
        eprintln!("adapter: {}", gpu.adapter());
        let plain: Vec<airlight_shaders::SpotRay> = rows.iter().map(SpotRay::from_row).collect();
        let got = gpu.spot(&src, &plain).map_err(|e| Failure(1, format!("{}: {e}", path.display())))?;
        let values: Vec<[f64; 3]> = got.iter().map(|v| v.map(f64::from)).collect();
        return write_csv(output, &points_csv::render_spots(&rows, &values));
    }
    if rays {
        let rows = read_rays(input, &|r, g| k.check_ray(r, g))?;
        let gpu = Gpu::open().map_err(|e| Failure(1, format!("{e}")))?;
        eprintln!("adapter: {}", gpu.adapter());
        let plain: Vec<airlight_shaders::Ray> = rows.iter().map(Ray::from_row).collect();
        let got = gpu.radiance(&src, &plain).map_err(|e| Failure(1, format!("{}: {e}", path.display())))?;
        let values: Vec<f64> = got.iter().map(|&v| f64::from(v)).collect();
        return write_csv(output, &points_csv::render_rays(&rows, &values));
    }
    let rows = read_points(input, &|p| k.check(p))?;
    points_csv::check_gamma_f32(&input.display().to_string(), &rows).map_err(bad_input)?;
    let gpu = Gpu::open().map_err(|e| Failure(1, format!("{e}")))?;
    eprintln!("adapter: {}", gpu.adapter());
    let raw: Vec<[f64; 4]> = rows.iter().map(|r| [r.point.tau, r.point.gamma, r.point.rho, r.point.g]).collect();
    let got = gpu.airlight(&src, &raw).map_err(|e| Failure(1, format!("{}: {e}", path.display())))?;
    let values: Vec<f64> = got.iter().map(|&v| airlight_shaders::from_kernel(v)).collect();
    write_csv(output, &points_csv::render(&rows, &values))
}

/// Writes a CSV to `output` (atomically, through a symbolic link; `-` or none:
/// standard output, where a closed pipe ends the run quietly).
pub(crate) fn write_csv(output: Option<&Path>, csv: &str) -> Result<(), Failure> {
    match output {
        Some(path) if path != Path::new("-") => airlight_truth::io::write_atomic(path, csv.as_bytes()).map_err(|e| {
            // A special file named as the output is a usage error (2); a failing write, a runtime one (1).
            let code = if e.kind() == std::io::ErrorKind::InvalidInput { 2 } else { 1 };
            Failure(code, format!("{}: cannot write: {e}", path.display()))
        }),
        _ => {
            use std::io::Write;
            let mut out = std::io::stdout().lock();
            match out.write_all(csv.as_bytes()).and_then(|()| out.flush()) {
                Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
                    Err(Failure(1, format!("standard output: cannot write: {e}")))
                }
                _ => Ok(()),
            }
        }
    }
}

/// The compiled f32 kernel called `name`.
pub(crate) fn compiled<'k>(ks: &'k [CompiledKernel], name: &str) -> Result<&'k CompiledKernel, Failure> {
    ks.iter().find(|k| k.name == name).ok_or_else(|| {
        let known: Vec<&str> = ks.iter().map(|k| k.name).collect();
        bad_input(format!("no generated f32 kernel '{name}'; kernels: {}", known.join(", ")))
    })
}

/// A kernel's shader text in `language`, its table, and the file's path.
pub(crate) fn shader_source(
    root: Option<PathBuf>,
    k: &airlight_shapes::vocab::IndexEntry,
    language: Target,
) -> Result<(String, Option<airlight_shaders::Table>, PathBuf), Failure> {
    let generated = generated_dir(root)?;
    let file = k.file(language).ok_or_else(|| bad_input(format!("kernel '{}' has no {language} file", k.name)))?;
    let path = generated.join(file);
    let text =
        std::fs::read_to_string(&path).map_err(|e| Failure(1, format!("{}: cannot read: {e}", path.display())))?;
    let table = airlight_shaders::load_table(&generated, k).map_err(|e| Failure(1, e.to_string()))?;
    Ok((text, table, path))
}
