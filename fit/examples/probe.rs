//! Ad-hoc: observed max on many fresh random points vs declared max.
use airlight_fit::domains::{Domain, SplitMix64};
use airlight_fit::model::Model;
use airlight_fit::reference::{airlight, Point};
use airlight_fit::stats::rel_error;
use std::f64::consts::PI;
fn main() {
    let mut files = airlight_fit::coeffs::load_dir(std::path::Path::new("generated/coefficients")).unwrap();
    files.sort_by(|a, b| a.model.name.cmp(&b.model.name));
    for m in &files {
        for (d, seed) in [(Domain::Thin, 11u64), (Domain::Dense, 12)] {
            let mut rng = SplitMix64(seed);
            let (tlo, thi) = d.tau_range();
            let g = m.model.g_range;
            let pts: Vec<Point> = (0..100_000)
                .map(|i| {
                    let e = |r: &mut SplitMix64| {
                        let x = r.next_f64();
                        if i % 4 == 0 {
                            x * x * x
                        } else if i % 4 == 1 {
                            1.0 - x * x * x
                        } else {
                            x
                        }
                    };
                    let tau = tlo + (thi - tlo) * e(&mut rng);
                    let gamma = 0.01 + (PI - 0.02) * e(&mut rng);
                    let rho = if rng.next_f64() < 0.15 { f64::INFINITY } else { 0.01 * 1e4f64.powf(e(&mut rng)) };
                    Point { tau, gamma, rho, g: g.0 + (g.1 - g.0) * e(&mut rng) }
                })
                .collect();
            let errs = airlight_fit::parallel::map(
                &pts,
                |p| rel_error(m.model.eval_unchecked(*p), airlight(*p).unwrap()),
                &|_, _| {},
            );
            let (i, w) = errs.iter().enumerate().fold((0, 0.0), |b, (i, &e)| if e > b.1 { (i, e) } else { b });
            let dec = m.error(d.name()).unwrap().max_rel;
            println!(
                "{:<18} {:<6} declared {:.3e} observed {:.3e} ratio {:.2} at {:?}",
                m.model.name,
                d.name(),
                dec,
                w,
                w / dec,
                pts[i]
            );
        }
    }
}
