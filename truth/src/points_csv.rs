//! The input files of `eval`: CSV with a header naming the columns (any order,
//! other columns ignored), one item per line. Errors name the file, the line and
//! the column.
//!
//! - Points of the canonical entry: `tau,gamma,rho,g`, `rho` may be `inf`.
//! - Rays of the physical entry ([`RAY_COLUMNS`]): viewer, direction, surface
//!   distance (negative or `inf`: none), light, intensity, σt, σs, g.
//! - Rays of the spot entry ([`SPOT_COLUMNS`]): the same with the cone's axis and
//!   cosines, and σt, σs per colour channel.
//! - Shadowed rays (`eval --entry shadowed`): either of the last two plus
//!   `spheres`, the occluders as `cx cy cz r` quadruples separated by `;`.

use crate::geometry::{Cone, PhysicalRay};
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
    let mut rows = Vec::new();
    for (line, vals, raw) in read_table(file, contents, &COLUMNS)? {
        let point = Point::new(vals[0], vals[1], vals[2], vals[3]);
        point
            .validate()
            .and_then(|_| check(&point))
            .map_err(|e| located(file, line, Some(e.param.name()), e.to_string()))?;
        rows.push(Row { line, point, text: raw });
    }
    Ok(rows)
}

fn located(file: &str, line: usize, column: Option<&str>, message: String) -> CsvError {
    CsvError { file: file.to_string(), line, column: column.map(str::to_string), message }
}

/// Why an f32 kernel cannot take `x` as column `col` (beyond f32's range, or
/// not zero but below its smallest normal number, so that it would become ∞, lose
/// its digits or be flushed to 0), or `None` where it can.
pub fn beyond_f32(col: &str, x: f64) -> Option<String> {
    // Subnormals too: they carry few digits, and GPUs may flush them to 0.
    let range = f64::from(f32::MIN_POSITIVE)..=f64::from(f32::MAX);
    (x.is_finite() && x != 0.0 && !range.contains(&x.abs()))
        .then(|| format!("{col} = {x:e} is outside what an f32 kernel can take (|x| in [1.2e-38, 3.4e38], or 0)"))
}

/// [`beyond_f32`] for the γ of each point (τ and ρ beyond f32 are exact: no
/// light through, no surface; below it, 0 and a surface at the viewer).
pub fn check_gamma_f32(file: &str, rows: &[Row]) -> Result<(), CsvError> {
    for r in rows {
        if let Some(m) = beyond_f32("gamma", r.point.gamma) {
            return Err(located(file, r.line, Some("gamma"), m));
        }
    }
    Ok(())
}

/// [`beyond_f32`] for the cone's axis of each spot row: the first such component
/// is the error.
pub fn check_axes_f32(file: &str, rows: &[SpotRow]) -> Result<(), CsvError> {
    for r in rows {
        if let Some(c) = &r.cone {
            for (col, x) in ["ax", "ay", "az"].into_iter().zip(c.axis) {
                if let Some(m) = beyond_f32(col, x) {
                    return Err(located(file, r.line, Some(col), m));
                }
            }
        }
    }
    Ok(())
}

/// The bytes of a CSV as text: UTF-8 (a BOM is kept for the header reader to
/// drop), or an error naming the line and byte of the first invalid sequence.
pub fn decode(file: &str, bytes: Vec<u8>) -> Result<String, CsvError> {
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        let b = e.as_bytes();
        let line = 1 + b[..at].iter().filter(|&&c| c == b'\n').count();
        located(file, line, None, format!("not UTF-8 text (byte {} of the file, 0x{:02x})", at + 1, b[at]))
    })
}

/// A row of [`read_table`]: its line, numbers and fields as written.
type TableRow<const N: usize> = (usize, [f64; N], [String; N]);

/// The rows of a CSV whose header names `columns` (any order, other columns
/// ignored, blank lines skipped): each row's 1-based line, its numbers in the
/// order of `columns`, and those fields as written. The shared reader of both
/// file kinds; errors name the file, the line and the column.
fn read_table<const N: usize>(file: &str, contents: &str, columns: &[&str; N]) -> Result<Vec<TableRow<N>>, CsvError> {
    let err = |line: usize, column: Option<&str>, message: String| located(file, line, column, message);
    let need = columns.join(",");
    // Lines end in LF, CRLF or a bare CR (classic Mac OS).
    let contents =
        if contents.contains('\r') { contents.replace("\r\n", "\n").replace('\r', "\n") } else { contents.to_string() };
    let mut lines = contents.lines().enumerate().map(|(i, l)| (i + 1, l)).filter(|(_, l)| !l.trim().is_empty());
    let (header_line, header) =
        lines.next().ok_or_else(|| err(1, None, format!("empty file: expected a header {need}")))?;
    let names: Vec<String> =
        header.split(',').map(|s| s.trim().trim_start_matches('\u{feff}').to_ascii_lowercase()).collect();
    for (i, n) in names.iter().enumerate() {
        if !n.is_empty() && names[..i].contains(n) {
            return Err(err(header_line, Some(n), format!("appears twice in the header '{}'", header.trim())));
        }
    }
    let mut index = [0usize; N];
    for (k, col) in columns.iter().enumerate() {
        index[k] = names.iter().position(|n| n == col).ok_or_else(|| {
            err(header_line, Some(col), format!("missing from the header '{}' (need {need})", header.trim()))
        })?;
    }
    let mut rows = Vec::new();
    for (line, text) in lines {
        let fields: Vec<&str> = text.split(',').map(str::trim).collect();
        if fields.len() > names.len() {
            let message = format!("the row has {} fields, the header {}", fields.len(), names.len());
            return Err(err(line, None, message));
        }
        let mut vals = [0.0; N];
        let mut raw: [String; N] = std::array::from_fn(|_| String::new());
        for k in 0..N {
            let f = fields.get(index[k]).ok_or_else(|| {
                err(
                    line,
                    Some(columns[k]),
                    format!("missing value (the row has {} fields, the header {})", fields.len(), names.len()),
                )
            })?;
            vals[k] = parse_number(f).ok_or_else(|| err(line, Some(columns[k]), format!("'{f}' is not a number")))?;
            raw[k] = f.to_string();
        }
        rows.push((line, vals, raw));
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

/// Columns of a rays file, in output order.
pub const RAY_COLUMNS: [&str; 14] =
    ["ox", "oy", "oz", "dx", "dy", "dz", "surface", "lx", "ly", "lz", "intensity", "sigma_t", "sigma_s", "g"];

/// Whether a CSV's header names the spot entry's cone (`cos_outer`): such a file
/// given to `--entry radiance` goes to the spot entry.
pub fn names_spot_columns(text: &str) -> bool {
    text.lines().find(|l| !l.trim().is_empty()).is_some_and(|h| h.split(',').any(|c| c.trim() == "cos_outer"))
}

/// A check of a parsed ray and its `g`: `Err((column, message))` refuses it.
pub type RayCheck<'a> = dyn Fn(&PhysicalRay, f64) -> Result<(), (&'static str, String)> + 'a;

/// One parsed row of a rays file.
#[derive(Debug, Clone, PartialEq)]
pub struct RayRow {
    /// 1-based line number in the file.
    pub line: usize,
    /// The ray, light and medium.
    pub ray: PhysicalRay,
    /// Henyey–Greenstein asymmetry.
    pub g: f64,
    /// The [`RAY_COLUMNS`] as written (trimmed).
    pub text: Vec<String>,
}

/// Parses a rays file. Every row is validated — finite positions and a non-zero
/// finite direction, finite σt, σs and intensity ≥ 0, `|g| < 1` — and then by
/// `check` (a model's g range, or what a generated kernel takes), which names
/// the column it refuses.
pub fn parse_rays(
    file: &str,
    contents: &str,
    check: impl Fn(&PhysicalRay, f64) -> Result<(), (&'static str, String)>,
) -> Result<Vec<RayRow>, CsvError> {
    let mut rows = Vec::new();
    for (line, v, raw) in read_table(file, contents, &RAY_COLUMNS)? {
        check_columns(file, line, &RAY_COLUMNS, &v, &raw)?;
        let ray = PhysicalRay {
            origin: [v[0], v[1], v[2]],
            direction: [v[3], v[4], v[5]],
            surface_distance: (v[6] >= 0.0 && v[6].is_finite()).then_some(v[6]),
            light: [v[7], v[8], v[9]],
            intensity: v[10],
            sigma_t: v[11],
            sigma_s: v[12],
        };
        if ray.direction.iter().all(|&x| x == 0.0) {
            return Err(located(file, line, Some("dx"), "the direction (dx, dy, dz) is zero".into()));
        }
        check(&ray, v[13]).map_err(|(col, m)| located(file, line, Some(col), m))?;
        rows.push(RayRow { line, ray, g: v[13], text: raw.to_vec() });
    }
    Ok(rows)
}

/// Writes ray rows with their values: the input columns as written plus
/// `radiance`, printed so that it round-trips (`inf` if infinite).
pub fn render_rays(rows: &[RayRow], values: &[f64]) -> String {
    let mut out = RAY_COLUMNS.join(",");
    out.push_str(",radiance\n");
    for (row, v) in rows.iter().zip(values) {
        out.push_str(&format!("{},{v:?}\n", row.text.join(",")));
    }
    out
}

/// Checks each column of a rays or spot rays row: finite positions and
/// directions, a surface that is not NaN, intensity and σ finite ≥ 0, `|g| < 1`,
/// a cone's `0 ≤ cos_outer ≤ 1` (or −1) and `cos_inner ≤ 1`; the first column out
/// of range is the error.
fn check_columns(file: &str, line: usize, columns: &[&'static str], v: &[f64], raw: &[String]) -> Result<(), CsvError> {
    for (k, (&col, &x)) in columns.iter().zip(v).enumerate() {
        let (ok, need) = match col {
            "surface" => (!x.is_nan(), "a distance ≥ 0, or negative or inf for none"),
            "intensity" | "sigma_t" | "sigma_s" | "sigma_t_r" | "sigma_t_g" | "sigma_t_b" | "sigma_s_r"
            | "sigma_s_g" | "sigma_s_b" => (x.is_finite() && x >= 0.0, "a finite number ≥ 0"),
            "g" => (x.abs() < 1.0, "in (−1, 1)"),
            "cos_outer" => {
                (x == -1.0 || (0.0..=1.0).contains(&x), "in [0, 1] (half-angles up to 90°), or -1 for a point light")
            }
            "cos_inner" => (x.is_finite() && x <= 1.0, "a finite number ≤ 1"),
            _ => (x.is_finite(), "a finite number"),
        };
        if !ok {
            let message = format!("{col} = {} is out of range: it must be {need}", raw[k]);
            return Err(located(file, line, Some(col), message));
        }
    }
    Ok(())
}

/// Columns a spot rays file must have, in output order.
pub const SPOT_COLUMNS: [&str; 23] = [
    "ox",
    "oy",
    "oz",
    "dx",
    "dy",
    "dz",
    "surface",
    "lx",
    "ly",
    "lz",
    "ax",
    "ay",
    "az",
    "cos_outer",
    "cos_inner",
    "intensity",
    "sigma_t_r",
    "sigma_t_g",
    "sigma_t_b",
    "sigma_s_r",
    "sigma_s_g",
    "sigma_s_b",
    "g",
];

/// One parsed row of a spot rays file.
#[derive(Debug, Clone, PartialEq)]
pub struct SpotRow {
    /// 1-based line number in the file.
    pub line: usize,
    /// The ray per colour channel (its σt and σs).
    pub rays: [PhysicalRay; 3],
    /// The cone; `None` for a point light (`cos_outer = −1`).
    pub cone: Option<Cone>,
    /// Henyey–Greenstein asymmetry.
    pub g: f64,
    /// The [`SPOT_COLUMNS`] as written (trimmed).
    pub text: Vec<String>,
}

impl SpotRow {
    /// The f64 radiance of each channel, `A` by `a`.
    pub fn radiance(&self, a: &dyn Fn(Point) -> f64) -> Result<[f64; 3], crate::geometry::GeometryError> {
        let mut out = [0.0; 3];
        for (o, ray) in out.iter_mut().zip(&self.rays) {
            *o = ray.light_radiance(self.cone.as_ref(), self.g, a)?;
        }
        Ok(out)
    }
}

/// Parses a spot rays file: every column as [`parse_rays`] checks it, a non-zero
/// axis, `0 ≤ cos_outer ≤ 1` (half-angles up to 90°) or `cos_outer = −1` for a point
/// light, `cos_inner ≤ 1`; then each channel's ray by `check`.
pub fn parse_spots(
    file: &str,
    contents: &str,
    check: impl Fn(&PhysicalRay, f64) -> Result<(), (&'static str, String)>,
) -> Result<Vec<SpotRow>, CsvError> {
    let mut rows = Vec::new();
    for (line, v, raw) in read_table(file, contents, &SPOT_COLUMNS)? {
        check_columns(file, line, &SPOT_COLUMNS, &v, &raw)?;
        let ray = |c: usize| PhysicalRay {
            origin: [v[0], v[1], v[2]],
            direction: [v[3], v[4], v[5]],
            surface_distance: (v[6] >= 0.0 && v[6].is_finite()).then_some(v[6]),
            light: [v[7], v[8], v[9]],
            intensity: v[15],
            sigma_t: v[16 + c],
            sigma_s: v[19 + c],
        };
        let rays = [ray(0), ray(1), ray(2)];
        if rays[0].direction.iter().all(|&x| x == 0.0) {
            return Err(located(file, line, Some("dx"), "the direction (dx, dy, dz) is zero".into()));
        }
        let cone = (v[13] > -1.0).then_some(Cone { axis: [v[10], v[11], v[12]], cos_outer: v[13], cos_inner: v[14] });
        if cone.is_some() && v[10..13].iter().all(|&x| x == 0.0) {
            return Err(located(file, line, Some("ax"), "the cone's axis (ax, ay, az) is zero".into()));
        }
        for r in &rays {
            check(r, v[22]).map_err(|(col, m)| {
                let col = match col {
                    "sigma_t" => "sigma_t_r",
                    "sigma_s" => "sigma_s_r",
                    c => c,
                };
                located(file, line, Some(col), m)
            })?;
        }
        rows.push(SpotRow { line, rays, cone, g: v[22], text: raw.to_vec() });
    }
    Ok(rows)
}

/// The `spheres` column of a shadowed rays file: for each data line (1-based),
/// its occluders and the field as written. Errors name the file, the line and
/// the column.
pub fn parse_spheres_column(
    file: &str,
    contents: &str,
) -> Result<Vec<(usize, Vec<crate::shafts::Occluder>, String)>, CsvError> {
    let contents =
        if contents.contains('\r') { contents.replace("\r\n", "\n").replace('\r', "\n") } else { contents.to_string() };
    let mut lines = contents.lines().enumerate().map(|(i, l)| (i + 1, l)).filter(|(_, l)| !l.trim().is_empty());
    let Some((header_line, header)) = lines.next() else {
        return Err(located(file, 1, None, "empty file: expected a header".into()));
    };
    let col = header
        .split(',')
        .position(|c| c.trim().trim_start_matches('\u{feff}').eq_ignore_ascii_case("spheres"))
        .ok_or_else(|| {
        located(
            file,
            header_line,
            Some("spheres"),
            format!("missing from the header '{}' (the occluders: cx cy cz r; …, empty for none)", header.trim()),
        )
    })?;
    let columns = header.split(',').count();
    let mut out = Vec::new();
    for (line, text) in lines {
        let fields = text.split(',').count();
        if fields < columns {
            // A short row is refused, as the other columns refuse it: it is not a ray
            // without occluders (write the field empty for that).
            let message = format!("missing value (the row has {fields} fields, the header {columns})");
            return Err(located(file, line, Some("spheres"), message));
        }
        if fields > columns && col + 1 == columns {
            let message = format!(
                "the row has {fields} fields, the header {columns}: commas separate CSV fields — write a sphere's \
                 numbers separated by spaces (cx cy cz r) and spheres by ';'"
            );
            return Err(located(file, line, Some("spheres"), message));
        }
        let field = text.split(',').nth(col).map(str::trim).unwrap_or("");
        let occ = crate::shafts::parse_spheres(field).map_err(|m| located(file, line, Some("spheres"), m))?;
        out.push((line, occ, field.to_string()));
    }
    Ok(out)
}

/// Writes spot rows with their values: the input columns as written plus `r`,
/// `g_out`, `b` (printed so that they round-trip).
pub fn render_spots(rows: &[SpotRow], values: &[[f64; 3]]) -> String {
    let mut out = SPOT_COLUMNS.join(",");
    out.push_str(",r,g_out,b\n");
    for (row, v) in rows.iter().zip(values) {
        out.push_str(&format!("{},{:?},{:?},{:?}\n", row.text.join(","), v[0], v[1], v[2]));
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
    fn spot_rows_parse_and_bad_cones_are_located() {
        let head = SPOT_COLUMNS.join(",");
        let row = "0,0,0,1,0,0,-1,5,1,0,0,-1,0,0.866,0.95,1,0.1,0.05,0.02,0.08,0.04,0.016,0.6";
        let point = "0,0,0,1,0,0,20,5,1,0,0,0,0,-1,-1,1,0.1,0.05,0.02,0.08,0.04,0.016,0.6";
        let rows = parse_spots("s.csv", &format!("{head}\n{row}\n{point}\n"), |_, _| Ok(())).unwrap();
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[0].cone, Some(Cone { axis: [0.0, -1.0, 0.0], cos_outer: 0.866, cos_inner: 0.95 }));
        assert_eq!([rows[0].rays[1].sigma_t, rows[0].rays[2].sigma_s], [0.05, 0.016]);
        assert_eq!((rows[1].cone, rows[1].rays[0].surface_distance), (None, Some(20.0)));
        let v = rows[0].radiance(&|p| crate::reference::airlight(p).unwrap()).unwrap();
        assert!(v[0] > v[1] && v[1] > v[2] && v[2] > 0.0, "{v:?}");
        let out = render_spots(&rows, &[v, [0.0; 3]]);
        assert!(out.starts_with(&format!("{head},r,g_out,b\n{row},")));
        for (bad, col) in [(row.replace(",0.866,", ",1.5,"), "cos_outer"), (row.replace(",0,-1,0,", ",0,0,0,"), "ax")] {
            let e = parse_spots("s.csv", &format!("{head}\n{bad}\n"), |_, _| Ok(())).unwrap_err().to_string();
            assert!(e.starts_with(&format!("s.csv:2: column '{col}'")), "{e}");
        }
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

    #[test]
    fn rays_parse_and_refuse_with_their_column() {
        let head = RAY_COLUMNS.join(",");
        let ok = |_: &PhysicalRay, _: f64| Ok(());
        let rows = parse_rays(
            "r.csv",
            &format!("{head}\n0,0,0,1,0,0,-1,2,1,0,10,0.1,0.05,0.5\n0,0,0,0,0,3,inf,0,0,1,1,0,0,0\n"),
            ok,
        )
        .unwrap();
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[0].ray.surface_distance, None);
        assert_eq!(rows[1].ray.surface_distance, None);
        assert_eq!(rows[0].g, 0.5);
        let out = render_rays(&rows, &[0.25, f64::INFINITY]);
        assert!(out.starts_with(&format!("{head},radiance\n0,0,0,1,0,0,-1,2,1,0,10,0.1,0.05,0.5,0.25\n")), "{out}");
        let e = |body: &str| parse_rays("r.csv", &format!("{head}\n{body}\n"), ok).unwrap_err().to_string();
        assert_eq!(e("0,0,0,0,0,0,1,1,1,1,1,1,1,0"), "r.csv:2: column 'dx': the direction (dx, dy, dz) is zero");
        assert!(
            e("0,0,0,1,0,0,1,1,1,1,1,-1,1,0").starts_with("r.csv:2: column 'sigma_t': sigma_t = -1 is out of range")
        );
        assert!(e("0,0,0,1,0,0,nan,1,1,1,1,1,1,0").starts_with("r.csv:2: column 'surface'"));
        assert!(e("0,0,0,1,0,0,1,inf,1,1,1,1,1,0").starts_with("r.csv:2: column 'lx'"));
        assert!(e("0,0,0,1,0,0,1,1,1,1,1,1,1").starts_with("r.csv:2: column 'g': missing value"));
    }

    #[test]
    fn a_header_naming_the_cone_is_the_spot_entry() {
        assert!(names_spot_columns("\n ox,oy,oz,dx,dy,dz,surface,lx,ly,lz,ax,ay,az, cos_outer ,cos_inner\n1,2"));
        assert!(!names_spot_columns("ox,oy,oz,dx,dy,dz,surface,lx,ly,lz,intensity,sigma_t,sigma_s,g\n"));
        assert!(!names_spot_columns("tau,gamma,rho,g\ncos_outer\n"));
        assert!(!names_spot_columns(""));
    }
}
