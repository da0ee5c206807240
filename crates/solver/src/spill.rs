//! The leading columns of reduced factors on disk: a factor that keeps
//! only its joint block ([`crate::linear::Model::joint_block`]) writes the
//! rest of its values to one unnamed file of the model, and a full solve
//! reads them back (whole, or last first through a small window for the
//! backward solve of joint-node loads) instead of factorizing the harmonic
//! again. A write may run behind the factorization on a thread of its
//! own; a read waits for it. The file has no name (removed when made), so
//! a killed run leaves nothing behind.
//! A factor is written only while writing is faster than factorizing it
//! was (the disk's rate measured on each write: a disk slower than the
//! factorization, or one whose cache is full, stops the writes). Where the
//! disk is short or the folder is in memory (tmpfs), the values are
//! dropped and a full solve factorizes again, as without the file.
//!
//! The file is written and read around the page cache (`O_DIRECT`, in
//! aligned blocks through a small buffer) where its file system allows:
//! a buffered write makes the kernel find a page of memory for every 4 KiB
//! written, which on a virtual machine costs as much as the factorization
//! (measured: 345 MB/s buffered, 1.7 GB/s direct, docs/performance.md).

use std::fs::File;
use std::io;
use std::os::unix::fs::FileExt;
use std::os::unix::io::AsRawFd;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Condvar, Mutex, RwLock};
use std::time::Instant;

/// Environment variable: the folder for the leading columns of reduced
/// factors; unset: `/var/tmp` if it exists, else the system's temporary
/// folder; `off`: none (a full solve of a reduced harmonic factorizes it
/// again). A folder in memory (tmpfs) counts as `off`.
pub const FACTOR_DISK_ENV: &str = "AXIJOINT_FACTOR_DISK";

/// Free space a write leaves on the disk at least: 1 GiB.
const RESERVE: u64 = 1 << 30;

/// Alignment of a direct transfer's offsets, lengths and memory (the
/// largest logical block size of Linux's file systems).
const ALIGN: usize = 4096;

/// Bytes a direct transfer moves through its buffer at a time.
const CHUNK: usize = 1 << 20;

/// The file of a model's written values; writes append.
pub(crate) struct SpillFile {
    file: File,
    /// Whether the file is written and read around the page cache.
    direct: bool,
    dir: PathBuf,
    end: Mutex<u64>,
    /// Bytes per second of the last write.
    rate: Mutex<Option<f64>>,
    /// Buffers of direct transfers done, for the next.
    buffers: Mutex<Vec<Aligned>>,
    /// Writes running behind the factorization, and how many may.
    behind: Mutex<(usize, usize)>,
    /// Signalled when a write behind ends.
    ended: Condvar,
    /// Whether the values are freed ([`SpillFile::release`]): reads and
    /// writes hold it shared, the release exclusive.
    released: RwLock<bool>,
}

/// Values written to a [`SpillFile`].
#[derive(Clone)]
pub(crate) struct Spilled {
    file: Arc<SpillFile>,
    at: u64,
    len: usize,
    /// A write behind: whether it succeeded once it has ended.
    pending: Option<Arc<(Mutex<Option<bool>>, Condvar)>>,
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
        let direct = set_direct(&file);
        Some(SpillFile::new(file, direct, dir))
    }

    /// An empty spill file on `file` (in folder `dir`), written and read
    /// around the page cache if `direct`.
    fn new(file: File, direct: bool, dir: PathBuf) -> Arc<SpillFile> {
        Arc::new(SpillFile {
            file,
            direct,
            dir,
            end: Mutex::new(0),
            rate: Mutex::new(None),
            buffers: Mutex::new(Vec::new()),
            behind: Mutex::new((0, 0)),
            ended: Condvar::new(),
            released: RwLock::new(false),
        })
    }

    /// Writes `values[..len]` if that takes less than `worth` seconds at
    /// the rate the last write took (the first is tried); none if not, if
    /// the disk would keep less than [`RESERVE`] free, or on an error.
    /// Then `done(values)`: at once, or, while fewer writes than
    /// [`SpillFile::allow_behind`] run behind, on a thread of its own
    /// after writing them there (a read waits for it).
    pub(crate) fn put(
        self: &Arc<Self>,
        values: Vec<f64>,
        len: usize,
        worth: f64,
        done: impl FnOnce(Vec<f64>) + Send + 'static,
    ) -> Option<Spilled> {
        let Some(at) = self.reserve(len, worth) else {
            done(values);
            return None;
        };
        let behind = self
            .behind
            .lock()
            .ok()
            .and_then(|mut b| (b.0 < b.1).then(|| b.0 += 1))
            .is_some();
        if !behind {
            let written = self.write(&values[..len], at);
            done(values);
            return written.then(|| Spilled {
                file: self.clone(),
                at,
                len,
                pending: None,
            });
        }
        let pending = Arc::new((Mutex::new(None), Condvar::new()));
        let (file, ended) = (self.clone(), pending.clone());
        let spawned = std::thread::Builder::new()
            .name("axijoint-spill".into())
            .spawn(move || {
                let ok = file.write(&values[..len], at);
                done(values);
                if let Ok(mut e) = ended.0.lock() {
                    *e = Some(ok);
                }
                ended.1.notify_all();
                if let Ok(mut b) = file.behind.lock() {
                    b.0 -= 1;
                }
                file.ended.notify_all();
            });
        if spawned.is_err() {
            if let Ok(mut b) = self.behind.lock() {
                b.0 -= 1;
            }
            return None;
        }
        Some(Spilled {
            file: self.clone(),
            at,
            len,
            pending: Some(pending),
        })
    }

    /// At most `n` writes run behind from now on; waits until no more do.
    pub(crate) fn allow_behind(&self, n: usize) {
        let Ok(mut b) = self.behind.lock() else {
            return;
        };
        b.1 = n;
        while b.0 > n {
            match self.ended.wait(b) {
                Ok(g) => b = g,
                Err(_) => return,
            }
        }
    }

    /// The file offset for `len` values, if writing them is worth it
    /// ([`SpillFile::put`]) and the disk has room.
    fn reserve(&self, len: usize, worth: f64) -> Option<u64> {
        let bytes = 8 * len as u64;
        let rate = *self.rate.lock().ok()?;
        if rate.is_some_and(|r| bytes as f64 / r > worth) {
            return None;
        }
        if free_space(&self.dir)? < bytes.saturating_add(RESERVE) {
            return None;
        }
        let mut end = self.end.lock().ok()?;
        let at = *end;
        *end += if self.direct {
            padded(bytes as usize) as u64
        } else {
            bytes
        };
        Some(at)
    }

    /// Frees the written values on a thread of its own (a file system
    /// that discards freed blocks, mounted with `discard`, takes about a
    /// second per GB: behind the outputs rather than at the exit); reads
    /// after it fail (a full solve then factorizes again).
    pub(crate) fn release(self: &Arc<Self>) {
        let file = self.clone();
        let freed = std::thread::Builder::new()
            .name("axijoint-spill-free".into())
            .spawn(move || {
                if let Ok(mut released) = file.released.write() {
                    *released = true;
                    let _ = file.file.set_len(0);
                }
            });
        drop(freed);
    }

    /// Writes `values` at `at` and measures the rate; whether it worked.
    fn write(&self, values: &[f64], at: u64) -> bool {
        let Ok(released) = self.released.read() else {
            return false;
        };
        if *released {
            return false;
        }
        let t = Instant::now();
        let bytes_of: &[u8] = bytemuck::cast_slice(values);
        let ok = if self.direct {
            let mut buffer = self.buffer();
            let ok = bytes_of.chunks(CHUNK).enumerate().all(|(k, part)| {
                self.file
                    .write_all_at(buffer.fill(part), at + (k * CHUNK) as u64)
                    .is_ok()
            });
            self.give_back(buffer);
            ok
        } else {
            self.file.write_all_at(bytes_of, at).is_ok()
        };
        if let Ok(mut rate) = self.rate.lock() {
            *rate = Some(bytes_of.len() as f64 / t.elapsed().as_secs_f64().max(1e-9));
        }
        ok
    }

    /// Holds the written values from being freed while read; an error if
    /// they are.
    fn kept(&self) -> io::Result<std::sync::RwLockReadGuard<'_, bool>> {
        match self.released.read() {
            Ok(r) if !*r => Ok(r),
            _ => Err(io::Error::other("the factors on disk are freed")),
        }
    }

    /// A buffer for a direct transfer: a kept one, else a new one.
    fn buffer(&self) -> Aligned {
        self.buffers
            .lock()
            .ok()
            .and_then(|mut b| b.pop())
            .unwrap_or_else(Aligned::new)
    }

    /// Keeps `buffer` for the next transfer.
    fn give_back(&self, buffer: Aligned) {
        if let Ok(mut b) = self.buffers.lock() {
            b.push(buffer);
        }
    }
}

impl Spilled {
    /// The written values, followed by `rest`, in `out` (cleared first).
    pub(crate) fn read_then(&self, rest: &[f64], mut out: Vec<f64>) -> io::Result<Vec<f64>> {
        self.written()?;
        let _kept = self.file.kept()?;
        out.clear();
        out.try_reserve_exact(self.len + rest.len())
            .map_err(|_| io::Error::new(io::ErrorKind::OutOfMemory, "out of memory for a whole factor"))?;
        if self.file.direct {
            let mut buffer = self.file.buffer();
            let per = CHUNK / 8;
            for k in 0..self.len.div_ceil(per) {
                let n = per.min(self.len - k * per);
                let block = buffer.block(8 * n);
                self.file
                    .file
                    .read_exact_at(block, self.at + (k * CHUNK) as u64)?;
                out.extend_from_slice(bytemuck::cast_slice(&block[..8 * n]));
            }
            self.file.give_back(buffer);
        } else {
            out.resize(self.len, 0.0);
            self.file
                .file
                .read_exact_at(bytemuck::cast_slice_mut(&mut out[..]), self.at)?;
        }
        out.extend_from_slice(rest);
        Ok(out)
    }
}

impl Spilled {
    /// A reader of the written values from the last towards the first
    /// ([`crate::factor::Leading`]): at most about [`CHUNK`] bytes beyond
    /// the range asked are in memory.
    pub(crate) fn backward(&self) -> io::Result<Backward<'_>> {
        self.written()?;
        Ok(Backward {
            spilled: self,
            buffer: self.file.direct.then(|| self.file.buffer()),
            lo: self.len,
            window: Vec::new(),
            spare: Vec::new(),
        })
    }

    /// Waits for a write behind; an error if it failed.
    fn written(&self) -> io::Result<()> {
        let Some(pending) = &self.pending else {
            return Ok(());
        };
        let failed = || io::Error::other("the write of a factor failed");
        let mut e = pending.0.lock().map_err(|_| failed())?;
        while e.is_none() {
            e = pending.1.wait(e).map_err(|_| failed())?;
        }
        if *e == Some(true) {
            Ok(())
        } else {
            Err(failed())
        }
    }
}

/// [`Spilled::backward`]: `window` holds the values `lo..` up to the end of
/// the last range asked.
pub(crate) struct Backward<'a> {
    spilled: &'a Spilled,
    buffer: Option<Aligned>,
    lo: usize,
    window: Vec<f64>,
    spare: Vec<f64>,
}

impl crate::factor::Leading for Backward<'_> {
    fn values(&mut self, from: usize, to: usize) -> io::Result<&[f64]> {
        assert!(
            from <= to && to <= self.lo + self.window.len(),
            "ranges asked last first"
        );
        let to_kept = to.saturating_sub(self.lo);
        if from < self.lo {
            // Read `start..self.lo` (at least a chunk, aligned) before the
            // values still wanted, `self.lo..to`.
            let per = CHUNK / 8;
            let align = ALIGN / 8;
            let start = from.min(self.lo.saturating_sub(per)) / align * align;
            let _kept = self.spilled.file.kept()?;
            let mut next = std::mem::take(&mut self.spare);
            next.clear();
            next.try_reserve(to - start)
                .map_err(|_| io::Error::new(io::ErrorKind::OutOfMemory, "out of memory for a read"))?;
            let (file, at) = (&self.spilled.file, self.spilled.at);
            match &mut self.buffer {
                Some(buffer) => {
                    let mut k = start;
                    while k < self.lo {
                        let n = per.min(self.lo - k);
                        let block = buffer.block(8 * n);
                        file.file.read_exact_at(block, at + 8 * k as u64)?;
                        next.extend_from_slice(bytemuck::cast_slice(&block[..8 * n]));
                        k += n;
                    }
                }
                None => {
                    next.resize(self.lo - start, 0.0);
                    file.file
                        .read_exact_at(bytemuck::cast_slice_mut(&mut next[..]), at + 8 * start as u64)?;
                }
            }
            next.extend_from_slice(&self.window[..to_kept]);
            self.spare = std::mem::replace(&mut self.window, next);
            self.lo = start;
        }
        Ok(&self.window[from - self.lo..to - self.lo])
    }
}

impl Drop for Backward<'_> {
    fn drop(&mut self) {
        if let Some(buffer) = self.buffer.take() {
            self.spilled.file.give_back(buffer);
        }
    }
}

/// `n` rounded up to a multiple of [`ALIGN`].
fn padded(n: usize) -> usize {
    n.div_ceil(ALIGN) * ALIGN
}

/// A buffer of [`CHUNK`] bytes at an [`ALIGN`]ed address, for direct
/// transfers.
struct Aligned {
    bytes: Vec<u8>,
    skip: usize,
}

impl Aligned {
    fn new() -> Self {
        let bytes = vec![0u8; CHUNK + ALIGN];
        let skip = bytes.as_ptr().align_offset(ALIGN);
        Aligned { bytes, skip }
    }

    /// The first `n` bytes (at most [`CHUNK`]), padded to [`ALIGN`].
    fn block(&mut self, n: usize) -> &mut [u8] {
        &mut self.bytes[self.skip..self.skip + padded(n)]
    }

    /// The block holding `part` (at most [`CHUNK`] bytes), zeros after it.
    fn fill(&mut self, part: &[u8]) -> &[u8] {
        let block = self.block(part.len());
        block[..part.len()].copy_from_slice(part);
        block[part.len()..].fill(0);
        block
    }
}

/// Sets or clears `O_DIRECT` on `file`; whether the call succeeded.
fn direct_flag(file: &File, on: bool) -> bool {
    let fd = file.as_raw_fd();
    // SAFETY: fcntl on an open descriptor reads and sets its status flags.
    let flags = unsafe { libc::fcntl(fd, libc::F_GETFL) };
    let want = if on {
        flags | libc::O_DIRECT
    } else {
        flags & !libc::O_DIRECT
    };
    // SAFETY: as above.
    flags >= 0 && unsafe { libc::fcntl(fd, libc::F_SETFL, want) } == 0
}

/// Sets `O_DIRECT` on `file` if its file system takes it (one aligned
/// block written and read back); whether it is set.
fn set_direct(file: &File) -> bool {
    if !direct_flag(file, true) {
        return false;
    }
    let mut buffer = Aligned::new();
    let probe: Vec<u8> = (0..ALIGN).map(|i| (i % 251) as u8).collect();
    let works = file.write_all_at(buffer.fill(&probe), 0).is_ok()
        && file.read_exact_at(buffer.block(ALIGN), 0).is_ok()
        && buffer.block(ALIGN) == probe.as_slice();
    if !works {
        direct_flag(file, false);
    }
    works
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

    /// Writes two arrays (one of several chunks and a partial block, one
    /// of 24 bytes) and reads them back.
    fn round_trip(file: &Arc<SpillFile>) {
        let a: Vec<f64> = (0..3_000_007).map(|i| (i as f64).sin() * 1e-300).collect();
        let b = vec![f64::MAX, -0.0, f64::MIN_POSITIVE];
        let sa = file
            .put(a.clone(), a.len(), f64::INFINITY, drop)
            .expect("written");
        // Behind: a thread writes the values (a partial chunk of them) and
        // hands them back; a read waits for it.
        file.allow_behind(1);
        let (tx, rx) = std::sync::mpsc::channel();
        let padded_b = [b.as_slice(), &[9.0; 5]].concat();
        let sb = file
            .put(padded_b, b.len(), f64::INFINITY, move |v| tx.send(v).unwrap())
            .expect("written");
        assert!(sb.pending.is_some(), "written behind");
        file.allow_behind(0);
        assert_eq!(
            rx.try_recv().expect("handed back once written").len(),
            b.len() + 5
        );
        assert!(
            file.put(a.clone(), a.len(), 0.0, drop).is_none(),
            "a write slower than its worth is not made"
        );
        assert_eq!(
            sb.read_then(&[1.5], vec![7.0; 9]).expect("read"),
            [b.as_slice(), &[1.5]].concat()
        );
        let back = sa.read_then(&[], Vec::new()).expect("read");
        assert!(back.len() == a.len() && back.iter().zip(&a).all(|(x, y)| x.to_bits() == y.to_bits()));
        // Backward in ranges of 1 to about 1.6 chunks, last first.
        use crate::factor::Leading;
        let mut reader = sa.backward().expect("written");
        let mut to = a.len();
        let mut k = 0usize;
        while to > 0 {
            k += 1;
            let from = to.saturating_sub(1 + (k * k * 7919) % 210_000);
            let got = reader.values(from, to).expect("read");
            assert!(
                got.iter()
                    .zip(&a[from..to])
                    .all(|(x, y)| x.to_bits() == y.to_bits())
                    && got.len() == to - from,
                "values {from}..{to}"
            );
            to = from;
        }
        assert!(k > 20, "{k} ranges");
        let mut reader = sb.backward().expect("written");
        assert_eq!(reader.values(1, 3).expect("read"), &b[1..]);
        assert_eq!(reader.values(0, 1).expect("read"), &b[..1]);
        drop(reader);
        // Released: the file is emptied behind, and reads fail after it.
        file.release();
        let t = Instant::now();
        while sb.read_then(&[], Vec::new()).is_ok() {
            assert!(t.elapsed().as_secs() < 60, "released within a minute");
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
        assert!(sa
            .backward()
            .and_then(|mut r| r.values(0, 1).map(<[f64]>::to_vec))
            .is_err());
        assert_eq!(
            file.file.metadata().expect("metadata").len(),
            0,
            "the file is emptied"
        );
        assert!(
            file.put(b.clone(), b.len(), f64::INFINITY, drop).is_none(),
            "no writes after"
        );
    }

    #[test]
    fn values_come_back_bit_for_bit_after_others() {
        let Some(file) = SpillFile::open() else {
            return; // no usable disk folder: nothing is written
        };
        round_trip(&file);
    }

    #[test]
    fn values_come_back_through_the_page_cache_too() {
        let Some(file) = SpillFile::open() else {
            return;
        };
        assert!(direct_flag(&file.file, false), "O_DIRECT cleared");
        let buffered = SpillFile::new(
            file.file.try_clone().expect("a second descriptor"),
            false,
            file.dir.clone(),
        );
        round_trip(&buffered);
    }
}
