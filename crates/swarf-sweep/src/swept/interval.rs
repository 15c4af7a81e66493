//! The interval a sweep removes from a ray, and the material intervals it is tested against.

/// A closed interval `[enter, exit]` of material along a ray, in the ray's coordinate (the
/// workpiece coordinate along the ray's axis), mm.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Interval {
    /// Where the ray enters the material.
    pub enter: f64,
    /// Where it leaves (`> enter`).
    pub exit: f64,
}

impl Interval {
    /// Length, mm.
    pub fn len(&self) -> f64 {
        self.exit - self.enter
    }

    /// True when empty (never for a stored interval).
    pub fn is_empty(&self) -> bool {
        self.exit <= self.enter
    }
}

/// True when some interval of `d` overlaps the open range `(lo, hi)`.
#[inline]
pub fn overlaps(d: &[Interval], lo: f64, hi: f64) -> bool {
    d.iter().any(|iv| iv.enter < hi && iv.exit > lo)
}
