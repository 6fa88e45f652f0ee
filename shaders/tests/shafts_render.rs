//! The light-shafts render (issue 24) on a small frame: a shadow map from a
//! depth pass, the fog by the scene kernel's accumulator and by the march, and
//! the reference over exact lit intervals. Every value is finite and ≥ 0, the
//! GPU frames find the same surfaces, and the accumulator's mean fog error is
//! below the march's at 64 steps.

mod common;

use airlight_shaders::gate;
use airlight_shaders::shafts::render::{self as sr, Method};

#[test]
fn the_shafts_render_runs_and_the_accumulator_beats_a_march() {
    let Some(gpu) = common::open_or_skip("the_shafts_render_runs_and_the_accumulator_beats_a_march") else {
        return;
    };
    let generated = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../generated");
    let index = gate::load_index(&generated).unwrap();
    let read = |name: &str| {
        let k = index.get(name).unwrap();
        (k, std::fs::read_to_string(generated.join(k.wgsl.as_deref().unwrap())).unwrap())
    };
    let (k, kernel) = read("scene-window-shafts");
    let (m, march) = read(sr::march_kernel());
    let view = sr::ShaftsView { width: 64, height: 36 };
    let acc = gpu.shafts_frame(k, &kernel, &view, Method::Accumulator(sr::LOOK_UPS), 1).unwrap();
    let m64 = gpu.shafts_frame(m, &march, &view, Method::March(64), 1).unwrap();
    for f in [&acc, &m64] {
        for p in f.fog.iter().chain(&f.color) {
            assert!(p.iter().all(|x| x.is_finite() && *x >= 0.0), "{:?}: {p:?}", f.method);
        }
    }
    assert!(acc.fog.iter().zip(&m64.fog).all(|(a, b)| a[3] == b[3]), "the frames end their rays at the same surfaces");
    let (fog, color) = sr::reference(&view, &acc);
    assert!(fog.iter().chain(&color).all(|p| p.iter().all(|x| x.is_finite() && *x >= 0.0)));
    let classes = sr::classify(&view, &fog);
    assert!(classes.iter().filter(|c| c.is_some()).count() > 200, "the spot lights much of the frame");
    let (a, b) = (sr::fog_errors(&acc, &fog, &classes), sr::fog_errors(&m64, &fog, &classes));
    eprintln!("accumulator {a:?}\nmarch 64 {b:?}");
    assert!(a.lit_mean < b.lit_mean && a.edge_mean < b.edge_mean, "{a:?} against {b:?}");
}
