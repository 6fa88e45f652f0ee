//! Every generated Rust f32 kernel's canonical entry on arbitrary f32 inputs: no
//! panic, no abort, and on valid input (τ ≥ 0 or +∞, γ ∈ [0, π], any ρ, g in the
//! kernel's range) a finite value ≥ 0.
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

fuzz_target!(|data: [u32; 4]| {
    let [tau, gamma, rho, g] = data.map(f32::from_bits);
    for k in airlight_kernels::KERNELS {
        let v = (k.airlight)(tau, gamma, rho, g);
        let [lo, hi] = g_range(k.name);
        let g_ok = !k.params.contains(&"g") || (lo..=hi).contains(&g);
        let valid = tau >= 0.0 && (0.0..=std::f32::consts::PI).contains(&gamma) && g_ok;
        if valid {
            assert!(v.is_finite() && v >= 0.0, "{}: airlight({tau:e}, {gamma:e}, {rho:e}, {g:e}) = {v}", k.name);
        }
    }
});
