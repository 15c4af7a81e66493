//! Closed form for a slab (flat end mill, a band of one, a shank), a ball end or a bull-nose
//! moving along a segment with its axis fixed at **any** direction, against the dexel rays: the
//! tilted fixed-axis moves of 3+2 programs and the fixed-axis pieces a 5-axis move of a flat
//! end mill is cut as, which otherwise take the general candidates (`line_interval`).
//!
//! # Why it holds
//! In the move frame (origin the tip at the start, `z` the tool axis, `x` the move's part
//! across the axis, so the move is `v = (a, 0, b)`) the slab at time `s ∈ [0, 1]` is the
//! points with `(x − s·a)² + y² ≤ R²` and `z0 ≤ z − s·b ≤ z1`. A line `p(λ) = o + λ·d` meets
//! the swept slab where some `s` satisfies, with `u = (x(λ) − s·a, y(λ))` and
//! `h = z(λ) − s·b` (both affine in `(λ, s)`):
//!
//! * `E`: `|u|² ≤ R²` — an ellipse in the `(λ, s)` plane (a strip when it degenerates);
//! * `T`: `0 ≤ s ≤ 1`, and `H`: `z0 ≤ h ≤ z1` — two strips, whose intersection is a
//!   parallelogram.
//!
//! The set `F = E ∩ T ∩ H` is convex and compact, and the line's chord is `F`'s extent in `λ`.
//! `F`'s least (and greatest) `λ` is attained at a boundary point of `F`, which is one of:
//! * the point of `∂E` where `λ` is extreme, when it lies inside `T ∩ H`: `y(λ) = ±R`, `u_x = 0`
//!   (`y` does not depend on `s`, since the move is along `x`);
//! * a corner of the parallelogram `T ∩ H` inside `E`;
//! * a point where an edge line of `T ∩ H` crosses `∂E` (a quadratic along the line), inside the
//!   other strip.
//!
//! (An extreme on an edge of `T ∩ H` inside `E`, or on a flat stretch of a degenerate `∂E`,
//! extends to one of the last two kinds.) Every candidate is a point of `F` — checked against
//! all three constraints within [`BAND_EPS`](super::BAND_EPS), so an accepted one lies within
//! that of the sweep — and every extreme is a candidate, so `[min, max]` over the candidates
//! is the chord: exact, with at most four square roots and no iteration.
//!
//! A ball end is the capsule of its sphere's centre (`capsule.rs`) united with the slab above
//! the centre; a bull-nose, the slab above its corner's spine united with the swept lozenge
//! (`lozenge.rs`: the zeros of a convex distance, by Newton steps — computed only where the
//! ray's material within the lozenge's box reaches beyond the slab's chord). The sweep of the
//! whole is convex, so the two chords of a line join into one. The property tests
//! (`tests/fast_paths.rs`) hold them to the general candidates, and `removed_volume_exact.rs`
//! the three cutters tilted 25° against the exact removed volume.

use super::fast::{CapsuleRays, FastProfile, RampRays};
use super::BAND_EPS;
use swarf_geom::math::{greater, lesser, Vec3};
use swarf_geom::Frame;

/// A slab, ball-end or bull-nose profile moving with its axis fixed off the world axes.
#[derive(Clone, Copy, Debug)]
pub(crate) struct TiltedSweep {
    shape: FastProfile,
    /// The move frame: tip at the start, `z` the tool axis, `x` along the move's part across it.
    frame: Frame,
    /// The move in the move frame, `(a, 0, b)`.
    v: Vec3,
}

impl TiltedSweep {
    /// The closed form for `shape` in the move frame `frame`, moving by `v` (move frame).
    pub(crate) fn new(shape: FastProfile, frame: Frame, v: Vec3) -> Self {
        Self { shape, frame, v }
    }

    /// The constants shared by the rays along world axis `k`, for the shape grown by `grow`
    /// mm all round (`0`: the shape itself; a block of rays within `grow` of one ray meets the
    /// sweep only where that ray meets the grown one's).
    pub(crate) fn rays(&self, k: usize, grow: f64) -> TiltedRays {
        let (r, z0, z1) = self.shape.slab;
        let f = &self.frame;
        let (fu, fv) = ((k + 1) % 3, (k + 2) % 3);
        // Move-frame coordinates of the ray's origin `(cu, cv)` on the cross axes, `0` along
        // `k`: affine in `(cu, cv)`.
        let at = |e: Vec3| {
            let base = -e.dot(f.origin);
            (base, e[fu], e[fv])
        };
        // The rounded end, whose tube reaches `below` under the slab's bottom (its spine) and
        // as far above it.
        let spine = z0;
        let (end, below) = match self.shape.lozenge {
            None => (None, 0.0),
            Some((0.0, zc, sr)) => {
                let c0 = f.origin + f.z * zc;
                let v = f.vector_to_world(self.v);
                let capsule = CapsuleRays::new(k, c0, v, sr + grow);
                (Some(RoundEnd::Sphere(capsule)), sr + grow)
            }
            Some((e, spine, lr)) => {
                let lozenge = RampRays::new((e, spine, lr + grow), *f, self.v, k);
                (Some(RoundEnd::Lozenge(lozenge)), lr + grow)
            }
        };
        let (r, z0, z1) = (r + grow, z0 - grow, z1 + grow);
        let (a, b) = (self.v.x, self.v.z);
        let e = BAND_EPS;
        let end_slab = (
            1.0 / f.z[k],
            spine - below + b.min(0.0) - e,
            spine + below + b.max(0.0) + e,
        );
        let slabs = [
            (1.0 / f.x[k], -r + a.min(0.0) - e, r + a.max(0.0) + e),
            (1.0 / f.y[k], -r - e, r + e),
            (
                1.0 / f.z[k],
                z0 - below + b.min(0.0) - e,
                z1 + b.max(0.0) + e,
            ),
        ];
        TiltedRays {
            slabs,
            end_slab,
            x: at(f.x),
            y: at(f.y),
            z: at(f.z),
            slab: SlabRays::new((f.x[k], f.y[k], f.z[k]), (a, b), (r, z0, z1)),
            end,
        }
    }
}

/// The rounded end of a ball or bull-nose, swept (below the slab's bottom).
#[derive(Clone, Copy, Debug)]
enum RoundEnd {
    /// A ball's sphere: a capsule.
    Sphere(CapsuleRays),
    /// A bull-nose's lozenge (`lozenge.rs`: the zeros of a convex distance, by Newton steps).
    Lozenge(RampRays),
}

/// One sweep's closed form for the rays along one world axis (see [`TiltedSweep::rays`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct TiltedRays {
    /// The move frame's `x`, `y`, `z` coordinates of the ray origin `(cu, cv)`:
    /// `base + cu·du + cv·dv`.
    x: (f64, f64, f64),
    y: (f64, f64, f64),
    z: (f64, f64, f64),
    /// The swept slab.
    slab: SlabRays,
    /// A ball's or bull-nose's rounded end, swept.
    end: Option<RoundEnd>,
    /// The sweep's box in the move frame, per axis: `(1/g, lo, hi)` (`1/g` infinite for a ray
    /// across that axis).
    slabs: [(f64, f64, f64); 3],
    /// The heights of the rounded end's box, as `slabs[2]`.
    end_slab: (f64, f64, f64),
}

impl TiltedRays {
    /// The stock update's query (as [`super::SweptConvex::dexel_cut`]): whether the exact
    /// chord was computed, and the chord; `None` without it when the ray's material
    /// `[first, last]` misses the sweep's box in the move frame (the slab's sweep lies in
    /// `|x − s·a| ≤ R`, `|y| ≤ R`, `z0 ≤ z − s·b ≤ z1` for some `s ∈ [0, 1]`: three slabs
    /// of the ray; a ball end's sphere, centred at `z0` with radius `R`, reaches `R` lower).
    #[inline]
    pub(crate) fn cut(
        &self,
        cu: f64,
        cv: f64,
        (first, last): (f64, f64),
    ) -> (bool, Option<(f64, f64)>) {
        let q = self.origin(cu, cv);
        let across = clip(clip((first, last), q.0, self.slabs[0]), q.1, self.slabs[1]);
        let (l0, l1) = clip(across, q.2, self.slabs[2]);
        if l0 > l1 {
            return (false, None);
        }
        let slab = self.slab(q);
        let end = match &self.end {
            None => return (true, slab),
            Some(RoundEnd::Sphere(c)) => c.interval::<false>(cu, cv),
            Some(RoundEnd::Lozenge(l)) => {
                // The lozenge's Newton walks only where they can matter: where the ray's
                // material within the lozenge's box reaches beyond the slab's chord, and
                // only towards that side when it is one (beyond the other end there is no
                // material the lozenge could add).
                let (m0, m1) = clip(across, q.2, self.end_slab);
                if m0 > m1 {
                    return (true, slab);
                }
                match slab {
                    Some((a, b)) => match (m0 < a, m1 > b) {
                        (false, false) => return (true, slab),
                        (true, false) => {
                            let lo = l.end(cu, cv, false).map_or(a, |t| lesser(a, t));
                            return (true, Some((lo, b)));
                        }
                        (false, true) => {
                            let hi = l.end(cu, cv, true).map_or(b, |t| greater(b, t));
                            return (true, Some((a, hi)));
                        }
                        (true, true) => l.chord(cu, cv),
                    },
                    None => l.chord(cu, cv),
                }
            }
        };
        (true, join(slab, end))
    }

    /// The chord of the ray whose cross coordinates are `(cu, cv)`, in world coordinates
    /// along the ray.
    #[inline]
    pub(crate) fn interval(&self, cu: f64, cv: f64) -> Option<(f64, f64)> {
        self.chord(cu, cv, self.origin(cu, cv))
    }

    /// The move-frame coordinates of the ray's origin.
    #[inline(always)]
    fn origin(&self, cu: f64, cv: f64) -> (f64, f64, f64) {
        let lin = |p: (f64, f64, f64)| p.0 + cu * p.1 + cv * p.2;
        (lin(self.x), lin(self.y), lin(self.z))
    }

    #[inline(always)]
    fn chord(&self, cu: f64, cv: f64, q: (f64, f64, f64)) -> Option<(f64, f64)> {
        let slab = self.slab(q);
        let end = match &self.end {
            None => return slab,
            Some(RoundEnd::Sphere(c)) => c.interval::<false>(cu, cv),
            Some(RoundEnd::Lozenge(l)) => l.chord(cu, cv),
        };
        join(slab, end)
    }

    /// The swept slab's chord (see the module doc for the candidates), the ray's origin at
    /// `(qx, qy, h0)` in the move frame.
    fn slab(&self, (qx, qy, h0): (f64, f64, f64)) -> Option<(f64, f64)> {
        let c = &self.slab;
        let (gx, gy, gz, a, b) = (c.gx, c.gy, c.gz, c.a, c.b);
        let in_e = |l: f64, s: f64| {
            let (ux, uy) = (qx + l * gx - s * a, qy + l * gy);
            ux * ux + uy * uy <= c.re2
        };
        let in_s = |s: f64| (-c.s_eps..=1.0 + c.s_eps).contains(&s);
        let in_h = |l: f64, s: f64| (c.z0e..=c.z1e).contains(&(h0 + l * gz - s * b));
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        let mut take = |l: f64| {
            lo = lesser(lo, l);
            hi = greater(hi, l);
        };
        let qyy = qy * qy - c.r2;
        // ∂E on the lines s = 0 and s = 1 (inside H).
        if c.gg > 0.0 {
            for s in [0.0, 1.0] {
                let px = qx - s * a;
                if let Some((l1, l2)) = roots(c.gg, c.inv_gg, gx * px + gy * qy, px * px + qyy) {
                    for l in [l1, l2] {
                        if in_h(l, s) {
                            take(l);
                        }
                    }
                }
            }
        }
        match c.h_lines {
            HLines::ByS {
                inv_gz,
                mu,
                sx,
                sy,
                ss,
                inv_ss,
            } => {
                // The lines h = z, parametrised by s (λ moves by at most `ext` along them):
                // λ = λz + s·μ.
                for z in [c.z0, c.z1] {
                    let lz = (z - h0) * inv_gz;
                    // The parallelogram's corners (inside E).
                    for s in [0.0, 1.0] {
                        let l = lz + s * mu;
                        if in_e(l, s) {
                            take(l);
                        }
                    }
                    // ∂E along it (inside T).
                    if ss > 0.0 {
                        let (px, py) = (qx + lz * gx, qy + lz * gy);
                        let qc = px * px + py * py - c.r2;
                        if let Some((s1, s2)) = roots(ss, inv_ss, px * sx + py * sy, qc) {
                            for s in [s1, s2] {
                                if in_s(s) {
                                    take(lz + s * mu);
                                }
                            }
                        }
                    }
                }
            }
            HLines::ByLambda {
                inv_b,
                nu,
                inv_nu,
                ex,
                ee,
                inv_ee,
            } => {
                // The lines h = z, nearly level in (λ, s) (the ray nearly across the axis):
                // parametrised by λ, s = sz + λ·ν. ∂E along them, inside T, and their corners
                // with T (none when the lines are level).
                for z in [c.z0, c.z1] {
                    let sz = (h0 - z) * inv_b;
                    let px = qx - sz * a;
                    if let Some((l1, l2)) = roots(ee, inv_ee, px * ex + qy * gy, px * px + qyy) {
                        for l in [l1, l2] {
                            if in_s(sz + l * nu) {
                                take(l);
                            }
                        }
                    }
                    if inv_nu != 0.0 {
                        for s in [0.0, 1.0] {
                            let l = (s - sz) * inv_nu;
                            if in_e(l, s) {
                                take(l);
                            }
                        }
                    }
                }
            }
            HLines::Level => {
                if !(c.z0e..=c.z1e).contains(&h0) {
                    // The ray runs across the axis at a height the slab never reaches.
                    return None;
                }
            }
        }
        // ∂E's extremes in λ: y = ±r, u_x = 0.
        if let Some((inv_gy, inv_a)) = c.extremes {
            for y in [-c.r, c.r] {
                let l = (y - qy) * inv_gy;
                let s = (qx + l * gx) * inv_a;
                if in_s(s) && in_h(l, s) {
                    take(l);
                }
            }
        }
        (lo <= hi).then_some((lo, hi))
    }
}

/// The roots of `qa·t² + 2·qb·t + qc = 0` (`qa > 0`, `inv_qa = 1/qa`), without cancellation.
#[inline(always)]
fn roots(qa: f64, inv_qa: f64, qb: f64, qc: f64) -> Option<(f64, f64)> {
    let disc = qb * qb - qa * qc;
    if disc.is_nan() || disc < 0.0 {
        return None;
    }
    let q = -(qb + disc.sqrt().copysign(qb));
    let t1 = q * inv_qa;
    Some((t1, if q != 0.0 { qc / q } else { t1 }))
}

/// The swept slab's constants for one family of rays (see [`TiltedRays::slab`]).
#[derive(Clone, Copy, Debug)]
struct SlabRays {
    /// The ray direction in the move frame.
    gx: f64,
    gy: f64,
    gz: f64,
    /// The move, `(a, 0, b)` in the move frame.
    a: f64,
    b: f64,
    /// The radius, its square, and the square of the radius grown by `BAND_EPS`.
    r: f64,
    r2: f64,
    re2: f64,
    /// The tolerance on the move parameter `s`: `BAND_EPS` along the move.
    s_eps: f64,
    /// The heights, and the heights grown by `BAND_EPS`.
    z0: f64,
    z1: f64,
    z0e: f64,
    z1e: f64,
    /// `gx² + gy²` (0 for a ray along the axis) and its inverse.
    gg: f64,
    inv_gg: f64,
    h_lines: HLines,
    /// `(1/gy, 1/a)` when ∂E has extremes in λ (the ellipse is no strip).
    extremes: Option<(f64, f64)>,
}

/// How the lines `h = z0`, `h = z1` of the `(λ, s)` plane are followed.
#[derive(Clone, Copy, Debug)]
enum HLines {
    /// By `s`: `λ = (z − h0)/gz + s·μ`, `(sx, sy)` the change of `u` per unit `s`, `ss` its
    /// square (`inv_ss` its inverse).
    ByS {
        inv_gz: f64,
        mu: f64,
        sx: f64,
        sy: f64,
        ss: f64,
        inv_ss: f64,
    },
    /// By `λ`: `s = (h0 − z)/b + λ·ν`, `(ex, gy)` the change of `u` per unit `λ`, `ee` its
    /// square; `inv_nu = 1/ν` (0 when the lines are level: `gz = 0`).
    ByLambda {
        inv_b: f64,
        nu: f64,
        inv_nu: f64,
        ex: f64,
        ee: f64,
        inv_ee: f64,
    },
    /// `gz = b = 0`: `h` is the same all over the plane.
    Level,
}

impl SlabRays {
    /// The constants of a slab `(r, z0, z1)` moving by `(a, 0, b)`, for a ray along `g` (move
    /// frame); `ext` a length beyond the sweep's size.
    fn new(
        (gx, gy, gz): (f64, f64, f64),
        (a, b): (f64, f64),
        (r, z0, z1): (f64, f64, f64),
    ) -> Self {
        let ext = 2.0 * r + (z1 - z0) + a.abs() + b.abs();
        let inv = |x: f64| if x != 0.0 { 1.0 / x } else { 0.0 };
        let gg = gx * gx + gy * gy;
        let h_lines = if gz != 0.0 && gz.abs() * ext >= b.abs() {
            let mu = b / gz;
            let (sx, sy) = (mu * gx - a, mu * gy);
            let ss = sx * sx + sy * sy;
            HLines::ByS {
                inv_gz: 1.0 / gz,
                mu,
                sx,
                sy,
                ss,
                inv_ss: inv(ss),
            }
        } else if b != 0.0 {
            let nu = gz / b;
            let ex = gx - nu * a;
            let ee = ex * ex + gy * gy;
            HLines::ByLambda {
                inv_b: 1.0 / b,
                nu,
                inv_nu: inv(nu),
                ex,
                ee,
                inv_ee: inv(ee),
            }
        } else {
            HLines::Level
        };
        SlabRays {
            gx,
            gy,
            gz,
            a,
            b,
            r,
            r2: r * r,
            re2: (r + BAND_EPS) * (r + BAND_EPS),
            s_eps: BAND_EPS / a.hypot(b),
            z0,
            z1,
            z0e: z0 - BAND_EPS,
            z1e: z1 + BAND_EPS,
            gg,
            inv_gg: inv(gg),
            h_lines,
            extremes: (gy != 0.0 && a != 0.0).then(|| (1.0 / gy, 1.0 / a)),
        }
    }
}

/// The chord of a convex sweep made of two parts, from the parts' chords (which meet).
#[inline(always)]
fn join(a: Option<(f64, f64)>, b: Option<(f64, f64)>) -> Option<(f64, f64)> {
    match (a, b) {
        (Some((a, b)), Some((c, d))) => Some((lesser(a, c), greater(b, d))),
        (a, b) => a.or(b),
    }
}

/// `(lo, hi)` cut down to where `a ≤ q + λ·g ≤ b`, with `inv` = 1/g (infinite when the ray
/// runs across that axis: then the bounds are ±∞, or NaN when `q` lies on a face's plane,
/// decided by `q` alone).
#[inline(always)]
fn clip((lo, hi): (f64, f64), q: f64, (inv, a, b): (f64, f64, f64)) -> (f64, f64) {
    let (t0, t1) = ((a - q) * inv, (b - q) * inv);
    if t0.is_nan() || t1.is_nan() {
        return if (a..=b).contains(&q) {
            (lo, hi)
        } else {
            (lo, f64::NEG_INFINITY)
        };
    }
    (greater(lo, lesser(t0, t1)), lesser(hi, greater(t0, t1)))
}
