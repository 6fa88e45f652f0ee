//! The gate's spot rows (issue 23) against the penumbra rules, in f64 so that
//! only the rules differ: the old single 8-point Gauss–Legendre rule in ω over
//! each penumbra stretch breaks the limit on some of them; the kernels' rule (the
//! weight at the end where it is smaller times the exact integral over the
//! stretch, the rest by 8-point Gauss–Legendre on 5 graded pieces) holds every one
//! far inside it.
//!
//! The fully lit stretch is the reference's own in both; a penumbra stretch is
//! where the direction cosine lies between `cos_outer` and `cos_inner` (the outer
//! cone's lit stretch less the inner one's), in ω the angle at the point between
//! the ray and the direction to the light, where `ds/t² = dω/h` and `s + t =
//! x0 + h tan(ω/2)` (canonical units), as the kernels integrate it.

use airlight_shaders::gate;
use airlight_shapes::vocab::f32_limit;
use airlight_truth::geometry::{Cone, PhysicalRay};
use airlight_truth::phase::Phase;
use airlight_truth::reference::{self, Point};
use std::path::Path;

/// The penumbra stretches of `ray` (distances along it): lit by the outer cone,
/// not by the inner one.
fn penumbra(ray: &PhysicalRay, cone: &Cone) -> Vec<(f64, f64)> {
    let Some((a, b)) = cone.lit(ray, cone.cos_outer) else { return Vec::new() };
    match cone.lit(ray, cone.cos_inner.min(1.0)) {
        None => vec![(a, b)],
        Some((c, d)) => [(a, c.max(a)), (d.min(b), b)].into_iter().filter(|(u, v)| v > u).collect(),
    }
}

/// The radiance over the stretch `[s0, s1]` with the weight of the cone: by the
/// old rule (`graded = false`) or the kernels' (`graded = true`).
fn stretch_rule(ray: &PhysicalRay, cone: &Cone, g: f64, s0: f64, s1: f64, graded: bool) -> f64 {
    let to_l: [f64; 3] = std::array::from_fn(|i| ray.light[i] - ray.origin[i]);
    let dl = (to_l[0] * to_l[0] + to_l[1] * to_l[1] + to_l[2] * to_l[2]).sqrt();
    let n = {
        let m = ray.direction.iter().map(|x| x * x).sum::<f64>().sqrt();
        ray.direction.map(|x| x / m)
    };
    let x0d = to_l[0] * n[0] + to_l[1] * n[1] + to_l[2] * n[2];
    let hd = ((dl - x0d) * (dl + x0d)).max(0.0).sqrt();
    let (h, x0, tau) = (hd / dl, x0d / dl, ray.sigma_t * dl);
    let omega = |s: f64| hd.atan2(x0d - s);
    let weight = |w: f64| {
        let s = x0d - hd / w.tan();
        let r: [f64; 3] = std::array::from_fn(|i| ray.origin[i] + s * n[i] - ray.light[i]);
        cone.weight(r)
    };
    let phase = Phase::from_g(g);
    let f = |w: f64| phase.eval(w) * (-tau * (x0 + h * (0.5 * w).tan())).exp() / h;
    let scale = ray.sigma_s * ray.intensity / dl;
    let (u, v) = (omega(s0), if s1.is_finite() { omega(s1) } else { std::f64::consts::PI });
    let (x, wts) = airlight_truth::quad::gauss_legendre(8);
    let gl = |a: f64, b: f64, we: f64| -> f64 {
        let (half, mid) = (0.5 * (b - a), 0.5 * (b + a));
        x.iter().zip(&wts).map(|(&xi, &wi)| wi * half * (weight(mid + half * xi) - we) * f(mid + half * xi)).sum()
    };
    if !graded {
        return scale * gl(u, v, 0.0);
    }
    // The end with the smaller weight: W − W(e) ≥ 0.
    let we = weight(u).min(weight(v));
    let (stretch, t) = ray.stretch(s0, s1);
    let exact = t * stretch.radiance(g, &|p: Point| reference::airlight(p).unwrap()).unwrap();
    let pieces = [0.0, 1.0 / 32.0, 0.25, 0.75, 31.0 / 32.0, 1.0];
    let rest: f64 = pieces.windows(2).map(|p| gl(u + (v - u) * p[0], u + (v - u) * p[1], we)).sum();
    we * exact + scale * rest
}

#[test]
fn the_new_spot_rows_break_the_old_penumbra_rule_and_hold_the_new_one() {
    let generated = Path::new(env!("CARGO_MANIFEST_DIR")).join("../generated");
    let index = gate::load_index(&generated).unwrap();
    let models = airlight_fit::catalog::load(&generated.join("coefficients")).unwrap();
    let k = index.get("phi-8").unwrap();
    let limit = f32_limit(gate::declared_max(k, &models).unwrap());
    let cases = gate::spot_rays(k, gate::SPOT_RAYS, airlight_truth::domains::VALIDATION_SEED ^ 0x5B07).unwrap();
    let (mut smooth, mut old_over, mut new_max, mut old_max) = (0, 0, 0.0f64, 0.0f64);
    for c in &cases {
        let Some(cone) = c.ray.cone() else { continue };
        if cone.cos_inner <= cone.cos_outer || c.reference[0] <= 0.0 {
            continue;
        }
        let ray = c.ray.physical(0);
        let g = f64::from(c.ray.g);
        let pen = penumbra(&ray, &cone);
        if pen.is_empty() {
            continue;
        }
        smooth += 1;
        // The fully lit stretch, exact in both.
        let lit = cone.lit(&ray, cone.cos_inner.min(1.0)).map_or(0.0, |(a, b)| {
            let (s, t) = ray.stretch(a, b);
            t * s.radiance(g, &|p| reference::airlight(p).unwrap()).unwrap()
        });
        let by = |graded| lit + pen.iter().map(|&(a, b)| stretch_rule(&ray, &cone, g, a, b, graded)).sum::<f64>();
        let exact = c.reference[0];
        let (old, new) = ((by(false) - exact).abs() / exact, (by(true) - exact).abs() / exact);
        if old > limit {
            old_over += 1;
        }
        new_max = new_max.max(new);
        old_max = old_max.max(old);
    }
    assert!(smooth >= 40, "{smooth} smooth-edged rows with a penumbra");
    eprintln!(
        "{smooth} smooth rows: old rule max {old_max:.2e} ({old_over} over {limit:.2e}), new rule max {new_max:.2e}"
    );
    assert!(old_over >= 1, "the old rule breaks the limit {limit:.2e} on {old_over} of {smooth} rows");
    assert!(new_max < 0.1 * limit, "the new rule's largest error {new_max:.2e} against the limit {limit:.2e}");
}
