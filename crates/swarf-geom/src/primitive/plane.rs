//! The plane `z = 0` of a frame.

use super::Implicit;
use crate::frame::Frame;
use crate::math::Vec3;
use crate::ray::Ray;

/// The plane through the frame origin, normal to the frame's z axis. **Inside** is the half
/// space `z < 0` (the normal points out).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Plane {
    /// Placement; the plane is the frame's xy plane.
    pub frame: Frame,
}

impl Plane {
    /// The plane through `point` with outward normal `normal` (non-zero).
    pub fn new(point: Vec3, normal: Vec3) -> Self {
        Self {
            frame: Frame::from_axis(point, normal),
        }
    }
}

impl Implicit for Plane {
    fn signed_distance(&self, p: Vec3) -> f64 {
        (p - self.frame.origin).dot(self.frame.z)
    }

    fn ray_intersections(&self, ray: &Ray, out: &mut Vec<f64>) {
        let dn = ray.dir.dot(self.frame.z);
        if dn != 0.0 {
            out.push(-self.signed_distance(ray.origin) / dn);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distance_and_hit() {
        let p = Plane::new(Vec3::new(0.0, 0.0, 2.0), Vec3::new(0.0, 0.0, -3.0));
        assert!((p.signed_distance(Vec3::new(5.0, 1.0, 0.0)) - 2.0).abs() < 1e-15);
        let mut h = Vec::new();
        p.ray_intersections(
            &Ray::new(Vec3::new(1.0, 1.0, -1.0), Vec3::new(1.0, 0.0, 2.0)),
            &mut h,
        );
        assert_eq!(h, vec![1.5]);
        h.clear();
        p.ray_intersections(&Ray::new(Vec3::ZERO, Vec3::X), &mut h);
        assert!(h.is_empty());
    }
}
