//! Leftovers of killed runs: the temporary folders a run makes carry its
//! process id (`.without_joints-PID-*` and `.NAME.partial-PID` beside the
//! output, `axijoint-PID-*` in the system's temporary folder), and a run
//! removes those of processes that are gone before it writes its own.

use std::path::Path;

/// The prefix of the comparison's folder beside the output.
pub const WITHOUT_JOINTS_PREFIX: &str = ".without_joints-";
/// The prefix of a run's folders in the system's temporary folder.
pub const TEMP_PREFIX: &str = "axijoint-";

/// `prefix PID -` for this process (a `tempfile` prefix).
pub fn tagged(prefix: &str) -> String {
    format!("{prefix}{}-", std::process::id())
}

/// A temporary folder in the system's, tagged with this process id.
pub fn tempdir() -> std::io::Result<tempfile::TempDir> {
    tempfile::Builder::new().prefix(&tagged(TEMP_PREFIX)).tempdir()
}

/// Whether process `pid` is alive (or cannot be told: then it counts as
/// alive and its folders stay).
fn alive(pid: u32) -> bool {
    if pid == 0 || pid > i32::MAX as u32 {
        return true;
    }
    // SAFETY: kill with signal 0 only checks that the process exists.
    let r = unsafe { libc::kill(pid as libc::pid_t, 0) };
    r == 0 || std::io::Error::last_os_error().raw_os_error() != Some(libc::ESRCH)
}

/// The process id a leftover's name carries, if it is one of ours: `.without_joints-PID-*`,
/// `.NAME.partial-PID` or (in the temporary folder) `axijoint-PID-*`.
fn owner(name: &str, in_temp: bool) -> Option<u32> {
    // Digits then '-': a random tempfile suffix (letters, digits, no '-')
    // is never read as a process id.
    let digits = |s: &str| -> Option<u32> {
        let end = s.find(|c: char| !c.is_ascii_digit())?;
        if !s[end..].starts_with('-') {
            return None;
        }
        s[..end].parse().ok()
    };
    if in_temp {
        return name.strip_prefix(TEMP_PREFIX).and_then(digits);
    }
    if let Some(rest) = name.strip_prefix(WITHOUT_JOINTS_PREFIX) {
        return digits(rest);
    }
    let (_, pid) = name.strip_prefix('.')?.rsplit_once(".partial-")?;
    pid.parse().ok()
}

/// Removes the leftovers of dead processes in `dir` (beside an output, or
/// the temporary folder when `in_temp`); what cannot be removed stays.
fn clean(dir: &Path, in_temp: bool) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(pid) = name.to_str().and_then(|n| owner(n, in_temp)) else {
            continue;
        };
        if !alive(pid) && entry.file_type().is_ok_and(|t| t.is_dir()) {
            let _ = std::fs::remove_dir_all(entry.path());
        }
    }
}

/// Removes the leftovers of dead runs beside `output` and in the
/// temporary folder.
pub fn clean_for(output: &Path) {
    let parent = match output.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    clean(parent, false);
    clean(&std::env::temp_dir(), true);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_our_names_carry_an_owner() {
        assert_eq!(owner(".without_joints-123-abc", false), Some(123));
        assert_eq!(owner(".out.partial-77", false), Some(77));
        assert_eq!(owner(".my.folder.partial-9", false), Some(9));
        assert_eq!(owner("axijoint-55-x1", true), Some(55));
        assert_eq!(owner("axijoint-sweep-x1", true), None);
        // Python's and tempfile's own random names: no '-' after digits.
        assert_eq!(owner("axijoint-12345678", true), None);
        assert_eq!(owner("axijoint-99x1abc", true), None);
        assert_eq!(owner(".without_joints12ab", false), None);
        assert_eq!(owner("out", false), None);
        assert_eq!(owner(".without_joints", false), None);
        assert_eq!(owner("results.partial-3", false), None);
        assert_eq!(owner("axijoint-55-x1", false), None);
    }

    #[test]
    fn leftovers_of_dead_processes_go_and_live_ones_stay() {
        let dir = tempfile::tempdir().unwrap();
        // A process id above the kernel's largest is never alive.
        let dead = 4_194_305 + 7;
        let mine = std::process::id();
        for name in [
            format!(".without_joints-{dead}-a"),
            format!(".out.partial-{dead}"),
            format!(".without_joints-{mine}-b"),
            format!(".out.partial-{mine}"),
            "out".to_string(),
            format!("keep.partial-{dead}"),
        ] {
            std::fs::create_dir(dir.path().join(name)).unwrap();
        }
        clean(dir.path(), false);
        let mut left: Vec<String> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        left.sort();
        let mut expected = vec![
            format!(".out.partial-{mine}"),
            format!(".without_joints-{mine}-b"),
            format!("keep.partial-{dead}"),
            "out".to_string(),
        ];
        expected.sort();
        assert_eq!(left, expected);
    }
}
