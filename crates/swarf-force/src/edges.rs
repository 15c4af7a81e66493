//! A cutter's cutting edges as the force model sees them: its flutes, their helix, and the
//! axial discs and bottom rings of the engagement with each slab's radius, axial immersion
//! angle, chip width and helix lag.

use swarf_engage::{EngageOptions, Strip, StripKind};
use swarf_tool::Cutter;

use crate::ForceError;

/// One slab of the cutter surface (an axial disc, or a ring of a flat bottom), in the cutter
/// frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Slab {
    /// Radius of the slab's circle, mm.
    pub rho: f64,
    /// Height of the circle above the tip, mm.
    pub z: f64,
    /// Axial immersion angle κ of the edge, radians: the angle between the tool axis and the
    /// surface normal (90° on a cylinder, 0 on a flat bottom, the profile angle on a ball,
    /// torus or cone).
    pub kappa: f64,
    /// Profile length of the slab, mm (the chip width `db`).
    pub width: f64,
    /// Helix lag at the slab's two ends, radians (`tan i·∫dz/ρ`, growing with height).
    pub lag: (f64, f64),
    /// The slab's parameter range (height or radius), mm.
    pub range: (f64, f64),
}

/// The edges of one cutter, prepared for the force model.
#[derive(Clone, Debug)]
pub struct CutterEdges {
    /// Number of flutes (uniform pitch).
    pub flutes: u32,
    /// Helix angle, degrees.
    pub helix_deg: f64,
    /// Normal rake, degrees, when known.
    pub rake_deg: Option<f64>,
    side: Option<Strip>,
    bottom: Option<Strip>,
}

impl CutterEdges {
    /// The edges of `cutter`, with the engagement's discs (`opts.dz_mm`). `label` names the
    /// tool in errors.
    ///
    /// # Errors
    /// A cutter whose flute count was not given (the model needs it; a default would be a
    /// silent guess).
    pub fn new(cutter: &Cutter, opts: &EngageOptions, label: &str) -> Result<Self, ForceError> {
        let flutes = cutter.flutes_given().ok_or_else(|| ForceError::NoFlutes {
            tool: label.to_string(),
        })?;
        Ok(Self {
            flutes,
            helix_deg: cutter.helix_deg(),
            rake_deg: cutter.rake_deg(),
            side: Strip::side(cutter, opts.dz_mm),
            bottom: Strip::bottom(cutter, opts.dz_mm),
        })
    }

    /// The slab of the disc (`kind` side) or ring (bottom) reported at parameter `at`.
    pub fn slab(&self, kind: StripKind, at: f64) -> Option<Slab> {
        let strip = match kind {
            StripKind::Side => self.side.as_ref()?,
            StripKind::Bottom => self.bottom.as_ref()?,
        };
        let k = strip.circle_at(at)?;
        if !strip.is_reported(k) {
            return None;
        }
        let c = strip.circles[k];
        let tan_i = self.helix_deg.to_radians().tan();
        let (t0, t1) = strip.slab_turn[k];
        Some(Slab {
            rho: c.rho,
            z: c.z,
            kappa: c.normal.x.atan2(-c.normal.y),
            width: strip.slab_width[k],
            lag: (tan_i * t0, tan_i * t1),
            range: strip.slab[k],
        })
    }
}

impl Slab {
    /// The slab cut down (or grown) to the parameter range `[a, b]` within its neighbours,
    /// width and lag scaled linearly (exact on cylinders and cones).
    pub fn clipped(&self, a: f64, b: f64) -> Slab {
        let (lo, hi) = self.range;
        let len = hi - lo;
        if len <= 0.0 || b <= a {
            return Slab {
                width: 0.0,
                ..*self
            };
        }
        let at = |x: f64| self.lag.0 + (self.lag.1 - self.lag.0) * (x - lo) / len;
        Slab {
            width: self.width * (b - a) / len,
            lag: (at(a), at(b)),
            range: (a, b),
            ..*self
        }
    }
}
