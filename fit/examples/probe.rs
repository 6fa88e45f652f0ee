use airlight_fit::model::Model;
use airlight_fit::reference::{airlight, Point};
fn main() {
    let files = airlight_fit::coeffs::load_dir(std::path::Path::new("generated/coefficients")).unwrap();
    for name in ["paper-as-printed", "paper", "paper-refit", "segments-3", "segments-8"] {
        let m = &files.iter().find(|f| f.model.name == name).unwrap().model;
        let mut line = format!("{name:<18}");
        for tau in [0.5, 1.0, 2.0, 5.0, 10.0] {
            let mut w: f64 = 0.0;
            for i in 0..=60 {
                let gamma = 0.05 + 1.45 * i as f64 / 60.0;
                for rho in [1.5, 3.0, f64::INFINITY] {
                    let p = Point { tau, gamma, rho, g: 0.0 };
                    w = w.max((m.eval_unchecked(p) / airlight(p).unwrap() - 1.0).abs());
                }
            }
            line += &format!(" τ={tau}: {w:.3}");
        }
        println!("{line}");
    }
}
