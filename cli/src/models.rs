//! `airlight models`: the registry with each model's declared errors.

use crate::workspace::registry;
use crate::Failure;
use airlight_shapes::vocab::Domain;
use std::path::PathBuf;

pub(crate) fn models(root: Option<PathBuf>) -> Result<(), Failure> {
    let (reg, files) = registry(root)?;
    println!(
        "{:<18} {:<14} {:>9} {:>9} {:>9} {:>9}  description",
        "model", "g range", "thin max", "thin p99", "dense max", "dense p99"
    );
    for m in reg.iter() {
        let e = |d: Domain, f: fn(&airlight_truth::domains::DomainErrors) -> f64| {
            files
                .iter()
                .find(|f| f.model.name == m.name())
                .and_then(|f| f.error(d))
                .map_or("-".to_string(), |e| format!("{:.1e}", f(e)))
        };
        println!(
            "{:<18} {:<14} {:>9} {:>9} {:>9} {:>9}  {}",
            m.name(),
            m.g_range_label(),
            e(Domain::Thin, |e| e.max_rel),
            e(Domain::Thin, |e| e.p99_rel),
            e(Domain::Dense, |e| e.max_rel),
            e(Domain::Dense, |e| e.p99_rel),
            m.summary()
        );
    }
    Ok(())
}
