//! Light shafts: the in-scattering along a view ray when opaque occluders stand
//! between the light and the medium (docs/MATH.md §8).
//!
//! With the visibility `v(s) ∈ [0, 1]` of the light from the point at distance `s`
//! along the ray, the shadowed in-scattering is `∫ v dC`, `C(s)` the unshadowed
//! in-scattering from the viewer to `s`. Visibility sampled at `s₁ < … < s_N` is
//! taken as constant between changes, each change placed between the samples
//! that straddle it (their midpoint, or where a bisection of the caller's
//! visibility puts it), so `∫ v dC = Σ_runs v_run · C[a, b]` over the runs of
//! constant visibility — the summation by parts `v_N C(end) + Σ (v_i − v_{i+1}) C(m_i)`
//! of the same sum, evaluated run by run. Each `C[a, b]` is the family's own
//! in-scattering of a ray whose viewer is moved to `a` (the phase angle at a point
//! does not depend on where the viewer stands), times `e^{−σt a}`: no difference
//! of two integrals is ever formed, dark runs cost nothing, and the result's
//! error is at most the family's bound times `C(end)` — with no growth in the
//! number of changes. This module holds the exact geometry (analytic occluders
//! and their lit intervals, found to double precision), the shadowed reference,
//! the accumulator in f64 (the generated kernels carry the same in f32), where a
//! shadow map's samples fall, and the engines' march with visibility.
//!
//! One concept per file: `occluders` (the exact geometry), `shadowed` (the
//! reference and the f64 accumulator), `feeds` (visibility sources and how they
//! feed the accumulator).

mod feeds;
mod occluders;
mod shadowed;
mod shadowmap;

pub use feeds::*;
pub use occluders::*;
pub use shadowed::*;
pub use shadowmap::*;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{dot, norm, sub, PhysicalRay, Vec3};
    use crate::reference;
    use crate::reference::Point;

    fn ray(surface: Option<f64>) -> PhysicalRay {
        PhysicalRay {
            origin: [0.0, 0.0, 0.0],
            direction: [1.0, 0.05, 0.0],
            surface_distance: surface,
            light: [6.0, 2.0, 0.5],
            intensity: 3.0,
            sigma_t: 0.12,
            sigma_s: 0.08,
        }
    }

    fn scene() -> Vec<Occluder> {
        vec![
            Occluder::Sphere { center: [3.0, 1.2, 0.3], radius: 0.35 },
            Occluder::Sphere { center: [7.0, 1.6, 0.4], radius: 0.25 },
            Occluder::Cuboid { min: [9.0, 1.0, -0.5], max: [9.4, 1.5, 1.5] },
        ]
    }

    #[test]
    fn boundaries_are_where_visibility_changes() {
        let r = ray(Some(25.0));
        let lit = lit_intervals(&r, &scene());
        assert!(lit.len() >= 2 && lit[0].0 > 0.0, "{lit:?}");
        for &(a, b) in &lit {
            assert!(visible(&r, &scene(), 0.5 * (a + b)));
            for &x in &[a, b] {
                if x > 0.0 && x < 25.0 {
                    let eps = 1e-12 * x.max(1.0);
                    assert_ne!(visible(&r, &scene(), x - eps), visible(&r, &scene(), x + eps), "boundary at {x}");
                }
            }
        }
    }

    #[test]
    fn sampled_feeds_add_the_viewers_and_the_surfaces_visibility() {
        // A ball over the viewer's end of the ray: dark from 0, lit later.
        let occ = vec![Occluder::Sphere { center: [0.6, 0.4, 0.0], radius: 0.3 }];
        let r = ray(Some(25.0));
        let look = feed(&r, &occ, 0.0, Feed::LookUps(8)).unwrap();
        let fed = feed(&r, &occ, 0.0, Feed::Samples(8)).unwrap();
        assert_eq!(look.len(), 8);
        assert_eq!(fed.len(), 10);
        assert_eq!(&fed[1..9], &look[..]);
        assert_eq!(fed[0], (0.0, if visible(&r, &occ, 0.0) { 1.0 } else { 0.0 }));
        assert_eq!(fed[9], (25.0, 1.0));
        // An open ray has no surface to add.
        let open = feed(&ray(None), &occ, 0.0, Feed::Samples(8)).unwrap();
        assert_eq!(open.len(), 9);
        assert_eq!(open[0].0, 0.0);
    }

    /// Against an independent evaluation: adaptive quadrature of `v(s) f(s)` over
    /// the ray with the boundaries as breakpoints.
    #[test]
    fn the_reference_is_the_integral_of_visibility_times_the_integrand() {
        let a = |p: Point| reference::airlight(p).unwrap();
        for g in [0.0, 0.6, -0.4] {
            for surface in [Some(25.0), None] {
                let r = ray(surface);
                let occ = scene();
                let lit = lit_intervals(&r, &occ);
                let want = shadowed_radiance(&r, None, g, &lit, &a).unwrap();
                let (d, _) = unit_and_end(&r);
                let far = surface.unwrap_or(400.0);
                let mut breaks = vec![0.0];
                for &(x, y) in &lit {
                    breaks.push(x);
                    breaks.push(y.min(far));
                }
                breaks.push(far);
                breaks.sort_by(f64::total_cmp);
                let q = crate::quad::gauss_kronrod(
                    |s| if visible(&r, &occ, s) { integrand(&r, d, g, s) } else { 0.0 },
                    &breaks,
                    1e-12,
                    4000,
                );
                assert!(((q.value - want) / want).abs() < 1e-9, "g {g}, {surface:?}: {} vs {want}", q.value);
                // The accumulator fed the exact intervals is the same sum.
                let mut acc = Accumulator::new();
                let mut run =
                    |x: f64, y: Option<f64>| run_radiance(&r, None, g, x, y.unwrap_or(f64::INFINITY), &a).unwrap();
                for (s, v) in exact_samples(&r, &lit) {
                    acc.push(s, v, &mut run);
                }
                let (got, calls) = acc.finish(surface, &mut run);
                assert!(((got - want) / want).abs() < 1e-13, "{got} vs {want}");
                assert_eq!(calls, lit.len());
            }
        }
    }

    #[test]
    fn refinement_places_a_change_by_bisection() {
        let r = ray(Some(25.0));
        let occ = scene();
        let lit = lit_intervals(&r, &occ);
        let a = |p: Point| reference::airlight(p).unwrap();
        let want = shadowed_radiance(&r, None, 0.3, &lit, &a).unwrap();
        let mut run = |x: f64, y: Option<f64>| run_radiance(&r, None, 0.3, x, y.unwrap_or(f64::INFINITY), &a).unwrap();
        let err = |k: usize, run: &mut dyn FnMut(f64, Option<f64>) -> f64| {
            let mut acc = Accumulator::new();
            for (s, v) in samples(&r, &occ, 16, 25.0) {
                acc.push(s, v, run);
                for _ in 0..k {
                    let Some(m) = acc.probe() else { break };
                    acc.refine(if visible(&r, &occ, m) { 1.0 } else { 0.0 });
                }
            }
            ((acc.finish(Some(25.0), run).0 - want) / want).abs()
        };
        let (e0, e20) = (err(0, &mut run), err(20, &mut run));
        assert!(e20 < 1e-5 && e20 < e0 / 10.0, "unrefined {e0:.2e}, refined {e20:.2e}");
    }

    /// The seed's table reproduces the reference where it is fine enough, and
    /// its error is the table's (interpolation), not the sampling's.
    #[test]
    fn the_seeds_table_is_the_in_scattering_it_was_built_from() {
        let a = |p: Point| reference::airlight(p).unwrap();
        let r = ray(Some(25.0));
        let g = 0.3;
        let fill =
            |d: Vec3, x: f64| PhysicalRay { direction: d, surface_distance: Some(x), ..r }.radiance(g, &a).unwrap();
        let table = FPrimeTable::build(256, r.origin, r.light, 25.0, &fill);
        let occ = scene();
        let exact = shadowed_radiance(&r, None, g, &lit_intervals(&r, &occ), &a).unwrap();
        let s = samples(&r, &occ, 64, 25.0);
        let (acc, _) = evaluate(&r, None, g, &s, &a, false).unwrap();
        let via_table = table.shadowed(&r, &s);
        // Same samples, same edges: the table adds only its interpolation error.
        assert!(((via_table - acc) / acc).abs() < 2e-2, "table {via_table}, accumulator {acc}, exact {exact}");
        let unshadowed = r.radiance(g, &a).unwrap();
        assert!(
            ((table.lookup(dot(unit_and_end(&r).0, sub(r.light, r.origin)) / norm(sub(r.light, r.origin)), 25.0)
                - unshadowed)
                / unshadowed)
                .abs()
                < 2e-2
        );
    }

    #[test]
    fn spheres_parse_and_refuse() {
        let s = parse_spheres("1 2 3 0.5; -1e3 0 2.5 4").unwrap();
        assert_eq!(s.len(), 2);
        assert_eq!(parse_spheres(&render_spheres(&s)).unwrap(), s);
        assert!(parse_spheres("").unwrap().is_empty());
        assert!(parse_spheres("1 2 3").unwrap_err().contains("4"));
        assert!(parse_spheres("1 2 3 -1").unwrap_err().contains("radius"));
        assert!(parse_spheres("1 2 3 x").unwrap_err().contains("'x'"));
        assert!(parse_spheres("1 2 3 1;;").unwrap_err().contains("empty"));
    }

    /// Issue 37's rays: `(origin, direction, light, σt, g, ball, mpmath's value)`;
    /// σs = σt, intensity 1, no surface.
    type Probe = (Vec3, Vec3, Vec3, f64, f64, (Vec3, f64), f64);
    const PROBES: [Probe; 6] = [
        // The light on the ball's surface (tangent plane x = 0).
        ([-1.0, 5.0, 0.0], [1.0, 0.0, 0.0], [0.0; 3], 0.1, 0.0, ([1.0, 0.0, 0.0], 1.0), 1.80666e-4),
        ([-1.0, 5.0, 0.0], [1.0, 0.0, 0.0], [0.0; 3], 0.1, 0.5, ([3.0, 0.0, 4.0], 5.0), 1.10352e-4),
        // Tiny occluders 1e6 away (r/d = 1e-9, 1e-10): lit edges at 499.745 and 1500.755.
        ([1000010.0, 0.002, 0.0], [1.0, -2e-6, 0.0], [0.0; 3], 1e-4, 0.0, ([1e6, 0.0, 0.0], 1e-3), 1.22181e-57),
        ([1000010.0, 0.002, 0.0], [1.0, -2e-6, 0.0], [0.0; 3], 1e-4, 0.0, ([1e6, 0.0, 0.0], 1e-4), 1.43990e-57),
        // r² beyond f64's range: the viewer and the light inside a ball 2e200 across
        // (a closed surface: they see each other, the ray is lit to the far wall —
        // NaN here means the unshadowed value); a light inside one 1e-300 across.
        ([0.0; 3], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], 0.1, 0.0, ([1.9e200, 0.0, 0.0], 2e200), f64::NAN),
        ([0.0; 3], [1.0, 0.0, 0.0], [5.0, 1.0, 0.0], 0.1, 0.0, ([5.0, 1.0, 0.0], 1e-300), 0.0),
    ];

    #[test]
    fn lights_on_surfaces_and_balls_of_any_size_cast_their_shadows() {
        for (o, d, l, st, g, (c, r), want) in PROBES {
            let ray = PhysicalRay {
                origin: o,
                direction: d,
                surface_distance: None,
                light: l,
                intensity: 1.0,
                sigma_t: st,
                sigma_s: st,
            };
            let occ = [Occluder::Sphere { center: c, radius: r }];
            let lit = lit_intervals(&ray, &occ);
            let got = shadowed_radiance(&ray, None, g, &lit, &|p| reference::airlight(p).unwrap()).unwrap();
            let want =
                if want.is_nan() { ray.radiance(g, &|p| reference::airlight(p).unwrap()).unwrap() } else { want };
            let err = if want == 0.0 { got } else { (got / want - 1.0).abs() };
            assert!(err < 1e-5, "ball {c:?} r {r}: {got:e} against {want:e} (lit {lit:?})");
        }
    }

    #[test]
    fn a_ball_blocks_exactly_what_its_tangent_cone_holds() {
        // A light on the surface shadows the whole half-space behind its tangent
        // plane, to within a few ulps of the plane.
        let (c, r, l) = ([3.0, 0.0, 4.0], 5.0, [0.0; 3]);
        let ball = Occluder::Sphere { center: c, radius: r };
        for x in [1e-6, 1e-3, 1.0, 1e6] {
            // n = c / 5 is the plane's normal; p ⟂ n.
            let p = [4.0, 7.0, -3.0];
            let side = |t: f64| [p[0] + t * 0.6, p[1], p[2] + t * 0.8];
            assert!(ball.blocks(side(x), l), "{x}");
            assert!(!ball.blocks(side(-x), l), "{x}");
        }
        // A ball 1e-12 of its distance across: its shadow's radius to 1e-9 relative.
        let (c, r) = ([1e6, 0.0, 0.0], 1e-6);
        let ball = Occluder::Sphere { center: c, radius: r };
        let x = 3e6; // 3 light distances behind: the shadow's radius is 3 r / sqrt(1 − (r/d)²).
        let edge = 3.0 * r;
        assert!(ball.blocks([x, edge * (1.0 - 1e-9), 0.0], [0.0; 3]));
        assert!(!ball.blocks([x, edge * (1.0 + 1e-9), 0.0], [0.0; 3]));
    }

    /// Issue 60 (4): a shadow's end on a ray with a surface at any finite
    /// distance is found to adjacent doubles, as on an open ray. The light at
    /// the origin, a ball of radius 1 at (0, 0, 2): its shadow is the cone of
    /// half-angle 30° behind it; the ray x = 1.2 along +z enters it at
    /// z = 1.2·√3 and never leaves; run back along −z from z = 3 it starts in
    /// it and leaves there.
    #[test]
    fn a_shadows_end_is_found_whatever_the_surfaces_distance() {
        let occ = [Occluder::Sphere { center: [0.0, 0.0, 2.0], radius: 1.0 }];
        let edge = 1.2 * 3f64.sqrt();
        for surface in [Some(20.0), Some(1e60), Some(1e70), Some(1e80), Some(1e200), Some(f64::MAX), None] {
            let ray = |origin: Vec3, dz: f64| PhysicalRay {
                origin,
                direction: [0.0, 0.0, dz],
                surface_distance: surface,
                light: [0.0; 3],
                intensity: 1.0,
                sigma_t: 0.1,
                sigma_s: 0.1,
            };
            let into = lit_intervals(&ray([1.2, 0.0, 0.0], 1.0), &occ);
            assert_eq!(into.len(), 1, "{surface:?}: {into:?}");
            assert!(into[0].0 == 0.0 && (into[0].1 / edge - 1.0).abs() < 1e-14, "{surface:?}: {into:?}");
            let out = lit_intervals(&ray([1.2, 0.0, 3.0], -1.0), &occ);
            let end = surface.unwrap_or(f64::INFINITY);
            assert_eq!(out.len(), 1, "{surface:?}: {out:?}");
            assert!((out[0].0 / (3.0 - edge) - 1.0).abs() < 1e-14 && out[0].1 == end, "{surface:?}: {out:?}");
        }
    }

    /// Issue 60 (5): an occluder is a closed opaque surface. A viewer and a
    /// light inside a ball see each other (the ray lit to the far wall); inside
    /// and outside do not; a light on the surface lights the inside.
    #[test]
    fn occluders_are_closed_surfaces() {
        let ball = Occluder::Sphere { center: [2.5, 1.0, 0.0], radius: 10.0 };
        let boxed = Occluder::Cuboid { min: [-5.0, -5.0, -5.0], max: [5.0, 5.0, 5.0] };
        for occ in [ball, boxed] {
            assert!(!occ.blocks([1.0, 0.5, 0.2], [0.0; 3]), "{occ:?}: inside to inside");
            assert!(occ.blocks([40.0, 0.5, 0.2], [0.0; 3]), "{occ:?}: outside to inside");
            assert!(occ.blocks([0.0; 3], [40.0, 0.5, 0.2]), "{occ:?}: inside to outside");
        }
        let ray = PhysicalRay {
            origin: [0.0; 3],
            direction: [1.0, 0.0, 0.0],
            surface_distance: Some(12.0),
            light: [1.0, 1.0, 0.0],
            intensity: 1.0,
            sigma_t: 0.1,
            sigma_s: 0.1,
        };
        assert_eq!(lit_intervals(&ray, &[ball]), vec![(0.0, 12.0)]);
        // A light on the ball's surface at the origin, the ball on +x: the ray
        // y = 0.5 along +x from x = −1 is lit up to the light's tangent plane
        // (s = 1), dark until it enters the ball (x = 1 − √0.75), lit inside it
        // and dark behind it.
        let on = Occluder::Sphere { center: [1.0, 0.0, 0.0], radius: 1.0 };
        let ray = PhysicalRay { origin: [-1.0, 0.5, 0.0], light: [0.0; 3], surface_distance: None, ..ray };
        let lit = lit_intervals(&ray, &[on]);
        let want = [(0.0, 1.0), (2.0 - 0.75f64.sqrt(), 2.0 + 0.75f64.sqrt())];
        assert_eq!(lit.len(), 2, "{lit:?}");
        for (x, y) in lit.iter().zip(want) {
            assert!((x.0 - y.0).abs() < 1e-12 && (x.1 - y.1).abs() < 1e-12, "{lit:?}");
        }
    }
}
