//! A bull-nose corner swept along a move, against a line, without the torus envelope's
//! degree-8 polynomial.
//!
//! # Why it holds
//! The corner of a bull-nose (a quarter torus of tube radius `r` about the spine circle of
//! radius `e` at height `f = r`, tangent to the flat bottom and to the vertical side) lies on
//! the boundary of the **lozenge** `L = D ⊕ B(r)`, `D` the disc of radius `e` at height `f`:
//! the points within `r` of `D`. Where the side above the corner stays vertical up to `f + r`,
//! `L` lies inside the tool (its lower half is the corner and the flat bottom, its upper half
//! within the side's radius `e + r`), so `L ⊕ [0, v]` lies in the sweep `S`, and every point
//! where a line leaves or enters `S` through the swept corner is where it leaves or enters
//! `L ⊕ [0, v]`: the two ends of that chord are candidates that replace the corner's caps and
//! envelope (`mod.rs`, "the geometry").
//!
//! `L ⊕ [0, v] = (D ⊕ [0, v]) ⊕ B(r)`, so along the line `p(t) = o + t·d` the chord is where
//! `G(t) = dist(p(t), K) − r ≤ 0`, `K = D ⊕ [0, v]` — convex, as the distance to a convex set
//! is. And `dist(p, K)² = min_{s ∈ [0, 1]} φ(s)`, `φ(s) = h(s)² + max(ρ(s) − e, 0)²` with
//! `h = p_z − s·v_z − f` and `ρ` the distance of `p − s·v` from the axis: a convex function of
//! `s` (sums of squares of convex non-negative functions), minimised by bracketed Newton steps.
//! The derivative of `G` is that of `φ` in `t` at the minimising `s` (envelope theorem). The
//! walks run on `F = dist² − r² = min φ − r²`, which has `G`'s zeros and sign and is convex too
//! (its `F″ ≤ 2`: the squared distance to a convex set has a 2-Lipschitz gradient), with no
//! square root of its own: Newton steps on it from the ends of the bounding capsule (where
//! `F ≥ 0`) close in on its zeros from outside, as for the torus caps (`convex.rs`).

use super::capsule::line_capsule;
use super::convex::{min_between, walk, zero_between, ConvexLine, Walk};
use super::{Acc, BAND_EPS};
use swarf_geom::math::Vec3;

/// Steps at most of the inner minimisation (bisection halves the bracket at least every
/// other).
const MAX_STEPS: usize = 120;

/// The corner `(e, f, r)` and the move `v`, in the move frame (tool axis +Z).
struct Corner {
    e: f64,
    f: f64,
    r: f64,
    v: Vec3,
}

impl Corner {
    /// `min_s φ` for the point `p`, with what its gradient in `p` is made of: `(φ, h, out, ρ,
    /// u_x, u_y)` at the minimising `s`, the gradient being `2h·ẑ + 2·out·(u_x, u_y, 0)/ρ`
    /// (`out = 0`, `ρ = 1` over the disc).
    fn nearest(&self, p: Vec3) -> [f64; 6] {
        let (a, b) = (self.v.x, self.v.z);
        // (Over the disc, `ρ ≤ e`, the distance is the height alone: no square root. The
        // walks wait on these chains of square roots and divisions.)
        let phi = |s: f64| -> [f64; 6] {
            let (ux, uy) = (p.x - s * a, p.y);
            let h = p.z - s * b - self.f;
            let rho2 = ux * ux + uy * uy;
            if rho2 <= self.e * self.e {
                return [h * h, h, 0.0, 1.0, ux, uy];
            }
            let rho = rho2.sqrt();
            let out = rho - self.e;
            [h * h + out * out, h, out, rho, ux, uy]
        };
        // φ′(s) = −∂φ/∂p · v.
        let slope = |s: f64| -> (f64, f64) {
            let (ux, uy) = (p.x - s * a, p.y);
            let h = p.z - s * b - self.f;
            let rho2 = ux * ux + uy * uy;
            if rho2 <= self.e * self.e {
                return (-2.0 * b * h, 2.0 * b * b);
            }
            // φ′ and φ″ times ρ³ (> 0): the Newton step and the signs are the same, with no
            // division but the step's.
            let rho = rho2.sqrt();
            let out = rho - self.e;
            let g = -2.0 * rho2 * (b * h * rho + a * out * ux);
            let curv = 2.0 * (b * b * rho2 * rho + a * a * (ux * ux * rho + out * uy * uy));
            (g, curv)
        };
        if a == 0.0 && b == 0.0 {
            // A static tool: the distance to the disc itself.
            return phi(0.0);
        }
        // Newton steps kept in [0, 1] (a bracket of the minimiser once the slope's sign is
        // seen at both ends of it), from the point of the move nearest to p across the axis,
        // which is the minimiser of a level move and near it otherwise.
        let start = if a != 0.0 {
            (p.x / a).clamp(0.0, 1.0)
        } else {
            0.5
        };
        let s = {
            let (mut lo, mut hi) = (0.0, 1.0);
            let mut s = start;
            for _ in 0..MAX_STEPS {
                let (g, c) = slope(s);
                if g == 0.0 || (g > 0.0 && s == 0.0) || (g < 0.0 && s == 1.0) {
                    // The minimiser, or rising away from an end of the move.
                    break;
                }
                if g < 0.0 {
                    lo = s;
                } else {
                    hi = s;
                }
                let next = if c > 0.0 { s - g / c } else { f64::NAN };
                let newton = next > lo && next < hi;
                if newton && (next - s).abs() <= 1e-14 {
                    s = next;
                    break;
                }
                s = if newton {
                    next
                } else if next <= lo && lo == 0.0 && s != 0.0 {
                    // Newton points past the start of the move: the minimiser may be there.
                    0.0
                } else if next >= hi && hi == 1.0 && s != 1.0 {
                    1.0
                } else {
                    0.5 * (lo + hi)
                };
                if hi - lo <= 1e-15 {
                    break;
                }
            }
            s
        };
        phi(s)
    }

    /// `(F(t), F′(t), −F/F′)` along the line `o + t·d`, `F = dist² − r²` (the step with one
    /// division, the slope's division by ρ off its chain).
    fn g(&self, o: Vec3, d: Vec3, t: f64) -> (f64, f64, f64) {
        let [q, h, out, rho, ux, uy] = self.nearest(o + d * t);
        let f = q - self.r * self.r;
        let slope_rho = 2.0 * (h * d.z * rho + out * (ux * d.x + uy * d.y));
        (f, slope_rho / rho, -f * rho / slope_rho)
    }
}

/// `F` along one line.
struct CornerLine<'c> {
    corner: &'c Corner,
    o: Vec3,
    d: Vec3,
}

impl ConvexLine for CornerLine<'_> {
    fn value_slope(&self, t: f64) -> (f64, f64) {
        let (f, g, _) = self.corner.g(self.o, self.d, t);
        (f, g)
    }

    fn value_slope_step(&self, t: f64) -> (f64, f64, f64) {
        self.corner.g(self.o, self.d, t)
    }

    fn curvature_bound(&self) -> Option<f64> {
        Some(2.0)
    }
}

/// Adds to `acc` the ends of the chord of the line `o + t·d` (unit `d`, move frame) through
/// `(D ⊕ B(r)) ⊕ [0, v]`, `D` the disc of radius `e` at height `f` about the axis (module
/// documentation), if the line meets it.
pub(crate) fn swept_chord(e: f64, f: f64, r: f64, o: Vec3, d: Vec3, v: Vec3, acc: &mut Acc) {
    if let Some((a, b)) = swept_interval(e, f, r, o, d, v) {
        acc.add(a);
        acc.add(b);
    }
}

/// The corner of a static tool: the ends of the line's chord through the lozenge that lie on
/// its lower half (`z ≤ f`), which is the tool's own boundary there (the torus band and the flat
/// bottom) — so they are crossings of the tool, as a static instance's candidates must be (it
/// stops at its first two); an end on the upper half lies inside the tool and is left out.
pub(crate) fn instance_crossings(e: f64, f: f64, r: f64, o: Vec3, d: Vec3, acc: &mut Acc) {
    if let Some((a, b)) = swept_interval(e, f, r, o, d, Vec3::ZERO) {
        for t in [a, b] {
            if o.z + t * d.z <= f + BAND_EPS {
                acc.add(t);
            }
        }
    }
}

/// A static lozenge along one line `o + t·d` (unit `d`, tool frame) — the tool instance's
/// kernels (`instance.rs`) — as `F = dist² − r²`, `dist` the distance to the disc of radius `e`
/// at height `f`. `F` has the zeros and sign of `G = dist − r` and is convex too (the square
/// of a convex non-negative function), with `F″ ≤ 2`; it takes one square root and one division
/// a Newton step where `G` takes two and three, and the walks wait on that chain.
pub(crate) struct StaticLine {
    pub(crate) e: f64,
    pub(crate) f: f64,
    pub(crate) r: f64,
    pub(crate) o: Vec3,
    pub(crate) d: Vec3,
}

impl ConvexLine for StaticLine {
    #[inline]
    fn value_slope(&self, t: f64) -> (f64, f64) {
        let (f, g, _) = self.value_slope_step(t);
        (f, g)
    }

    /// The step as `−F·ρ / (2·(h·d_z·ρ + out·(p·d)_xy))`: one division after the square root,
    /// where `F′` needs a division by `ρ` first.
    #[inline]
    fn value_slope_step(&self, t: f64) -> (f64, f64, f64) {
        let (o, d) = (self.o, self.d);
        let p = o + d * t;
        let rho2 = p.x * p.x + p.y * p.y;
        let h = p.z - self.f;
        if rho2 <= self.e * self.e {
            // Over the disc: the distance is the height.
            let (f, g) = (h * h - self.r * self.r, 2.0 * h * d.z);
            return (f, g, -f / g);
        }
        let rho = rho2.sqrt();
        let out = rho - self.e;
        let f = h * h + out * out - self.r * self.r;
        let half = h * d.z * rho + out * (p.x * d.x + p.y * d.y);
        (f, 2.0 * half / rho, -f * rho / (2.0 * half))
    }

    /// The squared distance to a convex set has a gradient that is 2-Lipschitz: `F″ ≤ 2`.
    fn curvature_bound(&self) -> Option<f64> {
        Some(2.0)
    }

    #[inline]
    fn value(&self, t: f64) -> f64 {
        let p = self.o + self.d * t;
        let out = ((p.x * p.x + p.y * p.y).sqrt() - self.e).max(0.0);
        let h = p.z - self.f;
        h * h + out * out - self.r * self.r
    }
}

impl StaticLine {
    /// `F` where `G = dist − r` is `g`: a depth `g` in mm as a threshold on `F`.
    #[inline]
    pub(crate) fn f_at(&self, g: f64) -> f64 {
        g * (g + 2.0 * self.r)
    }

    /// The first zero of `F` from `from` (where `F ≥ 0`; its value and slope when known)
    /// towards `toward` (where `F ≤ 0`).
    pub(crate) fn entry(&self, from: f64, at: Option<(f64, f64)>, toward: f64) -> f64 {
        let at = at.unwrap_or_else(|| self.value_slope(from));
        match walk(self, from, (at.0, Some(at.1)), toward) {
            Walk::Zero(t) => t,
            // Rounding at `toward`, or a slope the steps cannot follow: the one change of
            // sign between the two (F is convex, ≥ 0 at `from` and ≤ 0 at `toward`).
            Walk::NoZero | Walk::Stuck => {
                let (a, b) = (from.min(toward), from.max(toward));
                zero_between(self, a, b, self.value(a))
            }
        }
    }

    /// The zero of `F` between `from` (outside, `F ≥ 0`; its value and slope when known) and
    /// `inner` (inside, `F(inner) < 0` with its slope), walking along `dir` (±1) from `from`.
    ///
    /// Where `F` still falls along `dir` at `inner`, the zero of its tangent there is a nearer
    /// start: `F` is convex, so it lies above the tangent and is `≥ 0` at that zero, which lies
    /// between `from` and the zero sought — a Newton step or two from it instead of five or
    /// six from `from`.
    pub(crate) fn entry_near(
        &self,
        (from, at): (f64, Option<(f64, f64)>),
        (inner, (g, slope)): (f64, (f64, f64)),
        dir: f64,
    ) -> f64 {
        let falls = slope * dir < 0.0;
        let start = if falls { inner - g / slope } else { f64::NAN };
        if (start - from) * dir > 0.0 && (inner - start) * dir > 0.0 {
            self.entry(start, None, inner)
        } else {
            self.entry(from, at, inner)
        }
    }

    /// The chord within `(lo, hi)`, where `F ≥ 0` at both ends.
    pub(crate) fn chord_in(&self, lo: f64, hi: f64) -> Option<(f64, f64)> {
        chord_between(self, lo, hi)
    }
}

/// The chord of the line `o + t·d` (unit `d`, move frame) through the lozenge swept by `v`,
/// `(D ⊕ B(r)) ⊕ [0, v]`, if it meets it.
pub(crate) fn swept_interval(
    e: f64,
    f: f64,
    r: f64,
    o: Vec3,
    d: Vec3,
    v: Vec3,
) -> Option<(f64, f64)> {
    let (lo, hi) = swept_bracket((e, f, r), o, d, v)?;
    let corner = Corner { e, f, r, v };
    let line = CornerLine {
        corner: &corner,
        o,
        d,
    };
    chord_between(&line, lo, hi)
}

/// A range of the line `o + t·d` holding its chord through the lozenge `(e, f, r)` swept by
/// `v`, with `G ≥ 0` at both ends; `None` when the line misses a bound of it.
fn swept_bracket((e, f, r): (f64, f64, f64), o: Vec3, d: Vec3, v: Vec3) -> Option<(f64, f64)> {
    // Every point of it is within e + r of the disc centre's path …
    let c0 = Vec3::new(0.0, 0.0, f);
    let (mut lo, mut hi) = line_capsule::<false>(o, d, c0, v, e + r)?;
    // … and between the planes of its lowest and highest points (the flat bottom's swept
    // plane is reached at once by a line crossing it under the disc).
    if d.z != 0.0 {
        let (z_lo, z_hi) = (f - r + v.z.min(0.0), f + r + v.z.max(0.0));
        let (ta, tb) = ((z_lo - o.z) / d.z, (z_hi - o.z) / d.z);
        lo = lo.max(ta.min(tb));
        hi = hi.min(ta.max(tb));
        if lo > hi {
            return None;
        }
    }
    Some((lo, hi))
}

/// One end of [`swept_interval`]'s chord: the lower (`upper = false`) or the upper one, with
/// one walk instead of two where it settles (the whole chord where it does not); `None` when
/// the line misses the swept lozenge.
pub(crate) fn swept_end(
    (e, f, r): (f64, f64, f64),
    o: Vec3,
    d: Vec3,
    v: Vec3,
    upper: bool,
) -> Option<f64> {
    let (lo, hi) = swept_bracket((e, f, r), o, d, v)?;
    let corner = Corner { e, f, r, v };
    let line = CornerLine {
        corner: &corner,
        o,
        d,
    };
    let (from, toward) = if upper { (hi, lo) } else { (lo, hi) };
    let (value, slope) = line.value_slope(from);
    match walk(&line, from, (value, Some(slope)), toward) {
        Walk::Zero(t) => Some(t),
        Walk::NoZero => None,
        Walk::Stuck => chord_between(&line, lo, hi).map(|(a, b)| if upper { b } else { a }),
    }
}

/// The chord `{G ≤ 0}` of a convex `G` within `(lo, hi)`, where `G ≥ 0` at both ends.
fn chord_between<L: ConvexLine>(line: &L, lo: f64, hi: f64) -> Option<(f64, f64)> {
    let (at_lo, at_hi) = (line.value_slope(lo), line.value_slope(hi));
    let lower = match walk(line, lo, (at_lo.0, Some(at_lo.1)), hi) {
        Walk::NoZero => return None,
        Walk::Zero(t) => Some(t),
        Walk::Stuck => None,
    };
    let upper = match walk(line, hi, (at_hi.0, Some(at_hi.1)), lo) {
        Walk::NoZero => return None,
        Walk::Zero(t) => Some(t),
        Walk::Stuck => None,
    };
    if let (Some(a), Some(b)) = (lower, upper) {
        return Some((a, b));
    }
    // The walks did not settle (a line grazing the sweep): the minimum, then each side.
    let t_min = if at_lo.1 >= 0.0 {
        lo
    } else if at_hi.1 <= 0.0 {
        hi
    } else {
        min_between(line, lo, hi)
    };
    let f_min = line.value(t_min);
    if f_min > 0.0 {
        return None;
    }
    Some((
        lower.unwrap_or_else(|| zero_between(line, lo, t_min, at_lo.0)),
        upper.unwrap_or_else(|| zero_between(line, t_min, hi, f_min)),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What the walks rely on, at `t` of a line whose `(F, F′, step)` there is given: the slope
    /// against a central difference of `value`, the step against `−F/F′`, and `F″ ≤ 2` (the
    /// walk's early stop) by a second difference.
    fn check_line_at(value: impl Fn(f64) -> f64, t: f64, (f, fs, step): (f64, f64, f64)) {
        let w = 1e-6;
        let diff = (value(t + w) - value(t - w)) / (2.0 * w);
        assert!(
            (diff - fs).abs() <= 1e-5 * (1.0 + fs.abs()),
            "{diff} vs {fs} at {t}"
        );
        if fs != 0.0 {
            assert!((step + f / fs).abs() <= 1e-12 * (1.0 + step.abs()));
        }
        let w2 = 1e-4;
        let second = (value(t + w2) - 2.0 * f + value(t - w2)) / (w2 * w2);
        assert!(second <= 2.0 + 1e-4, "F″ ≈ {second} at {t}");
    }

    /// A static lozenge's `F` agrees with `G` written out (`F = G·(G + 2r)`), its slope with a
    /// central difference, its step with `−F/F′`, `F″ ≤ 2`, and a walk on it lands on `G`'s
    /// zero.
    #[test]
    fn a_static_lozenge_is_g_squared_with_its_slope_and_step() {
        let (mut zeros, mut n) = (0, 0);
        for i in 0..400 {
            let a = i as f64 * 0.37;
            let d = Vec3::new(
                a.cos() * 0.8,
                a.sin() * 0.8,
                if i % 3 == 0 { 0.6 } else { -0.6 },
            )
            .normalize();
            let o = Vec3::new(
                0.9 * (a * 1.7).sin(),
                0.7 * (a * 2.3).cos(),
                1.5 + 0.5 * a.sin(),
            ) - d * 6.0;
            let line = StaticLine {
                e: 3.0,
                f: 2.0,
                r: 2.0,
                o,
                d,
            };
            // G = dist − r written out, as the reference.
            let g_of = |t: f64| -> f64 {
                let p = o + d * t;
                let out = ((p.x * p.x + p.y * p.y).sqrt() - line.e).max(0.0);
                let h = p.z - line.f;
                (h * h + out * out).sqrt() - line.r
            };
            for j in 0..60 {
                let t = j as f64 * 0.2;
                let g = g_of(t);
                let (f, fs, step) = line.value_slope_step(t);
                let want = g * (g + 2.0 * line.r);
                assert!(
                    (f - want).abs() <= 1e-12 * (1.0 + want.abs()),
                    "{f} vs {want}"
                );
                assert_eq!(line.value(t), f);
                assert!((line.f_at(g) - want).abs() <= 1e-12 * (1.0 + want.abs()));
                check_line_at(|t| line.value(t), t, (f, fs, step));
                n += 1;
            }
            // Where the line enters the lozenge, the walk on F finds G's zero, from its start's
            // (F, F′) given or not.
            let inside = (0..120)
                .map(|j| j as f64 * 0.1)
                .find(|&t| line.value(t) < -1e-3);
            if let (Some(tin), true) = (inside, line.value(0.0) > 0.0) {
                let t = line.entry(0.0, None, tin);
                assert!(g_of(t).abs() <= 1e-9, "G({t}) = {}", g_of(t));
                let given = line.entry(0.0, Some(line.value_slope(0.0)), tin);
                assert_eq!(given, t);
                zeros += 1;
            }
        }
        assert!(n == 24_000 && zeros > 100, "{n} {zeros}");
    }

    /// The swept corner's `F = dist² − r²` against the distance to the swept disc found by
    /// dense sampling of the move, its slope against a central difference, its step against
    /// `−F/F′`, and `F″ ≤ 2`.
    #[test]
    fn the_swept_corner_is_the_squared_distance_to_the_swept_disc() {
        let corner = Corner {
            e: 3.0,
            f: 2.0,
            r: 2.0,
            v: Vec3::new(0.5, 0.0, 0.12),
        };
        // Distance² from p to the disc (radius e, height f) moved by s·v, s ∈ [0, 1] sampled.
        let sampled = |p: Vec3| -> f64 {
            (0..=20_000)
                .map(|i| {
                    let s = i as f64 / 20_000.0;
                    let (ux, uy) = (p.x - s * corner.v.x, p.y);
                    let h = p.z - s * corner.v.z - corner.f;
                    let out = ((ux * ux + uy * uy).sqrt() - corner.e).max(0.0);
                    h * h + out * out
                })
                .fold(f64::INFINITY, f64::min)
        };
        let mut checked = 0;
        for i in 0..60 {
            let a = i as f64 * 0.61;
            let d = Vec3::new(a.cos(), a.sin(), 0.4 * (a * 1.3).sin()).normalize();
            let o = Vec3::new(0.3 * a.sin(), 0.2 * a.cos(), 1.0 + 0.4 * (a * 0.7).cos()) - d * 7.0;
            for j in 0..28 {
                let t = j as f64 * 0.5;
                let (f, fs, step) = corner.g(o, d, t);
                let want = sampled(o + d * t) - corner.r * corner.r;
                // Sampling the move every 1/20,000 leaves ≈ (|v|/20,000)² / 4 above the minimum.
                assert!(
                    (f - want).abs() <= 1e-9 * (1.0 + want.abs()),
                    "{f} vs {want}"
                );
                check_line_at(|t| corner.g(o, d, t).0, t, (f, fs, step));
                checked += 1;
            }
        }
        assert_eq!(checked, 1_680);
    }
}
