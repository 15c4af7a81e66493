//! A cutter prepared for sweeping: the convex profiles of its cutting part and of its shank and
//! holder, each swept exactly by [`crate::swept`].

use swarf_tool::Cutter;

use crate::five_axis::Reach;
use crate::swept::SweepShape;

/// A part of a shape that turns (5-axis), cut into bands no taller than this many times its
/// radius: the band's reach from its middle is then at most `√(1 + (BAND_HEIGHT_RADII/2)²)`
/// radii (≈ 1.12), where a long part's reach grows with its length.
pub const BAND_HEIGHT_RADII: f64 = 1.0;

/// Bands under this height are not cut further, mm (a guard for needle-thin parts).
pub const MIN_BAND_HEIGHT_MM: f64 = 0.5;

/// A cutter prepared for sweeping: its cutting part and its non-cutting parts (shank and
/// holder) as unions of convex profiles.
#[derive(Clone, Debug)]
pub struct ToolShape {
    cutting: SweepShape,
    non_cutting: SweepShape,
    /// The bands of each, with their reach (for 5-axis moves).
    bands: [Vec<(SweepShape, Reach)>; 2],
}

impl ToolShape {
    /// The shapes of `cutter` (cutting part; shank plus holder).
    pub fn new(cutter: &Cutter) -> Self {
        let cutting = SweepShape::from_solid(cutter.cutting_solid());
        let mut nc = SweepShape::from_solid(cutter.shank_solid())
            .parts()
            .to_vec();
        if let Some(h) = cutter.holder_solid() {
            nc.extend_from_slice(SweepShape::from_solid(h).parts());
        }
        let non_cutting = SweepShape::from_parts(nc);
        let bands = [&cutting, &non_cutting].map(rotating_bands);
        Self {
            cutting,
            non_cutting,
            bands,
        }
    }

    /// The cutting part.
    pub fn cutting(&self) -> &SweepShape {
        &self.cutting
    }

    /// Shank and holder.
    pub fn non_cutting(&self) -> &SweepShape {
        &self.non_cutting
    }

    /// The cutting part's (`0`) or the shank and holder's (`1`) bands for a move whose axis
    /// turns, each a one-part shape with its [`Reach`] about its middle.
    pub fn rotating_bands(&self, which: usize) -> &[(SweepShape, Reach)] {
        &self.bands[which]
    }
}

/// `shape` cut into one-part bands no taller than [`BAND_HEIGHT_RADII`] radii of their part,
/// with their reach: the same solid, and each band's 5-axis error bound scales with its own
/// reach instead of the whole part's length.
fn rotating_bands(shape: &SweepShape) -> Vec<(SweepShape, Reach)> {
    let mut out = Vec::new();
    for part in shape.parts() {
        let whole = SweepShape::from_parts(vec![part.clone()]);
        let height = (BAND_HEIGHT_RADII * part.r_max()).max(MIN_BAND_HEIGHT_MM);
        for band in whole.bands(height).parts() {
            let band = SweepShape::from_parts(vec![band.clone()]);
            if let Some(reach) = Reach::of(&band) {
                out.push((band, reach));
            }
        }
    }
    out
}
