//! What the probe tests (`third_probe.rs`, `fourth_probe.rs`) share: the
//! binary, a scratch folder, and whether a GPU adapter is required.

use std::path::PathBuf;
use std::process::{Command, Output};

/// Runs the `airlight` binary with `args`.
pub fn airlight(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_airlight")).args(args).output().expect("runs")
}

/// A fresh scratch folder for this process and `name`.
pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("airlight-probe-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A run's standard error.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Whether `AIRLIGHT_REQUIRE_GPU=1`: a missing adapter fails instead of skipping.
pub fn gpu_required() -> bool {
    std::env::var("AIRLIGHT_REQUIRE_GPU").is_ok_and(|v| v == "1")
}

/// The physical shadowed entry's header.
pub const HEAD: &str = "ox,oy,oz,dx,dy,dz,surface,lx,ly,lz,intensity,sigma_t,sigma_s,g,spheres";
