//! Profiles of convex solids of revolution, built from swarf-tool's pieces and checked for
//! convexity; non-convex solids (holders with steps, unusual APT sets) are split into convex
//! slabs.

use super::fast::FastProfile;
use super::{circle, line, sphere, torus, Acc, DirConsts, Scratch};
use crate::error::SweepError;
use swarf_geom::math::{Vec2, Vec3};
use swarf_tool::{AnyPiece, Piece, RevolvedSolid};

/// Tolerance (mm) on profile joints and convexity turns when a profile is built.
const PROFILE_EPS: f64 = 1e-7;

/// One element of a profile in the meridian half-plane `(ρ, z)`, traversed from the axis at
/// the bottom, outwards and up, back to the axis at the top.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Element {
    /// Segment from `p` to `q`: a disc (horizontal), cylinder (vertical) or cone surface.
    Line {
        /// Start `(ρ, z)`.
        p: Vec2,
        /// End `(ρ, z)`.
        q: Vec2,
    },
    /// Circular arc centred at `(e, f)` of radius `r`, profile point
    /// `(e + r·sin φ, f − r·cos φ)` for `φ ∈ [phi0, phi1]`: a torus (e > 0) or sphere (e = 0).
    Arc {
        /// Distance from the axis to the centre.
        e: f64,
        /// Height of the centre.
        f: f64,
        /// Radius.
        r: f64,
        /// Start polar angle (radians, 0 = straight down from the centre).
        phi0: f64,
        /// End polar angle.
        phi1: f64,
    },
}

impl Element {
    fn start(&self) -> Vec2 {
        match *self {
            Element::Line { p, .. } => p,
            Element::Arc { e, f, r, phi0, .. } => Vec2::new(e + r * phi0.sin(), f - r * phi0.cos()),
        }
    }
    fn end(&self) -> Vec2 {
        match *self {
            Element::Line { q, .. } => q,
            Element::Arc { e, f, r, phi1, .. } => Vec2::new(e + r * phi1.sin(), f - r * phi1.cos()),
        }
    }
    fn tangent_start(&self) -> Vec2 {
        match *self {
            Element::Line { p, q } => (q - p).normalize(),
            Element::Arc { phi0, .. } => Vec2::new(phi0.cos(), phi0.sin()),
        }
    }
    fn tangent_end(&self) -> Vec2 {
        match *self {
            Element::Line { p, q } => (q - p).normalize(),
            Element::Arc { phi1, .. } => Vec2::new(phi1.cos(), phi1.sin()),
        }
    }
    fn z_band(&self) -> (f64, f64) {
        let (a, b) = (self.start().y, self.end().y);
        (a.min(b), a.max(b))
    }
    fn max_rho(&self) -> f64 {
        let m = self.start().x.max(self.end().x);
        match *self {
            Element::Arc {
                e, r, phi0, phi1, ..
            } if phi0 <= std::f64::consts::FRAC_PI_2 && phi1 >= std::f64::consts::FRAC_PI_2 => {
                m.max(e + r)
            }
            _ => m,
        }
    }
    fn from_piece(piece: &AnyPiece) -> Element {
        match piece {
            AnyPiece::Disc(d) => {
                let (a, b) = (Vec2::new(d.inner, d.z), Vec2::new(d.outer, d.z));
                if d.facing_up {
                    Element::Line { p: b, q: a }
                } else {
                    Element::Line { p: a, q: b }
                }
            }
            AnyPiece::Cylinder(c) => Element::Line {
                p: Vec2::new(c.radius, c.z0),
                q: Vec2::new(c.radius, c.z1),
            },
            AnyPiece::Cone(c) => Element::Line {
                p: c.bottom,
                q: c.top,
            },
            AnyPiece::Torus(t) => Element::Arc {
                e: t.major,
                f: t.center_z,
                r: t.minor,
                phi0: t.phi0,
                phi1: t.phi1,
            },
            AnyPiece::Sphere(s) => Element::Arc {
                e: 0.0,
                f: s.center_z,
                r: s.radius,
                phi0: s.phi0,
                phi1: s.phi1,
            },
        }
    }
}

/// The closed profile of a convex solid of revolution about +Z (tool frame), with its joint
/// circles, ready for swept-line queries.
#[derive(Clone, Debug, PartialEq)]
pub struct ConvexProfile {
    elements: Vec<Element>,
    /// Joint circles `(ρ, z)` with `ρ > 0`.
    joints: Vec<Vec2>,
    /// Per element: lowest z, highest z, largest ρ (precomputed: arcs need trigonometry).
    extents: Vec<(f64, f64, f64)>,
    z_min: f64,
    z_max: f64,
    r_max: f64,
    /// The heights where the radius is largest (an interval: a cylinder side, or a point).
    z_of_max: (f64, f64),
    /// Per element: `(sin φ0, sin φ1, cos φ1)` for arcs (zeros for lines).
    trig: Vec<(f64, f64, f64)>,
    /// Per element: the unit directions `(sin φ, −cos φ)` from an arc's centre to its two ends
    /// (zeros for lines), so point queries need no trigonometry.
    arc_ends: Vec<(Vec2, Vec2)>,
    /// What the closed-form kernels see in it, if anything.
    fast: Option<FastProfile>,
}

impl ConvexProfile {
    /// The profile of `elements` (axis-to-axis, bottom to top). Errors when the elements do not
    /// join, do not start and end on the axis, or turn the wrong way (not convex).
    pub fn new(elements: Vec<Element>) -> Result<Self, SweepError> {
        let first = elements.first().ok_or(SweepError::BadProfile {
            why: "no elements".into(),
        })?;
        let last = elements.last().unwrap_or(first);
        if first.start().x.abs() > PROFILE_EPS || last.end().x.abs() > PROFILE_EPS {
            return Err(SweepError::BadProfile {
                why: "the profile must start and end on the axis".into(),
            });
        }
        let mut joints = Vec::new();
        for w in elements.windows(2) {
            let (a, b) = (w[0].end(), w[1].start());
            if (a - b).length() > PROFILE_EPS {
                return Err(SweepError::BadProfile {
                    why: format!(
                        "elements do not join: ({}, {}) vs ({}, {})",
                        a.x, a.y, b.x, b.y
                    ),
                });
            }
            let turn = w[0].tangent_end().perp_dot(w[1].tangent_start());
            if turn < -PROFILE_EPS {
                return Err(SweepError::NotConvex { rho: a.x, z: a.y });
            }
            if a.x > 0.0 {
                joints.push(a);
            }
        }
        // z must be monotone along the profile (no overhang).
        for el in &elements {
            let (s, e) = (el.start(), el.end());
            if e.y < s.y - PROFILE_EPS {
                return Err(SweepError::NotConvex { rho: s.x, z: s.y });
            }
        }
        let z_min = elements
            .iter()
            .map(|e| e.z_band().0)
            .fold(f64::INFINITY, f64::min);
        let z_max = elements
            .iter()
            .map(|e| e.z_band().1)
            .fold(f64::NEG_INFINITY, f64::max);
        let r_max = elements.iter().map(Element::max_rho).fold(0.0, f64::max);
        let (mut zm_lo, mut zm_hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for el in &elements {
            let mut note = |z: f64| {
                zm_lo = zm_lo.min(z);
                zm_hi = zm_hi.max(z);
            };
            match *el {
                Element::Line { p, q } => {
                    for pt in [p, q] {
                        if pt.x == r_max {
                            note(pt.y);
                        }
                    }
                }
                Element::Arc { e, f, r, .. } => {
                    if el.max_rho() == r_max {
                        note(if e + r == r_max { f } else { el.end().y });
                    }
                }
            }
        }
        let z_of_max = if zm_lo <= zm_hi {
            (zm_lo, zm_hi)
        } else {
            (z_min, z_min)
        };
        let trig = elements
            .iter()
            .map(|el| match *el {
                Element::Arc { phi0, phi1, .. } => (phi0.sin(), phi1.sin(), phi1.cos()),
                Element::Line { .. } => (0.0, 0.0, 0.0),
            })
            .collect();
        let arc_ends = elements
            .iter()
            .map(|el| match *el {
                Element::Arc { phi0, phi1, .. } => (
                    Vec2::new(phi0.sin(), -phi0.cos()),
                    Vec2::new(phi1.sin(), -phi1.cos()),
                ),
                Element::Line { .. } => (Vec2::ZERO, Vec2::ZERO),
            })
            .collect();
        let extents = elements
            .iter()
            .map(|e| {
                let (z0, z1) = e.z_band();
                (z0, z1, e.max_rho())
            })
            .collect();
        let fast = FastProfile::classify(&elements);
        Ok(Self {
            elements,
            joints,
            extents,
            z_min,
            z_max,
            r_max,
            z_of_max,
            trig,
            arc_ends,
            fast,
        })
    }

    /// The profile of a swarf-tool solid (cutting part, shank, one holder segment) when it is
    /// convex.
    pub fn from_solid(solid: &RevolvedSolid) -> Result<Self, SweepError> {
        Self::from_pieces(solid.pieces())
    }

    /// The profile of the pieces (bottom to top), when they bound a convex solid.
    pub fn from_pieces(pieces: &[AnyPiece]) -> Result<Self, SweepError> {
        Self::new(pieces.iter().map(Element::from_piece).collect())
    }

    /// The part of the solid between heights `za` and `zb` (the solid ∩ a slab: convex again),
    /// closed by discs at the cut heights; `None` when the slab holds less than a sliver of it.
    pub fn clipped(&self, za: f64, zb: f64) -> Option<ConvexProfile> {
        let (za, zb) = (za.max(self.z_min), zb.min(self.z_max));
        if zb - za <= PROFILE_EPS {
            return None;
        }
        let mut els: Vec<Element> = Vec::new();
        for el in &self.elements {
            let (z0, z1) = el.z_band();
            if z1 < za || z0 > zb {
                continue;
            }
            let clipped = match *el {
                Element::Line { p, q } => {
                    if (q.y - p.y).abs() <= PROFILE_EPS {
                        Element::Line { p, q }
                    } else {
                        let at = |z: f64| p + (q - p) * ((z - p.y) / (q.y - p.y)).clamp(0.0, 1.0);
                        let (a, b) = if q.y > p.y { (za, zb) } else { (zb, za) };
                        Element::Line { p: at(a), q: at(b) }
                    }
                }
                Element::Arc {
                    e,
                    f,
                    r,
                    phi0,
                    phi1,
                } => {
                    // z = f − r·cos φ grows with φ on [0, π].
                    let phi = |z: f64| ((f - z) / r).clamp(-1.0, 1.0).acos();
                    Element::Arc {
                        e,
                        f,
                        r,
                        phi0: phi0.max(phi(za)),
                        phi1: phi1.min(phi(zb)),
                    }
                }
            };
            if (clipped.end() - clipped.start()).length() > PROFILE_EPS {
                els.push(clipped);
            }
        }
        let (first, last) = (els.first()?.start(), els.last()?.end());
        if first.x > PROFILE_EPS {
            els.insert(
                0,
                Element::Line {
                    p: Vec2::new(0.0, first.y),
                    q: first,
                },
            );
        }
        if last.x > PROFILE_EPS {
            els.push(Element::Line {
                p: last,
                q: Vec2::new(0.0, last.y),
            });
        }
        ConvexProfile::new(els).ok()
    }

    /// The elements, bottom to top.
    pub fn elements(&self) -> &[Element] {
        &self.elements
    }

    /// Lowest z.
    pub fn z_min(&self) -> f64 {
        self.z_min
    }

    /// Highest z.
    pub fn z_max(&self) -> f64 {
        self.z_max
    }

    /// Largest radius.
    pub fn r_max(&self) -> f64 {
        self.r_max
    }

    /// The profile as the closed-form kernels see it (slab, or sphere on a slab).
    pub(crate) fn fast(&self) -> Option<FastProfile> {
        self.fast
    }

    /// Radius of a cylinder about the axis holding the solid.
    pub(crate) fn bound_radius(&self) -> f64 {
        self.r_max
    }

    /// Height of the solid's lowest point at distance `rho` from the axis (the lower profile,
    /// from the tip outwards while the radius grows); `None` beyond the largest radius. It is
    /// non-decreasing in `rho` for a convex solid.
    pub fn lower_z(&self, rho: f64) -> Option<f64> {
        if rho > self.r_max {
            return None;
        }
        for (el, &(s0, s1, c1)) in self.elements.iter().zip(&self.trig) {
            match *el {
                Element::Line { p, q } => {
                    if q.x <= p.x {
                        break;
                    }
                    if rho <= q.x {
                        let t = ((rho - p.x) / (q.x - p.x)).clamp(0.0, 1.0);
                        return Some(p.y + t * (q.y - p.y));
                    }
                }
                Element::Arc { e, f, r, phi1, .. } => {
                    let (rho1, top) = if phi1 >= std::f64::consts::FRAC_PI_2 {
                        (e + r, f)
                    } else {
                        (e + r * s1, f - r * c1)
                    };
                    if rho <= rho1 {
                        let dr = (rho - e).max(r * s0);
                        return Some((f - (r * r - dr * dr).max(0.0).sqrt()).min(top));
                    }
                    if phi1 > std::f64::consts::FRAC_PI_2 {
                        break;
                    }
                }
            }
        }
        // At the largest radius, on a vertical side: its lowest point.
        self.elements
            .iter()
            .filter_map(|el| match *el {
                Element::Line { p, q }
                    if p.x == q.x && (p.x - rho).abs() <= 1e-12 * self.r_max.max(1.0) =>
                {
                    Some(p.y.min(q.y))
                }
                _ => None,
            })
            .reduce(f64::min)
            .or(Some(self.z_min))
    }

    /// Radius of the solid at height `z` (`None` outside `[z_min, z_max]`).
    pub fn radius_at(&self, z: f64) -> Option<f64> {
        if z < self.z_min || z > self.z_max {
            return None;
        }
        let mut best: f64 = 0.0;
        for (el, &(z0, z1, _)) in self.elements.iter().zip(&self.extents) {
            if z < z0 || z > z1 {
                continue;
            }
            let r = match *el {
                Element::Line { p, q } => {
                    if p.y == q.y {
                        p.x.max(q.x)
                    } else {
                        p.x + (z - p.y) / (q.y - p.y) * (q.x - p.x)
                    }
                }
                Element::Arc { e, f, r, .. } => e + (r * r - (z - f) * (z - f)).max(0.0).sqrt(),
            };
            best = best.max(r);
        }
        Some(best)
    }

    /// Largest radius over the heights `[lo, hi]` ∩ `[z_min, z_max]` (`None` when empty). The
    /// radius is concave in z, so the maximum is at the clamp of a height of the largest
    /// radius into the range.
    pub fn max_radius_in(&self, lo: f64, hi: f64) -> Option<f64> {
        let (lo, hi) = (lo.max(self.z_min), hi.min(self.z_max));
        if lo > hi {
            return None;
        }
        let (a, b) = self.z_of_max;
        if lo <= b && hi >= a {
            return Some(self.r_max);
        }
        self.radius_at(if hi < a { hi } else { lo })
    }

    /// The tube radius of element `i` when it is a torus band (an arc off the axis) whose
    /// neighbours on both sides continue it tangentially (as a bull-nose's bottom disc and
    /// side do); `None` otherwise.
    pub fn smooth_torus_radius(&self, i: usize) -> Option<f64> {
        let Element::Arc {
            e, r, phi0, phi1, ..
        } = self.elements[i]
        else {
            return None;
        };
        if e <= 0.0 || i == 0 || i + 1 >= self.elements.len() {
            return None;
        }
        // Tangent directions of the profile, bottom to top.
        let arc_tangent = |phi: f64| Vec2::new(phi.cos(), phi.sin());
        let direction = |el: &Element, at_start: bool| match *el {
            Element::Line { p, q } => (q - p).normalize(),
            Element::Arc { phi0, phi1, .. } => arc_tangent(if at_start { phi0 } else { phi1 }),
        };
        let tangent = |a: Vec2, b: Vec2| (a - b).length() <= 1e-9;
        (tangent(direction(&self.elements[i - 1], false), arc_tangent(phi0))
            && tangent(direction(&self.elements[i + 1], true), arc_tangent(phi1)))
        .then_some(r)
    }

    /// The joint circles `(ρ, z)` (ρ > 0) between consecutive elements.
    pub fn joints(&self) -> &[Vec2] {
        &self.joints
    }

    /// Unit directions from arc `i`'s centre to its start and end (zeros for a line).
    pub(crate) fn arc_ends(&self, i: usize) -> (Vec2, Vec2) {
        self.arc_ends[i]
    }

    /// The bull-nose corners (bit `i`: element `i`) whose lozenge lies in the solid
    /// (`lozenge.rs`): quarter tori from the bottom (tangent to it, `f = r`) to a vertical side
    /// that rises at least `r` above the spine.
    pub(crate) fn lozenge_corners(&self) -> u64 {
        let els = &self.elements;
        let mut bits = 0u64;
        for i in 0..els.len().min(64) {
            let Element::Arc {
                e,
                f,
                r,
                phi0,
                phi1,
            } = els[i]
            else {
                continue;
            };
            let quarter = e > 0.0
                && phi0 == 0.0
                && (phi1 - std::f64::consts::FRAC_PI_2).abs() <= 1e-12
                && (f - r).abs() <= 1e-12 * r.max(1.0);
            let side_rises = matches!(els.get(i + 1), Some(Element::Line { p, q })
                if p.x == q.x
                    && (p.x - (e + r)).abs() <= 1e-12 * (e + r)
                    && (p.y - f).abs() <= 1e-12 * r.max(1.0)
                    && q.y >= f + r);
            if quarter && side_rises {
                bits |= 1 << i;
            }
        }
        bits
    }

    /// Adds the ends of the line's chord through the lozenge of bull-nose corner `i` swept by
    /// `v` (move frame; `lozenge.rs`); for a static tool (`v = 0`) only those on the tool's
    /// boundary.
    #[inline]
    pub(crate) fn swept_corner(&self, i: usize, o: Vec3, d: Vec3, v: Vec3, acc: &mut Acc) {
        if let Element::Arc { e, f, r, .. } = self.elements[i] {
            if v == Vec3::ZERO {
                super::lozenge::instance_crossings(e, f, r, o, d, acc);
            } else {
                super::lozenge::swept_chord(e, f, r, o, d, v, acc);
            }
        }
    }

    /// Height band and largest radius of element `i`.
    pub(crate) fn element_extent(&self, i: usize) -> (f64, f64, f64) {
        self.extents[i]
    }

    /// Adds the line's crossings with element `i` (tool frame, unit `d`).
    #[inline]
    pub(crate) fn cap_element(
        &self,
        i: usize,
        o: Vec3,
        d: Vec3,
        acc: &mut Acc,
        scratch: &mut Scratch,
    ) {
        let el = &self.elements[i];
        match *el {
            Element::Line { p, q } => line::cap(p, q, o, d, acc),
            Element::Arc {
                e,
                f,
                r,
                phi0,
                phi1,
            } => {
                let (z0, z1, _) = self.extents[i];
                if e == 0.0 {
                    sphere::cap(f, r, z0, z1, o, d, acc);
                } else {
                    torus::cap(e, f, r, (phi0, phi1), (z0, z1), o, d, acc, scratch);
                }
            }
        }
    }

    /// Adds the line's crossings with the envelope of element `i` swept by `dc.v`.
    #[inline]
    pub(crate) fn envelope_element(
        &self,
        i: usize,
        o: Vec3,
        dc: &DirConsts,
        acc: &mut Acc,
        scratch: &mut Scratch,
    ) {
        let el = &self.elements[i];
        match *el {
            Element::Line { p, q } => line::envelope(p, q, o, dc, acc),
            Element::Arc {
                e,
                f,
                r,
                phi0,
                phi1,
            } => {
                let (z0, z1, _) = self.extents[i];
                if e == 0.0 {
                    sphere::envelope(f, r, z0, z1, o, dc, acc);
                } else {
                    torus::envelope(e, f, r, (phi0, phi1), (z0, z1), o, dc, acc, scratch);
                }
            }
        }
    }

    /// Adds the line's crossings with the extrusion of joint circle `j` along `dc.v`.
    #[inline]
    pub(crate) fn envelope_joint(&self, j: usize, o: Vec3, dc: &DirConsts, acc: &mut Acc) {
        let c = self.joints[j];
        circle::envelope(c.x, c.y, o, dc, acc);
    }
}

/// A solid of revolution as a union of convex profiles: one when the solid is convex (the APT
/// cutting part, a shank), else one convex slab per non-horizontal piece (stepped holders,
/// unusual APT parameter sets). The swept volume of the union is the union of the sweeps, so
/// every part is cut separately.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepShape {
    parts: Vec<ConvexProfile>,
}

impl SweepShape {
    /// The shape of `solid`: itself when convex, else its slabs. An empty solid gives an empty
    /// shape.
    pub fn from_solid(solid: &RevolvedSolid) -> Self {
        if solid.pieces().is_empty() {
            return Self { parts: Vec::new() };
        }
        if let Ok(p) = ConvexProfile::from_solid(solid) {
            return Self { parts: vec![p] };
        }
        Self::slabs(solid.pieces())
    }

    /// One convex slab per non-horizontal piece: the piece closed by discs at its two ends.
    pub fn slabs(pieces: &[AnyPiece]) -> Self {
        let mut parts = Vec::new();
        for piece in pieces {
            if piece.is_horizontal() {
                continue;
            }
            let el = Element::from_piece(piece);
            let (a, b) = (el.start(), el.end());
            let els = vec![
                Element::Line {
                    p: Vec2::new(0.0, a.y),
                    q: a,
                },
                el,
                Element::Line {
                    p: b,
                    q: Vec2::new(0.0, b.y),
                },
            ];
            if let Ok(p) = ConvexProfile::new(els) {
                parts.push(p);
            }
        }
        Self { parts }
    }

    /// A shape made of the given convex parts (a union).
    pub fn from_parts(parts: Vec<ConvexProfile>) -> Self {
        Self { parts }
    }

    /// The convex parts.
    pub fn parts(&self) -> &[ConvexProfile] {
        &self.parts
    }

    /// True when the solid is a single convex part.
    pub fn is_convex(&self) -> bool {
        self.parts.len() == 1
    }

    /// The shape cut into horizontal bands no taller than `height` (each part into equal
    /// bands): the same solid as a union of shorter convex parts. A short part reaches less far
    /// from a pivot at its middle, so a rotating tool's band needs fewer constant-axis pieces
    /// ([`crate::five_axis`]).
    pub fn bands(&self, height: f64) -> SweepShape {
        let mut parts = Vec::new();
        for p in &self.parts {
            let span = p.z_max - p.z_min;
            let n = if height > 0.0 && span.is_finite() {
                ((span / height).ceil() as usize).clamp(1, 64)
            } else {
                1
            };
            if n == 1 {
                parts.push(p.clone());
                continue;
            }
            for i in 0..n {
                let za = p.z_min + span * i as f64 / n as f64;
                let zb = if i + 1 == n {
                    p.z_max
                } else {
                    p.z_min + span * (i + 1) as f64 / n as f64
                };
                parts.extend(p.clipped(za, zb));
            }
        }
        SweepShape { parts }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::SweptConvex;
    use swarf_geom::math::Vec3;
    use swarf_tool::Cutter;

    #[test]
    fn bands_are_the_same_solid() {
        // Every line through a tilted, moving instance meets the union of the bands' sweeps in
        // the one interval it meets the whole part's sweep in.
        let mut seed = 0x2545_F491_4F6C_DD1Du64;
        let mut rnd = |a: f64, b: f64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            a + (b - a) * (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for spec in [
            "flat:d=10",
            "ball:d=10",
            "bull:d=16,r=2",
            "taper-ball:d=6,taper=5",
            "chamfer:d=12,angle=90",
            "drill:d=8,angle=118",
        ] {
            let c = Cutter::from_spec(spec).unwrap();
            let whole = SweepShape::from_solid(c.cutting_solid());
            for height in [0.7, 2.5, 100.0] {
                let bands = whole.bands(height);
                let span = whole.parts()[0].z_max() - whole.parts()[0].z_min();
                assert_eq!(
                    bands.parts().len(),
                    ((span / height).ceil() as usize).clamp(1, 64)
                );
                fn sweep(p: &ConvexProfile) -> SweptConvex<'_> {
                    SweptConvex::new(
                        p,
                        Vec3::new(0.3, -0.2, 0.1),
                        Vec3::new(0.3, -0.4, 1.0).normalize(),
                        Vec3::new(2.0, 1.0, -0.5),
                    )
                }
                let mut hits = 0;
                for _ in 0..400 {
                    let k = (rnd(0.0, 3.0) as usize).min(2);
                    let mut o = Vec3::ZERO;
                    o[(k + 1) % 3] = rnd(-9.0, 9.0);
                    o[(k + 2) % 3] = rnd(-9.0, 9.0);
                    let want = sweep(&whole.parts()[0]).axis_ray_interval(o, k);
                    let mut got: Vec<(f64, f64)> = bands
                        .parts()
                        .iter()
                        .filter_map(|p| sweep(p).axis_ray_interval(o, k))
                        .collect();
                    got.sort_by(|a, b| a.0.total_cmp(&b.0));
                    match want {
                        None => assert!(got.is_empty(), "{spec} {height}: {got:?}"),
                        Some((lo, hi)) => {
                            hits += 1;
                            let (glo, ghi) = (got[0].0, got.iter().map(|g| g.1).fold(lo, f64::max));
                            assert!((glo - lo).abs() < 1e-9 && (ghi - hi).abs() < 1e-9, "{spec}");
                            // No gap between consecutive bands' intervals.
                            let mut reach = got[0].1;
                            for g in &got[1..] {
                                assert!(g.0 <= reach + 1e-9, "{spec} {height}: gap {got:?}");
                                reach = reach.max(g.1);
                            }
                        }
                    }
                }
                assert!(hits > 50, "{spec}: {hits}");
            }
        }
    }

    #[test]
    fn every_named_cutter_is_convex() {
        for spec in [
            "flat:d=10",
            "ball:d=10",
            "bull:d=16,r=2",
            "taper-flat:d=6,taper=10",
            "taper-ball:d=6,taper=5",
            "chamfer:d=12,angle=90",
            "drill:d=8,angle=118",
        ] {
            let c = Cutter::from_spec(spec).unwrap();
            let p = ConvexProfile::from_solid(c.cutting_solid());
            assert!(p.is_ok(), "{spec}: {p:?}");
            assert!((p.unwrap().r_max() - c.max_diameter() / 2.0).abs() < 1e-12);
        }
    }

    #[test]
    fn lower_z_is_the_lowest_boundary_point() {
        let specs = [
            "flat:d=10",
            "ball:d=10",
            "bull:d=16,r=2",
            "taper-flat:d=6,taper=10",
            "taper-ball:d=6,taper=5",
            "chamfer:d=12,angle=90",
            "drill:d=8,angle=118",
        ];
        for spec in specs {
            let c = Cutter::from_spec(spec).unwrap();
            let p = ConvexProfile::from_solid(c.cutting_solid()).unwrap();
            for i in 0..=200 {
                let rho = p.r_max() * i as f64 / 200.0 * (1.0 - 1e-9);
                let z = p.lower_z(rho).unwrap();
                if z < p.z_max() - 1e-6 {
                    assert!(
                        c.contains(Vec3::new(rho, 0.0, z + 1e-7)),
                        "{spec} ρ={rho} z={z}"
                    );
                }
                assert!(
                    !c.contains(Vec3::new(rho, 0.0, z - 1e-7)),
                    "{spec} ρ={rho} z={z}"
                );
            }
            assert!(p.lower_z(p.r_max() * 1.001).is_none());
        }
    }

    #[test]
    fn radius_queries_match_the_cutter() {
        let specs = [
            "flat:d=10",
            "ball:d=10",
            "bull:d=16,r=2",
            "taper-flat:d=6,taper=10",
            "taper-ball:d=6,taper=5",
            "chamfer:d=12,angle=90",
            "drill:d=8,angle=118",
        ];
        for spec in specs {
            let c = Cutter::from_spec(spec).unwrap();
            let p = ConvexProfile::from_solid(c.cutting_solid()).unwrap();
            let n = 300;
            let zs: Vec<f64> = (0..=n).map(|i| p.z_max() * i as f64 / n as f64).collect();
            for &z in &zs {
                let (a, b) = (p.radius_at(z).unwrap(), c.profile_radius(z).unwrap());
                assert!((a - b).abs() < 1e-9, "{spec} z={z}: {a} vs {b}");
            }
            for w in zs.windows(37) {
                let m = w
                    .iter()
                    .map(|&z| c.profile_radius(z).unwrap())
                    .fold(0.0, f64::max);
                let got = p.max_radius_in(w[0], w[36]).unwrap();
                assert!(
                    got >= m - 1e-9 && got <= c.max_diameter() / 2.0 + 1e-9,
                    "{spec}: {got} < {m}"
                );
            }
        }
    }

    #[test]
    fn stepped_holder_is_split_into_slabs() {
        // Widening steps upwards make a non-convex profile.
        let els = vec![
            Element::Line {
                p: Vec2::new(0.0, 0.0),
                q: Vec2::new(2.0, 0.0),
            },
            Element::Line {
                p: Vec2::new(2.0, 0.0),
                q: Vec2::new(2.0, 5.0),
            },
            Element::Line {
                p: Vec2::new(2.0, 5.0),
                q: Vec2::new(6.0, 5.0),
            },
            Element::Line {
                p: Vec2::new(6.0, 5.0),
                q: Vec2::new(6.0, 9.0),
            },
            Element::Line {
                p: Vec2::new(6.0, 9.0),
                q: Vec2::new(0.0, 9.0),
            },
        ];
        assert!(matches!(
            ConvexProfile::new(els),
            Err(SweepError::NotConvex { .. })
        ));
    }
}
