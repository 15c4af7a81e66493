//! A cutter prepared for sweeping: the convex profiles of its cutting part and of its shank and
//! holder, each swept exactly by [`crate::swept`].

use swarf_geom::math::Vec2;
use swarf_tool::Cutter;

use crate::five_axis::Reach;
use crate::swept::{ConvexProfile, Element, SweepShape};

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
    /// Per band, its height range when it may be cut as instances.
    instance_bands: [Vec<Option<(f64, f64)>>; 2],
    /// `(ρ, z_s)` of [`rolling_region`], when the tool has one.
    rolling: Option<(f64, f64)>,
}

/// A band of a turning tool that may be cut as a union of exact tool instances instead of
/// constant-axis sweeps (`swarf_sweep::five_axis`, "Instances"): every point of the band lies
/// in a ball of radius `rho` inside the tool.
#[derive(Clone, Debug)]
pub struct InstanceBand {
    /// The band's height range above the tip, mm.
    pub range: (f64, f64),
    /// The tool within `2·rho` of the band (every ball that holds a point of the band), as the
    /// cutting part's (`[0]`) and the shank and holder's (`[1]`) pieces of it, tool frame.
    pub slabs: [SweepShape; 2],
    /// Radius of the balls, mm.
    pub rho: f64,
    /// Largest distance of a ball's centre from the tip, mm.
    pub centre_reach: f64,
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
        let rolling = rolling_region(&cutting, &non_cutting);
        let instance_bands = [0, 1].map(|w| {
            bands[w]
                .iter()
                .map(|(band, _)| {
                    let (rho, smooth_top) = rolling?;
                    let range = band
                        .parts()
                        .iter()
                        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                            (a.min(p.z_min()), b.max(p.z_max()))
                        });
                    (range.1 <= smooth_top - 2.0 * rho).then_some(range)
                })
                .collect()
        });
        Self {
            cutting,
            non_cutting,
            bands,
            instance_bands,
            rolling,
        }
    }

    /// For each of [`ToolShape::rotating_bands`]`(which)`, its height range when the band may
    /// be cut as instances (its points all lie in balls of one radius inside the tool,
    /// [`ToolShape::round_region`]).
    pub fn instance_bands(&self, which: usize) -> &[Option<(f64, f64)>] {
        &self.instance_bands[which]
    }

    /// The tool around the heights `range` (tool frame, mm) for cutting them as instances,
    /// when every point there lies in a ball of one radius inside the tool; `None` otherwise.
    pub fn round_region(&self, range: (f64, f64)) -> Option<InstanceBand> {
        let (rho, smooth_top) = self.rolling?;
        instance_band(range, rho, smooth_top, [&self.cutting, &self.non_cutting])
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

/// Where the tool is round enough to be cut as instances: `(ρ, z_s)` such that every boundary
/// point of the tool below `z_s − ρ` is touched from inside by a ball of radius `ρ` within the
/// tool (so every point of the tool below `z_s − 2ρ` lies in such a ball); `None` when the tool
/// has a sharp edge at its bottom (a flat end mill's rim, a drill's point).
///
/// The side of the union of the parts is walked up from the tip while it is made of outward
/// arcs (spheres, tori: profile radius `r`, and the other principal radius, along the normal to
/// the axis, is at least `r`) and vertical lines (cylinders of radius `R`) meeting
/// tangentially (C¹; a junction of two parts counts when the sides meet in one point with one
/// tangent), after a bottom disc from the axis or a sphere starting on it. Its curvature is
/// at most `1/ρ` with `ρ` the least of those radii, and closing it above `z_s − ρ` by a
/// rounded cap of radius `ρ` gives a convex body inside the tool with the same boundary below
/// `z_s − ρ`, in which a ball of radius `ρ` rolls freely (Blaschke's rolling theorem).
fn rolling_region(cutting: &SweepShape, non_cutting: &SweepShape) -> Option<(f64, f64)> {
    const EPS: f64 = 1e-7;
    let mut parts: Vec<&ConvexProfile> =
        cutting.parts().iter().chain(non_cutting.parts()).collect();
    parts.sort_by(|a, b| a.z_min().total_cmp(&b.z_min()));
    let lowest = parts.first()?;
    if lowest.z_min().abs() > EPS {
        return None;
    }
    let horizontal =
        |el: &Element| matches!(*el, Element::Line { p, q } if (q.y - p.y).abs() <= EPS);
    // The bottom: a disc from the axis, or the side starting on the axis.
    let (mut at, mut tangent) = (Vec2::ZERO, Vec2::new(1.0, 0.0));
    let first = lowest.elements().first()?;
    if let (Element::Line { p, q }, true) = (first, horizontal(first)) {
        if p.x.abs() > EPS || q.x <= p.x {
            return None;
        }
        at = *q;
    }
    let mut rho = f64::INFINITY;
    let mut top = 0.0f64;
    let sides = parts.iter().flat_map(|p| {
        p.elements()
            .iter()
            .filter(|el| !horizontal(el))
            .map(move |el| (p.z_min(), el))
    });
    for (part_bottom, el) in sides {
        // A part whose side does not continue the round side may cover it from its bottom up
        // (a holder around the shank): the round region ends there at the latest.
        let stop = |top: f64| top.min(part_bottom);
        let (start, end, t0, t1, radius) = match *el {
            Element::Line { p, q } if (q.x - p.x).abs() <= EPS && q.y > p.y => {
                let t = Vec2::new(0.0, 1.0);
                (p, q, t, t, p.x)
            }
            Element::Arc {
                e,
                f,
                r,
                phi0,
                phi1,
            } if e >= -EPS && phi0 >= -EPS && phi1 <= std::f64::consts::FRAC_PI_2 + EPS => (
                Vec2::new(e + r * phi0.sin(), f - r * phi0.cos()),
                Vec2::new(e + r * phi1.sin(), f - r * phi1.cos()),
                Vec2::new(phi0.cos(), phi0.sin()),
                Vec2::new(phi1.cos(), phi1.sin()),
                r,
            ),
            _ => {
                top = stop(top);
                break;
            }
        };
        if (start - at).length() > EPS || (t0 - tangent).length() > 1e-9 {
            top = stop(top);
            break;
        }
        rho = rho.min(radius);
        (at, tangent, top) = (end, t1, end.y);
    }
    (rho.is_finite() && rho > EPS && top > 0.0).then_some((rho, top))
}

/// The [`InstanceBand`] of the heights `(lo, hi)` when they lie low enough in the round region `(ρ, z_s)` of
/// the tool made of `parts` (cutting part, shank and holder).
fn instance_band(
    (lo, hi): (f64, f64),
    rho: f64,
    smooth_top: f64,
    parts: [&SweepShape; 2],
) -> Option<InstanceBand> {
    if !(lo <= hi && hi <= smooth_top - 2.0 * rho) {
        return None;
    }
    let slabs = parts.map(|shape| {
        SweepShape::from_parts(
            shape
                .parts()
                .iter()
                .filter_map(|p| p.clipped(lo - 2.0 * rho, hi + 2.0 * rho))
                .collect(),
        )
    });
    // Centres within ρ of a band point: heights in [lo − ρ, hi + ρ], at most the tool's
    // radius there less ρ from the axis.
    let r_max = parts
        .iter()
        .flat_map(|s| s.parts())
        .filter_map(|p| p.max_radius_in(lo - rho, hi + rho))
        .fold(0.0, f64::max);
    let centre_reach = (r_max - rho)
        .max(0.0)
        .hypot((lo - rho).abs().max((hi + rho).abs()));
    Some(InstanceBand {
        range: (lo, hi),
        slabs,
        rho,
        centre_reach,
    })
}
