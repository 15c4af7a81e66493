//! A family's dexel query with its kernel chosen once.
//!
//! The kind of kernel that answers a family's rays (closed form along or across the tool axis,
//! an instance, a tilted axis, the general candidates) is decided by
//! [`SweptConvex::dexel_rays`]. A caller that queries many rays of one family — the stock's
//! loop over a tile — hands its loop to [`SweptConvex::with_kernel`] as a [`KernelTask`]: the
//! kind is matched once, and the loop is compiled once per kernel, with the kernel's query
//! inlined into it (matching it at every ray cost about 30 instructions a ray and kept the
//! query out of line). [`SweptConvex::dexel_cut`], for callers that query one ray, runs the
//! same kernels through the same dispatch.

use super::fast::{AcrossRays, AlongRays};
use super::instance::InstanceRays;
use super::tilted::TiltedRays;
use super::{DirConsts, Interval, Scratch, SweptConvex};

/// The stock update's query for one family's rays, its kernel resolved: for the dexel `d` of
/// the ray through cross coordinates `(cu, cv)`, whether an exact query ran and the interval
/// to remove (as [`SweptConvex::dexel_cut`]). Implemented by this crate's kernels only (it is
/// sealed): other crates name it to write a [`KernelTask`].
pub trait DexelKernel: sealed::Sealed {
    /// The query of the ray through `(cu, cv)` whose material is `d`.
    fn cut(
        &self,
        cu: f64,
        cv: f64,
        d: &[Interval],
        scratch: &mut Scratch,
    ) -> (bool, Option<(f64, f64)>);
}

/// Work over one family's rays, run by [`SweptConvex::with_kernel`] with that family's kernel.
pub trait KernelTask {
    /// What the work returns.
    type Output;
    /// Runs the work with `kernel` answering the family's rays.
    fn run<K: DexelKernel>(self, kernel: &K) -> Self::Output;
}

mod sealed {
    /// Only this crate's kernels are [`super::DexelKernel`]s.
    pub trait Sealed {}
    impl Sealed for super::AlongRays {}
    impl Sealed for super::AcrossRays {}
    impl Sealed for super::InstanceRays {}
    impl Sealed for super::TiltedRays {}
    impl Sealed for super::General<'_, '_> {}
}

/// The material's first and last ends, `None` for an empty dexel.
#[inline(always)]
fn ends(d: &[Interval]) -> Option<(f64, f64)> {
    match (d.first(), d.last()) {
        (Some(f), Some(l)) => Some((f.enter, l.exit)),
        _ => None,
    }
}

impl DexelKernel for AlongRays {
    #[inline(always)]
    fn cut(&self, cu: f64, cv: f64, d: &[Interval], _: &mut Scratch) -> (bool, Option<(f64, f64)>) {
        match ends(d) {
            Some(m) => (true, self.interval(cu, cv, Some(m))),
            None => (false, None),
        }
    }
}

impl DexelKernel for AcrossRays {
    #[inline(always)]
    fn cut(&self, cu: f64, cv: f64, d: &[Interval], _: &mut Scratch) -> (bool, Option<(f64, f64)>) {
        match ends(d) {
            Some(_) => (true, self.interval(cu, cv)),
            None => (false, None),
        }
    }
}

impl DexelKernel for InstanceRays {
    #[inline(always)]
    fn cut(&self, cu: f64, cv: f64, d: &[Interval], _: &mut Scratch) -> (bool, Option<(f64, f64)>) {
        InstanceRays::cut(self, cu, cv, d)
    }
}

impl DexelKernel for TiltedRays {
    #[inline(always)]
    fn cut(&self, cu: f64, cv: f64, d: &[Interval], _: &mut Scratch) -> (bool, Option<(f64, f64)>) {
        match ends(d) {
            Some(m) => TiltedRays::cut(self, cu, cv, m),
            None => (false, None),
        }
    }
}

/// The general candidates (no closed form): the material-first range test, a separating
/// plane, then the candidates pruned to the material (`SweptConvex::general_cut`).
pub(crate) struct General<'s, 'a> {
    pub(crate) sweep: &'s SweptConvex<'a>,
    pub(crate) k: usize,
    pub(crate) dc: &'s DirConsts,
    pub(crate) owner: u64,
}

impl DexelKernel for General<'_, '_> {
    #[inline]
    fn cut(
        &self,
        cu: f64,
        cv: f64,
        d: &[Interval],
        scratch: &mut Scratch,
    ) -> (bool, Option<(f64, f64)>) {
        self.sweep
            .general_cut((cu, cv), self.k, d, self.dc, self.owner, scratch)
    }
}
