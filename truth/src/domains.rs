//! The named error domains of docs/MATH.md §5 and their seeded, low-discrepancy
//! validation sets.
//!
//! Points come from a Halton sequence (bases 2, 3, 5, 7) under a Cranley–Patterson
//! rotation drawn from a SplitMix64 stream, so a (domain, seed) pair always gives
//! the same set, and different seeds give sets that share no points. Fits use
//! other seeds than validation.

use crate::reference::Point;
use std::f64::consts::PI;

/// A named error domain (docs/MATH.md §5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Domain {
    /// τ ∈ [0, 2]: light fog, the paper's regime.
    Thin,
    /// τ ∈ [2, 20]: fog, smoke, underwater.
    Dense,
    /// The corners: τ ∈ {0, 1e-8, 50, 100}, γ ∈ {1e-4, π − 1e-4}, ρ ∈ {1e-4, 1e4, ∞}.
    Extreme,
}

/// Seed of the validation sets every report uses. Fits must use another.
pub const VALIDATION_SEED: u64 = 0x5EED_0A1F_11A7_0001;
/// Default number of low-discrepancy points per sampled domain (before corners).
pub const VALIDATION_POINTS: usize = 10_000;
/// Share of sampled points with no surface (`ρ = ∞`).
pub const INFINITE_RHO_SHARE: f64 = 0.1;

impl std::fmt::Display for Domain {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

const GAMMA_MIN: f64 = 0.01;
const RHO_MIN: f64 = 0.01;
const RHO_MAX: f64 = 100.0;

impl Domain {
    /// All domains, in report order.
    pub const ALL: [Domain; 3] = [Domain::Thin, Domain::Dense, Domain::Extreme];

    /// Lower-case name used in files and tables.
    pub const fn name(self) -> &'static str {
        match self {
            Domain::Thin => "thin",
            Domain::Dense => "dense",
            Domain::Extreme => "extreme",
        }
    }

    /// The τ interval (for `Extreme`, the hull of its values).
    pub fn tau_range(self) -> (f64, f64) {
        match self {
            Domain::Thin => (0.0, 2.0),
            Domain::Dense => (2.0, 20.0),
            Domain::Extreme => (0.0, 100.0),
        }
    }

    /// One-line description for reports.
    pub fn describe(self) -> &'static str {
        match self {
            Domain::Thin => "τ ∈ [0, 2], γ ∈ [0.01, π − 0.01], ρ ∈ [0.01, 100] ∪ {∞}",
            Domain::Dense => "τ ∈ [2, 20], γ ∈ [0.01, π − 0.01], ρ ∈ [0.01, 100] ∪ {∞}",
            Domain::Extreme => "τ ∈ {0, 1e-8, 50, 100}, γ ∈ {1e-4, π − 1e-4}, ρ ∈ {1e-4, 1e4, ∞}",
        }
    }

    /// The corner points of the domain for each `g` in `gs`.
    pub fn corners(self, gs: &[f64]) -> Vec<Point> {
        let (taus, gammas, rhos): (Vec<f64>, Vec<f64>, Vec<f64>) = match self {
            Domain::Extreme => (vec![0.0, 1e-8, 50.0, 100.0], vec![1e-4, PI - 1e-4], vec![1e-4, 1e4, f64::INFINITY]),
            _ => {
                let (lo, hi) = self.tau_range();
                (vec![lo, hi], vec![GAMMA_MIN, PI - GAMMA_MIN], vec![RHO_MIN, RHO_MAX, f64::INFINITY])
            }
        };
        let mut out = Vec::new();
        for &tau in &taus {
            for &gamma in &gammas {
                for &rho in &rhos {
                    for &g in gs {
                        out.push(Point { tau, gamma, rho, g });
                    }
                }
            }
        }
        out
    }

    /// Grids of `n × n` points on the faces of a sampled domain's box where
    /// errors peak — the nearest surface (ρ = 0.01), no surface (ρ = ∞), and both
    /// ends of τ — for each `g` in `gs`: peaks on an edge are narrow and easily
    /// missed by a low-discrepancy set. Empty for `Extreme`. (The fits use these;
    /// the validation adds [`Domain::gamma_faces`].)
    pub fn faces(self, gs: &[f64], n: usize) -> Vec<Point> {
        if self == Domain::Extreme || n < 2 {
            return Vec::new();
        }
        let (tlo, thi) = self.tau_range();
        let at = |i: usize, lo: f64, hi: f64| lo + (hi - lo) * i as f64 / (n - 1) as f64;
        let mut out = Vec::new();
        for &g in gs {
            for i in 0..n {
                for j in 0..n {
                    let gamma = at(j, GAMMA_MIN, PI - GAMMA_MIN);
                    let tau = at(i, tlo, thi);
                    out.push(Point { tau, gamma, rho: RHO_MIN, g });
                    out.push(Point { tau, gamma, rho: f64::INFINITY, g });
                    let rho = RHO_MIN * (RHO_MAX / RHO_MIN).powf(i as f64 / (n - 1) as f64);
                    out.push(Point { tau: tlo, gamma, rho, g });
                    out.push(Point { tau: thi, gamma, rho, g });
                }
            }
        }
        out
    }

    /// Grids of `n × n` points (τ by ρ, the last column an open ray) on the two
    /// faces of γ, the ray grazing the light looking at it (γ = 0.01) and away
    /// (γ = π − 0.01), for each `g` in `gs`: where the thin-medium peaks of the
    /// one-path rules sit (issue 37). Empty for `Extreme`.
    pub fn gamma_faces(self, gs: &[f64], n: usize) -> Vec<Point> {
        if self == Domain::Extreme || n < 3 {
            return Vec::new();
        }
        let (tlo, thi) = self.tau_range();
        let mut out = Vec::new();
        for &g in gs {
            for i in 0..n {
                let tau = tlo + (thi - tlo) * i as f64 / (n - 1) as f64;
                for j in 0..n {
                    let rho = if j + 1 == n {
                        f64::INFINITY
                    } else {
                        RHO_MIN * (RHO_MAX / RHO_MIN).powf(j as f64 / (n - 2) as f64)
                    };
                    out.push(Point { tau, gamma: GAMMA_MIN, rho, g });
                    out.push(Point { tau, gamma: PI - GAMMA_MIN, rho, g });
                }
            }
        }
        out
    }

    /// `n` low-discrepancy points of the domain with `g` uniform in `g_range`
    /// (constant when `lo == hi`), followed by the corners at `g ∈ {lo, hi}`.
    /// `Extreme` has corners only.
    pub fn validation_set(self, g_range: (f64, f64), n: usize, seed: u64) -> Vec<Point> {
        let gs: Vec<f64> = if g_range.0 == g_range.1 { vec![g_range.0] } else { vec![g_range.0, g_range.1] };
        let mut pts = Vec::new();
        if self != Domain::Extreme {
            let (tlo, thi) = self.tau_range();
            let mut rng = SplitMix64(seed ^ (self as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15));
            let shift: [f64; 4] = std::array::from_fn(|_| rng.next_f64());
            for i in 0..n {
                let z: [f64; 4] =
                    std::array::from_fn(|d| (radical_inverse(i as u64 + 1, PRIMES[d]) + shift[d]).fract());
                let tau = tlo + (thi - tlo) * z[0];
                let gamma = GAMMA_MIN + (PI - 2.0 * GAMMA_MIN) * z[1];
                let rho = if z[2] >= 1.0 - INFINITE_RHO_SHARE {
                    f64::INFINITY
                } else {
                    RHO_MIN * (RHO_MAX / RHO_MIN).powf(z[2] / (1.0 - INFINITE_RHO_SHARE))
                };
                let g = g_range.0 + (g_range.1 - g_range.0) * z[3];
                pts.push(Point { tau, gamma, rho, g });
            }
        }
        pts.extend(self.corners(&gs));
        pts
    }
}

const PRIMES: [u64; 4] = [2, 3, 5, 7];

/// Van der Corput radical inverse of `i` in `base`.
fn radical_inverse(mut i: u64, base: u64) -> f64 {
    let inv = 1.0 / base as f64;
    let mut f = inv;
    let mut r = 0.0;
    while i > 0 {
        r += f * (i % base) as f64;
        i /= base;
        f *= inv;
    }
    r
}

/// SplitMix64 (Steele, Lea & Flood 2014): a tiny, well-mixed, seedable stream.
#[derive(Debug, Clone)]
pub struct SplitMix64(pub u64);

impl SplitMix64 {
    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in `[0, 1)` with 53 random bits.
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// Errors measured on one domain's validation set.
#[derive(Debug, Clone, PartialEq)]
pub struct DomainErrors {
    /// The domain.
    pub domain: Domain,
    /// Points measured.
    pub points: usize,
    /// The declared bound on the relative error of `A`: the largest error the
    /// searches found times `1 +` `DECLARED_MARGIN` (airlight-fit's `catalog`).
    pub max_rel: f64,
    /// The largest relative error the searches found (absent in files written
    /// before bounds carried a margin: then `max_rel`).
    pub searched_max_rel: Option<f64>,
    /// 99th percentile.
    pub p99_rel: f64,
    /// Where the largest error occurs.
    pub worst: Point,
    /// NaN or ∞ where `A` is finite.
    pub non_finite: usize,
    /// Negative values.
    pub negative: usize,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sets_are_deterministic_inside_their_domain_and_seed_dependent() {
        let a = Domain::Dense.validation_set((-0.5, 0.9), 1000, 7);
        let b = Domain::Dense.validation_set((-0.5, 0.9), 1000, 7);
        let c = Domain::Dense.validation_set((-0.5, 0.9), 1000, 8);
        assert_eq!(a, b);
        assert_ne!(a[0], c[0]);
        let inf = a.iter().filter(|p| p.rho.is_infinite()).count();
        assert!((80..=140).contains(&inf), "{inf} points with ρ = ∞");
        for p in &a {
            assert!((2.0..=20.0).contains(&p.tau));
            assert!((GAMMA_MIN..=PI - GAMMA_MIN).contains(&p.gamma));
            assert!(p.rho.is_infinite() || (RHO_MIN..=RHO_MAX).contains(&p.rho));
            assert!((-0.5..=0.9).contains(&p.g));
            p.validate().unwrap();
        }
    }

    #[test]
    fn extreme_is_the_corner_grid() {
        let e = Domain::Extreme.validation_set((0.0, 0.0), 10_000, 1);
        assert_eq!(e.len(), 4 * 2 * 3);
    }
}
