//! What the machine a benchmark runs on gives it right now, measured in about half a second:
//! the latency of a read that misses every cache, and the time of one dependent `f64`
//! multiply-add. The benchmarks print both beside their figures, because the shared machines
//! they run on change from hour to hour: on 2026-11-28 the same binary ran 2–3× slower than on
//! 2026-11-25 while the arithmetic ran at full speed (2.05 ns per multiply-add, a 3 GHz core's
//! six cycles) and a read from memory took 235–286 ns (an idle server of this kind takes roughly 80–130 ns). A run of
//! the stock's benchmarks at scale waits on memory, so its time says little unless the memory
//! figure says the machine was quiet.

use std::hint::black_box;
use std::time::Instant;

/// The two figures of [`probe`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HostProbe {
    /// Nanoseconds per read of a chain of dependent reads at random places in 64 MiB (larger
    /// than the last-level cache of the machines this runs on).
    pub memory_latency_ns: f64,
    /// Nanoseconds per step of a chain of dependent `f64` multiply-adds.
    pub fma_chain_ns: f64,
}

impl std::fmt::Display for HostProbe {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "host: memory latency {:.0} ns (dependent reads over 64 MiB), {:.2} ns per \
             dependent f64 multiply-add",
            self.memory_latency_ns, self.fma_chain_ns
        )
    }
}

/// [`probe`], unless the environment sets `SWARF_BENCH_NO_PROBE` (to count a benchmark's
/// instructions under `valgrind`, where the probe would add its own and take minutes).
pub fn probe_unless_asked_not_to() -> Option<HostProbe> {
    std::env::var_os("SWARF_BENCH_NO_PROBE")
        .is_none()
        .then(probe)
}

/// Measures the machine now (about half a second, 64 MiB).
pub fn probe() -> HostProbe {
    const SLOTS: usize = 8 << 20;
    const READS: usize = 2_000_000;
    const STEPS: usize = 100_000_000;
    let next = one_cycle(SLOTS);
    let mut at = 0u32;
    let start = Instant::now();
    for _ in 0..READS {
        at = next[at as usize];
    }
    let memory = start.elapsed().as_secs_f64();
    black_box(at);
    let mut x = black_box(1.0_f64);
    let (m, a) = (black_box(1.000_000_1), black_box(1e-9));
    let start = Instant::now();
    for _ in 0..STEPS {
        x = x * m + a;
    }
    let fma = start.elapsed().as_secs_f64();
    black_box(x);
    HostProbe {
        memory_latency_ns: memory * 1e9 / READS as f64,
        fma_chain_ns: fma * 1e9 / STEPS as f64,
    }
}

/// `next[i]` for one cycle through all `n` slots in a random order (Sattolo's shuffle, a fixed
/// seed): following it from any slot visits every slot once before coming back, so no read
/// can start before the previous one has returned and no prefetcher can guess the next.
fn one_cycle(n: usize) -> Vec<u32> {
    let mut next: Vec<u32> = (0..n as u32).collect();
    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    for i in (1..n).rev() {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        let j = ((state >> 33) % i as u64) as usize;
        next.swap(i, j);
    }
    next
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The chain the memory figure follows is one cycle through every slot (a shorter cycle
    /// would stay in the cache and measure the cache).
    #[test]
    fn the_read_chain_visits_every_slot_once() {
        for n in [2, 3, 10, 1000, 65_536] {
            let next = one_cycle(n);
            let mut seen = vec![false; n];
            let mut at = 0usize;
            for _ in 0..n {
                assert!(!seen[at], "slot {at} of {n} visited twice");
                seen[at] = true;
                at = next[at] as usize;
            }
            assert_eq!(at, 0, "the chain of {n} slots does not close");
        }
    }
}
