//! A content-addressed cache of the meshes gmsh makes, so that a run whose
//! inputs did not change skips gmsh.
//!
//! The key is the SHA-256 of everything gmsh's output depends on that
//! axijoint can see:
//!
//! - the `.geo` text, and the text of every file it names in an
//!   `Include "..."` or `Merge "..."` with a literal path (recursively,
//!   relative to the including file; a missing one counts as missing);
//! - the gmsh parameters (`-setnumber` names and values, sorted by name);
//! - the command line axijoint passes (`-2 -format msh41`);
//! - the gmsh program: its resolved path, size and modification time (an
//!   upgrade replaces the file; gmsh is not started to ask its version, so
//!   a hit does not start gmsh at all).
//!
//! An entry is `<dir>/meshes/<key>.msh`: a header line
//! `axijoint-mesh-cache 1 <bytes> <sha256 of the payload>` then gmsh's
//! `.msh` unchanged. It is written to a temporary file in the same folder
//! and renamed into place, so readers see a whole entry or none; a reader
//! checks the length and the hash, and an entry that fails (a truncated or
//! corrupted file) is a miss: gmsh runs and the entry is rewritten. Runs
//! may share a folder. Nothing is ever deleted: remove the folder to clear
//! it.
//!
//! The folder: `$AXIJOINT_CACHE` if set and not empty, else
//! `$XDG_CACHE_HOME/axijoint`, else `$HOME/.cache/axijoint`
//! ([`default_dir`]). The library uses no cache unless [`set_dir`] gives
//! it one (the `axijoint` binary does, unless `--no-cache`).

use sha2::{Digest, Sha256};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// Environment variable naming the cache folder.
pub const ENV: &str = "AXIJOINT_CACHE";

/// Format of the key and of the entries; bump to orphan old entries.
const VERSION: u32 = 1;

/// First word of an entry's header line.
const MAGIC: &str = "axijoint-mesh-cache";

/// Deepest `Include` nesting followed.
const MAX_DEPTH: usize = 16;

static DIR: Mutex<Option<PathBuf>> = Mutex::new(None);

/// The cache folder of this process (`None`: no cache).
pub fn dir() -> Option<PathBuf> {
    DIR.lock().unwrap_or_else(|e| e.into_inner()).clone()
}

/// Sets the cache folder of this process (`None`: no cache, the default).
pub fn set_dir(dir: Option<PathBuf>) {
    *DIR.lock().unwrap_or_else(|e| e.into_inner()) = dir;
}

/// `$AXIJOINT_CACHE` if set and not empty, else `$XDG_CACHE_HOME/axijoint`
/// (an absolute path), else `$HOME/.cache/axijoint`; `None` without any.
pub fn default_dir() -> Option<PathBuf> {
    dir_from(|name| std::env::var_os(name))
}

/// [`default_dir`] with the environment `env`.
fn dir_from(env: impl Fn(&str) -> Option<std::ffi::OsString>) -> Option<PathBuf> {
    let var = |name: &str| env(name).filter(|v| !v.is_empty()).map(PathBuf::from);
    if let Some(d) = var(ENV) {
        return Some(d);
    }
    if let Some(x) = var("XDG_CACHE_HOME").filter(|p| p.is_absolute()) {
        return Some(x.join("axijoint"));
    }
    var("HOME").map(|h| h.join(".cache").join("axijoint"))
}

/// The key of meshing `geo` with `parameters` by `program`, as 64 hex
/// digits; `None` when the `.geo` cannot be read or `program` is not found
/// (then gmsh runs uncached and reports the problem itself).
pub fn key(geo: &Path, parameters: &[(String, f64)], program: &Path) -> Option<String> {
    let mut h = Sha256::new();
    h.update(format!("{MAGIC} {VERSION}\nargs -2 -format msh41\n"));
    let exe = resolve_program(program)?;
    let meta = std::fs::metadata(&exe).ok()?;
    let mtime = meta
        .modified()
        .ok()
        .and_then(|t| t.duration_since(std::time::UNIX_EPOCH).ok())
        .map_or(0, |d| d.as_nanos());
    h.update(format!("gmsh {} {} {mtime}\n", exe.display(), meta.len()));
    let text = std::fs::read(geo).ok()?;
    h.update(format!("geo {}\n", text.len()));
    h.update(&text);
    let mut seen = vec![geo.canonicalize().unwrap_or_else(|_| geo.to_path_buf())];
    hash_includes(&mut h, geo, &text, 0, &mut seen);
    let mut params: Vec<&(String, f64)> = parameters.iter().collect();
    // Stable: repeated names keep their order (gmsh keeps the last).
    params.sort_by(|a, b| a.0.cmp(&b.0));
    for (name, value) in params {
        h.update(format!("set {} {name} {value:?}\n", name.len()));
    }
    Some(hex(&h.finalize()))
}

/// Hashes the files that `text` (the contents of `file`) includes.
fn hash_includes(h: &mut Sha256, file: &Path, text: &[u8], depth: usize, seen: &mut Vec<PathBuf>) {
    let base = file.parent().unwrap_or(Path::new("."));
    for name in included_names(text) {
        let path = base.join(&name);
        match std::fs::read(&path) {
            Ok(bytes) => {
                h.update(format!("include {} {name} {}\n", name.len(), bytes.len()));
                h.update(&bytes);
                let canon = path.canonicalize().unwrap_or(path.clone());
                if depth < MAX_DEPTH && !seen.contains(&canon) {
                    seen.push(canon);
                    hash_includes(h, &path, &bytes, depth + 1, seen);
                }
            }
            Err(_) => h.update(format!("include {} {name} missing\n", name.len())),
        }
    }
}

/// The literal paths of `Include "..."` and `Merge "..."` in a `.geo`
/// text, in order (comments are not skipped: a commented-out one only adds
/// a dependency).
pub fn included_names(text: &[u8]) -> Vec<String> {
    let text = String::from_utf8_lossy(text);
    let mut out = Vec::new();
    for word in ["Include", "Merge"] {
        let mut rest = text.as_ref();
        while let Some(i) = rest.find(word) {
            let before = text.len() - rest.len() + i;
            rest = &rest[i + word.len()..];
            let standalone = text[..before]
                .chars()
                .next_back()
                .is_none_or(|c| !(c.is_alphanumeric() || c == '_'));
            let arg = rest.trim_start();
            if standalone && arg.starts_with('"') {
                if let Some(end) = arg[1..].find('"') {
                    out.push((before, arg[1..1 + end].to_string()));
                }
            }
        }
    }
    out.sort();
    out.into_iter().map(|(_, name)| name).collect()
}

/// `program` as run by `Command`: a path as it is, a bare name searched on
/// `PATH`; canonical.
fn resolve_program(program: &Path) -> Option<PathBuf> {
    if program.components().count() > 1 {
        return program.canonicalize().ok();
    }
    std::env::split_paths(&std::env::var_os("PATH")?)
        .map(|d| d.join(program))
        .find(|p| is_executable(p))
        .and_then(|p| p.canonicalize().ok())
}

#[cfg(unix)]
fn is_executable(p: &Path) -> bool {
    use std::os::unix::fs::PermissionsExt;
    std::fs::metadata(p).is_ok_and(|m| m.is_file() && m.permissions().mode() & 0o111 != 0)
}

#[cfg(not(unix))]
fn is_executable(p: &Path) -> bool {
    p.is_file()
}

fn entry_path(dir: &Path, key: &str) -> PathBuf {
    dir.join("meshes").join(format!("{key}.msh"))
}

/// The `.msh` bytes of entry `key`, if it is there and whole.
pub fn get(dir: &Path, key: &str) -> Option<Vec<u8>> {
    let bytes = std::fs::read(entry_path(dir, key)).ok()?;
    let nl = bytes.iter().position(|&b| b == b'\n')?;
    let header = std::str::from_utf8(&bytes[..nl]).ok()?;
    let payload = &bytes[nl + 1..];
    let mut words = header.split(' ');
    let ok = words.next() == Some(MAGIC)
        && words.next() == Some(&VERSION.to_string())
        && words.next() == Some(&payload.len().to_string())
        && words.next() == Some(&hex(&Sha256::digest(payload)))
        && words.next().is_none();
    ok.then(|| payload.to_vec())
}

/// Stores `msh` as entry `key` (temporary file, then an atomic rename).
pub fn put(dir: &Path, key: &str, msh: &[u8]) -> std::io::Result<()> {
    let target = entry_path(dir, key);
    let folder = target.parent().expect("entries sit in a folder");
    std::fs::create_dir_all(folder)?;
    let header = format!("{MAGIC} {VERSION} {} {}\n", msh.len(), hex(&Sha256::digest(msh)));
    crate::atomic::write(&target, |tmp| {
        tmp.write_all(header.as_bytes())?;
        tmp.write_all(msh)?;
        tmp.flush()?;
        tmp.get_ref().sync_all()
    })
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn include_and_merge_names_in_order() {
        let text =
            b"a = 1;\nInclude \"base.geo\";\nMyInclude \"no.geo\";\nMerge  \"bg.pos\"; Include\"x y.geo\";\n";
        assert_eq!(included_names(text), ["base.geo", "bg.pos", "x y.geo"]);
    }

    #[test]
    fn folder_from_the_environment() {
        let env = |vars: &'static [(&'static str, &'static str)]| {
            move |name: &str| vars.iter().find(|v| v.0 == name).map(|v| v.1.into())
        };
        let all: &[_] = &[(ENV, "/c"), ("XDG_CACHE_HOME", "/x"), ("HOME", "/h")];
        assert_eq!(dir_from(env(all)), Some(PathBuf::from("/c")));
        let no_env: &[_] = &[(ENV, ""), ("XDG_CACHE_HOME", "/x"), ("HOME", "/h")];
        assert_eq!(dir_from(env(no_env)), Some(PathBuf::from("/x/axijoint")));
        let relative_xdg: &[_] = &[("XDG_CACHE_HOME", "x"), ("HOME", "/h")];
        assert_eq!(
            dir_from(env(relative_xdg)),
            Some(PathBuf::from("/h/.cache/axijoint"))
        );
        assert_eq!(dir_from(env(&[])), None);
    }

    #[test]
    fn entries_round_trip_and_damage_is_a_miss() {
        let dir = tempfile::tempdir().unwrap();
        let key = "k".repeat(64);
        assert_eq!(get(dir.path(), &key), None);
        put(dir.path(), &key, b"$MeshFormat\n4.1 0 8\n").unwrap();
        assert_eq!(
            get(dir.path(), &key).as_deref(),
            Some(&b"$MeshFormat\n4.1 0 8\n"[..])
        );
        let path = entry_path(dir.path(), &key);
        let whole = std::fs::read(&path).unwrap();
        // Truncated (a half-written file), then one byte changed.
        std::fs::write(&path, &whole[..whole.len() - 3]).unwrap();
        assert_eq!(get(dir.path(), &key), None);
        let mut bad = whole.clone();
        let last = bad.len() - 2;
        bad[last] ^= 1;
        std::fs::write(&path, &bad).unwrap();
        assert_eq!(get(dir.path(), &key), None);
        // No temporary file is left behind.
        assert_eq!(std::fs::read_dir(path.parent().unwrap()).unwrap().count(), 1);
    }
}
