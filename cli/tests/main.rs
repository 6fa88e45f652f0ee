//! Every integration test of this crate, in one binary: one link instead of one
//! per file, and their tests run side by side on every core. Each file is a
//! module named after it (`cargo test -p <crate> --test integration <module>::`).

mod cli;
mod docs;
mod fourth_probe;
mod plan;
mod probe;
mod third_probe;
