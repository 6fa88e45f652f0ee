//! The report's robustness table from the recorded gate (`generated/gate.toml`):
//! per regime and target, the largest error of the most accurate isotropic and
//! Henyey–Greenstein model kernels, and the bad values over every kernel.

use airlight_shapes::record::{self, GateRecord};
use airlight_shapes::vocab::Domain;
use serde::Serialize;

/// What each regime of the gate checks, in words, in [`record::REGIMES`]' order.
const WHAT: [&str; 9] = [
    "canonical, `thin`",
    "canonical, `dense`",
    "canonical, `extreme` corners",
    "canonical, edges: the exact axis (γ = 0, π), γ down to 1e-37, surfaces at the light and out to 1e300",
    "physical entry, random rays at 1e-3 … 1e4 units",
    "physical entry, extreme rays (1e-4 … 1e30 units, grazing, far planes, ∞)",
    "spot entry, spot lights (2°–80°, and a grid of 5°–80° cones with inner half-angles from equal to a quarter, half of them turned so that the ray leaves through the penumbra) in RGB media, per channel; rays passing close by the light with the cone's cut near its foot; rays on the line through the light; a ray whose answer one f32 ulp of an input moves by over 1e-5 counts where it breaks the limit widened by 32 such changes",
    "shafts accumulator, 96 rays among 1–4 analytic occluders (balls, boxes) fed the exact lit intervals, 8 of them also from a 40° spot light (smooth and hard edges, per channel); error relative to the ray's unshadowed value times (1 + visibility changes)",
    "shafts accumulator fed the shadow-map walk: 32 of those rays, their occluders cast into a 256² cube map at the light, against the reference in-scattering over the same map's exact runs (f64); error as for `shadowed`",
];

/// One regime × target cell of the robustness table.
#[derive(Serialize)]
struct RegimeCell {
    /// Largest relative error of the most accurate isotropic model kernel ("—"
    /// when the target did not run).
    iso: String,
    /// The same for the most accurate Henyey–Greenstein model kernel.
    hg: String,
    /// NaN / negative / spurious ∞ values over every kernel.
    bad: usize,
    /// Points checked over every kernel.
    points: usize,
}

#[derive(Serialize)]
pub(super) struct RegimeRow {
    regime: &'static str,
    what: &'static str,
    cells: Vec<RegimeCell>,
}

/// The model kernel (not a scene's) whose name starts with `prefix` and whose
/// f64 model is most accurate on `thin`.
fn best_kernel<'r>(r: &'r GateRecord, prefix: &str) -> Option<&'r str> {
    r.rows
        .iter()
        .filter(|x| x.is(None, Domain::Thin.name()) && x.kernel.starts_with(prefix))
        .min_by(|a, b| a.max_rel.total_cmp(&b.max_rel))
        .map(|x| x.kernel.as_str())
}

/// The table's rows, and the isotropic and HG kernels it follows.
pub(super) fn regime_rows(r: &GateRecord) -> (Vec<RegimeRow>, String, String) {
    // The families it follows (an isotropic one, then a Henyey–Greenstein one):
    // `gate_followed` in fit/src/roles.toml.
    let followed = &airlight_fit::roles::roles().report.gate_followed;
    let iso = followed.first().and_then(|p| best_kernel(r, p)).unwrap_or("—");
    let hg = followed.get(1).and_then(|p| best_kernel(r, p)).unwrap_or("—");
    let rows = record::REGIMES
        .iter()
        .zip(WHAT)
        .map(|(&regime, what)| RegimeRow {
            regime,
            what,
            cells: record::TARGETS
                .iter()
                .map(|&t| {
                    let rows: Vec<_> = r.rows.iter().filter(|x| x.is(t, regime)).collect();
                    let of = |name: &str| {
                        rows.iter()
                            .find(|x| x.kernel == name)
                            .map_or("—".to_string(), |x| format!("{:.2e}", x.max_rel))
                    };
                    RegimeCell {
                        iso: of(iso),
                        hg: of(hg),
                        bad: rows.iter().map(|x| x.bad).sum(),
                        points: rows.iter().map(|x| x.points).sum(),
                    }
                })
                .collect(),
        })
        .collect();
    (rows, iso.to_string(), hg.to_string())
}
