//! A ball end's sweep on the rays normal to the plane of its motion (chords nested from one
//! move to the next) and on the rays along the plane (one span each, closed form), so that a
//! run of moves in one plane can be cut together on those rays.
//!
//! A raster finishing pass (passes along X at fixed Y, a vertical tool) keeps the tool axis and
//! the tip's path in one plane `x_k = c`, normal to one ray family `k` (the Y rays there). A
//! point at `δ` from that plane lies in a ball-end instance — the points within `r` of the
//! segment from the sphere's centre up the axis to the top `z1` — iff `δ² ≤ r² − w² −
//! min(0, h − f)²` (`w` its in-plane distance from the axis, `h` its height over the tip, `f`
//! the centre's height) and `h ≤ z1`. Below the tool's top, that is `δ² ≤ r² − D²` with `D` the
//! in-plane distance from the point to the half-line up from the centre; swept along the move,
//! `D` becomes the distance to the union of those half-lines — the region on and above the
//! centre's path (its epigraph, convex). So every ray of family `k` meets the sweep in the chord
//! `c ± √(r² − D²)`, centred on the plane, and the sweeps of several moves in the same plane
//! meet it in nested chords: the widest is their union, and the next move changes the ray only
//! if its `D` is smaller than every earlier one's and than the air about the plane allows. The
//! stock's batched cut (`cut_planar`, `swarf-stock/src/tridexel.rs`) visits each ray once for a
//! run of such moves and computes a move's chord only where its bound ([`KeyBound`]) can beat
//! that.
//!
//! The rays of the family along the plane's other axis (`x`, across the tool axis: the X rays
//! of that raster) lie in planes parallel to the motion's: at `δ` from it and height `z`, a ray
//! meets the sweep where `D(x, z) ≤ √(r² − δ²)`, one interval of `x`
//! ([`PlanarMember::line_span`], closed form). The stock's batched cut (`cut_along`) visits
//! each such ray once for a run too, and measures each move's share of the spans.
//!
//! Exactly the chord of [`super::SweptConvex::axis_ray_interval`] (to rounding) where the ray
//! lies below the tool's lowest top over the move ([`PlanarMember::top`]); the caller keeps to
//! that.

use swarf_geom::math::{greater, lesser};

/// A bound on [`PlanarMember::dist2`] in a ray's cross coordinates, without computing it: at
/// least `eu² + ev²`, `eu`, `ev` how far `cu`, `cv` lie outside the ranges `u` and `v`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KeyBound {
    /// Range of the first cross coordinate.
    pub u: (f64, f64),
    /// Range of the second.
    pub v: (f64, f64),
}

impl KeyBound {
    /// The bound at `(cu, cv)`.
    #[inline(always)]
    pub fn at(&self, cu: f64, cv: f64) -> f64 {
        let eu = greater(greater(self.u.0 - cu, cu - self.u.1), 0.0);
        let ev = greater(greater(self.v.0 - cv, cv - self.v.1), 0.0);
        eu * eu + ev * ev
    }

    /// The smallest bound that is at most both `self` and `other` anywhere: the bound of the
    /// hull of their ranges.
    #[inline]
    pub fn hull(self, other: KeyBound) -> KeyBound {
        KeyBound {
            u: (lesser(self.u.0, other.u.0), greater(self.u.1, other.u.1)),
            v: (lesser(self.v.0, other.v.0), greater(self.v.1, other.v.1)),
        }
    }

    /// The bound over the box `us × vs` of cross coordinates.
    #[inline]
    pub fn over(&self, us: (f64, f64), vs: (f64, f64)) -> f64 {
        let eu = (self.u.0 - us.1).max(us.0 - self.u.1).max(0.0);
        let ev = (self.v.0 - vs.1).max(vs.0 - self.v.1).max(0.0);
        eu * eu + ev * ev
    }
}

/// How the members of a run, in order, move along the plane's axis across the tool axis
/// (`x`): on a raster pass their sphere centres' `x` ranges only advance or only retreat.
/// Then the members a ray's [`KeyBound`] can let through begin where the ranges stop ending
/// more than `√beat` behind the ray. (Where they end, the stock's loop finds from the hull of
/// the later members' bounds, [`KeyBound::hull`].)
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Progress {
    /// Both ends of the ranges never decrease.
    Advancing,
    /// Both ends never increase.
    Retreating,
    /// Neither: every member is checked.
    Mixed,
}

impl Progress {
    /// The progress of the ranges `spans` (`x` ranges, in the run's order).
    pub fn of(spans: &[(f64, f64)]) -> Progress {
        let pairs = || spans.windows(2).map(|w| (w[0], w[1]));
        if pairs().all(|(a, b)| a.0 <= b.0 && a.1 <= b.1) {
            Progress::Advancing
        } else if pairs().all(|(a, b)| a.0 >= b.0 && a.1 >= b.1) {
            Progress::Retreating
        } else {
            Progress::Mixed
        }
    }

    /// The first member of `spans` whose bound at a ray at `x` can be under `beat` (those
    /// before cannot, nor under any smaller `beat`): their ranges end more than `√beat`
    /// behind the ray.
    #[inline(always)]
    pub fn first(self, spans: &[(f64, f64)], x: f64, beat: f64) -> usize {
        // A margin on the square root: a member is left out only where its bound is clearly
        // at least `beat`, so every member left out is one the bound would reject.
        // (A mixed run needs no square root.)
        let reach = || greater(beat, 0.0).sqrt() * (1.0 + 1e-9) + 1e-12;
        match self {
            Progress::Advancing => {
                let behind = x - reach();
                spans.partition_point(|s| s.1 < behind)
            }
            Progress::Retreating => {
                let ahead = x + reach();
                spans.partition_point(|s| s.0 > ahead)
            }
            Progress::Mixed => 0,
        }
    }
}

/// One move of a ball end (sphere on a slab reaching its top) whose tool axis (a world axis)
/// and motion lie in a plane normal to the ray family `k`, seen in that plane: coordinates
/// `x` (the third world axis) and `z` (along the tool axis).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanarMember {
    k: usize,
    kt: usize,
    plane: f64,
    r: f64,
    rr: f64,
    /// The sphere centre's path: start and move.
    x0: f64,
    z0: f64,
    dx: f64,
    dz: f64,
    inv_dx: f64,
    /// `1/(dx² + dz²)` (0 for a vertical or no move): the projection onto the path.
    inv_ll: f64,
    /// `1/dz` (0 for a level move) and `|dx|/√(dx² + dz²)`: the in-plane rays' tangent points
    /// (`line_span`).
    inv_dz: f64,
    slope: f64,
    /// Its extent: `x` range and lowest height.
    xmin: f64,
    xmax: f64,
    zlow: f64,
    /// The tool's lowest top over the move (along the tool axis).
    top: f64,
    /// Whether the family's first cross axis is the tool axis.
    height_is_u: bool,
}

impl PlanarMember {
    /// The member for a ball end of radius `r` whose sphere centre moves from `c0` by `delta`
    /// (world) along tool axis `+e_kt`, `f` over the tip, slab top `z1` over the tip, for the
    /// rays along world axis `k`, when the motion lies in a plane normal to them.
    pub(crate) fn new(
        k: usize,
        kt: usize,
        c0: swarf_geom::math::Vec3,
        delta: swarf_geom::math::Vec3,
        (f, r, z1): (f64, f64, f64),
    ) -> Option<PlanarMember> {
        if k == kt || delta[k] != 0.0 || r.is_nan() || r <= 0.0 {
            return None;
        }
        let a = 3 - k - kt;
        let (x0, z0, dx, dz) = (c0[a], c0[kt], delta[a], delta[kt]);
        let ll = dx * dx + dz * dz;
        Some(PlanarMember {
            k,
            kt,
            plane: c0[k],
            r,
            rr: r * r,
            x0,
            z0,
            dx,
            dz,
            inv_dx: if dx != 0.0 { 1.0 / dx } else { 0.0 },
            inv_ll: if dx != 0.0 { 1.0 / ll } else { 0.0 },
            inv_dz: if dz != 0.0 { 1.0 / dz } else { 0.0 },
            slope: if dx != 0.0 { dx.abs() / ll.sqrt() } else { 0.0 },
            xmin: x0.min(x0 + dx),
            xmax: x0.max(x0 + dx),
            zlow: z0.min(z0 + dz),
            top: z0.min(z0 + dz) - f + z1,
            height_is_u: (k + 1) % 3 == kt,
        })
    }

    /// The plane's coordinate along the rays: every chord is centred on it.
    pub fn plane(&self) -> f64 {
        self.plane
    }

    /// The ball's radius: the widest half-chord.
    pub fn radius(&self) -> f64 {
        self.r
    }

    /// The tool axis (a world axis).
    pub fn tool_axis(&self) -> usize {
        self.kt
    }

    /// The highest coordinate along the tool axis at which a ray's chord is exact: the tool's
    /// lowest top over the move (above it, the flat top would cut the chord short). A run is
    /// cut together only where the stock lies below it.
    pub fn top(&self) -> f64 {
        self.top
    }

    /// Whether `o`'s chords and this one's are nested on every ray: the same family, tool
    /// axis, plane and radius.
    pub fn nests_with(&self, o: &PlanarMember) -> bool {
        self.k == o.k && self.kt == o.kt && self.plane == o.plane && self.r == o.r
    }

    /// The sphere centre path's range along the plane's axis across the tool axis (`x`).
    pub fn span(&self) -> (f64, f64) {
        (self.xmin, self.xmax)
    }

    /// The in-plane point `(x, z)` of the ray through cross coordinates `(cu, cv)`.
    #[inline(always)]
    pub fn point(&self, cu: f64, cv: f64) -> (f64, f64) {
        if self.height_is_u {
            (cv, cu)
        } else {
            (cu, cv)
        }
    }

    /// [`PlanarMember::dist2`]'s bound in cross coordinates: `x` outside the sphere centre
    /// path's range, `z` below its lowest height.
    pub fn bound(&self) -> KeyBound {
        let (x, z) = ((self.xmin, self.xmax), (self.zlow, f64::INFINITY));
        let (u, v) = if self.height_is_u { (z, x) } else { (x, z) };
        KeyBound { u, v }
    }

    /// The squared in-plane distance from `(x, z)` to the region on and above the sphere
    /// centre's path: the ray there meets the sweep in `plane ± √(r² − D²)` when `D² < r²`.
    #[inline(always)]
    pub fn dist2(&self, x: f64, z: f64) -> f64 {
        let (px, pz) = (x - self.x0, z - self.z0);
        if self.dx == 0.0 {
            // A plunge, a lift or no motion: the half-line up from the lower centre.
            let v = greater(self.zlow - z, 0.0);
            return px * px + v * v;
        }
        let s = px * self.inv_dx;
        if (0.0..=1.0).contains(&s) && pz >= s * self.dz {
            return 0.0;
        }
        // Outside: the nearest point of the boundary — the path, or a half-line up from an
        // end the point is level with or above.
        let t = ((px * self.dx + pz * self.dz) * self.inv_ll).clamp(0.0, 1.0);
        let (ex, ez) = (px - t * self.dx, pz - t * self.dz);
        let mut d2 = ex * ex + ez * ez;
        if pz >= 0.0 {
            d2 = lesser(px * px, d2);
        }
        if pz >= self.dz {
            let qx = px - self.dx;
            d2 = lesser(qx * qx, d2);
        }
        d2
    }

    /// [`PlanarMember::dist2`] of the ray through cross coordinates `(cu, cv)`.
    #[inline(always)]
    pub fn key(&self, cu: f64, cv: f64) -> f64 {
        let (x, z) = self.point(cu, cv);
        self.dist2(x, z)
    }

    /// The squared distance a move's must be under to change a ray whose material is the
    /// sorted intervals `ends` (`(enter, exit)`): `r² − gap²`, `gap` the air about the plane;
    /// `None` when no chord can reach the material.
    #[inline(always)]
    pub fn threshold(&self, ends: impl Iterator<Item = (f64, f64)>) -> Option<f64> {
        let c = self.plane;
        let mut gap = f64::INFINITY;
        for (enter, exit) in ends {
            if exit < c {
                gap = c - exit;
            } else {
                gap = lesser(greater(enter - c, 0.0), gap);
                break;
            }
        }
        (gap < self.r).then_some(self.rr - gap * gap)
    }

    /// The chord of a squared distance under `r²`.
    #[inline(always)]
    pub fn chord(&self, d2: f64) -> (f64, f64) {
        let s = greater(self.rr - d2, 0.0).sqrt();
        (self.plane - s, self.plane + s)
    }

    /// The world axis of the rays that lie in planes parallel to the move's (`x`, across the
    /// tool axis): they meet the sweep in [`PlanarMember::line_span`]s.
    pub fn in_plane_axis(&self) -> usize {
        3 - self.k - self.kt
    }

    /// The sphere centre path's lowest height (along the tool axis): an in-plane-axis ray at
    /// height `z` whose section of the sweep has half-width `ρ` (`√(r² − δ²)`, `δ` its offset
    /// from the plane) meets the sweep only if `zlow − z < ρ`.
    pub fn zlow(&self) -> f64 {
        self.zlow
    }

    /// The interval along `x` of the in-plane-axis ray at height `z` (along the tool axis) and
    /// `δ` from the plane, `rho = √(r² − δ²)`, inside the sweep, below the tool's top; `None`
    /// where it misses (`rho` not positive, or the path's lowest centre `rho` or more above
    /// `z`).
    ///
    /// The point `(x, z)` lies within `rho` of the region on and above the centre's path iff it
    /// lies within `rho` of the half-line up from some centre `p(t)`, `t ∈ [0, 1]`: iff
    /// `|x − p_x| ≤ w(g)`, `g = p_z − z`, `w = rho` for `g ≤ 0` and `√(rho² − g²)` for
    /// `0 < g < rho`. So the interval's ends are `min p_x − w` and `max p_x + w` over `t`. `w(g)`
    /// is concave (flat, then a quarter circle with a level tangent at `g = 0`) and `g` affine
    /// in `t`, so `±p_x + w` is concave in `t`: its maximum is where the slope `±dx + w'(g)·dz`
    /// vanishes, `g* = rho·|dx|/√(dx² + dz²)` (the circle's point whose normal is the path's),
    /// clamped to the move, or an end of the move where the slope keeps its sign.
    #[inline(always)]
    pub fn line_span(&self, z: f64, rho: f64) -> Option<(f64, f64)> {
        if rho.is_nan() || rho <= 0.0 || self.zlow - z >= rho {
            return None;
        }
        let g0 = self.z0 - z;
        let (dx, dz) = (self.dx, self.dz);
        // The parameters maximising `∓dx·t + w(g0 + t·dz)` on [0, 1]: with the motion level,
        // the end the motion heads for; else the lower end of the move, where `w` alone
        // decides or where both terms agree (rising against the motion, falling with it), and
        // the tangent point otherwise (the same `g*` for both signs).
        let (tl, th) = if dz == 0.0 {
            let ahead = f64::from(u8::from(dx > 0.0));
            (1.0 - ahead, ahead)
        } else {
            let low = f64::from(u8::from(dz < 0.0));
            // (Not `clamp`: a subnormal `dz` makes `inv_dz` infinite and the product NaN
            // where the numerator is 0; `greater` takes that to the move's start, as `max`
            // would, in one comparison.)
            let tangent = lesser(greater((rho * self.slope - g0) * self.inv_dz, 0.0), 1.0);
            if dx == 0.0 {
                (low, low)
            } else if (dz > 0.0) == (dx > 0.0) {
                (low, tangent)
            } else {
                (tangent, low)
            }
        };
        let w = |t: f64| {
            let g = g0 + t * dz;
            if g <= 0.0 {
                rho
            } else {
                greater(rho * rho - g * g, 0.0).sqrt()
            }
        };
        Some((self.x0 + tl * dx - w(tl), self.x0 + th * dx + w(th)))
    }
}

#[cfg(test)]
mod tests {
    use super::PlanarMember;
    use crate::swept::test_rng;
    use crate::{ConvexProfile, SweptConvex};
    use swarf_geom::math::Vec3;
    use swarf_tool::Cutter;

    /// Against the per-move exact kernel, for random moves in planes normal to each family
    /// and random rays below the tool's top (half of them within 1 mm of it).
    #[test]
    fn chords_are_the_exact_kernels() {
        let mut rnd = test_rng(7);
        let mut compared = (0, 0);
        for spec in [
            "ball:d=10",
            "ball:d=3,flute-length=20",
            "ball:d=12",
            "ball:d=10,flute-length=10",
        ] {
            let c = Cutter::from_spec(spec).unwrap();
            let prof = ConvexProfile::from_solid(c.cutting_solid()).unwrap();
            for kt in 0..3 {
                for k in (0..3).filter(|&k| k != kt) {
                    for n in 0..60 {
                        let tip = Vec3::new(rnd(), rnd(), rnd()) * 20.0;
                        let mut delta = Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5) * 6.0;
                        delta[k] = 0.0;
                        match n % 4 {
                            0 => delta[3 - k - kt] = 0.0,
                            1 => delta[kt] = 0.0,
                            2 => delta = Vec3::ZERO,
                            _ => {}
                        }
                        let sw = SweptConvex::new(&prof, tip, Vec3::AXES[kt], delta);
                        let m: PlanarMember = sw.planar(k).expect("a ball in the plane");
                        let bound = m.bound();
                        for i in 0..200 {
                            let mut o =
                                tip + Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5) * 24.0;
                            o[k] = 0.0;
                            // Every other ray within 1 mm under the tool's top, where a wrong
                            // top would show (the short flute's: the sphere's top).
                            if i % 2 == 1 {
                                o[kt] = m.top() - rnd();
                            }
                            if o[kt] > m.top() {
                                continue;
                            }
                            let (cu, cv) = (o[(k + 1) % 3], o[(k + 2) % 3]);
                            let (x, z) = m.point(cu, cv);
                            assert!(bound.at(cu, cv) <= m.dist2(x, z) + 1e-12);
                            let exact = sw.axis_ray_interval(o, k);
                            let d2 = m.dist2(x, z);
                            let mine = (d2 < m.radius() * m.radius()).then(|| m.chord(d2));
                            match (exact, mine) {
                                (Some(e), Some(p)) => {
                                    assert!(
                                        (e.0 - p.0).abs() < 1e-9 && (e.1 - p.1).abs() < 1e-9,
                                        "{spec} kt {kt} k {k}: {e:?} vs {p:?}"
                                    );
                                    compared.0 += 1;
                                }
                                (None, None) => compared.1 += 1,
                                // A graze: a chord of (numerically) no length either way.
                                (Some(e), None) => assert!(e.1 - e.0 < 1e-6, "{e:?}"),
                                (None, Some(p)) => assert!(p.1 - p.0 < 1e-6, "{p:?}"),
                            }
                        }
                    }
                }
            }
        }
        assert!(compared.0 > 5000 && compared.1 > 5000, "{compared:?}");
    }

    /// The in-plane rays' spans against the per-move exact kernel: random moves in planes normal
    /// to each family, rays along the plane's other axis at random heights (a third within 1 mm
    /// under the tool's top) and offsets from the plane (a third within 0.2 mm of the section's
    /// edge, where the span shrinks to a point).
    #[test]
    fn line_spans_are_the_exact_kernels() {
        let mut rnd = test_rng(11);
        let mut compared = (0, 0);
        for spec in [
            "ball:d=10",
            "ball:d=3,flute-length=20",
            "ball:d=10,flute-length=10",
        ] {
            let c = Cutter::from_spec(spec).unwrap();
            let prof = ConvexProfile::from_solid(c.cutting_solid()).unwrap();
            for kt in 0..3 {
                for k in (0..3).filter(|&k| k != kt) {
                    let a = 3 - k - kt;
                    for n in 0..80 {
                        let tip = Vec3::new(rnd(), rnd(), rnd()) * 20.0;
                        let mut delta = Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5) * 6.0;
                        delta[k] = 0.0;
                        match n % 5 {
                            0 => delta[a] = 0.0,
                            1 => delta[kt] = 0.0,
                            2 => delta = Vec3::ZERO,
                            _ => {}
                        }
                        let sw = SweptConvex::new(&prof, tip, Vec3::AXES[kt], delta);
                        let m: PlanarMember = sw.planar(k).expect("a ball in the plane");
                        assert_eq!(m.in_plane_axis(), a);
                        let r = m.radius();
                        for i in 0..150 {
                            let mut o =
                                tip + Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5) * 24.0;
                            let off = match i % 3 {
                                0 => (r - 0.2 * rnd()) * if rnd() < 0.5 { -1.0 } else { 1.0 },
                                _ => (rnd() - 0.5) * 2.2 * r,
                            };
                            o[k] = m.plane() + off;
                            if i % 3 == 1 {
                                o[kt] = m.top() - rnd();
                            }
                            if o[kt] > m.top() {
                                continue;
                            }
                            let exact = sw.axis_ray_interval(o, a);
                            let rho = (r * r - off * off).max(0.0).sqrt();
                            let mine = if off.abs() < r {
                                m.line_span(o[kt], rho)
                            } else {
                                None
                            };
                            match (exact, mine) {
                                (Some(e), Some(p)) => {
                                    assert!(
                                        (e.0 - p.0).abs() < 1e-9 && (e.1 - p.1).abs() < 1e-9,
                                        "{spec} kt {kt} k {k} n {n}: {e:?} vs {p:?}"
                                    );
                                    compared.0 += 1;
                                }
                                (None, None) => compared.1 += 1,
                                // A graze: a span of (numerically) no length either way.
                                (Some(e), None) => assert!(e.1 - e.0 < 1e-6, "{e:?}"),
                                (None, Some(p)) => assert!(p.1 - p.0 < 1e-6, "{p:?}"),
                            }
                        }
                    }
                }
            }
        }
        assert!(compared.0 > 5000 && compared.1 > 3000, "{compared:?}");
    }

    /// The stock's planar loop leaves out only members whose bound is at least the ray's
    /// `beat`: before `Progress::first` and, once the hull of the later members' bounds fails,
    /// every later one — on advancing, retreating and mixed sequences of ranges, with rays
    /// inside, between and beyond them, and beats down to ranges' distances (where a rounding
    /// would show).
    #[test]
    fn progress_leaves_out_only_members_that_cannot_beat() {
        use super::{KeyBound, Progress};
        let mut rnd = test_rng(9);
        let mut seen = [0usize; 3];
        let (mut skipped, mut broken) = (0, 0);
        for n in 0..3000 {
            let len = 1 + (rnd() * 30.0) as usize;
            let mut x = rnd() * 20.0;
            let step = if n % 3 == 2 { 0.0 } else { 0.5 * rnd() };
            let mut spans = Vec::new();
            // One width a sequence (a pass's moves), or none (plunges).
            let width = if n % 7 == 0 { 0.0 } else { rnd() };
            for _ in 0..len {
                let w = if n % 3 == 2 { rnd() } else { width };
                spans.push((x, x + w));
                x += match n % 3 {
                    0 => step,
                    1 => -step,
                    _ => (rnd() - 0.5) * 2.0,
                };
            }
            let progress = Progress::of(&spans);
            seen[match progress {
                Progress::Advancing => 0,
                Progress::Retreating => 1,
                Progress::Mixed => 2,
            }] += 1;
            let bounds: Vec<KeyBound> = spans
                .iter()
                .map(|&s| KeyBound {
                    u: s,
                    v: (rnd() * 5.0, f64::INFINITY),
                })
                .collect();
            for _ in 0..20 {
                let (cu, cv) = (rnd() * 40.0 - 10.0, rnd() * 5.0);
                // A beat at a member's squared distance now and then: the ties.
                let beat = if rnd() < 0.3 {
                    let s = spans[(rnd() * len as f64) as usize];
                    let e = (s.0 - cu).max(cu - s.1).max(0.0);
                    e * e
                } else {
                    rnd() * 30.0
                };
                let from = progress.first(&spans, cu, beat);
                for b in &bounds[..from] {
                    assert!(b.at(cu, cv) >= beat, "{progress:?} skipped a member");
                    skipped += 1;
                }
                // The stock's loop stops at the first member whose later members' hull
                // bound (its own included) fails.
                let hulls: Vec<KeyBound> = (0..len)
                    .map(|i| bounds[i..].iter().copied().reduce(KeyBound::hull).unwrap())
                    .collect();
                for (i, h) in hulls.iter().enumerate().skip(from) {
                    if h.at(cu, cv) >= beat {
                        for later in &bounds[i..] {
                            assert!(later.at(cu, cv) >= beat, "{progress:?} broke too soon");
                            broken += 1;
                        }
                        break;
                    }
                }
            }
        }
        assert!(seen.iter().all(|&c| c > 500), "{seen:?}");
        assert!(skipped > 10_000 && broken > 10_000, "{skipped} {broken}");
    }

    /// The key bounds over a box and at a point never exceed the key of a point of the box.
    #[test]
    fn key_bounds_are_lower_bounds() {
        let mut rnd = test_rng(8);
        let c = Cutter::from_spec("ball:d=10").unwrap();
        let prof = ConvexProfile::from_solid(c.cutting_solid()).unwrap();
        for n in 0..4000 {
            let tip = Vec3::new(rnd(), rnd(), rnd()) * 10.0;
            let mut d = Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5) * 6.0;
            let k = n % 2;
            d[k] = 0.0;
            let sw = SweptConvex::new(&prof, tip, Vec3::Z, d);
            let Some(m) = sw.planar(k) else {
                continue;
            };
            let b = m.bound();
            let (u0, v0) = (rnd() * 24.0 - 6.0, rnd() * 24.0 - 6.0);
            let (u1, v1) = (u0 + rnd(), v0 + rnd());
            let over = b.over((u0, u1), (v0, v1));
            for _ in 0..20 {
                let (cu, cv) = (u0 + rnd() * (u1 - u0), v0 + rnd() * (v1 - v0));
                let key = m.key(cu, cv);
                assert!(over <= b.at(cu, cv) && b.at(cu, cv) <= key + 1e-12);
            }
        }
    }
}
