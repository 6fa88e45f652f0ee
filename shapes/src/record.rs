//! `generated/gate.toml`: the error gate's figures as `airlight check --record`
//! measured them on one machine — every kernel × target × domain row, and the
//! adapter. Like `bench.json` it is an input the report quotes, never written by
//! `regenerate` (a GPU's rounding differs between adapters, and regenerating
//! must stay byte-identical on any machine). It carries a digest of the kernel
//! sources it was measured on, so the report can say when it is stale.

use crate::vocab::{Domain, Target};
use serde::{Deserialize, Serialize};

/// The file's name under `generated/`.
pub const FILE: &str = "gate.toml";

/// The gate's targets, in the order its tables list them: the kernel's f64
/// model (`None`, the column every f32 target is compared with), then the f32
/// targets.
pub const TARGETS: [Option<Target>; 4] = [None, Some(Target::Rust), Some(Target::Wgsl), Some(Target::Glsl)];

/// The gate's label of a target: where and in what precision it runs.
pub fn target_label(t: Option<Target>) -> &'static str {
    match t {
        None => "f64",
        Some(Target::Rust) => "rust-f32",
        Some(t) => t.name(),
    }
}

/// The physical entry's rows on random placements.
pub const PHYSICAL: &str = "physical";
/// The physical entry's rows on the extreme set.
pub const PHYS_EXTREME: &str = "phys-extreme";
/// The spot entry's rows.
pub const SPOT: &str = "spot";
/// The canonical entry's rows at its edges: the exact axis, tiny angles, far and
/// touching surfaces.
pub const EDGE: &str = "edge";

/// The shafts accumulator's rows: rays among analytic occluders, fed the exact
/// lit intervals.
pub const SHADOWED: &str = "shadowed";

/// The shafts accumulator fed the lit runs of the shadow-map walk: rays among
/// analytic occluders cast into a cube map, against the same map's exact runs.
pub const SHADOW_MAP: &str = "shadow-map";

/// The gate's regimes, in the order its tables list them: the canonical entry's
/// domains, then the physical, spot, shadowed and shadow-map sets.
pub const REGIMES: [&str; 9] = [
    Domain::Thin.name(),
    Domain::Dense.name(),
    Domain::Extreme.name(),
    EDGE,
    PHYSICAL,
    PHYS_EXTREME,
    SPOT,
    SHADOWED,
    SHADOW_MAP,
];

/// One kernel × target × domain row of the gate.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GateRow {
    /// Kernel name.
    pub kernel: String,
    /// `f64` (the kernel's model), `rust-f32`, `wgsl` or `glsl`.
    pub target: String,
    /// `thin`, `dense`, `extreme`, `physical` or `phys-extreme`.
    pub domain: String,
    /// Points in the error statistics (value within f32's checked range).
    pub points: usize,
    /// Largest relative error against the reference.
    pub max_rel: f64,
    /// 99th-percentile relative error.
    pub p99_rel: f64,
    /// The limit the gate held it to (f32 targets).
    pub limit: f64,
    /// NaN, negative or spurious infinite values.
    pub bad: usize,
}

impl GateRow {
    /// Whether it is the row of `target` on `regime` (one of [`REGIMES`]).
    pub fn is(&self, target: Option<Target>, regime: &str) -> bool {
        self.target == target_label(target) && self.domain == regime
    }
}

/// Everything `airlight check --record` writes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GateRecord {
    /// The GPU adapter the WGSL and GLSL rows ran on, or why there were none.
    pub adapter: String,
    /// [`digest`] of the kernel sources measured.
    pub kernels_digest: String,
    /// Every row.
    pub rows: Vec<GateRow>,
    /// Every kernel's f32 bound on each of its sampled domains, measured on its
    /// f32 targets: what `kernels.toml` and the crate's `KERNELS` declare and the
    /// gate holds the f32 targets to ([`F32Bound`]).
    pub f32_bounds: Vec<F32Bound>,
}

/// A kernel's f32 bound on one domain (docs/MATH.md §5): the largest relative
/// error its f32 targets reach, measured by `airlight check --record` — the Rust
/// f32 kernel on the domain's validation set, face grids, held-out rounds and
/// local searches from their worst points (those of the f64 bound, run on the
/// kernel itself), each GPU target on the validation set and at the Rust
/// searches' worst point — times `1 +` `DECLARED_MARGIN` (airlight-fit's `catalog`), as every
/// declared bound, and never below the f64 model's declared bound.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct F32Bound {
    /// Kernel name.
    pub kernel: String,
    /// `thin` or `dense`.
    pub domain: String,
    /// The bound.
    pub max_rel: f64,
    /// The f64 model's declared bound it is never below.
    pub f64_max_rel: f64,
    /// What set it: the target (`rust-f32`, `wgsl`, `glsl`, or `f64` where no f32
    /// target exceeded the model's bound).
    pub set_by: String,
    /// Where that target's largest error was found `[τ, γ, ρ, g]` (ρ = -1: no
    /// surface); absent where the model's bound set it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub at: Option<[f64; 4]>,
}

impl GateRecord {
    /// The recorded f32 bound of `kernel` on `domain`.
    pub fn f32_bound(&self, kernel: &str, domain: Domain) -> Option<f64> {
        self.f32_bounds.iter().find(|b| b.kernel == kernel && b.domain == domain.name()).map(|b| b.max_rel)
    }
}

impl GateRecord {
    /// The file's text: deterministic for a value.
    pub fn to_toml(&self) -> String {
        let mut out =
            String::from("# Written by `airlight check --record`; quoted by REPORT.md (`airlight generate`).\n");
        out.push_str(&toml::to_string(self).expect("plain data serialises"));
        out
    }

    /// Reads the file's text; `file` names it in the error.
    pub fn from_toml(file: &str, text: &str) -> Result<GateRecord, airlight_truth::tomlfile::FieldError> {
        airlight_truth::tomlfile::from_str(file, text, "rows")
    }
}

/// Whether a generated file is a kernel source the gate measures.
pub fn is_kernel_source(path: &str) -> bool {
    (path.starts_with("wgsl/") || path.starts_with("glsl/") || path.starts_with("airlight-kernels/src/"))
        && !path.ends_with("lib.rs")
}

/// FNV-1a (64-bit) over the kernel sources' paths and bytes, in path order: what
/// ties a record to the kernels it measured.
pub fn digest(files: &[(String, Vec<u8>)]) -> String {
    let mut sorted: Vec<&(String, Vec<u8>)> = files.iter().filter(|(p, _)| is_kernel_source(p)).collect();
    sorted.sort_by(|a, b| a.0.cmp(&b.0));
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for (path, bytes) in sorted {
        for &b in path.as_bytes().iter().chain([0u8].iter()).chain(bytes.iter()) {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x0100_0000_01b3);
        }
    }
    format!("{h:016x}")
}

/// `generated/fuzz.toml`: what `fuzz/run` did (libFuzzer's own figures), which
/// the report quotes. Written by that script, re-rendered by `generate`.
pub const FUZZ_FILE: &str = "fuzz.toml";

/// One fuzz target's run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FuzzRun {
    /// The cargo-fuzz target.
    pub target: String,
    /// Seconds it ran.
    pub seconds: u64,
    /// Inputs executed.
    pub runs: u64,
    /// Coverage points (libFuzzer's `cov`) at the end.
    pub coverage: u64,
    /// Inputs in the committed corpus afterwards.
    pub corpus: u64,
    /// Crashes, panics and sanitizer reports.
    pub crashes: u64,
    /// The fuzzer's exit status (0: ran out its time).
    pub exit: i64,
}

/// Everything `fuzz/run` records.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FuzzRecord {
    /// `rustc +nightly --version` of the run.
    pub toolchain: String,
    /// One per target.
    pub runs: Vec<FuzzRun>,
}

impl FuzzRecord {
    /// The file's text: deterministic for a value.
    pub fn to_toml(&self) -> String {
        let mut out = String::from("# Written by fuzz/run; quoted by REPORT.md (`airlight generate`).\n");
        out.push_str(&toml::to_string(self).expect("plain data serialises"));
        out
    }

    /// Reads the file's text; `file` names it in the error.
    pub fn from_toml(file: &str, text: &str) -> Result<FuzzRecord, airlight_truth::tomlfile::FieldError> {
        airlight_truth::tomlfile::from_str(file, text, "runs")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_and_digests() {
        let r = GateRecord {
            adapter: "llvmpipe".into(),
            kernels_digest: "00".into(),
            rows: vec![GateRow {
                kernel: "segments-8".into(),
                target: "wgsl".into(),
                domain: "thin".into(),
                points: 10,
                max_rel: 1e-3,
                p99_rel: 5e-4,
                limit: 2e-3,
                bad: 0,
            }],
            f32_bounds: vec![F32Bound {
                kernel: "segments-8".into(),
                domain: "thin".into(),
                max_rel: 1.5e-3,
                f64_max_rel: 1e-3,
                set_by: "wgsl".into(),
                at: Some([0.5, 1.0, -1.0, 0.0]),
            }],
        };
        assert_eq!(r.f32_bound("segments-8", Domain::Thin), Some(1.5e-3));
        assert_eq!(r.f32_bound("segments-8", Domain::Dense), None);
        assert_eq!(GateRecord::from_toml("g.toml", &r.to_toml()).unwrap(), r);
        let a = digest(&[("wgsl/a.wgsl".into(), b"x".to_vec()), ("REPORT.md".into(), b"y".to_vec())]);
        let b = digest(&[("wgsl/a.wgsl".into(), b"x".to_vec())]);
        assert_eq!(a, b, "only kernel sources count");
        assert_ne!(b, digest(&[("wgsl/a.wgsl".into(), b"z".to_vec())]));
    }
}
