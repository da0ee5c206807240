//! CPU-time helpers shared by the linear-solve benchmark targets
//! (`benches/linear.rs`, `examples/bench_linear.rs`).
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
