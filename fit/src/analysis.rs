//! Measurements against the reference that are not any one family's: grids,
//! docs/MATH.md §4's grid and a model's error on it, and the cost of ignoring
//! extinction (what the planner weighs against the closed form).

use airlight_truth::reference::Point;
use std::f64::consts::PI;

/// `n` points from `lo` to `hi`, evenly spaced.
pub fn linspace(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    (0..n).map(|i| lo + (hi - lo) * i as f64 / (n - 1) as f64).collect()
}

/// `n` points from `lo` to `hi` (both > 0), evenly spaced in the logarithm.
pub fn logspace(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    (0..n).map(|i| lo * (hi / lo).powf(i as f64 / (n - 1) as f64)).collect()
}

/// docs/MATH.md §4's grid: isotropic, γ ∈ [0.05, 1.5] (61 values), ρ ∈ {1.5, 3, ∞}.
pub fn math_grid(tau: f64) -> Vec<airlight_truth::reference::Point> {
    (0..=60)
        .flat_map(|i| {
            let gamma = 0.05 + 1.45 * i as f64 / 60.0;
            [1.5, 3.0, f64::INFINITY].map(|rho| airlight_truth::reference::Point { tau, gamma, rho, g: 0.0 })
        })
        .collect()
}

/// Largest relative error of `model` (an evaluator of `A`) on [`math_grid`]`(tau)`.
pub fn math_grid_error(model: &dyn Fn(airlight_truth::reference::Point) -> f64, tau: f64) -> f64 {
    math_grid(tau)
        .into_iter()
        .map(|p| airlight_truth::stats::rel_error(model(p), airlight_truth::reference::airlight(p).expect("valid")))
        .fold(0.0, f64::max)
}

/// The largest relative error of dropping extinction (`A(0)` for `A(τ)`) at
/// optical distance `tau` over `γ ∈ [0.01, π − 0.01]`, `ρ = ∞` and, with `surfaces`,
/// `ρ ∈ [0.01, 100]`, and the given `g`: measured with the reference on a grid (41
/// angles × 9 surface distances and ∞). The error only grows with `τ` (`A` falls
/// with it while `A(0)` stays), so this bounds every scene up to `tau`.
pub fn extinction_error(tau: f64, surfaces: bool, gs: &[f64]) -> f64 {
    if tau <= 0.0 {
        return 0.0;
    }
    let mut rhos = vec![f64::INFINITY];
    if surfaces {
        rhos.extend((0..9).map(|i| 0.01 * 10f64.powf(0.5 * f64::from(i))));
    }
    let mut worst = 0.0f64;
    for &g in gs {
        for &rho in &rhos {
            for i in 0..41 {
                let gamma = 0.01 + (PI - 0.02) * f64::from(i) / 40.0;
                let at = |tau| airlight_truth::reference::airlight(Point { tau, gamma, rho, g }).unwrap_or(f64::NAN);
                let (a, a0) = (at(tau), at(0.0));
                worst = worst.max(airlight_truth::stats::rel_error(a0, a));
            }
        }
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ignoring_extinction_costs_more_with_depth() {
        assert_eq!(extinction_error(0.0, true, &[0.0]), 0.0);
        let (a, b) = (extinction_error(1e-4, false, &[0.0]), extinction_error(0.1, true, &[0.0]));
        assert!(a > 0.0 && a < 1e-2 && b > a, "{a:e} {b:e}");
    }
}
