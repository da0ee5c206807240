//! Wall time, CPU time and peak memory of a child process (`wait4`).

use anyhow::{bail, Context, Result};
use std::process::{Command, Stdio};
use std::time::Instant;

/// What one child process cost.
#[derive(Clone, Debug)]
pub struct Measured {
    /// Wall-clock time (s).
    pub wall_seconds: f64,
    /// User + system CPU time of the child (s).
    pub cpu_seconds: f64,
    /// Peak resident set size of the child (bytes).
    pub peak_rss_bytes: u64,
    /// Captured standard output.
    pub stdout: String,
    /// Captured standard error.
    pub stderr: String,
}

/// Runs `cmd` to completion and measures it. A non-zero exit status is an
/// error that quotes the command and the tail of its standard error.
pub fn run_measured(cmd: &mut Command) -> Result<Measured> {
    let shown = format!("{cmd:?}");
    let out_file = tempfile::tempfile().context("temporary file for stdout")?;
    let err_file = tempfile::tempfile().context("temporary file for stderr")?;
    let start = Instant::now();
    let child = cmd
        .stdin(Stdio::null())
        .stdout(out_file.try_clone()?)
        .stderr(err_file.try_clone()?)
        .spawn()
        .with_context(|| format!("cannot start {shown}"))?;
    let pid = child.id() as libc::pid_t;
    let mut status: libc::c_int = 0;
    // SAFETY: an all-zero `rusage` is a valid value of this plain C struct.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: `pid` is our own child, not yet reaped; the pointers are valid.
    let rc = loop {
        let rc = unsafe { libc::wait4(pid, &mut status, 0, &mut usage) };
        if rc == -1 && std::io::Error::last_os_error().kind() == std::io::ErrorKind::Interrupted {
            continue;
        }
        break rc;
    };
    let wall_seconds = start.elapsed().as_secs_f64();
    if rc != pid {
        bail!("wait4 failed for {shown}: {}", std::io::Error::last_os_error());
    }
    let read = |mut f: std::fs::File| -> Result<String> {
        use std::io::{Read, Seek};
        f.rewind()?;
        let mut s = String::new();
        f.read_to_string(&mut s)?;
        Ok(s)
    };
    let stdout = read(out_file)?;
    let stderr = read(err_file)?;
    let ok = libc::WIFEXITED(status) && libc::WEXITSTATUS(status) == 0;
    if !ok {
        let tail: Vec<&str> = stderr.lines().rev().take(15).collect();
        let tail: Vec<&str> = tail.into_iter().rev().collect();
        bail!("{shown} failed (status {status}):\n{}", tail.join("\n"));
    }
    let secs = |t: libc::timeval| t.tv_sec as f64 + 1e-6 * t.tv_usec as f64;
    Ok(Measured {
        wall_seconds,
        cpu_seconds: secs(usage.ru_utime) + secs(usage.ru_stime),
        // Linux reports ru_maxrss in KiB.
        peak_rss_bytes: usage.ru_maxrss as u64 * 1024,
        stdout,
        stderr,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn measures_a_child_that_allocates() {
        // python3 is not guaranteed; `head -c` into memory via `sort` is.
        let m =
            run_measured(Command::new("sh").args(["-c", "head -c 50000000 /dev/zero | sort > /dev/null"]))
                .unwrap();
        assert!(m.peak_rss_bytes > 40_000_000, "{}", m.peak_rss_bytes);
        assert!(m.wall_seconds > 0.0);
    }

    #[test]
    fn failure_is_an_error_with_stderr() {
        let e = run_measured(Command::new("sh").args(["-c", "echo boom >&2; exit 3"])).unwrap_err();
        assert!(format!("{e:#}").contains("boom"));
    }
}
