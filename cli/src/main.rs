//! `airlight`: the command line (see the crate's library). It does not link the
//! generated Rust kernels; the commands that run them go to `airlight-run`.

fn main() -> std::process::ExitCode {
    airlight_cli::main_with(airlight_cli::Kernels::Elsewhere)
}
