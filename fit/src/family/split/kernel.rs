//! What the split family's core templates (`core.*.tera` here) need: segments
//! re-expressed in α, the backward sums, the ratio, the phase (isotropic, baked
//! or banded), and the Rust imports.

use super::expsum::{ExpSum, LOCAL_RATIO, SPLIT};
use super::phase_exp::ExpPhase;
use super::{PhaseModel, Split};
use airlight_shapes::template::{lit, lits, Context, KernelPhase, KernelView, WantPhase};
use airlight_shapes::vocab::Target;
use serde::Serialize;
use std::f64::consts::FRAC_PI_2;

#[derive(Serialize)]
struct Seg {
    lo: String,
    hi: String,
    slope: String,
    icpt: String,
}

#[derive(Serialize)]
struct Term {
    c: String,
    s: String,
}

#[derive(Serialize)]
struct BandCtx {
    g_hi: String,
    g_mid: String,
    a: Vec<Vec<String>>,
    b: Vec<Vec<String>>,
}

#[derive(Serialize)]
struct FixedCtx {
    c: Vec<String>,
    b: Vec<String>,
    mirrored: bool,
}

#[derive(Serialize)]
struct RatioCtx {
    f: Vec<String>,
    g: Vec<String>,
    h: Vec<String>,
}

/// The phase of a split kernel: isotropic models fold `1/(4π)` in; fitted phases
/// bake one `g` or keep the bands a scene's `g` range can reach.
pub(super) fn kernel_phase(s: &Split, want: WantPhase) -> KernelPhase {
    let e = match &s.phase {
        PhaseModel::Isotropic => return KernelPhase::Isotropic,
        PhaseModel::Exp(e) => e,
    };
    match want {
        WantPhase::General => KernelPhase::Banded((0..e.bands.len()).collect()),
        WantPhase::Isotropic => KernelPhase::Isotropic,
        WantPhase::Fixed(g) => KernelPhase::Fixed(g),
        WantPhase::Range(lo, hi) => {
            let (alo, ahi) = if lo <= 0.0 && hi >= 0.0 {
                (0.0, lo.abs().max(hi.abs()))
            } else {
                (lo.abs().min(hi.abs()), lo.abs().max(hi.abs()))
            };
            KernelPhase::Banded(
                (0..e.bands.len())
                    .filter(|&i| {
                        let b = &e.bands[i];
                        // the band search takes the first band whose top reaches |g|
                        let below = if i == 0 { f64::NEG_INFINITY } else { e.bands[i - 1].g_hi };
                        (b.g_hi >= alo || i + 1 == e.bands.len()) && below < ahi
                    })
                    .collect(),
            )
        }
    }
}

/// The segments in α = π/2 − θ', increasing in α.
fn segments(sp: &Split) -> Vec<Seg> {
    let s = &sp.forward;
    (0..s.n())
        .rev()
        .map(|j| Seg {
            lo: lit(FRAC_PI_2 - s.breakpoints[j + 1]),
            hi: lit(FRAC_PI_2 - s.breakpoints[j]),
            slope: lit(-s.slopes[j]),
            icpt: lit(s.intercepts[j] + s.slopes[j] * FRAC_PI_2),
        })
        .collect()
}

fn terms(e: &ExpSum) -> Vec<Term> {
    e.c.iter().zip(&e.s).map(|(&c, &s)| Term { c: lit(c), s: lit(s) }).collect()
}

/// The phase's values: `("isotropic" | "fixed" | "banded", terms)`.
fn phase(ctx: &mut Context, k: &KernelView, exp: Option<&ExpPhase>) -> (&'static str, usize) {
    match (k.phase, exp) {
        (KernelPhase::Isotropic | KernelPhase::Exact, _) | (_, None) => ("isotropic", 1),
        (KernelPhase::Fixed(g), Some(e)) => {
            let t = e.terms(*g);
            ctx.insert(
                "fixed",
                &FixedCtx {
                    c: t.terms.iter().map(|x| lit(x.0)).collect(),
                    b: t.terms.iter().map(|x| lit(x.1)).collect(),
                    mirrored: t.mirrored,
                },
            );
            ctx.insert("fixed_g", &format!("{g}"));
            ("fixed", e.k())
        }
        (KernelPhase::Banded(which), Some(e)) => {
            let bands: Vec<BandCtx> = which
                .iter()
                .map(|&i| {
                    let b = &e.bands[i];
                    // Re-centred on the band's middle: the paper's quadratics cancel
                    // to 1e-5 in f32 when evaluated in g itself (b ≈ 7e4 g² − 1.5e5 g + 7e4).
                    let mid = 0.5 * (b.g_lo + b.g_hi);
                    let centre =
                        |r: &[f64; 3]| lits(&[r[0], r[1] + 2.0 * r[0] * mid, r[2] + (r[1] + r[0] * mid) * mid]);
                    BandCtx {
                        g_hi: lit(b.g_hi),
                        g_mid: lit(mid),
                        a: b.a.iter().map(centre).collect(),
                        b: b.b.iter().map(centre).collect(),
                    }
                })
                .collect();
            ctx.insert("bands", &bands);
            ctx.insert("phase_scale", &lit(e.scale));
            ("banded", e.k())
        }
    }
}

/// The Rust module's imports: exactly what the kernel uses.
fn rust_imports(ctx: &mut Context, sp: &Split, k: &KernelView, iso: bool) {
    let mut math = vec![
        "atan2",
        "exp",
        "exp_neg_parts",
        "exprel",
        "mul_exp_neg",
        "ray_geometry",
        "scaled",
        "scaled_pow2",
        "sin_cos",
        "HUGE",
        "TAU_MAX",
    ];
    if k.surfaces {
        math.push("RHO_OPEN");
        if k.backscatter {
            math.push("sqrt");
        }
    }
    if k.backscatter {
        math.push("phi");
        if !iso {
            math.push("atan");
        }
    }
    if k.backscatter && sp.ratio.is_some() {
        math.push("ln");
    }
    math.sort_by_key(|s| s.to_lowercase());
    ctx.insert("math_imports", &math.join(", "));
    let mut consts = Vec::new();
    if k.backscatter && sp.ratio.is_some() {
        consts.push("FRAC_PI_2");
    }
    if !iso {
        consts.push("PI");
    }
    ctx.insert("const_imports", &consts.join(", "));
}

/// Everything the split family's core templates need for `k`.
pub(super) fn context(sp: &Split, k: &KernelView) -> Context {
    let iso = *k.phase == KernelPhase::Isotropic;
    let mut ctx = Context::new();
    let (name, summary) = (k.model_name.unwrap_or_default(), k.model_summary.unwrap_or_default());
    ctx.insert("summary", &format!("the `{name}` model ({summary}), specialised: {}.", k.specialisations));
    // The shared math include: exprel for the forward part, φ for the backward sums.
    ctx.insert("needs_exprel", &true);
    ctx.insert("needs_phi", &k.backscatter);
    ctx.insert("segs", &segments(sp));
    ctx.insert("near", &terms(&sp.expsum.near));
    ctx.insert("local", &terms(&sp.expsum.local));
    ctx.insert("split", &lit(SPLIT));
    ctx.insert("split_doc", &SPLIT);
    ctx.insert("local_ratio_doc", &LOCAL_RATIO);
    ctx.insert("local_ratio", &lit(LOCAL_RATIO));
    ctx.insert("attenuate", &sp.forward_attenuation);
    let ratio = sp.ratio.as_ref().map(|r| RatioCtx { f: lits(&r.f), g: lits(&r.g), h: lits(&r.h) });
    ctx.insert("ratio", &ratio);
    let exp = match &sp.phase {
        PhaseModel::Exp(e) => Some(e),
        PhaseModel::Isotropic => None,
    };
    let (phase, terms) = phase(&mut ctx, k, exp);
    ctx.insert("phase", phase);
    ctx.insert("k", &terms);
    rust_imports(&mut ctx, sp, k, iso);
    let (ph_param, ph_arg) = match (iso, k.target) {
        (true, _) => (String::new(), String::new()),
        (false, Target::Rust) => (", ph: &Phase".to_string(), ", &ph".to_string()),
        (false, Target::Wgsl) => (format!(", ph: {}Phase", k.prefix), ", ph".to_string()),
        (false, Target::Glsl) => (format!(", {}Phase ph", k.prefix), ", ph".to_string()),
    };
    ctx.insert("ph_param", &ph_param);
    ctx.insert("ph_arg", &ph_arg);
    ctx
}
