//! Shader and Rust kernels, rendered through tera: for each kernel (a
//! [`KernelSpec`]) and each row of the output table (`codegen/outputs.toml`),
//! the family's core template (`fit/src/family/<name>/core.<ext>.tera`) extends
//! the shared kernel template of the target (`codegen/templates/kernels/
//! kernel.<ext>.tera`: header, shared math, every entry point, written once).
//!
//! The generator names no family: the template, and what it is given, come from
//! the kernel's family through `airlight_fit::family`. Names, f32 literals and
//! every derived constant are computed in Rust; the templates only lay code out.

mod index;
mod outputs;
mod packages;
mod plan;
mod rust_crate;
pub mod spec;

pub use index::{index_entry_of, render_index};
pub use outputs::{FileOutput, KernelOutput, OutputTable, SharedFile, Translation, OUTPUT_TABLE};
pub use plan::render_plan;
pub use spec::{join_domains, specialisations, KernelPhase, KernelSpec, Measured, SPOT_EDGE_NODES, SPOT_EDGE_PIECES};

use crate::output::Output;
use airlight_shapes::template::{lit, lits, KernelView};
use airlight_shapes::vocab::{Arg, ArgType, Entry, Target};
pub use airlight_shapes::vocab::{Index, IndexEntry};
use std::f64::consts::PI;

/// The generator's own templates, by name: one kernel template per target (the
/// entry points), the spot entry and the shared math they include, the Rust
/// crate's files and the scene plan.
pub const TEMPLATES: [(&str, &str); 59] = [
    ("kernel.wgsl.tera", include_str!("../../templates/kernels/kernel.wgsl.tera")),
    ("kernel.glsl.tera", include_str!("../../templates/kernels/kernel.glsl.tera")),
    ("kernel.rs.tera", include_str!("../../templates/kernels/kernel.rs.tera")),
    ("spot.wgsl.tera", include_str!("../../templates/kernels/spot.wgsl.tera")),
    ("spot.glsl.tera", include_str!("../../templates/kernels/spot.glsl.tera")),
    ("spot.rs.tera", include_str!("../../templates/kernels/spot.rs.tera")),
    ("shafts/accumulator.wgsl.tera", include_str!("../../templates/kernels/shafts/accumulator.wgsl.tera")),
    ("shafts/accumulator.glsl.tera", include_str!("../../templates/kernels/shafts/accumulator.glsl.tera")),
    ("shafts/accumulator.rs.tera", include_str!("../../templates/kernels/shafts/accumulator.rs.tera")),
    ("shafts/shadowmap.wgsl.tera", include_str!("../../templates/kernels/shafts/shadowmap.wgsl.tera")),
    ("shafts/shadowmap.glsl.tera", include_str!("../../templates/kernels/shafts/shadowmap.glsl.tera")),
    ("shafts/shadowmap.rs.tera", include_str!("../../templates/kernels/shafts/shadowmap.rs.tera")),
    ("shafts/atlas.wgsl.tera", include_str!("../../templates/kernels/shafts/atlas.wgsl.tera")),
    ("shafts/atlas.glsl.tera", include_str!("../../templates/kernels/shafts/atlas.glsl.tera")),
    ("shafts/pyramid.wgsl.tera", include_str!("../../templates/kernels/shafts/pyramid.wgsl.tera")),
    ("shafts/pyramid.frag.glsl.tera", include_str!("../../templates/kernels/shafts/pyramid.frag.glsl.tera")),
    ("math.wgsl.tera", include_str!("../../templates/kernels/math.wgsl.tera")),
    ("math.glsl.tera", include_str!("../../templates/kernels/math.glsl.tera")),
    ("math.rs.tera", include_str!("../../templates/kernels/math.rs.tera")),
    ("u_interval.wgsl.tera", include_str!("../../templates/kernels/u_interval.wgsl.tera")),
    ("u_interval.glsl.tera", include_str!("../../templates/kernels/u_interval.glsl.tera")),
    ("u_interval.rs.tera", include_str!("../../templates/kernels/u_interval.rs.tera")),
    ("plan.md.tera", include_str!("../../templates/kernels/plan.md.tera")),
    ("Cargo.toml.tera", include_str!("../../templates/kernels/Cargo.toml.tera")),
    ("README.md.tera", include_str!("../../templates/kernels/README.md.tera")),
    ("lib.rs.tera", include_str!("../../templates/kernels/lib.rs.tera")),
    ("unity/shader_graph.hlsl.tera", include_str!("../../templates/packages/unity/shader_graph.hlsl.tera")),
    ("unity/package.json.tera", include_str!("../../templates/packages/unity/package.json.tera")),
    ("unity/README.md.tera", include_str!("../../templates/packages/unity/README.md.tera")),
    ("unreal/Airlight.uplugin.tera", include_str!("../../templates/packages/unreal/Airlight.uplugin.tera")),
    ("unreal/Build.cs.tera", include_str!("../../templates/packages/unreal/Build.cs.tera")),
    ("unreal/Module.cpp.tera", include_str!("../../templates/packages/unreal/Module.cpp.tera")),
    ("unreal/README.md.tera", include_str!("../../templates/packages/unreal/README.md.tera")),
    ("three/sources.js.tera", include_str!("../../templates/packages/three/sources.js.tera")),
    ("three/sources.d.ts.tera", include_str!("../../templates/packages/three/sources.d.ts.tera")),
    ("three/shadow.js.tera", include_str!("../../templates/packages/three/shadow.js.tera")),
    ("three/shadow.d.ts.tera", include_str!("../../templates/packages/three/shadow.d.ts.tera")),
    ("three/exact.wgsl.tera", include_str!("../../templates/packages/three/exact.wgsl.tera")),
    ("three/exact.glsl.tera", include_str!("../../templates/packages/three/exact.glsl.tera")),
    ("three/walk.js.tera", include_str!("../../templates/packages/three/walk.js.tera")),
    ("three/walk.d.ts.tera", include_str!("../../templates/packages/three/walk.d.ts.tera")),
    ("three/shadowmap.js.tera", include_str!("../../templates/packages/three/shadowmap.js.tera")),
    ("three/shadowmap.d.ts.tera", include_str!("../../templates/packages/three/shadowmap.d.ts.tera")),
    ("three/lights.js.tera", include_str!("../../templates/packages/three/lights.js.tera")),
    ("three/lights.d.ts.tera", include_str!("../../templates/packages/three/lights.d.ts.tera")),
    ("three/lightset.js.tera", include_str!("../../templates/packages/three/lightset.js.tera")),
    ("three/lightset.d.ts.tera", include_str!("../../templates/packages/three/lightset.d.ts.tera")),
    ("three/webgl.js.tera", include_str!("../../templates/packages/three/webgl.js.tera")),
    ("three/webgl.d.ts.tera", include_str!("../../templates/packages/three/webgl.d.ts.tera")),
    ("three/kernel.js.tera", include_str!("../../templates/packages/three/kernel.js.tera")),
    ("three/kernel.d.ts.tera", include_str!("../../templates/packages/three/kernel.d.ts.tera")),
    ("three/package.json.tera", include_str!("../../templates/packages/three/package.json.tera")),
    ("three/index.js.tera", include_str!("../../templates/packages/three/index.js.tera")),
    ("three/index.d.ts.tera", include_str!("../../templates/packages/three/index.d.ts.tera")),
    ("three/README.md.tera", include_str!("../../templates/packages/three/README.md.tera")),
    ("bevy/Cargo.toml.tera", include_str!("../../templates/packages/bevy/Cargo.toml.tera")),
    ("bevy/lib.rs.tera", include_str!("../../templates/packages/bevy/lib.rs.tera")),
    ("bevy/README.md.tera", include_str!("../../templates/packages/bevy/README.md.tera")),
    ("bevy/menu.rs.tera", include_str!("../../templates/packages/bevy/menu.rs.tera")),
];

/// The file extension of `target`'s templates.
fn ext(target: Target) -> &'static str {
    match target {
        Target::Wgsl => "wgsl",
        Target::Glsl => "glsl",
        Target::Rust => "rs",
    }
}

/// The name (and path under `fit/src/family/`) of a family's core template.
fn core_template(dir: &str, target: Target) -> String {
    format!("{dir}/core.{}.tera", ext(target))
}

/// Every template: the generator's and each family's core per target.
fn engine() -> Result<tera::Tera, tera::Error> {
    let mut t = tera::Tera::default();
    t.autoescape_on(vec![]);
    let mut all: Vec<(String, &str)> = TEMPLATES.iter().map(|&(n, s)| (n.to_string(), s)).collect();
    for (dir, templates) in airlight_fit::family::all_templates() {
        for target in Target::ALL {
            all.push((core_template(dir, target), templates.get(target)));
        }
    }
    t.add_raw_templates(all)?;
    Ok(t)
}

/// Where a model's table lives under `generated/`.
pub fn table_path(model: &str) -> String {
    format!("airlight-kernels/{}", crate_table_path(model))
}

/// The same inside the crate `airlight-kernels`, which owns its tables so that it
/// packages on its own (`cargo package`); the shaders bind them from there.
pub fn crate_table_path(model: &str) -> String {
    format!("tables/{model}.f32")
}

/// Comment lines of a generated file's header (without comment markers).
fn header_lines(spec: &KernelSpec, out: &KernelOutput) -> Vec<String> {
    let lang = ext(out.target);
    let mut h = vec![
        format!("airlight kernel `{}` — {}.", spec.name, out.variant.replace("{ident}", &spec.ident())),
        "Generated by `airlight generate` — edit the template, not this file.".to_string(),
        format!(
            "templates: fit/src/family/{} and codegen/templates/kernels/kernel.{lang}.tera",
            core_template(spec.body().dir(), out.target)
        ),
    ];
    match &spec.model {
        Some(m) => {
            h.push(format!("model: {}; coefficients: generated/coefficients/{}.toml", m.model.name, m.model.name))
        }
        None => h.push("model: none (exact closed form without extinction, seed 003)".into()),
    }
    if let Some(s) = &spec.scene {
        h.push(format!("scene: {s}; plan: generated/plans/{}.md", spec.name));
    }
    h.push(format!("declared bound: {}", spec.bound));
    h
}

/// `text` inside the include guard `#ifndef GUARD`/`#define GUARD` … `#endif`,
/// after its leading comment lines: a file included twice (directly and through
/// another include) defines everything once.
fn include_guard(text: &str, guard: &str) -> String {
    let at: usize = text.lines().take_while(|l| l.starts_with("//")).map(|l| l.len() + 1).sum();
    let (head, body) = text.split_at(at.min(text.len()));
    format!("{head}#ifndef {guard}\n#define {guard}\n{body}#endif // {guard}\n")
}

/// A kernel's include-guard macro in `lang` (`AIRLIGHT_PHI_4_HLSL_INCLUDED`, as
/// Unity's own includes spell theirs).
pub fn guard_macro(prefix: &str, lang: &str) -> String {
    format!("{}{}_INCLUDED", prefix.to_ascii_uppercase(), lang.to_ascii_uppercase())
}

fn comment(lines: &[String], marker: &str) -> String {
    lines.iter().map(|l| format!("{marker} {l}")).collect::<Vec<_>>().join("\n")
}

/// Each entry point's parameter list in `lang`, and the canonical arguments in words.
fn signatures(ctx: &mut tera::Context, spec: &KernelSpec, lang: Target) {
    let (f, v3_ty) = match lang {
        Target::Rust => ("f32", "[f32; 3]"),
        Target::Wgsl => ("f32", "vec3<f32>"),
        Target::Glsl => ("float", "vec3"),
    };
    let typed = |args: Vec<Arg>| -> String {
        args.into_iter()
            .map(|a| {
                let ty = if a.ty() == ArgType::Vec3 { v3_ty } else { f };
                match lang {
                    Target::Glsl => format!("{ty} {}", a.name()),
                    _ => format!("{}: {ty}", a.name()),
                }
            })
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut args = spec
        .params()
        .iter()
        .filter_map(|p| match p {
            Arg::Tau => Some("τ"),
            Arg::Gamma => Some("γ"),
            Arg::Rho => Some("ρ"),
            _ => None,
        })
        .collect::<Vec<_>>()
        .join(", ");
    if spec.g_param() {
        args.push_str("; g");
    }
    ctx.insert("canonical_args", &args);
    // `<entry>_params` for every entry point (empty where the kernel has none).
    for entry in Entry::ALL {
        ctx.insert(format!("{}_params", entry.function()), &typed(spec.args(entry)));
    }
    // The shafts accumulator's: each lit run is the entry called with the viewer
    // moved (`o`) and the run's length as its surface (`len`); the caller passes
    // the entry's other arguments to every push.
    for entry in [Entry::Radiance, Entry::Spot] {
        let args: Vec<Arg> = spec.args(entry).into_iter().filter(|&a| a != Arg::Surface).collect();
        let names = |args: &[Arg]| args.iter().map(|a| a.name()).collect::<Vec<_>>().join(", ");
        let call = spec
            .args(entry)
            .iter()
            .map(|a| match a {
                Arg::Origin => "o",
                Arg::Surface => "len",
                a => a.name(),
            })
            .collect::<Vec<_>>()
            .join(", ");
        ctx.insert(format!("{}_shafts_params", entry.function()), &typed(args.clone()));
        // The registry's uniform signature (Rust): every argument but `surface`,
        // those the kernel does not take `_`-prefixed.
        let uniform = entry
            .all_args()
            .iter()
            .filter(|&&a| a != Arg::Surface)
            .map(|&a| {
                let ty = if a.ty() == ArgType::Vec3 { "[f32; 3]" } else { "f32" };
                let name = if args.contains(&a) { a.name().to_string() } else { format!("_{}", a.name()) };
                format!("{name}: {ty}")
            })
            .collect::<Vec<_>>()
            .join(", ");
        ctx.insert(format!("{}_shafts_uniform", entry.function()), &uniform);
        ctx.insert(format!("{}_shafts_pass", entry.function()), &names(&args));
        ctx.insert(format!("{}_shafts_call", entry.function()), &call);
    }
}

/// What the shared kernel template needs, whatever the family.
fn shared_context(spec: &KernelSpec, out: &KernelOutput) -> tera::Context {
    let ident = spec.ident();
    let mut ctx = tera::Context::new();
    let header = comment(&header_lines(spec, out), "//");
    let header = match &out.import_path {
        Some(p) => format!("#define_import_path {}\n\n{header}", p.replace("{ident}", &ident)),
        None => header,
    };
    ctx.insert("header", &header);
    ctx.insert("p", &out.prefix.replace("{ident}", &ident));
    ctx.insert("title", &spec.name);
    ctx.insert("surfaces", &spec.surfaces);
    ctx.insert("extinction", &spec.extinction);
    ctx.insert("backscatter", &spec.backscatter);
    ctx.insert("g_param", &spec.g_param());
    ctx.insert("p_iso", &lit(1.0 / (4.0 * PI)));
    ctx.insert("iso", &(spec.phase == KernelPhase::Isotropic));
    // The shared math's optional helpers; a family's context turns on what it uses.
    ctx.insert("needs_exprel", &false);
    ctx.insert("needs_phi", &false);
    signatures(&mut ctx, spec, out.target);
    // The spot entry (shared by every family through its `along`).
    ctx.insert("spot", &spec.spot);
    // The shafts accumulator (shadowed in-scattering), on the entries above.
    ctx.insert("shafts", &spec.shafts);
    ctx.insert("takes_tau", &spec.takes_tau());
    // Families whose core shares its nodes across channels emit an RGB variant of it.
    let shared_rgb = spec.spot && spec.body().shares_rgb_nodes();
    ctx.insert("shared_rgb", &shared_rgb);
    ctx.insert("geometry_variants", &if shared_rgb { vec![false, true] } else { vec![false] });
    ctx.insert("spot_g", &lit(spec.phase.fixed_g().unwrap_or(0.0)));
    let (ex, ew) = airlight_truth::quad::gauss_legendre(SPOT_EDGE_NODES);
    ctx.insert("edge_x", &lits(&ex));
    ctx.insert("edge_w", &lits(&ew));
    ctx.insert("edge_pieces", &lits(&SPOT_EDGE_PIECES));
    if let (Some(_), Some(m)) = (spec.body().texture(), &spec.model) {
        ctx.insert("table_path", &crate_table_path(&m.model.name));
        ctx.insert("table_file", &table_path(&m.model.name));
    }
    ctx
}

/// Renders one kernel for one table row: the shared context, then the family's.
fn render_kernel(tera: &tera::Tera, spec: &KernelSpec, out: &KernelOutput) -> Result<Output, tera::Error> {
    let mut ctx = shared_context(spec, out);
    let prefix = out.prefix.replace("{ident}", &spec.ident());
    let specialised = specialisations(spec);
    let view = KernelView {
        name: &spec.name,
        model_name: spec.model.as_ref().map(|m| m.model.name.as_str()),
        model_summary: spec.model.as_ref().map(|m| m.model.summary.as_str()),
        specialisations: &specialised,
        phase: &spec.phase,
        surfaces: spec.surfaces,
        backscatter: spec.backscatter,
        spot: spec.spot,
        target: out.target,
        prefix: &prefix,
    };
    let family = tera::Context::from_serialize(spec.body().kernel_context(&view))?;
    ctx.extend(family);
    let mut text = tera.render(&core_template(spec.body().dir(), out.target), &ctx)?;
    if !text.ends_with('\n') {
        text.push('\n');
    }
    // The C-preprocessed languages get a guard (WGSL and WESL have no preprocessor;
    // their items are prefixed or module-scoped).
    if out.target == Target::Glsl {
        text = include_guard(&text, &guard_macro(&prefix, "glsl"));
    }
    Ok(Output::text(outputs::expand(&out.path, &spec.name), text))
}

/// naga's translations (HLSL, MSL) of a kernel's validated WGSL, from `rendered`.
fn translations(spec: &KernelSpec, table: &OutputTable, rendered: &[Output]) -> Result<Vec<Output>, tera::Error> {
    let name = |p: &str| outputs::expand(p, &spec.name);
    let functions: Vec<String> = Entry::ALL
        .into_iter()
        .filter(|&e| !spec.args(e).is_empty())
        .map(|e| format!("{}{}", spec.prefix(), e.function()))
        .collect();
    let mut out = Vec::new();
    for row in &table.translation {
        let from = name(&row.from);
        let Some(src) = rendered.iter().find(|o| o.path == from) else { continue };
        let wgsl = String::from_utf8_lossy(&src.contents).into_owned();
        let text = crate::translate::translate(&wgsl, row.backend, &spec.prefix(), &functions)
            .map_err(|e| tera::Error::msg(format!("{from} to {}: {e}", row.backend.name())))?;
        let text = include_guard(&text, &guard_macro(&spec.prefix(), row.backend.name()));
        let lines = [
            "Generated by `airlight generate` from the validated WGSL: edit its template, not this file.".to_string(),
            format!("source: generated/{from} (its header documents the entry points)"),
            format!("variant: {}", name(&row.variant)),
            "translated by naga 30's back end, so names, arguments and behaviour are the WGSL's".to_string(),
        ];
        out.push(Output::text(name(&row.path), format!("{}\n{text}", comment(&lines, "//"))));
    }
    Ok(out)
}

/// Steps the shadow-map walk may take per ray (its loop's bound; past it the rest
/// of the ray counts as shadowed, and the walk says so).
pub const WALK_STEPS: u32 = 4096;

/// How far short of a node's side the shadow-map walk takes a ray to be on it,
/// relative to the size of the terms of its face coordinates there: 16 ulps of
/// f32, more than the rounding of a corner's crossing, less than 1e-5 of a
/// texel at the largest map. As a literal for the templates (`walk_side_tol`).
pub fn walk_side_tol() -> String {
    format!("{:e}", 16.0 * f32::EPSILON)
}

/// The walk's constants every template that renders it is given.
pub(crate) fn walk_constants(ctx: &mut tera::Context) {
    ctx.insert("walk_steps", &WALK_STEPS);
    ctx.insert("walk_side_tol", &walk_side_tol());
}

/// Where the shadow-map walk reads its pyramid (the walk templates' `atlas`,
/// `pyramid_params`, `pyramid_args`): one mip-mapped `texture_2d_array` in WGSL
/// and a caller's `airlight_smap_node` in GLSL (`atlas` false), or airlight-three's
/// two atlases, passed down as textures (`atlas` true: three.js binds textures as
/// function arguments only).
pub(crate) fn walk_pyramid(ctx: &mut tera::Context, glsl: bool, atlas: bool) {
    let (params, args) = match (glsl, atlas) {
        (false, false) => ("pyramid: texture_2d_array<f32>", "pyramid"),
        (false, true) => ("even: texture_2d<f32>, odd: texture_2d<f32>", "even, odd"),
        (true, false) => ("", ""),
        (true, true) => (", highp sampler2D even, highp sampler2D odd", ", even, odd"),
    };
    ctx.insert("atlas", &atlas);
    ctx.insert("pyramid_params", params);
    ctx.insert("pyramid_args", args);
}

/// The files every kernel shares (the shadow-map walk and its pyramid passes),
/// and naga's HLSL and MSL of the WGSL walk.
fn render_shared(tera: &tera::Tera, table: &OutputTable) -> Result<Vec<Output>, tera::Error> {
    let mut out = Vec::new();
    for f in &table.shared_file {
        let mut ctx = tera::Context::new();
        let lines = [
            "Generated by `airlight generate` — edit the template, not this file.".to_string(),
            format!("template: codegen/templates/kernels/{}", f.template),
        ];
        ctx.insert("header", &comment(&lines, "//"));
        walk_constants(&mut ctx);
        walk_pyramid(&mut ctx, f.path.ends_with(".glsl"), false);
        let mut text = tera.render(&f.template, &ctx)?;
        // A GLSL library gets a guard; a whole shader (its #version first) none.
        if f.path.ends_with(".glsl") && !f.path.ends_with(".frag.glsl") {
            text = include_guard(&text, &guard_macro("airlight_smap_", "glsl"));
        }
        for (path, backend) in [(&f.hlsl, crate::translate::Backend::Hlsl), (&f.msl, crate::translate::Backend::Msl)] {
            let Some(path) = path else { continue };
            let t = crate::translate::translate(&text, backend, "airlight_smap_", &["airlight_smap_next".to_string()])
                .map_err(|e| tera::Error::msg(format!("{} to {}: {e}", f.path, backend.name())))?;
            let lines = [
                "Generated by `airlight generate` from the validated WGSL: edit its template, not this file."
                    .to_string(),
                format!("source: generated/{} (its header documents the walk)", f.path),
                "translated by naga 30's back end, so names, arguments and behaviour are the WGSL's".to_string(),
            ];
            let t = include_guard(&t, &guard_macro("airlight_smap_", backend.name()));
            out.push(Output::text(path.clone(), format!("{}\n{t}", comment(&lines, "//"))));
        }
        out.push(Output::text(f.path.clone(), text));
    }
    Ok(out)
}

/// Every kernel output: per-kernel files from the table, naga's translations,
/// the tables kernels read, the Rust crate's own files and the engine packages.
pub fn render(specs: &[KernelSpec]) -> Result<Vec<Output>, tera::Error> {
    let mut out = render_sources(specs)?;
    out.extend(render_crate(specs)?);
    let packages = packages::render(&engine()?, &OutputTable::standard(), specs, &out)?;
    out.extend(packages);
    Ok(out)
}

/// The Rust crate's registry and manifest (`lib.rs`, `Cargo.toml`): what carries
/// the declared bounds, f32 ones included, and none of the kernels' code.
pub fn render_crate(specs: &[KernelSpec]) -> Result<Vec<Output>, tera::Error> {
    rust_crate::render(&engine()?, &OutputTable::standard(), specs)
}

/// Every kernel source (and table) of `specs`, without the crate's registry:
/// what the gate measures ([`airlight_shapes::record::digest`]).
pub fn render_sources(specs: &[KernelSpec]) -> Result<Vec<Output>, tera::Error> {
    let table = OutputTable::standard();
    let tera = engine()?;
    let mut out = Vec::new();
    for spec in specs {
        for row in &table.kernel {
            if spec.targets.contains(&row.target) {
                out.push(render_kernel(&tera, spec, row)?);
            }
        }
    }
    for spec in specs {
        let t = translations(spec, &table, &out)?;
        out.extend(t);
    }
    out.extend(render_shared(&tera, &table)?);
    // Tables (the texture of a table-driven kernel), once per model.
    for spec in specs {
        if let (Some(t), Some(m)) = (spec.body().texture(), &spec.model) {
            let path = table_path(&m.model.name);
            if !out.iter().any(|o: &Output| o.path == path) {
                out.push(Output { path, contents: t.to_le_bytes() });
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_family_has_a_core_template_per_target_and_it_parses() {
        let tera = engine().unwrap();
        for (dir, _) in airlight_fit::family::all_templates() {
            for target in Target::ALL {
                assert!(tera.get_template_names().any(|n| n == core_template(dir, target)), "{dir} {target:?}");
            }
        }
    }
}
