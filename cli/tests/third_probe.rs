//! Issue 37's reproductions from a shell, on every target they reach: a light on
//! an occluder's surface, balls from 1e-10 to 1e200 of their distance across, a
//! ray with more lit runs than the accumulators hold at once, samples past the
//! GPU harness's old 128, and the input the shadowed entry used to take.

use crate::probe;

use probe::{airlight, gpu_required, scratch, stderr, HEAD};

/// `eval --entry shadowed` of `input` with `args`: the last column of each row,
/// or `None` where the GPU targets are skipped (no adapter, not required).
fn shadowed(input: &std::path::Path, args: &[&str]) -> Option<Vec<f64>> {
    let mut all = vec!["eval", "--entry", "shadowed", "-i", input.to_str().unwrap()];
    all.extend_from_slice(args);
    let o = airlight(&all);
    if !o.status.success() && !gpu_required() && stderr(&o).contains("no GPU adapter") {
        eprintln!("SKIPPED eval --entry shadowed {args:?}: {}", stderr(&o));
        return None;
    }
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    let out = String::from_utf8(o.stdout).unwrap();
    Some(out.lines().skip(1).map(|l| l.rsplit(',').next().unwrap().parse().unwrap()).collect())
}

/// The targets a model's shadowed entry runs on.
const TARGETS: [&[&str]; 4] = [&[], &["--precision", "f32"], &["--target", "wgsl"], &["--target", "glsl"]];

#[test]
fn lights_on_surfaces_and_balls_of_any_size_are_shadowed_on_every_target() {
    let dir = scratch("surface");
    let input = dir.join("rays.csv");
    // mpmath's values over lit intervals found by bisection (issue 37), then rays
    // whose values lie in f32's range (the tiny balls' at σt = 1e-6, I = 1e12).
    let rows: [(&str, Option<f64>); 9] = [
        ("-1,5,0,1,0,0,inf,0,0,0,1,0.1,0.1,0,1 0 0 1", Some(1.80666e-4)),
        ("-1,5,0,1,0,0,inf,0,0,0,1,0.1,0.1,0.5,3 0 4 5", Some(1.10352e-4)),
        ("1000010,0.002,0,1,-0.000002,0,inf,0,0,0,1,0.0001,0.0001,0,1000000 0 0 0.001", Some(1.22181e-57)),
        ("1000010,0.002,0,1,-0.000002,0,inf,0,0,0,1,0.0001,0.0001,0,1000000 0 0 0.0001", Some(1.43990e-57)),
        // The viewer and the light inside a ball 2e200 across: a closed surface,
        // so they see each other and the ray is lit to the far wall (issue 60:
        // NaN here stands for the unshadowed value, computed below).
        ("0,0,0,1,0,0,inf,1,1,0,1,0.1,0.1,0,1.9e200 0 0 2e200", Some(f64::NAN)),
        ("0,0,0,1,0,0,inf,5,1,0,1,0.1,0.1,0,5 1 0 1e-300", Some(0.0)),
        ("1000010,0.002,0,1,-0.000002,0,inf,0,0,0,1e12,0.000001,0.000001,0,1000000 0 0 0.001", None),
        ("1000010,0.0002,0,1,-0.0000002,0,inf,0,0,0,1e12,0.000001,0.000001,0.3,1000000 0 0 0.0001", None),
        ("-1,5,0,1,0.2,0.1,30,0,0,0,1,0.8,0.8,-0.4,-3 0 -4 5", None),
    ];
    let text: String =
        std::iter::once(HEAD.to_string()).chain(rows.iter().map(|r| r.0.to_string())).collect::<Vec<_>>().join("\n");
    std::fs::write(&input, text + "\n").unwrap();
    let reference = shadowed(&input, &["--model", "reference"]).unwrap();
    let unshadowed = airlight_truth::geometry::PhysicalRay {
        origin: [0.0; 3],
        direction: [1.0, 0.0, 0.0],
        surface_distance: None,
        light: [1.0, 1.0, 0.0],
        intensity: 1.0,
        sigma_t: 0.1,
        sigma_s: 0.1,
    }
    .radiance(0.0, &|p| airlight_truth::reference::airlight(p).unwrap())
    .unwrap();
    for ((row, want), got) in rows.iter().zip(&reference) {
        if let Some(w) = want.map(|w| if w.is_nan() { unshadowed } else { w }) {
            let err = if w == 0.0 { got.abs() } else { (got / w - 1.0).abs() };
            assert!(err < 1e-5, "{row}: {got:e} against {w:e}");
        }
    }
    // The unshadowed ray would be 4.6x brighter on the first: the shadow is there.
    assert!(reference[8] > 0.0);
    for args in TARGETS {
        let mut all = vec!["--model", "phi-8"];
        all.extend_from_slice(args);
        let Some(got) = shadowed(&input, &all) else { continue };
        for ((row, r), x) in rows.iter().zip(&reference).zip(&got) {
            if *r == 0.0 {
                assert_eq!(*x, 0.0, "{args:?} {}", row.0);
            } else if *r > 1e-30 {
                assert!(((x - r) / r).abs() < 2e-5, "{args:?} {}: {x:e} against {r:e}", row.0);
            }
        }
    }
    // The spot entry: the same ball, a cone up the y axis (the ray inside it).
    let spot = dir.join("spot.csv");
    std::fs::write(
        &spot,
        "ox,oy,oz,dx,dy,dz,surface,lx,ly,lz,ax,ay,az,cos_outer,cos_inner,intensity,sigma_t_r,sigma_t_g,sigma_t_b,\
         sigma_s_r,sigma_s_g,sigma_s_b,g,spheres\n\
         -1,5,0,1,0,0,inf,0,0,0,0,1,0,0.5,0.6,1,0.1,0.1,0.1,0.1,0.1,0.1,0.5,3 0 4 5\n",
    )
    .unwrap();
    let o = airlight(&["eval", "--entry", "shadowed", "-i", spot.to_str().unwrap(), "--model", "reference"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8(o.stdout).unwrap();
    let r: f64 = out.lines().nth(1).unwrap().split(',').nth_back(2).unwrap().parse().unwrap();
    assert!((r / 1.10352e-4 - 1.0).abs() < 1e-4, "spot r {r:e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// 100 small balls cast 100 shadows across one ray: 101 lit runs, more than the
/// 32 the accumulators hold before they evaluate. Every target sums them all (the
/// merging this replaced was 0.97% off here, ~500x phi-8's f32 bound).
#[test]
fn a_hundred_and_one_lit_runs_are_summed_exactly_on_every_target() {
    let dir = scratch("runs");
    let input = dir.join("runs.csv");
    let balls: Vec<String> = (0..100).map(|k| format!("{} 20 0 0.08", 0.5 * (f64::from(k) + 0.5) + 25.0)).collect();
    std::fs::write(&input, format!("{HEAD}\n0,0,0,1,0,0,100,50,40,0,1,0.02,0.02,0.3,{}\n", balls.join(";"))).unwrap();
    let reference = shadowed(&input, &["--model", "reference"]).unwrap()[0];
    // The ray really has 101 lit runs.
    let occ = airlight_truth::shafts::parse_spheres(&balls.join(";")).unwrap();
    let ray = airlight_truth::geometry::PhysicalRay {
        origin: [0.0; 3],
        direction: [1.0, 0.0, 0.0],
        surface_distance: Some(100.0),
        light: [50.0, 40.0, 0.0],
        intensity: 1.0,
        sigma_t: 0.02,
        sigma_s: 0.02,
    };
    assert_eq!(airlight_truth::shafts::lit_intervals(&ray, &occ).len(), 101);
    for args in TARGETS {
        let mut all = vec!["--model", "phi-8"];
        all.extend_from_slice(args);
        let Some(got) = shadowed(&input, &all) else { continue };
        assert!(((got[0] - reference) / reference).abs() < 2e-5, "{args:?}: {} against {reference}", got[0]);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The GPU harness takes any number of samples: a march of 256 steps, 300
/// look-ups, and an exact feed of 400 samples run on the shader targets.
#[test]
fn the_gpu_harness_takes_any_number_of_samples() {
    let dir = scratch("samples");
    let input = dir.join("rays.csv");
    let balls: Vec<String> = (0..100).map(|k| format!("{} 20 0 0.08", 0.5 * (f64::from(k) + 0.5) + 25.0)).collect();
    std::fs::write(
        &input,
        format!("{HEAD}\n0,0,0,1,0,0,100,50,40,0,1,0.02,0.02,0.3,{}\n0,0,0,1,0.05,0,25,6,2,0.5,3,0.12,0.08,0.6,3 1.2 0.3 0.35\n", balls.join(";")),
    )
    .unwrap();
    for (model, extra) in [("raymarch-256", &[][..]), ("phi-8", &["--samples", "300"][..]), ("phi-8", &[][..])] {
        let mut base = vec!["--model", model];
        base.extend_from_slice(extra);
        let want = shadowed(&input, &base).unwrap();
        for target in ["wgsl", "glsl"] {
            let mut all = base.clone();
            all.extend_from_slice(&["--target", target]);
            let Some(got) = shadowed(&input, &all) else { continue };
            for (x, w) in got.iter().zip(&want) {
                assert!(((x - w) / w).abs() < 1e-4, "{model} {extra:?} {target}: {x} against {w}");
            }
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A row shorter than the header is refused (it was taken as a ray without
/// occluders), with its line and column and exit 2; so is a model unknown
/// outside the repository, with the hint every entry gives.
#[test]
fn short_rows_and_unknown_models_are_refused_with_their_reason() {
    let dir = scratch("short");
    let input = dir.join("short.csv");
    std::fs::write(&input, format!("{HEAD}\n-1,5,0,1,0,0,inf,0,0,0,1,0.1,0.1,0\n")).unwrap();
    let o = airlight(&["eval", "--entry", "shadowed", "-i", input.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(
        e.contains("short.csv:2") && e.contains("spheres") && e.contains("14 fields") && e.lines().count() == 1,
        "{e}"
    );
    std::fs::write(&input, format!("{HEAD}\n-1,5,0,1,0,0,inf,0,0,0,1,0.1,0.1,0,\n")).unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_airlight"))
        .args(["eval", "--entry", "shadowed", "--model", "phi-8", "-i", input.to_str().unwrap()])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(e.contains("pass --root") && e.contains("phi-8"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `eval` of `csv` (written to a scratch file) with `args`: each row's last column.
fn eval_rows(dir: &std::path::Path, csv: &str, args: &[&str]) -> Option<Vec<f64>> {
    let input = dir.join("in.csv");
    std::fs::write(&input, csv).unwrap();
    let mut all = vec!["eval", "-i", input.to_str().unwrap()];
    all.extend_from_slice(args);
    let o = airlight(&all);
    if !o.status.success() && !gpu_required() && stderr(&o).contains("no GPU adapter") {
        eprintln!("SKIPPED eval {args:?}: {}", stderr(&o));
        return None;
    }
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    let out = String::from_utf8(o.stdout).unwrap();
    Some(out.lines().skip(1).map(|l| l.rsplit(',').next().unwrap().parse().unwrap()).collect())
}

/// The f32 kernels where `e^{−τ}` is subnormal (τ > 87) but the answer is not
/// (issue 37 item 9: every φ and lite member was 1.7% off), and a product that
/// underflowed in its middle (item 11: `equiangular-32` gave 0 for 1.2e-20).
#[test]
fn f32_kernels_keep_their_digits_where_a_factor_is_subnormal() {
    let dir = scratch("subnormal");
    let csv = "tau,gamma,rho,g\n100,1e-30,1.0000009536743164,0\n100,1e-30,1.0000009536743164,0.9\n50,1e-30,0.5,0.95\n";
    let want = eval_rows(&dir, csv, &["--model", "reference"]).unwrap();
    // Isotropic members take g = 0 only: the first row.
    let iso_csv = csv.lines().take(2).collect::<Vec<_>>().join("\n") + "\n";
    for model in ["phi-6", "phi-iso-6", "lite-12", "lite-iso-5", "equiangular-32"] {
        let rows = if model.contains("iso") { iso_csv.as_str() } else { csv };
        for target in [&["--precision", "f32"][..], &["--target", "wgsl"], &["--target", "glsl"]] {
            let mut args = vec!["--model", model];
            args.extend_from_slice(target);
            let Some(got) = eval_rows(&dir, rows, &args) else { continue };
            for (i, (x, w)) in got.iter().zip(&want).enumerate() {
                // The equiangular rule's item is the third row (its first two are its
                // own quadrature error past the light, 5%, within its declared 0.21).
                if model.starts_with("equi") && i < 2 {
                    continue;
                }
                let tol = if model.starts_with("lite") || model.starts_with("equi") { 1e-2 } else { 1e-4 };
                assert!(((x - w) / w).abs() < tol, "{model} {target:?} row {i}: {x:e} against {w:e}");
            }
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The split family (`segments-N`, `hg-expN`) where `e^{−τ}` is subnormal in f32
/// (item 11: `segments-N` gave 0 for a near-light radiance of 1.8e-18): its sums are
/// taken relative to `e^{−τ}`, so a canonical value f32 holds is kept, and the
/// radiance is formed from mantissas and exponents, so a radiance f32 holds is kept
/// where `A` alone is subnormal. Against the f64 model of the same member (its own
/// approximation error is not at issue here), on every target.
#[test]
fn split_kernels_keep_values_that_f32_holds_past_tau_87() {
    let dir = scratch("split-subnormal");
    // Near the axis ahead of the viewer, past and before the light: A ≈ 1e-34 … 1e-15.
    let points = "tau,gamma,rho,g\n\
                  102.0258,1.11959e-30,inf,0\n92.8988,7.52398e-23,inf,0\n88.3587,4.60407e-17,0.9999990463256836,0\n95,1e-20,1.5,0\n";
    // Light 1e-3 off the ray, σt = 6188, τ ≈ 95–99: A ≈ 1e-42 (subnormal), the radiance ≈ 1e-18.
    let rays = "ox,oy,oz,dx,dy,dz,surface,lx,ly,lz,intensity,sigma_t,sigma_s,g\n\
                0,0,0,1,0,0,inf,0.0153,0.001,0,2.4e18,6188,6188,0\n\
                0,0,0,1,0,0,inf,0.016,0.001,0,1e20,6188,6188,0\n\
                0,0,0,1,0,0,0.5,-0.016,0.001,0,1e20,6188,6188,0\n";
    for model in ["segments-2", "segments-16", "hg-exp2"] {
        for (csv, entry) in [(points, "airlight"), (rays, "radiance")] {
            let want = eval_rows(&dir, csv, &["--model", model, "--entry", entry]).unwrap();
            assert!(want.iter().all(|w| *w > 1e-36 && *w < 1e-10), "{model} {entry}: {want:?}");
            for target in [&["--precision", "f32"][..], &["--target", "wgsl"], &["--target", "glsl"]] {
                let mut args = vec!["--model", model, "--entry", entry];
                args.extend_from_slice(target);
                let Some(got) = eval_rows(&dir, csv, &args) else { continue };
                for (i, (x, w)) in got.iter().zip(&want).enumerate() {
                    assert!(((x - w) / w).abs() < 1e-3, "{model} {entry} {target:?} row {i}: {x:e} against {w:e}");
                }
            }
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The Sun tables behind the viewer near the axis, where their two look-ups
/// cancel, returned f32's largest value for an answer of ~1e-45 (item 8); and a
/// ray of length zero gave light (item 10). Every target now stays within the
/// physical bound `A ≤ e^{−τ} P (π − γ)/h`, and an empty ray is dark.
#[test]
fn sun_tables_stay_within_the_physical_bound_and_an_empty_ray_is_dark() {
    let dir = scratch("sun");
    let csv = "ox,oy,oz,dx,dy,dz,surface,lx,ly,lz,intensity,sigma_t,sigma_s,g\n\
               31.947594,28.840456,0,0,-1e20,0,-1,31.947594,38.840454,-0.00001,115.87657,10,10,0\n\
               -0.0023041944950819016,0.0013113360619172454,-0.0011038840748369694,690923201626112,-163974653935616,\
               704086202646528,0,-0.0014061576221138239,0.0017435409827157855,-0.0010218555107712746,0.6553020477294922,\
               1000,10000,0\n";
    for model in ["sun2005-64", "sun2005-128", "sun2005-512"] {
        for target in [&[][..], &["--precision", "f32"], &["--target", "wgsl"], &["--target", "glsl"]] {
            let mut args = vec!["--entry", "radiance", "--model", model];
            args.extend_from_slice(target);
            let Some(got) = eval_rows(&dir, csv, &args) else { continue };
            // σs I / D · e^{−100} P · (π − γ)/h, (π − γ)/h within 1% of 1 here: 3.4e-43.
            assert!(got[0].is_finite() && got[0] >= 0.0 && got[0] < 1e-36, "{model} {target:?}: {}", got[0]);
            assert_eq!(got[1], 0.0, "{model} {target:?}: an empty ray");
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
