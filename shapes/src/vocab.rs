//! The vocabulary every crate shares, typed once: the target languages, the
//! kernels' arguments (name, type, GPU packing slot), the error domains
//! ([`Domain`], whose box lives in [`airlight_truth::domains`]), the f32 allowance of the
//! gate and the tests, and the kernel index `generated/kernels.toml` that the
//! harness, the gate and the CLI read.
//!
//! Strings appear only at the edges (files, command lines); an unknown name is an
//! error there, never a silent default.

pub use airlight_truth::domains::Domain;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// Whose a family (or a model) is: airlight's own, or what a user would pick
/// instead. Serialised as `airlight` / `baseline` (bench.json's `kind`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Role {
    /// One of airlight's models (fitted or derived here).
    Airlight,
    /// A baseline: what a rendering engineer would use instead.
    Baseline,
}

/// A language the generator emits kernels in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Target {
    /// WGSL for wgpu (plain, and as a Bevy / naga_oil module); run on the GPU adapter.
    Wgsl,
    /// A GLSL include (ES 3.00 and 4.50); run on the GPU adapter as GLSL 4.50 compute.
    Glsl,
    /// A module of the `no_std` f32 crate `airlight-kernels`; run on the CPU.
    Rust,
}

impl Target {
    /// Every target, in the order tables list them.
    pub const ALL: [Target; 3] = [Target::Wgsl, Target::Glsl, Target::Rust];

    /// As written in scene files, the output table, the index and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Target::Wgsl => "wgsl",
            Target::Glsl => "glsl",
            Target::Rust => "rust",
        }
    }

    /// Whether it is a shading language (evaluated on the GPU adapter).
    pub fn is_shader(self) -> bool {
        self != Target::Rust
    }
}

impl fmt::Display for Target {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A name that is not one of `known`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UnknownName {
    /// What was asked for.
    pub what: &'static str,
    /// The name given.
    pub name: String,
    /// The names that exist.
    pub known: Vec<&'static str>,
}

impl fmt::Display for UnknownName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "unknown {} '{}' (known: {})", self.what, self.name, self.known.join(", "))
    }
}

impl std::error::Error for UnknownName {}

impl FromStr for Target {
    type Err = UnknownName;
    fn from_str(s: &str) -> Result<Target, UnknownName> {
        Target::ALL.into_iter().find(|t| t.name() == s).ok_or_else(|| UnknownName {
            what: "target",
            name: s.into(),
            known: Target::ALL.map(Target::name).to_vec(),
        })
    }
}

/// Which entry point of a kernel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Entry {
    /// `airlight(tau, gamma, rho, g)`: the canonical `A`.
    Canonical,
    /// `radiance(origin, dir, surface, light, intensity, sigma_t, sigma_s, g)`.
    Radiance,
    /// `spot(origin, dir, surface, light, axis, cos_outer, cos_inner, intensity,
    /// sigma_t, sigma_s, g) -> vec3`: a spot light (`cos_outer <= -1`: a point
    /// light) in a medium with RGB `sigma_t`, `sigma_s`.
    Spot,
}

impl Entry {
    /// The function's name (after the kernel's prefix).
    pub fn function(self) -> &'static str {
        match self {
            Entry::Canonical => "airlight",
            Entry::Radiance => "radiance",
            Entry::Spot => "spot",
        }
    }

    /// Every entry, in the order the index lists them.
    pub const ALL: [Entry; 3] = [Entry::Canonical, Entry::Radiance, Entry::Spot];

    /// f32 values it returns per item: 1, or 3 (RGB) for [`Entry::Spot`].
    pub fn outputs(self) -> usize {
        match self {
            Entry::Spot => 3,
            _ => 1,
        }
    }

    /// Every argument the entry can take, in signature order (a kernel takes a
    /// subsequence of it).
    pub fn all_args(self) -> &'static [Arg] {
        match self {
            Entry::Canonical => &[Arg::Tau, Arg::Gamma, Arg::Rho, Arg::G],
            Entry::Radiance => {
                &[Arg::Origin, Arg::Dir, Arg::Surface, Arg::Light, Arg::Intensity, Arg::SigmaT, Arg::SigmaS, Arg::G]
            }
            Entry::Spot => &[
                Arg::Origin,
                Arg::Dir,
                Arg::Surface,
                Arg::Light,
                Arg::Axis,
                Arg::CosOuter,
                Arg::CosInner,
                Arg::Intensity,
                Arg::SigmaTRgb,
                Arg::SigmaSRgb,
                Arg::G,
            ],
        }
    }

    /// `vec4`s per item when the GPU harness packs this entry's arguments.
    pub fn packed_vec4s(self) -> usize {
        match self {
            Entry::Canonical => 1,
            Entry::Radiance => 4,
            Entry::Spot => 6,
        }
    }
}

/// The scalar type of an argument.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ArgType {
    /// One f32.
    Scalar,
    /// Three f32 (a position or direction).
    Vec3,
}

/// An argument of a kernel's entry points.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Arg {
    /// Optical distance to the light, `σt·D`.
    Tau,
    /// Angle between the view ray and the direction to the light, radians.
    Gamma,
    /// Distance to the first surface over `D`; negative: none.
    Rho,
    /// Henyey–Greenstein asymmetry.
    G,
    /// Ray origin (the viewer).
    Origin,
    /// Ray direction (need not be normalised).
    Dir,
    /// Distance to the first surface along the ray; negative: none.
    Surface,
    /// Light position.
    Light,
    /// Radiant intensity.
    Intensity,
    /// Extinction coefficient.
    SigmaT,
    /// Scattering coefficient.
    SigmaS,
    /// A spot light's axis, from the light (any non-zero length).
    Axis,
    /// Cosine of a spot light's outer half-angle (weight 0 beyond; `<= -1`: a point light).
    CosOuter,
    /// Cosine of its inner half-angle (weight 1 within; `<= cos_outer`: a hard edge).
    CosInner,
    /// Extinction coefficient per colour channel (RGB).
    SigmaTRgb,
    /// Scattering coefficient per colour channel (RGB).
    SigmaSRgb,
}

impl Arg {
    /// Its name in every generated signature.
    pub fn name(self) -> &'static str {
        match self {
            Arg::Tau => "tau",
            Arg::Gamma => "gamma",
            Arg::Rho => "rho",
            Arg::G => "g",
            Arg::Origin => "origin",
            Arg::Dir => "dir",
            Arg::Surface => "surface",
            Arg::Light => "light",
            Arg::Intensity => "intensity",
            Arg::SigmaT | Arg::SigmaTRgb => "sigma_t",
            Arg::SigmaS | Arg::SigmaSRgb => "sigma_s",
            Arg::Axis => "axis",
            Arg::CosOuter => "cos_outer",
            Arg::CosInner => "cos_inner",
        }
    }

    /// Scalar or vec3.
    pub fn ty(self) -> ArgType {
        match self {
            Arg::Origin | Arg::Dir | Arg::Light | Arg::Axis | Arg::SigmaTRgb | Arg::SigmaSRgb => ArgType::Vec3,
            _ => ArgType::Scalar,
        }
    }

    /// Where the GPU harness packs it for `entry`: `(vec4 index, first lane)`
    /// (a vec3 takes lanes `first..first + 3`); `None` if the entry has no such argument.
    pub fn slot(self, entry: Entry) -> Option<(usize, usize)> {
        Some(match (entry, self) {
            (Entry::Canonical, Arg::Tau) => (0, 0),
            (Entry::Canonical, Arg::Gamma) => (0, 1),
            (Entry::Canonical, Arg::Rho) => (0, 2),
            (Entry::Canonical, Arg::G) => (0, 3),
            (Entry::Radiance, Arg::Origin) => (0, 0),
            (Entry::Radiance, Arg::Surface) => (0, 3),
            (Entry::Radiance, Arg::Dir) => (1, 0),
            (Entry::Radiance, Arg::Intensity) => (1, 3),
            (Entry::Radiance, Arg::Light) => (2, 0),
            (Entry::Radiance, Arg::SigmaT) => (2, 3),
            (Entry::Radiance, Arg::SigmaS) => (3, 0),
            (Entry::Radiance, Arg::G) => (3, 1),
            (Entry::Spot, Arg::Origin) => (0, 0),
            (Entry::Spot, Arg::Surface) => (0, 3),
            (Entry::Spot, Arg::Dir) => (1, 0),
            (Entry::Spot, Arg::Intensity) => (1, 3),
            (Entry::Spot, Arg::Light) => (2, 0),
            (Entry::Spot, Arg::CosOuter) => (2, 3),
            (Entry::Spot, Arg::Axis) => (3, 0),
            (Entry::Spot, Arg::CosInner) => (3, 3),
            (Entry::Spot, Arg::SigmaTRgb) => (4, 0),
            (Entry::Spot, Arg::G) => (4, 3),
            (Entry::Spot, Arg::SigmaSRgb) => (5, 0),
            _ => return None,
        })
    }
}

impl fmt::Display for Arg {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// What f32 evaluation may add to a kernel's declared relative error, absolute:
/// f32 rounding of the arguments and of exponents up to τ = 20, and GPU
/// `exp`/`log` (Vulkan allows 3 + 2|x| ulp). Measured on the validation sets
/// (lavapipe and the Rust kernels): at most 8.4e-6 over a declared bound.
pub const F32_ALLOWANCE: f64 = 1e-4;

/// The same, relative to the declared bound (for bounds far above 1, where the
/// error is dominated by the model and f32 rounding scales with it; measured:
/// 1.4e-8 of `paper-as-printed`'s 4.9e8).
pub const F32_REL_ALLOWANCE: f64 = 1e-4;

/// Below (or above) this, `A` is not representable in f32 with relative
/// precision: only finiteness and sign are checked there.
pub const F32_RANGE: (f64, f64) = (1e-30, 1e30);

/// The value of `rho` that means "no surface" (`ρ = ∞`) in every kernel's
/// canonical entry.
pub const NO_SURFACE: f32 = -1.0;

/// `ρ` as every kernel's canonical entry takes it: [`NO_SURFACE`] for `ρ = ∞`.
pub fn rho_arg(rho: f64) -> f32 {
    if rho.is_infinite() {
        NO_SURFACE
    } else {
        rho as f32
    }
}

/// The largest relative error an f32 kernel (any target) may show on the sets its
/// f32 bound was not measured on (the edge and extreme sets, the physical, spot
/// and shafts entries) where it declares `declared`.
pub fn f32_limit(declared: f64) -> f64 {
    declared * (1.0 + F32_REL_ALLOWANCE) + F32_ALLOWANCE
}

/// What another adapter's (or compiler's) rounding may add to an f32 bound
/// measured on one: 64 units in the last place of 1 (2⁻¹⁸ = 3.8e-6), twice the
/// largest gap measured between two implementations on the same points (the
/// gate record of 2026-12-03: lavapipe's WGSL and GLSL against the Rust f32
/// kernel, `phi-iso-8` on `dense`, 3.58e-6 against 1.78e-6).
pub const F32_ADAPTER_ALLOWANCE: f64 = 1.0 / 262_144.0;

/// The largest relative error an f32 target may show on `thin` or `dense`, where
/// the kernel declares its own f32 bound `f32_bound` (measured on its f32
/// targets): the bound, widened by [`F32_REL_ALLOWANCE`] and
/// [`F32_ADAPTER_ALLOWANCE`] only.
pub fn f32_domain_limit(f32_bound: f64) -> f64 {
    f32_bound * (1.0 + F32_REL_ALLOWANCE) + F32_ADAPTER_ALLOWANCE
}

/// A compiled Rust kernel's canonical entry, uniform signature `(tau, gamma, rho, g)`
/// (`airlight_kernels::Canonical`).
pub type CanonicalFn = fn(f32, f32, f32, f32) -> f32;

/// A compiled Rust kernel's physical entry, uniform signature `(origin, dir,
/// surface, light, intensity, sigma_t, sigma_s, g)` (`airlight_kernels::Radiance`).
pub type RadianceFn = fn([f32; 3], [f32; 3], f32, [f32; 3], f32, f32, f32, f32) -> f32;

/// A compiled Rust kernel's spot entry, uniform signature `(origin, dir, surface,
/// light, axis, cos_outer, cos_inner, intensity, sigma_t, sigma_s, g)` with RGB
/// `sigma_t`, `sigma_s` and result (`airlight_kernels::Spot`).
pub type SpotFn = fn([f32; 3], [f32; 3], f32, [f32; 3], [f32; 3], f32, f32, f32, [f32; 3], [f32; 3], f32) -> [f32; 3];

/// A compiled Rust kernel's shafts accumulator over its physical entry, uniform
/// signature `(samples, end, origin, dir, light, intensity, sigma_t, sigma_s, g)`
/// (`airlight_kernels::Shadowed`): the `[s, v]` visibility samples in order, then
/// the shadowed radiance to the surface at `end` (negative: none).
pub type ShadowedFn = fn(&[[f32; 2]], f32, [f32; 3], [f32; 3], [f32; 3], f32, f32, f32, f32) -> f32;

/// The same over the spot entry (`airlight_kernels::SpotShadowed`).
pub type SpotShadowedFn =
    fn(&[[f32; 2]], f32, [f32; 3], [f32; 3], [f32; 3], [f32; 3], f32, f32, f32, [f32; 3], [f32; 3], f32) -> [f32; 3];

/// A generated Rust kernel as compiled into some binary: the gate and the render
/// take these from whoever links `airlight-kernels` (the `airlight-run` binary),
/// so that nothing else has to compile the generator's output.
#[derive(Debug, Clone, Copy)]
pub struct CompiledKernel {
    /// Its name in the index.
    pub name: &'static str,
    /// The canonical entry.
    pub airlight: CanonicalFn,
    /// The physical entry.
    pub radiance: RadianceFn,
    /// The spot (RGB) entry, where the kernel has one.
    pub spot: Option<SpotFn>,
    /// The shafts accumulator over `radiance`, where the kernel has one.
    pub shadowed: Option<ShadowedFn>,
    /// The shafts accumulator over `spot`, where the kernel has both.
    pub spot_shadowed: Option<SpotShadowedFn>,
    /// The shadow-map walk of the same crate (`airlight_kernels::shadowmap`),
    /// which feeds either accumulator its lit runs.
    pub walk: Option<WalkFn>,
}

/// Where the walk reads a pyramid: `(layer, level, x, y) → [min, max]`.
pub type NodeFn<'a> = &'a dyn Fn(u32, u32, i32, i32) -> [f32; 2];

/// A map as the walk takes it: `(light, rows, cube, res, bias)` (docs/MATH.md §9).
pub type WalkMap = ([f32; 3], [[f32; 3]; 3], bool, u32, f32);

/// The generated f32 shadow-map walk (`airlight_kernels::shadowmap::Walk`):
/// `(origin, dir, end, map, node)` → the lit runs `[a, b]` in order (`b < 0`:
/// to infinity), the steps taken, and whether it ran out of steps.
pub type WalkFn = fn([f32; 3], [f32; 3], f32, WalkMap, NodeFn) -> (Vec<[f32; 2]>, u32, bool);

/// The path of the kernel index under `generated/`.
pub const INDEX_FILE: &str = "kernels.toml";

/// A table a kernel reads (a texture in the shaders).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TableRef {
    /// Path under `generated/`: `size × size` little-endian f32, row-major.
    pub path: String,
    /// Texels per side.
    pub size: usize,
}

/// One kernel of the index `generated/kernels.toml`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IndexEntry {
    /// Kernel name (`segments-8`, `scene-fog-street`).
    pub name: String,
    /// The model it evaluates; absent for the exact closed form.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub model: Option<String>,
    /// The scene file it was specialised for, if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scene: Option<String>,
    /// Error domains its declared bound covers.
    pub domains: Vec<Domain>,
    /// Arguments of the canonical entry `<prefix>airlight`, in order.
    pub params: Vec<Arg>,
    /// Arguments of the physical entry `<prefix>radiance`, in order.
    pub radiance_params: Vec<Arg>,
    /// Arguments of the spot entry `<prefix>spot`, in order; empty: it has none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub spot_params: Vec<Arg>,
    /// `g` the kernel takes at run time (both ends equal when baked in).
    pub g: [f64; 2],
    /// Whether rays may end on a surface (else ρ = ∞).
    pub surfaces: bool,
    /// Whether extinction is modelled (else τ = 0).
    pub extinction: bool,
    /// Whether the backward part is kept.
    pub backscatter: bool,
    /// Whether it has the shafts accumulator (shadowed in-scattering).
    #[serde(default)]
    pub shafts: bool,
    /// The plain WGSL file, under `generated/`.
    pub wgsl: Option<String>,
    /// The Bevy variant.
    pub wgsl_bevy: Option<String>,
    /// The GLSL include.
    pub glsl: Option<String>,
    /// The Rust module (its kernel is `airlight_kernels::kernel(name)`).
    pub rust: Option<String>,
    /// Prefix of every item in the plain WGSL and GLSL files.
    pub prefix: String,
    /// The table it reads (bound as a texture in the shaders), if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub table: Option<TableRef>,
    /// Its f32 bound on `thin`, as `airlight check --record` measured it on its
    /// f32 targets (absent: not recorded for these sources; the gate then fails).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub f32_thin_max_rel: Option<f64>,
    /// Its f32 bound on `dense`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub f32_dense_max_rel: Option<f64>,
}

impl IndexEntry {
    /// Its recorded f32 bound on `domain` (`thin` or `dense`).
    pub fn f32_bound(&self, domain: Domain) -> Option<f64> {
        match domain {
            Domain::Thin => self.f32_thin_max_rel,
            Domain::Dense => self.f32_dense_max_rel,
            Domain::Extreme => None,
        }
    }

    /// Whether the kernel can evaluate `p` as it is: `p` in the domain of `A`, and
    /// nothing the kernel was specialised away from (extinction: only `τ = 0`;
    /// surfaces: only `ρ = ∞`; its `g`, or its `g` range) — a kernel would otherwise
    /// evaluate another point than the one asked for, silently.
    pub fn check(&self, p: &airlight_truth::reference::Point) -> Result<(), airlight_truth::reference::ParamError> {
        use airlight_truth::reference::{Param, ParamError};
        p.validate()?;
        let only = |param, value, v: f64| Err(ParamError { param, value, allowed: Some((v, v)) });
        if !self.extinction && p.tau != 0.0 {
            return only(Param::Tau, p.tau, 0.0);
        }
        if !self.surfaces && p.rho.is_finite() {
            return only(Param::Rho, p.rho, f64::INFINITY);
        }
        if p.g < self.g[0] || p.g > self.g[1] {
            return Err(ParamError { param: Param::G, value: p.g, allowed: Some((self.g[0], self.g[1])) });
        }
        Ok(())
    }

    /// The physical entry's [`IndexEntry::check`]: a ray with `g` that this kernel's
    /// `radiance` evaluates as given — σt = 0 without extinction, no surface
    /// without surfaces, `g` in its range. The error names the column.
    pub fn check_ray(&self, ray: &airlight_truth::geometry::PhysicalRay, g: f64) -> Result<(), (&'static str, String)> {
        // The f32 contract: what an f32 argument cannot hold is refused. A surface or
        // σt past f32's range is handled exactly instead (no surface; no light
        // through), and so is one below it (0 and e^0 = 1 to f32).
        let (o, d, l) = (ray.origin, ray.direction, ray.light);
        let named = [
            ("ox", o[0]),
            ("oy", o[1]),
            ("oz", o[2]),
            ("dx", d[0]),
            ("dy", d[1]),
            ("dz", d[2]),
            ("lx", l[0]),
            ("ly", l[1]),
            ("lz", l[2]),
            ("intensity", ray.intensity),
            ("sigma_s", ray.sigma_s),
        ];
        for (col, x) in named {
            if let Some(m) = airlight_truth::points_csv::beyond_f32(col, x) {
                return Err((col, m));
            }
        }
        if !self.extinction && ray.sigma_t != 0.0 {
            return Err(("sigma_t", format!("kernel {} ignores extinction: it takes only sigma_t = 0", self.name)));
        }
        if !self.surfaces && ray.surface_distance.is_some() {
            return Err((
                "surface",
                format!("kernel {} has no surfaces: it takes only surface = inf or < 0", self.name),
            ));
        }
        if g < self.g[0] || g > self.g[1] {
            let p = airlight_truth::reference::Point { tau: 0.0, gamma: 0.0, rho: f64::INFINITY, g };
            return Err(("g", self.check(&p).err().map(|e| e.to_string()).unwrap_or_default()));
        }
        Ok(())
    }

    /// The arguments of `entry`.
    pub fn args(&self, entry: Entry) -> &[Arg] {
        match entry {
            Entry::Canonical => &self.params,
            Entry::Radiance => &self.radiance_params,
            Entry::Spot => &self.spot_params,
        }
    }

    /// Whether it has `entry` (every kernel has the canonical and physical ones).
    pub fn has(&self, entry: Entry) -> bool {
        entry != Entry::Spot || !self.spot_params.is_empty()
    }

    /// The file of `target` under `generated/` (the plain WGSL for [`Target::Wgsl`]).
    pub fn file(&self, target: Target) -> Option<&str> {
        match target {
            Target::Wgsl => self.wgsl.as_deref(),
            Target::Glsl => self.glsl.as_deref(),
            Target::Rust => self.rust.as_deref(),
        }
    }
}

/// The whole index.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Index {
    /// Every kernel, models first, then scenes.
    pub kernel: Vec<IndexEntry>,
}

impl Index {
    /// Reads the text of `generated/kernels.toml`.
    pub fn parse(file: &str, text: &str) -> Result<Index, airlight_truth::tomlfile::FieldError> {
        airlight_truth::tomlfile::from_str(file, text, "kernel")
    }

    /// Reads `generated/kernels.toml` under `generated`.
    pub fn load(generated: &std::path::Path) -> Result<Index, airlight_truth::tomlfile::FieldError> {
        let (name, text) = airlight_truth::tomlfile::read(&generated.join(INDEX_FILE), " (run `airlight generate`)")?;
        Index::parse(&name, &text)
    }

    /// The kernel called `name`, or an error listing the ones there are.
    pub fn get(&self, name: &str) -> Result<&IndexEntry, String> {
        self.kernel.iter().find(|k| k.name == name).ok_or_else(|| {
            let known: Vec<&str> = self.kernel.iter().map(|k| k.name.as_str()).collect();
            format!("no generated kernel '{name}'; kernels: {}", known.join(", "))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_unknown_names_are_errors() {
        for t in Target::ALL {
            assert_eq!(t.name().parse::<Target>(), Ok(t));
        }
        let e = "hlsl".parse::<Target>().unwrap_err().to_string();
        assert_eq!(e, "unknown target 'hlsl' (known: wgsl, glsl, rust)");
        for entry in Entry::ALL {
            let mut used = Vec::new();
            for a in entry.all_args() {
                let (v, lane) = a.slot(entry).expect("every argument of an entry has a slot");
                let width = if a.ty() == ArgType::Vec3 { 3 } else { 1 };
                assert!(v < entry.packed_vec4s() && lane + width <= 4, "{a} fits its vec4");
                for l in lane..lane + width {
                    assert!(!used.contains(&(v, l)), "{a} overlaps another argument");
                    used.push((v, l));
                }
            }
        }
        assert_eq!(f32_limit(0.0), F32_ALLOWANCE);
    }
}
