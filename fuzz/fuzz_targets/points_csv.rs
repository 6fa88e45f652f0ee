//! The eval input files: any text as a points file and as a rays file parses to
//! rows or to one located error, never a panic; what parses renders.
#![no_main]
use airlight_truth::points_csv;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    match points_csv::parse("in.csv", text, |_| Ok(())) {
        Ok(rows) => {
            let values: Vec<f64> = rows.iter().map(|r| r.point.tau).collect();
            let _ = points_csv::render(&rows, &values);
        }
        Err(e) => assert!(e.to_string().starts_with("in.csv:"), "{e}"),
    }
    let any = |_: &airlight_truth::geometry::PhysicalRay, _: f64| Ok(());
    match points_csv::parse_rays("in.csv", text, &any) {
        Ok(rows) => {
            for r in &rows {
                // The f64 physical entry on whatever parsed: a value or a typed error.
                let v = r.ray.radiance(r.g, &|_| 1.0);
                if let Ok(v) = v {
                    assert!(!v.is_nan() && v >= 0.0, "{v} at line {}", r.line);
                }
            }
            let _ = points_csv::render_rays(&rows, &vec![0.0; rows.len()]);
        }
        Err(e) => assert!(e.to_string().starts_with("in.csv:"), "{e}"),
    }
});
