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
