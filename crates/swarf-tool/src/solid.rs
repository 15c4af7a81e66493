//! Closed solids of revolution bounded by [`Piece`]s: the cutting part, the shank, the holder.

use crate::piece::{AnyPiece, Piece};
use swarf_geom::math::Vec3;
use swarf_geom::{Aabb, Ray};

/// A closed solid of revolution about +Z, bounded by pieces ordered bottom to top.
///
/// Invariants (kept by the builders in this crate): the pieces form a closed boundary, every
/// horizontal line in the band meets the non-horizontal pieces in exactly one profile point
/// (z is monotone along the profile apart from horizontal discs), and the solid is
/// `{p : z_min ≤ z ≤ z_max, ρ ≤ R(z)}` for the profile radius `R`.
#[derive(Clone, Debug, PartialEq)]
pub struct RevolvedSolid {
    pieces: Vec<AnyPiece>,
    z_min: f64,
    z_max: f64,
}

impl RevolvedSolid {
    /// The solid bounded by `pieces` (bottom to top) between `z_min` and `z_max`.
    pub(crate) fn new(pieces: Vec<AnyPiece>, z_min: f64, z_max: f64) -> Self {
        Self {
            pieces,
            z_min,
            z_max,
        }
    }

    /// A stack of frustums `(z0, z1, r0, r1)` (ascending, contiguous), closed by discs at the
    /// ends and annuli at radius steps. Used for shanks and holders.
    pub(crate) fn stack(segments: &[(f64, f64, f64, f64)]) -> Self {
        use crate::piece::{ConePiece, CylinderPiece, DiscPiece};
        use swarf_geom::math::Vec2;
        let mut pieces = Vec::new();
        let mut below = 0.0; // radius of the previous segment's top
        for &(z0, z1, r0, r1) in segments {
            if r0 != below {
                // Step between segments (or the bottom face): faces down when widening.
                pieces.push(AnyPiece::Disc(DiscPiece::new(
                    z0,
                    below.min(r0),
                    below.max(r0),
                    r0 < below,
                )));
            }
            if r0 == r1 {
                pieces.push(AnyPiece::Cylinder(CylinderPiece::new(r0, z0, z1)));
            } else {
                pieces.push(AnyPiece::Cone(ConePiece::new(
                    Vec2::new(r0, z0),
                    Vec2::new(r1, z1),
                )));
            }
            below = r1;
        }
        let z_min = segments.first().map_or(0.0, |s| s.0);
        let z_max = segments.last().map_or(0.0, |s| s.1);
        if below > 0.0 {
            pieces.push(AnyPiece::Disc(DiscPiece::new(z_max, 0.0, below, true)));
        }
        Self::new(pieces, z_min, z_max)
    }

    /// The boundary pieces, bottom to top.
    pub fn pieces(&self) -> &[AnyPiece] {
        &self.pieces
    }

    /// Lowest and highest z.
    pub fn z_range(&self) -> (f64, f64) {
        (self.z_min, self.z_max)
    }

    /// Radius of the solid at height `z` (the largest where pieces meet at a step); `None`
    /// outside `[z_min, z_max]`.
    pub fn profile_radius(&self, z: f64) -> Option<f64> {
        if !(z >= self.z_min && z <= self.z_max) {
            return None;
        }
        let r = self
            .pieces
            .iter()
            .filter_map(|p| p.radius_at(z))
            .fold(f64::NEG_INFINITY, f64::max);
        Some(r.max(0.0))
    }

    /// Largest radius over the whole solid.
    pub fn max_radius(&self) -> f64 {
        // Extremes of a profile of segments and arcs: segment ends, and for arcs their ends or
        // the outermost point φ = π/2 when inside the arc.
        let mut m: f64 = 0.0;
        for p in &self.pieces {
            m = m.max(p.profile_point(0.0).x).max(p.profile_point(1.0).x);
            let (phi0, phi1, rho_max) = match p {
                AnyPiece::Torus(t) => (t.phi0, t.phi1, t.major + t.minor),
                AnyPiece::Sphere(s) => (s.phi0, s.phi1, s.radius),
                _ => continue,
            };
            if phi0 <= std::f64::consts::FRAC_PI_2 && phi1 >= std::f64::consts::FRAC_PI_2 {
                m = m.max(rho_max);
            }
        }
        m
    }

    /// True when `p` (local coordinates) is in the closed solid.
    pub fn contains(&self, p: Vec3) -> bool {
        match self.profile_radius(p.z) {
            Some(r) => p.x.hypot(p.y) <= r,
            None => false,
        }
    }

    /// Appends every parameter where `ray` (local coordinates) crosses the boundary, sorted
    /// ascending among the appended ones. Rays through a junction circle count once.
    pub fn ray_intersections(&self, ray: &Ray, out: &mut Vec<f64>) {
        let start = out.len();
        for p in &self.pieces {
            p.ray_intersections(ray, out);
        }
        out[start..].sort_by(f64::total_cmp);
    }

    /// Axis-aligned bounding box in local coordinates.
    pub fn aabb(&self) -> Aabb {
        let r = self.max_radius();
        Aabb::new(Vec3::new(-r, -r, self.z_min), Vec3::new(r, r, self.z_max))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stepped_stack() {
        // Shank Ø6 from 10 to 40, then a Ø20→Ø30 cone to 60.
        let s = RevolvedSolid::stack(&[(10.0, 40.0, 3.0, 3.0), (40.0, 60.0, 10.0, 15.0)]);
        assert_eq!(s.profile_radius(20.0), Some(3.0));
        assert_eq!(s.profile_radius(40.0), Some(10.0));
        assert_eq!(s.profile_radius(50.0), Some(12.5));
        assert_eq!(s.profile_radius(61.0), None);
        assert_eq!(s.max_radius(), 15.0);
        assert!(s.contains(Vec3::new(0.0, 9.0, 45.0)) && !s.contains(Vec3::new(0.0, 9.0, 35.0)));
        // Vertical ray at ρ = 5: enters the step annulus at z = 40 and leaves through the top.
        let mut h = Vec::new();
        s.ray_intersections(&Ray::new(Vec3::new(5.0, 0.0, 0.0), Vec3::Z), &mut h);
        assert_eq!(h, vec![40.0, 60.0]);
        // Vertical ray at ρ = 1: through everything.
        h.clear();
        s.ray_intersections(&Ray::new(Vec3::new(1.0, 0.0, 0.0), Vec3::Z), &mut h);
        assert_eq!(h, vec![10.0, 60.0]);
    }
}
