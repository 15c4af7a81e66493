//! Closed-form kernels for the common case, chosen once per profile and once per move: a
//! profile that is a cylinder slab (flat end mill, shank), a sphere on a cylinder slab (ball
//! end mill) or a lozenge on one (bull-nose), on a move whose tool axis is a world axis, against
//! rays along world axes (the dexels).
//!
//! The bull-nose's corner is the lozenge `L = D ⊕ B(r)` (`D` the disc of radius `e` at the
//! spine's height; `lozenge.rs`). Moved across the axis or along it, `D` sweeps the product
//! `P × I` of a plane set `P` (the stadium of radius `e` about the spine centre's path, or the
//! disc) and a height interval `I`, so `dist(x, P × I)² = d_P(x)² + d_I(x)²` and the swept
//! lozenge is `{d_P² + d_I² ≤ r²}`: a ray along the axis (fixed `d_P`) leaves it at
//! `min I − √(r² − d_P²)`, a ray across it (fixed `d_I`) is inside where `d_P ≤ √(r² − d_I²)`,
//! the chord of the stadium of radius `e + √(r² − d_I²)`. A ramp mixes the two: its swept
//! lozenge is the general path's (`lozenge.rs`: Newton steps on a convex distance), in the
//! move's frame, and only where the slab's closed form cannot settle the ray. They compute the same exact interval as the general candidates of
//! [`super::SweptConvex::line_interval`] with a few square roots, and the property tests
//! (`tests/fast_paths.rs`) hold them to it.
//!
//! This module is the one dispatch point: [`FastProfile::classify`] decides what a profile
//! is, [`FastSweep::new`] whether a move qualifies, [`FastSweep::dexel`] answers the query.

use super::capsule::line_capsule;
use super::lozenge;
use super::planar::PlanarMember;
use super::slab::{self, AxisMove};
use super::{ConvexProfile, Element};
use swarf_geom::math::{greater, lesser, Vec3};
use swarf_geom::Frame;

/// Relative tolerance with which profile parameters are taken as equal when a profile is
/// classified (far below any geometric effect: 1e-12 of the tool size).
const CLASSIFY_EPS: f64 = 1e-12;

/// What a convex profile is, for the closed-form kernels. The solid is exactly the union of
/// the listed parts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct FastProfile {
    /// The lozenge `(e, f, r)` of a ball (`e = 0`: a whole sphere) or bull-nose end: the
    /// points within `r` of the disc of radius `e` at height `f`. Its upper half lies in the
    /// slab, which starts at `f`.
    pub(crate) lozenge: Option<(f64, f64, f64)>,
    /// The slab `(radius, z0, z1)`.
    pub(crate) slab: (f64, f64, f64),
}

impl FastProfile {
    /// Recognises a slab (disc, cylinder, disc), a ball end (sphere arc from the tip to the
    /// equator, cylinder of the same radius, disc) and a bull-nose end (disc, quarter torus
    /// tangent to it and to the side, cylinder, disc) whose cylinder reaches at least `r` above
    /// the arc's centre, so that the solid is the union of the whole lozenge and the slab.
    pub(crate) fn classify(els: &[Element]) -> Option<FastProfile> {
        let same = |a: f64, b: f64, scale: f64| (a - b).abs() <= CLASSIFY_EPS * scale.max(1.0);
        let side_and_top = |els: &[Element], r: f64, z0: f64| -> Option<f64> {
            let [Element::Line { p: sp, q: sq }, Element::Line { p: tp, q: tq }] = els else {
                return None;
            };
            let ok = same(sp.x, r, r)
                && same(sq.x, r, r)
                && same(sp.y, z0, r)
                && sq.y > sp.y
                && same(tp.x, r, r)
                && same(tp.y, sq.y, r)
                && tq.x == 0.0
                && tq.y == tp.y;
            ok.then_some(sq.y)
        };
        // A quarter arc from the bottom (radius `e0` there, at height `z0`) to the side.
        let rounded = |els: &[Element], e0: f64, z0: f64| -> Option<FastProfile> {
            let [Element::Arc {
                e,
                f,
                r,
                phi0,
                phi1,
            }, rest @ ..] = els
            else {
                return None;
            };
            let ok = same(*e, e0, *r)
                && same(*f, z0 + r, *r)
                && *phi0 == 0.0
                && same(*phi1, std::f64::consts::FRAC_PI_2, 1.0)
                && *r > 0.0;
            if !ok {
                return None;
            }
            let z1 = side_and_top(rest, e + r, *f)?;
            (z1 >= f + r).then_some(FastProfile {
                lozenge: Some((*e, *f, *r)),
                slab: (e + r, *f, z1),
            })
        };
        match els {
            [Element::Line { p, q }, rest @ ..] => {
                let (r, z0) = (q.x, q.y);
                if !(p.x == 0.0 && p.y == q.y && r > 0.0) {
                    return None;
                }
                if let Some(bull) = rounded(rest, r, z0) {
                    return Some(bull);
                }
                let z1 = side_and_top(rest, r, z0)?;
                Some(FastProfile {
                    lozenge: None,
                    slab: (r, z0, z1),
                })
            }
            [Element::Arc { e, f, r, .. }, ..] if *e == 0.0 => rounded(els, 0.0, f - r),
            _ => None,
        }
    }

    /// The sphere `(centre height, radius)` of a ball end.
    pub(crate) fn sphere(&self) -> Option<(f64, f64)> {
        self.lozenge
            .and_then(|(e, f, r)| (e == 0.0).then_some((f, r)))
    }
}

/// A move prepared for the closed-form kernels: tool axis `+e_kt`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FastSweep {
    /// The bull-nose's lozenge `(e, r)` and the spine centre's heights `I` (world, along the
    /// axis), when the profile has one (`e > 0`).
    lozenge: Option<(f64, f64, (f64, f64))>,
    /// On a ramp: the move's frame (tip at the origin, `x` across the axis along the move) and
    /// the move in it, `(a, 0, b)`, for the swept lozenge of `lozenge.rs`.
    ramp: Option<(Frame, Vec3)>,
    kt: usize,
    shape: FastProfile,
    mv: AxisMove,
    /// Sphere centre at the start and the move (world), when the profile has a sphere.
    c0: Vec3,
    delta: Vec3,
}

impl FastSweep {
    /// The kernels for `prof` placed at `tip` with axis `+e_kt` moving by `delta`, when the
    /// profile qualifies.
    pub(crate) fn new(prof: &ConvexProfile, kt: usize, tip: Vec3, delta: Vec3) -> Option<Self> {
        let shape = prof.fast()?;
        let (u, w) = ((kt + 1) % 3, (kt + 2) % 3);
        let (mut lozenge, mut ramp) = (None, None);
        if let Some((e, f, r)) = shape.lozenge.filter(|l| l.0 > 0.0) {
            let h = tip[kt] + f;
            lozenge = Some((e, r, (h + delta[kt].min(0.0), h + delta[kt].max(0.0))));
            // A ramp's swept lozenge is no product (the caller's move frame snaps a negligible
            // part of either kind to exactly zero).
            let mut across = delta;
            across[kt] = 0.0;
            if across != Vec3::ZERO && delta[kt] != 0.0 {
                let frame = Frame::from_axis_and_x(tip, Vec3::AXES[kt], across);
                ramp = Some((frame, Vec3::new(across.length(), 0.0, delta[kt])));
            }
        }
        let c0 = tip + Vec3::AXES[kt] * shape.sphere().map_or(0.0, |s| s.0);
        Some(Self {
            lozenge,
            ramp,
            kt,
            shape,
            mv: AxisMove {
                p: [tip[u], tip[w], tip[kt]],
                m: [delta[u], delta[w], delta[kt]],
            },
            c0,
            delta,
        })
    }

    /// A ball end's move seen in its plane by the rays along world axis `k`, when that plane
    /// is normal to them (`planar.rs`).
    pub(crate) fn planar(&self, k: usize) -> Option<PlanarMember> {
        let (f, r) = self.shape.sphere()?;
        PlanarMember::new(k, self.kt, self.c0, self.delta, (f, r, self.shape.slab.2))
    }

    /// The constants shared by all rays along world axis `k`.
    pub(crate) fn rays(&self, k: usize) -> FastRays {
        let (r, z0, z1) = self.shape.slab;
        let (pa, ma) = (self.mv.p[2], self.mv.m[2]);
        let fu = (k + 1) % 3;
        let sphere = self
            .shape
            .sphere()
            .map(|(_, sr)| CapsuleRays::new(k, self.c0, self.delta, sr));
        let end = match (sphere, self.lozenge, self.ramp) {
            (Some(c), _, _) => Some(RoundEnd::Sphere(c)),
            (None, Some((e, lr, _)), Some((frame, v))) => Some(RoundEnd::Ramp(RampRays::new(
                (e, self.shape.lozenge.map_or(0.0, |l| l.1), lr),
                frame,
                v,
                k,
            ))),
            (None, Some((e, lr, heights)), None) => Some(RoundEnd::Lozenge(LozengeRays {
                e,
                r: lr,
                heights,
                mv: self.mv,
            })),
            (None, None, _) => None,
        };
        if k == self.kt {
            let (mu, mw) = (self.mv.m[0], self.mv.m[1]);
            let aa = mu * mu + mw * mw;
            return FastRays::Along(AlongRays {
                mv: self.mv,
                inv_aa: if aa > 0.0 { 1.0 / aa } else { 0.0 },
                r,
                z0,
                z1,
                hi_min: pa + z1 + ma.min(0.0),
                // (Under a bull-nose: the lowest spine height less r, without the parabola.)
                low_base: match (self.shape.sphere(), self.lozenge) {
                    (Some((f, sr)), _) => pa + f + ma.min(0.0) - sr,
                    (None, Some((_, lr, heights))) => heights.0 - lr,
                    (None, None) => pa + z0 + ma.min(0.0),
                },
                low_k: self.shape.sphere().map_or(0.0, |(_, sr)| 0.5 / sr),
                end,
            });
        }
        let ray = if k == (self.kt + 1) % 3 { 0 } else { 1 };
        let o = 1 - ray;
        let full = Stadium::new(
            (self.mv.p[ray], self.mv.p[o]),
            (self.mv.m[ray], self.mv.m[o]),
            r,
        );
        // Heights where the rounded end may stick out of the slab's sweep: from its lowest
        // point to the highest centre (above it every section lies in the slab's disc of the
        // same position).
        let end_band = match (self.shape.sphere(), self.lozenge) {
            (Some((_, sr)), _) => (
                self.c0[self.kt] + ma.min(0.0) - sr,
                self.c0[self.kt] + ma.max(0.0),
            ),
            (None, Some((_, lr, heights))) => (heights.0 - lr, heights.1),
            (None, None) => (f64::INFINITY, f64::NEG_INFINITY),
        };
        FastRays::Across(AcrossRays {
            height_is_u: fu == self.kt,
            ray,
            mv: self.mv,
            r,
            z0,
            z1,
            full_band: (pa + z0 + ma.max(0.0), pa + z1 + ma.min(0.0)),
            band: (pa + z0 + ma.min(0.0), pa + z1 + ma.max(0.0)),
            full,
            end_band,
            end,
        })
    }
}

/// The kernels of one sweep for the rays along one world axis.
#[derive(Clone, Copy, Debug)]
pub(crate) enum FastRays {
    /// Rays along the tool axis.
    Along(AlongRays),
    /// Rays across it.
    Across(AcrossRays),
}

impl FastRays {
    /// The interval of the ray whose coordinates on the family's cross axes (`(k+1) % 3`,
    /// `(k+2) % 3`, `k` the rays' axis) are `(cu, cv)`, in world coordinates along the ray.
    /// With `material = Some((lo, hi))`, the ray's material lies in `[lo, hi]` and the result
    /// is exact where it meets that range (an end beyond the material may be replaced by a
    /// cheaper bound beyond it).
    #[inline]
    pub(crate) fn interval(
        &self,
        cu: f64,
        cv: f64,
        material: Option<(f64, f64)>,
    ) -> Option<(f64, f64)> {
        match self {
            FastRays::Along(a) => a.interval(cu, cv, material),
            FastRays::Across(a) => a.interval(cu, cv),
        }
    }
}

/// A chord that misses, where the kernels' chords are plain pairs: an `Option<(f64, f64)>`
/// that the optimiser cannot keep in registers is assembled in memory with 8-byte stores and
/// read back as one 16-byte load, which stalls on store forwarding (11–12 % of the finishing
/// kernel's samples, at whichever option came through memory). A miss is tested on the lower
/// end (`lo.is_nan()`); options are made only for the result.
const MISS: (f64, f64) = (f64::NAN, f64::NAN);

/// A capsule (swept sphere) against the lines along x through `(0, y, z)`, in a rays' family
/// frame.
#[derive(Clone, Copy, Debug)]
pub(crate) struct CapsuleRays {
    c0: Vec3,
    ba: Vec3,
    baba: f64,
    /// `ba·d`.
    bard: f64,
    /// `|ba × d|²`.
    a: f64,
    rr: f64,
}

impl CapsuleRays {
    /// The capsule of radius `r` about the segment from `c0` by `delta` (world), for the rays
    /// along world axis `k`.
    pub(crate) fn new(k: usize, c0: Vec3, delta: Vec3, r: f64) -> Self {
        // Held in the family's frame (along the rays, then its two cross axes), where the
        // rays run along x from x = 0.
        let (fu, fv) = ((k + 1) % 3, (k + 2) % 3);
        let perm = |x: Vec3| Vec3::new(x[k], x[fu], x[fv]);
        let baba = delta.length_squared();
        let bard = delta[k];
        CapsuleRays {
            c0: perm(c0),
            ba: perm(delta),
            baba,
            bard,
            a: baba - bard * bard,
            rr: r * r,
        }
    }

    /// The capsule's interval on the line through `o` along `d` (world coordinates along
    /// `d`), computed as [`line_capsule`] does with the direction's constants shared.
    /// (Inlined: out of line, its pair came back through memory, and it is the hot kernel of
    /// a ball's 3-axis cut.)
    #[inline(always)]
    pub(crate) fn interval<const LOW_ONLY: bool>(&self, cu: f64, cv: f64) -> Option<(f64, f64)> {
        let (lo, hi) = self.ends::<LOW_ONLY>(cu, cv);
        (!lo.is_nan()).then_some((lo, hi))
    }

    /// The line along the segment (no side to cross): [`line_capsule`], a miss as [`MISS`].
    #[cold]
    #[inline(never)]
    fn along<const LOW_ONLY: bool>(&self, cu: f64, cv: f64) -> (f64, f64) {
        let o = Vec3::new(0.0, cu, cv);
        line_capsule::<LOW_ONLY>(o, Vec3::X, self.c0, self.ba, self.rr.sqrt()).unwrap_or(MISS)
    }

    /// [`CapsuleRays::interval`] as a plain pair, a miss as [`MISS`].
    #[inline(always)]
    fn ends<const LOW_ONLY: bool>(&self, cu: f64, cv: f64) -> (f64, f64) {
        if self.a <= 1e-20 * self.baba {
            return self.along::<LOW_ONLY>(cu, cv);
        }
        // Re-based at the point of the line level with c0: oa = (0, oy, oz) ⊥ the line
        // (components written out: IEEE products by the zeros of a unit vector do not fold).
        let t0 = self.c0.x;
        let (oy, oz) = (cu - self.c0.y, cv - self.c0.z);
        let (ba, baba, bard, a, rr) = (self.ba, self.baba, self.bard, self.a, self.rr);
        let baoa = ba.y * oy + ba.z * oz;
        let oaoa = oy * oy + oz * oz;
        let b = -baoa * bard;
        let c = baba * oaoa - baoa * baoa - rr * baba;
        let h = b * b - a * c;
        if h < 0.0 {
            return MISS;
        }
        // Which piece holds each end, decided before any square root: the side's crossing
        // t = (−b ∓ √h)/a projects on the segment at y = baoa + t·bard, i.e.
        // a·y = L ∓ bard·√h with L = baoa·a − bard·b; an end projecting beyond the segment
        // lies on that end's sphere (one square root, no side root at all).
        let l = baoa * a - bard * b;
        let bh2 = bard * bard * h;
        // x ≤ s·bard·√h, for s = ±1.
        let le = |x: f64, s: f64| {
            if s * bard >= 0.0 {
                x <= 0.0 || x * x <= bh2
            } else {
                x <= 0.0 && x * x >= bh2
            }
        };
        // 0: the start sphere, 1: the end sphere, 2: the side; for the end with
        // a·y = L + s·bard·√h (s = −1 near, +1 far): y ≤ 0 iff L ≤ −s·bard·√h, y > |ba|² iff
        // L − |ba|²·a > −s·bard·√h.
        let piece = |s: f64| {
            if le(l, -s) {
                0
            } else if !le(l - baba * a, -s) {
                1
            } else {
                2
            }
        };
        // The chord of the sphere centred at (−x, −y, −z) from the line's base point.
        let chord = |x: f64, y: f64, z: f64| -> (f64, f64) {
            let h = rr - (y * y + z * z);
            if h >= 0.0 {
                let s = h.sqrt();
                (-x - s, -x + s)
            } else {
                MISS
            }
        };
        let side = || -> (f64, f64) {
            // Cancellation-free roots q/a and c/q, (near, far).
            let sh = h.sqrt();
            let q = if b > 0.0 { -(b + sh) } else { -b + sh };
            let other = if q != 0.0 { c / q } else { 0.0 };
            if b > 0.0 {
                (q / a, other)
            } else {
                (other, q / a)
            }
        };
        let at = |p: u8| -> (f64, f64) {
            match p {
                0 => chord(0.0, oy, oz),
                1 => chord(-ba.x, oy - ba.y, oz - ba.z),
                _ => side(),
            }
        };
        let pn = piece(-1.0);
        let (lo, hi) = if LOW_ONLY {
            let lo = at(pn).0;
            (lo, lo)
        } else {
            let pf = piece(1.0);
            if pn == pf {
                // Both ends on one piece: one square root.
                at(pn)
            } else {
                let ((lo, _), (_, hi)) = (at(pn), at(pf));
                if lo.is_nan() || hi.is_nan() {
                    return MISS;
                }
                (lo, hi)
            }
        };
        (lo + t0, hi + t0)
    }
}

/// The rounded end of a ball or bull-nose, swept, for one family of rays.
#[derive(Clone, Copy, Debug)]
pub(crate) enum RoundEnd {
    /// A ball's sphere: a capsule.
    Sphere(CapsuleRays),
    /// A bull-nose's lozenge moved across the axis or along it.
    Lozenge(LozengeRays),
    /// A bull-nose's lozenge on a ramp.
    Ramp(RampRays),
}

impl RoundEnd {
    /// Where a ray along the tool axis through `(qu, qw)`, `rho2` squared from the tip's path
    /// across the axis, enters it (world, along the axis).
    #[inline(always)]
    fn lower(&self, qu: f64, qw: f64, rho2: f64) -> Option<f64> {
        match self {
            RoundEnd::Sphere(c) => c.interval::<true>(qu, qw).map(|(l, _)| l),
            RoundEnd::Lozenge(l) => l.lower(rho2),
            RoundEnd::Ramp(l) => l.chord(qu, qw).map(|(lo, _)| lo),
        }
    }

    /// The chord of the ray through `(cu, cv)` across the tool axis (along cross axis `ray`,
    /// at height `za`, `q` its other cross coordinate), a miss as [`MISS`].
    #[inline(always)]
    fn across(&self, (cu, cv): (f64, f64), ray: usize, za: f64, q: f64) -> (f64, f64) {
        match self {
            RoundEnd::Sphere(c) => c.ends::<false>(cu, cv),
            RoundEnd::Lozenge(l) => l.across(ray, za, q).unwrap_or(MISS),
            RoundEnd::Ramp(l) => l.chord(cu, cv).unwrap_or(MISS),
        }
    }
}

/// A bull-nose's lozenge (disc radius `e`, tube `r`) swept across the tool axis or along it:
/// its spine centre on the path `mv` (cross coordinates), at heights `heights` (world).
#[derive(Clone, Copy, Debug)]
pub(crate) struct LozengeRays {
    e: f64,
    r: f64,
    heights: (f64, f64),
    mv: AxisMove,
}

impl LozengeRays {
    /// Entry of the ray along the axis at squared distance `rho2` from the spine centre's path
    /// (the tip's, across the axis): `min I − √(r² − d_P²)`, `d_P = (ρ − e)⁺`.
    #[inline]
    fn lower(&self, rho2: f64) -> Option<f64> {
        let dp = greater(rho2.sqrt() - self.e, 0.0);
        let h2 = self.r * self.r - dp * dp;
        (h2 >= 0.0).then(|| self.heights.0 - h2.sqrt())
    }

    /// Chord of the ray across the axis along cross axis `ray` at height `za`, other cross
    /// coordinate `q`: the stadium of radius `e + √(r² − d_I²)` about the spine centre's path.
    #[inline]
    fn across(&self, ray: usize, za: f64, q: f64) -> Option<(f64, f64)> {
        let dz = greater(greater(self.heights.0 - za, za - self.heights.1), 0.0);
        let h2 = self.r * self.r - dz * dz;
        if h2 < 0.0 {
            return None;
        }
        let o = 1 - ray;
        let (p, m) = (self.mv.p, self.mv.m);
        slab::stadium_chord(
            (p[ray], p[o]),
            (p[ray] + m[ray], p[o] + m[o]),
            self.e + h2.sqrt(),
            q,
        )
    }
}

/// A bull-nose's lozenge (disc radius `e` at height `f`, tube `r`) on a ramp `v` (move frame
/// `frame`), against the rays along world axis `k` (direction `d` in the move frame).
#[derive(Clone, Copy, Debug)]
pub(crate) struct RampRays {
    e: f64,
    f: f64,
    r: f64,
    frame: Frame,
    v: Vec3,
    k: usize,
    d: Vec3,
}

impl RampRays {
    /// The lozenge `(e, f, r)` moving by `v` in the move frame `frame` (tip at the origin, the
    /// tool axis `z`), for the rays along world axis `k`.
    pub(crate) fn new((e, f, r): (f64, f64, f64), frame: Frame, v: Vec3, k: usize) -> Self {
        RampRays {
            e,
            f,
            r,
            frame,
            v,
            k,
            d: frame.vector_to_local(Vec3::AXES[k]),
        }
    }

    /// The lower (`upper = false`) or upper end of [`RampRays::chord`], with one walk.
    #[inline]
    pub(crate) fn end(&self, cu: f64, cv: f64, upper: bool) -> Option<f64> {
        let (o, t0) = self.line(cu, cv);
        let t = lozenge::swept_end((self.e, self.f, self.r), o, self.d, self.v, upper)?;
        Some(t + t0)
    }

    /// The chord of the ray through `(cu, cv)` (world coordinates along it).
    #[inline]
    pub(crate) fn chord(&self, cu: f64, cv: f64) -> Option<(f64, f64)> {
        let (o, t0) = self.line(cu, cv);
        let (a, b) = lozenge::swept_interval(self.e, self.f, self.r, o, self.d, self.v)?;
        Some((a + t0, b + t0))
    }

    /// The ray through `(cu, cv)` in the move frame, re-based at its point nearest the tip (a
    /// few mm, not hundreds): that point, and its world coordinate along the ray.
    #[inline(always)]
    fn line(&self, cu: f64, cv: f64) -> (Vec3, f64) {
        let mut o = Vec3::ZERO;
        o[(self.k + 1) % 3] = cu;
        o[(self.k + 2) % 3] = cv;
        let o = self.frame.to_local(o);
        let t0 = -o.dot(self.d);
        (o + self.d * t0, t0)
    }
}

/// Rays along the tool axis.
#[derive(Clone, Copy, Debug)]
pub(crate) struct AlongRays {
    mv: AxisMove,
    inv_aa: f64,
    r: f64,
    z0: f64,
    z1: f64,
    /// The upper end is at least this for every ray that meets the sweep.
    hi_min: f64,
    /// The lower end is at least `low_base + ρ²·low_k` for a ray at distance ρ from the tip
    /// path: `min centre height − r + ρ²/2r` under a sphere (`r − √(r² − ρ²) ≥ ρ²/2r`), the
    /// lowest bottom under a flat slab.
    low_base: f64,
    low_k: f64,
    end: Option<RoundEnd>,
}

impl AlongRays {
    #[inline(always)]
    pub(crate) fn interval(
        &self,
        qu: f64,
        qw: f64,
        material: Option<(f64, f64)>,
    ) -> Option<(f64, f64)> {
        let (du, dw) = (qu - self.mv.p[0], qw - self.mv.p[1]);
        let (mu, mw) = (self.mv.m[0], self.mv.m[1]);
        // The ray meets the sweep iff it is within r of the tip's path (both parts project to
        // that stadium along the axis).
        let s_near = ((du * mu + dw * mw) * self.inv_aa).clamp(0.0, 1.0);
        let (eu, ew) = (du - s_near * mu, dw - s_near * mw);
        let rho2 = eu * eu + ew * ew;
        if rho2 > self.r * self.r {
            return None;
        }
        // Material-first: the sweep's lowest point on this ray is at least `low_base +
        // ρ²·low_k` (ρ the ray's distance from the tip path); material below it is untouched.
        if material.is_some_and(|m| m.1 <= self.low_base + rho2 * self.low_k) {
            return None;
        }
        let (pa, ma) = (self.mv.p[2], self.mv.m[2]);
        // Positions whose disc holds the ray: the slab's ends come from them.
        let span = || slab::disc_params(&self.mv, self.r, qu, qw).unwrap_or((s_near, s_near));
        let need_hi = material.map_or(true, |m| m.1 > self.hi_min);
        let mut spanned = None;
        let hi = if need_hi {
            let (s0, s1) = *spanned.get_or_insert_with(span);
            pa + self.z1 + greater(s0 * ma, s1 * ma)
        } else {
            self.hi_min
        };
        let lo = match self.end.as_ref().and_then(|c| c.lower(qu, qw, rho2)) {
            Some(l) => l,
            None => {
                let (s0, s1) = *spanned.get_or_insert_with(span);
                pa + self.z0 + lesser(s0 * ma, s1 * ma)
            }
        };
        Some((lo, hi))
    }
}

/// Rays across the tool axis: along cross axis `ray` (0 = u, 1 = w) of the tool's frame.
#[derive(Clone, Copy, Debug)]
pub(crate) struct AcrossRays {
    /// True when the family's first cross axis is the tool axis.
    height_is_u: bool,
    ray: usize,
    mv: AxisMove,
    r: f64,
    z0: f64,
    z1: f64,
    /// Heights (world, along the tool axis) at which every position's slab holds the ray.
    full_band: (f64, f64),
    /// Heights at which some position's slab holds it.
    band: (f64, f64),
    /// The cross-section of the whole move's slab sweep at a height of `full_band`.
    full: Stadium,
    /// Heights at which the rounded end may stick out of the slab's sweep.
    end_band: (f64, f64),
    end: Option<RoundEnd>,
}

impl AcrossRays {
    #[inline(always)]
    pub(crate) fn interval(&self, cu: f64, cv: f64) -> Option<(f64, f64)> {
        let (za, q) = if self.height_is_u { (cu, cv) } else { (cv, cu) };
        // The chords as plain pairs up to the result (see `MISS`).
        let a = if za >= self.full_band.0 && za <= self.full_band.1 {
            self.full.chord(q)
        } else if za >= self.band.0 && za <= self.band.1 {
            slab::across(&self.mv, self.r, self.z0, self.z1, self.ray, q, za).unwrap_or(MISS)
        } else {
            MISS
        };
        let (lo, hi) = match &self.end {
            Some(c) if za >= self.end_band.0 && za <= self.end_band.1 => {
                let b = c.across((cu, cv), self.ray, za, q);
                if a.0.is_nan() {
                    b
                } else if b.0.is_nan() {
                    a
                } else {
                    (lesser(a.0, b.0), greater(a.1, b.1))
                }
            }
            _ => a,
        };
        (!lo.is_nan()).then_some((lo, hi))
    }
}

/// A stadium (the points within `r` of a segment) in a plane with coordinates (along the
/// rays, across them), for chords of lines along the first coordinate.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Stadium {
    /// Segment start and vector.
    a: (f64, f64),
    e: (f64, f64),
    inv_ee: f64,
    inv_ey: f64,
    r_el: f64,
    rr: f64,
}

impl Stadium {
    pub(crate) fn new(a: (f64, f64), e: (f64, f64), r: f64) -> Self {
        let ee = e.0 * e.0 + e.1 * e.1;
        Self {
            a,
            e,
            inv_ee: if ee > 0.0 { 1.0 / ee } else { 0.0 },
            inv_ey: if e.1 != 0.0 { 1.0 / e.1 } else { 0.0 },
            r_el: r * ee.sqrt(),
            rr: r * r,
        }
    }

    /// The chord of the end disc centred at `(ca, cb)` on the line at `q`, a miss as [`MISS`].
    #[inline(always)]
    fn disc(&self, ca: f64, cb: f64, q: f64) -> (f64, f64) {
        let dq = q - cb;
        let h2 = self.rr - dq * dq;
        if h2 >= 0.0 {
            let h = h2.sqrt();
            (ca - h, ca + h)
        } else {
            MISS
        }
    }

    /// The chord on the line through `(·, q)` along the first coordinate, a miss as [`MISS`].
    #[inline(always)]
    pub(crate) fn chord(&self, q: f64) -> (f64, f64) {
        let (a, e) = (self.a, self.e);
        let b = (a.0 + e.0, a.1 + e.1);
        if self.e.1 == 0.0 {
            // The segment runs along the line (or is a point): both discs have the same chord
            // half-width.
            let (lo, hi) = self.disc(a.0, a.1, q);
            if lo.is_nan() {
                return MISS;
            }
            return (lesser(lo, lo + e.0), greater(hi, hi + e.0));
        }
        // The strip |(x − a)·ey − (q − a_y)·ex| ≤ r·|e| about the segment's line.
        let dq = q - a.1;
        let x1 = a.0 + (dq * e.0 - self.r_el) * self.inv_ey;
        let x2 = a.0 + (dq * e.0 + self.r_el) * self.inv_ey;
        let (xl, xh) = (lesser(x1, x2), greater(x1, x2));
        // Where each end projects on the segment (0 at a, 1 at b).
        let proj = |x: f64| ((x - a.0) * e.0 + dq * e.1) * self.inv_ee;
        let (yl, yh) = (proj(xl), proj(xh));
        if yl < 0.0 && yh < 0.0 {
            return self.disc(a.0, a.1, q);
        }
        if yl > 1.0 && yh > 1.0 {
            return self.disc(b.0, b.1, q);
        }
        // The line crosses the segment's normal band, so it meets the stadium; an end beyond
        // the band is on that end's disc (which the line meets, up to rounding).
        let end_disc = |y: f64| {
            let (ca, cb) = if y < 0.0 { a } else { b };
            let dq = q - cb;
            (ca, greater(self.rr - dq * dq, 0.0).sqrt())
        };
        let lo = if (0.0..=1.0).contains(&yl) {
            xl
        } else {
            let (c, h) = end_disc(yl);
            c - h
        };
        let hi = if (0.0..=1.0).contains(&yh) {
            xh
        } else {
            let (c, h) = end_disc(yh);
            c + h
        };
        (lo, hi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::swept::test_rng;
    use swarf_tool::Cutter;

    /// With the ray's material range given, the kernels may skip work beyond it: the result
    /// clipped to the material must not change.
    #[test]
    fn material_pruning_keeps_the_material_part_exact() {
        let mut rnd = test_rng(11);
        let mut compared = 0;
        for spec in [
            "ball:d=10",
            "flat:d=6",
            "ball:d=3,flute-length=20",
            "bull:d=10,r=2",
        ] {
            let c = Cutter::from_spec(spec).unwrap();
            let prof = ConvexProfile::from_solid(c.cutting_solid()).unwrap();
            for kt in 0..3 {
                for n in 0..40 {
                    let tip = Vec3::new(rnd(), rnd(), rnd()) * 20.0;
                    let mut delta = Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5) * 8.0;
                    if spec.starts_with("bull") {
                        // Ramps, moves across the axis and along it.
                        match n % 3 {
                            0 => delta = Vec3::AXES[kt] * delta[kt],
                            1 => delta[kt] = 0.0,
                            _ => {}
                        }
                    }
                    let fs = FastSweep::new(&prof, kt, tip, delta).unwrap();
                    for k in 0..3 {
                        let rays = fs.rays(k);
                        for _ in 0..100 {
                            let mut o =
                                tip + Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5) * 24.0;
                            o[k] = 0.0;
                            let (a, b) = ((rnd() - 0.2) * 60.0, (rnd() - 0.2) * 60.0);
                            let m = (a.min(b), a.max(b));
                            let clip = |x: Option<(f64, f64)>| {
                                x.and_then(|(l, h)| {
                                    let (l, h) = (l.max(m.0), h.min(m.1));
                                    (l < h).then_some((l, h))
                                })
                            };
                            let (cu, cv) = (o[(k + 1) % 3], o[(k + 2) % 3]);
                            let full = clip(rays.interval(cu, cv, None));
                            let pruned = clip(rays.interval(cu, cv, Some(m)));
                            match (full, pruned) {
                                (None, None) => {}
                                (Some(f), Some(p)) => {
                                    assert!(
                                        (f.0 - p.0).abs() < 1e-12 && (f.1 - p.1).abs() < 1e-12,
                                        "{spec} {f:?} {p:?}"
                                    );
                                    compared += 1;
                                }
                                (f, p) => panic!("{spec}: full {f:?} vs pruned {p:?}"),
                            }
                        }
                    }
                }
            }
        }
        assert!(compared > 2000, "{compared}");
    }
}
