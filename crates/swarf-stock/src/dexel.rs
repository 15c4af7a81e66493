//! One dexel: the sorted, disjoint solid intervals of material along one ray.

use smallvec::SmallVec;
use swarf_geom::math::{greater, lesser};

/// Intervals shorter than this (mm) left by a subtraction are dropped (counted as removed).
pub const MIN_INTERVAL_MM: f64 = 1e-9;

/// Number of intervals a dexel holds inline before it spills to the heap (once per ray, not
/// per interval).
pub const INLINE_INTERVALS: usize = 2;

pub use swarf_sweep::swept::{overlaps, Interval};

/// The intervals of one ray: sorted ascending, disjoint, each longer than
/// [`MIN_INTERVAL_MM`]. The first [`INLINE_INTERVALS`] live inline.
pub type Dexel = SmallVec<[Interval; INLINE_INTERVALS]>;

/// Total material length of a dexel.
pub fn dexel_length(d: &[Interval]) -> f64 {
    d.iter().map(Interval::len).sum()
}

/// Identifies the move that cut an interval end: the tag the stock was cutting under
/// ([`crate::TriDexel::set_move_tag`]; `simulate` tags every cut with its move's index in the
/// program), or [`UNCUT`] for an end that is still the original stock's boundary.
pub type MoveTag = u32;

/// The tag of an interval end no move has cut (the stock as built).
pub const UNCUT: MoveTag = MoveTag::MAX;

/// Provenance of one interval: the tag of the move that last cut each of its ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
pub struct EndTags {
    /// Tag of the `enter` end.
    pub enter: MoveTag,
    /// Tag of the `exit` end.
    pub exit: MoveTag,
}

impl EndTags {
    /// Both ends uncut.
    pub const UNCUT: EndTags = EndTags {
        enter: UNCUT,
        exit: UNCUT,
    };
}

/// The provenance of one dexel, interval by interval (kept beside the dexel, in step with it,
/// only by stocks that track provenance: one integer per interval end).
pub type DexelTags = SmallVec<[EndTags; INLINE_INTERVALS]>;

/// Where [`subtract_with`] keeps the provenance of the dexel it edits: `()` keeps none (and
/// compiles to nothing), a [`DexelTags`] is edited in step with the dexel.
pub(crate) trait EndStore {
    fn get(&self, i: usize) -> EndTags;
    fn set(&mut self, i: usize, e: EndTags);
    fn insert(&mut self, i: usize, e: EndTags);
    fn drain(&mut self, a: usize, b: usize);
}

impl EndStore for () {
    #[inline(always)]
    fn get(&self, _: usize) -> EndTags {
        EndTags::UNCUT
    }
    #[inline(always)]
    fn set(&mut self, _: usize, _: EndTags) {}
    #[inline(always)]
    fn insert(&mut self, _: usize, _: EndTags) {}
    #[inline(always)]
    fn drain(&mut self, _: usize, _: usize) {}
}

impl EndStore for DexelTags {
    #[inline]
    fn get(&self, i: usize) -> EndTags {
        self[i]
    }
    #[inline]
    fn set(&mut self, i: usize, e: EndTags) {
        self[i] = e;
    }
    #[inline]
    fn insert(&mut self, i: usize, e: EndTags) {
        SmallVec::insert(self, i, e);
    }
    #[inline]
    fn drain(&mut self, a: usize, b: usize) {
        SmallVec::drain(self, a..b);
    }
}

/// What a cut leaves on one side of it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Side {
    /// Nothing: the material ends inside the cut.
    Nothing,
    /// A remainder, kept.
    Keep,
    /// A sliver below [`MIN_INTERVAL_MM`], removed with the cut.
    Drop,
}

/// What becomes of a remainder `piece` of a cut.
#[inline(always)]
fn side(piece: Interval) -> Side {
    if piece.exit <= piece.enter {
        Side::Nothing
    } else if piece.len() >= MIN_INTERVAL_MM {
        Side::Keep
    } else {
        Side::Drop
    }
}

/// The remainders the cut `[lo, hi]` leaves of the material from `first` (the first interval
/// it meets) to `last` (the last): left and right, each with what becomes of it.
#[inline(always)]
fn sides(first: Interval, last: Interval, lo: f64, hi: f64) -> [(Interval, Side); 2] {
    let left = Interval {
        enter: first.enter,
        exit: lo,
    };
    let right = Interval {
        enter: hi,
        exit: last.exit,
    };
    [(left, side(left)), (right, side(right))]
}

/// Removes `[lo, hi]` from the dexel; returns the length removed.
#[inline]
pub fn subtract(d: &mut Dexel, lo: f64, hi: f64) -> f64 {
    // One interval (most rays): the same cut as `subtract_with`'s, without its bookkeeping.
    if let [iv] = d[..] {
        if hi.partial_cmp(&lo) != Some(std::cmp::Ordering::Greater)
            || iv.exit <= lo
            || iv.enter >= hi
        {
            return 0.0;
        }
        let mut removed = lesser(iv.exit, hi) - greater(iv.enter, lo);
        let [(left, l), (right, r)] = sides(iv, iv, lo, hi);
        if l == Side::Drop {
            removed += left.len();
        }
        if r == Side::Drop {
            removed += right.len();
        }
        match (matches!(l, Side::Keep), matches!(r, Side::Keep)) {
            (true, true) => {
                d[0] = left;
                d.push(right);
            }
            (true, false) => d[0] = left,
            (false, true) => d[0] = right,
            (false, false) => d.clear(),
        }
        return removed;
    }
    subtract_with(d, &mut (), lo, hi, UNCUT, |_| {})
}

/// [`subtract`], keeping the provenance `ends` in step (the new ends get `tag`) and telling
/// `removed` every piece of material it takes away (in ascending order; slivers shorter than
/// [`MIN_INTERVAL_MM`] that the cut leaves behind are removed too, and reported).
#[inline]
pub(crate) fn subtract_with<E: EndStore, F: FnMut(Interval)>(
    d: &mut Dexel,
    ends: &mut E,
    lo: f64,
    hi: f64,
    tag: MoveTag,
    mut removed_piece: F,
) -> f64 {
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
        let (a, b) = (greater(d[k].enter, lo), lesser(d[k].exit, hi));
        removed += b - a;
        removed_piece(Interval { enter: a, exit: b });
        k += 1;
    }
    let first = d[i];
    let last = d[k - 1];
    let (first_ends, last_ends) = (ends.get(i), ends.get(k - 1));
    let [(left, l), (right, r)] = sides(first, last, lo, hi);
    if l == Side::Drop {
        removed += left.len();
        removed_piece(left);
    }
    if r == Side::Drop {
        removed += right.len();
        removed_piece(right);
    }
    let (keep_left, keep_right) = (l == Side::Keep, r == Side::Keep);
    // An end the cut moved by no more than a sliver keeps the move that made it: a later
    // pass along the same wall (a retract up the tool's own cut) recomputes it a rounding
    // away, and was credited with cutting it.
    let moved = |from: f64, to: f64| (from - to).abs() > MIN_INTERVAL_MM;
    let mut w = i;
    if keep_left {
        d[w] = left;
        ends.set(
            w,
            EndTags {
                enter: first_ends.enter,
                exit: if moved(first.exit, lo) {
                    tag
                } else {
                    first_ends.exit
                },
            },
        );
        w += 1;
    }
    if keep_right {
        let right_ends = EndTags {
            enter: if moved(last.enter, hi) {
                tag
            } else {
                last_ends.enter
            },
            exit: last_ends.exit,
        };
        if w < k {
            d[w] = right;
            ends.set(w, right_ends);
        } else {
            d.insert(w, right);
            ends.insert(w, right_ends);
            return removed;
        }
        w += 1;
    }
    if w < k {
        d.drain(w..k);
        ends.drain(w, k);
    }
    removed
}

#[cfg(test)]
mod tests {
    use super::*;
    use smallvec::smallvec;

    fn iv(a: f64, b: f64) -> Interval {
        Interval { enter: a, exit: b }
    }

    /// A cut that moves an end by no more than a sliver (a retract up the wall its own move
    /// cut, recomputed a rounding away) leaves the end's tag to the move that made it; one that
    /// moves it further takes it.
    #[test]
    fn an_end_moved_by_a_rounding_keeps_its_tag() {
        let mut d: Dexel = smallvec![iv(0.0, 10.0)];
        let mut t: DexelTags = smallvec![EndTags::UNCUT];
        subtract_with(&mut d, &mut t, 5.0, 20.0, 1, |_| {});
        subtract_with(&mut d, &mut t, 5.0 - 1e-12, 20.0, 2, |_| {});
        assert_eq!(d[0].exit, 5.0 - 1e-12);
        assert_eq!(
            t[0],
            EndTags {
                enter: UNCUT,
                exit: 1
            }
        );
        subtract_with(&mut d, &mut t, -5.0, 1e-12, 3, |_| {});
        assert_eq!(
            t[0],
            EndTags {
                enter: UNCUT,
                exit: 1
            }
        );
        subtract_with(&mut d, &mut t, 4.0, 20.0, 4, |_| {});
        assert_eq!(
            t[0],
            EndTags {
                enter: UNCUT,
                exit: 4
            }
        );
    }

    /// The one-interval shortcut of `subtract` cuts exactly as the general `subtract_with`:
    /// every placement of the cut against the interval, slivers on either side included.
    #[test]
    fn one_interval_shortcut_matches_the_general_cut() {
        let m = MIN_INTERVAL_MM;
        let marks = [
            -1.0,
            0.0,
            0.5 * m,
            m,
            2.0 * m,
            0.3,
            1.0 - 2.0 * m,
            1.0 - m,
            1.0 - 0.5 * m,
            1.0,
            2.0,
        ];
        for &lo in &marks {
            for &hi in &marks {
                let mut fast: Dexel = smallvec::smallvec![iv(0.0, 1.0)];
                let mut general = fast.clone();
                let a = subtract(&mut fast, lo, hi);
                let b = subtract_with(&mut general, &mut (), lo, hi, UNCUT, |_| {});
                assert_eq!(
                    (a, fast.as_slice()),
                    (b, general.as_slice()),
                    "cut [{lo}, {hi}]"
                );
            }
        }
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

    /// Applies the cut to a dexel with provenance and to one without; checks they agree and
    /// that the reported pieces add up to the removed length.
    fn cut_tracked(d: &mut Dexel, t: &mut DexelTags, lo: f64, hi: f64, tag: MoveTag) -> f64 {
        let mut plain = d.clone();
        let want = subtract(&mut plain, lo, hi);
        let mut pieces = Vec::new();
        let got = subtract_with(d, t, lo, hi, tag, |iv| pieces.push(iv));
        assert_eq!(got, want);
        assert_eq!(*d, plain);
        assert_eq!(d.len(), t.len());
        let sum: f64 = pieces.iter().map(Interval::len).sum();
        assert!((sum - got).abs() < 1e-12, "{sum} {got}");
        assert!(pieces.windows(2).all(|w| w[0].exit <= w[1].enter));
        got
    }

    #[test]
    fn provenance_follows_the_cuts() {
        let e = |a, b| EndTags { enter: a, exit: b };
        let mut d: Dexel = smallvec![iv(0.0, 10.0)];
        let mut t: DexelTags = smallvec![EndTags::UNCUT];
        cut_tracked(&mut d, &mut t, 2.0, 3.0, 7);
        assert_eq!(t.as_slice(), &[e(UNCUT, 7), e(7, UNCUT)]);
        cut_tracked(&mut d, &mut t, 8.0, 12.0, 8);
        assert_eq!(t.as_slice(), &[e(UNCUT, 7), e(7, 8)]);
        cut_tracked(&mut d, &mut t, 5.0, 6.0, 9);
        assert_eq!(d.as_slice(), &[iv(0.0, 2.0), iv(3.0, 5.0), iv(6.0, 8.0)]);
        assert_eq!(t.as_slice(), &[e(UNCUT, 7), e(7, 9), e(9, 8)]);
        // One cut across two intervals joins their outer ends.
        cut_tracked(&mut d, &mut t, 1.0, 4.0, 10);
        assert_eq!(d.as_slice(), &[iv(0.0, 1.0), iv(4.0, 5.0), iv(6.0, 8.0)]);
        assert_eq!(t.as_slice(), &[e(UNCUT, 10), e(10, 9), e(9, 8)]);
        // A cut between intervals changes nothing; a cut of everything leaves nothing.
        assert_eq!(cut_tracked(&mut d, &mut t, 5.5, 5.8, 11), 0.0);
        assert_eq!(t.len(), 3);
        cut_tracked(&mut d, &mut t, -1.0, 100.0, 12);
        assert!(d.is_empty() && t.is_empty());
    }
}
