//! Scene files: any text parses to a scene or to one error naming the file, and
//! a parsed scene plans against the committed models or says why not; never a
//! panic.
#![no_main]
use airlight_codegen::scene;
use libfuzzer_sys::fuzz_target;
use std::sync::OnceLock;

fn models() -> &'static [airlight_fit::coeffs::ModelFile] {
    static M: OnceLock<Vec<airlight_fit::coeffs::ModelFile>> = OnceLock::new();
    M.get_or_init(|| {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../generated/coefficients");
        airlight_fit::catalog::load(&dir).expect("committed coefficient files")
    })
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    match scene::parse("s.toml", text) {
        Ok(s) => {
            let _ = scene::plan(&s, models()).map_err(|e| s.plan_error(&e).to_string());
        }
        Err(e) => assert!(e.to_string().starts_with("s.toml"), "{e}"),
    }
});
