//! Every integration test of this crate, in one binary: one link instead of one
//! per file, and their tests run side by side on every core. Each file is a
//! module named after it (`cargo test -p <crate> --test integration <module>::`).

mod coefficient_files;
mod declared_bounds;
mod engine_packages;
mod examples;
mod generated_is_current;
mod glsl_twins;
mod import_graph;
mod includes_compose;
mod ir_cost;
mod issue23_edges;
mod model_properties;
mod paper_facts;
mod phi_family;
mod physical_scene;
mod properties;
mod rust_kernels;
mod scene_kernels;
mod shader_validation;
mod shadowmap_walk;
mod shafts;
mod three_package;
mod wesl_npm;
