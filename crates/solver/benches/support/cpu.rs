//! CPU-time and memory helpers shared by the benchmark targets
//! (`benches/linear.rs`, `examples/bench_linear.rs`,
//! `examples/bench_nonlinear.rs`).
#![allow(dead_code)]

#[repr(C)]
struct Timespec {
    tv_sec: i64,
    tv_nsec: i64,
}

extern "C" {
    fn clock_gettime(clock: i32, tp: *mut Timespec) -> i32;
}

/// CPU time of all threads of this process so far, in seconds
/// (`CLOCK_PROCESS_CPUTIME_ID`): unlike the wall time, it does not grow
/// while other processes hold the CPUs.
pub fn cpu_seconds() -> f64 {
    const CLOCK_PROCESS_CPUTIME_ID: i32 = 2;
    let mut t = Timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `t` is a valid `struct timespec` (x86_64 / aarch64 Linux layout).
    let rc = unsafe { clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &mut t) };
    if rc == 0 {
        t.tv_sec as f64 + 1e-9 * t.tv_nsec as f64
    } else {
        f64::NAN
    }
}

/// CPU time the whole machine has spent busy so far (all CPUs, all
/// processes; `/proc/stat`, 1/100 s ticks), in seconds.
pub fn machine_busy_seconds() -> f64 {
    std::fs::read_to_string("/proc/stat")
        .ok()
        .and_then(|s| {
            let f: Vec<f64> = s
                .lines()
                .next()?
                .split_whitespace()
                .skip(1)
                .map(|v| v.parse().unwrap_or(0.0))
                .collect();
            // user nice system idle iowait irq softirq steal
            let busy = f.iter().take(8).sum::<f64>() - f.get(3)? - f.get(4)?;
            Some(busy / 100.0)
        })
        .unwrap_or(f64::NAN)
}

/// A `kB` field of `/proc/self/status` or `/proc/meminfo`, in MiB.
fn proc_kb_field(file: &str, field: &str) -> f64 {
    std::fs::read_to_string(file)
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with(field))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|kb| kb.parse::<f64>().ok())
        })
        .map_or(f64::NAN, |kb| kb / 1024.0)
}

/// Peak resident set size of this process so far (`VmHWM`), in MiB.
pub fn peak_rss_mb() -> f64 {
    proc_kb_field("/proc/self/status", "VmHWM:")
}

/// Resident set size of this process now (`VmRSS`), in MiB.
pub fn rss_mb() -> f64 {
    proc_kb_field("/proc/self/status", "VmRSS:")
}

/// Memory the kernel estimates is available to a new allocation without
/// swapping (`MemAvailable` of `/proc/meminfo`), in MiB.
pub fn mem_available_mb() -> f64 {
    proc_kb_field("/proc/meminfo", "MemAvailable:")
}

/// Average number of CPUs other processes kept busy since
/// `(machine_busy_seconds(), cpu_seconds(), Instant::now())` were read.
pub fn others_cpus(since: (f64, f64, std::time::Instant)) -> f64 {
    let (busy0, cpu0, t0) = since;
    ((machine_busy_seconds() - busy0) - (cpu_seconds() - cpu0)).max(0.0)
        / t0.elapsed().as_secs_f64().max(1e-9)
}
