//! Canned cycles as LinuxCNC 2.9's `rs274` expands them, call for call. Every expected listing
//! below was printed by the real `rs274 -g` (Debian's linuxcnc 2.9 interpreter) for the program
//! above it and is written in here as it printed it: the motion calls, the dwells and the
//! spindle calls, in the program's units (the closing `STOP_SPINDLE_TURNING` of `M2` left out).
//! swarf's events for the same program are printed alike and compared to 1e-4.

use swarf_path::canon::{OwnedCanon, Recorder};
use swarf_path::gcode::{read_gcode, GcodeOptions};
use swarf_path::{Canon, PathError, SpindleDir, Units};

fn read(src: &str) -> Result<Recorder, PathError> {
    let mut rec = Recorder::default();
    read_gcode(src, "t.ngc", &GcodeOptions::default(), &mut rec).map(|()| rec)
}

/// swarf's events written as rs274 writes the same calls.
fn calls(events: &[(u32, OwnedCanon)]) -> Vec<String> {
    let mut per_mm = 1.0;
    let mut out = Vec::new();
    for (_, e) in events {
        match e {
            Canon::Units(u) => per_mm = if *u == Units::Inch { 1.0 / 25.4 } else { 1.0 },
            Canon::Traverse { end } | Canon::Feed { end } => {
                let name = if matches!(e, Canon::Traverse { .. }) {
                    "STRAIGHT_TRAVERSE"
                } else {
                    "STRAIGHT_FEED"
                };
                out.push(format!(
                    "{name}({:.4}, {:.4}, {:.4}, {:.4}, {:.4}, {:.4})",
                    end.x * per_mm,
                    end.y * per_mm,
                    end.z * per_mm,
                    end.a,
                    end.b,
                    end.c
                ));
            }
            Canon::Dwell(t) => out.push(format!("DWELL({t:.4})")),
            Canon::Spindle { dir, .. } => out.push(
                match dir {
                    SpindleDir::Clockwise => "START_SPINDLE_CLOCKWISE(0)",
                    SpindleDir::CounterClockwise => "START_SPINDLE_COUNTERCLOCKWISE(0)",
                    SpindleDir::Stopped => "STOP_SPINDLE_TURNING(0)",
                }
                .to_string(),
            ),
            _ => {}
        }
    }
    if out.last().is_some_and(|l| l.starts_with("STOP_SPINDLE")) {
        out.pop();
    }
    out
}

fn split(call: &str) -> (&str, Vec<f64>) {
    let (name, args) = call.split_once('(').unwrap();
    let nums = args
        .trim_end_matches(')')
        .split(',')
        .map(|a| a.trim().parse().unwrap())
        .collect();
    (name, nums)
}

/// The program's calls are rs274's (`want`, one a line) to 1e-4 in program units.
fn assert_rs274(src: &str, want: &str) {
    let rec = read(src).unwrap_or_else(|e| panic!("{e}"));
    let got = calls(&rec.events);
    let want: Vec<&str> = want
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect();
    let same = got.len() == want.len()
        && got.iter().zip(&want).all(|(g, w)| {
            let ((gn, ga), (wn, wa)) = (split(g), split(w));
            gn == wn
                && ga.len() == wa.len()
                && ga.iter().zip(&wa).all(|(a, b)| (a - b).abs() < 1e-4)
        });
    assert!(
        same,
        "swarf:\n{}\nrs274:\n{}",
        got.join("\n"),
        want.join("\n")
    );
}

/// LinuxCNC's `nc_files/hole-circle.ngc`: six holes on a bolt circle, each 60° on from the
/// last about the origin (`G91` with `^`, repeated by `L`). swarf refused polar words in G91.
#[test]
fn a_polar_bolt_circle_in_g91_turns_each_repeat_about_the_origin() {
    let src = "G20 G17 G90\nG0 X1.5 Y0 Z0\nG91 G81 R.1 Z-.5 ^60 L6 F10\nM2\n";
    assert_rs274(
        src,
        "STRAIGHT_TRAVERSE(1.5000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(1.5000, 0.0000, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(0.7500, 1.2990, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(0.7500, 1.2990, -0.4000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(0.7500, 1.2990, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(-0.7500, 1.2990, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(-0.7500, 1.2990, -0.4000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(-0.7500, 1.2990, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(-1.5000, 0.0000, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(-1.5000, 0.0000, -0.4000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(-1.5000, 0.0000, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(-0.7500, -1.2990, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(-0.7500, -1.2990, -0.4000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(-0.7500, -1.2990, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(0.7500, -1.2990, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(0.7500, -1.2990, -0.4000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(0.7500, -1.2990, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(1.5000, -0.0000, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(1.5000, -0.0000, -0.4000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(1.5000, -0.0000, 0.1000, 0.0000, 0.0000, 0.0000)",
    );
}

/// `@` and `^` together in G91: the radius grows, then the angle turns, at every repeat; a
/// later G90 block takes its radius from `@` and its angle from where the tool is.
#[test]
fn polar_radius_and_angle_increments_and_absolute_polar_holes() {
    let src = "G20 G17 F10\nG0 X1 Y1 Z1\nG91 G81 @0.5 ^45 R-0.5 Z-0.5 L2\n^-90\n\
               G90 @2 R0.1 Z-0.5\nM2\n";
    assert_rs274(
        src,
        "STRAIGHT_TRAVERSE(1.0000, 1.0000, 1.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(0.0000, 1.9142, 1.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(0.0000, 1.9142, 0.5000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(0.0000, 1.9142, 0.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(0.0000, 1.9142, 0.5000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(-1.7071, 1.7071, 0.5000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(-1.7071, 1.7071, 0.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(-1.7071, 1.7071, 0.5000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(1.7071, 1.7071, 0.5000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(1.7071, 1.7071, 0.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(1.7071, 1.7071, 0.5000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(1.4142, 1.4142, 0.5000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(1.4142, 1.4142, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(1.4142, 1.4142, -0.5000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(1.4142, 1.4142, 0.1000, 0.0000, 0.0000, 0.0000)",
    );
    // rs274's refusals: polar words out of G17 ("Cannot use polar coordinate except in G17
    // plane"), beside X or Y, and in G91 at the origin (after the rise to R).
    let e = read("G20 F10\nG0 X1 Y1 Z1\nG18 G81 X1 Y-0.5 R0.1\n^30\nM2\n").unwrap_err();
    assert!(e.message.contains("outside the G17 plane"), "{e}");
    let e = read("G20 F10\nG0 X1 Y1 Z1\nG91 G81 X1 ^30 Z-0.5 R0.1\nM2\n").unwrap_err();
    assert!(e.message.contains("X or Y cannot be used"), "{e}");
    let e = read("G20 F10\nG0 X0 Y0 Z1\nG91 G81 ^30 Z-0.5 R0.1\nM2\n").unwrap_err();
    assert!(e.message.contains("indeterminate at the origin"), "{e}");
}

/// G85 feeds out to R and always rapids to the clearance level, a move of no length under
/// G99; G89 dwells and feeds all the way out to the clearance level (swarf fed to R and
/// rapided on, and dropped G85's G99 traverse).
#[test]
fn g85_rapids_out_from_r_and_g89_feeds_out_to_the_clearance_level() {
    let src = "G20 F10 S500 M3\nG0 X0 Y0 Z2\nG98 G85 X1 Z-0.5 R0.1\nG89 X2 Z-0.5 R0.1 P1\n\
               G99 G85 X3 Z-0.5 R0.1\nG89 X4 P0.5 Z-0.5 R0.1\nM2\n";
    assert_rs274(
        src,
        "START_SPINDLE_CLOCKWISE(0)
         STRAIGHT_TRAVERSE(0.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(1.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(1.0000, 0.0000, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(1.0000, 0.0000, -0.5000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(1.0000, 0.0000, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(1.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(2.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(2.0000, 0.0000, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(2.0000, 0.0000, -0.5000, 0.0000, 0.0000, 0.0000)
         DWELL(1.0000)
         STRAIGHT_FEED(2.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(3.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(3.0000, 0.0000, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(3.0000, 0.0000, -0.5000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(3.0000, 0.0000, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(3.0000, 0.0000, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(4.0000, 0.0000, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(4.0000, 0.0000, -0.5000, 0.0000, 0.0000, 0.0000)
         DWELL(0.5000)
         STRAIGHT_FEED(4.0000, 0.0000, 0.1000, 0.0000, 0.0000, 0.0000)",
    );
}

/// The initial level (`cycle_il`): where the cycle mode began, kept until G80 or G0–G3. A G98
/// hole after G99 holes is reached at it and returns to it; a hole after the tool was moved
/// higher (G28) is reached where the tool is; a mode that began below R rises to R where the
/// tool stands at every block, a move of no length after the first.
#[test]
fn the_initial_level_of_the_cycle_mode_sets_each_blocks_levels() {
    let src = "G20 F10\nG0 X0 Y0 Z1\nG98 G81 X1 Z-0.5 R0.1\nG99 X2\nX3\nG98 X4\nG28\nX5\n\
               G80\nG0 X0 Z-0.2\nG81 X6 Z-0.5 R0.1\nX7\nM2\n";
    assert_rs274(
        src,
        "STRAIGHT_TRAVERSE(0.0000, 0.0000, 1.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(1.0000, 0.0000, 1.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(1.0000, 0.0000, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(1.0000, 0.0000, -0.5000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(1.0000, 0.0000, 1.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(2.0000, 0.0000, 1.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(2.0000, 0.0000, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(2.0000, 0.0000, -0.5000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(2.0000, 0.0000, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(3.0000, 0.0000, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(3.0000, 0.0000, -0.5000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(3.0000, 0.0000, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(4.0000, 0.0000, 1.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(4.0000, 0.0000, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(4.0000, 0.0000, -0.5000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(4.0000, 0.0000, 1.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(4.0000, 0.0000, 1.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(5.0000, 0.0000, 1.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(5.0000, 0.0000, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(5.0000, 0.0000, -0.5000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(5.0000, 0.0000, 1.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(0.0000, 0.0000, -0.2000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(0.0000, 0.0000, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(6.0000, 0.0000, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(6.0000, 0.0000, -0.5000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(6.0000, 0.0000, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(6.0000, 0.0000, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(7.0000, 0.0000, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(7.0000, 0.0000, -0.5000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(7.0000, 0.0000, 0.1000, 0.0000, 0.0000, 0.0000)",
    );
    // G91: R counts from the initial level Z20 for the second hole too, not from its Z2.
    assert_rs274(
        "G21 F100\nG0 X0 Y0 Z20\nG91 G99 G81 X10 Y0 Z-7 R-18\nX10\nG90 G80\nM2\n",
        "STRAIGHT_TRAVERSE(0.0000, 0.0000, 20.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(10.0000, 0.0000, 20.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(10.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(10.0000, 0.0000, -5.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(10.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(20.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(20.0000, 0.0000, -5.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(20.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)",
    );
}

/// G88 stops (PROGRAM_STOP) for the operator to take the tool out by hand: rs274 has no move
/// out, and the next hole starts from the clearance level. swarf puts the tool there without
/// a move (it printed a rapid out).
#[test]
fn g88_has_no_programmed_move_out_of_the_hole() {
    let src = "G20 F10 S500 M3\nG0 X0 Y0 Z1\nG98 G88 X1 Y1 Z-0.5 R0.1 P1\nX2\nG80\nM2\n";
    assert_rs274(
        src,
        "START_SPINDLE_CLOCKWISE(0)
         STRAIGHT_TRAVERSE(0.0000, 0.0000, 1.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(1.0000, 1.0000, 1.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(1.0000, 1.0000, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(1.0000, 1.0000, -0.5000, 0.0000, 0.0000, 0.0000)
         DWELL(1.0000)
         STOP_SPINDLE_TURNING(0)
         START_SPINDLE_CLOCKWISE(0)
         STRAIGHT_TRAVERSE(2.0000, 1.0000, 1.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(2.0000, 1.0000, 0.1000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(2.0000, 1.0000, -0.5000, 0.0000, 0.0000, 0.0000)
         DWELL(1.0000)
         STOP_SPINDLE_TURNING(0)
         START_SPINDLE_CLOCKWISE(0)",
    );
    // The simulation's tool is out of the hole, at the clearance level, while it is stopped.
    let rec = read(src).unwrap();
    let put: Vec<[f64; 3]> = rec
        .events
        .iter()
        .filter_map(|(_, e)| match e {
            Canon::SetPosition(p) => Some([p.x, p.y, p.z].map(|v| v / 25.4)),
            _ => None,
        })
        .collect();
    assert_eq!(put.len(), 2, "{put:?}");
    for (p, x) in put.iter().zip([1.0, 2.0]) {
        assert!((p[0] - x).abs() < 1e-9 && (p[1] - 1.0).abs() < 1e-9 && (p[2] - 1.0).abs() < 1e-9);
    }
}

/// G87 in G91: K, the back bore's level, counts from the bottom of the hole (swarf counted
/// it from the tool's level).
#[test]
fn g87_in_g91_measures_k_from_the_bottom() {
    let src = "G21 F100 S100 M3\nG0 X0 Y0 Z5\nG91 G98 G87 X10 Z-10 R-3 I2 J0 K3 L2\nG90 G80\nM2\n";
    let hole = |x: f64| {
        format!(
            "STRAIGHT_TRAVERSE({x}, 0, 5, 0, 0, 0)
             STRAIGHT_TRAVERSE({x}, 0, 2, 0, 0, 0)
             STRAIGHT_TRAVERSE({o}, 0, 2, 0, 0, 0)
             STOP_SPINDLE_TURNING(0)
             STRAIGHT_TRAVERSE({o}, 0, -8, 0, 0, 0)
             STRAIGHT_TRAVERSE({x}, 0, -8, 0, 0, 0)
             START_SPINDLE_CLOCKWISE(0)
             STRAIGHT_FEED({x}, 0, -5, 0, 0, 0)
             STRAIGHT_FEED({x}, 0, -8, 0, 0, 0)
             STOP_SPINDLE_TURNING(0)
             STRAIGHT_TRAVERSE({o}, 0, -8, 0, 0, 0)
             STRAIGHT_TRAVERSE({o}, 0, 5, 0, 0, 0)
             STRAIGHT_TRAVERSE({x}, 0, 5, 0, 0, 0)
             START_SPINDLE_CLOCKWISE(0)\n",
            o = x + 2.0
        )
    };
    let want = format!(
        "START_SPINDLE_CLOCKWISE(0)\nSTRAIGHT_TRAVERSE(0, 0, 5, 0, 0, 0)\n{}{}",
        hole(10.0),
        hole(20.0)
    );
    assert_rs274(src, &want);
}

/// The planes: a G18 G91 G73 with L2 (pecks along Y, the plane's normal) and a G19 G89, each
/// followed by a block in the other retract mode.
#[test]
fn zx_and_yz_cycles_with_repeats_and_both_retract_modes() {
    let src = "G20 F10 S500 M3\nG0 X0 Y1 Z0\nG18 G98 G91 G73 X1 Z0.5 Y-0.3 R-0.5 Q0.25 L2\n\
               G99 Z0.5\nG90 G80\nG19 G0 X1\nG98 G89 Y1 Z1 X-0.5 R0.1 P0.5\nG99 Y2\nG17 G80\nM2\n";
    assert_rs274(
        src,
        "START_SPINDLE_CLOCKWISE(0)
         STRAIGHT_TRAVERSE(0.0000, 1.0000, 0.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(1.0000, 1.0000, 0.5000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(1.0000, 0.5000, 0.5000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(1.0000, 0.2500, 0.5000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(1.0000, 0.2600, 0.5000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(1.0000, 0.2000, 0.5000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(1.0000, 1.0000, 0.5000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(2.0000, 1.0000, 1.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(2.0000, 0.5000, 1.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(2.0000, 0.2500, 1.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(2.0000, 0.2600, 1.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(2.0000, 0.2000, 1.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(2.0000, 1.0000, 1.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(2.0000, 1.0000, 1.5000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(2.0000, 0.5000, 1.5000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(2.0000, 0.2500, 1.5000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(2.0000, 0.2600, 1.5000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(2.0000, 0.2000, 1.5000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(2.0000, 0.5000, 1.5000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(1.0000, 0.5000, 1.5000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(1.0000, 1.0000, 1.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(0.1000, 1.0000, 1.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(-0.5000, 1.0000, 1.0000, 0.0000, 0.0000, 0.0000)
         DWELL(0.5000)
         STRAIGHT_FEED(1.0000, 1.0000, 1.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(1.0000, 2.0000, 1.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(0.1000, 2.0000, 1.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(-0.5000, 2.0000, 1.0000, 0.0000, 0.0000, 0.0000)
         DWELL(0.5000)
         STRAIGHT_FEED(0.1000, 2.0000, 1.0000, 0.0000, 0.0000, 0.0000)",
    );
}

/// rs274 refuses a tapping cycle with the spindle turning the other way or stopped, a boring
/// cycle (G86–G88) with it stopped, and an L word with G74.
#[test]
fn cycles_that_linuxcnc_refuses_for_the_spindle_or_an_l_word() {
    for (src, word) in [
        (
            "G20 F10 S100 M4\nG0 X1 Y0 Z1\nG84 X1 Z-0.5 R0.1\nM2\n",
            "counterclockwise in G84",
        ),
        (
            "G20 F10 S100 M3\nG0 X1 Y0 Z1\nG74 X1 Z-0.5 R0.1\nM2\n",
            "clockwise in G74",
        ),
        (
            "G20 F10\nG0 X1 Y0 Z1\nG84 X1 Z-0.5 R0.1\nM2\n",
            "not turning in G84",
        ),
        (
            "G20 F10\nG0 X1 Y0 Z1\nG86 X1 Z-0.5 R0.1 P1\nM2\n",
            "not turning in G86",
        ),
        (
            "G20 F10\nG0 X1 Y0 Z1\nG87 X1 Z-0.5 R0.1 I0.1 J0 K0.2\nM2\n",
            "not turning in G87",
        ),
        (
            "G20 F10\nG0 X1 Y0 Z1\nG88 X1 Z-0.5 R0.1 P1\nM2\n",
            "not turning in G88",
        ),
        (
            "G20 F10 S100 M4\nG0 X0 Y0 Z1\nG74 X1 Z-1 R0.5 L2\nM2\n",
            "L word with G74",
        ),
    ] {
        let e = read(src).unwrap_err();
        assert!(e.message.contains(word), "{src}: {e}");
        assert_eq!(e.pos.line, 3, "{e}");
    }
}

/// A G98 block after G99 holes, with its R lower than theirs: the tool stands at the old R
/// (5), above the new one (2), and goes over to the hole there, not at the initial level (20);
/// it returns to the initial level (G98). swarf rapided diagonally up to Z20 on the way (a
/// reviewer's random cycle programs: 11 of 180 differed so).
#[test]
fn a_g98_block_with_a_lower_r_goes_over_where_the_tool_stands() {
    let src = "G21 G17 G90 F100 M3 S1000\nG0 X0 Y0 Z20\nG99 G81 X10 Y0 R5 Z-5\n\
               G98 G81 X20 R2 Z-5\nG80\nM2\n";
    assert_rs274(
        src,
        "START_SPINDLE_CLOCKWISE(0)
         STRAIGHT_TRAVERSE(0.0000, 0.0000, 20.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(10.0000, 0.0000, 20.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(10.0000, 0.0000, 5.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(10.0000, 0.0000, -5.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(10.0000, 0.0000, 5.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(20.0000, 0.0000, 5.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(20.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_FEED(20.0000, 0.0000, -5.0000, 0.0000, 0.0000, 0.0000)
         STRAIGHT_TRAVERSE(20.0000, 0.0000, 20.0000, 0.0000, 0.0000, 0.0000)",
    );
}
