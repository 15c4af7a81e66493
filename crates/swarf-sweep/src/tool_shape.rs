//! A cutter prepared for sweeping: the convex profiles of its cutting part and of its shank and
//! holder, each swept exactly by [`crate::swept`].

use swarf_tool::Cutter;

use crate::swept::SweepShape;

/// A cutter prepared for sweeping: its cutting part and its non-cutting parts (shank and
/// holder) as unions of convex profiles.
#[derive(Clone, Debug)]
pub struct ToolShape {
    cutting: SweepShape,
    non_cutting: SweepShape,
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
        Self {
            cutting,
            non_cutting: SweepShape::from_parts(nc),
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
}
