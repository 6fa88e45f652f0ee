//! What every TOML input of the project (coefficient files, scene specs) shares:
//! the one-line error naming file, line and field, and finding that line.

use std::fmt;

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
    text.parse().map_err(|e: toml::de::Error| FieldError {
        file: file.into(),
        line: e.span().map_or(1, |s| text[..s.start.min(text.len())].lines().count().max(1)),
        field: "(syntax)".into(),
        message: e.message().replace('\n', " "),
    })
}

/// The line of `key = …` inside `[section]` or `[[section]]` (the last component
/// of a dotted `key`), else the section header's line, else 1.
pub fn locate(text: &str, section: &str, key: &str) -> usize {
    let header = format!("[{section}]");
    let mut in_section = section.is_empty();
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

/// The error for `section.key` of `file`, located in `text`.
pub fn field_error(file: &str, text: &str, section: &str, key: &str, message: impl Into<String>) -> FieldError {
    FieldError {
        file: file.into(),
        line: locate(text, section, key),
        field: format!("{section}.{key}"),
        message: message.into(),
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
    }
}
