//! Atomic file writes: the content goes to a hidden partial file in the
//! target's folder (`.NAME.PID.N.partial`), renamed over the target once
//! whole. A reader sees the old file or the new one, never a half-written
//! file under the target's name; on any error the partial file is removed.
//!
//! Nothing is synced to disk (an fsync costs milliseconds a file); a caller
//! that needs it syncs in its writer (`w.get_ref().sync_all()`).

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Writes `path` with `f` through a partial file renamed into place.
pub fn write(path: &Path, f: impl FnOnce(&mut BufWriter<File>) -> io::Result<()>) -> io::Result<()> {
    stage(path, f)?.commit()
}

/// Writes `bytes` to `path` through a partial file renamed into place.
pub fn write_bytes(path: &Path, bytes: &[u8]) -> io::Result<()> {
    write(path, |w| w.write_all(bytes))
}

/// A file written under its partial name, not yet in place: [`commit`]
/// renames it; dropped uncommitted, it is removed. Lets several files be
/// written before any of them is put in place.
///
/// [`commit`]: Staged::commit
#[must_use = "a staged file is removed unless committed"]
#[derive(Debug)]
pub struct Staged {
    partial: PathBuf,
    path: PathBuf,
}

/// Writes `path`'s content with `f` to a partial file beside it, flushed
/// and closed, and returns it staged; removes it on error.
pub fn stage(path: &Path, f: impl FnOnce(&mut BufWriter<File>) -> io::Result<()>) -> io::Result<Staged> {
    let staged = Staged {
        partial: partial_path(path)?,
        path: path.to_path_buf(),
    };
    let mut w = BufWriter::new(File::create(&staged.partial)?);
    f(&mut w)?;
    w.into_inner().map_err(io::IntoInnerError::into_error)?;
    Ok(staged)
}

impl Staged {
    /// Renames the partial file over the target.
    pub fn commit(self) -> io::Result<()> {
        // On success nothing is left to remove; on failure `drop` removes it.
        std::fs::rename(&self.partial, &self.path)?;
        std::mem::forget(self);
        Ok(())
    }
}

impl Drop for Staged {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.partial);
    }
}

/// `.NAME.PID.N.partial` beside `path`, N counting this process's writes
/// (two threads writing one target never share a partial file).
fn partial_path(path: &Path) -> io::Result<PathBuf> {
    static COUNT: AtomicU64 = AtomicU64::new(0);
    let name = path
        .file_name()
        .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "not a file name"))?;
    let n = COUNT.fetch_add(1, Ordering::Relaxed);
    let mut partial = std::ffi::OsString::from(".");
    partial.push(name);
    partial.push(format!(".{}.{n}.partial", std::process::id()));
    Ok(path.with_file_name(partial))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn writes_replace_whole_files_and_leave_nothing_else() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.csv");
        write_bytes(&path, b"old").unwrap();
        write(&path, |w| w.write_all(b"new, longer")).unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"new, longer");
        assert_eq!(names(dir.path()), ["a.csv"]);
    }

    #[test]
    fn a_failed_write_keeps_the_old_file_and_no_partial_one() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.csv");
        write_bytes(&path, b"old").unwrap();
        let e = write(&path, |w| {
            w.write_all(b"half")?;
            Err(io::Error::other("refused"))
        })
        .unwrap_err();
        assert_eq!(e.to_string(), "refused");
        assert_eq!(std::fs::read(&path).unwrap(), b"old");
        assert_eq!(names(dir.path()), ["a.csv"]);
    }

    #[test]
    fn staged_files_appear_only_when_committed() {
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = (dir.path().join("a"), dir.path().join("b"));
        let sa = stage(&a, |w| w.write_all(b"1")).unwrap();
        let sb = stage(&b, |w| w.write_all(b"2")).unwrap();
        let partial = names(dir.path());
        assert_eq!(partial.len(), 2);
        assert!(partial
            .iter()
            .all(|n| n.starts_with('.') && n.ends_with(".partial")));
        sa.commit().unwrap();
        drop(sb);
        assert_eq!(names(dir.path()), ["a"]);
        assert!(write_bytes(Path::new("/"), b"").is_err());
    }
}
