//! One dexel: the sorted, disjoint solid intervals of material along one ray.

use smallvec::SmallVec;

/// Intervals shorter than this (mm) left by a subtraction are dropped (counted as removed).
pub const MIN_INTERVAL_MM: f64 = 1e-9;

/// Number of intervals a dexel holds inline before it spills to the heap (once per ray, not
/// per interval).
pub const INLINE_INTERVALS: usize = 2;

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

/// The intervals of one ray: sorted ascending, disjoint, each longer than
/// [`MIN_INTERVAL_MM`]. The first [`INLINE_INTERVALS`] live inline.
pub type Dexel = SmallVec<[Interval; INLINE_INTERVALS]>;

/// Total material length of a dexel.
pub fn dexel_length(d: &[Interval]) -> f64 {
    d.iter().map(Interval::len).sum()
}

/// Removes `[lo, hi]` from the dexel; returns the length removed.
pub fn subtract(d: &mut Dexel, lo: f64, hi: f64) -> f64 {
    if hi.partial_cmp(&lo) != Some(std::cmp::Ordering::Greater) {
        return 0.0;
    }
    let n = d.len();
    let mut i = 0;
    while i < n && d[i].exit <= lo {
        i += 1;
    }
    if i == n || d[i].enter >= hi {
        return 0.0;
    }
    let mut k = i;
    let mut removed = 0.0;
    while k < n && d[k].enter < hi {
        removed += d[k].exit.min(hi) - d[k].enter.max(lo);
        k += 1;
    }
    let first = d[i];
    let last = d[k - 1];
    let left = Interval {
        enter: first.enter,
        exit: lo,
    };
    let right = Interval {
        enter: hi,
        exit: last.exit,
    };
    let keep_left = first.enter < lo;
    let keep_right = last.exit > hi;
    // Slivers below MIN_INTERVAL_MM are dropped and counted as removed.
    let keep_left = keep_left && left.len() >= MIN_INTERVAL_MM;
    let keep_right = keep_right && right.len() >= MIN_INTERVAL_MM;
    if first.enter < lo && !keep_left {
        removed += left.len();
    }
    if last.exit > hi && !keep_right {
        removed += right.len();
    }
    let mut w = i;
    if keep_left {
        d[w] = left;
        w += 1;
    }
    if keep_right {
        if w < k {
            d[w] = right;
        } else {
            d.insert(w, right);
            return removed;
        }
        w += 1;
    }
    if w < k {
        d.drain(w..k);
    }
    removed
}

/// True when some interval of `d` overlaps the open range `(lo, hi)`.
#[inline]
pub fn overlaps(d: &[Interval], lo: f64, hi: f64) -> bool {
    d.iter().any(|iv| iv.enter < hi && iv.exit > lo)
}

#[cfg(test)]
mod tests {
    use super::*;
    use smallvec::smallvec;

    fn iv(a: f64, b: f64) -> Interval {
        Interval { enter: a, exit: b }
    }

    #[test]
    fn subtract_cases() {
        let mut d: Dexel = smallvec![iv(0.0, 10.0)];
        assert_eq!(subtract(&mut d, 2.0, 3.0), 1.0);
        assert_eq!(d.as_slice(), &[iv(0.0, 2.0), iv(3.0, 10.0)]);
        assert_eq!(subtract(&mut d, 1.0, 4.0), 2.0);
        assert_eq!(d.as_slice(), &[iv(0.0, 1.0), iv(4.0, 10.0)]);
        assert_eq!(subtract(&mut d, -5.0, 0.5), 0.5);
        assert_eq!(d.as_slice(), &[iv(0.5, 1.0), iv(4.0, 10.0)]);
        assert_eq!(subtract(&mut d, 9.0, 20.0), 1.0);
        assert_eq!(d.as_slice(), &[iv(0.5, 1.0), iv(4.0, 9.0)]);
        // Three intervals: spills once.
        assert_eq!(subtract(&mut d, 5.0, 6.0), 1.0);
        assert_eq!(d.as_slice(), &[iv(0.5, 1.0), iv(4.0, 5.0), iv(6.0, 9.0)]);
        assert_eq!(subtract(&mut d, 0.0, 100.0), 4.5);
        assert!(d.is_empty());
        assert_eq!(subtract(&mut d, 0.0, 100.0), 0.0);
    }

    #[test]
    fn subtract_between_and_sliver() {
        let mut d: Dexel = smallvec![iv(0.0, 1.0), iv(2.0, 3.0)];
        assert_eq!(subtract(&mut d, 1.2, 1.8), 0.0);
        assert_eq!(d.len(), 2);
        let r = subtract(&mut d, 0.0, 1.0 - 1e-12);
        assert!((r - 1.0).abs() < 1e-15, "{r}");
        assert_eq!(d.as_slice(), &[iv(2.0, 3.0)]);
        assert!(overlaps(&d, 2.5, 2.6) && !overlaps(&d, 3.0, 4.0));
    }
}
