//! Error surfaces behind the report's figures: each family's own error over its
//! own variables, against exact quadrature.

use crate::family::split::ratio::{exact_backward, Ratio};
use crate::family::split::segments::{exact_forward, Segments};
use std::f64::consts::FRAC_PI_2;

/// Relative error of `∫₀^θ e^{−T k̂}` over the grid `ts × thetas` (row per T),
/// as in the paper's Fig. 4 (its `θ` is `π/2 − γ`).
pub fn forward_error_grid(seg: &Segments, ts: &[f64], thetas: &[f64]) -> Vec<Vec<f64>> {
    let cells: Vec<(f64, f64)> = ts.iter().flat_map(|&t| thetas.iter().map(move |&th| (t, th))).collect();
    let errs = crate::parallel::map(
        &cells,
        |&(t, th)| (seg.integrate(0.0, th, t, 0.0, 0.0) / exact_forward(t, 0.0, th) - 1.0).abs(),
        &|_, _| {},
    );
    errs.chunks(thetas.len()).map(<[f64]>::to_vec).collect()
}

/// Relative error of the backward integral `ratio(θ1, κ) · ∫₀^{π/2} e^{−κ(sec − tan)}`
/// against `∫₀^{θ1} e^{−κ(sec + tan)}`, per `θ1` (rows) and `κ` (columns).
pub fn ratio_error_grid(r: &Ratio, theta1s: &[f64], kappas: &[f64]) -> Vec<Vec<f64>> {
    theta1s
        .iter()
        .map(|&th| {
            kappas
                .iter()
                .map(|&k| {
                    let approx = r.eval(th, k) * exact_forward(k, 0.0, FRAC_PI_2);
                    (approx / exact_backward(k, 0.0, th) - 1.0).abs()
                })
                .collect()
        })
        .collect()
}

/// `n` points from `lo` to `hi`, evenly spaced.
pub fn linspace(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    (0..n).map(|i| lo + (hi - lo) * i as f64 / (n - 1) as f64).collect()
}

/// `n` points from `lo` to `hi` (both > 0), evenly spaced in the logarithm.
pub fn logspace(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    (0..n).map(|i| lo * (hi / lo).powf(i as f64 / (n - 1) as f64)).collect()
}

/// docs/MATH.md §4's grid: isotropic, γ ∈ [0.05, 1.5] (61 values), ρ ∈ {1.5, 3, ∞}.
pub fn math_grid(tau: f64) -> Vec<crate::reference::Point> {
    (0..=60)
        .flat_map(|i| {
            let gamma = 0.05 + 1.45 * i as f64 / 60.0;
            [1.5, 3.0, f64::INFINITY].map(|rho| crate::reference::Point { tau, gamma, rho, g: 0.0 })
        })
        .collect()
}

/// Largest relative error of `model` (an evaluator of `A`) on [`math_grid`]`(tau)`.
pub fn math_grid_error(model: &dyn Fn(crate::reference::Point) -> f64, tau: f64) -> f64 {
    math_grid(tau)
        .into_iter()
        .map(|p| crate::stats::rel_error(model(p), crate::reference::airlight(p).expect("valid")))
        .fold(0.0, f64::max)
}
