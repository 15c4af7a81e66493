//! Horizontal discs and annuli (flat bottoms, top caps, steps of shanks and holders).

use super::{retain_from, Piece};
use swarf_geom::math::{Vec2, Vec3};
use swarf_geom::{Implicit, Plane, Ray};

/// The annulus `ρ ∈ [inner, outer)` at height `z`, facing down (`facing_up = false`, a bottom)
/// or up (a top cap).
#[derive(Clone, Debug, PartialEq)]
pub struct DiscPiece {
    /// Height of the disc.
    pub z: f64,
    /// Inner radius (0 for a full disc).
    pub inner: f64,
    /// Outer radius.
    pub outer: f64,
    /// Whether the outward normal is +Z.
    pub facing_up: bool,
}

impl DiscPiece {
    /// The annulus at `z` between `inner` and `outer`.
    pub fn new(z: f64, inner: f64, outer: f64, facing_up: bool) -> Self {
        Self {
            z,
            inner,
            outer,
            facing_up,
        }
    }
}

impl Piece for DiscPiece {
    fn z_range(&self) -> (f64, f64) {
        (self.z, self.z)
    }

    fn profile_point(&self, s: f64) -> Vec2 {
        Vec2::new(self.inner + s * (self.outer - self.inner), self.z)
    }

    fn profile_normal(&self, _s: f64) -> Vec2 {
        Vec2::new(0.0, if self.facing_up { 1.0 } else { -1.0 })
    }

    fn radius_at(&self, z: f64) -> Option<f64> {
        (z == self.z).then_some(self.outer)
    }

    fn ray_intersections(&self, ray: &Ray, out: &mut Vec<f64>) {
        let start = out.len();
        Plane::new(Vec3::new(0.0, 0.0, self.z), Vec3::Z).ray_intersections(ray, out);
        let (inner, outer) = (self.inner, self.outer);
        retain_from(out, start, ray, |p| {
            let rho = p.x.hypot(p.y);
            rho >= inner && rho < outer
        });
    }

    fn is_horizontal(&self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hits_inside_annulus_only() {
        let d = DiscPiece::new(2.0, 1.0, 3.0, true);
        let mut h = Vec::new();
        d.ray_intersections(&Ray::new(Vec3::new(2.0, 0.0, 0.0), Vec3::Z), &mut h);
        assert_eq!(h, vec![2.0]);
        d.ray_intersections(&Ray::new(Vec3::new(0.5, 0.0, 0.0), Vec3::Z), &mut h);
        d.ray_intersections(&Ray::new(Vec3::new(3.5, 0.0, 0.0), Vec3::Z), &mut h);
        assert_eq!(h.len(), 1);
        assert_eq!(d.normal(0.5, 1.0), Vec3::Z);
        assert_eq!(d.radius_at(2.0), Some(3.0));
    }
}
