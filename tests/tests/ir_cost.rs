//! The kernels' IR operation counts (`airlight_shapes::ircost`) on the committed
//! WGSL: every branch counts at least the worst path; a straight-line rule
//! (`equiangular-8`) has nearly none beside it; the φ kernels' head, far and tail
//! branches add a third or more — what REPORT.md "What the cost follows" quotes.

use airlight_shapes::ircost::ir_costs;
use airlight_tests::generated_dir;

fn counts(name: &str) -> (usize, usize) {
    let src = std::fs::read_to_string(generated_dir().join(format!("wgsl/{name}.wgsl"))).unwrap();
    let f = format!("airlight_{}_airlight", name.replace('-', "_"));
    let (worst, every) = ir_costs(&src, &f).unwrap();
    (worst.ops, every.ops)
}

#[test]
fn every_branch_counts_at_least_the_worst_path_and_the_phi_branches_add_most() {
    let mut n = 0;
    // The kernels of the index (not the shadow-map walk every kernel shares).
    let index = airlight_shapes::vocab::Index::load(&generated_dir()).unwrap();
    for e in std::fs::read_dir(generated_dir().join("wgsl")).unwrap() {
        let path = e.unwrap().path();
        if path.extension().is_none_or(|x| x != "wgsl") {
            continue;
        }
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        if name.starts_with("scene-") || index.get(&name).is_err() {
            continue;
        }
        let (worst, every) = counts(&name);
        assert!(every >= worst && worst > 0, "{name}: every branch {every}, worst path {worst}");
        n += 1;
    }
    assert!(n >= 30, "{n} kernels");
    let (w, e) = counts("equiangular-8");
    assert!((e as f64) < 1.05 * w as f64, "equiangular-8: {e} against {w}");
    for name in ["phi-iso-4", "phi-4"] {
        let (w, e) = counts(name);
        assert!(e as f64 > 1.25 * w as f64, "{name}: {e} against {w}");
    }
}
