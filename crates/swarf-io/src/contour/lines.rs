//! The spans of every lattice line of the three families, copied once from the grid into flat
//! arrays (offsets + spans), clipped to the lattice domain, sorted and merged; and the queries
//! the extraction asks of a line.

use super::{HermiteGrid, Lattice, Span};
use rayon::prelude::*;

/// The lines of one family (axis `a`), indexed `u + nu · v`.
pub(crate) struct Family {
    nu: usize,
    nv: usize,
    offsets: Vec<usize>,
    spans: Vec<Span>,
}

impl Family {
    /// Spans of line `(u, v)`; lines outside the lattice are empty.
    #[inline]
    pub(crate) fn get(&self, u: isize, v: isize) -> &[Span] {
        if u < 0 || v < 0 || u as usize >= self.nu || v as usize >= self.nv {
            return &[];
        }
        let l = u as usize + self.nu * v as usize;
        &self.spans[self.offsets[l]..self.offsets[l + 1]]
    }
}

/// All three families plus the lattice and its domain.
pub(crate) struct Store {
    pub(crate) lattice: Lattice,
    pub(crate) fam: [Family; 3],
    /// Domain bounds per axis.
    pub(crate) lo: [f64; 3],
    pub(crate) hi: [f64; 3],
}

/// Drops non-finite or reversed spans, clips to `[lo, hi]`, sorts and merges overlapping or
/// touching spans.
fn sanitize(buf: &mut Vec<Span>, lo: f64, hi: f64) {
    buf.retain_mut(|s| {
        if !(s.enter.is_finite() && s.exit.is_finite()) {
            return false;
        }
        s.enter = s.enter.max(lo);
        s.exit = s.exit.min(hi);
        s.exit > s.enter
    });
    if buf.windows(2).any(|w| w[1].enter <= w[0].exit) {
        buf.sort_by(|a, b| a.enter.total_cmp(&b.enter));
        let mut out: Vec<Span> = Vec::with_capacity(buf.len());
        for &s in buf.iter() {
            match out.last_mut() {
                Some(l) if s.enter <= l.exit => l.exit = l.exit.max(s.exit),
                _ => out.push(s),
            }
        }
        *buf = out;
    }
}

impl Store {
    pub(crate) fn build<G: HermiteGrid + ?Sized>(grid: &G, lattice: Lattice) -> Store {
        let dom = lattice.domain();
        let lo = [dom.min.x, dom.min.y, dom.min.z];
        let hi = [dom.max.x, dom.max.y, dom.max.z];
        let fam = [0, 1, 2].map(|a| {
            let (nu, nv) = (lattice.n[(a + 1) % 3], lattice.n[(a + 2) % 3]);
            let rows: Vec<(Vec<usize>, Vec<Span>)> = (0..nv)
                .into_par_iter()
                .map_init(Vec::new, |buf, v| {
                    let mut counts = Vec::with_capacity(nu);
                    let mut spans = Vec::new();
                    for u in 0..nu {
                        buf.clear();
                        grid.line_spans(a, u, v, buf);
                        sanitize(buf, lo[a], hi[a]);
                        counts.push(buf.len());
                        spans.extend_from_slice(buf);
                    }
                    (counts, spans)
                })
                .collect();
            let total: usize = rows.iter().map(|r| r.1.len()).sum();
            let mut offsets = Vec::with_capacity(nu * nv + 1);
            let mut spans = Vec::with_capacity(total);
            offsets.push(0);
            for (counts, s) in rows {
                for c in counts {
                    offsets.push(offsets.last().copied().unwrap_or(0) + c);
                }
                spans.extend(s);
            }
            Family {
                nu,
                nv,
                offsets,
                spans,
            }
        });
        Store {
            lattice,
            fam,
            lo,
            hi,
        }
    }

    pub(crate) fn line_count(&self) -> usize {
        self.fam.iter().map(|f| f.nu * f.nv).sum()
    }

    pub(crate) fn span_count(&self) -> usize {
        self.fam.iter().map(|f| f.spans.len()).sum()
    }
}

/// The first interval end of the given kind (`exit` or enter) in `[lo, hi]`.
#[inline]
pub(crate) fn boundary_in(spans: &[Span], lo: f64, hi: f64, exit: bool) -> Option<f64> {
    let t = if exit {
        let i = spans.partition_point(|s| s.exit < lo);
        spans.get(i)?.exit
    } else {
        let i = spans.partition_point(|s| s.enter < lo);
        spans.get(i)?.enter
    };
    (t <= hi).then_some(t)
}

/// The interval end of the given kind nearest to `t`.
#[inline]
pub(crate) fn nearest(spans: &[Span], t: f64, exit: bool) -> Option<f64> {
    let val = |s: &Span| if exit { s.exit } else { s.enter };
    let i = spans.partition_point(|s| val(s) < t);
    let a = i.checked_sub(1).map(|k| val(&spans[k]));
    let b = spans.get(i).map(val);
    match (a, b) {
        (Some(a), Some(b)) => Some(if t - a <= b - t { a } else { b }),
        (a, b) => a.or(b),
    }
}

/// A maximal run of consecutive inside lattice points `lo..=hi` on an X line, with the
/// crossings before its first and after its last point.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Run {
    pub(crate) lo: i32,
    pub(crate) hi: i32,
    pub(crate) t_lo: f64,
    pub(crate) t_hi: f64,
}

/// Appends the runs of lattice points (along axis `a` of `lat`) inside `spans`.
pub(crate) fn runs(spans: &[Span], lat: &Lattice, a: usize, out: &mut Vec<Run>) {
    let n = lat.n[a] as i64;
    let (o, h) = (lat.origin[a], lat.spacing[a]);
    let x = |i: i64| o + i as f64 * h;
    let start = out.len();
    for s in spans {
        // First index with x ≥ enter, last with x ≤ exit (exactly, as `x` computes them).
        let mut lo = ((s.enter - o) / h).ceil() as i64;
        while x(lo) < s.enter {
            lo += 1;
        }
        while x(lo - 1) >= s.enter {
            lo -= 1;
        }
        let mut hi = ((s.exit - o) / h).floor() as i64;
        while x(hi) > s.exit {
            hi -= 1;
        }
        while x(hi + 1) <= s.exit {
            hi += 1;
        }
        let (lo, hi) = (lo.max(0), hi.min(n - 1));
        if lo > hi {
            continue;
        }
        match out[start..].last_mut() {
            Some(r) if r.hi as i64 + 1 >= lo => {
                r.hi = hi as i32;
                r.t_hi = s.exit;
            }
            _ => out.push(Run {
                lo: lo as i32,
                hi: hi as i32,
                t_lo: s.enter,
                t_hi: s.exit,
            }),
        }
    }
}

/// The runs of inside points of every X line of one point level, line by line: what the
/// extraction and the blocks' decisions read a level's sides and X crossings from.
#[derive(Default)]
pub(crate) struct LevelRuns {
    runs: Vec<Run>,
    /// Where each line's runs start in `runs`, and the end.
    offsets: Vec<usize>,
}

impl LevelRuns {
    /// Fills in the runs of point level `lev` of `store`'s lattice (none for a level outside
    /// it).
    pub(crate) fn read(&mut self, store: &Store, lev: i32) {
        let lat = &store.lattice;
        let (n1, n2) = (lat.n[1] as i32, lat.n[2] as i32);
        self.runs.clear();
        self.offsets.clear();
        self.offsets.push(0);
        for j in 0..n1 {
            if (0..n2).contains(&lev) {
                runs(
                    store.fam[0].get(j as isize, lev as isize),
                    lat,
                    0,
                    &mut self.runs,
                );
            }
            self.offsets.push(self.runs.len());
        }
    }

    /// The runs of line `j` (none outside the lattice).
    #[inline]
    pub(crate) fn line(&self, j: i32) -> &[Run] {
        if j < 0 || j as usize + 1 >= self.offsets.len() {
            return &[];
        }
        &self.runs[self.offsets[j as usize]..self.offsets[j as usize + 1]]
    }
}

/// True when index `i` is in one of the (sorted) runs.
#[inline]
pub(crate) fn in_runs(runs: &[Run], i: i32) -> bool {
    let k = runs.partition_point(|r| r.hi < i);
    k < runs.len() && runs[k].lo <= i
}

/// Calls `f(i, in_a)` for every index inside exactly one of the run lists `a`, `b`.
pub(crate) fn xor_runs(a: &[Run], b: &[Run], mut f: impl FnMut(i32, bool)) {
    // Toggle positions: a run lo..=hi toggles at lo and hi + 1.
    let (mut ia, mut ib) = (0usize, 0usize);
    let (mut in_a, mut in_b) = (false, false);
    let next = |runs: &[Run], k: usize| -> i32 {
        let r = k / 2;
        if r >= runs.len() {
            i32::MAX
        } else if k % 2 == 0 {
            runs[r].lo
        } else {
            runs[r].hi + 1
        }
    };
    let mut pos = next(a, 0).min(next(b, 0));
    while pos != i32::MAX {
        while next(a, ia) == pos {
            in_a = !in_a;
            ia += 1;
        }
        while next(b, ib) == pos {
            in_b = !in_b;
            ib += 1;
        }
        let to = next(a, ia).min(next(b, ib));
        if in_a != in_b && to != i32::MAX {
            for i in pos..to {
                f(i, in_a);
            }
        }
        pos = to;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use swarf_geom::math::Vec3;

    #[test]
    fn runs_xor_and_boundaries() {
        let lat = Lattice::new(Vec3::ZERO, Vec3::ONE, [10, 1, 1]);
        let spans = [
            Span {
                enter: 0.5,
                exit: 3.0,
            },
            Span {
                enter: 3.2,
                exit: 3.8,
            },
            Span {
                enter: 3.9,
                exit: 5.5,
            },
            Span {
                enter: 7.0,
                exit: 7.0,
            },
            Span {
                enter: 8.5,
                exit: 20.0,
            },
        ];
        let mut r = Vec::new();
        runs(&spans, &lat, 0, &mut r);
        let got: Vec<(i32, i32)> = r.iter().map(|r| (r.lo, r.hi)).collect();
        // 1..=3, 4..=5 merge (adjacent), 7 is a single point, 9 clipped at n − 1.
        assert_eq!(got, vec![(1, 5), (7, 7), (9, 9)]);
        assert_eq!((r[0].t_lo, r[0].t_hi), (0.5, 5.5));
        assert!(in_runs(&r, 5) && !in_runs(&r, 6) && in_runs(&r, 7) && !in_runs(&r, 0));
        let other = [Run {
            lo: 0,
            hi: 2,
            t_lo: 0.0,
            t_hi: 0.0,
        }];
        let mut x = Vec::new();
        xor_runs(&r, &other, |i, a| x.push((i, a)));
        assert_eq!(
            x,
            vec![
                (0, false),
                (3, true),
                (4, true),
                (5, true),
                (7, true),
                (9, true)
            ]
        );
        assert_eq!(boundary_in(&spans, 5.0, 6.0, true), Some(5.5));
        assert_eq!(boundary_in(&spans, 5.0, 6.0, false), None);
        assert_eq!(nearest(&spans, 4.0, false), Some(3.9));
        let mut messy = vec![
            Span {
                enter: 2.0,
                exit: 4.0,
            },
            Span {
                enter: f64::NAN,
                exit: 1.0,
            },
            Span {
                enter: -5.0,
                exit: 2.5,
            },
        ];
        sanitize(&mut messy, -1.0, 3.0);
        assert_eq!(
            messy,
            vec![Span {
                enter: -1.0,
                exit: 3.0
            }]
        );
    }
}
