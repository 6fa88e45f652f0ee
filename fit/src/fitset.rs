//! The points a family's parameter fit is judged on: a fitting set (low-discrepancy
//! points inside `thin` and `dense`, plus grids on their faces) and a check set of a
//! seed of its own, each with the reference `A`, computed once per request and
//! shared by every member that asks for the same sets.

use airlight_truth::domains::Domain;
use airlight_truth::reference::{self, Point};
use airlight_truth::stats::rel_error;
use std::sync::{Arc, Mutex, OnceLock};

/// Points with reference `A`.
pub type Set = Arc<Vec<(Point, f64)>>;

/// What a pair of sets is drawn from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SetSpec {
    /// The `g` range (face grids at its ends and 0).
    pub g_range: (f64, f64),
    /// Low-discrepancy points per domain in the fitting set, and their seed.
    pub fit_points: usize,
    /// Seed of the fitting set.
    pub fit_seed: u64,
    /// Face grid per domain (`n × n` per face).
    pub faces: usize,
    /// Points per domain in the check set.
    pub check_points: usize,
    /// Seed of the check set.
    pub check_seed: u64,
}

/// The sets computed so far.
type SetCache = Mutex<Vec<(SetSpec, Set, Set)>>;

/// The fitting and check sets of `spec` (thin ∪ dense; the fitting set with face
/// grids), computed once and cached.
pub fn sets(spec: SetSpec) -> (Set, Set) {
    static CACHE: OnceLock<SetCache> = OnceLock::new();
    let cache = CACHE.get_or_init(|| Mutex::new(Vec::new()));
    if let Some((_, a, b)) = cache.lock().expect("not poisoned").iter().find(|c| c.0 == spec) {
        return (a.clone(), b.clone());
    }
    let gs = face_gs(spec.g_range);
    let with_ref = |pts: Vec<Point>| -> Set {
        let v = airlight_truth::parallel::map(
            &pts,
            |p| reference::airlight(*p).expect("domain points are valid"),
            &|_, _| {},
        );
        Arc::new(pts.into_iter().zip(v).filter(|(_, a)| a.is_finite() && *a > 0.0).collect())
    };
    let (mut fit, mut check) = (Vec::new(), Vec::new());
    for d in [Domain::Thin, Domain::Dense] {
        fit.extend(d.validation_set(spec.g_range, spec.fit_points, spec.fit_seed));
        fit.extend(d.faces(&gs, spec.faces));
        check.extend(d.validation_set(spec.g_range, spec.check_points, spec.check_seed));
    }
    let (fit, check) = (with_ref(fit), with_ref(check));
    cache.lock().expect("not poisoned").push((spec, fit.clone(), check.clone()));
    (fit, check)
}

/// The largest relative error of `eval` on `set`.
pub fn max_on(eval: &(dyn Fn(Point) -> f64 + Sync), set: &[(Point, f64)]) -> f64 {
    let errs = airlight_truth::parallel::map(set, |(p, a)| rel_error(eval(*p), *a), &|_, _| {});
    errs.into_iter().fold(0.0, f64::max)
}

/// Edges of the bands of `g` over which [`median_on`] takes its medians.
pub const MEDIAN_G_EDGES: [f64; 11] = [-1.0, -0.8, -0.6, -0.4, -0.2, 0.0, 0.2, 0.4, 0.6, 0.8, 1.0];

/// The largest median relative error of `eval` on `set`, the medians taken within
/// each domain (`τ ≤ 2`: thin, else dense) and each band of `g`
/// ([`MEDIAN_G_EDGES`]; an isotropic set is one band): what the bench's median levels
/// ask of every `g`. NaN or infinite errors count as infinite.
pub fn median_on(eval: &(dyn Fn(Point) -> f64 + Sync), set: &[(Point, f64)]) -> f64 {
    let errs = airlight_truth::parallel::map(set, |(p, a)| rel_error(eval(*p), *a), &|_, _| {});
    let mut groups: Vec<Vec<f64>> = vec![Vec::new(); 2 * (MEDIAN_G_EDGES.len() - 1)];
    for ((p, _), e) in set.iter().zip(errs) {
        let band = MEDIAN_G_EDGES[1..].iter().position(|&hi| p.g < hi).unwrap_or(MEDIAN_G_EDGES.len() - 2);
        let dense = usize::from(p.tau > 2.0);
        groups[2 * band + dense].push(if e.is_finite() { e } else { f64::INFINITY });
    }
    groups
        .iter_mut()
        .filter(|g| !g.is_empty())
        .map(|g| {
            g.sort_by(f64::total_cmp);
            g[g.len() / 2]
        })
        .fold(0.0, f64::max)
}

/// The `g` values of the face grids for a `g` range: its ends and 0 if inside.
pub fn face_gs(g_range: (f64, f64)) -> Vec<f64> {
    let mut gs = vec![g_range.0];
    if g_range.0 < 0.0 && g_range.1 > 0.0 {
        gs.push(0.0);
    }
    if g_range.1 != g_range.0 {
        gs.push(g_range.1);
    }
    gs
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_on_takes_the_largest_median_over_domains_and_bands_of_g() {
        // Errors set by the point's ρ: thin at g = −0.5 has 1e-3, 2e-3, 9e-1 (median
        // 2e-3); dense at g = −0.5 has 1e-4 ×3; thin at g = 0.9 has 5e-3, 6e-3, 7e-3
        // (median 6e-3, the largest); one point at g = 0.3 is NaN (its band's median
        // is infinite only if it is the band's middle: it is the only point there).
        let pt = |tau: f64, g: f64, e: f64| (Point { tau, gamma: 1.0, rho: e, g }, 1.0);
        let mut set = vec![
            pt(1.0, -0.5, 1e-3),
            pt(1.0, -0.5, 2e-3),
            pt(1.0, -0.5, 0.9),
            pt(5.0, -0.5, 1e-4),
            pt(5.0, -0.5, 1e-4),
            pt(5.0, -0.5, 1e-4),
            pt(1.0, 0.9, 5e-3),
            pt(1.0, 0.9, 6e-3),
            pt(1.0, 0.9, 7e-3),
        ];
        let eval = |p: Point| if p.rho.is_nan() { f64::NAN } else { 1.0 + p.rho };
        assert!((median_on(&eval, &set) - 6e-3).abs() < 1e-12, "{}", median_on(&eval, &set));
        // The max is the outlier; the median objective does not see it.
        assert!((max_on(&eval, &set) - 0.9).abs() < 1e-12);
        set.push(pt(1.0, 0.3, f64::NAN));
        assert_eq!(median_on(&eval, &set), f64::INFINITY);
    }
}
