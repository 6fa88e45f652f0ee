use airlight_fit::catalog::*;
use std::time::Instant;
fn main() {
    let t = Instant::now();
    let fits = fit(None, &|_, _| {});
    eprintln!("fit {:.1}s", t.elapsed().as_secs_f64());
    for (n, f) in &fits.segments {
        eprintln!("seg {n}: rms {:.2e} max {:.2e} it {} {} kern {:.2e}", f.rms_rel, f.max_rel, f.outcome.iterations, f.outcome.termination, f.segments.kernel_error(airlight_fit::family::segments::Side::Forward).0);
    }
    eprintln!("paper seg {:?}", fits.paper_segments);
    for (k, b) in &fits.phase {
        for f in b { eprintln!("phase k{k} [{},{}]: rms {:.2e} max {:.2e} it {} {}", f.band.g_lo, f.band.g_hi, f.rms_rel, f.max_rel, f.outcome.iterations, f.outcome.termination); }
    }
    eprintln!("paper phase {:?} node {:.1e}", fits.paper_phase, fits.phase_node_error);
    let r = fits.ratio.as_ref().unwrap();
    let (n, f) = fits.expsum.as_ref().unwrap(); eprintln!("expsum near {:?} it {} far {:?} it {}", n.max_rel, n.outcome.iterations, f.max_rel, f.outcome.iterations);
    eprintln!("ratio rms {:.2e} max {:.2e} it {} {} ; paper {:?}", r.rms_rel, r.max_rel, r.outcome.iterations, r.outcome.termination, fits.paper_ratio);
    let t = Instant::now();
    let vals = validations(&[(0.0, 0.0), PAPER_G, MIRRORED_G], &|_, _| {});
    eprintln!("validation refs {:.1}s", t.elapsed().as_secs_f64());
    for spec in CATALOG.iter() {
        let mf = assemble(spec, &fits).unwrap();
        let mut line = format!("{:<18}", spec.name);
        for v in vals.iter().filter(|v| v.g_range == spec.g_range) {
            let e = measure(&mf.model, v);
            line += &format!(" {} max {:.2e} p99 {:.2e} nf {} neg {} |", e.domain, e.max_rel, e.p99_rel, e.non_finite, e.negative);
            if e.domain != "extreme" { line += &format!(" at {:?}|", e.worst); }
        }
        eprintln!("{line}");
    }
    eprintln!("total {:.1}s", t.elapsed().as_secs_f64());
}
