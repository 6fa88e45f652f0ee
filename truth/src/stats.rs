//! Error statistics over a point set: max, 99th percentile, where the max occurs.

use crate::reference::Point;

/// Summary of relative errors over a set of points.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ErrorStats {
    /// Number of points measured.
    pub count: usize,
    /// Largest relative error.
    pub max: f64,
    /// 99th percentile (nearest-rank) relative error.
    pub p99: f64,
    /// The point where the largest error occurs.
    pub worst: Option<Point>,
    /// Points whose error is NaN or infinite (counted, and make `max` infinite).
    pub non_finite: usize,
}

impl ErrorStats {
    /// Builds the summary from `(point, relative error)` pairs.
    pub fn from_errors(errors: impl IntoIterator<Item = (Point, f64)>) -> ErrorStats {
        let mut all: Vec<(Point, f64)> = errors.into_iter().collect();
        let non_finite = all.iter().filter(|(_, e)| !e.is_finite()).count();
        let key = |e: f64| if e.is_finite() { e } else { f64::INFINITY };
        all.sort_by(|a, b| key(a.1).total_cmp(&key(b.1)));
        let count = all.len();
        if count == 0 {
            return ErrorStats { count, max: 0.0, p99: 0.0, worst: None, non_finite };
        }
        let sorted: Vec<f64> = all.iter().map(|e| key(e.1)).collect();
        ErrorStats {
            count,
            max: key(all[count - 1].1),
            p99: nearest_rank(&sorted, 0.99),
            worst: Some(all[count - 1].0),
            non_finite,
        }
    }
}

/// The nearest-rank `q`-quantile of ascending `sorted` values (`q = 1`: the
/// largest; NaN when empty).
pub fn nearest_rank(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let rank = ((q * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len());
    sorted[rank - 1]
}

/// Root-mean-square and largest magnitude of signed relative errors (0, 0 when empty).
pub fn rms_max(errs: &[f64]) -> (f64, f64) {
    let rms = (errs.iter().map(|e| e * e).sum::<f64>() / errs.len().max(1) as f64).sqrt();
    (rms, errs.iter().fold(0.0, |m: f64, e| m.max(e.abs())))
}

/// `|approx − exact| / exact`; 0 when both are equal (including both `+∞` or
/// both 0), `+∞` when only one is infinite or the approximation is NaN.
pub fn rel_error(approx: f64, exact: f64) -> f64 {
    if approx == exact {
        0.0
    } else if approx.is_nan() || approx.is_infinite() || exact.is_infinite() {
        f64::INFINITY
    } else {
        ((approx - exact) / exact).abs()
    }
}

/// A relative error with two significant digits (`0` when exactly zero).
pub fn fmt_err(e: f64) -> String {
    if e == 0.0 {
        "0".into()
    } else if e.is_finite() {
        format!("{e:.1e}")
    } else {
        "∞".into()
    }
}

/// A point, compactly, for tables.
pub fn fmt_point(p: &Point) -> String {
    let rho = if p.rho.is_infinite() { "∞".to_string() } else { format!("{:.6}", p.rho) };
    format!("τ = {:.6}, γ = {:.6}, ρ = {}, g = {:.4}", p.tau, p.gamma, rho, p.g)
        .replace(".000000,", ",")
        .replace("g = 0.0000", "g = 0")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentile_and_worst() {
        let p = |i: usize| Point { tau: i as f64, gamma: 1.0, rho: 1.0, g: 0.0 };
        let s = ErrorStats::from_errors((0..200).map(|i| (p(i), i as f64)));
        assert_eq!(s.count, 200);
        assert_eq!(s.max, 199.0);
        assert_eq!(s.p99, 197.0);
        assert_eq!(s.worst.unwrap().tau, 199.0);
        let s = ErrorStats::from_errors([(p(1), f64::NAN), (p(2), 0.5)]);
        assert_eq!(s.non_finite, 1);
        assert_eq!(s.max, f64::INFINITY);
        assert_eq!(s.worst.unwrap().tau, 1.0);
    }

    #[test]
    fn relative_error_edge_cases() {
        assert_eq!(rel_error(f64::INFINITY, f64::INFINITY), 0.0);
        assert_eq!(rel_error(0.0, 0.0), 0.0);
        assert_eq!(rel_error(1.0, f64::INFINITY), f64::INFINITY);
        assert_eq!(rel_error(f64::NAN, 1.0), f64::INFINITY);
        assert!((rel_error(1.1, 1.0) - 0.1).abs() < 1e-15);
    }

    #[test]
    fn number_formats() {
        assert_eq!(fmt_err(0.0), "0");
        assert_eq!(fmt_err(3.25e-15), "3.2e-15");
        assert_eq!(fmt_err(f64::INFINITY), "∞");
        let p = Point::new(2.0, 0.5, f64::INFINITY, 0.0);
        assert_eq!(fmt_point(&p), "τ = 2, γ = 0.500000, ρ = ∞, g = 0");
    }
}
