//! Closed forms for a tool **instance** (a sweep that does not move: the exact instances a
//! 5-axis move is cut as) of a flat, ball or bull-nose profile at any axis, against the dexel
//! rays — the general candidates' answer with one quadratic for most rays.
//!
//! # Why it holds
//! The profiles of [`FastProfile`] are a slab `P` (radius `R`, heights `[z_s, z1]`) united,
//! for a ball or bull-nose end, with the lozenge `L = D ⊕ B(r)` (`D` the disc of radius
//! `e = R − r` at height `f = z_s`; `e = 0` for a ball: a sphere) whose upper half lies in the
//! slab (`z1 ≥ f + r`). So above `f` the solid is the slab, below `f` it is the lower half of
//! `L`, and the whole lies in the cylinder `C = {ρ ≤ R, z ∈ [z_b, z1]}`, `z_b` the lowest point
//! (`f − r`, or `z_s` without a lozenge).
//!
//! Along a line `p(t) = o + t·d` (tool frame) the solid is convex, so its chord is one interval,
//! and:
//! * `C`'s chord — `ρ(t)² = R²` is a quadratic, the heights two divisions — holds it: a ray whose
//!   material misses `C`'s chord is left at once (no exact query, no separating plane);
//! * above `f` the chord is `C`'s: only the end on the side where the line goes below `f`
//!   (`t_f`, where it crosses `z = f`, inside `C`) can differ. There the lower half of `L` is the
//!   boundary: for a ball the sphere's chord, for a bull-nose the first zero of the convex
//!   `G(t) = dist(p(t), D) − r` (`lozenge.rs`; walked on `dist² − r²`, which has its zeros
//!   and sign) from `C`'s end, where `G ≥ 0` (every
//!   point of `C`'s boundary within `r` of the height `f` is at least `r` from `D`), towards
//!   `t_f`, where `G ≤ 0` (the disc of radius `R` at height `f` lies in `L`);
//! * that end is only computed when it can matter: when `C`'s end there lies beyond the ray's
//!   material, every end between the two gives the same cut (the result is exact where it
//!   meets the material, as the general path's);
//! * a line that stays below `f` inside `C` meets only `L`: its chord is `L`'s.
//!
//! The property tests (`tests/instance_paths.rs`) hold the kernels to the general candidates of
//! the same instance.

use super::convex::ConvexLine;
use super::fast::FastProfile;
use super::interval::{overlaps, Interval};
use super::lozenge::StaticLine;
use swarf_geom::math::{greater, lesser, Vec3};
use swarf_geom::Frame;

/// Material ending less than this (mm) inside the lozenge is left where it is: no cut is
/// worth less, and cutting the same instance again (whose ends the first cut made, found by
/// whatever path, lie within rounding of the surface) removes nothing more.
pub const SLIVER_MM: f64 = 1e-11;

/// Roots of a ray's quadratic with the bounding cylinder up to this far from the ray's base
/// point (mm) are taken as `(−b ∓ √h)/a`: their absolute error is then a few ulps of this
/// (≈ 10⁻¹³ mm), and they wait on no division after the square root, which the chords'
/// latency does (the 5-axis bench ≈ 8 % faster). Beyond it — a ray nearly along the axis,
/// whose other root lies far off — the cancellation-free form (`q/a`, `c/q`) keeps the nearer
/// root's precision.
const DIRECT_ROOTS_MM: f64 = 1e3;

/// Below this `|d_⊥|²` a line runs along the tool axis (its distance from it changes by less
/// than 10⁻¹² mm per mm of travel, far under the exact query's acceptance).
const ALONG_AXIS: f64 = 1e-24;

/// An instance's profile and pose, for [`InstanceRays`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct InstanceShape {
    shape: FastProfile,
    frame: Frame,
}

impl InstanceShape {
    pub(crate) fn new(shape: FastProfile, frame: Frame) -> Self {
        Self { shape, frame }
    }

    /// The constants shared by the rays along world axis `k`.
    pub(crate) fn rays(&self, k: usize) -> InstanceRays {
        let (u, v) = ((k + 1) % 3, (k + 2) % 3);
        let fr = &self.frame;
        let d = fr.vector_to_local(Vec3::AXES[k]);
        let (r, z_s, z1) = self.shape.slab;
        let z_b = self.shape.lozenge.map_or(z_s, |(_, f, lr)| f - lr);
        let a = d.x * d.x + d.y * d.y;
        InstanceRays {
            eu: fr.vector_to_local(Vec3::AXES[u]),
            ev: fr.vector_to_local(Vec3::AXES[v]),
            d,
            tip: (fr.origin[u], fr.origin[v], fr.origin[k]),
            a,
            inv_a: 1.0 / a,
            rr: r * r,
            heights: (z_b, z1),
            inv_dz: if d.z != 0.0 { 1.0 / d.z } else { 0.0 },
            lozenge: self.shape.lozenge,
        }
    }
}

/// One instance against the rays along one world axis, in the tool frame: the ray through
/// `(cu, cv)` on the family's cross axes is `o + t'·d` with `o = eu·(cu − tip_u) + ev·(cv −
/// tip_v)` (its point level with the tip along the ray) and world coordinate `t' + tip_k`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct InstanceRays {
    eu: Vec3,
    ev: Vec3,
    d: Vec3,
    tip: (f64, f64, f64),
    /// `|d_⊥|²`.
    a: f64,
    /// `1 / |d_⊥|²` (infinite along the axis, where it is not used).
    inv_a: f64,
    rr: f64,
    /// `(z_b, z1)`: the heights of `C`.
    heights: (f64, f64),
    inv_dz: f64,
    lozenge: Option<(f64, f64, f64)>,
}

impl InstanceRays {
    /// The stock update's query for the dexel `dex` of the ray through `(cu, cv)`: whether an
    /// exact query ran, and the interval to remove (world coordinates along the ray), exact
    /// where it meets the material.
    #[inline(always)]
    pub(crate) fn cut(&self, cu: f64, cv: f64, dex: &[Interval]) -> (bool, Option<(f64, f64)>) {
        match (dex.first(), dex.last()) {
            (Some(f), Some(l)) => self.cut_within(cu, cv, dex, (f.enter, l.exit)),
            _ => (false, None),
        }
    }

    /// [`InstanceRays::cut`] for a dexel with material, from its first entry to its last exit.
    #[inline(always)]
    fn cut_within(
        &self,
        cu: f64,
        cv: f64,
        dex: &[Interval],
        (first, last): (f64, f64),
    ) -> (bool, Option<(f64, f64)>) {
        let (o, t0) = self.line(cu, cv);
        let Some((lo, hi)) = self.cylinder(o) else {
            return (false, None);
        };
        if !overlaps(dex, lo + t0, hi + t0) {
            return (false, None);
        }
        let chord = self.chord(o, (lo, hi), (first - t0, last - t0));
        (true, chord.map(|(a, b)| (a + t0, b + t0)))
    }

    /// The whole chord of the ray through `(cu, cv)` (world coordinates along it).
    pub(crate) fn interval(&self, cu: f64, cv: f64) -> Option<(f64, f64)> {
        let (o, t0) = self.line(cu, cv);
        let c = self.cylinder(o)?;
        let (a, b) = self.chord(o, c, (f64::NEG_INFINITY, f64::INFINITY))?;
        Some((a + t0, b + t0))
    }

    /// The ray's base point (tool frame) and the world coordinate of `t' = 0`.
    #[inline(always)]
    fn line(&self, cu: f64, cv: f64) -> (Vec3, f64) {
        let (tu, tv, tk) = self.tip;
        (self.eu * (cu - tu) + self.ev * (cv - tv), tk)
    }

    /// `C`'s chord of the line `o + t·d`.
    #[inline(always)]
    fn cylinder(&self, o: Vec3) -> Option<(f64, f64)> {
        self.cylinder_grown(o, self.rr, self.heights)
    }

    /// The chord of the line `o + t·d` through the cylinder of squared radius `rr` about the
    /// axis between the heights `(z_b, z1)`.
    #[inline(always)]
    fn cylinder_grown(&self, o: Vec3, rr: f64, (z_b, z1): (f64, f64)) -> Option<(f64, f64)> {
        let d = self.d;
        let c = o.x * o.x + o.y * o.y - rr;
        let (mut lo, mut hi) = if self.a > ALONG_AXIS {
            let b = o.x * d.x + o.y * d.y;
            let h = b * b - self.a * c;
            if h < 0.0 {
                return None;
            }
            let s = h.sqrt();
            if (b.abs() + s) * self.inv_a <= DIRECT_ROOTS_MM {
                // Without a division: the roots' absolute error is a few ulps of the bound.
                ((-b - s) * self.inv_a, (-b + s) * self.inv_a)
            } else {
                // Cancellation-free roots q/a and c/q (a line nearly along the axis, where
                // (−b ∓ √h)/a would lose the nearer root to the farther one's rounding).
                // (`signum`, `min` and `max` order NaN, which no operand here is, at a cost
                // of several instructions each: plain comparisons.)
                let q = -(b + if b < 0.0 { -s } else { s });
                let (r1, r2) = (q / self.a, if q != 0.0 { c / q } else { 0.0 });
                (lesser(r1, r2), greater(r1, r2))
            }
        } else if c <= 0.0 {
            (f64::NEG_INFINITY, f64::INFINITY)
        } else {
            return None;
        };
        if d.z != 0.0 {
            let (ta, tb) = ((z_b - o.z) * self.inv_dz, (z1 - o.z) * self.inv_dz);
            lo = greater(lo, lesser(ta, tb));
            hi = lesser(hi, greater(ta, tb));
        } else if o.z < z_b || o.z > z1 {
            return None;
        }
        (lo <= hi).then_some((lo, hi))
    }

    /// A range holding the chords of all the rays whose cross coordinates are within `half`
    /// of `(cu, cv)` (a square block, e.g. a tile; world coordinates along the rays): such a
    /// ray is within `half·√2` of the block's centre ray, across it, so the centre ray meets
    /// `C` grown by that wherever the other meets `C`, at the same parameter.
    pub(crate) fn block(&self, cu: f64, cv: f64, half: f64) -> Option<(f64, f64)> {
        let grow = half * std::f64::consts::SQRT_2 + 1e-9;
        let r = self.rr.sqrt() + grow;
        let (z_b, z1) = self.heights;
        let (o, t0) = self.line(cu, cv);
        let (lo, hi) = self.cylinder_grown(o, r * r, (z_b - grow, z1 + grow))?;
        Some((lo + t0, hi + t0))
    }

    /// The instance's chord from `C`'s chord `(lo, hi)`, exact where it meets `(m_lo, m_hi)`
    /// (line parameters; the material overlaps `(lo, hi)`).
    #[inline]
    fn chord(&self, o: Vec3, (lo, hi): (f64, f64), material: (f64, f64)) -> Option<(f64, f64)> {
        let Some((e, f, r)) = self.lozenge else {
            return Some((lo, hi));
        };
        let d = self.d;
        // Which ends of C's chord lie below the spine's level (there L's boundary is the
        // tool's), and where the line crosses that level.
        let (lo_below, hi_below, tf) = if d.z == 0.0 {
            let below = o.z < f;
            (below, below, f64::NAN)
        } else {
            let tf = (f - o.z) * self.inv_dz;
            if d.z > 0.0 {
                (lo < tf, hi < tf, tf)
            } else {
                (lo > tf, hi > tf, tf)
            }
        };
        if !lo_below && !hi_below {
            return Some((lo, hi));
        }
        if e == 0.0 {
            // A ball: the sphere's chord, one square root (it holds the point at tf, up to
            // rounding).
            let (a, b) = sphere_chord(f, r, o, d)?;
            return match (lo_below, hi_below) {
                (true, true) => Some((a, b)),
                (true, false) => Some((a.clamp(lo, hi), hi)),
                _ => Some((lo, b.clamp(lo, hi))),
            };
        }
        let line = StaticLine { e, f, r, o, d };
        match (lo_below, hi_below) {
            (true, true) => lozenge_chord(&line, (lo, hi), material),
            (true, false) => Some((lozenge_end(&line, lo, tf, material, 1.0)?, hi)),
            _ => Some((
                lo,
                lozenge_end(&line, hi, tf, (material.1, material.0), -1.0)?,
            )),
        }
    }
}

/// Several tool instances queried together (the parts of a tool at the poses a 5-axis move's
/// band is cut at): each ray's chords through them, joined, so that a ray the instances trim
/// one after the other (each a sliver beyond the last) is read and changed once, not once per
/// instance. The union of the chords is what cutting them one by one removes, up to slivers
/// (`SLIVER_MM`, the stock's shortest interval) and the lozenge walk's tolerance: each chord is
/// exact where it meets the ray's material as it was before any of them, which holds the
/// material left after the earlier ones. At most [`InstanceSet::MAX`] instances.
#[derive(Clone, Debug, Default)]
pub struct InstanceSet<'r> {
    rays: smallvec::SmallVec<[&'r InstanceRays; InstanceSet::MAX]>,
}

impl<'r> InstanceSet<'r> {
    /// The most instances in one set.
    pub const MAX: usize = 8;

    /// An empty set.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds the instance whose rays along a family are `rays`; `false` (and nothing added)
    /// when they are not an instance's closed form or the set is full.
    pub fn push(&mut self, rays: &'r super::DexelRays) -> bool {
        match rays.instance() {
            Some(i) if self.rays.len() < Self::MAX => {
                self.rays.push(i);
                true
            }
            _ => false,
        }
    }

    /// The union of the instances' chords of the ray through `(cu, cv)` whose material is
    /// `d` (world coordinates along it), each exact where it meets the material: whether an
    /// exact query ran, and how many disjoint intervals, ascending, begin `out`.
    #[inline]
    pub fn cut(
        &self,
        cu: f64,
        cv: f64,
        d: &[Interval],
        out: &mut [(f64, f64); InstanceSet::MAX],
    ) -> (bool, usize) {
        let (Some(f), Some(l)) = (d.first(), d.last()) else {
            return (false, 0);
        };
        let material = (f.enter, l.exit);
        let (mut tested, mut n) = (false, 0);
        for i in &self.rays {
            let (t, hit) = i.cut_within(cu, cv, d, material);
            tested |= t;
            let Some((lo, hi)) = hit else { continue };
            // Kept sorted by their lower ends (a handful at most).
            let mut at = n;
            while at > 0 && out[at - 1].0 > lo {
                out[at] = out[at - 1];
                at -= 1;
            }
            out[at] = (lo, hi);
            n += 1;
        }
        // Join chords that overlap or touch.
        let mut w = 0;
        for r in 0..n {
            if w > 0 && out[r].0 <= out[w - 1].1 {
                out[w - 1].1 = greater(out[w - 1].1, out[r].1);
            } else {
                out[w] = out[r];
                w += 1;
            }
        }
        (tested, w)
    }
}

/// Whether `x` comes before `y` walking along `dir` (±1).
#[inline(always)]
fn before(x: f64, y: f64, dir: f64) -> bool {
    (y - x) * dir > 0.0
}

/// The end of the instance's chord that lies on the lozenge, walking along `dir` (+1: the
/// lower end, −1: the upper end) from `C`'s end `c` to `tf`, inside the lozenge, given the
/// ray's material from `near` to `far` in that order: `C`'s end where the true one lies before
/// the material (the same cut), `None` where the material ends before the chord starts (or
/// within [`SLIVER_MM`] of it).
#[inline]
fn lozenge_end(
    line: &StaticLine,
    c: f64,
    tf: f64,
    (near, far): (f64, f64),
    dir: f64,
) -> Option<f64> {
    if !before(near, tf, dir) {
        // The chord holds tf, which the material does not come before.
        return Some(c);
    }
    let mut from = (c, None);
    if before(c, near, dir) {
        let at = line.value_slope(near);
        if at.0 <= 0.0 {
            return Some(c);
        }
        // Outside, and before the chord (F ≤ 0 at tf further on): a nearer start.
        from = (near, Some(at));
    }
    if !before(far, tf, dir) {
        return Some(line.entry(from.0, from.1, tf));
    }
    // The material ends before tf: outside the lozenge (or within a sliver inside) it ends
    // before the chord starts (F is convex, ≤ 0 at tf); inside, the end lies between, and
    // the tangent there gives a nearer start.
    let at = line.value_slope(far);
    if at.0 > line.f_at(-SLIVER_MM) {
        return None;
    }
    Some(line.entry_near(from, (far, at), dir))
}

/// The chord of a line that stays below the spine's level inside `C` (whose chord is
/// `(lo, hi)`): `L`'s, exact where it meets the material `(m_lo, m_hi)`; `None` where they do
/// not meet (or only within [`SLIVER_MM`]).
///
/// Only ends that can lie inside the material are found, each walked from the nearest point
/// known outside: the tangent's zero at a material end inside, the material's end before it
/// when that lies outside, or `C`'s end.
#[inline]
fn lozenge_chord(
    line: &StaticLine,
    (lo, hi): (f64, f64),
    (m_lo, m_hi): (f64, f64),
) -> Option<(f64, f64)> {
    // Per end (lower, upper): a start outside L before it, and the material's end on that
    // side when it lies inside L (that end of the chord then lies beyond the material).
    let mut from = [(lo, None), (hi, None)];
    let mut inside = [None; 2];
    for (end, m) in [(0, m_lo), (1, m_hi)] {
        if m <= lo || m >= hi {
            continue;
        }
        let (fm, slope) = line.value_slope(m);
        if fm <= line.f_at(-SLIVER_MM) {
            inside[end] = Some((m, (fm, slope)));
            continue;
        }
        // Outside (or within a sliver): before the chord on its side (descending towards it
        // from below, rising from above) it is a nearer start; past it, the material and the
        // chord do not meet.
        let towards = if end == 0 { slope < 0.0 } else { slope > 0.0 };
        if !towards {
            return None;
        }
        if fm >= 0.0 {
            from[end] = (m, Some((fm, slope)));
        }
    }
    match inside {
        // All the material between lies in the chord.
        [Some(_), Some(_)] => Some((lo, hi)),
        [None, Some(inner)] => Some((line.entry_near(from[0], inner, 1.0), hi)),
        [Some(inner), None] => Some((lo, line.entry_near(from[1], inner, -1.0))),
        [None, None] => line.chord_in(from[0].0, from[1].0),
    }
}

/// The chord of the line `o + t·d` (unit `d`) through the sphere of radius `r` centred on the
/// axis at height `f`.
#[inline]
fn sphere_chord(f: f64, r: f64, o: Vec3, d: Vec3) -> Option<(f64, f64)> {
    let oc = Vec3::new(o.x, o.y, o.z - f);
    // Re-based at the point nearest the centre.
    let t0 = -oc.dot(d);
    let p = oc + d * t0;
    let h = r * r - p.dot(p);
    (h >= 0.0).then(|| {
        let s = h.sqrt();
        (t0 - s, t0 + s)
    })
}
