//! Writing files so that a failure never leaves a half-written or truncated one.

use std::io::Write;
use std::path::{Path, PathBuf};

/// The file a write to `path` lands in: `path` itself, or what its symbolic
/// links point to (followed to the end, even if that file does not exist yet).
fn resolve(path: &Path) -> std::io::Result<PathBuf> {
    let mut p = path.to_path_buf();
    for _ in 0..40 {
        match std::fs::symlink_metadata(&p) {
            Ok(m) if m.file_type().is_symlink() => {
                let target = std::fs::read_link(&p)?;
                p = match p.parent() {
                    Some(dir) if target.is_relative() => dir.join(target),
                    _ => target,
                };
            }
            _ => return Ok(p),
        }
    }
    Err(std::io::Error::other("too many levels of symbolic links"))
}

/// A file of a set that could not be written, and why.
#[derive(Debug)]
pub struct WriteError {
    /// The file.
    pub path: PathBuf,
    /// What failed.
    pub error: std::io::Error,
}

impl std::fmt::Display for WriteError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: cannot write: {}", self.path.display(), self.error)
    }
}

impl std::error::Error for WriteError {}

/// Writes every `(path, contents)` or none: each is first written in full to a
/// temporary file beside its path (directories created as needed); only when all
/// of them are on disk are they renamed into place. On an error before that, every
/// temporary file (and every directory this call created) is removed and no path
/// has changed; the error names the file that failed.
pub fn write_all_or_none(files: &[(PathBuf, &[u8])]) -> Result<(), WriteError> {
    let mut temps: Vec<(PathBuf, PathBuf)> = Vec::with_capacity(files.len());
    let mut created: Vec<PathBuf> = Vec::new();
    let staged = files.iter().try_for_each(|(path, contents)| {
        let fail = |error| WriteError { path: path.clone(), error };
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            let mut missing: Vec<&Path> = dir.ancestors().take_while(|d| !d.exists()).collect();
            std::fs::create_dir_all(dir).map_err(fail)?;
            missing.reverse();
            created.extend(missing.into_iter().map(Path::to_path_buf));
        }
        let target = resolve(path).map_err(fail)?;
        let tmp = stage(&target, contents).map_err(fail)?;
        temps.push((tmp, target));
        Ok(())
    });
    if let Err(e) = staged {
        for (tmp, _) in &temps {
            let _ = std::fs::remove_file(tmp);
        }
        for dir in created.iter().rev() {
            let _ = std::fs::remove_dir(dir);
        }
        return Err(e);
    }
    for (tmp, target) in &temps {
        std::fs::rename(tmp, target).map_err(|error| WriteError { path: target.clone(), error })?;
    }
    Ok(())
}

/// Writes `contents` to a temporary file beside `path` (a regular file or none
/// yet; it keeps an existing file's permissions) and syncs it: the file to rename
/// over `path`.
fn stage(path: &Path, contents: &[u8]) -> std::io::Result<PathBuf> {
    let existing = match std::fs::metadata(path) {
        Ok(m) if !m.is_file() => {
            return Err(std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "not a regular file (a directory, FIFO or device): refusing to replace it",
            ))
        }
        Ok(m) => Some(m.permissions()),
        Err(_) => None,
    };
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = path.file_name().ok_or_else(|| std::io::Error::other("not a file path"))?;
    let tmp = dir.join(format!(".{}.{}.tmp", name.to_string_lossy(), std::process::id()));
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(contents)?;
        f.sync_all()?;
        if let Some(perm) = existing {
            std::fs::set_permissions(&tmp, perm)?;
        }
        Ok(())
    })();
    match result {
        Ok(()) => Ok(tmp),
        Err(e) => {
            let _ = std::fs::remove_file(&tmp);
            Err(e)
        }
    }
}

/// Writes `contents` to a temporary file beside `path`, syncs it, then renames it
/// over `path`. On error nothing at `path` has changed. A symbolic link is written
/// through (its target is replaced, the link stays); an existing file keeps its
/// permissions; anything but a regular file (a directory, a FIFO, a device) is
/// refused rather than replaced.
pub fn write_atomic(path: &Path, contents: &[u8]) -> std::io::Result<()> {
    let path = resolve(path)?;
    let tmp = stage(&path, contents)?;
    std::fs::rename(&tmp, &path).inspect_err(|_| {
        let _ = std::fs::remove_file(&tmp);
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn replaces_whole_file_and_leaves_no_temporary() {
        let dir = std::env::temp_dir().join(format!("airlight-io-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("out.csv");
        std::fs::write(&p, "old contents that are longer").unwrap();
        write_atomic(&p, b"new").unwrap();
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "new");
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
        // A directory that does not exist: an error, and nothing created.
        assert!(write_atomic(&dir.join("missing/out.csv"), b"x").is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn writes_through_links_keeps_the_mode_and_refuses_special_files() {
        use std::os::unix::fs::PermissionsExt;
        let dir = std::env::temp_dir().join(format!("airlight-io-links-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let target = dir.join("target.csv");
        std::fs::write(&target, "old").unwrap();
        std::fs::set_permissions(&target, std::fs::Permissions::from_mode(0o640)).unwrap();
        let link = dir.join("link.csv");
        std::os::unix::fs::symlink("target.csv", &link).unwrap();
        write_atomic(&link, b"new").unwrap();
        assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink(), "the link stays a link");
        assert_eq!(std::fs::read_to_string(&target).unwrap(), "new");
        assert_eq!(std::fs::metadata(&target).unwrap().permissions().mode() & 0o777, 0o640);
        // A dangling link: its target is created.
        std::os::unix::fs::symlink("later.csv", dir.join("dangling.csv")).unwrap();
        write_atomic(&dir.join("dangling.csv"), b"x").unwrap();
        assert_eq!(std::fs::read_to_string(dir.join("later.csv")).unwrap(), "x");
        // A FIFO and a directory are refused and left as they are.
        let fifo = dir.join("fifo");
        assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
        let e = write_atomic(&fifo, b"x").unwrap_err();
        assert!(e.to_string().contains("not a regular file"), "{e}");
        assert!(!std::fs::metadata(&fifo).unwrap().is_file());
        assert!(write_atomic(&dir, b"x").is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_set_is_written_whole_or_not_at_all() {
        let dir = std::env::temp_dir().join(format!("airlight-io-set-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("blocked")).unwrap();
        std::fs::write(dir.join("a.txt"), "old a").unwrap();
        // The last file's path is a directory: nothing is written, the directories
        // made for the second are gone again, and the error names the last.
        let files: Vec<(PathBuf, &[u8])> =
            vec![(dir.join("a.txt"), b"new a"), (dir.join("new/deep/c.txt"), b"c"), (dir.join("blocked"), b"x")];
        let e = write_all_or_none(&files).unwrap_err();
        assert_eq!(e.path, dir.join("blocked"), "{e}");
        assert_eq!(std::fs::read_to_string(dir.join("a.txt")).unwrap(), "old a");
        assert!(!dir.join("new").exists());
        let names: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert_eq!(names.len(), 2, "no temporary left: {names:?}");
        let files: Vec<(PathBuf, &[u8])> = vec![(dir.join("a.txt"), b"new a"), (dir.join("new/deep/c.txt"), b"c")];
        write_all_or_none(&files).unwrap();
        assert_eq!(std::fs::read_to_string(dir.join("a.txt")).unwrap(), "new a");
        assert_eq!(std::fs::read_to_string(dir.join("new/deep/c.txt")).unwrap(), "c");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
