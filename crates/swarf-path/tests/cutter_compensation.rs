//! Cutter radius compensation (G40/G41/G42/G41.1/G42.1): hand-derived paths, errors with their
//! positions, and the property that the compensated path keeps exactly the tool radius from
//! the programmed contour.
//!
//! The expected paths follow LinuxCNC's rules (LinuxCNC G-code manual, "G41, G42 Cutter
//! Compensation" and "Cutter Compensation" chapter; its interpreter's
//! `convert_straight_comp1/2`): the entry move ends the radius away from its programmed end,
//! perpendicular to it; a convex corner is rounded by an arc about the programmed corner; at a
//! concave corner the move before is cut back to where the two offset moves meet; after G40 the
//! next move goes straight from the compensated position to its programmed end.

use proptest::prelude::*;
use swarf_path::canon::{OwnedCanon, Recorder};
use swarf_path::gcode::{read_gcode, GcodeOptions};
use swarf_path::{Canon, PathError, PathErrorKind};

fn read(src: &str, options: &GcodeOptions) -> Result<Recorder, PathError> {
    let mut rec = Recorder::default();
    read_gcode(src, "comp.ngc", options, &mut rec)?;
    Ok(rec)
}

/// The motion: `(kind, end x, end y, centre)`, kind `L` feed, `R` rapid, `A+`/`A-` arcs.
fn motion(rec: &Recorder) -> Vec<(String, f64, f64, Option<[f64; 2]>)> {
    rec.events
        .iter()
        .filter_map(|(_, e)| match e {
            Canon::Feed { end } => Some(("L".to_string(), end.x, end.y, None)),
            Canon::Traverse { end } => Some(("R".to_string(), end.x, end.y, None)),
            Canon::Arc {
                end,
                center,
                rotation,
                ..
            } => Some((
                if *rotation > 0 { "A+" } else { "A-" }.to_string(),
                end.x,
                end.y,
                Some(*center),
            )),
            _ => None,
        })
        .collect()
}

fn assert_path(got: &[(String, f64, f64, Option<[f64; 2]>)], want: &[(&str, f64, f64)]) {
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (g, w) in got.iter().zip(want) {
        assert!(
            g.0 == w.0 && (g.1 - w.1).abs() < 1e-9 && (g.2 - w.2).abs() < 1e-9,
            "got {g:?}, want {w:?}\n{got:?}"
        );
    }
}

#[test]
fn outside_of_a_square_rounds_convex_corners_and_cuts_back_the_entry() {
    // CCW square, tool on the right (outside), r = 2.
    let rec = read(
        "G21 G17 G90 F100\nG0 X-10 Y-10\nG42.1 D4\nG1 X0 Y0\nX20\nY20\nX0\nY0\nG40\nG1 X-10 Y-10\nM2\n",
        &GcodeOptions::default(),
    )
    .unwrap();
    // Entry along (1, 1) ends at (√2, −√2); the first side's offset is y = −2, a right turn
    // for a tool on the right: concave, the entry is cut back along (1, 1) to y = −2.
    let s = 2.0 - 2f64.sqrt();
    assert_path(
        &motion(&rec)[1..],
        &[
            ("L", 2f64.sqrt() - s, -2.0),
            ("L", 20.0, -2.0),
            ("A+", 22.0, 0.0),
            ("L", 22.0, 20.0),
            ("A+", 20.0, 22.0),
            ("L", 0.0, 22.0),
            ("A+", -2.0, 20.0),
            ("L", -2.0, 0.0),
            ("L", -10.0, -10.0),
        ],
    );
    let centres: Vec<_> = motion(&rec).iter().filter_map(|m| m.3).collect();
    assert_eq!(centres, vec![[20.0, 0.0], [20.0, 20.0], [0.0, 20.0]]);
}

#[test]
fn inside_of_a_square_cuts_every_corner_back() {
    // CCW square, tool on the left (inside, a pocket wall), r = 2, D from the tool table.
    let options = GcodeOptions::default().with_tool_diameter(7, 4.0);
    let rec = read(
        "G21 G90 F100 T7 M6\nG0 X10 Y5\nG41 D7\nG1 Y0\nX20\nY20\nX0\nY0\nX10\nG40\nG1 Y5\nM2\n",
        &options,
    )
    .unwrap();
    assert_path(
        &motion(&rec)[1..],
        &[
            ("L", 12.0, 2.0),
            ("L", 18.0, 2.0),
            ("L", 18.0, 18.0),
            ("L", 2.0, 18.0),
            ("L", 2.0, 2.0),
            ("L", 10.0, 2.0),
            ("L", 10.0, 5.0),
        ],
    );
    // G41 without D uses the loaded tool: the same path.
    let again = read(
        "G21 G90 F100 T7 M6\nG0 X10 Y5\nG41\nG1 Y0\nX20\nY20\nX0\nY0\nX10\nG40\nG1 Y5\nM2\n",
        &options,
    )
    .unwrap();
    assert_eq!(motion(&rec), motion(&again));
}

#[test]
fn arcs_keep_their_centre_at_the_offset_radius() {
    // A full boss: G2 about the origin, radius 10, tool outside on the left (G41, clockwise).
    let rec = read(
        "G21 G90 F100\nG0 X-20 Y0\nG41.1 D2\nG1 X-10 Y0\nG2 X-10 Y0 I10 J0\nG40\nG1 X-20\nM2\n",
        &GcodeOptions::default(),
    )
    .unwrap();
    let m = motion(&rec);
    // Entry from the left along +X: the left normal is +Y, so it ends at (−10, 1); the circle
    // starts going +Y (clockwise at 180°): a left turn for a tool on the left: concave — the
    // entry is cut back to where y = 1 meets the radius-11 circle.
    let x = -(121f64 - 1.0).sqrt();
    assert_path(
        &m[1..],
        &[("L", x, 1.0), ("A-", -11.0, 0.0), ("L", -20.0, 0.0)],
    );
    assert_eq!(m[2].3, Some([0.0, 0.0]));
}

fn comp_error(src: &str) -> PathError {
    read(src, &GcodeOptions::default()).unwrap_err()
}

#[test]
fn errors_name_the_line_and_what_is_wrong() {
    let e = comp_error("G21 F100\nG41.1 D4\nG1 X1\nM2\n");
    assert_eq!(
        (e.kind, e.pos.line, e.pos.column),
        (PathErrorKind::Semantic, 3, 1)
    );
    assert!(
        e.message
            .contains("entry move is not greater than the tool radius"),
        "{e}"
    );

    // An entry arc whose end is no farther than the radius (2) from its start.
    let e = comp_error("G21 F100\nG41.1 D4\nG2 X1.5 Y0 I0.75\nM2\n");
    assert_eq!((e.pos.line, e.pos.column), (3, 1));
    assert!(
        e.message
            .contains("entry arc is not greater than the tool radius"),
        "{e}"
    );

    // An inside arc of radius 1 with a tool of radius 2 (G41, counter-clockwise arc).
    let e = comp_error("G21 F100\nG0 X0 Y-10\nG41.1 D4\nG1 X0 Y0\nG3 X2 Y0 I1\nM2\n");
    assert_eq!((e.pos.line, e.pos.column), (5, 1));
    assert!(e.message.contains("not less than the arc radius"), "{e}");

    // A slot 1 mm wide for a tool 4 mm wide: the cut-back would run backwards.
    let e = comp_error("G21 F100\nG0 X-10 Y-10\nG41.1 D4\nG1 X0 Y0\nX10\nY1\nX0\nG40\nM2\n");
    assert_eq!((e.pos.line, e.pos.column), (7, 1));
    assert!(
        e.message
            .contains("in concave corner cannot be reached by the tool without gouging"),
        "{e}"
    );

    let e = comp_error("G21\nG41.1 D4\nG42.1 D4\nM2\n");
    assert_eq!((e.pos.line, e.pos.column), (3, 1));
    assert!(e.message.contains("already on"), "{e}");

    let e = comp_error("G21\nG41.1 D4\nG18\nM2\n");
    assert_eq!((e.pos.line, e.pos.column), (3, 1));
    assert!(e.message.contains("cannot change planes"), "{e}");

    let e = comp_error("G21 F10\nG41.1 D4\nG81 X1 Y1 Z-1 R1\nM2\n");
    assert!(e.message.contains("canned cycles"), "{e}");

    let e = comp_error("G19\nG41.1 D4\nM2\n");
    assert!(e.message.contains("XY (G17) and XZ (G18)"), "{e}");
}

#[test]
fn negative_diameter_swaps_sides_and_zero_leaves_the_path() {
    let a = read(
        "G21 F100\nG0 X-10 Y-10\nG41.1 D-4\nG1 X0 Y0\nX20\nG40\nM2\n",
        &GcodeOptions::default(),
    )
    .unwrap();
    let b = read(
        "G21 F100\nG0 X-10 Y-10\nG42.1 D4\nG1 X0 Y0\nX20\nG40\nM2\n",
        &GcodeOptions::default(),
    )
    .unwrap();
    assert_eq!(motion(&a), motion(&b));
    let z = read(
        "G21 F100\nG0 X-10 Y-10\nG41.1 D0\nG1 X0 Y0\nX20\nG40\nM2\n",
        &GcodeOptions::default(),
    )
    .unwrap();
    assert_path(
        &motion(&z),
        &[("R", -10.0, -10.0), ("L", 0.0, 0.0), ("L", 20.0, 0.0)],
    );
}

/// Distance from `p` to the closed polygon's boundary.
fn boundary_distance(poly: &[[f64; 2]], p: [f64; 2]) -> f64 {
    (0..poly.len())
        .map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
            let d = [b[0] - a[0], b[1] - a[1]];
            let t = (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / (d[0] * d[0] + d[1] * d[1]))
                .clamp(0.0, 1.0);
            (p[0] - a[0] - t * d[0]).hypot(p[1] - a[1] - t * d[1])
        })
        .fold(f64::INFINITY, f64::min)
}

fn inside(poly: &[[f64; 2]], p: [f64; 2]) -> bool {
    let mut c = false;
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        if (a[1] > p[1]) != (b[1] > p[1])
            && p[0] < a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0])
        {
            c = !c;
        }
    }
    c
}

/// Points along the compensated moves between the entry move and G40's exit move.
fn samples(events: &[(u32, OwnedCanon)]) -> Vec<[f64; 2]> {
    let mut pts = Vec::new();
    let mut at: Option<[f64; 2]> = None;
    let moves: Vec<_> = events
        .iter()
        .filter(|(_, e)| matches!(e, Canon::Feed { .. } | Canon::Arc { .. }))
        .collect();
    // Skip the entry move (the first feed) and the exit move (the last).
    for (k, (_, e)) in moves.iter().enumerate() {
        let (end, arc) = match e {
            Canon::Feed { end } => ([end.x, end.y], None),
            Canon::Arc {
                end,
                center,
                rotation,
                ..
            } => ([end.x, end.y], Some((*center, *rotation))),
            _ => unreachable!(),
        };
        if k > 0 && k + 1 < moves.len() {
            let s = at.unwrap();
            for i in 0..=16 {
                let t = f64::from(i) / 16.0;
                pts.push(match arc {
                    None => [s[0] + t * (end[0] - s[0]), s[1] + t * (end[1] - s[1])],
                    Some((c, rot)) => {
                        let a0 = (s[1] - c[1]).atan2(s[0] - c[0]);
                        let a1 = (end[1] - c[1]).atan2(end[0] - c[0]);
                        let mut sw = a1 - a0;
                        if rot > 0 && sw <= 0.0 {
                            sw += std::f64::consts::TAU;
                        }
                        if rot < 0 && sw >= 0.0 {
                            sw -= std::f64::consts::TAU;
                        }
                        let r = (s[0] - c[0]).hypot(s[1] - c[1]);
                        let a = a0 + t * sw;
                        [c[0] + r * a.cos(), c[1] + r * a.sin()]
                    }
                });
            }
        }
        at = Some(end);
    }
    pts
}

/// A star-shaped polygon, counter-clockwise, with every corner turning by more than LinuxCNC's
/// tangency tolerance (0.05 rad), so every corner gets an arc or a cut-back.
fn star() -> impl Strategy<Value = Vec<[f64; 2]>> {
    (5usize..10)
        .prop_flat_map(|n| {
            (
                prop::collection::vec(0.0f64..1.0, n),
                prop::collection::vec(20.0f64..40.0, n),
            )
        })
        .prop_map(|(gaps, radii)| {
            // Angles around the whole turn, in order, each step at least half the mean.
            let total: f64 = gaps.iter().map(|g| 1.0 + g).sum();
            let mut a = 0.0;
            gaps.iter()
                .zip(&radii)
                .map(|(g, r)| {
                    a += std::f64::consts::TAU * (1.0 + g) / total;
                    [r * a.cos(), r * a.sin()]
                })
                .collect::<Vec<_>>()
        })
        .prop_filter("corners clearly not tangent", |p| {
            (0..p.len()).all(|i| {
                let (a, b, c) = (p[i], p[(i + 1) % p.len()], p[(i + 2) % p.len()]);
                let t1 = (b[1] - a[1]).atan2(b[0] - a[0]);
                let t2 = (c[1] - b[1]).atan2(c[0] - b[0]);
                let turn = (t2 - t1 + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
                    - std::f64::consts::PI;
                turn.abs() > 0.06 && turn.abs() < std::f64::consts::PI - 0.06
            })
        })
}

proptest! {
    #![proptest_config(swarf_testdata::proptest_config(256))]

    /// Around a closed profile, inside (G41) or outside (G42), every point of the compensated
    /// path between the entry and the exit is exactly the tool radius from the programmed
    /// contour, on the side asked for — unless the reader raises LinuxCNC's gouging error.
    #[test]
    fn compensated_path_keeps_the_radius(poly in star(), r in 0.3f64..3.0, left in any::<bool>()) {
        let mut src = String::from("G21 G17 G90 F500\n");
        let start = if left { [0.0, 0.0] } else { [poly[0][0] * 3.0, poly[0][1] * 3.0] };
        src += &format!("G0 X{} Y{}\n", start[0], start[1]);
        src += &format!("G{}.1 D{}\n", if left { 41 } else { 42 }, 2.0 * r);
        for p in poly.iter().chain(std::iter::once(&poly[0])) {
            src += &format!("G1 X{} Y{}\n", p[0], p[1]);
        }
        // Run on along the first side, so the exit does not close the last corner.
        let mid = [(poly[0][0] + poly[1][0]) / 2.0, (poly[0][1] + poly[1][1]) / 2.0];
        src += &format!("G1 X{} Y{}\nG40\nG1 X{} Y{}\nM2\n", mid[0], mid[1], start[0], start[1]);
        match read(&src, &GcodeOptions::default()) {
            Ok(rec) => {
                let pts = samples(&rec.events);
                prop_assert!(pts.len() > 16 * poly.len());
                for p in pts {
                    let d = boundary_distance(&poly, p);
                    prop_assert!((d - r).abs() < 1e-7, "{p:?} is {d} from the contour, r = {r}");
                    prop_assert_eq!(inside(&poly, p), left);
                }
            }
            Err(e) => prop_assert!(e.message.contains("without gouging"), "{}", e),
        }
    }
}

/// A full circle followed by a concave corner: LinuxCNC moves the circle's end back to where
/// it meets the next move's offset line (`move_endpoint_and_flush`). The circle's compensated
/// start and end differ by rounding only, which must not read as an arc of sweep ≈ 0 that
/// cannot reach the meeting point (a false gouging error).
#[test]
fn a_full_circle_then_a_concave_corner_is_cut_back() {
    let rec = read(
        "G21 G17 G90 G40\nG0 X-10 Y-10 Z0\nG41.1 D2\nG1 X0 Y0 F100\nG3 X0 Y0 I5 J0\n\
         G1 X10 Y-10\nG40\nM2\n",
        &GcodeOptions::default(),
    )
    .unwrap();
    // r = 1, tool on the left. The entry along (1, 1) ends a from (0, 0) on its left,
    // (−a, a) with a = 1/√2; the circle (centre (5, 0), CCW, starting down) has the tool
    // inside, at radius 4, starting at (1, 0): a right turn for a tool on the left, convex, so
    // an arc about (0, 0). The last line along (1, −1) has its offset through (a, a): the
    // point (a + t, a − t) lies at distance 4 from (5, 0) for t² − 5t + 5 − 5a = 0, the
    // smaller root (≈ (1.0196, 0.3946)), where the circle ends.
    let a = std::f64::consts::FRAC_1_SQRT_2;
    let t = (5.0 - (5.0 + 20.0 * a).sqrt()) / 2.0;
    assert_path(
        &motion(&rec)[1..],
        &[
            ("L", -a, a),
            ("A-", 1.0, 0.0),
            ("A+", a + t, a - t),
            ("L", 10.0 + a, -10.0 + a),
        ],
    );
    let centres: Vec<_> = motion(&rec).iter().filter_map(|m| m.3).collect();
    assert_eq!(centres, vec![[0.0, 0.0], [5.0, 0.0]]);
}

/// `got` against rs274's canonical calls (four decimals printed): within 1e-4.
fn assert_rs274(got: &[(String, f64, f64, Option<[f64; 2]>)], want: &[(&str, f64, f64)]) {
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (g, w) in got.iter().zip(want) {
        assert!(
            g.0 == w.0 && (g.1 - w.1).abs() < 1e-4 && (g.2 - w.2).abs() < 1e-4,
            "got {g:?}, want {w:?}\n{got:?}"
        );
    }
}

/// A full circle (a boss, tool outside) entered tangentially and left back down the lead-in:
/// the concave corner at its end cuts the circle back to where the offset lead-out x = −9
/// meets it. Of the two meeting points LinuxCNC's formula (`convert_straight_comp2`, arc to
/// line) takes the one after ~325° of the circle, not the one ~35° in: the expected calls
/// are rs274's (LinuxCNC 2.9) for this program.
#[test]
fn a_full_circle_then_a_reversing_move_keeps_the_circle() {
    let rec = read(
        "G21 G17 G90 G40 F100\nG0 X-10 Y-20 Z-1\nG41.1 D2\nG1 X-10 Y-10\nG1 X-10 Y0\n\
         G2 X-10 Y0 I10 J0\nG1 X-10 Y-10\nG40 G1 X-10 Y-20\nM2\n",
        &GcodeOptions::default(),
    )
    .unwrap();
    let m = motion(&rec);
    assert_rs274(
        &m,
        &[
            ("R", -10.0, -20.0),
            ("L", -11.0, -10.0),
            ("L", -11.0, 0.0),
            ("A-", -9.0, -6.3246),
            ("L", -9.0, -10.0),
            ("L", -10.0, -20.0),
        ],
    );
    assert_eq!(m[3].3, Some([0.0, 0.0]));
}

/// Corners as LinuxCNC makes them, its formulas and checks rather than exact geometry; each
/// expected path is rs274's (LinuxCNC 2.9) output for the program.
#[test]
fn corners_follow_linuxcncs_formulas_and_checks() {
    let path = |src: &str| motion(&read(src, &GcodeOptions::default()).unwrap());

    // Arc to line after an entry arc whose centre moved beyond its end: LinuxCNC's triangle
    // takes the programmed corner to be r from the arc's end along the radius, which it is
    // not here, so the arc ends 0.03 off the new offset line, at rs274's point.
    let m = path(
        "G21 G17 G90 G40 F100\nG0 X-17.5854 Y2.5469 Z0\nG41.1 D2\n\
         G3 X-16.8986 Y-0.4424 I8.0015 J0.2647\nG1 X4.1459 Y8.5463\nG40 G1 X10 Y0\nM2\n",
    );
    assert_rs274(
        &m[1..],
        &[
            ("A+", -36.9081, -7.8692),
            ("L", 3.7531, 9.4659),
            ("L", 10.0, 0.0),
        ],
    );
    let c = m[1].3.unwrap();
    assert!(
        (c[0] + 26.2099).abs() < 1e-4 && (c[1] + 4.5846).abs() < 1e-4,
        "{c:?}"
    );

    // The entry line queues its normal as its direction (`convert_straight_comp1`): cut back
    // past its start it is not a gouge to LinuxCNC.
    let m =
        path("G21 G90 F100\nG0 X0 Y0 Z0\nG41.1 D2\nG1 X10 Y0\nG1 X-30 Y3\nG40 G1 X-30 Y20\nM2\n");
    assert_rs274(
        &m[1..],
        &[
            ("L", -16.7041, 1.0),
            ("L", -30.0748, 2.0028),
            ("L", -30.0, 20.0),
        ],
    );

    // A convex corner before a rapid: a straight traverse to the offset start (there is no
    // arc traverse), not an arc.
    let m = path(
        "G21 G90 F100\nG0 X0 Y-10 Z0\nG41.1 D2\nG1 X0 Y0\nG0 X10 Y0\nG1 X10 Y10\nG40 G0 X20 Y10\nM2\n",
    );
    assert_rs274(
        &m[1..],
        &[
            ("L", -1.0, 0.0),
            ("R", 0.0, 1.0),
            ("R", 9.0, 1.0),
            ("L", 9.0, 10.0),
            ("R", 20.0, 10.0),
        ],
    );

    // G40 flushes the held move as a moved end is checked: this one was cut back past its
    // end (a 3 mm wide turn for a 6 mm tool) and runs backwards: rs274 refuses it at G40.
    let e =
        comp_error("G21 G90 F100\nG0 X0 Y0 Z0\nG41.1 D6\nG1 X20 Y0\nG1 X0 Y2\nG40 G1 X0 Y20\nM2\n");
    assert_eq!((e.kind, e.pos.line), (PathErrorKind::Semantic, 6), "{e}");
    assert!(
        e.message.contains(
            "straight feed in concave corner cannot be reached by the tool without gouging"
        ),
        "{e}"
    );

    // The entry move must move in the plane (`convert_straight_comp1`): a plunge first is
    // refused, as rs274 refuses it; after the entry move a plunge stays where the tool is.
    let e = comp_error("G21 G90 F100\nG0 X0 Y0 Z0\nG41.1 D2\nG1 Z-1\nG1 X10\nM2\n");
    assert_eq!((e.pos.line, e.pos.column), (4, 1), "{e}");
    assert!(
        e.message
            .contains("entry move is not greater than the tool radius"),
        "{e}"
    );
}

/// Arcs after the entry move as LinuxCNC makes their corners (`convert_arc_comp2`): each
/// expected path is rs274's (LinuxCNC 2.9) output for the program.
#[test]
fn arc_corners_follow_linuxcncs_formulas() {
    let path = |src: &str| motion(&read(src, &GcodeOptions::default()).unwrap());

    // A full circle (boss, tool outside at radius 11), then a clockwise arc starting back
    // down: the two compensated circles meet at (−10.3333, ±3.7712), equally near the
    // circle's end; LinuxCNC's turns take the one after ~340° of the circle.
    let m = path(
        "G21 G17 G90 G40 F100\nG0 X-10 Y-20 Z-1\nG41.1 D2\nG1 X-10 Y-10\nG1 X-10 Y0\n\
         G2 X-10 Y0 I10 J0\nG2 X-20 Y0 I-5 J0\nG40 G1 X-20 Y-20\nM2\n",
    );
    assert_rs274(
        &m[1..],
        &[
            ("L", -11.0, -10.0),
            ("L", -11.0, 0.0),
            ("A-", -10.3333, -3.7712),
            ("A-", -21.0, 0.0),
            ("L", -20.0, -20.0),
        ],
    );

    // Line to arc after the entry line, whose tool path is not parallel to the programmed
    // line: LinuxCNC's formula ends the line at (7.3203, 10.1290), 0.001 from where the two
    // offset paths cross.
    let m = path(
        "G21 G17 G90 G40 F100\nG0 X-2.4740 Y-7.1116 Z0\nG41.1 D6\nG1 X9.7188 Y8.3256\n\
         G2 X11.5298 Y7.1122 I0.9005 J-0.6142\nG1 X14.2988 Y9.4906\nG1 X5.1098 Y-9.8353\n\
         G40 G1 X7.9154 Y21.3620\nM2\n",
    );
    assert_rs274(
        &m[1..],
        &[
            ("L", 7.3203, 10.1290),
            ("A-", 12.0736, 11.5341),
            ("L", 12.3441, 11.7663),
            ("A-", 17.0081, 8.2024),
            ("L", 7.8191, -11.1235),
            ("L", 7.9154, 21.3620),
        ],
    );

    // A full circle (tool outside) after the entry line, then a line and a plunge: the
    // circle is cut back where the line leaves it, the plunge stays where the tool is.
    let m = path(
        "G21 G17 G90 G40 F100\nG0 X4.7523 Y18.3568 Z0\nG42.1 D4\nG1 X12.3999 Y16.3601\n\
         G3 X12.3999 Y16.3601 I0.2630 J1.0075\nG1 X6.3061 Y-16.3100\nG1 Z-4.9318\n\
         G1 X2.8915 Y-6.4098\nG40 G1 X5.8383 Y3.2787\nM2\n",
    );
    assert_rs274(
        &m[1..],
        &[
            ("L", 11.8947, 14.4250),
            ("A+", 10.2164, 15.5610),
            ("L", 5.7282, -8.5006),
            ("L", 5.7282, -8.5006),
            ("L", 4.7822, -5.7577),
            ("L", 5.8383, 3.2787),
        ],
    );
}

#[test]
fn after_g40_the_current_point_is_the_programmed_one() {
    // LinuxCNC's `convert_cutter_compensation_off`: current = programmed point. The tool is at
    // (20, 2) when G40 comes; the incremental Y10 counts from (20, 0), an omitted Y is the
    // programmed 0, and a Z move goes to the programmed X Y.
    let rec = read(
        "G21 G90 F100\nG0 X-10 Y0 Z0\nG41.1 D4 G1 X0 Y0\nG1 X20\nG40\nG91 G1 Y10\nG1 X-30\n\
         G90 G41.1 D4 G1 X0 Y0\nG1 X20\nG40\nG1 X30\nG41.1 D4 G1 X40 Y0\nG1 X50\nG40\nG0 Z5\nM2\n",
        &GcodeOptions::default(),
    )
    .unwrap();
    assert_path(
        &motion(&rec),
        &[
            ("R", -10.0, 0.0),
            ("L", 0.0, 2.0),
            ("L", 20.0, 2.0),
            ("L", 20.0, 10.0),
            ("L", -10.0, 10.0),
            // The diagonal entry's offset line (through (√2, √2), along (1, −1)) cut back to
            // the next move's offset y = 2: x = 2√2 − 2.
            ("L", 2.0 * 2f64.sqrt() - 2.0, 2.0),
            ("L", 20.0, 2.0),
            ("L", 30.0, 0.0),
            ("L", 40.0, 2.0),
            ("L", 50.0, 2.0),
            ("R", 50.0, 0.0),
        ],
    );
    // The move right after G40 must be straight.
    let e = comp_error("G21 F100\nG0 X-10 Y0\nG41.1 D4\nG1 X0 Y0\nX20\nG40\nG2 X30 Y0 R6\nM2\n");
    assert_eq!((e.kind, e.pos.line), (PathErrorKind::Semantic, 7), "{e}");
    assert!(e.message.contains("must be"), "{e}");
    // Not when no compensated move was made between G41 and G40.
    let rec = read(
        "G21 G90 G17 F100\nG0 X0 Y0 Z5\nG41.1 D4\nG40\nG2 X10 Y0 I5 J0\nM2\n",
        &GcodeOptions::default(),
    )
    .unwrap();
    assert_eq!(
        motion(&rec).last().map(|m| m.0.clone()),
        Some("A-".to_string())
    );
}
