//! The leading columns of reduced factors on disk: a factor that keeps
//! only its joint block ([`crate::linear::Model::joint_block`]) writes the
//! rest of its values to one unnamed file of the model, and a full solve
//! reads them back instead of factorizing the harmonic again. The file has
//! no name (removed when made), so a killed run leaves nothing behind.
//! A factor is written only while writing is faster than factorizing it
//! was (the disk's rate measured on each write: a disk slower than the
//! factorization, or one whose cache is full, stops the writes). Where the
//! disk is short or the folder is in memory (tmpfs), the values are
//! dropped and a full solve factorizes again, as without the file.

use std::fs::File;
use std::io;
use std::os::unix::fs::FileExt;
use std::os::unix::io::AsRawFd;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::Instant;

/// Environment variable: the folder for the leading columns of reduced
/// factors; unset: `/var/tmp` if it exists, else the system's temporary
/// folder; `off`: none (a full solve of a reduced harmonic factorizes it
/// again). A folder in memory (tmpfs) counts as `off`.
pub const FACTOR_DISK_ENV: &str = "AXIJOINT_FACTOR_DISK";

/// Free space a write leaves on the disk at least: 1 GiB.
const RESERVE: u64 = 1 << 30;

/// The file of a model's written values; writes append.
pub(crate) struct SpillFile {
    file: File,
    dir: PathBuf,
    end: Mutex<u64>,
    /// Bytes per second of the last write.
    rate: Mutex<Option<f64>>,
}

/// Values written to a [`SpillFile`].
#[derive(Clone)]
pub(crate) struct Spilled {
    file: Arc<SpillFile>,
    at: u64,
    len: usize,
}

impl SpillFile {
    /// An unnamed file in the folder of [`FACTOR_DISK_ENV`], if there is a
    /// usable one.
    pub(crate) fn open() -> Option<Arc<SpillFile>> {
        let dir = match std::env::var(FACTOR_DISK_ENV) {
            Ok(v) if v.trim() == "off" => return None,
            Ok(v) if !v.trim().is_empty() => PathBuf::from(v.trim()),
            _ => {
                let var_tmp = PathBuf::from("/var/tmp");
                if var_tmp.is_dir() {
                    var_tmp
                } else {
                    std::env::temp_dir()
                }
            }
        };
        let file = tempfile::tempfile_in(&dir).ok()?;
        if in_memory(&file) {
            return None;
        }
        Some(Arc::new(SpillFile {
            file,
            dir,
            end: Mutex::new(0),
            rate: Mutex::new(None),
        }))
    }

    /// Writes `values` if that takes less than `worth` seconds at the rate
    /// the last write took (the first is tried); none if not, if the disk
    /// would keep less than [`RESERVE`] free, or on an error.
    pub(crate) fn put(self: &Arc<Self>, values: &[f64], worth: f64) -> Option<Spilled> {
        let bytes = 8 * values.len() as u64;
        let rate = *self.rate.lock().ok()?;
        if rate.is_some_and(|r| bytes as f64 / r > worth) {
            return None;
        }
        if free_space(&self.dir)? < bytes.saturating_add(RESERVE) {
            return None;
        }
        let at = {
            let mut end = self.end.lock().ok()?;
            let at = *end;
            *end += bytes;
            at
        };
        let t = Instant::now();
        self.file.write_all_at(bytemuck::cast_slice(values), at).ok()?;
        if let Ok(mut rate) = self.rate.lock() {
            *rate = Some(bytes as f64 / t.elapsed().as_secs_f64().max(1e-9));
        }
        Some(Spilled {
            file: self.clone(),
            at,
            len: values.len(),
        })
    }
}

impl Spilled {
    /// The written values, followed by `rest`, in `out` (cleared first).
    pub(crate) fn read_then(&self, rest: &[f64], mut out: Vec<f64>) -> io::Result<Vec<f64>> {
        out.clear();
        out.try_reserve_exact(self.len + rest.len())
            .map_err(|_| io::Error::new(io::ErrorKind::OutOfMemory, "out of memory for a whole factor"))?;
        out.resize(self.len, 0.0);
        self.file
            .file
            .read_exact_at(bytemuck::cast_slice_mut(&mut out[..]), self.at)?;
        out.extend_from_slice(rest);
        Ok(out)
    }
}

/// Whether reduced factors can keep the rest of their values on disk here
/// (the folder of [`FACTOR_DISK_ENV`] exists, is writable and not in
/// memory).
pub fn usable() -> bool {
    SpillFile::open().is_some()
}

/// Free bytes for an unprivileged user on the disk of `path` (its nearest
/// existing folder), if known.
pub(crate) fn free_space(path: &Path) -> Option<u64> {
    use std::os::unix::ffi::OsStrExt;
    let existing = path
        .ancestors()
        .find(|a| !a.as_os_str().is_empty() && a.is_dir())
        .unwrap_or(Path::new("."));
    let c = std::ffi::CString::new(existing.as_os_str().as_bytes()).ok()?;
    let mut s = std::mem::MaybeUninit::<libc::statvfs>::uninit();
    // SAFETY: statvfs writes the struct for a NUL-terminated path.
    if unsafe { libc::statvfs(c.as_ptr(), s.as_mut_ptr()) } != 0 {
        return None;
    }
    // SAFETY: initialized by the successful call.
    let s = unsafe { s.assume_init() };
    // The field types differ between platforms.
    #[allow(clippy::unnecessary_cast)]
    Some(s.f_bavail as u64 * s.f_frsize as u64)
}

/// Whether the file's folder is in memory (tmpfs, ramfs): writing there
/// would take the memory the reduction saves.
fn in_memory(file: &File) -> bool {
    let mut s = std::mem::MaybeUninit::<libc::statfs>::uninit();
    // SAFETY: fstatfs writes the struct for an open descriptor.
    let r = unsafe { libc::fstatfs(file.as_raw_fd(), s.as_mut_ptr()) };
    if r != 0 {
        return true;
    }
    // SAFETY: initialized by the successful call.
    let s = unsafe { s.assume_init() };
    // The field's type differs between platforms.
    #[allow(clippy::unnecessary_cast)]
    let t = s.f_type as i64;
    const TMPFS: i64 = 0x0102_1994;
    const RAMFS: i64 = 0x8584_58f6;
    t == TMPFS || t == RAMFS
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_come_back_bit_for_bit_after_others() {
        let Some(file) = SpillFile::open() else {
            return; // no usable disk folder: nothing is written
        };
        let a: Vec<f64> = (0..3_000_007).map(|i| (i as f64).sin() * 1e-300).collect();
        let b = vec![f64::MAX, -0.0, f64::MIN_POSITIVE];
        let sa = file.put(&a, f64::INFINITY).expect("written");
        let sb = file.put(&b, f64::INFINITY).expect("written");
        assert!(
            file.put(&a, 0.0).is_none(),
            "a write slower than its worth is not made"
        );
        assert_eq!(
            sb.read_then(&[1.5], vec![7.0; 9]).expect("read"),
            [b.as_slice(), &[1.5]].concat()
        );
        let back = sa.read_then(&[], Vec::new()).expect("read");
        assert!(back.len() == a.len() && back.iter().zip(&a).all(|(x, y)| x.to_bits() == y.to_bits()));
    }
}
