//! The light-shafts render on small frames, both stages (the spot's
//! `window-shafts`, the point light's `street-lamp` with a cube shadow map):
//! a shadow map from depth passes, the fog by the exact walk, by the sampled
//! accumulator and by the march, and the reference over exact lit intervals.
//! Every value is finite and ≥ 0, the GPU frames find the same surfaces, the
//! walk's own counts agree with the exact frame's fog, the
//! exact frame leaks nowhere and beats the 512-step march on lit pixels, and
//! the sampled accumulator's mean fog error is below the 64-step march's.

use crate::common;

use airlight_shaders::gate;
use airlight_shaders::shafts::render::{self as sr, Method};
use airlight_truth::shafts::ShadowMap;

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
        // The walk alone counts what the exact frame's walks took: a pixel with
        // fog had lit runs, one without runs has none, and no walk ran out of steps.
        let walk_only = frame(k, &kernel, Method::Walk);
        let counts = sr::WalkCounts::of(&walk_only).unwrap();
        assert!(sr::WalkCounts::of(&exact).is_none());
        assert!(counts.walked > 0 && counts.runs_mean > 0.0 && counts.steps_max < 4096.0, "{}: {counts:?}", stage.name);
        for (e, w) in exact.fog.iter().zip(&walk_only.fog) {
            let lit = e[..3].iter().any(|x| *x > 0.0);
            assert!(!lit || w[1] >= 1.0, "{}: fog {e:?} from a ray without lit runs {w:?}", stage.name);
        }
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

/// The depth passes draw the map the reference casts: for each stage (the spot's
/// one face, the point light's six cube faces, at 256² here), the linear depth
/// the shipped pyramid pass makes of the rasterised map agrees with the f64
/// reference's map of the same faces (`ShadowMap::from_rows`: each texel's centre
/// ray cast against the analytic occluders) to 0.2%, on all but a few texels on
/// the occluders' silhouettes (the ball's facets, the raster's edge rule). A face
/// drawn upside down, or with another face's rows, fails on thousands.
#[test]
fn the_depth_passes_draw_the_map_the_reference_casts() {
    let Some(gpu) = common::open_or_skip("the_depth_passes_draw_the_map_the_reference_casts") else {
        return;
    };
    let generated = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../generated");
    let texts = airlight_shaders::shafts::WalkTexts::load(&generated).unwrap();
    for mut stage in [sr::Stage::window_shafts(), sr::Stage::street_lamp()] {
        stage.shadow_map = 256;
        let view = sr::ShaftsView { width: 64, height: 36 };
        let pyramid = gpu.stage_pyramid(&stage, &view, texts.sources().pyramid).unwrap();
        let rows: Vec<_> = stage.faces().iter().map(|f| f.map(|r| r.map(f64::from))).collect();
        let res = stage.shadow_map as usize;
        let map = ShadowMap::from_rows(stage.light.map(f64::from), &rows, res, &stage.occluders(), 0.0).unwrap();
        let (mut n, mut off, mut hits) = (0usize, 0usize, 0usize);
        for (f, levels) in pyramid.iter().enumerate() {
            for j in 0..res {
                for i in 0..res {
                    let finite = |x: f32| (x < 1e38).then_some(f64::from(x));
                    let want = finite(map.texel(f, i, j));
                    let got = finite(levels[0][j * res + i][0]);
                    n += 1;
                    hits += usize::from(want.is_some());
                    off += usize::from(match (want, got) {
                        (Some(w), Some(g)) => (g - w).abs() > 2e-3 * w,
                        (w, g) => w.is_some() != g.is_some(),
                    });
                }
            }
        }
        eprintln!("{}: {off} of {n} texels ({hits} on an occluder) differ", stage.name);
        assert_eq!(pyramid.len(), rows.len(), "{}: a layer per face", stage.name);
        assert!(hits * 20 > n, "{}: the occluders cover the map ({hits} of {n})", stage.name);
        assert!(off * 500 < hits, "{}: {off} of {n} texels differ from the cast", stage.name);
    }
}
