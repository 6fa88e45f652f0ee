//! End-to-end tests across the airlight crates live in `tests/`; this library
//! holds what they share: where the repository and its committed outputs are.

use std::path::PathBuf;

/// The repository root (the workspace directory).
pub fn repo_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).parent().expect("tests/ sits in the workspace").to_path_buf()
}

/// The committed `generated/` directory.
pub fn generated_dir() -> PathBuf {
    repo_root().join("generated")
}

/// The committed coefficient files, in catalog order.
pub fn committed_models() -> Vec<airlight_fit::coeffs::ModelFile> {
    airlight_fit::catalog::load(&generated_dir().join("coefficients")).expect("committed coefficient files parse")
}
