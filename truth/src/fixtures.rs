//! The public 30-digit reference values (see `tests/data/README.md`), compiled
//! in so that every report can measure against them wherever it runs.

use crate::reference::Point;

/// A fixture file: its name and contents.
pub const PUBLIC: [(&str, &str); 2] = [
    ("airlight_public.csv", include_str!("../tests/data/airlight_public.csv")),
    ("airlight_public_extreme.csv", include_str!("../tests/data/airlight_public_extreme.csv")),
];

/// Parses a fixture: `(point, exact A)` per row (`inf` allowed).
pub fn parse(contents: &str) -> Vec<(Point, f64)> {
    let num = |s: &str| if s == "inf" { f64::INFINITY } else { s.parse::<f64>().expect("fixture values are numbers") };
    contents
        .lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|f| num(f.trim())).collect();
            (Point::new(v[0], v[1], v[2], v[3]), v[4])
        })
        .collect()
}
