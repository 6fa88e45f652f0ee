//! The light-shafts render on small frames, both stages (the spot's
//! `window-shafts`, the point light's `street-lamp` with a cube shadow map):
//! a shadow map from depth passes, the fog by the exact walk, by the sampled
//! accumulator and by the march, and the reference over exact lit intervals.
//! Every value is finite and ≥ 0, the GPU frames find the same surfaces, the
//! exact frame leaks nowhere and beats the 512-step march on lit pixels, and
//! the sampled accumulator's mean fog error is below the 64-step march's.

mod common;

use airlight_shaders::gate;
use airlight_shaders::shafts::render::{self as sr, Method};

#[test]
fn the_shafts_renders_run_and_the_exact_walk_beats_the_march() {
    let Some(gpu) = common::open_or_skip("the_shafts_renders_run_and_the_exact_walk_beats_the_march") else {
        return;
    };
    let generated = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../generated");
    let index = gate::load_index(&generated).unwrap();
    let read = |name: &str| {
        let k = index.get(name).unwrap();
        (k, std::fs::read_to_string(generated.join(k.wgsl.as_deref().unwrap())).unwrap())
    };
    let texts = airlight_shaders::shafts::WalkTexts::load(&generated).unwrap();
    let src = texts.sources();
    let walk = sr::WalkWgsl { walk: src.wgsl, pyramid: src.pyramid };
    let (m, march) = read(sr::march_kernel());
    for stage in [sr::Stage::window_shafts(), sr::Stage::street_lamp()] {
        let (k, kernel) = read(&format!("scene-{}", stage.name));
        let view = sr::ShaftsView { width: 80, height: 45 };
        let frame = |k, kernel: &str, method| gpu.shafts_frame(&stage, k, kernel, walk, &view, method, 1).unwrap();
        let exact = frame(k, &kernel, Method::Exact);
        let sampled = frame(k, &kernel, Method::Sampled(128));
        let m64 = frame(m, &march, Method::March(64));
        let m512 = frame(m, &march, Method::March(512));
        for f in [&exact, &sampled, &m64, &m512] {
            for p in f.fog.iter().chain(&f.color) {
                assert!(p.iter().all(|x| x.is_finite() && *x >= 0.0), "{}: {:?}: {p:?}", stage.name, f.method);
            }
            assert!(exact.fog.iter().zip(&f.fog).all(|(a, b)| a[3] == b[3]), "the frames end their rays alike");
        }
        let (fog, color) = sr::reference(&stage, &view, &exact);
        assert!(fog.iter().chain(&color).all(|p| p.iter().all(|x| x.is_finite() && *x >= 0.0)));
        let classes = sr::classify(&view, &fog);
        assert!(classes.iter().filter(|c| c.is_some()).count() > 300, "{}: the light fills the frame", stage.name);
        let e = |f: &sr::Frame| sr::fog_errors(f, &fog, &classes);
        let (ex, sa, a64, a512) = (e(&exact), e(&sampled), e(&m64), e(&m512));
        eprintln!("{}:\nexact {ex:?}\nsampled 128 {sa:?}\nmarch 64 {a64:?}\nmarch 512 {a512:?}", stage.name);
        assert_eq!(sr::leak_pixels(&exact, &fog), 0, "{}: the exact frame leaks", stage.name);
        assert!(ex.lit_max < a512.lit_max && ex.lit_mean < a512.lit_mean, "{}: {ex:?} against {a512:?}", stage.name);
        assert!(sa.lit_mean < a64.lit_mean, "{}: {sa:?} against {a64:?}", stage.name);
    }
}
