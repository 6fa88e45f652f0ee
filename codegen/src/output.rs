//! A set of generated files, written atomically or compared with what is on disk.

use std::fmt;
use std::path::{Path, PathBuf};

/// One generated file, its path relative to the `generated/` directory.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Output {
    /// Path under `generated/`, with `/` separators.
    pub path: String,
    /// Full contents (text for everything but images).
    pub contents: Vec<u8>,
}

impl Output {
    /// A text output.
    pub fn text(path: impl Into<String>, contents: String) -> Output {
        Output { path: path.into(), contents: contents.into_bytes() }
    }
}

/// How a file on disk differs from what the generator renders.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Difference {
    /// The file does not exist.
    Missing(PathBuf),
    /// The file exists with other contents; the first differing line (1-based).
    Stale(PathBuf, usize),
    /// A file under the root that the generator does not produce.
    Orphaned(PathBuf),
}

impl fmt::Display for Difference {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Difference::Missing(p) => write!(f, "{}: missing", p.display()),
            Difference::Stale(p, line) => {
                write!(f, "{}:{}: differs from what the generator renders", p.display(), line)
            }
            Difference::Orphaned(p) => write!(f, "{}: not produced by the generator (orphaned)", p.display()),
        }
    }
}

/// Writes every output under `root` that differs from what is there, all of them
/// or none ([`airlight_truth::io::write_all_or_none`]): a failure leaves every file
/// as it was and names the file that failed. Returns the files written.
pub fn write_all(root: &Path, outputs: &[Output]) -> Result<Vec<PathBuf>, airlight_truth::io::WriteError> {
    let changed: Vec<(PathBuf, &[u8])> = outputs
        .iter()
        .map(|o| (root.join(&o.path), &o.contents[..]))
        .filter(|(path, contents)| std::fs::read(path).ok().as_deref() != Some(*contents))
        .collect();
    airlight_truth::io::write_all_or_none(&changed)?;
    Ok(changed.into_iter().map(|(p, _)| p).collect())
}

/// Every file under `dir`, recursively, sorted.
fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    if let Ok(entries) = std::fs::read_dir(dir) {
        for e in entries.flatten() {
            let p = e.path();
            if p.is_dir() {
                out.extend(files_under(&p));
            } else {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

/// Compares every output with the file under `root`, and lists files under
/// `root` that no output produces; empty when all match.
pub fn check(root: &Path, outputs: &[Output]) -> Vec<Difference> {
    let mut diffs = Vec::new();
    for o in outputs {
        let path = root.join(&o.path);
        match std::fs::read(&path) {
            Err(_) => diffs.push(Difference::Missing(path)),
            Ok(disk) if disk != o.contents => {
                let (a, b) = (String::from_utf8_lossy(&disk), String::from_utf8_lossy(&o.contents));
                let line = a.lines().zip(b.lines()).take_while(|(x, y)| x == y).count() + 1;
                diffs.push(Difference::Stale(path, line));
            }
            Ok(_) => {}
        }
    }
    let expected: Vec<PathBuf> = outputs.iter().map(|o| root.join(&o.path)).collect();
    diffs.extend(files_under(root).into_iter().filter(|p| !expected.contains(p)).map(Difference::Orphaned));
    diffs
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn write_then_check() {
        let root = std::env::temp_dir().join(format!("airlight-out-{}", std::process::id()));
        let outs = vec![Output::text("a/b.md", "x\ny\n".into())];
        assert_eq!(check(&root, &outs), vec![Difference::Missing(root.join("a/b.md"))]);
        assert_eq!(write_all(&root, &outs).unwrap().len(), 1);
        assert!(check(&root, &outs).is_empty());
        assert!(write_all(&root, &outs).unwrap().is_empty(), "unchanged files are not rewritten");
        std::fs::write(root.join("a/b.md"), "x\nz\n").unwrap();
        assert_eq!(check(&root, &outs), vec![Difference::Stale(root.join("a/b.md"), 2)]);
        std::fs::write(root.join("a/extra.txt"), "").unwrap();
        assert_eq!(check(&root, &outs)[1], Difference::Orphaned(root.join("a/extra.txt")));
        std::fs::remove_dir_all(&root).unwrap();
    }
}
