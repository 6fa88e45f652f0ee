//! The points file: CSV with a header naming `tau,gamma,rho,g` (any order, other
//! columns ignored), one point per line, `rho` may be `inf`. Errors name the
//! file, the line and the column.

use crate::reference::{ParamError, Point};
use std::fmt;

/// Columns a points file must have, in output order.
pub const COLUMNS: [&str; 4] = ["tau", "gamma", "rho", "g"];

/// One parsed row: the point and its four fields' text as written.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// 1-based line number in the file.
    pub line: usize,
    /// The point.
    pub point: Point,
    /// `tau, gamma, rho, g` as written in the file (trimmed).
    pub text: [String; 4],
}

/// A problem in a points file, located.
#[derive(Debug, Clone, PartialEq)]
pub struct CsvError {
    /// File name as given by the user.
    pub file: String,
    /// 1-based line number.
    pub line: usize,
    /// Column concerned, or `None` for the whole line.
    pub column: Option<String>,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for CsvError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.column {
            Some(c) => write!(f, "{}:{}: column '{}': {}", self.file, self.line, c, self.message),
            None => write!(f, "{}:{}: {}", self.file, self.line, self.message),
        }
    }
}

impl std::error::Error for CsvError {}

fn parse_number(text: &str) -> Option<f64> {
    match text.to_ascii_lowercase().as_str() {
        "inf" | "+inf" | "infinity" | "+infinity" => Some(f64::INFINITY),
        "-inf" | "-infinity" => Some(f64::NEG_INFINITY),
        "nan" | "+nan" | "-nan" => Some(f64::NAN),
        _ => text.parse::<f64>().ok(),
    }
}

/// Parses a points file. `file` is only used in messages. Every point is
/// validated against the domain of `A` (`check` may narrow it further, e.g. to a
/// model's g range) so that nothing is evaluated until the whole file is good.
pub fn parse(
    file: &str,
    contents: &str,
    check: impl Fn(&Point) -> Result<(), ParamError>,
) -> Result<Vec<Row>, CsvError> {
    let err = |line: usize, column: Option<&str>, message: String| CsvError {
        file: file.to_string(),
        line,
        column: column.map(str::to_string),
        message,
    };
    let mut lines = contents.lines().enumerate().map(|(i, l)| (i + 1, l)).filter(|(_, l)| !l.trim().is_empty());
    let (header_line, header) =
        lines.next().ok_or_else(|| err(1, None, "empty file: expected a header tau,gamma,rho,g".into()))?;
    let names: Vec<String> =
        header.split(',').map(|s| s.trim().trim_start_matches('\u{feff}').to_ascii_lowercase()).collect();
    let mut index = [0usize; 4];
    for (k, col) in COLUMNS.iter().enumerate() {
        index[k] = names.iter().position(|n| n == col).ok_or_else(|| {
            err(header_line, Some(col), format!("missing from the header '{}' (need tau,gamma,rho,g)", header.trim()))
        })?;
    }
    let mut rows = Vec::new();
    for (line, text) in lines {
        let fields: Vec<&str> = text.split(',').map(str::trim).collect();
        let mut vals = [0.0; 4];
        let mut raw: [String; 4] = Default::default();
        for k in 0..4 {
            let f = fields.get(index[k]).ok_or_else(|| {
                err(
                    line,
                    Some(COLUMNS[k]),
                    format!("missing value (the row has {} fields, the header {})", fields.len(), names.len()),
                )
            })?;
            vals[k] = parse_number(f).ok_or_else(|| err(line, Some(COLUMNS[k]), format!("'{f}' is not a number")))?;
            raw[k] = f.to_string();
        }
        let point = Point::new(vals[0], vals[1], vals[2], vals[3]);
        point.validate().and_then(|_| check(&point)).map_err(|e| err(line, Some(e.param.name()), e.to_string()))?;
        rows.push(Row { line, point, text: raw });
    }
    Ok(rows)
}

/// Writes rows with their values: the four input columns as written, plus
/// `airlight` printed so that it round-trips to the same f64 (`inf` if infinite).
pub fn render(rows: &[Row], values: &[f64]) -> String {
    let mut out = String::from("tau,gamma,rho,g,airlight\n");
    for (row, v) in rows.iter().zip(values) {
        out.push_str(&format!("{},{},{},{},{:?}\n", row.text[0], row.text[1], row.text[2], row.text[3], v));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ok(_: &Point) -> Result<(), ParamError> {
        Ok(())
    }

    #[test]
    fn parses_any_column_order_and_inf() {
        let rows = parse("p.csv", "g, rho ,tau,gamma,extra\n0.5,inf,1,0.25,x\n\n0,2,0,3\n", ok).unwrap();
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[0].point, Point::new(1.0, 0.25, f64::INFINITY, 0.5));
        assert_eq!(rows[1].line, 4);
        let out = render(&rows, &[1.5, f64::INFINITY]);
        assert_eq!(out, "tau,gamma,rho,g,airlight\n1,0.25,inf,0.5,1.5\n0,3,2,0,inf\n");
    }

    #[test]
    fn round_trips_values() {
        let v = [0.1 + 0.2, 1e-300, 6.02e23, 5e-324];
        let rows: Vec<Row> = (0..4)
            .map(|i| Row { line: i + 2, point: Point::new(0.0, 1.0, 1.0, 0.0), text: Default::default() })
            .collect();
        let out = render(&rows, &v);
        for (line, want) in out.lines().skip(1).zip(v) {
            assert_eq!(line.rsplit(',').next().unwrap().parse::<f64>().unwrap(), want);
        }
    }

    #[test]
    fn errors_name_file_line_and_column() {
        let e = |s: &str| parse("in.csv", s, ok).unwrap_err().to_string();
        assert_eq!(e(""), "in.csv:1: empty file: expected a header tau,gamma,rho,g");
        assert!(e("tau,gamma,rho\n1,1,1\n").starts_with("in.csv:1: column 'g': missing from the header"));
        assert_eq!(e("tau,gamma,rho,g\n1,1,1,0\n1,x,1,0\n"), "in.csv:3: column 'gamma': 'x' is not a number");
        assert!(e("tau,gamma,rho,g\n1,1,1\n").starts_with("in.csv:2: column 'g': missing value"));
        assert!(e("tau,gamma,rho,g\n-1,1,1,0\n").starts_with("in.csv:2: column 'tau': tau = -1 is out of range"));
        assert!(e("tau,gamma,rho,g\n1,4,1,0\n").starts_with("in.csv:2: column 'gamma'"));
        assert!(e("tau,gamma,rho,g\n1,1,0,0\n").starts_with("in.csv:2: column 'rho'"));
        assert!(e("tau,gamma,rho,g\n1,1,1,nan\n").starts_with("in.csv:2: column 'g'"));
        let isotropic = |p: &Point| {
            if p.g == 0.0 {
                Ok(())
            } else {
                Err(ParamError { param: crate::Param::G, value: p.g, allowed: Some((0.0, 0.0)) })
            }
        };
        let narrow = parse("in.csv", "tau,gamma,rho,g\n1,1,1,0.5\n", isotropic);
        assert!(narrow.unwrap_err().to_string().starts_with("in.csv:2: column 'g': g = 0.5"));
    }
}
