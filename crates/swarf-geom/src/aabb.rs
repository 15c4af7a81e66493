//! Axis-aligned bounding boxes.

use crate::math::Vec3;

/// A closed axis-aligned box `[min, max]` (componentwise `min ≤ max` for a non-empty box).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Aabb {
    /// Lower corner.
    pub min: Vec3,
    /// Upper corner.
    pub max: Vec3,
}

impl Aabb {
    /// The box with corners `a` and `b` (in any order).
    pub fn new(a: Vec3, b: Vec3) -> Self {
        Self {
            min: a.min(b),
            max: a.max(b),
        }
    }

    /// The smallest box holding all points, or `None` for no points.
    pub fn from_points<I: IntoIterator<Item = Vec3>>(points: I) -> Option<Self> {
        let mut it = points.into_iter();
        let first = it.next()?;
        Some(it.fold(Self::new(first, first), |b, p| b.extended(p)))
    }

    /// The smallest box holding this one and `p`.
    pub fn extended(&self, p: Vec3) -> Self {
        Self {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    /// The smallest box holding both.
    pub fn union(&self, other: &Aabb) -> Self {
        Self {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    /// True when `p` is in the closed box.
    pub fn contains(&self, p: Vec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }

    /// True when the boxes share at least one point.
    pub fn intersects(&self, other: &Aabb) -> bool {
        self.min.cmple(other.max).all() && other.min.cmple(self.max).all()
    }

    /// Edge lengths.
    pub fn size(&self) -> Vec3 {
        self.max - self.min
    }

    /// Centre point.
    pub fn center(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    /// The box grown by `margin` on every side.
    pub fn inflated(&self, margin: f64) -> Self {
        Self {
            min: self.min - Vec3::splat(margin),
            max: self.max + Vec3::splat(margin),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn from_points_union_contains() {
        let b = Aabb::from_points([Vec3::new(1.0, 5.0, -1.0), Vec3::new(-2.0, 0.0, 3.0)]).unwrap();
        assert_eq!(b.min, Vec3::new(-2.0, 0.0, -1.0));
        assert_eq!(b.max, Vec3::new(1.0, 5.0, 3.0));
        assert!(b.contains(Vec3::new(1.0, 0.0, 0.0)));
        assert!(!b.contains(Vec3::new(1.0 + 1e-12, 0.0, 0.0)));
        let c = b.union(&Aabb::new(Vec3::splat(10.0), Vec3::splat(9.0)));
        assert_eq!(c.max, Vec3::splat(10.0));
        assert!(b.intersects(&c) && !b.intersects(&Aabb::new(Vec3::splat(6.0), Vec3::splat(7.0))));
        assert!(Aabb::from_points(std::iter::empty()).is_none());
        let j = serde_json::to_string(&b).unwrap();
        assert_eq!(j, r#"{"min":[-2.0,0.0,-1.0],"max":[1.0,5.0,3.0]}"#);
    }
}
