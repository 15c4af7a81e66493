//! 4- and 5-axis maps: the orientation columns after the 14 of the 3-axis CSV, the JSON summary
//! keys unchanged, and every point's size consistent with a direct solve at its orientation.

use std::f64::consts::FRAC_1_SQRT_2;

use swarf_geom::math::Vec3;
use swarf_plan::size::map::CSV_HEADER;
use swarf_plan::size::{
    allowable_along, allowable_map, Axes, Axis4Options, Axis5Options, CutterFamily, MapOptions,
    RotaryAxis, ToolAngles,
};
use swarf_surface::PreparedSurface;
use swarf_surface::{CompoundSurface, NurbsSurface, Patch, Surface};

/// The trough of `size_orient_4axis.rs` (radius 5, along Y, open towards +X), normal inwards.
fn trough() -> CompoundSurface {
    let r = 5.0;
    let w = FRAC_1_SQRT_2;
    let arc = [
        (Vec3::new(0.0, 0.0, -r), 1.0),
        (Vec3::new(-r, 0.0, -r), w),
        (Vec3::new(-r, 0.0, 0.0), 1.0),
        (Vec3::new(-r, 0.0, r), w),
        (Vec3::new(0.0, 0.0, r), 1.0),
    ];
    let pts: Vec<Vec<Vec3>> = arc
        .iter()
        .map(|(p, _)| vec![*p - 20.0 * Vec3::Y, *p + 20.0 * Vec3::Y])
        .collect();
    let ws: Vec<Vec<f64>> = arc.iter().map(|(_, w)| vec![*w, *w]).collect();
    let s = NurbsSurface::new(
        2,
        1,
        vec![0.0, 0.0, 0.0, 0.5, 0.5, 1.0, 1.0, 1.0],
        vec![0.0, 0.0, 1.0, 1.0],
        &pts,
        Some(&ws),
    )
    .unwrap();
    let mut patch = Patch::new(Surface::Nurbs(s));
    patch.name = Some("trough".to_string());
    let mut part = CompoundSurface::new(vec![patch]);
    part.flip_all();
    part
}

fn csv(part: &CompoundSurface, axes: Axes) -> (String, swarf_plan::size::ToolSizeMap) {
    let ccs = part.grid(3);
    let opts = MapOptions {
        axes,
        ..MapOptions::default()
    };
    let map = allowable_map(part, &CutterFamily::ball_with_side(), &ccs, &opts);
    let mut out = Vec::new();
    map.write_csv(part, &mut out).unwrap();
    (String::from_utf8(out).unwrap(), map)
}

#[test]
fn four_axis_map_adds_b_deg_and_reaches_the_curvature_radius() {
    let part = trough();
    let (text, map) = csv(&part, Axes::Four(Axis4Options::DEFAULT));
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        format!("{CSV_HEADER},b_deg,certified")
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 9);
    for (row, p) in rows.iter().zip(&map.points) {
        assert_eq!(row.len(), 16);
        // (The ball-with-side in a trough of its own radius is a line of ties its solve may
        // not close within the node budget: the column says which.)
        assert_eq!(row[15], p.size.unwrap().certified.to_string());
        let b: f64 = row[14].parse().unwrap();
        let r: f64 = row[9].parse().unwrap();
        // With its shank, the ball fits the trough only with the axis along +X: B = 90°.
        assert!((b - 90.0).abs() < 1e-3, "{row:?}");
        assert!((r - 5.0).abs() < 1e-6, "{row:?}");
        let Some((ToolAngles::Rotary { b_deg }, axis)) = p.orientation else {
            panic!("no orientation")
        };
        assert_eq!(b_deg, b);
        assert!((axis - RotaryAxis::Y.tool_axis(b)).length() < 1e-15);
    }
    // Summary keys as in 3-axis.
    let json = serde_json::to_value(map.summary()).unwrap();
    let mut keys: Vec<&str> = json
        .as_object()
        .unwrap()
        .keys()
        .map(|k| k.as_str())
        .collect();
    keys.sort_unstable();
    assert_eq!(
        keys,
        [
            "bounded_points",
            "elapsed_s",
            "evaluations_per_point",
            "max_radius_mm",
            "median_radius_mm",
            "min_radius_mm",
            "points",
            "uncertified_points",
            "unreachable_points"
        ]
    );
    // 3-axis: the shank stands up into the trough's upper half everywhere.
    let (_, three) = csv(&part, Axes::Three);
    let s3 = three.summary();
    assert!(s3.max_radius_mm.unwrap() < 1.0, "{s3:?}");
    assert!(map.summary().evaluations_per_point > s3.evaluations_per_point);
}

#[test]
fn five_axis_map_adds_lead_and_tilt_consistent_with_a_direct_solve() {
    let part = trough();
    let opts5 = Axis5Options::DEFAULT.with_limits(10.0, 10.0);
    let (text, map) = csv(&part, Axes::Five(opts5));
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        format!("{CSV_HEADER},lead_deg,tilt_deg,certified")
    );
    let prep = PreparedSurface::new(&part);
    for (line, p) in lines.zip(&map.points) {
        let row: Vec<&str> = line.split(',').collect();
        assert_eq!(row.len(), 17);
        assert_eq!(row[16], p.size.unwrap().certified.to_string());
        let (l, t): (f64, f64) = (row[14].parse().unwrap(), row[15].parse().unwrap());
        assert!(l.abs() <= 10.0 && t.abs() <= 10.0);
        let (_, axis) = p.orientation.unwrap();
        let c = swarf_plan::size::Contact {
            point: p.point,
            normal: p.normal.unwrap(),
            curvature: None,
        };
        let direct = allowable_along(
            &prep,
            &CutterFamily::ball_with_side(),
            &c,
            axis,
            &opts5.certified,
        );
        let s = p.size.unwrap().size;
        // (The map's contact has its curvature; the direct one does not: the sizes agree where
        // a test point, not the curvature bound, limits them, and are never smaller.)
        assert!(direct.size >= s - 1e-6, "{} vs {}", direct.size, s);
    }
    // At the middle row (normal +X) the axis is the normal: the radius of curvature.
    let mid = &map.points[4];
    assert!((mid.radius_mm.unwrap() - 5.0).abs() < 1e-6, "{mid:?}");
    assert!(matches!(
        mid.orientation,
        Some((ToolAngles::LeadTilt { lead_deg, tilt_deg }, _)) if lead_deg == 0.0 && tilt_deg == 0.0
    ));
}
