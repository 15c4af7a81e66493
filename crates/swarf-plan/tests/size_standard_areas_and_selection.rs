//! Standard cutters (Liu §4.2): cell areas against analytic areas, the largest standard cutter
//! on hand-made radii, and the suggested set on a case worked out by hand.

use std::f64::consts::{FRAC_PI_2, PI};

use swarf_geom::math::Vec3;
use swarf_geom::Frame;
use swarf_plan::size::standard::{param_area, StandardError};
use swarf_plan::size::{
    allowable_map, grid_cell_areas, AreaRule, CutterFamily, MapOptions, StandardCutters,
    StandardOptions, StandardReport,
};
use swarf_surface::{
    CompoundSurface, CylindricalSurface, ParamBox, Patch, PlaneSurface, SphericalSurface, Surface,
};

/// Relative accuracy the default 4-node rule must reach on these smooth integrands.
const AREA_REL_TOL: f64 = 1e-10;

fn frame() -> Frame {
    Frame::from_axis_and_x(Vec3::new(1.0, -2.0, 3.0), Vec3::new(0.3, 0.4, 1.0), Vec3::X)
}

fn one(surface: Surface) -> CompoundSurface {
    CompoundSurface::new(vec![Patch::new(surface)])
}

fn close(a: f64, b: f64, what: &str) {
    assert!(
        (a - b).abs() <= AREA_REL_TOL * b.abs().max(1.0),
        "{what}: {a} vs {b}"
    );
}

/// Cell edges of an n-grid over [a, b]: the ends and the midpoints between grid parameters.
fn edges(a: f64, b: f64, n: usize) -> Vec<[f64; 2]> {
    let h = (b - a) / (n - 1) as f64;
    (0..n)
        .map(|i| {
            let c = a + i as f64 * h;
            [(c - 0.5 * h).max(a), (c + 0.5 * h).min(b)]
        })
        .collect()
}

#[test]
fn plane_cells_are_their_parameter_rectangles() {
    let part = one(Surface::Plane(PlaneSurface::new(
        frame(),
        ParamBox {
            u: [-2.0, 8.0],
            v: [0.0, 5.0],
        },
    )));
    let n = 5;
    let areas = grid_cell_areas(&part, n, AreaRule::DEFAULT);
    assert_eq!(areas.len(), n * n);
    let (eu, ev) = (edges(-2.0, 8.0, n), edges(0.0, 5.0, n));
    for i in 0..n {
        for j in 0..n {
            let exact = (eu[i][1] - eu[i][0]) * (ev[j][1] - ev[j][0]);
            close(areas[i * n + j], exact, "plane cell");
        }
    }
    close(areas.iter().sum(), 50.0, "plane total");
    // Interior, edge and corner cells: full, half and quarter of 2.5 × 1.25.
    close(areas[n + 1], 3.125, "interior");
    close(areas[1], 1.5625, "edge");
    close(areas[0], 0.78125, "corner");
}

#[test]
fn cylinder_cells_are_radius_times_angle_times_height() {
    let r = 7.0;
    let dom = ParamBox {
        u: [0.3, 0.3 + FRAC_PI_2],
        v: [-1.0, 9.0],
    };
    let part = one(Surface::Cylinder(
        CylindricalSurface::new(frame(), r, dom).unwrap(),
    ));
    let n = 6;
    let areas = grid_cell_areas(&part, n, AreaRule::DEFAULT);
    let (eu, ev) = (edges(dom.u[0], dom.u[1], n), edges(dom.v[0], dom.v[1], n));
    for i in 0..n {
        for j in 0..n {
            let exact = r * (eu[i][1] - eu[i][0]) * (ev[j][1] - ev[j][0]);
            close(areas[i * n + j], exact, "cylinder cell");
        }
    }
    close(areas.iter().sum(), r * FRAC_PI_2 * 10.0, "cylinder total");
}

#[test]
fn sphere_octant_cells_and_total() {
    let r = 3.0;
    let dom = ParamBox {
        u: [0.0, FRAC_PI_2],
        v: [0.0, FRAC_PI_2],
    };
    let part = one(Surface::Sphere(
        SphericalSurface::new(frame(), r, dom).unwrap(),
    ));
    let n = 7;
    let areas = grid_cell_areas(&part, n, AreaRule::DEFAULT);
    let (eu, ev) = (edges(0.0, FRAC_PI_2, n), edges(0.0, FRAC_PI_2, n));
    for i in 0..n {
        for j in 0..n {
            // ∫∫ R² cos v du dv.
            let exact = r * r * (eu[i][1] - eu[i][0]) * (ev[j][1].sin() - ev[j][0].sin());
            close(areas[i * n + j], exact, "sphere cell");
        }
    }
    close(areas.iter().sum(), 4.0 * PI * r * r / 8.0, "octant total");
    // The rule matters: one node per direction (the midpoint rule) is visibly off on one
    // big cell.
    let mid = param_area(&part, 0, dom.u, dom.v, AreaRule { nodes: 1 });
    let exact = PI * r * r / 2.0;
    assert!(
        (mid - exact).abs() > 1e-2 * exact,
        "midpoint rule {mid} vs {exact}"
    );
    let gl4 = param_area(&part, 0, dom.u, dom.v, AreaRule::DEFAULT);
    assert!(
        (gl4 - exact).abs() < 1e-6 * exact,
        "4-node rule {gl4} vs {exact}"
    );
}

#[test]
fn largest_standard_cutter_on_hand_made_radii() {
    // Liu's inch cutters, as diameters, given in any order.
    let c = StandardCutters::parse("6.35, 25.4,3.175,12.7,12.7").unwrap();
    assert_eq!(c.diameters_mm(), &[25.4, 12.7, 6.35, 3.175]);
    let cases = [
        (Some(f64::INFINITY), Some(25.4)),
        (Some(12.7), Some(25.4)), // D/2 = 12.7 ≤ 12.7: fits exactly
        (Some(12.699), Some(12.7)),
        (Some(12.7 - 5e-7), Some(25.4)), // within the 1e-6 mm fit slack
        (Some(12.7 - 2e-6), Some(12.7)), // outside it
        (Some(3.175), Some(6.35)),
        (Some(3.0), Some(3.175)),
        (Some(1.5875), Some(3.175)),
        (Some(1.5), None), // even the smallest does not fit
        (Some(0.0), None), // unreachable
        (None, None),      // undefined normal
    ];
    for (r, want) in cases {
        assert_eq!(c.largest_fitting(r), want, "radius {r:?}");
    }
    let strict = c.clone().with_fit_tolerance(0.0);
    assert_eq!(strict.largest_fitting(Some(12.7 - 5e-7)), Some(12.7));
    assert_eq!(strict.largest_fitting(Some(12.7)), Some(25.4));
    assert_eq!(StandardCutters::parse(""), Err(StandardError::Empty));
    assert!(matches!(
        StandardCutters::parse("3,-1"),
        Err(StandardError::BadDiameter(_))
    ));
    assert!(matches!(
        StandardCutters::parse("3,x"),
        Err(StandardError::BadDiameter(_))
    ));
}

/// Six cells worked out by hand (areas in mm², diameters 20, 10, 4, 2 and 1 mm):
///
/// | cell | radius | area | largest fitting |
/// |------|--------|------|-----------------|
/// | A    | inf    | 50   | 20              |
/// | B    | 6      | 30   | 10              |
/// | C    | 2.5    | 2    | 4               |
/// | D    | 1      | 15   | 2               |
/// | E    | 0      | 3    | none            |
/// | F    | —      | 0.5  | (no normal)     |
///
/// Total 100.5. Finishing cutter: 2 (the smallest "largest fitting"). With a 5 % threshold:
/// 20 finishes A (50); 10 finishes B (30); 4 would add only C (2 < 5.025): skipped; 2 finishes
/// C + D (17); 1 is never needed. Uncovered: E (3); undefined: F (0.5).
#[test]
fn suggested_set_on_a_hand_worked_case() {
    let c = StandardCutters::new(&[1.0, 2.0, 4.0, 10.0, 20.0]).unwrap();
    let radii = [
        Some(f64::INFINITY),
        Some(6.0),
        Some(2.5),
        Some(1.0),
        Some(0.0),
        None,
    ];
    let areas = [50.0, 30.0, 2.0, 15.0, 3.0, 0.5];
    let rep = StandardReport::from_radii(&c, &radii, &areas, &StandardOptions::DEFAULT);
    let total = 100.5;
    assert_eq!(rep.total_area_mm2, total);
    assert_eq!(rep.suggested_mm, vec![20.0, 10.0, 2.0]);
    let by_d = |d: f64| rep.cutters.iter().find(|x| x.diameter_mm == d).unwrap();
    let expect = [
        // d, fits area, largest-at points, finishes
        (20.0, 50.0, 1, 50.0),
        (10.0, 80.0, 1, 30.0),
        (4.0, 82.0, 1, 0.0),
        (2.0, 97.0, 1, 17.0),
        (1.0, 97.0, 0, 0.0),
    ];
    for (d, fits, at, fin) in expect {
        let x = by_d(d);
        assert_eq!(x.fits_area_mm2, fits, "fits {d}");
        assert!((x.fits_share - fits / total).abs() < 1e-15);
        assert_eq!(x.largest_at_points, at, "largest at {d}");
        assert_eq!(x.finishes_area_mm2, fin, "finishes {d}");
        assert_eq!(x.suggested, fin > 0.0);
    }
    assert_eq!(rep.uncovered_area_mm2, 3.0);
    assert_eq!(rep.undefined_area_mm2, 0.5);
    // Everything with a normal is finished or uncovered, once.
    let finished: f64 = rep.cutters.iter().map(|x| x.finishes_area_mm2).sum();
    assert_eq!(
        finished + rep.uncovered_area_mm2 + rep.undefined_area_mm2,
        total
    );

    // Without a threshold the 4 mm cutter takes C, leaving D to the 2 mm one.
    let all = StandardReport::from_radii(
        &c,
        &radii,
        &areas,
        &StandardOptions {
            min_gain_share: 0.0,
            ..StandardOptions::DEFAULT
        },
    );
    assert_eq!(all.suggested_mm, vec![20.0, 10.0, 4.0, 2.0]);
    assert_eq!(
        all.cutters
            .iter()
            .find(|x| x.diameter_mm == 2.0)
            .unwrap()
            .finishes_area_mm2,
        15.0
    );
}

#[test]
fn report_of_a_real_map_covers_the_floor_with_the_largest_cutter() {
    // A 20 × 20 floor: the flat end mill is unbounded everywhere, so the largest standard
    // cutter finishes all of it.
    let part = one(Surface::Plane(PlaneSurface::new(
        Frame::WORLD,
        ParamBox {
            u: [0.0, 20.0],
            v: [0.0, 20.0],
        },
    )));
    let n = 5;
    let map = allowable_map(
        &part,
        &CutterFamily::flat(),
        &part.grid(n),
        &MapOptions::default(),
    );
    let c = StandardCutters::new(&[6.0, 12.0]).unwrap();
    let rep = StandardReport::from_grid_map(&c, &part, &map, n, &StandardOptions::DEFAULT).unwrap();
    close(rep.total_area_mm2, 400.0, "floor area");
    assert_eq!(rep.suggested_mm, vec![12.0]);
    close(
        rep.cutters[0].finishes_area_mm2,
        400.0,
        "12 mm finishes all",
    );
    assert_eq!(rep.cutters[0].fits_share, 1.0);
    assert!(StandardReport::from_grid_map(&c, &part, &map, 4, &StandardOptions::DEFAULT).is_err());
}

#[test]
fn csv_gets_the_standard_column_last() {
    // A floor whose name needs quoting (with a newline), next to a wall 20 mm away.
    let mut floor = Patch::new(Surface::Plane(PlaneSurface::new(
        Frame::WORLD,
        ParamBox {
            u: [0.0, 20.0],
            v: [0.0, 20.0],
        },
    )));
    floor.name = Some("floor,\n\"left\"".into());
    let wall = Patch::new(Surface::Plane(PlaneSurface::new(
        Frame::from_axis_and_x(Vec3::new(20.0, 20.0, 0.0), -Vec3::X, -Vec3::Y),
        ParamBox {
            u: [0.0, 20.0],
            v: [0.0, 10.0],
        },
    )));
    let part = CompoundSurface::new(vec![floor, wall]);
    let n = 3;
    let map = allowable_map(
        &part,
        &CutterFamily::flat(),
        &part.grid(n),
        &MapOptions::default(),
    );
    let c = StandardCutters::new(&[10.0, 20.0, 30.0]).unwrap();
    let mut out = Vec::new();
    c.write_csv(&map, &part, &mut out).unwrap();
    let text = String::from_utf8(out).unwrap();
    let mut base = Vec::new();
    map.write_csv(&part, &mut base).unwrap();
    let base = String::from_utf8(base).unwrap();
    let header = text.lines().next().unwrap();
    assert!(header.starts_with(swarf_plan::size::map::CSV_HEADER));
    assert_eq!(
        header,
        format!("{},standard_d_mm", base.lines().next().unwrap())
    );
    // Each record: the map's record, then the column (the quoted name spans two lines).
    let ends: Vec<&str> = text.split('\n').filter(|l| !l.is_empty()).collect();
    let base_ends: Vec<&str> = base.split('\n').filter(|l| !l.is_empty()).collect();
    assert_eq!(ends.len(), base_ends.len());
    let mut record = 0;
    for (got, was) in ends.iter().zip(&base_ends).skip(1) {
        if was.starts_with("\"floor,") {
            assert_eq!(got, was, "first line of a quoted name is untouched");
            continue;
        }
        let p = &map.points[record];
        record += 1;
        let want = c
            .largest_fitting(p.radius_mm)
            .map_or(String::new(), |d| format!("{d:?}"));
        assert_eq!(*got, format!("{was},{want}"), "point {record}");
    }
    assert_eq!(record, map.points.len());
    // The floor point in the middle of the floor is 10 mm from the wall: the 20 mm cutter.
    assert_eq!(
        map.points[4].radius_mm.map(|r| (r * 1e6).round() / 1e6),
        Some(10.0)
    );
    assert_eq!(c.largest_fitting(map.points[4].radius_mm), Some(20.0));
}
