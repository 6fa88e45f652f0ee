//! What every TOML input of the project (coefficient files, scene specs) shares:
//! the one-line error naming file, line and field, and finding that line.

use crate::hexf;
use std::fmt;
use std::fmt::Write as _;
use toml::{Table, Value};

/// A free-form provenance table: `(table name, ordered key/values)`.
pub type Provenance = (String, Vec<(String, Value)>);

/// A TOML file that cannot be used: `file:line: field 'x': message`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FieldError {
    /// The file.
    pub file: String,
    /// 1-based line (the field's line where it can be found, else its table's).
    pub line: usize,
    /// Dotted path of the field.
    pub field: String,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for FieldError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}: field '{}': {}", self.file, self.line, self.field, self.message)
    }
}

impl std::error::Error for FieldError {}

/// Parses `text` as a TOML table; a syntax error names its line.
pub fn parse_table(file: &str, text: &str) -> Result<toml::Table, FieldError> {
    from_str(file, text, "(syntax)")
}

/// The text of `path` and its name for messages; a file that cannot be read is a
/// one-line error naming it, with `hint` (what to run) appended.
pub fn read(path: &std::path::Path, hint: &str) -> Result<(String, String), FieldError> {
    let name = path.display().to_string();
    match std::fs::read_to_string(path) {
        Ok(text) => Ok((name, text)),
        Err(e) => {
            Err(FieldError { file: name, line: 1, field: "(file)".into(), message: format!("cannot read: {e}{hint}") })
        }
    }
}

/// Deserialises `text` (serde); an error names the file, the line of its span and `field`.
pub fn from_str<T: serde::de::DeserializeOwned>(file: &str, text: &str, field: &str) -> Result<T, FieldError> {
    toml::from_str(text).map_err(|e: toml::de::Error| FieldError {
        file: file.into(),
        line: e.span().map_or(1, |s| text[..s.start.min(text.len())].lines().count().max(1)),
        field: field.into(),
        message: e.message().replace('\n', " "),
    })
}

/// The line of `key = …` inside `[section]` or `[[section]]` (the last component
/// of a dotted `key`), else the section header's line, else 1. With `section`
/// empty: a top-level `key = …`, or the header of the table `key`.
pub fn locate(text: &str, section: &str, key: &str) -> usize {
    if section.is_empty() {
        return locate_top(text, key);
    }
    let header = format!("[{section}]");
    let mut in_section = false;
    let mut section_line = 1;
    let leaf = key.rsplit('.').next().unwrap_or(key);
    for (i, line) in text.lines().enumerate() {
        let l = line.trim();
        if l.starts_with('[') {
            in_section = l == header || l == format!("[{header}]");
            if in_section {
                section_line = i + 1;
            }
            continue;
        }
        if in_section && l.split('=').next().is_some_and(|k| k.trim() == leaf) {
            return i + 1;
        }
    }
    section_line
}

/// [`locate`] in the `n`-th (from 0) `[[section]]` table of an array of tables:
/// the line of `key = …` there, else that table's header, else 1.
pub fn locate_nth(text: &str, section: &str, n: usize, key: &str) -> usize {
    let header = format!("[[{section}]]");
    let leaf = key.rsplit('.').next().unwrap_or(key);
    let mut seen = 0usize;
    let mut inside = None;
    for (i, line) in text.lines().enumerate() {
        let l = line.trim();
        if l.starts_with('[') {
            if inside.is_some() {
                break;
            }
            if l == header {
                if seen == n {
                    inside = Some(i + 1);
                }
                seen += 1;
            }
            continue;
        }
        if inside.is_some() && l.split('=').next().is_some_and(|k| k.trim() == leaf) {
            return i + 1;
        }
    }
    inside.unwrap_or(1)
}

/// The error for `section.key` of `file`, located in `text`.
pub fn field_error(file: &str, text: &str, section: &str, key: &str, message: impl Into<String>) -> FieldError {
    FieldError {
        file: file.into(),
        line: locate(text, section, key),
        field: format!("{section}.{key}"),
        message: message.into(),
    }
}

/// Rejects every key of `table` (the table `section` of `file`; `""` for the
/// top level) that is not in `allowed`: a misspelt key would otherwise be
/// silently dropped by the next rewrite of the file.
pub fn deny_unknown(
    file: &str,
    text: &str,
    table: &toml::Table,
    section: &str,
    allowed: &[&str],
) -> Result<(), FieldError> {
    match table.keys().find(|k| !allowed.contains(&k.as_str())) {
        None => Ok(()),
        Some(k) => {
            let what = if table.get(k).is_some_and(toml::Value::is_table) { "table" } else { "key" };
            let field = if section.is_empty() { k.clone() } else { format!("{section}.{k}") };
            let line = locate(text, section, k);
            Err(FieldError {
                file: file.into(),
                line,
                field,
                message: format!("unknown {what} (known: {})", allowed.join(", ")),
            })
        }
    }
}

/// The line of a top-level `key = …` or `[key]` / `[key.…]` header.
fn locate_top(text: &str, key: &str) -> usize {
    let mut in_top = true;
    for (i, line) in text.lines().enumerate() {
        let l = line.trim();
        if let Some(h) = l.strip_prefix('[') {
            let name = h.trim_start_matches('[').trim_end_matches(']');
            if name == key || name.starts_with(&format!("{key}.")) {
                return i + 1;
            }
            in_top = false;
        } else if in_top && l.split('=').next().is_some_and(|k| k.trim() == key) {
            return i + 1;
        }
    }
    1
}

/// A number for a one-line message: short (4 significant digits), never 300 digits.
pub fn short(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || (1e-3..1e5).contains(&x.abs()) {
        let s = format!("{x:.4}");
        let s = if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_string() } else { s };
        if x.is_finite() {
            s
        } else {
            format!("{x}")
        }
    } else {
        format!("{x:.3e}")
    }
}

/// Reads typed fields of a TOML file, each error naming file, line and field.
pub struct Reader<'a> {
    /// The file, as named in messages.
    pub file: &'a str,
    /// Its text (to locate fields).
    pub text: &'a str,
}

impl Reader<'_> {
    /// Rejects keys of `t` (table `section`) not in `allowed`.
    pub fn deny(&self, t: &Table, section: &str, allowed: &[&str]) -> Result<(), FieldError> {
        deny_unknown(self.file, self.text, t, section, allowed)
    }
    /// The error for `section.key`.
    pub fn err(&self, section: &str, key: &str, msg: &str) -> FieldError {
        let sec = section.trim_start_matches('[').trim_end_matches(']');
        field_error(self.file, self.text, sec, key, msg)
    }
    /// The value of `key`, or "missing".
    pub fn get<'t>(&self, t: &'t Table, sec: &str, key: &str) -> Result<&'t Value, FieldError> {
        t.get(key).ok_or_else(|| self.err(sec, key, "missing"))
    }
    /// The sub-table `key` of `t`.
    pub fn table<'t>(&self, t: &'t Table, key: &str) -> Result<&'t Table, FieldError> {
        t.get(key).and_then(Value::as_table).ok_or_else(|| FieldError {
            file: self.file.into(),
            line: 1,
            field: key.into(),
            message: "missing table".into(),
        })
    }
    /// A string.
    pub fn string(&self, t: &Table, sec: &str, key: &str) -> Result<String, FieldError> {
        self.get(t, sec, key)?.as_str().map(str::to_string).ok_or_else(|| self.err(sec, key, "must be a string"))
    }
    /// A string that must equal `want`.
    pub fn expect_str(&self, t: &Table, sec: &str, key: &str, want: &str) -> Result<(), FieldError> {
        let got = self.string(t, sec, key)?;
        if got == want {
            Ok(())
        } else {
            Err(self.err(sec, key, &format!("unknown family '{got}' (expected '{want}')")))
        }
    }
    /// `true` or `false`.
    pub fn boolean(&self, t: &Table, sec: &str, key: &str) -> Result<bool, FieldError> {
        self.get(t, sec, key)?.as_bool().ok_or_else(|| self.err(sec, key, "must be true or false"))
    }
    /// A non-negative integer.
    pub fn uint(&self, t: &Table, sec: &str, key: &str) -> Result<usize, FieldError> {
        self.get(t, sec, key)?
            .as_integer()
            .and_then(|i| usize::try_from(i).ok())
            .ok_or_else(|| self.err(sec, key, "must be a non-negative integer"))
    }
    /// A number (not NaN).
    pub fn float(&self, t: &Table, sec: &str, key: &str) -> Result<f64, FieldError> {
        let v = self.get(t, sec, key)?;
        v.as_float()
            .or_else(|| v.as_integer().map(|i| i as f64))
            .filter(|x| !x.is_nan())
            .ok_or_else(|| self.err(sec, key, "must be a number"))
    }
    /// An array.
    pub fn array<'t>(&self, t: &'t Table, sec: &str, key: &str) -> Result<&'t Vec<Value>, FieldError> {
        self.get(t, sec, key)?.as_array().ok_or_else(|| self.err(sec, key, "must be an array"))
    }
    /// An array of numbers, of length `len` if given.
    pub fn floats(&self, t: &Table, sec: &str, key: &str, len: Option<usize>) -> Result<Vec<f64>, FieldError> {
        let a = self.array(t, sec, key)?;
        if len.is_some_and(|n| n != a.len()) {
            return Err(self.err(sec, key, &format!("needs {} numbers", len.unwrap_or(0))));
        }
        a.iter()
            .map(|v| {
                v.as_float()
                    .or_else(|| v.as_integer().map(|i| i as f64))
                    .ok_or_else(|| self.err(sec, key, "must be numbers"))
            })
            .collect()
    }
    /// An exact hexadecimal float, finite and within f32 (the kernels use it in f32).
    pub fn hex_value(&self, v: &Value, sec: &str, key: &str) -> Result<f64, FieldError> {
        let s = v.as_str().ok_or_else(|| self.err(sec, key, "coefficients are strings like \"0x1.8p+0\""))?;
        let x = hexf::parse(s).map_err(|e| self.err(sec, key, &e.to_string()))?;
        if !x.is_finite() {
            return Err(self.err(sec, key, "must be finite"));
        }
        // The kernels evaluate every coefficient in f32.
        if (x as f32).is_infinite() {
            return Err(self.err(
                sec,
                key,
                &format!("{s} = {} is outside f32's range (|x| <= 3.4e38), where the kernels evaluate it", short(x)),
            ));
        }
        Ok(x)
    }
    /// The hexadecimal float `key`.
    pub fn hex(&self, t: &Table, sec: &str, key: &str) -> Result<f64, FieldError> {
        self.hex_value(self.get(t, sec, key)?, sec, key)
    }
    /// An array of hexadecimal floats, of length `len` if given.
    pub fn hexes(&self, t: &Table, sec: &str, key: &str, len: Option<usize>) -> Result<Vec<f64>, FieldError> {
        let a = self.array(t, sec, key)?;
        if let Some(n) = len {
            if a.len() != n {
                return Err(self.err(sec, key, &format!("needs {n} values, has {}", a.len())));
            }
        }
        a.iter().map(|v| self.hex_value(v, sec, key)).collect()
    }
}

// ---- writing: the counterparts of the readers above ----

/// Shortest text that reads back as the same f64 (TOML spells infinity `inf`).
pub fn dec(x: f64) -> String {
    if x.is_infinite() {
        if x > 0.0 {
            "inf".into()
        } else {
            "-inf".into()
        }
    } else {
        format!("{x:?}")
    }
}

/// `key = [ "hex", # decimal ... ]`.
pub fn hex_list(out: &mut String, key: &str, xs: &[f64]) {
    let _ = writeln!(out, "{key} = [");
    for x in xs {
        let _ = writeln!(out, "  \"{}\", # {}", hexf::format(*x), dec(*x));
    }
    out.push_str("]\n");
}

/// Rows of quadratics in g as hexadecimal floats.
pub fn quad_rows(out: &mut String, key: &str, rows: &[[f64; 3]]) {
    let _ = writeln!(out, "{key} = [");
    for r in rows {
        let _ = writeln!(
            out,
            "  [\"{}\", \"{}\", \"{}\"], # {} g² + {} g + {}",
            hexf::format(r[0]),
            hexf::format(r[1]),
            hexf::format(r[2]),
            dec(r[0]),
            dec(r[1]),
            dec(r[2])
        );
    }
    out.push_str("]\n");
}

/// Short constructors of provenance values (the coefficient files' `[*.fit]` tables).
pub mod value {
    use toml::Value;

    /// A string.
    pub fn s(v: &str) -> Value {
        Value::String(v.to_string())
    }
    /// An integer (saturating).
    pub fn i(v: impl TryInto<i64>) -> Value {
        Value::Integer(v.try_into().unwrap_or(i64::MAX))
    }
    /// A float.
    pub fn f(v: f64) -> Value {
        Value::Float(v)
    }
    /// Owned keys.
    pub fn kv(pairs: Vec<(&str, Value)>) -> Vec<(String, Value)> {
        pairs.into_iter().map(|(k, v)| (k.to_string(), v)).collect()
    }
    /// A seed as `0x…` (16 hex digits).
    pub fn hex_seed(seed: u64) -> Value {
        s(&format!("{seed:#018x}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn locates_keys_in_tables_and_arrays_of_tables() {
        let text = "[a]\nx = 1\n\n[[b.c]]\ny = 2\n[d]\n";
        assert_eq!(locate(text, "a", "x"), 2);
        assert_eq!(locate(text, "b.c", "y"), 5);
        assert_eq!(locate(text, "d", "missing"), 6);
        assert_eq!(locate(text, "nowhere", "x"), 1);
        let e = parse_table("f.toml", "[a]\nx = \n").unwrap_err();
        assert_eq!((e.line, e.field.as_str()), (2, "(syntax)"));
        let doc = parse_table("f.toml", text).unwrap();
        let e = deny_unknown("f.toml", text, &doc, "", &["a", "b"]).unwrap_err();
        assert_eq!((e.line, e.field.as_str()), (6, "d"));
        let a = doc["a"].as_table().unwrap();
        assert!(deny_unknown("f.toml", text, a, "a", &["x"]).is_ok());
        let e = deny_unknown("f.toml", text, a, "a", &["y"]).unwrap_err();
        assert_eq!((e.line, e.field.as_str()), (2, "a.x"));
        assert_eq!(short(-1e300), "-1.000e300");
        assert_eq!(short(0.5), "0.5");
    }
}
