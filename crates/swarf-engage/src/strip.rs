//! The cutter's surface cut into circles: axial discs on its side, rings on its flat bottom.
//!
//! Both are **strips**: a family of circles of the cutter's surface of revolution, ordered by a
//! parameter (height `z` above the tip for the axial discs, radius `r` for the bottom rings),
//! each knowing its radius `ρ`, height and outward profile normal, plus the true surface area
//! per radian of the band between consecutive circles (and of the half bands at both ends). An
//! engagement is sampled on the circles and integrated over the bands
//! ([`crate::Engagement`]).
//!
//! Axial discs have height `dz` and their circles sit at the disc centres `z = (k + ½)·dz`
//! inside the cutting part's side (every non-horizontal piece: cones, torus, sphere, cylinder).
//! Bottom rings (a flat bottom of radius `e`, flat and bull-nose cutters) split `[0, e]` into
//! `n = ⌈e/dz⌉` equal rings, circles at their mid radii. Each strip also has a circle at both
//! ends of its range (the tip or the bottom's centre, the top of the cutting part, the bottom's
//! rim) and the side one at every joint of its profile (each piece's own where the normal
//! turns there), with more where the profile runs long between discs: they are sampled for the
//! integration (the area of a half band can be large where the surface turns flat, as at the
//! bottom of a torus; the feasibility has a kink or a jump at a joint) but are not reported as
//! discs or rings.

use swarf_geom::math::Vec2;
use swarf_tool::{AnyPiece, Cutter, Piece};

/// One circle of the cutter's surface (cutter frame: tip at the origin, axis +Z).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Circle {
    /// Height above the tip, mm.
    pub z: f64,
    /// Radius, mm.
    pub rho: f64,
    /// Outward unit profile normal `(n_ρ, n_z)`.
    pub normal: Vec2,
}

/// Which surface a strip covers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StripKind {
    /// The side, in axial discs (parameter: height `z`).
    Side,
    /// The flat bottom face, in rings (parameter: radius `r`).
    Bottom,
}

/// Circles of one surface and the areas between them.
#[derive(Clone, Debug, PartialEq)]
pub struct Strip {
    /// Side or bottom.
    pub kind: StripKind,
    /// The circles, by increasing parameter: the first and the last at the ends of the
    /// strip's range, the others at the disc centres (or ring mid radii).
    pub circles: Vec<Circle>,
    /// Each circle's parameter (`z` or `r`), mm.
    pub param: Vec<f64>,
    /// Surface area per radian between circle `k` and `k + 1`, mm².
    pub band_area: Vec<f64>,
    /// Whether circle `k` is a reported disc (or ring); the others serve the integration.
    pub reported: Vec<bool>,
    /// The slice of the surface a reported circle stands for: its parameter range (axial discs:
    /// `[k·dz, (k+1)·dz]`, the first from the strip's start, the last to its end; rings: the
    /// ring), so the slabs of the reported circles tile the strip. Empty for the others.
    pub slab: Vec<(f64, f64)>,
    /// Profile length of each slab, mm (the chip width a force model integrates over).
    pub slab_width: Vec<f64>,
    /// `∫ dz/ρ` from the strip's start to both ends of each slab (side only; 0 on the bottom):
    /// the angle by which a helical edge of helix angle `i` lags, divided by `tan i`.
    pub slab_turn: Vec<(f64, f64)>,
}

impl Strip {
    /// The side of `cutter`'s cutting part in axial discs of height `dz`; `None` when the
    /// cutter has no side (never for a valid APT cutter).
    pub fn side(cutter: &Cutter, dz: f64) -> Option<Strip> {
        let pieces: Vec<&AnyPiece> = cutter
            .pieces()
            .iter()
            .filter(|p| !p.is_horizontal())
            .collect();
        let lo = pieces.iter().map(|p| p.z_range().0).reduce(f64::min)?;
        let hi = pieces.iter().map(|p| p.z_range().1).reduce(f64::max)?;
        let n = ((hi / dz) - 0.5).ceil().max(0.0) as usize;
        let mut param = vec![lo];
        for k in 0..n {
            let z = (k as f64 + 0.5) * dz;
            if z > lo && z < hi {
                param.push(z);
            }
        }
        param.push(hi);
        if param.len() < 3 {
            return None;
        }
        // Integration circles between the discs wherever the profile runs longer than `dz`
        // between two of them (a torus or sphere turning flat): every band is then at most
        // `dz` long on the surface, so its area is sampled as finely as a cylinder's. And one
        // at every joint of two pieces — two, each piece's own, where the normal turns there
        // (a cone on a cylinder) — so that no band spans a joint: the feasibility `f` has a
        // kink or a jump at a joint (on a ball plunging along its axis it falls to 0 at the
        // sphere's equator and stays there on the cylinder), which a band's interpolation
        // between its circles would smear over the band (the plunge's area came out half a
        // disc high). (A joint within 10⁻⁹ mm of a disc's circle is that circle, the lower
        // piece's.)
        let mut joints: Vec<f64> = pieces
            .iter()
            .flat_map(|p| [p.z_range().0, p.z_range().1])
            .filter(|&z| z > lo && z < hi)
            .collect();
        joints.sort_by(f64::total_cmp);
        joints.dedup();
        let mut reported = vec![false];
        let mut refined: Vec<(f64, Option<&AnyPiece>)> = vec![(lo, None)];
        for (i, w) in param.windows(2).enumerate() {
            let cuts = joints
                .iter()
                .copied()
                .filter(|&z| z > w[0] + 1e-9 && z < w[1] - 1e-9);
            let mut from = w[0];
            for to in cuts.chain([w[1]]) {
                let len = arc_length(&pieces, from, to);
                let m = (len / (dz * (1.0 + 1e-9))).ceil().max(1.0) as usize;
                for q in 1..m {
                    let z = z_at_arc_length(&pieces, from, to, len * q as f64 / m as f64);
                    refined.push((z, None));
                    reported.push(false);
                }
                if to < w[1] {
                    // The joint: the piece below's circle, then the piece above's if its
                    // normal differs.
                    let below = pieces.iter().copied().find(|p| p.z_range().1 == to);
                    let above = pieces.iter().copied().find(|p| p.z_range().0 == to);
                    refined.push((to, below));
                    reported.push(false);
                    if let (Some(a), Some(b)) = (below, above) {
                        let (na, nb) = (a.profile_normal(1.0), b.profile_normal(0.0));
                        if (na - nb).length() > 1e-9 {
                            refined.push((to, Some(b)));
                            reported.push(false);
                        }
                    }
                }
                from = to;
            }
            refined.push((w[1], None));
            reported.push(i + 2 < param.len());
        }
        let circles = refined
            .iter()
            .map(|&(z, piece)| match piece {
                Some(p) => Some(circle_on(p, z)),
                None => side_circle(&pieces, z),
            })
            .collect::<Option<Vec<_>>>()?;
        let param: Vec<f64> = refined.iter().map(|r| r.0).collect();
        let band_area = param
            .windows(2)
            .map(|w| side_area(&pieces, w[0], w[1]))
            .collect();
        let first = reported.iter().position(|&r| r);
        let last = reported.iter().rposition(|&r| r);
        let mut slab = Vec::with_capacity(param.len());
        let mut slab_width = Vec::with_capacity(param.len());
        let mut slab_turn = Vec::with_capacity(param.len());
        let mut turn = 0.0;
        let mut turn_at = lo;
        for (k, &z) in param.iter().enumerate() {
            if !reported[k] {
                slab.push((z, z));
                slab_width.push(0.0);
                slab_turn.push((0.0, 0.0));
                continue;
            }
            let disc = (z / dz - 0.5).round();
            let a = if Some(k) == first { lo } else { disc * dz };
            let b = if Some(k) == last {
                hi
            } else {
                (disc + 1.0) * dz
            };
            turn += turn_between(&pieces, turn_at, a);
            let ta = turn;
            turn += turn_between(&pieces, a, b);
            turn_at = b;
            slab.push((a, b));
            slab_width.push(arc_length(&pieces, a, b));
            slab_turn.push((ta, turn));
        }
        Some(Strip {
            kind: StripKind::Side,
            circles,
            param,
            band_area,
            reported,
            slab,
            slab_width,
            slab_turn,
        })
    }

    /// The flat bottom face of `cutter` (a downward disc at the tip of radius `e > 0`) in rings
    /// of width at most `dr`; `None` without one.
    pub fn bottom(cutter: &Cutter, dr: f64) -> Option<Strip> {
        let e = cutter.pieces().iter().find_map(|p| match p {
            AnyPiece::Disc(d) if !d.facing_up && d.outer > 0.0 => Some(d.outer),
            _ => None,
        })?;
        let n = ((e / dr) * (1.0 - 1e-12)).ceil().max(1.0) as usize;
        let w = e / n as f64;
        let mut param = vec![0.0];
        param.extend((0..n).map(|i| (i as f64 + 0.5) * w));
        param.push(e);
        let mut reported = vec![true; param.len()];
        (reported[0], reported[n + 1]) = (false, false);
        let slab: Vec<(f64, f64)> = param
            .iter()
            .zip(&reported)
            .map(|(&r, &rep)| {
                if rep {
                    (r - 0.5 * w, r + 0.5 * w)
                } else {
                    (r, r)
                }
            })
            .collect();
        let slab_width = slab.iter().map(|s| s.1 - s.0).collect();
        let slab_turn = vec![(0.0, 0.0); param.len()];
        let circles = param
            .iter()
            .map(|&r| Circle {
                z: 0.0,
                rho: r,
                normal: Vec2::new(0.0, -1.0),
            })
            .collect();
        Some(Strip {
            kind: StripKind::Bottom,
            circles,
            band_area: param
                .windows(2)
                .map(|p| 0.5 * (p[1] * p[1] - p[0] * p[0]))
                .collect(),
            param,
            reported,
            slab,
            slab_width,
            slab_turn,
        })
    }

    /// Index of the circle at parameter `at` (a disc's height or a ring's radius as an
    /// engagement reports it), if there is one.
    pub fn circle_at(&self, at: f64) -> Option<usize> {
        let k = self.param.partition_point(|&p| p < at - 1e-12);
        (k < self.param.len() && (self.param[k] - at).abs() <= 1e-9).then_some(k)
    }

    /// Number of circles (the two end circles included).
    pub fn len(&self) -> usize {
        self.circles.len()
    }

    /// The parameter range `[lo, hi]`, mm.
    pub fn range(&self) -> (f64, f64) {
        (self.param[0], self.param[self.param.len() - 1])
    }

    /// True for the circles reported as discs or rings.
    pub fn is_reported(&self, k: usize) -> bool {
        self.reported[k]
    }

    /// True without circles (never for a built strip).
    pub fn is_empty(&self) -> bool {
        self.circles.is_empty()
    }

    /// Total area of the strip, mm² (all 2π).
    pub fn total_area(&self) -> f64 {
        std::f64::consts::TAU * self.band_area.iter().sum::<f64>()
    }
}

/// The profile parameter of `piece` at height `z` (non-horizontal pieces are monotone in z).
fn s_at(piece: &AnyPiece, z: f64) -> f64 {
    let (mut a, mut b) = (0.0f64, 1.0f64);
    for _ in 0..60 {
        let m = 0.5 * (a + b);
        if piece.profile_point(m).y < z {
            a = m;
        } else {
            b = m;
        }
    }
    0.5 * (a + b)
}

fn side_circle(pieces: &[&AnyPiece], z: f64) -> Option<Circle> {
    let p = pieces.iter().find(|p| {
        let (a, b) = p.z_range();
        z >= a && z <= b
    })?;
    Some(circle_on(p, z))
}

/// The circle of `piece` at height `z` (within its range).
fn circle_on(piece: &AnyPiece, z: f64) -> Circle {
    let s = s_at(piece, z);
    let q = piece.profile_point(s);
    Circle {
        z,
        rho: q.x,
        normal: piece.profile_normal(s),
    }
}

/// Profile speed `|dP/ds|` of a piece (constant: lines and arcs are parameterised uniformly).
fn speed(p: &AnyPiece) -> f64 {
    let eps = 1e-6;
    (p.profile_point(0.5 + eps) - p.profile_point(0.5 - eps)).length() / (2.0 * eps)
}

/// Length of the side's profile between heights `a < b`, mm.
fn arc_length(pieces: &[&AnyPiece], a: f64, b: f64) -> f64 {
    pieces
        .iter()
        .map(|p| {
            let (z0, z1) = p.z_range();
            let (lo, hi) = (a.max(z0), b.min(z1));
            if hi > lo {
                speed(p) * (s_at(p, hi) - s_at(p, lo))
            } else {
                0.0
            }
        })
        .sum()
}

/// The height between `a` and `b` where the profile length from `a` is `len`.
fn z_at_arc_length(pieces: &[&AnyPiece], a: f64, b: f64, len: f64) -> f64 {
    let (mut lo, mut hi) = (a, b);
    for _ in 0..60 {
        let m = 0.5 * (lo + hi);
        if arc_length(pieces, a, m) < len {
            lo = m;
        } else {
            hi = m;
        }
    }
    0.5 * (lo + hi)
}

/// `∫ dz/ρ` over the side between heights `a < b`: Gauss–Legendre in each piece's profile
/// parameter, where the integrand `z'(s)/ρ(s)` stays finite even at a ball's tip (`ρ → 0` as
/// `z' → 0`), so a helical edge's lag is finite there.
fn turn_between(pieces: &[&AnyPiece], a: f64, b: f64) -> f64 {
    const PANELS: usize = 4;
    let mut turn = 0.0;
    for p in pieces {
        let (z0, z1) = p.z_range();
        let (lo, hi) = (a.max(z0), b.min(z1));
        if hi <= lo {
            continue;
        }
        let (s0, s1) = (s_at(p, lo), s_at(p, hi));
        let panel = (s1 - s0) / PANELS as f64;
        for q in 0..PANELS {
            let half = 0.5 * panel;
            let mid = s0 + panel * (q as f64 + 0.5);
            for (x, w) in GL5_X.iter().zip(GL5_W) {
                let s = mid + half * x;
                let eps = 1e-7;
                let (sa, sb) = ((s - eps).max(0.0), (s + eps).min(1.0));
                let dz = (p.profile_point(sb).y - p.profile_point(sa).y) / (sb - sa);
                let rho = p.profile_point(s).x;
                if rho > 0.0 {
                    turn += w * half * dz / rho;
                }
            }
        }
    }
    turn
}

const GL5_X: [f64; 5] = [
    -0.906_179_845_938_664,
    -0.538_469_310_105_683,
    0.0,
    0.538_469_310_105_683,
    0.906_179_845_938_664,
];
const GL5_W: [f64; 5] = [
    0.236_926_885_056_189,
    0.478_628_670_499_366,
    0.568_888_888_888_889,
    0.478_628_670_499_366,
    0.236_926_885_056_189,
];

/// `∫ ρ ds` over the side between heights `a < b` (area per radian): 5-point Gauss–Legendre in
/// each piece's profile parameter, exact for cones and cylinders and to ~1e-12 on arcs.
fn side_area(pieces: &[&AnyPiece], a: f64, b: f64) -> f64 {
    let mut area = 0.0;
    for p in pieces {
        let (z0, z1) = p.z_range();
        let (lo, hi) = (a.max(z0), b.min(z1));
        if hi <= lo {
            continue;
        }
        let (s0, s1) = (s_at(p, lo), s_at(p, hi));
        let half = 0.5 * (s1 - s0);
        for (x, w) in GL5_X.iter().zip(GL5_W) {
            let s = s0 + half * (1.0 + x);
            let eps = 1e-6;
            let d = (p.profile_point((s + eps).min(1.0)) - p.profile_point((s - eps).max(0.0)))
                .length()
                / ((s + eps).min(1.0) - (s - eps).max(0.0));
            area += w * half * p.profile_point(s).x * d;
        }
    }
    area
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{PI, TAU};

    #[test]
    fn flat_end_mill_side_and_bottom_areas() {
        let c = Cutter::flat(10.0).unwrap();
        let side = Strip::side(&c, 0.1).unwrap();
        let h = c.apt_params().h;
        assert!((side.total_area() - TAU * 5.0 * h).abs() < 1e-9);
        assert!((side.circles[1].z - 0.05).abs() < 1e-12 && side.circles[1].rho == 5.0);
        assert_eq!(side.circles[0].z, 0.0);
        assert_eq!(
            side.reported.iter().filter(|&&r| r).count(),
            (c.apt_params().h / 0.1).round() as usize
        );
        let bottom = Strip::bottom(&c, 0.1).unwrap();
        assert_eq!(bottom.len(), 52);
        assert!((bottom.total_area() - PI * 25.0).abs() < 1e-9);
    }

    #[test]
    fn ball_zone_area_is_archimedes() {
        let c = Cutter::ball(10.0).unwrap();
        let side = Strip::side(&c, 0.1).unwrap();
        // Between circles at z = 0.05 and z = 2.95: a zone of height 2.9 on a sphere of radius 5.
        let k1 = side
            .param
            .iter()
            .position(|&z| (z - 2.95).abs() < 1e-9)
            .unwrap();
        let k0 = side
            .param
            .iter()
            .position(|&z| (z - 0.05).abs() < 1e-9)
            .unwrap();
        let a: f64 = side.band_area[k0..k1].iter().sum();
        assert!((a - 5.0 * 2.9).abs() < 1e-9, "{a}");
        assert!(Strip::bottom(&c, 0.1).is_none());
        let s = side.circles[k1];
        assert!((s.rho - (25.0f64 - 2.05 * 2.05).sqrt()).abs() < 1e-9);
        assert!((s.normal - Vec2::new(s.rho / 5.0, -2.05 / 5.0)).length() < 1e-9);
    }

    #[test]
    fn slabs_tile_the_strip_and_turn_is_exact() {
        // Flat: slabs [k·dz, (k+1)·dz], the last to h; turn = z/R.
        let c = Cutter::flat(10.0).unwrap();
        let side = Strip::side(&c, 0.1).unwrap();
        let rep: Vec<usize> = (0..side.len()).filter(|&k| side.reported[k]).collect();
        let h = c.apt_params().h;
        assert_eq!(side.slab[rep[0]].0, 0.0);
        assert!((side.slab[*rep.last().unwrap()].1 - h).abs() < 1e-12);
        for w in rep.windows(2) {
            assert_eq!(side.slab[w[0]].1, side.slab[w[1]].0);
        }
        let width: f64 = rep.iter().map(|&k| side.slab_width[k]).sum();
        assert!((width - h).abs() < 1e-9);
        let k = side.circle_at(2.05).unwrap();
        assert!(side.slab[k].0 == 2.0 && (side.slab[k].1 - 2.1).abs() < 1e-12);
        assert!((side.slab_turn[k].0 - 2.0 / 5.0).abs() < 1e-9);
        assert!((side.slab_turn[k].1 - 2.1 / 5.0).abs() < 1e-9);
        // Ball of radius 5: z = 5(1 − cos θ), ρ = 5 sin θ, so ∫dz/ρ = θ (finite at the tip).
        let c = Cutter::ball(10.0).unwrap();
        let side = Strip::side(&c, 0.1).unwrap();
        for z in [0.05, 1.05, 4.95] {
            let k = side.circle_at(z).unwrap();
            let (a, b) = side.slab[k];
            let theta = |z: f64| (1.0 - z / 5.0).acos();
            assert!((side.slab_turn[k].0 - theta(a)).abs() < 1e-6, "{z}");
            assert!((side.slab_turn[k].1 - theta(b)).abs() < 1e-6, "{z}");
            let arc = 5.0 * (theta(b) - theta(a));
            assert!((side.slab_width[k] - arc).abs() < 1e-6, "{z}");
        }
        // Bottom rings tile [0, e].
        let c = Cutter::bull(10.0, 2.0).unwrap();
        let bottom = Strip::bottom(&c, 0.1).unwrap();
        let w: f64 = bottom.slab_width.iter().sum();
        assert!((w - 3.0).abs() < 1e-12);
    }

    #[test]
    fn every_joint_of_the_profile_has_a_circle_of_each_piece() {
        // The ball's sphere meets its cylinder at z = R with one normal: one circle there,
        // the normal (1, 0). A 118° drill's cone meets its cylinder at R/tan 59° with two:
        // two circles there, a band of no area between them, the cone's normal then the
        // cylinder's. No band spans a joint, and the circles still tile the areas.
        let side = Strip::side(&Cutter::ball(10.0).unwrap(), 0.1).unwrap();
        let at: Vec<usize> = (0..side.len())
            .filter(|&k| (side.param[k] - 5.0).abs() < 1e-12)
            .collect();
        assert_eq!(at.len(), 1);
        assert!((side.circles[at[0]].normal - Vec2::new(1.0, 0.0)).length() < 1e-9);
        assert!(!side.is_reported(at[0]));
        let c = Cutter::drill(10.0, 118.0).unwrap();
        let side = Strip::side(&c, 0.1).unwrap();
        let joint = 5.0 / 59f64.to_radians().tan();
        let at: Vec<usize> = (0..side.len())
            .filter(|&k| (side.param[k] - joint).abs() < 1e-12)
            .collect();
        assert_eq!(at.len(), 2, "{:?}", &side.param[..40]);
        let (cone, cyl) = (side.circles[at[0]], side.circles[at[1]]);
        let t = 59f64.to_radians();
        assert!(
            (cone.normal - Vec2::new(t.cos(), -t.sin())).length() < 1e-9,
            "{cone:?}"
        );
        assert!(
            (cyl.normal - Vec2::new(1.0, 0.0)).length() < 1e-9,
            "{cyl:?}"
        );
        assert_eq!(side.band_area[at[0]], 0.0);
        let h = c.apt_params().h;
        let want = 0.5 * 5.0 * 5.0 / t.sin() + 5.0 * (h - joint);
        assert!((side.total_area() / TAU - want).abs() < 1e-9);
        // The reported discs are the same as without the joints: one every dz.
        let reported = (0..side.len()).filter(|&k| side.is_reported(k)).count();
        assert_eq!(reported, (h / 0.1).ceil() as usize);
    }

    #[test]
    fn bull_nose_side_area() {
        let c = Cutter::bull(10.0, 2.0).unwrap();
        let side = Strip::side(&c, 0.1).unwrap();
        // Quarter torus e = 3, r = 2: ∫(e + r sin ψ) r dψ over [0, π/2] = r(eπ/2 + r).
        let torus = 2.0 * (3.0 * PI / 2.0 + 2.0);
        let cyl = 5.0 * (c.apt_params().h - 2.0);
        assert!((side.total_area() / TAU - (torus + cyl)).abs() < 1e-9);
        assert!((Strip::bottom(&c, 0.1).unwrap().total_area() - 9.0 * PI).abs() < 1e-9);
    }
}
