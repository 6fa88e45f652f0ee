//! The output table (`codegen/outputs.toml`): which files each kernel gets,
//! where they go and how their items are prefixed. It names targets, paths and
//! prefixes only: which templates render a kernel follows from its family and
//! the target ([`super::templates`]).

use airlight_shapes::vocab::Target;
use serde::Deserialize;

/// The output table (`codegen/outputs.toml`).
pub const OUTPUT_TABLE: &str = include_str!("../../outputs.toml");

/// One row of the kernel table.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KernelOutput {
    /// The language.
    pub target: Target,
    /// Output path pattern.
    pub path: String,
    /// Prefix of every item (pattern).
    pub prefix: String,
    /// `#define_import_path` (pattern), for naga_oil modules.
    #[serde(default)]
    pub import_path: Option<String>,
    /// What this variant is.
    pub variant: String,
}

/// A file rendered once.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FileOutput {
    /// Template.
    pub template: String,
    /// Output path (pattern, for plans).
    pub path: String,
}

/// A file every kernel shares, rendered once, and naga's translations of it.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SharedFile {
    /// Template.
    pub template: String,
    /// Output path.
    pub path: String,
    /// Its HLSL, where it is a WGSL library.
    #[serde(default)]
    pub hlsl: Option<String>,
    /// Its MSL, where it is a WGSL library.
    #[serde(default)]
    pub msl: Option<String>,
}

/// The whole table.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputTable {
    /// Per-kernel outputs.
    pub kernel: Vec<KernelOutput>,
    /// Files of the Rust crate.
    pub crate_file: Vec<FileOutput>,
    /// Files every kernel shares, rendered once (the shadow-map walk).
    pub shared_file: Vec<SharedFile>,
    /// Per-scene plan.
    pub plan: Vec<FileOutput>,
    /// Per-kernel translations of a rendered kernel by naga.
    pub translation: Vec<Translation>,
    /// Per-kernel files of the engine packages.
    pub package_kernel: Vec<PackageKernel>,
    /// Per-kernel ES modules of the three.js package.
    pub package_module: Vec<PackageModule>,
    /// Files of the engine packages, rendered once.
    pub package_file: Vec<FileOutput>,
    /// The package whose files get Unity `.meta` files.
    pub unity_meta: UnityMeta,
}

/// A kernel's file in an engine package: a rendered file copied in.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PackageKernel {
    /// The rendered file (pattern).
    pub from: String,
    /// Output path pattern.
    pub path: String,
    /// What is appended after the kernel.
    #[serde(default)]
    pub wrappers: Option<Wrappers>,
}

/// A kernel's ES module in the three.js package: two rendered sources as strings.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PackageModule {
    /// The GLSL ES 3.00 include (pattern).
    pub glsl: String,
    /// The plain WGSL (pattern).
    pub wgsl: String,
    /// The module of TSL nodes (pattern).
    pub path: String,
    /// Its TypeScript declarations (pattern).
    pub types: String,
    /// The module of the sources alone (pattern).
    pub sources: String,
    /// Its TypeScript declarations (pattern).
    pub source_types: String,
    /// The package's folder: the four paths above start with it.
    pub root: String,
    /// Where a kernel kept for comparison and research (not on the menu) goes
    /// instead of `root`, the rest of each path the same.
    pub research: String,
}

/// Wrappers appended to a kernel in a package.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Wrappers {
    /// Unity Shader Graph Custom Function (File mode): `<entry>_float` and
    /// `<entry>_half`, `void`, the result an `out` parameter.
    ShaderGraph,
}

/// Where Unity `.meta` files are written.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UnityMeta {
    /// The package root (every file and folder under it gets one).
    pub root: String,
}

/// A kernel file translated from another by one of naga's back ends.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Translation {
    /// The rendered file it translates (pattern).
    pub from: String,
    /// naga's back end.
    pub backend: crate::translate::Backend,
    /// Output path pattern.
    pub path: String,
    /// What this variant is (pattern).
    pub variant: String,
}

impl OutputTable {
    /// The committed table.
    pub fn standard() -> OutputTable {
        toml::from_str(OUTPUT_TABLE).expect("codegen/outputs.toml parses (checked by a test)")
    }
}

/// `{name}` and `{ident}` of an output pattern, for the kernel `name`.
pub fn expand(pattern: &str, name: &str) -> String {
    pattern.replace("{name}", name).replace("{ident}", &name.replace('-', "_"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_parses_and_names_only_targets_paths_and_prefixes() {
        let t = OutputTable::standard();
        assert!(!t.kernel.is_empty() && !t.crate_file.is_empty() && !t.plan.is_empty());
        for family in airlight_fit::family::all_templates().iter().map(|(dir, _)| *dir) {
            assert!(!OUTPUT_TABLE.contains(family), "outputs.toml names the family {family}");
        }
    }
}
