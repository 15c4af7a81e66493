//! Running a sequence of short parallel sections without paying for the pool's sleep.
//!
//! A cut of one move, or one location of the engagement, is a few parallel sections of a
//! fraction of a millisecond each, with a little serial work between them. Between sections
//! rayon's idle workers go to sleep within microseconds, and each section then waits for a
//! worker to be woken (≈ 25–30 µs on the 2-core machines measured here, against ≈ 0.5 ms for
//! a 5-axis move's cut on two threads). [`hot`] keeps the other workers awake for the length of a computation: each
//! runs pending work of the pool (rayon's `yield_now`) or spins until the computation ends,
//! now and then yielding its core to any other thread the system has to run. They burn CPU
//! while the computation is serial, and the wall time falls.

use std::sync::atomic::{AtomicBool, Ordering};

/// Idle turns of a kept-awake worker between two yields of its core to the system (a turn
/// looks at the pool's queues once: well under a microsecond).
const YIELD_EVERY: u32 = 64;

/// Runs `f` on one of rayon's workers while the pool's other workers stay awake, taking the
/// parallel work `f` makes (or any other of the pool's) as soon as it is there; returns what
/// `f` returns. With one thread, `f` runs on the pool's worker, where its parallel sections
/// run inline (from another thread each would be handed to the worker and waited for: the
/// engagement took 1.24–1.31 s instead of 0.97 s at 1,000 locations).
///
/// No deadlock: a worker kept awake only waits for `f` to end, and runs every job it finds
/// meanwhile; `f` never waits for it. A keeper that the worker running `f` takes for itself
/// (while it waits inside a parallel section) returns at once.
pub fn hot<R: Send>(f: impl FnOnce() -> R + Send) -> R {
    let keepers = rayon::current_num_threads().saturating_sub(1);
    if keepers == 0 {
        return rayon::scope(|_| f());
    }
    let done = AtomicBool::new(false);
    rayon::scope(|s| {
        let runner = rayon::current_thread_index();
        for _ in 0..keepers {
            let done = &done;
            s.spawn(move |_| {
                if rayon::current_thread_index() == runner {
                    return;
                }
                let mut idle = 0u32;
                while !done.load(Ordering::Acquire) {
                    if rayon::yield_now() == Some(rayon::Yield::Executed) {
                        idle = 0;
                    } else {
                        idle = idle.wrapping_add(1);
                        // Now and then let the system run another thread on this core (a
                        // test harness's, say): the spinning must not slow what runs beside.
                        if idle % YIELD_EVERY == 0 {
                            std::thread::yield_now();
                        } else {
                            std::hint::spin_loop();
                        }
                    }
                }
            });
        }
        // Set when `f` ends, returning or panicking: a panic unwinding past keepers that still
        // spun would never let the scope end (the process hung instead of failing).
        let _done = Done(&done);
        f()
    })
}

/// Tells the kept-awake workers that the computation ended, when dropped.
struct Done<'a>(&'a AtomicBool);

impl Drop for Done<'_> {
    fn drop(&mut self) {
        self.0.store(true, Ordering::Release);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rayon::prelude::*;

    #[test]
    fn hot_returns_what_f_returns_and_runs_its_sections() {
        for threads in [1, 2, 3] {
            let sums = swarf_testdata::on_threads(threads, || {
                hot(|| {
                    (0..200u64)
                        .map(|k| (0..1000u64).into_par_iter().map(|i| i * k).sum::<u64>())
                        .collect::<Vec<_>>()
                })
            });
            let expect: Vec<u64> = (0..200u64).map(|k| k * 999 * 1000 / 2).collect();
            assert_eq!(sums, expect, "{threads} threads");
        }
    }

    #[test]
    fn hot_runs_f_on_a_worker_of_the_pool() {
        // Called from outside the pool, as the command line calls it (the global pool; the
        // test `one_thread_pool.rs` does the same with a pool of one thread).
        let on_worker = std::thread::spawn(|| hot(|| rayon::current_thread_index().is_some()));
        assert!(on_worker.join().unwrap());
    }

    #[test]
    fn a_panic_in_f_ends_the_call_with_the_panic() {
        // The keepers must stop when `f` unwinds: the call then fails instead of hanging.
        let r = swarf_testdata::on_threads(2, || {
            std::panic::catch_unwind(|| hot(|| -> u32 { panic!("in f") }))
        });
        assert!(r.is_err());
    }

    #[test]
    fn nested_and_concurrent_hot_calls_end() {
        // Several callers at once, each nesting a second: every keeper ends with its own
        // computation, whichever worker took it.
        let total: u64 = swarf_testdata::on_threads(2, || {
            (0..8u64)
                .into_par_iter()
                .map(|k| hot(|| hot(|| (0..500u64).into_par_iter().map(|i| i + k).sum::<u64>())))
                .sum()
        });
        let expect: u64 = (0..8u64).map(|k| 499 * 500 / 2 + 500 * k).sum();
        assert_eq!(total, expect);
    }
}
