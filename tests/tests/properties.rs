//! Property tests (proptest, fixed case counts, no persistence) over the whole
//! parameter space, for every committed model's f64 evaluator and every
//! generated Rust f32 kernel, on both of its entries:
//!
//! - finite and ≥ 0 for every input a renderer can pass (the kernels' `HUGE`
//!   only where `A` diverges or the value passes f32's range);
//! - non-increasing in τ and non-decreasing in ρ at fixed geometry (more medium
//!   dims, more lit ray adds), up to each evaluator's rounding;
//! - no jump across a branch, segment or band boundary larger than the declared
//!   bound: γ across π/2 (where the backward part changes form), ρ across the
//!   foot point and across the u-split of the backward weight, g across every
//!   band edge, γ across every segment breakpoint;
//! - Henyey–Greenstein: the phase terms at −g are those at g seen from the back
//!   (`P_{−g}(α) = P_g(π − α)`).

use airlight_fit::coeffs::ModelFile;
use airlight_fit::family::Body;
use airlight_fit::model::Model;
use airlight_kernels::{Kernel, KERNELS};
use airlight_shapes::vocab::{Domain, Index, IndexEntry};
use airlight_tests::{committed_models, generated_dir};
use airlight_truth::reference::Point;
use proptest::prelude::*;
use std::f64::consts::PI;
use std::sync::OnceLock;

fn models() -> &'static [ModelFile] {
    static MODELS: OnceLock<Vec<ModelFile>> = OnceLock::new();
    MODELS.get_or_init(committed_models)
}

fn index() -> &'static Index {
    static INDEX: OnceLock<Index> = OnceLock::new();
    INDEX.get_or_init(|| Index::load(&generated_dir()).expect("generated/kernels.toml loads"))
}

/// Every compiled kernel with its index entry.
fn kernels() -> impl Iterator<Item = (&'static Kernel, &'static IndexEntry)> {
    KERNELS.iter().map(|k| (k, index().get(k.name).expect("every compiled kernel is in the index")))
}

/// The declared bound of a model over thin ∪ dense.
fn declared(m: &ModelFile) -> f64 {
    [Domain::Thin, Domain::Dense].iter().filter_map(|&d| m.error(d)).map(|e| e.max_rel).fold(0.0, f64::max)
}

fn g_of(range: (f64, f64), u: f64) -> f64 {
    range.0 + (range.1 - range.0) * u
}

/// How far a model may step against monotonicity, relative. An isotropic split
/// model is monotone by construction — positive exponential terms decaying in
/// τ, limits growing with ρ — up to its approximants of the backward weight: a
/// surface moves the backward part from one (the exponential sum for `1/y²` on a
/// short far part) to another (the exact φ form), each within its own fitted
/// error of `w`, so to twice the larger of those (plus φ's 2e-7). Where the phase
/// is taken at mean points that move with τ and ρ (the HG families), or the
/// backscatter is the paper's cubic ratio fit, only what the declared bound
/// implies holds: two values each within `b` of a monotone `A` are ordered up to
/// `(1 + b)/(1 − b)` (hg-exp1 steps 0.27% at τ = 21.5, γ = 2.19).
fn monotone_slack(m: &ModelFile) -> f64 {
    use airlight_fit::family::split::expsum::Target;
    let isotropic = m.model.g_range == (0.0, 0.0);
    let s = match &m.model.body {
        Body::Split(s) => s,
        // Exact, and monotone: τ only dropped, ρ an angle growing with it.
        Body::NoExtinction(_) => return 1e-6,
        // Quadrature rules move their nodes with τ and ρ (a march also its
        // cut-off and step): nothing is promised.
        _ => return f64::INFINITY,
    };
    if isotropic && s.ratio.is_none() {
        2.0 * s.expsum.near.error(Target::Near).0.max(s.expsum.local.error(Target::Local).0) + 1e-6
    } else {
        let b = declared(m);
        if b < 1.0 {
            (1.0 + b) / (1.0 - b) - 1.0
        } else {
            f64::INFINITY
        }
    }
}

/// The slack of a kernel: its model's, or at least f32's (2e-5).
fn kernel_slack(e: &IndexEntry) -> f64 {
    let model = models().iter().find(|m| Some(&m.model.name) == e.model.as_ref());
    model.map_or(0.0, monotone_slack).max(2e-5)
}

/// `true` when `later ≤ earlier` up to a relative `rel` and an absolute `abs`.
fn not_above(later: f64, earlier: f64, rel: f64, abs: f64) -> bool {
    if rel.is_infinite() {
        return true;
    }
    later <= earlier * (1.0 + rel) + abs
}

/// f32 inputs over the whole range: τ from 0 to beyond f32's overflow of σt·D, γ
/// on the axis, grazing and across, ρ from the viewer to `f32::MAX` and `+∞`.
fn f32_canonical() -> impl Strategy<Value = (f32, f32, f32, f64)> {
    (
        prop_oneof![Just(0.0f32), 1e-30f32..1e-3, 1e-3f32..20.0, 20.0f32..1e4, Just(f32::MAX)],
        prop_oneof![Just(0.0f32), 1e-30f32..1e-4, 1e-4f32..std::f32::consts::PI, Just(std::f32::consts::PI)],
        prop_oneof![
            Just(-1.0f32),
            Just(0.0f32),
            1e-30f32..1e-2,
            1e-2f32..1e2,
            1e2f32..1e30,
            Just(f32::MAX),
            Just(f32::INFINITY)
        ],
        0.0..1.0f64,
    )
}

/// Finite f32 component magnitudes from subnormal-free tiny to huge, either sign.
fn coord() -> impl Strategy<Value = f32> {
    prop_oneof![Just(0.0f32), -1e3f32..1e3, -1e30f32..1e30, (1e-30f32..1e-20).prop_map(|x| -x)]
}

fn vec3() -> impl Strategy<Value = [f32; 3]> {
    [coord(), coord(), coord()]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 1500, failure_persistence: None, ..ProptestConfig::default() })]

    /// Both entries of every kernel: finite and ≥ 0 for any input.
    #[test]
    fn kernels_are_finite_and_non_negative(
        (tau, gamma, rho, u) in f32_canonical(),
        origin in vec3(), dir in vec3(), light in vec3(),
        surface in prop_oneof![Just(-1.0f32), Just(0.0f32), 0.0f32..1e3, 1e3f32..f32::MAX, Just(f32::INFINITY)],
        intensity in prop_oneof![Just(0.0f32), 1e-3f32..1e6, Just(1e30f32)],
        (sigma_t, sigma_s) in (prop_oneof![Just(0.0f32), 1e-30f32..1e3, Just(1e30f32)],
                               prop_oneof![Just(0.0f32), 1e-30f32..1e3, Just(1e30f32)]),
    ) {
        for (k, e) in kernels() {
            let g = g_of((e.g[0], e.g[1]), u) as f32;
            let a = (k.airlight)(tau, gamma, rho, g);
            prop_assert!(a.is_finite() && a >= 0.0, "{}: airlight({tau}, {gamma}, {rho}, {g}) = {a}", k.name);
            let r = (k.radiance)(origin, dir, surface, light, intensity, sigma_t, sigma_s, g);
            prop_assert!(
                r.is_finite() && r >= 0.0,
                "{}: radiance({origin:?}, {dir:?}, {surface}, {light:?}, {intensity}, {sigma_t}, {sigma_s}, {g}) = {r}",
                k.name
            );
        }
    }
}

/// A σ from none through tiny to huge.
fn sigma() -> impl Strategy<Value = f32> {
    prop_oneof![Just(0.0f32), 1e-30f32..1e3, Just(1e30f32)]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 600, failure_persistence: None, ..ProptestConfig::default() })]

    /// The spot entry of every kernel that has one: finite and ≥ 0 in every
    /// channel for any input — any axis (zero too), cosines from a point light
    /// (−1) through cones past 90° to degenerate ones (inner below outer, above 1).
    #[test]
    fn spot_entries_are_finite_and_non_negative(
        origin in vec3(), dir in vec3(), light in vec3(), axis in vec3(),
        surface in prop_oneof![Just(-1.0f32), Just(0.0f32), 0.0f32..1e3, 1e3f32..f32::MAX, Just(f32::INFINITY)],
        cos_outer in prop_oneof![Just(-1.0f32), -1.0f32..0.0, 0.0f32..1.0, 0.999f32..1.0, Just(1.0f32)],
        cos_inner in prop_oneof![Just(-1.0f32), 0.0f32..1.0, 0.999f32..1.0, Just(1.0f32), Just(2.0f32)],
        intensity in prop_oneof![Just(0.0f32), 1e-3f32..1e6, Just(1e30f32)],
        sigma_t in [sigma(), sigma(), sigma()],
        sigma_s in [sigma(), sigma(), sigma()],
        u in 0.0..1.0f64,
    ) {
        for (k, e) in kernels() {
            let Some(spot) = k.spot else { continue };
            let g = g_of((e.g[0], e.g[1]), u) as f32;
            let r = spot(origin, dir, surface, light, axis, cos_outer, cos_inner, intensity, sigma_t, sigma_s, g);
            prop_assert!(
                r.iter().all(|v| v.is_finite() && *v >= 0.0),
                "{}: spot({origin:?}, {dir:?}, {surface}, {light:?}, {axis:?}, {cos_outer}, {cos_inner}, {intensity}, {sigma_t:?}, {sigma_s:?}, {g}) = {r:?}",
                k.name
            );
        }
    }
}

fn geometry() -> impl Strategy<Value = (f64, f64, f64)> {
    (
        prop_oneof![1e-6..1e-2f64, 1e-2..PI - 1e-2, (1e-6..1e-2f64).prop_map(|d| PI - d)],
        prop_oneof![1e-4..1e-2f64, 1e-2..1e2f64, 1e2..1e4f64],
        0.0..1.0f64,
    )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 600, failure_persistence: None, ..ProptestConfig::default() })]

    /// More medium dims: A is non-increasing in τ (f64: to 1e-9; f32: to 1e-5).
    #[test]
    fn non_increasing_in_tau((gamma, rho, u) in geometry(), t1 in 0.0..30.0f64, dt in 0.0..30.0f64) {
        let t2 = t1 + dt;
        for m in models() {
            let p = Point { tau: t1, gamma, rho, g: g_of(m.model.g_range, u) };
            let (a1, a2) = (m.model.eval_unchecked(p), m.model.eval_unchecked(Point { tau: t2, ..p }));
            prop_assert!(not_above(a2, a1, monotone_slack(m), 1e-300), "{}: A({t2}) = {a2:e} > A({t1}) = {a1:e} at {p:?}", m.model.name);
        }
        for (k, e) in kernels().filter(|(_, e)| e.extinction) {
            let g = g_of((e.g[0], e.g[1]), u) as f32;
            let r = if e.surfaces { rho as f32 } else { -1.0 };
            let (a1, a2) = ((k.airlight)(t1 as f32, gamma as f32, r, g), (k.airlight)(t2 as f32, gamma as f32, r, g));
            prop_assert!(
                not_above(f64::from(a2), f64::from(a1), kernel_slack(e), 1e-37),
                "{}: A({t2}) = {a2:e} > A({t1}) = {a1:e} at γ {gamma}, ρ {rho}, g {g}", k.name
            );
        }
    }

    /// More lit ray adds: A is non-decreasing in ρ (f64: to 1e-9; f32: to 1e-5).
    #[test]
    fn non_decreasing_in_rho((gamma, rho, u) in geometry(), tau in 0.0..30.0f64, f in 1.0..100.0f64) {
        let r2 = rho * f;
        for m in models() {
            let p = Point { tau, gamma, rho, g: g_of(m.model.g_range, u) };
            let (a1, a2) = (m.model.eval_unchecked(p), m.model.eval_unchecked(Point { rho: r2, ..p }));
            prop_assert!(not_above(a1, a2, monotone_slack(m), 1e-300), "{}: A(ρ {r2}) = {a2:e} < A(ρ {rho}) = {a1:e} at {p:?}", m.model.name);
            let open = m.model.eval_unchecked(Point { rho: f64::INFINITY, ..p });
            prop_assert!(not_above(a2, open, monotone_slack(m), 1e-300), "{}: A(ρ {r2}) = {a2:e} > A(∞) = {open:e} at {p:?}", m.model.name);
        }
        for (k, e) in kernels().filter(|(_, e)| e.surfaces) {
            let g = g_of((e.g[0], e.g[1]), u) as f32;
            let t = if e.extinction { tau as f32 } else { 0.0 };
            let (a1, a2) = ((k.airlight)(t, gamma as f32, rho as f32, g), (k.airlight)(t, gamma as f32, r2 as f32, g));
            prop_assert!(
                not_above(f64::from(a1), f64::from(a2), kernel_slack(e), 1e-37),
                "{}: A(ρ {r2}) = {a2:e} < A(ρ {rho}) = {a1:e} at τ {t}, γ {gamma}, g {g}", k.name
            );
        }
    }
}

/// The boundaries where a split model changes branch, segment or band, at a
/// base point `p`: pairs of points just either side.
fn boundaries(m: &ModelFile, p: Point) -> Vec<(&'static str, Point, Point)> {
    let d = 1e-9;
    let mut out = vec![
        ("γ = π/2", Point { gamma: PI / 2.0 - d, ..p }, Point { gamma: PI / 2.0 + d, ..p }),
        // The surface at the foot point (ρ = cos γ).
        (
            "ρ = cos γ",
            Point { rho: p.gamma.cos().abs() * (1.0 - d), ..p },
            Point { rho: p.gamma.cos().abs() * (1.0 + d), ..p },
        ),
    ];
    if let Body::Split(s) = &m.model.body {
        // Every breakpoint θ_j of the forward kernel, as γ = π/2 − θ_j (the
        // forward part starts there).
        for &th in &s.forward.breakpoints[1..s.forward.breakpoints.len() - 1] {
            let g0 = PI / 2.0 - th;
            out.push(("segment breakpoint", Point { gamma: g0 - d, ..p }, Point { gamma: g0 + d, ..p }));
        }
        // The u-split of the backward weight: a surface at u = 16 behind the foot point.
        let (h, x0) = (p.gamma.sin(), p.gamma.cos());
        let u = airlight_fit::family::split::expsum::SPLIT;
        let rho = x0 + h * (u * u - 1.0) / (2.0 * u);
        if rho > 0.0 {
            out.push(("u = SPLIT", Point { rho: rho * (1.0 - d), ..p }, Point { rho: rho * (1.0 + d), ..p }));
        }
        if let airlight_fit::family::split::PhaseModel::Exp(e) = &s.phase {
            if m.model.g_range.0 < 0.0 {
                out.push(("g = 0 (mirroring)", Point { g: -d, ..p }, Point { g: d, ..p }));
            }
            for b in &e.bands[..e.bands.len() - 1] {
                for sign in [1.0, -1.0] {
                    let g = sign * b.g_hi;
                    if (m.model.g_range.0..=m.model.g_range.1).contains(&(g - d))
                        && (m.model.g_range.0..=m.model.g_range.1).contains(&(g + d))
                    {
                        out.push(("band edge", Point { g: g - d, ..p }, Point { g: g + d, ..p }));
                    }
                }
            }
        }
    }
    out
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, failure_persistence: None, ..ProptestConfig::default() })]

    /// Across every boundary, a jump no larger than the model's declared bound
    /// (thin ∪ dense, where the boundaries lie).
    #[test]
    fn no_jump_across_boundaries(
        tau in 0.0..20.0f64,
        gamma in 0.01..PI - 0.01,
        rho in prop_oneof![Just(f64::INFINITY), 0.01..100.0f64],
        u in 0.0..1.0f64,
    ) {
        for m in models() {
            let p = Point { tau, gamma, rho, g: g_of(m.model.g_range, u) };
            let bound = declared(m);
            for (what, a, b) in boundaries(m, p) {
                let (va, vb) = (m.model.eval_unchecked(a), m.model.eval_unchecked(b));
                // Both 0 (a table whose lookups cancel to nothing): no jump.
                let jump = if va == vb { 0.0 } else { (va - vb).abs() / va.max(vb) };
                prop_assert!(jump <= bound + 1e-6, "{}: {what}: jump {jump:.2e} > bound {bound:.2e} between {a:?} and {b:?}", m.model.name);
            }
        }
    }

    /// Henyey–Greenstein: the f64 phase terms at −g are those at g seen from the
    /// back, `P_{−g}(α) = P_g(π − α)` (g ≠ 0: at 0 the fitted terms are only
    /// nearly isotropic, a step the boundary test bounds); and every f32 kernel
    /// taking g agrees with its f64 model at g and at −g alike (within the f32
    /// allowance), so its own mirroring is the model's.
    #[test]
    fn hg_mirror_is_consistent(u in 1e-3..1.0f64, alpha in 0.0..PI, (tau, gamma, rho) in (0.0..20.0f64, 0.01..PI - 0.01, prop_oneof![Just(f64::INFINITY), 0.01..100.0f64])) {
        for m in models() {
            let Body::Split(s) = &m.model.body else { continue };
            let airlight_fit::family::split::PhaseModel::Exp(e) = &s.phase else { continue };
            let (lo, hi) = m.model.g_range;
            if lo >= 0.0 {
                continue;
            }
            let g = g_of((0.0, hi.min(-lo)), u);
            let (front, back) = (e.terms(g).eval(alpha), e.terms(-g).eval(PI - alpha));
            prop_assert!((front - back).abs() <= 1e-12 * front.abs(), "{}: P_{g}({alpha}) = {front} but P_-{g}(π − {alpha}) = {back}", m.model.name);
        }
        for (k, e) in kernels().filter(|(_, e)| e.g[0] < 0.0 && e.g[1] > 0.0) {
            let m = models().iter().find(|m| Some(&m.model.name) == e.model.as_ref()).expect("a g kernel has its model");
            let g = g_of((0.0, e.g[1].min(-e.g[0])), u);
            let r = if e.surfaces { rho } else { f64::INFINITY };
            for g in [g, -g] {
                let p = Point { tau, gamma, rho: r, g };
                let want = m.model.eval_unchecked(p);
                let got = f64::from((k.airlight)(tau as f32, gamma as f32, airlight_shapes::vocab::rho_arg(r), g as f32));
                // The f32 inputs move A by their rounding: compare at the model's
                // own value of the rounded point.
                let p32 = Point { tau: f64::from(tau as f32), gamma: f64::from(gamma as f32), rho: r, g: f64::from(g as f32) };
                let want32 = m.model.eval_unchecked(p32);
                if !(1e-30..1e30).contains(&want32) {
                    continue; // beyond f32's range
                }
                let rel = (got - want32).abs() / want32;
                prop_assert!(rel <= airlight_shapes::vocab::F32_ALLOWANCE, "{}: g {g}: f32 {got:e} vs f64 {want32:e} ({want:e} unrounded), {rel:.2e} at {p:?}", k.name);
            }
        }
    }
}

/// Inputs the fuzzers found (fuzz/corpus/*/regression-*), kept: each was a bad
/// value before its fix.
#[test]
fn fuzz_findings_stay_fixed() {
    // kernel_canonical: hg-exp3's phase terms, each subnormal at τ = 101.8,
    // cancelled to −3.5e-44; a phase ≥ 0 now sums to ≥ 0.
    let bits: [u32; 4] = [0x42cb_a400, 0x3d24_c7c3, 0xff03_ff00, 0xbdba_2e7e];
    let [tau, gamma, rho, g] = bits.map(f32::from_bits);
    for (k, _) in kernels() {
        let v = (k.airlight)(tau, gamma, rho, g);
        assert!(v.is_finite() && v >= 0.0, "{}: {v}", k.name);
    }
}
