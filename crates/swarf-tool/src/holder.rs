//! Tool holders: stacks of cylinders and cones above the tool, for collision checks.

use crate::error::ToolError;
use crate::solid::RevolvedSolid;

/// One segment of a holder: a frustum `length_mm` tall from `bottom_diameter_mm` to
/// `top_diameter_mm` (equal diameters: a cylinder).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct HolderSegment {
    /// Height of the segment, mm (> 0).
    pub length_mm: f64,
    /// Diameter at the bottom, mm (> 0).
    pub bottom_diameter_mm: f64,
    /// Diameter at the top, mm (> 0).
    pub top_diameter_mm: f64,
}

/// A holder: segments stacked upwards from `base_z_mm`, the height of the holder's bottom face
/// above the tool tip (the gauge stick-out).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Holder {
    /// Height of the holder's bottom face above the tool tip, mm (> 0).
    pub base_z_mm: f64,
    /// Segments, bottom to top (at least one).
    pub segments: Vec<HolderSegment>,
}

impl Holder {
    /// The holder as a closed solid in the cutter frame, after validating every number.
    pub fn solid(&self) -> Result<RevolvedSolid, ToolError> {
        let bad = |param: String, value: f64| ToolError::OutOfRange {
            param,
            value,
            requirement: "a finite number > 0 mm".into(),
        };
        if !(self.base_z_mm.is_finite() && self.base_z_mm > 0.0) {
            return Err(bad("holder base height".into(), self.base_z_mm));
        }
        if self.segments.is_empty() {
            return Err(ToolError::OutOfRange {
                param: "holder segment count".into(),
                value: 0.0,
                requirement: ">= 1".into(),
            });
        }
        let mut z = self.base_z_mm;
        let mut stack = Vec::with_capacity(self.segments.len());
        for (i, s) in self.segments.iter().enumerate() {
            for (name, v) in [
                ("length", s.length_mm),
                ("bottom diameter", s.bottom_diameter_mm),
                ("top diameter", s.top_diameter_mm),
            ] {
                if !(v.is_finite() && v > 0.0) {
                    return Err(bad(format!("holder segment {} {name}", i + 1), v));
                }
            }
            stack.push((
                z,
                z + s.length_mm,
                s.bottom_diameter_mm / 2.0,
                s.top_diameter_mm / 2.0,
            ));
            z += s.length_mm;
        }
        Ok(RevolvedSolid::stack(&stack))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use swarf_geom::math::Vec3;

    #[test]
    fn holder_solid_and_validation() {
        let h = Holder {
            base_z_mm: 40.0,
            segments: vec![
                HolderSegment {
                    length_mm: 20.0,
                    bottom_diameter_mm: 20.0,
                    top_diameter_mm: 30.0,
                },
                HolderSegment {
                    length_mm: 10.0,
                    bottom_diameter_mm: 50.0,
                    top_diameter_mm: 50.0,
                },
            ],
        };
        let s = h.solid().unwrap();
        assert_eq!(s.z_range(), (40.0, 70.0));
        assert_eq!(s.profile_radius(50.0), Some(12.5));
        assert!(s.contains(Vec3::new(24.0, 0.0, 65.0)));
        let mut bad = h.clone();
        bad.segments[1].length_mm = -1.0;
        let e = bad.solid().unwrap_err().to_string();
        assert!(
            e.contains("holder segment 2 length") && e.contains("-1"),
            "{e}"
        );
    }
}
