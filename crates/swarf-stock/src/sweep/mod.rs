//! Exact intersection of a line with the volume swept by a convex solid of revolution moving
//! along a straight segment with a fixed axis.
//!
//! # The geometry (re-derived; Aras 2008 §4.2.3 is the starting point)
//! Let `K` be a **convex** solid of revolution about the tool axis (the APT cutting part is
//! one: its profile radius `r(z)` is concave on `[0, h]` for valid parameters, which
//! [`ConvexProfile::from_pieces`] verifies). Moving `K` by `s·v`, `s ∈ [0, 1]`, with a fixed
//! axis sweeps the Minkowski sum `S = K ⊕ [0, v]`, which is convex. For a line `o + t·d` the set
//! `C = {(t, s) : s ∈ [0, 1], o + t·d − s·v ∈ K}` is convex, so `S` meets the line in **one**
//! interval `[t_min, t_max]`, the projection of `C` on `t`.
//!
//! Where is `t_min` attained? Either at `s = 0` or `s = 1` (the line against `K` at the start
//! or end pose: the *caps*), or at an interior `s` where, by the KKT conditions, some normal
//! `n` of `K` at the touching point satisfies `n·v = 0`: the point lies on the **grazing
//! curve** of `K` for direction `v`, which for a fixed axis is fixed on the tool, and the line
//! meets the grazing curve extruded along `v` (the *envelope*). Every candidate we compute is
//! a point `g + s·v` with `g ∈ K` and `s ∈ [0, 1]`, i.e. a point of `S`, and every extreme
//! point is among the candidates; so `[min, max]` of the candidates **is** the interval, and
//! over-including candidates (e.g. all joint circles, grazing or not) is harmless.
//!
//! The grazing curves, in a move frame whose x axis is the horizontal part of `v`
//! (`v = (a, 0, b)`; `a = 0` for plunges along the axis, where any x axis does, unlike the
//! frame of Aras eq. 4.20 which is undefined there):
//! * sphere (ball corner): the great circle `⊥ v`; its extrusion is the cylinder of radius
//!   `r` about the centre's path (a capsule side) — [`sphere`];
//! * cone and cylinder sides: the generator lines at `cos θ = −n_z·b / (n_ρ·a)`, whose
//!   extrusions are parallelograms — [`line`];
//! * profile joints (sharp or smooth circles, the flat bottom's edge, the top cap's edge): the
//!   circle extruded along `v`, an elliptic cylinder — [`circle`];
//! * torus (bull-nose corner): the spine circle offset by `±r·m(θ)`, `m = unit(c′ × v)`, a
//!   degree-8 polynomial in `tan(θ/2)` solved by guaranteed root isolation
//!   (`swarf_geom::poly`), with the horizontal move (where `m` is undefined on two meridians)
//!   in closed form — [`torus`].
//!
//! Flat faces (discs) parallel to `v` are grazing as a whole, but their extrusion's boundary
//! is made of the joint circles' extrusions and the caps, so they need no candidates of their
//! own.

pub(crate) mod circle;
pub(crate) mod line;
pub(crate) mod profile;
pub(crate) mod sphere;
pub(crate) mod torus;

pub use profile::{ConvexProfile, Element, SweepShape};

use smallvec::SmallVec;
use swarf_geom::math::Vec3;
use swarf_geom::{Aabb, Frame};

/// Below this relative size a component of the move direction is taken as exactly zero
/// (`|v_h| ≤ AXIS_SNAP·|v|` is a plunge along the axis, `|v_z| ≤ AXIS_SNAP·|v|` a horizontal
/// move). The geometric effect is below `AXIS_SNAP·|v|·tool size`, far under any resolution.
pub const AXIS_SNAP: f64 = 1e-10;

/// Tolerance (mm) with which a candidate point is accepted on a piece's band or a parameter
/// in `[0, 1]`: a candidate accepted this far outside lies within this distance of `S`.
pub const BAND_EPS: f64 = 1e-9;

/// Running minimum and maximum of candidate line parameters.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Acc {
    pub(crate) lo: f64,
    pub(crate) hi: f64,
}

impl Acc {
    pub(crate) const EMPTY: Acc = Acc {
        lo: f64::INFINITY,
        hi: f64::NEG_INFINITY,
    };
    #[inline]
    pub(crate) fn add(&mut self, t: f64) {
        if t < self.lo {
            self.lo = t;
        }
        if t > self.hi {
            self.hi = t;
        }
    }
    pub(crate) fn get(&self) -> Option<(f64, f64)> {
        (self.lo <= self.hi).then_some((self.lo, self.hi))
    }
}

/// Per-thread scratch space (root lists) so the per-ray loop never allocates.
#[derive(Debug, Default)]
pub struct Scratch {
    pub(crate) roots: Vec<f64>,
}

impl Scratch {
    /// Empty scratch with room for the largest root list.
    pub fn new() -> Self {
        Self {
            roots: Vec::with_capacity(32),
        }
    }
}

/// A piece of work for one line: an element (its two caps and its envelope) or a joint
/// circle's extrusion, with the bounding box of what it can contribute.
#[derive(Clone, Copy, Debug)]
struct Unit {
    /// Element index, or joint index when `joint`.
    index: usize,
    joint: bool,
    /// Workpiece-frame box holding every candidate point of the unit.
    bbox: Aabb,
}

/// A convex profile moving with a fixed axis along a segment, prepared for line queries.
#[derive(Clone, Debug)]
pub struct SweptConvex<'a> {
    prof: &'a ConvexProfile,
    frame: Frame,
    /// Move in the move frame: `(a, 0, b)`.
    v: Vec3,
    bbox: Aabb,
    units: SmallVec<[Unit; 10]>,
}

/// Box of the band `z ∈ [z0, z1]` of radius ≤ `rho` about `axis` from `tip`, at the start and
/// at the end (`tip + delta`) of a move: it holds the band's sweep (convex hull of the two).
fn band_box(tip: Vec3, axis: Vec3, delta: Vec3, z0: f64, z1: f64, rho: f64) -> Aabb {
    let ext = Vec3::new(
        rho * (1.0 - axis.x * axis.x).max(0.0).sqrt(),
        rho * (1.0 - axis.y * axis.y).max(0.0).sqrt(),
        rho * (1.0 - axis.z * axis.z).max(0.0).sqrt(),
    );
    let c0 = tip + axis * z0;
    let mut bbox = Aabb::new(c0, c0);
    for c in [c0, tip + axis * z1, c0 + delta, tip + delta + axis * z1] {
        bbox = bbox.extended(c - ext).extended(c + ext);
    }
    bbox.inflated(1e-9)
}

/// Quantities of one line direction against one move, shared by all parallel lines.
#[derive(Clone, Copy, Debug)]
pub(crate) struct DirConsts {
    /// Direction in the move frame (unit).
    pub(crate) d: Vec3,
    /// The move in the move frame, `(a, 0, b)`.
    pub(crate) v: Vec3,
    /// `d × v`.
    pub(crate) w: Vec3,
    /// `d·v`.
    pub(crate) dv: f64,
    /// `v·v`.
    pub(crate) vv: f64,
    /// `|d × v|²`; the envelope is skipped when the line is parallel to the move.
    pub(crate) det: f64,
    /// False when the line is parallel to the move or the move has zero length.
    pub(crate) envelope: bool,
}

impl DirConsts {
    /// Solves `o + t·d = g + s·v` (coplanar by construction) for `(t, s)` by least squares.
    #[inline]
    pub(crate) fn solve_ts(&self, o: Vec3, g: Vec3) -> (f64, f64) {
        let r0 = g - o;
        let dr = self.d.dot(r0);
        let vr = self.v.dot(r0);
        let t = (dr * self.vv - self.dv * vr) / self.det;
        let s = (self.dv * dr - vr) / self.det;
        (t, s)
    }
}

impl<'a> SweptConvex<'a> {
    /// `prof` (tool frame: tip at the origin, axis +Z) placed with its tip at `tip` and axis
    /// `axis` (unit), moving by `delta` (workpiece frame) with the axis fixed.
    pub fn new(prof: &'a ConvexProfile, tip: Vec3, axis: Vec3, delta: Vec3) -> Self {
        let axis = axis.normalize();
        let len = delta.length();
        let mut b = delta.dot(axis);
        let horiz = delta - axis * b;
        let mut a = horiz.length();
        let frame = if a > AXIS_SNAP * len {
            Frame::from_axis_and_x(tip, axis, horiz)
        } else {
            a = 0.0;
            Frame::from_axis(tip, axis)
        };
        if b.abs() <= AXIS_SNAP * len {
            b = 0.0;
        }
        let v = Vec3::new(a, 0.0, b);
        let delta = frame.vector_to_world(v);
        let bbox = band_box(tip, axis, delta, prof.z_min(), prof.z_max(), prof.r_max());
        let mut units = SmallVec::new();
        for i in 0..prof.elements().len() {
            let (z0, z1, rho) = prof.element_extent(i);
            units.push(Unit {
                index: i,
                joint: false,
                bbox: band_box(tip, axis, delta, z0, z1, rho),
            });
        }
        for (j, c) in prof.joints().iter().enumerate() {
            units.push(Unit {
                index: j,
                joint: true,
                bbox: band_box(tip, axis, delta, c.y, c.y, c.x),
            });
        }
        Self {
            prof,
            frame,
            v,
            bbox,
            units,
        }
    }

    /// Bounding box of the swept volume, workpiece frame.
    pub fn bbox(&self) -> Aabb {
        self.bbox
    }

    /// The interval of the line `origin + t·dir` (workpiece frame, `dir` unit) inside the
    /// swept volume, `None` when the line misses it. (The stock update uses a batched form of
    /// this query that shares the per-direction constants among parallel rays and skips work
    /// that cannot change the material.)
    pub fn ray_interval(&self, origin: Vec3, dir: Vec3) -> Option<(f64, f64)> {
        let dir = dir.normalize();
        let dc = self.dir_consts(dir);
        self.line_interval(origin, &dc, None, &mut Scratch::new())
    }

    /// Constants for lines with world direction `dir` (unit).
    pub(crate) fn dir_consts(&self, dir: Vec3) -> DirConsts {
        let d = self.frame.vector_to_local(dir);
        let v = self.v;
        let w = d.cross(v);
        let vv = v.dot(v);
        let dv = d.dot(v);
        let det = w.length_squared();
        DirConsts {
            d,
            v,
            w,
            dv,
            vv,
            det,
            envelope: vv > 0.0 && det > 1e-20 * vv,
        }
    }

    /// The interval of the line `origin + t·dir` inside the swept volume (`dc` from
    /// [`SweptConvex::dir_consts`] for `dir`).
    ///
    /// With `dexel = Some((k, m_lo, m_hi))` the line is a ray along world axis `k` with
    /// `origin[k] = 0` whose material lies within `[m_lo, m_hi]`; then work that cannot change
    /// `[lo, hi] ∩ [m_lo, m_hi]` is skipped, so the returned interval is exact where it meets
    /// the material (and may be shorter outside it).
    pub(crate) fn line_interval(
        &self,
        origin: Vec3,
        dc: &DirConsts,
        dexel: Option<(usize, f64, f64)>,
        scratch: &mut Scratch,
    ) -> Option<(f64, f64)> {
        let d = dc.d;
        let o_full = self.frame.to_local(origin);
        // Re-base the line at its point nearest the tool origin, for precision (t values of a
        // few mm instead of hundreds in the quartic and octic).
        let t0 = -o_full.dot(d);
        let o = o_full + d * t0;
        if !self.near(o, dc) {
            return None;
        }
        let mut acc = Acc::EMPTY;
        let prof = self.prof;
        let v = self.v;
        for unit in &self.units {
            if let Some((k, m_lo, m_hi)) = dexel {
                let (u, w) = ((k + 1) % 3, (k + 2) % 3);
                let b = &unit.bbox;
                if origin[u] < b.min[u] || origin[u] > b.max[u] || origin[w] < b.min[w] || origin[w] > b.max[w] {
                    continue;
                }
                // Local parameter = world coordinate along k − t0.
                let need_lo = b.min[k] - t0 < acc.lo && acc.lo > m_lo - t0;
                let need_hi = b.max[k] - t0 > acc.hi && acc.hi < m_hi - t0;
                if !(need_lo || need_hi) {
                    continue;
                }
            }
            if unit.joint {
                if dc.envelope {
                    prof.envelope_joint(unit.index, o, dc, &mut acc);
                }
            } else {
                prof.cap_element(unit.index, o, d, &mut acc, scratch);
                if v != Vec3::ZERO {
                    prof.cap_element(unit.index, o - v, d, &mut acc, scratch);
                }
                if dc.envelope {
                    prof.envelope_element(unit.index, o, dc, &mut acc, scratch);
                }
            }
        }
        acc.get().map(|(lo, hi)| (lo + t0, hi + t0))
    }

    /// False when the line (move frame, re-based at its point nearest the tool origin) stays
    /// farther than the profile's largest radius from the parallelogram swept by the axis
    /// segment `[z_min, z_max]`, hence misses the sweep; a conservative pre-test.
    #[inline]
    fn near(&self, o: Vec3, dc: &DirConsts) -> bool {
        let p = self.prof;
        let d = dc.d;
        let r = p.bound_radius();
        // Project along d onto the plane ⊥ d; 2-D coordinates in any basis of that plane.
        let (e1, e2) = d.any_orthonormal_pair();
        let pr = |x: Vec3| (x.dot(e1), x.dot(e2));
        let q = pr(o);
        let a = pr(Vec3::new(0.0, 0.0, p.z_min()));
        let ax = pr(Vec3::new(0.0, 0.0, p.z_max() - p.z_min()));
        let vv = pr(self.v);
        let sub = |x: (f64, f64), y: (f64, f64)| (x.0 - y.0, x.1 - y.1);
        let rel = sub(q, a);
        // Inside the projected parallelogram a + α·ax + s·vv (α, s ∈ [0, 1])?
        let det = ax.0 * vv.1 - ax.1 * vv.0;
        let scale = (ax.0 * ax.0 + ax.1 * ax.1).max(vv.0 * vv.0 + vv.1 * vv.1);
        if det.abs() > 1e-12 * scale {
            let al = (rel.0 * vv.1 - rel.1 * vv.0) / det;
            let s = (ax.0 * rel.1 - ax.1 * rel.0) / det;
            if (0.0..=1.0).contains(&al) && (0.0..=1.0).contains(&s) {
                return true;
            }
        }
        // Distance to the four edges.
        let seg = |p0: (f64, f64), e: (f64, f64)| {
            let w = sub(q, p0);
            let ee = e.0 * e.0 + e.1 * e.1;
            let t = if ee > 0.0 { ((w.0 * e.0 + w.1 * e.1) / ee).clamp(0.0, 1.0) } else { 0.0 };
            let dx = (w.0 - t * e.0, w.1 - t * e.1);
            dx.0 * dx.0 + dx.1 * dx.1
        };
        let a2 = (a.0 + ax.0, a.1 + ax.1);
        let a3 = (a.0 + vv.0, a.1 + vv.1);
        let m = seg(a, ax).min(seg(a, vv)).min(seg(a2, vv)).min(seg(a3, ax));
        let rr = r * (1.0 + 1e-12) + 1e-9;
        m <= rr * rr
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use swarf_tool::Cutter;

    fn interval(
        c: &Cutter,
        tip: Vec3,
        axis: Vec3,
        delta: Vec3,
        o: Vec3,
        dir: Vec3,
    ) -> Option<(f64, f64)> {
        let prof = ConvexProfile::from_solid(c.cutting_solid()).unwrap();
        let sw = SweptConvex::new(&prof, tip, axis, delta);
        let dc = sw.dir_consts(dir);
        sw.line_interval(o, &dc, None, &mut Scratch::new())
    }

    #[test]
    fn flat_slot_vertical_ray() {
        // Flat Ø10 moving +X by 20 at z = 0: a vertical ray at (10, 4) enters at z = 0 and
        // leaves at the top of the cutting part (h = 30); t is measured from z = −50.
        let c = Cutter::flat(10.0).unwrap();
        let (lo, hi) = interval(
            &c,
            Vec3::ZERO,
            Vec3::Z,
            Vec3::new(20.0, 0.0, 0.0),
            Vec3::new(10.0, 4.0, -50.0),
            Vec3::Z,
        )
        .unwrap();
        assert!(
            (lo - 50.0).abs() < 1e-12 && (hi - 80.0).abs() < 1e-12,
            "{lo} {hi}"
        );
        // Outside the slot width: no hit.
        assert!(interval(
            &c,
            Vec3::ZERO,
            Vec3::Z,
            Vec3::new(20.0, 0.0, 0.0),
            Vec3::new(10.0, 5.01, -50.0),
            Vec3::Z
        )
        .is_none());
        // A ray along X at y = 3, z = 1: from x = −4 to 24.
        let (lo, hi) = interval(
            &c,
            Vec3::ZERO,
            Vec3::Z,
            Vec3::new(20.0, 0.0, 0.0),
            Vec3::new(-100.0, 3.0, 1.0),
            Vec3::X,
        )
        .unwrap();
        assert!(
            (lo - 96.0).abs() < 1e-12 && (hi - 124.0).abs() < 1e-12,
            "{lo} {hi}"
        );
    }

    #[test]
    fn ball_groove_x_ray_across() {
        // Ball Ø10 along +Y: a ray along X at z = 2 (3 below the centre) crosses the capsule
        // where x² + 3² ≤ 25: x ∈ [−4, 4].
        let c = Cutter::ball(10.0).unwrap();
        let (lo, hi) = interval(
            &c,
            Vec3::ZERO,
            Vec3::Z,
            Vec3::new(0.0, 20.0, 0.0),
            Vec3::new(-50.0, 10.0, 2.0),
            Vec3::X,
        )
        .unwrap();
        assert!(
            (lo - 46.0).abs() < 1e-9 && (hi - 54.0).abs() < 1e-9,
            "{lo} {hi}"
        );
    }

    #[test]
    fn plunge_vertical_and_side_rays() {
        // Flat Ø10 plunging 20 mm down along its axis (the thesis frame is undefined here).
        let c = Cutter::flat(10.0).unwrap();
        let (lo, hi) = interval(
            &c,
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::Z,
            Vec3::new(0.0, 0.0, -20.0),
            Vec3::new(-50.0, 1.0, -10.0),
            Vec3::X,
        )
        .unwrap();
        let x = (25.0f64 - 1.0).sqrt();
        assert!(
            (lo - (50.0 - x)).abs() < 1e-9 && (hi - (50.0 + x)).abs() < 1e-9,
            "{lo} {hi}"
        );
    }

    #[test]
    fn dexel_pruning_keeps_the_material_part_exact() {
        // The pruned query must agree with the full one wherever the material is.
        let mut seed = 7u64;
        let mut rnd = move || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((seed >> 11) as f64) / ((1u64 << 53) as f64)
        };
        let cutters = ["ball:d=10", "flat:d=8", "bull:d=12,r=3", "drill:d=6,angle=118", "taper-ball:d=6,taper=8"];
        let mut compared = 0;
        for (ci, spec) in cutters.iter().cycle().take(60).enumerate() {
            let c = Cutter::from_spec(spec).unwrap();
            let prof = ConvexProfile::from_solid(c.cutting_solid()).unwrap();
            let axis = if ci % 2 == 0 { Vec3::Z } else { Vec3::new(rnd() - 0.5, rnd() - 0.5, 1.0).normalize() };
            let delta = Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5) * 10.0;
            let sw = SweptConvex::new(&prof, Vec3::ZERO, axis, delta);
            let bb = sw.bbox();
            for k in 0..3 {
                let dc = sw.dir_consts(Vec3::AXES[k]);
                for _ in 0..200 {
                    let mut o = bb.min + (bb.max - bb.min) * Vec3::new(rnd(), rnd(), rnd());
                    o[k] = 0.0;
                    let (a, b) = (bb.min[k] + rnd() * (bb.max[k] - bb.min[k]), bb.min[k] + rnd() * (bb.max[k] - bb.min[k]));
                    let (m_lo, m_hi) = (a.min(b), a.max(b));
                    let full = sw.line_interval(o, &dc, None, &mut Scratch::new());
                    let pruned = sw.line_interval(o, &dc, Some((k, m_lo, m_hi)), &mut Scratch::new());
                    let clip = |x: Option<(f64, f64)>| x.and_then(|(l, h)| {
                        let (l, h) = (l.max(m_lo), h.min(m_hi));
                        (l < h).then_some((l, h))
                    });
                    match (clip(full), clip(pruned)) {
                        (None, None) => {}
                        (Some(f), Some(p)) => {
                            assert!((f.0 - p.0).abs() < 1e-9 && (f.1 - p.1).abs() < 1e-9, "{spec} {f:?} {p:?}");
                            compared += 1;
                        }
                        (f, p) => panic!("{spec}: full {f:?} vs pruned {p:?}"),
                    }
                }
            }
        }
        assert!(compared > 1000, "{compared}");
    }
}
