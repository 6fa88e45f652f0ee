//! Every generated Rust f32 kernel's shafts accumulator (point and spot lights) on
//! arbitrary f32 inputs and up to 12 visibility samples: no panic, no abort, no
//! hang, and on valid input (the physical entry's, samples at finite distances
//! ≥ 0 in increasing order with visibility in [0, 1], any end) finite values ≥ 0.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::sync::OnceLock;

/// Each kernel's g range, from the committed index.
fn g_range(name: &str) -> [f32; 2] {
    static INDEX: OnceLock<airlight_shapes::vocab::Index> = OnceLock::new();
    let index = INDEX.get_or_init(|| {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../generated");
        airlight_shapes::vocab::Index::load(&dir).expect("generated/kernels.toml")
    });
    index.get(name).map(|e| [e.g[0] as f32, e.g[1] as f32]).expect("every kernel is in the index")
}

fuzz_target!(|data: ([u32; 24], Vec<(u32, u8)>)| {
    let (head, raw) = data;
    let x = head.map(f32::from_bits);
    let (origin, dir, end, light, axis) = ([x[0], x[1], x[2]], [x[3], x[4], x[5]], x[6], [x[7], x[8], x[9]], [x[10], x[11], x[12]]);
    let (cos_outer, cos_inner, intensity) = (x[13], x[14], x[15]);
    let (sigma_t, sigma_s, g) = ([x[16], x[17], x[18]], [x[19], x[20], x[21]], x[22]);
    // Samples: distances as given (sorted where the input is to be valid), visibility in steps of 1/255.
    let mut samples: Vec<[f32; 2]> = raw.iter().take(12).map(|&(s, v)| [f32::from_bits(s), f32::from(v) / 255.0]).collect();
    let ordered = samples.iter().all(|p| p[0].is_finite() && p[0] >= 0.0);
    if ordered && x[23].to_bits() & 1 == 0 {
        samples.sort_by(|a, b| a[0].total_cmp(&b[0]));
    }
    let increasing = ordered && samples.windows(2).all(|w| w[0][0] <= w[1][0]);
    let finite = |v: &[f32]| v.iter().all(|c| c.is_finite());
    for k in airlight_kernels::KERNELS {
        let [lo, hi] = g_range(k.name);
        let g_ok = !k.params.contains(&"g") || (lo..=hi).contains(&g);
        let valid_point = finite(&origin)
            && finite(&dir)
            && finite(&light)
            && intensity.is_finite()
            && intensity >= 0.0
            && sigma_t[0].is_finite()
            && sigma_t[0] >= 0.0
            && sigma_s[0].is_finite()
            && sigma_s[0] >= 0.0
            && g_ok
            && increasing
            && !end.is_nan();
        if let Some(f) = k.shadowed {
            let v = f(&samples, end, origin, dir, light, intensity, sigma_t[0], sigma_s[0], g);
            if valid_point {
                assert!(v.is_finite() && v >= 0.0, "{}: shadowed({samples:?}, {end:e}, {origin:?}, {dir:?}, {light:?}, {intensity:e}, {:e}, {:e}, {g:e}) = {v}", k.name, sigma_t[0], sigma_s[0]);
            }
        }
        if let Some(f) = k.spot_shadowed {
            let v = f(&samples, end, origin, dir, light, axis, cos_outer, cos_inner, intensity, sigma_t, sigma_s, g);
            let valid = valid_point
                && finite(&axis)
                && finite(&[cos_outer, cos_inner])
                && sigma_t.iter().chain(&sigma_s).all(|&s| s.is_finite() && s >= 0.0);
            if valid {
                assert!(v.iter().all(|c| c.is_finite() && *c >= 0.0), "{}: shadowed spot = {v:?}", k.name);
            }
        }
    }
});
