//! Progress reports and cancellation of long computations: one [`Observer`] type for every
//! crate.
//!
//! A long computation (a simulation, a program check, a tool-size map, a verification, an
//! engagement walk) takes `&dyn Observer` and calls [`Observer::progress`] with how much of
//! its work is done and how much there is, in the computation's own unit (moves, CC points,
//! ray rows: each documents which). The observer answers [`ControlFlow::Continue`] to go on or
//! [`ControlFlow::Break`] to stop: the computation then ends early, at the next point where it
//! can stop cleanly, with its "cancelled" result (an error variant that carries how much was
//! done, or [`Cancelled`] itself), never with a partial answer that looks whole.
//!
//! An observer may be called from several threads at once (parallel computations report as
//! their pieces finish), hence `Sync`; `done` need not grow monotonically across threads.
//! [`Quiet`] observes nothing and never stops; any `Fn(u64, u64) -> ControlFlow<()> + Sync`
//! closure is an observer.
//!
//! ```
//! use std::ops::ControlFlow;
//! use std::sync::atomic::{AtomicU64, Ordering};
//! use swarf_geom::progress::{Observer, Quiet};
//!
//! /// A computation over `n` items that reports after each and may be stopped.
//! fn count(n: u64, observer: &dyn Observer) -> Result<u64, u64> {
//!     for i in 1..=n {
//!         if observer.progress(i, n).is_break() {
//!             return Err(i);
//!         }
//!     }
//!     Ok(n)
//! }
//! assert_eq!(count(10, &Quiet), Ok(10));
//! let calls = AtomicU64::new(0);
//! let stop_at_3 = |done: u64, _total: u64| {
//!     calls.fetch_add(1, Ordering::Relaxed);
//!     if done >= 3 { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
//! };
//! assert_eq!(count(10, &stop_at_3), Err(3));
//! assert_eq!(calls.load(Ordering::Relaxed), 3);
//! ```

use std::fmt;
use std::ops::ControlFlow;

/// Watches a long computation: told how far it has got, and may ask it to stop.
pub trait Observer: Sync {
    /// `done` of `total` units of work are finished. [`ControlFlow::Break`] asks the
    /// computation to stop (it ends with its cancelled result); [`ControlFlow::Continue`] lets
    /// it go on.
    fn progress(&self, done: u64, total: u64) -> ControlFlow<()>;
}

/// The observer that watches nothing and never stops a computation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Quiet;

impl Observer for Quiet {
    fn progress(&self, _done: u64, _total: u64) -> ControlFlow<()> {
        ControlFlow::Continue(())
    }
}

impl<F> Observer for F
where
    F: Fn(u64, u64) -> ControlFlow<()> + Sync,
{
    fn progress(&self, done: u64, total: u64) -> ControlFlow<()> {
        self(done, total)
    }
}

/// A computation stopped by its [`Observer`] after `done` of `total` units of work: whatever it
/// computed so far is dropped (or left as documented by the computation, e.g. a stock cut by
/// the finished moves), and no result is returned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Cancelled {
    /// Units of work finished when it stopped.
    pub done: u64,
    /// Units of work in all.
    pub total: u64,
}

impl fmt::Display for Cancelled {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "stopped after {} of {}", self.done, self.total)
    }
}

impl std::error::Error for Cancelled {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quiet_never_stops_and_closures_are_observers() {
        assert!(Quiet.progress(0, 0).is_continue());
        let stop = |d: u64, t: u64| {
            if d == t {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        };
        let o: &dyn Observer = &stop;
        assert!(o.progress(1, 2).is_continue());
        assert!(o.progress(2, 2).is_break());
        assert_eq!(
            Cancelled { done: 3, total: 7 }.to_string(),
            "stopped after 3 of 7"
        );
    }
}
