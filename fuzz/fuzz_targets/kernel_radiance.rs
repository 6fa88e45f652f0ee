//! Every generated Rust f32 kernel's physical entry on arbitrary f32 inputs: no
//! panic, no abort, and on valid input (finite positions, a finite direction,
//! finite σt, σs and intensity ≥ 0, any surface but NaN's meaning "none", g in
//! range) a finite value ≥ 0.
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

fuzz_target!(|data: [u32; 14]| {
    let x = data.map(f32::from_bits);
    let (origin, dir, surface, light) = ([x[0], x[1], x[2]], [x[3], x[4], x[5]], x[6], [x[7], x[8], x[9]]);
    let (intensity, sigma_t, sigma_s, g) = (x[10], x[11], x[12], x[13]);
    let finite = |v: &[f32]| v.iter().all(|c| c.is_finite());
    for k in airlight_kernels::KERNELS {
        let v = (k.radiance)(origin, dir, surface, light, intensity, sigma_t, sigma_s, g);
        let [lo, hi] = g_range(k.name);
        let g_ok = !k.params.contains(&"g") || (lo..=hi).contains(&g);
        let valid = finite(&origin)
            && finite(&dir)
            && finite(&light)
            && [intensity, sigma_t, sigma_s].iter().all(|&s| s.is_finite() && s >= 0.0)
            && g_ok;
        if valid {
            assert!(
                v.is_finite() && v >= 0.0,
                "{}: radiance({origin:?}, {dir:?}, {surface:e}, {light:?}, {intensity:e}, {sigma_t:e}, {sigma_s:e}, {g:e}) = {v}",
                k.name
            );
        }
    }
});
