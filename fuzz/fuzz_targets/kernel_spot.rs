//! Every generated Rust f32 kernel's spot entry on arbitrary f32 inputs: no
//! panic, no abort, and on valid input (finite positions, direction and axis,
//! finite cone cosines, finite intensity, σt and σs ≥ 0 per channel, any surface
//! but NaN's meaning "none", g in range) three finite values ≥ 0.
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

fuzz_target!(|data: [u32; 23]| {
    let x = data.map(f32::from_bits);
    let (origin, dir, surface, light, axis) = ([x[0], x[1], x[2]], [x[3], x[4], x[5]], x[6], [x[7], x[8], x[9]], [x[10], x[11], x[12]]);
    let (cos_outer, cos_inner, intensity) = (x[13], x[14], x[15]);
    let (sigma_t, sigma_s, g) = ([x[16], x[17], x[18]], [x[19], x[20], x[21]], x[22]);
    let finite = |v: &[f32]| v.iter().all(|c| c.is_finite());
    for k in airlight_kernels::KERNELS {
        let Some(spot) = k.spot else { continue };
        let v = spot(origin, dir, surface, light, axis, cos_outer, cos_inner, intensity, sigma_t, sigma_s, g);
        let [lo, hi] = g_range(k.name);
        let g_ok = !k.params.contains(&"g") || (lo..=hi).contains(&g);
        let valid = finite(&origin)
            && finite(&dir)
            && finite(&light)
            && finite(&axis)
            && finite(&[cos_outer, cos_inner])
            && intensity.is_finite()
            && intensity >= 0.0
            && sigma_t.iter().chain(&sigma_s).all(|&s| s.is_finite() && s >= 0.0)
            && g_ok;
        if valid {
            assert!(
                v.iter().all(|c| c.is_finite() && *c >= 0.0),
                "{}: spot({origin:?}, {dir:?}, {surface:e}, {light:?}, {axis:?}, {cos_outer:e}, {cos_inner:e}, {intensity:e}, {sigma_t:?}, {sigma_s:?}, {g:e}) = {v:?}",
                k.name
            );
        }
    }
});
