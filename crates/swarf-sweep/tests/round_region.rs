//! The round region of a tool (`ToolShape::round_region`), where a turning tool is cut as exact
//! instances: every point of a band said to be round lies in a ball of the stated radius inside
//! the whole tool (cutting part, shank and holder), with its centre within the stated reach of
//! the tip. Checked by brute force in the meridian half-plane: a ball centred at distance `c`
//! from the axis and height `h` lies inside the tool iff `c + √(ρ² − (z − h)²) ≤ P(z)` at every
//! height `z` it spans, `P` the tool's radius (the largest of its parts' radii there).

use swarf_sweep::{Element, ToolShape};
use swarf_tool::{Cutter, CutterKind, CutterOptions, Holder, HolderSegment};

/// The tool's radius at height `z` (tool frame), `None` outside its height range.
fn radius(tool: &ToolShape, z: f64) -> Option<f64> {
    [tool.cutting(), tool.non_cutting()]
        .iter()
        .flat_map(|s| s.parts())
        .filter_map(|p| p.radius_at(z))
        .reduce(f64::max)
}

/// The largest distance from the axis at which a ball of radius `rho` centred at height `h`
/// lies inside the tool (to 1e-9 mm), if any: balls nearer the axis then fit too (the tool's
/// cross-sections are discs about the axis).
fn widest_centre(tool: &ToolShape, h: f64, rho: f64) -> Option<f64> {
    let mut c = f64::INFINITY;
    for i in 0..=400 {
        let z = h - rho + 2.0 * rho * i as f64 / 400.0;
        let w = (rho * rho - (z - h) * (z - h)).max(0.0).sqrt();
        c = c.min(radius(tool, z)? - w + 1e-9);
    }
    (c >= 0.0).then_some(c)
}

fn with(kind: CutterKind, nums: &[f64], opts: CutterOptions) -> Cutter {
    Cutter::named(kind, nums, &opts).unwrap()
}

fn holder() -> Holder {
    Holder {
        base_z_mm: 60.0,
        segments: vec![HolderSegment {
            length_mm: 20.0,
            bottom_diameter_mm: 20.0,
            top_diameter_mm: 30.0,
        }],
    }
}

#[test]
fn round_bands_lie_in_balls_inside_the_tool() {
    let narrow = CutterOptions {
        shank_diameter: Some(6.0),
        ..CutterOptions::default()
    };
    let held = CutterOptions {
        holder: Some(holder()),
        ..CutterOptions::default()
    };
    let cutters = [
        (Cutter::ball(10.0).unwrap(), 5.0),
        (Cutter::bull(10.0, 2.0).unwrap(), 2.0),
        (Cutter::bull(12.0, 0.5).unwrap(), 0.5),
        (with(CutterKind::Bull, &[10.0, 3.0], narrow.clone()), 3.0),
        (with(CutterKind::Ball, &[8.0], narrow), 4.0),
        (with(CutterKind::Bull, &[16.0, 4.0], held), 4.0),
    ];
    for (cutter, rho_expected) in cutters {
        let tool = ToolShape::new(&cutter);
        let mut round = 0;
        for k in 0..2 {
            for range in tool.instance_bands(k).iter().flatten() {
                round += 1;
                let region = tool.round_region(*range).unwrap();
                assert_eq!(region.rho, rho_expected, "{cutter:?}");
                let rho = region.rho;
                // A ball as round as an arc of the profile fits only at the arc's centre.
                let arc_centres: Vec<f64> = [tool.cutting(), tool.non_cutting()]
                    .iter()
                    .flat_map(|s| s.parts())
                    .flat_map(|p| p.elements())
                    .filter_map(|el| match *el {
                        Element::Arc { f, .. } => Some(f),
                        Element::Line { .. } => None,
                    })
                    .collect();
                // Points of the band on a grid of the half-plane (the tool's inside).
                for i in 0..=24 {
                    let z = range.0 + (range.1 - range.0) * i as f64 / 24.0;
                    let p = radius(&tool, z).unwrap();
                    for j in 0..=12 {
                        let r = p * j as f64 / 12.0;
                        // A centre within ρ of (r, z) whose ball is inside: for heights on
                        // a grid, the allowed centre nearest to (r, z).
                        let grid = (0..=64).map(|b| z + rho * (b as f64 / 32.0 - 1.0));
                        let found = grid.chain(arc_centres.iter().copied()).any(|h| {
                            widest_centre(&tool, h, rho).is_some_and(|cmax| {
                                let c = r.min(cmax);
                                (c - r).hypot(h - z) <= rho + 1e-9
                                    && c.hypot(h) <= region.centre_reach + 1e-9
                            })
                        });
                        assert!(
                            found,
                            "{:?} d {}: ({r}, {z}) in no ball of radius {rho}",
                            cutter.kind(),
                            cutter.max_diameter()
                        );
                    }
                }
            }
        }
        assert!(round > 0, "{cutter:?} has no round band");
    }
}

#[test]
fn sharp_tools_have_no_round_band() {
    for cutter in [
        Cutter::flat(10.0).unwrap(),
        Cutter::drill(8.0, 118.0).unwrap(),
        Cutter::chamfer(10.0, 90.0).unwrap(),
        Cutter::taper_flat(10.0, 5.0).unwrap(),
    ] {
        let tool = ToolShape::new(&cutter);
        for k in 0..2 {
            assert!(
                tool.instance_bands(k).iter().all(Option::is_none),
                "{cutter:?}"
            );
        }
        assert!(tool.round_region((0.0, 1.0)).is_none(), "{cutter:?}");
    }
}

#[test]
fn round_region_stops_two_radii_below_the_first_sharp_edge() {
    // A 10 mm ball, 30 mm of flutes and a 20 mm shank of the same diameter: round up to the
    // shank's top rim at 50 mm, so bands reaching above 50 − 2·5 are not round.
    let tool = ToolShape::new(&Cutter::ball(10.0).unwrap());
    assert!(tool.round_region((0.0, 40.0)).is_some());
    assert!(tool.round_region((0.0, 40.001)).is_none());
    // A narrower shank: the cutting part's top rim (30 mm) is sharp.
    let narrow = with(
        CutterKind::Ball,
        &[10.0],
        CutterOptions {
            shank_diameter: Some(6.0),
            ..CutterOptions::default()
        },
    );
    let tool = ToolShape::new(&narrow);
    let top = narrow.flute_length();
    assert!(tool.round_region((0.0, top - 10.0)).is_some());
    assert!(tool.round_region((0.0, top - 9.999)).is_none());
}
