//! Running the gmsh command line on a `.geo` file, through the mesh
//! [`cache`] when the process has one.

pub mod cache;

use crate::{parse_msh, read_msh, Mesh, MeshError};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The gmsh executable: `$AXIJOINT_GMSH` if set, else `gmsh` on PATH.
pub fn gmsh_program() -> PathBuf {
    std::env::var_os("AXIJOINT_GMSH")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("gmsh"))
}

/// The environment variable bounding gmsh's CPU time, in seconds.
pub const GMSH_SECONDS_ENV: &str = "AXIJOINT_GMSH_SECONDS";
/// The environment variable bounding gmsh's memory (address space), in
/// bytes (suffix `K`, `M` or `G`: KiB, MiB, GiB).
pub const GMSH_MEMORY_ENV: &str = "AXIJOINT_GMSH_MEMORY";
/// gmsh's CPU time bound unless [`GMSH_SECONDS_ENV`] says otherwise: a 2D
/// mesh of a million elements takes about a minute.
pub const GMSH_SECONDS: u64 = 600;

/// The bounds gmsh runs under: CPU seconds and address space (bytes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GmshBounds {
    /// CPU seconds.
    pub seconds: u64,
    /// Address space, bytes (0: none).
    pub memory: u64,
}

impl GmshBounds {
    /// [`GMSH_SECONDS_ENV`] (default [`GMSH_SECONDS`]) and
    /// [`GMSH_MEMORY_ENV`] (default: 3/4 of the machine's memory); a value
    /// that is not a number is refused, naming the variable.
    pub fn from_env() -> Result<GmshBounds, String> {
        let var = |name: &str| std::env::var(name).ok().filter(|v| !v.trim().is_empty());
        let seconds = match var(GMSH_SECONDS_ENV) {
            Some(v) => v
                .trim()
                .parse::<u64>()
                .ok()
                .filter(|&s| s > 0)
                .ok_or_else(|| format!("{GMSH_SECONDS_ENV}={v}: give whole seconds > 0"))?,
            None => GMSH_SECONDS,
        };
        let memory = match var(GMSH_MEMORY_ENV) {
            Some(v) => crate::parse_bytes(v.trim()).ok_or_else(|| {
                format!("{GMSH_MEMORY_ENV}={v}: give bytes, or a number with K, M or G (e.g. 4G)")
            })?,
            None => physical_memory() / 4 * 3,
        };
        Ok(GmshBounds { seconds, memory })
    }
}

/// The machine's memory in bytes (0 when unknown).
fn physical_memory() -> u64 {
    #[cfg(unix)]
    {
        // SAFETY: sysconf has no preconditions.
        let (pages, size) = unsafe {
            (
                libc::sysconf(libc::_SC_PHYS_PAGES),
                libc::sysconf(libc::_SC_PAGESIZE),
            )
        };
        if pages > 0 && size > 0 {
            return pages as u64 * size as u64;
        }
    }
    0
}

/// Makes the child die with this process (Linux: `PR_SET_PDEATHSIG`): a
/// killed run must not leave gmsh meshing, and holding gigabytes, as an
/// orphan. The signal follows the thread that spawns the child, which
/// waits for it in [`mesh_geo`]. The child runs under `bounds`
/// (`RLIMIT_CPU`, `RLIMIT_AS`): a mesh parameter off by orders of
/// magnitude ends in a message, not in a machine out of memory.
#[cfg(target_os = "linux")]
fn dies_with_this_process(cmd: &mut Command, bounds: GmshBounds) {
    use std::os::unix::process::CommandExt;
    let parent = std::process::id();
    // SAFETY: the closure runs in the forked child before exec and calls
    // only async-signal-safe functions (prctl, getppid, setrlimit).
    unsafe {
        cmd.pre_exec(move || {
            if libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            // The parent died before the prctl took effect.
            if libc::getppid() as u32 != parent {
                return Err(std::io::Error::other("the parent process is gone"));
            }
            let cpu = libc::rlimit {
                rlim_cur: bounds.seconds as libc::rlim_t,
                rlim_max: bounds.seconds as libc::rlim_t,
            };
            libc::setrlimit(libc::RLIMIT_CPU, &cpu);
            if bounds.memory > 0 {
                let mem = libc::rlimit {
                    rlim_cur: bounds.memory as libc::rlim_t,
                    rlim_max: bounds.memory as libc::rlim_t,
                };
                libc::setrlimit(libc::RLIMIT_AS, &mem);
            }
            Ok(())
        });
    }
}

#[cfg(not(target_os = "linux"))]
fn dies_with_this_process(_cmd: &mut Command, _bounds: GmshBounds) {}

/// Why gmsh stopped at a bound, from how it ended: killed at its CPU
/// bound (SIGKILL or SIGXCPU), or out of memory (`std::bad_alloc`, or a
/// library it could not map). `None` when it ended otherwise.
fn bound_hit(status: &std::process::ExitStatus, stderr: &str, bounds: GmshBounds) -> Option<String> {
    #[cfg(unix)]
    {
        use std::os::unix::process::ExitStatusExt;
        if matches!(status.signal(), Some(libc::SIGKILL | libc::SIGXCPU)) {
            return Some(format!(
                "gmsh stopped at its bound of {} s of CPU time (${GMSH_SECONDS_ENV})",
                bounds.seconds
            ));
        }
    }
    let out_of_memory = stderr.contains("bad_alloc")
        || stderr.contains("failed to map segment")
        || stderr.contains("Cannot allocate memory")
        || stderr.contains("out of memory");
    (bounds.memory > 0 && !status.success() && out_of_memory).then(|| {
        format!(
            "gmsh ran out of its memory bound of {} MiB (${GMSH_MEMORY_ENV})",
            bounds.memory >> 20
        )
    })
}

/// Meshes `geo` in 2D with gmsh into `msh` (MSH 4.1 ASCII), passing each
/// `(name, value)` as `-setnumber name value`.
///
/// gmsh exits non-zero on errors but may still leave a partial file, so the
/// exit status decides, and gmsh's own `Error` lines are passed through.
pub fn mesh_geo(geo: &Path, parameters: &[(String, f64)], msh: &Path) -> Result<(), MeshError> {
    if !geo.is_file() {
        return Err(MeshError::Io {
            path: geo.to_path_buf(),
            source: std::io::Error::new(std::io::ErrorKind::NotFound, "no such file"),
        });
    }
    let mut cmd = Command::new(gmsh_program());
    cmd.arg(geo).args(["-2", "-format", "msh41", "-o"]).arg(msh);
    for (name, value) in parameters {
        cmd.arg("-setnumber").arg(name).arg(format!("{value:?}"));
    }
    let out = run_bounded(cmd, geo, parameters)?;
    let stderr = String::from_utf8_lossy(&out.stderr);
    let stdout = String::from_utf8_lossy(&out.stdout);
    let errors: Vec<&str> = stderr
        .lines()
        .chain(stdout.lines())
        .filter(|l| l.starts_with("Error"))
        .collect();
    if !out.status.success() || !errors.is_empty() {
        let output = if errors.is_empty() {
            stderr.trim().to_string()
        } else {
            errors.join("\n")
        };
        return Err(MeshError::GmshFailed {
            path: geo.to_path_buf(),
            status: out.status.to_string(),
            output,
        });
    }
    Ok(())
}

/// Runs the gmsh command `cmd` on `geo` (with `parameters` among its
/// arguments) under [`GmshBounds::from_env`], dying with this process;
/// its output when it ran to its end (the caller reads its status and
/// errors), an error when it could not start or stopped at a bound.
pub fn run_bounded(
    mut cmd: Command,
    geo: &Path,
    parameters: &[(String, f64)],
) -> Result<std::process::Output, MeshError> {
    let bounds = GmshBounds::from_env().map_err(|message| MeshError::GmshFailed {
        path: geo.to_path_buf(),
        status: "not started".into(),
        output: message,
    })?;
    dies_with_this_process(&mut cmd, bounds);
    let out = cmd.output().map_err(|e| match e.kind() {
        std::io::ErrorKind::NotFound => MeshError::GmshMissing {
            path: geo.to_path_buf(),
        },
        // gmsh is there but could not be started (not executable, ...): a
        // gmsh failure, not one of the input file.
        _ => MeshError::GmshFailed {
            path: geo.to_path_buf(),
            status: format!("{} could not be started", gmsh_program().display()),
            output: e.to_string(),
        },
    })?;
    let stderr = String::from_utf8_lossy(&out.stderr);
    if let Some(bound) = bound_hit(&out.status, &stderr, bounds) {
        let given: Vec<String> = parameters.iter().map(|(n, v)| format!("{n} = {v}")).collect();
        let given = if given.is_empty() {
            "its own defaults".to_string()
        } else {
            given.join(", ")
        };
        return Err(MeshError::GmshFailed {
            path: geo.to_path_buf(),
            status: out.status.to_string(),
            output: format!(
                "{bound}, meshing with {given}: a mesh parameter off by orders of magnitude (a units slip?) makes gmsh mesh without end; raise the bound only for a mesh that needs it"
            ),
        });
    }
    Ok(out)
}

/// Where [`load_with`] took a mesh from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshSource {
    /// A `.msh` file read as it is.
    File,
    /// gmsh meshed the `.geo`.
    Gmsh,
    /// The cache held gmsh's mesh of the same inputs.
    Cache,
    /// This process meshed the same inputs already and has no usable
    /// cache folder (a run's comparison without joints reuses its scene's
    /// mesh under `--no-cache` or with a cache it cannot write).
    Memory,
}

/// gmsh's outputs this process made, by cache key: the last few.
static MEMO: std::sync::Mutex<Vec<(String, std::sync::Arc<Vec<u8>>)>> = std::sync::Mutex::new(Vec::new());
/// Meshes [`MEMO`] keeps.
const MEMO_LEN: usize = 4;

fn memo_get(key: &str) -> Option<std::sync::Arc<Vec<u8>>> {
    let memo = MEMO.lock().unwrap_or_else(|p| p.into_inner());
    memo.iter().find(|(k, _)| k == key).map(|(_, b)| b.clone())
}

fn memo_put(key: String, bytes: Vec<u8>) {
    let mut memo = MEMO.lock().unwrap_or_else(|p| p.into_inner());
    memo.retain(|(k, _)| *k != key);
    memo.push((key, std::sync::Arc::new(bytes)));
    let extra = memo.len().saturating_sub(MEMO_LEN);
    memo.drain(..extra);
}

/// Whether a cache folder failed to be written in this process (its
/// meshes are then kept in [`MEMO`]).
static UNWRITABLE: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Says once per process that the cache folder cannot be written.
fn cache_unwritable(dir: &Path, e: &std::io::Error) {
    static SAID: std::sync::Once = std::sync::Once::new();
    UNWRITABLE.store(true, std::sync::atomic::Ordering::Relaxed);
    SAID.call_once(|| {
        eprintln!(
            "warning: the mesh cache {} cannot be written ({e}): meshes are not kept for later runs (set AXIJOINT_CACHE to a writable folder, or --no-cache)",
            dir.display()
        );
    });
}

/// Reads a `.msh`, or meshes a `.geo` with gmsh (in a temporary folder, or
/// into `keep_msh` when given) and reads the result; through the process's
/// mesh cache ([`cache::dir`]) if it has one.
pub fn load(path: &Path, parameters: &[(String, f64)], keep_msh: Option<&Path>) -> Result<Mesh, MeshError> {
    load_with(path, parameters, keep_msh, cache::dir().as_deref()).map(|(mesh, _)| mesh)
}

/// [`load`] with the cache folder `cache` (`None`: no cache), telling
/// where the mesh came from. A `.geo` whose key ([`cache::key`]) has a
/// whole entry is read from it; else gmsh runs and its `.msh` is stored (a
/// cache that cannot be written is skipped, and said so once). Without a
/// cache folder, or with one that could not be written, the last
/// four meshes of this process are kept in memory and not meshed
/// again.
pub fn load_with(
    path: &Path,
    parameters: &[(String, f64)],
    keep_msh: Option<&Path>,
    cache: Option<&Path>,
) -> Result<(Mesh, MeshSource), MeshError> {
    let is_geo = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("geo"));
    if !is_geo {
        return Ok((read_msh(path)?, MeshSource::File));
    }
    let keep = |bytes: &[u8]| match keep_msh {
        Some(keep) => std::fs::write(keep, bytes).map_err(|e| MeshError::Io {
            path: keep.to_path_buf(),
            source: e,
        }),
        None => Ok(()),
    };
    let memo_key = cache::key(path, parameters, &gmsh_program());
    let key = cache.and_then(|dir| Some((dir, memo_key.clone()?)));
    let label = meshed_label(path);
    // Without a usable cache folder, this process's own meshes.
    let use_memo = || cache.is_none() || UNWRITABLE.load(std::sync::atomic::Ordering::Relaxed);
    if let Some(bytes) = memo_key.as_deref().filter(|_| use_memo()).and_then(memo_get) {
        let mesh = parse_msh(&bytes, &label)?.to_mesh(&label)?;
        keep(&bytes)?;
        return Ok((mesh, MeshSource::Memory));
    }
    if let Some((dir, key)) = &key {
        if let Some(bytes) = cache::get(dir, key) {
            let mesh = parse_msh(&bytes, &label)?.to_mesh(&label)?;
            keep(&bytes)?;
            return Ok((mesh, MeshSource::Cache));
        }
    }
    let dir = tempfile::tempdir().map_err(|e| MeshError::Io {
        path: std::env::temp_dir(),
        source: e,
    })?;
    let tmp = dir.path().join("mesh.msh");
    mesh_geo(path, parameters, &tmp)?;
    let bytes = std::fs::read(&tmp).map_err(|e| MeshError::Io {
        path: tmp.clone(),
        source: e,
    })?;
    let mesh = parse_msh(&bytes, &tmp)
        .and_then(|f| f.to_mesh(&tmp))
        .map_err(|e| rename_path(e, &tmp, path))?;
    keep(&bytes)?;
    if let Some((dir, key)) = &key {
        // A read-only or full cache only loses the reuse: said once.
        if let Err(e) = cache::put(dir, key, &bytes) {
            cache_unwritable(dir, &e);
        }
    }
    if let Some(key) = memo_key.filter(|_| use_memo()) {
        memo_put(key, bytes);
    }
    Ok((mesh, MeshSource::Gmsh))
}

/// How errors in gmsh's output name the `.geo`.
fn meshed_label(geo: &Path) -> PathBuf {
    PathBuf::from(format!("{} (meshed by gmsh)", geo.display()))
}

/// Errors in the temporary `.msh` are reported against the `.geo`.
fn rename_path(e: MeshError, tmp: &Path, geo: &Path) -> MeshError {
    let label = meshed_label(geo);
    match e {
        MeshError::Parse { path, line, message } if path == tmp => MeshError::Parse {
            path: label,
            line,
            message,
        },
        MeshError::Invalid { path, message } if path == tmp => MeshError::Invalid { path: label, message },
        other => other,
    }
}
