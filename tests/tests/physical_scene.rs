//! A scene in world units, from viewer/light/ray placement to radiance, against
//! a direct quadrature of the physical integral of docs/MATH.md §1 — no canonical
//! form involved — at scales from 1e-3 to 1e4 units.

use airlight_truth::domains::SplitMix64;
use airlight_truth::geometry::PhysicalRay;
use airlight_truth::quad::gauss_kronrod;
use airlight_truth::Phase;

/// `σs I ∫₀^Dp P(α) e^{−σt (s + t)} / t² ds` in world units, with `t` the
/// distance from the point at `s` to the light. Breakpoints around the point
/// nearest the light at multiples of the light's distance from the ray.
fn direct_radiance(ray: &PhysicalRay, g: f64) -> f64 {
    let d = ray.direction;
    let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    let dir = [d[0] / len, d[1] / len, d[2] / len];
    let l = [ray.light[0] - ray.origin[0], ray.light[1] - ray.origin[1], ray.light[2] - ray.origin[2]];
    let foot = l[0] * dir[0] + l[1] * dir[1] + l[2] * dir[2];
    let dist = (l[0] * l[0] + l[1] * l[1] + l[2] * l[2]).sqrt();
    let miss = (dist * dist - foot * foot).max(0.0).sqrt();
    let end = ray.surface_distance.unwrap_or(dist * 200.0 + 60.0 / ray.sigma_t.max(1e-12));
    let phase = Phase::from_g(g);
    let f = |s: f64| {
        let x = [dir[0] * s - l[0], dir[1] * s - l[1], dir[2] * s - l[2]]; // light → point
        let t = (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
        // Light travels light → point, then point → viewer (−dir): cos α = (x̂ · −dir).
        let cos_a = -(x[0] * dir[0] + x[1] * dir[1] + x[2] * dir[2]) / t;
        phase.eval(cos_a.clamp(-1.0, 1.0).acos()) * (-ray.sigma_t * (s + t)).exp() / (t * t)
    };
    let mut bps = vec![0.0, end];
    for k in 0..40 {
        for s in [foot + miss * 2f64.powi(k - 8), foot - miss * 2f64.powi(k - 8)] {
            if s > 0.0 && s < end {
                bps.push(s);
            }
        }
    }
    bps.sort_by(f64::total_cmp);
    ray.sigma_s * ray.intensity * gauss_kronrod(f, &bps, 1e-11, 5000).value
}

#[test]
fn radiance_through_geometry_and_reference_matches_direct_integration() {
    let mut rng = SplitMix64(0x5CE4E);
    for i in 0..300 {
        let scale = 10f64.powf(-3.0 + 7.0 * rng.next_f64());
        let mut v = || (2.0 * rng.next_f64() - 1.0) * scale;
        let origin = [v(), v(), v()];
        let light = [v(), v(), v()];
        let direction = [v(), v(), v()];
        let surface_distance = if i % 3 == 0 { None } else { Some(scale * 3.0 * rng.next_f64() + scale * 1e-3) };
        let dist =
            ((light[0] - origin[0]).powi(2) + (light[1] - origin[1]).powi(2) + (light[2] - origin[2]).powi(2)).sqrt();
        let tau = 10f64.powf(-2.0 + 3.0 * rng.next_f64());
        let sigma_t = tau / dist;
        let g = if i % 2 == 0 { 0.0 } else { 1.6 * rng.next_f64() - 0.8 };
        let ray = PhysicalRay {
            origin,
            direction,
            surface_distance,
            light,
            intensity: 40.0,
            sigma_t,
            sigma_s: 0.7 * sigma_t,
        };
        let c = ray.to_canonical(g).unwrap();
        let via_canonical = c.scale * airlight_truth::airlight(c.point).unwrap();
        let direct = direct_radiance(&ray, g);
        let rel = ((via_canonical - direct) / direct).abs();
        // The direct path takes α through acos and positions through differences
        // of world coordinates, so it is the less accurate of the two.
        assert!(rel < 1e-7, "scale {scale:e}, {c:?}: {via_canonical:e} vs direct {direct:e} ({rel:e})");
    }
}
