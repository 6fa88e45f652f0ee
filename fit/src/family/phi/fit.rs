//! The φ family's fit (`eˣE₂`'s rational; the rules are Gauss's and the splits
//! the tier's) and the assembly of a member from its tier.

use super::{E2Fit, PhiRule, E2_DEGREE, EIN_TERMS};
use crate::family::{phase_label, Assembled};
use crate::tomlfile::value::{f, i, kv, s};

/// The part `airlight fit --family phi` names.
pub const PART: &str = "phi";

/// The parameters of one member of the φ family (`fit/src/family/phi/`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhiTier {
    /// Head nodes (Gauss–Legendre in φ).
    pub head: usize,
    /// Far-correction nodes (Gauss–Legendre in `v = 1/u`).
    pub far: usize,
    /// Tail nodes (Gauss–Laguerre).
    pub tail: usize,
    /// `L`: the head's transmittance cut.
    pub cut: f64,
    /// The far correction's transmittance cut.
    pub far_cut: f64,
}

/// A member of the φ family (errors not yet measured): the rules are Gauss's, the
/// splits the tier's, `eˣE₂` fitted.
pub fn assemble(t: PhiTier, g_range: (f64, f64), fit: Option<&E2Fit>) -> Result<Assembled<PhiRule>, String> {
    let fit = fit.ok_or("the phi family's e^x E2 was not fitted")?;
    let rule = PhiRule::new(t.head, t.far, t.tail, t.cut, t.far_cut, fit.e2.clone());
        let families = vec![
        format!(
            "phi-{} ({}-point Gauss-Legendre head, {}-point far correction, {}-point Gauss-Laguerre tail)",
            t.head, t.head, t.far, t.tail
        ),
        phase_label(g_range),
    ];
    let provenance = vec![
        (
            "e2.fit".into(),
            kv(vec![
                ("source", s("this project: e^x E2(x) = 1 - x e^x E1(x); Ein's Taylor series below x = 1, a rational in t = 1/x beyond")),
                ("target", s("e^x E2(x), x >= 1, through the reference complex E1 (fit/src/e1.rs, about 1e-15)")),
                ("form", s(&format!("t P(t)/Q(t), P, Q of degree {E2_DEGREE} with unit constant terms; Ein to x^{EIN_TERMS}"))),
                ("objective", s("relative error, linearised (Sanathanan-Koerner): each step linear least squares by SVD (nalgebra 0.34), weighted by the previous denominator")),
                ("points", i(fit.points)),
                ("points_from", s("Chebyshev points of t = 1/x in (0, 1]")),
                ("iterations", i(fit.iterations)),
                ("max_rel", f(fit.max_rel.0)),
                ("max_rel_at_x", f(fit.max_rel.1)),
                ("series_max_rel", f(fit.series_max_rel.0)),
                ("series_max_rel_at_x", f(fit.series_max_rel.1)),
            ]),
        ),
    ];
    Ok(Assembled {
        body: rule,
        families,
        provenance,
        method: kv(vec![
            ("method", s("whole A in the u form: Gauss-Legendre head in the HG variable phi (u past X or on short intervals) to the transmittance cut e^-L, Gauss-Laguerre tail from both ends; for small T X, C/u^2 exactly through e^x E2 and the rest by Gauss-Legendre in v = 1/u (fit/src/family/phi/)")),
            ("fitted", s("e^x E2's rational (see [e2.fit]); node counts and splits are the tier's")),
        ]),
    })
}

/// What `airlight fit --family phi` prints.
pub fn summary(fit: &E2Fit) -> String {
    format!(
        "phi e^x E2 (x >= 1): t P(t)/Q(t), degree {E2_DEGREE}/{E2_DEGREE}, {} Chebyshev points, {} Sanathanan-Koerner iterations: max rel {:.2e} at x = {:.4}; Ein series to x^{EIN_TERMS} below 1: max rel {:.2e} at x = {:.4}",
        fit.points, fit.iterations, fit.max_rel.0, fit.max_rel.1, fit.series_max_rel.0, fit.series_max_rel.1
    )
}
