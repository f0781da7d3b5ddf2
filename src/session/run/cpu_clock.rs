//! The CPU time a run spends, for its summary's "s CPU": the calling thread's own CPU
//! clock where the platform gives one (Linux), so that other processes and threads do
//! not inflate it (a study runs several simulations at once); a wall clock elsewhere.

/// A clock started at a run's beginning.
pub(super) struct CpuClock {
    start: f64,
}

impl CpuClock {
    /// Started now.
    pub(super) fn start() -> CpuClock {
        CpuClock { start: now() }
    }

    /// Seconds since [`CpuClock::start`].
    pub(super) fn seconds(&self) -> f64 {
        (now() - self.start).max(0.0)
    }
}

/// The calling thread's CPU time in seconds.
#[cfg(all(target_os = "linux", target_arch = "x86_64"))]
fn now() -> f64 {
    let mut t = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `t` is a valid timespec the call writes; the clock id is a constant.
    if unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut t) } == 0 {
        t.tv_sec as f64 + 1e-9 * t.tv_nsec as f64
    } else {
        wall()
    }
}

#[cfg(not(all(target_os = "linux", target_arch = "x86_64")))]
fn now() -> f64 {
    wall()
}

/// Seconds of a monotonic wall clock since its first call.
fn wall() -> f64 {
    use std::sync::OnceLock;
    use std::time::Instant;
    static ORIGIN: OnceLock<Instant> = OnceLock::new();
    ORIGIN.get_or_init(Instant::now).elapsed().as_secs_f64()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_busy_thread_counts_its_cpu_and_a_sleeping_one_does_not() {
        let clock = CpuClock::start();
        std::thread::sleep(std::time::Duration::from_millis(50));
        let slept = clock.seconds();
        let mut x = 0u64;
        let busy = std::time::Instant::now();
        while busy.elapsed().as_millis() < 50 {
            x = std::hint::black_box(x.wrapping_add(1));
        }
        let worked = clock.seconds() - slept;
        if cfg!(all(target_os = "linux", target_arch = "x86_64")) {
            assert!(slept < 0.02, "{slept}");
        }
        assert!(worked > 0.005, "{worked}");
    }
}
