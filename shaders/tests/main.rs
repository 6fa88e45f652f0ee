//! Every integration test of this crate, in one binary: one link instead of one
//! per file, and their tests run side by side on every core. Each file is a
//! module named after it (`cargo test -p <crate> --test integration <module>::`).

mod common;
mod gate;
mod harness;
mod penumbra_rule;
mod scene_variants;
mod shafts_extremes;
mod shafts_mapped;
mod shafts_render;
mod shafts_sampled;
