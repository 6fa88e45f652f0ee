//! Engine packages, built from kernels already rendered: a Unity package (UPM
//! layout, each kernel's HLSL with Shader Graph Custom Function wrappers and a
//! `.meta` beside every asset), an Unreal plugin (each kernel's HLSL as a `.ush`
//! under the plugin's virtual shader path) and the Bevy 0.20 plugin crate that
//! embeds the WESL modules with `load_shader_library!`. Which files go where is
//! the output table's (`[[package_kernel]]`, `[[package_file]]`); this module
//! writes the wrappers, the registrations and the metadata.

use super::outputs::{expand, OutputTable, Wrappers};
use super::spec::KernelSpec;
use super::{comment, guard_macro};
use crate::output::Output;
use airlight_fit::vocab::{ArgType, Domain, Entry, Target};
use serde::Serialize;

/// The largest finite `half`: Shader Graph's `_half` wrappers clamp to it, so a
/// kernel's f32 `HUGE` stays finite.
const HALF_MAX: &str = "65504.0";

/// One entry point's Shader Graph wrappers.
#[derive(Serialize)]
struct WrapperEntry {
    /// The kernel's function (`airlight_phi_4_radiance`).
    name: String,
    /// The result's type in float and in half.
    out_float: &'static str,
    out_half: &'static str,
    params_float: String,
    params_half: String,
    /// The kernel call's arguments: as passed, and promoted from half.
    args: String,
    args_half: String,
}

/// A kernel as the package files list it.
#[derive(Serialize)]
struct PackageKernelView {
    name: String,
    ident: String,
    /// `thin 5.5e-4, dense 3.2e-4` (f64 model) and the f32 bound where recorded.
    bound: String,
    /// Its entry points (prefixed names).
    entries: Vec<String>,
    /// Whether it has the shafts accumulator.
    shafts: bool,
    /// Whether it takes g at run time.
    g_param: bool,
}

/// Kernels that go into the engine packages: the general models without a
/// texture to bind.
fn packaged(specs: &[KernelSpec]) -> impl Iterator<Item = &KernelSpec> {
    specs.iter().filter(|s| s.scene.is_none() && s.model.is_some() && s.body().texture().is_none())
}

fn entries(spec: &KernelSpec) -> Vec<Entry> {
    Entry::ALL.into_iter().filter(|&e| !spec.args(e).is_empty()).collect()
}

fn wrapper_entries(spec: &KernelSpec) -> Vec<WrapperEntry> {
    entries(spec)
        .into_iter()
        .map(|e| {
            let args = spec.args(e);
            let ty = |vec: bool, half: bool| match (vec, half) {
                (true, false) => "float3",
                (true, true) => "half3",
                (false, false) => "float",
                (false, true) => "half",
            };
            let params = |half: bool| {
                args.iter().map(|a| format!("{} {}", ty(a.ty() == ArgType::Vec3, half), a.name())).collect::<Vec<_>>()
            };
            let rgb = e.outputs() == 3;
            WrapperEntry {
                name: format!("{}{}", spec.prefix(), e.function()),
                out_float: ty(rgb, false),
                out_half: ty(rgb, true),
                params_float: params(false).join(", "),
                params_half: params(true).join(", "),
                args: args.iter().map(|a| a.name()).collect::<Vec<_>>().join(", "),
                args_half: args
                    .iter()
                    .map(|a| format!("({}){}", ty(a.ty() == ArgType::Vec3, false), a.name()))
                    .collect::<Vec<_>>()
                    .join(", "),
            }
        })
        .collect()
}

fn view(spec: &KernelSpec) -> PackageKernelView {
    let f32s: Vec<String> = [Domain::Thin, Domain::Dense]
        .iter()
        .filter_map(|&d| spec.f32_bound(d).map(|b| format!("{} {b:.1e}", d.name())))
        .collect();
    let bound = if f32s.is_empty() { spec.bound.clone() } else { format!("{}; f32: {}", spec.bound, f32s.join(", ")) };
    PackageKernelView {
        name: spec.name.clone(),
        ident: spec.ident(),
        bound,
        entries: entries(spec).iter().map(|e| format!("{}{}", spec.prefix(), e.function())).collect(),
        shafts: spec.shafts,
        g_param: spec.g_param(),
    }
}

/// The engine packages' files: each packaged kernel's copy (with wrappers where
/// the row asks), the files rendered once, and Unity's `.meta` files.
pub(super) fn render(
    tera: &tera::Tera,
    table: &OutputTable,
    specs: &[KernelSpec],
    rendered: &[Output],
) -> Result<Vec<Output>, tera::Error> {
    let mut out = Vec::new();
    for spec in packaged(specs) {
        for row in &table.package_kernel {
            let from = expand(&row.from, &spec.name);
            let Some(src) = rendered.iter().find(|o| o.path == from) else { continue };
            let mut text = String::from_utf8_lossy(&src.contents).into_owned();
            if row.wrappers == Some(Wrappers::ShaderGraph) {
                let mut ctx = tera::Context::new();
                ctx.insert("guard", &guard_macro(&spec.prefix(), "shader_graph"));
                ctx.insert("entries", &wrapper_entries(spec));
                ctx.insert("half_max", HALF_MAX);
                text.push_str(&tera.render("unity/shader_graph.hlsl.tera", &ctx)?);
            }
            let lines = [format!("packaged by `airlight generate` from generated/{from}")];
            out.push(Output::text(expand(&row.path, &spec.name), format!("{}\n{text}", comment(&lines, "//"))));
        }
    }
    let kernels: Vec<PackageKernelView> = packaged(specs).map(view).collect();
    let modules: Vec<PackageKernelView> =
        specs.iter().filter(|s| s.targets.contains(&Target::Wgsl)).map(view).collect();
    for f in &table.package_file {
        let mut ctx = tera::Context::new();
        ctx.insert("kernels", &kernels);
        ctx.insert("modules", &modules);
        ctx.insert("version", env!("CARGO_PKG_VERSION"));
        ctx.insert("generated_by", "Generated by `airlight generate`: edit the template, not this file.");
        ctx.insert("template", &format!("codegen/templates/packages/{}", f.template));
        out.push(Output::text(f.path.clone(), tera.render(&f.template, &ctx)?));
    }
    let metas = unity_metas(&table.unity_meta.root, &out);
    out.extend(metas);
    Ok(out)
}

/// A GUID for a Unity asset that is the same on every machine: FNV-1a over
/// its path, twice with different offsets (128 bits, as 32 hex digits).
fn unity_guid(path: &str) -> String {
    let fnv = |seed: u64| path.bytes().fold(seed, |h, b| (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3));
    format!("{:016x}{:016x}", fnv(0xcbf2_9ce4_8422_2325), fnv(0x8422_2325_cbf2_9ce4))
}

/// The `.meta` of every file and folder under `root` among `files`.
fn unity_metas(root: &str, files: &[Output]) -> Vec<Output> {
    let mut folders = std::collections::BTreeSet::new();
    let mut metas = Vec::new();
    for f in files.iter().filter(|f| f.path.starts_with(&format!("{root}/"))) {
        let rel = &f.path[root.len() + 1..];
        let mut dir = std::path::Path::new(rel).parent();
        while let Some(d) = dir.filter(|d| !d.as_os_str().is_empty()) {
            folders.insert(d.to_string_lossy().replace('\\', "/"));
            dir = d.parent();
        }
        let importer = if rel.ends_with(".hlsl") {
            "ShaderIncludeImporter:\n  externalObjects: {}\n  userData: \n  assetBundleName: \n  assetBundleVariant: \n"
        } else if rel == "package.json" {
            "PackageManifestImporter:\n  externalObjects: {}\n  userData: \n  assetBundleName: \n  assetBundleVariant: \n"
        } else {
            "TextScriptImporter:\n  externalObjects: {}\n  userData: \n  assetBundleName: \n  assetBundleVariant: \n"
        };
        metas.push(Output::text(
            format!("{}.meta", f.path),
            format!("fileFormatVersion: 2\nguid: {}\n{importer}", unity_guid(&f.path)),
        ));
    }
    for d in folders {
        let path = format!("{root}/{d}");
        metas.push(Output::text(
            format!("{path}.meta"),
            format!(
                "fileFormatVersion: 2\nguid: {}\nfolderAsset: yes\nDefaultImporter:\n  externalObjects: {{}}\n  userData: \n  assetBundleName: \n  assetBundleVariant: \n",
                unity_guid(&path)
            ),
        ));
    }
    metas
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unity_guids_are_distinct_hex_and_stable() {
        let a = unity_guid("unity/com.airlight.kernels/Runtime/Shaders/phi-4.hlsl");
        let b = unity_guid("unity/com.airlight.kernels/Runtime/Shaders/phi-6.hlsl");
        assert_eq!(a.len(), 32);
        assert!(a.chars().all(|c| c.is_ascii_hexdigit()));
        assert_ne!(a, b);
        assert_eq!(a, unity_guid("unity/com.airlight.kernels/Runtime/Shaders/phi-4.hlsl"));
    }

    #[test]
    fn every_file_and_folder_under_the_root_gets_a_meta() {
        let files = [
            Output::text("u/pkg/package.json", String::new()),
            Output::text("u/pkg/Runtime/Shaders/k.hlsl", String::new()),
            Output::text("other/x.hlsl", String::new()),
        ];
        let mut paths: Vec<String> = unity_metas("u/pkg", &files).into_iter().map(|m| m.path).collect();
        paths.sort();
        assert_eq!(
            paths,
            [
                "u/pkg/Runtime.meta",
                "u/pkg/Runtime/Shaders.meta",
                "u/pkg/Runtime/Shaders/k.hlsl.meta",
                "u/pkg/package.json.meta"
            ]
        );
    }
}
