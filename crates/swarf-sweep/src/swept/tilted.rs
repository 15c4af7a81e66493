//! Closed form for a slab (flat end mill, a band of one, a shank) or a ball end moving along a
//! segment with its axis fixed at **any** direction, against the dexel rays: the tilted
//! fixed-axis moves of 3+2 programs and the fixed-axis pieces a 5-axis move of a flat end mill
//! is cut as, which otherwise take the general candidates (`line_interval`).
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
//! the centre; the sweep of the whole is convex, so the two chords of a line join into one.
//! The property tests (`tests/fast_paths.rs`) hold both to the general candidates.

use super::fast::{CapsuleRays, FastProfile};
use super::BAND_EPS;
use swarf_geom::math::{greater, lesser, Vec3};
use swarf_geom::Frame;

/// Tolerance on the move parameter `s` (dimensionless; `BAND_EPS` over a move of 1 mm).
const S_EPS: f64 = 1e-12;

/// A slab or ball-end profile moving with its axis fixed off the world axes.
#[derive(Clone, Copy, Debug)]
pub(crate) struct TiltedSweep {
    shape: FastProfile,
    /// The move frame: tip at the start, `z` the tool axis, `x` along the move's part across it.
    frame: Frame,
    /// The move in the move frame, `(a, 0, b)`.
    v: Vec3,
}

impl TiltedSweep {
    /// The closed form for `shape` in the move frame `frame`, moving by `v` (move frame), when
    /// the shape is a slab or a ball end (not a bull-nose's lozenge).
    pub(crate) fn new(shape: FastProfile, frame: Frame, v: Vec3) -> Option<Self> {
        match shape.lozenge {
            None => Some(Self { shape, frame, v }),
            Some(_) if shape.sphere().is_some() => Some(Self { shape, frame, v }),
            Some(_) => None,
        }
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
        let sphere = self.shape.sphere().map(|(zc, sr)| {
            let c0 = f.origin + f.z * zc;
            CapsuleRays::new(k, c0, f.vector_to_world(self.v), sr + grow)
        });
        let (r, z0, z1) = (r + grow, z0 - grow, z1 + grow);
        let (a, b) = (self.v.x, self.v.z);
        let e = BAND_EPS;
        let below = if sphere.is_some() { r } else { 0.0 };
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
            x: at(f.x),
            y: at(f.y),
            z: at(f.z),
            g: (f.x[k], f.y[k], f.z[k]),
            a,
            b,
            ext: 2.0 * r + (z1 - z0) + a.abs() + b.abs(),
            r,
            z0,
            z1,
            sphere,
        }
    }
}

/// One sweep's closed form for the rays along one world axis (see [`TiltedSweep::rays`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct TiltedRays {
    /// The move frame's `x`, `y`, `z` coordinates of the ray origin `(cu, cv)`:
    /// `base + cu·du + cv·dv`.
    x: (f64, f64, f64),
    y: (f64, f64, f64),
    z: (f64, f64, f64),
    /// The ray direction in the move frame.
    g: (f64, f64, f64),
    /// The move, `(a, 0, b)` in the move frame.
    a: f64,
    b: f64,
    /// A length beyond the sweep's size (its box's diagonal and more).
    ext: f64,
    /// The slab: radius and heights.
    r: f64,
    z0: f64,
    z1: f64,
    /// A ball end's capsule.
    sphere: Option<CapsuleRays>,
    /// The sweep's box in the move frame, per axis: `(1/g, lo, hi)` (`1/g` infinite for a ray
    /// across that axis).
    slabs: [(f64, f64, f64); 3],
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
        let (mut l0, mut l1) = (first, last);
        // a ≤ q + λ·g ≤ b with `inv` = 1/g (infinite when the ray runs across that axis:
        // then the bounds are ±∞, or NaN when q lies on a face's plane, decided by q alone).
        let mut clip = |q: f64, (inv, a, b): (f64, f64, f64)| {
            let (t0, t1) = ((a - q) * inv, (b - q) * inv);
            if t0.is_nan() || t1.is_nan() {
                if !(a..=b).contains(&q) {
                    l1 = f64::NEG_INFINITY;
                }
                return;
            }
            l0 = greater(l0, lesser(t0, t1));
            l1 = lesser(l1, greater(t0, t1));
        };
        clip(q.0, self.slabs[0]);
        clip(q.1, self.slabs[1]);
        clip(q.2, self.slabs[2]);
        if l0 > l1 {
            return (false, None);
        }
        (true, self.chord(cu, cv, q))
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
        let Some(c) = &self.sphere else {
            return slab;
        };
        // The two chords of a convex sweep's parts meet: one interval.
        match (slab, c.interval::<false>(cu, cv)) {
            (Some((a, b)), Some((c, d))) => Some((lesser(a, c), greater(b, d))),
            (s, c) => s.or(c),
        }
    }

    /// The swept slab's chord (see the module doc for the candidates), the ray's origin at
    /// `(qx, qy, h0)` in the move frame.
    fn slab(&self, (qx, qy, h0): (f64, f64, f64)) -> Option<(f64, f64)> {
        let (gx, gy, gz) = self.g;
        let (a, b, r, z0, z1) = (self.a, self.b, self.r, self.z0, self.z1);
        let rr = (r + BAND_EPS) * (r + BAND_EPS);
        let in_e = |l: f64, s: f64| {
            let (ux, uy) = (qx + l * gx - s * a, qy + l * gy);
            ux * ux + uy * uy <= rr
        };
        let in_s = |s: f64| (-S_EPS..=1.0 + S_EPS).contains(&s);
        let in_h = |l: f64, s: f64| {
            let h = h0 + l * gz - s * b;
            h >= z0 - BAND_EPS && h <= z1 + BAND_EPS
        };
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        let mut take = |l: f64| {
            lo = lesser(lo, l);
            hi = greater(hi, l);
        };
        // Roots of `A·t² + 2·B·t + C = 0`.
        let roots = |qa: f64, qb: f64, qc: f64| -> Option<(f64, f64)> {
            if qa <= 0.0 {
                return None;
            }
            let disc = qb * qb - qa * qc;
            if disc.is_nan() || disc < 0.0 {
                return None;
            }
            let q = -(qb + qb.signum() * disc.sqrt());
            if q == 0.0 {
                return Some((0.0, 0.0));
            }
            Some((q / qa, qc / q))
        };
        let gg = gx * gx + gy * gy;
        // ∂E on the lines s = 0 and s = 1 (inside H).
        for s in [0.0, 1.0] {
            let px = qx - s * a;
            if let Some((l1, l2)) = roots(gg, gx * px + gy * qy, px * px + qy * qy - r * r) {
                for l in [l1, l2] {
                    if in_h(l, s) {
                        take(l);
                    }
                }
            }
        }
        if gz != 0.0 && gz.abs() * self.ext >= b.abs() {
            // The lines h = z, parametrised by s (λ moves by at most `ext` along them).
            let mu = b / gz;
            for z in [z0, z1] {
                // The line h = z: λ = λz + s·μ.
                let lz = (z - h0) / gz;
                // The parallelogram's corners (inside E).
                for s in [0.0, 1.0] {
                    let l = lz + s * mu;
                    if in_e(l, s) {
                        take(l);
                    }
                }
                // ∂E along it (inside T).
                let (px, py) = (qx + lz * gx, qy + lz * gy);
                let (sx, sy) = (mu * gx - a, mu * gy);
                if let Some((s1, s2)) = roots(
                    sx * sx + sy * sy,
                    px * sx + py * sy,
                    px * px + py * py - r * r,
                ) {
                    for s in [s1, s2] {
                        if in_s(s) {
                            take(lz + s * mu);
                        }
                    }
                }
            }
        } else if b != 0.0 {
            // The lines h = z, nearly level in (λ, s) (the ray nearly across the axis):
            // parametrised by λ, s = sz + λ·ν. ∂E along them, inside T; their corners with
            // T lie where a chord across the caps' planes ends, also ∂E's crossings or
            // beyond E unless T's lines cross ∂E there too (taken above).
            let nu = gz / b;
            for z in [z0, z1] {
                let sz = (h0 - z) / b;
                let (px, ex) = (qx - sz * a, gx - nu * a);
                if let Some((l1, l2)) = roots(
                    ex * ex + gy * gy,
                    px * ex + qy * gy,
                    px * px + qy * qy - r * r,
                ) {
                    for l in [l1, l2] {
                        if in_s(sz + l * nu) {
                            take(l);
                        }
                    }
                }
                if gz != 0.0 {
                    for s in [0.0, 1.0] {
                        let l = (s - sz) / nu;
                        if in_e(l, s) {
                            take(l);
                        }
                    }
                }
            }
        } else if !(h0 >= z0 - BAND_EPS && h0 <= z1 + BAND_EPS) {
            // The ray runs across the axis at a height the slab never reaches.
            return None;
        }
        // ∂E's extremes in λ: y = ±r, u_x = 0.
        if gy != 0.0 && a != 0.0 {
            for y in [-r, r] {
                let l = (y - qy) / gy;
                let s = (qx + l * gx) / a;
                if in_s(s) && in_h(l, s) {
                    take(l);
                }
            }
        }
        (lo <= hi).then_some((lo, hi))
    }
}
