//! Every G-code file in the third-party data folder (`SWARF_TEST_DATA`, `gcode/`) reads without
//! error, or fails with the documented error; event counts and positions checked against values
//! worked out independently of the reader (by counting lines of the text, or analytically).
//! Tests of the data skip, saying so, without it.

use swarf_path::canon::Recorder;
use swarf_path::gcode::{read_gcode, read_gcode_file, GcodeOptions};
use swarf_path::Canon;

/// The data file `gcode/NAME`'s text, or `None` (the test skips, saying so) without it.
fn text(name: &str) -> Option<String> {
    let path = swarf_testdata::path(&format!("gcode/{name}"))?;
    Some(std::fs::read_to_string(path).unwrap())
}

/// `text` read as `name`.
fn read(name: &str, text: &str) -> Recorder {
    let mut rec = Recorder::default();
    read_gcode(text, name, &GcodeOptions::default(), &mut rec)
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    rec
}

fn count(rec: &Recorder, f: impl Fn(&Canon<'_>) -> bool) -> usize {
    rec.events.iter().filter(|(_, e)| f(e)).count()
}

fn is_feed(e: &Canon<'_>) -> bool {
    matches!(e, Canon::Feed { .. })
}
fn is_traverse(e: &Canon<'_>) -> bool {
    matches!(e, Canon::Traverse { .. })
}
fn is_arc(e: &Canon<'_>) -> bool {
    matches!(e, Canon::Arc { .. })
}

/// Lines of `text` whose code starts with `prefix` (case-insensitive) — a count made from the
/// text alone.
fn lines_starting(text: &str, prefixes: &[&str]) -> usize {
    text.lines()
        .filter(|l| {
            prefixes
                .iter()
                .any(|p| l.trim().to_ascii_uppercase().starts_with(p))
        })
        .count()
}

#[test]
fn every_shared_gcode_file_reads_or_fails_as_documented() {
    let Some(dir) = swarf_testdata::path("gcode") else {
        return;
    };
    let mut seen = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        if !matches!(ext, "ngc" | "gcode" | "ptp") {
            continue;
        }
        seen += 1;
        let name = path.file_name().unwrap().to_str().unwrap().to_string();
        let mut rec = Recorder::default();
        let r = read_gcode_file(&path, &GcodeOptions::default(), &mut rec);
        if name == "nx_haas_vf3_testpart.ptp" {
            // `G41X3.5D1` on a Haas: the offset of register D1 is the control's, which the
            // program does not carry; the path is read as the tool centre's (as the post wrote
            // it for wear compensation), with a warning at the D word.
            r.unwrap();
            let w: Vec<_> = rec
                .warnings
                .iter()
                .filter(|w| w.message.contains("register D1"))
                .collect();
            assert_eq!(w.len(), 1, "{:?}", rec.warnings);
            assert_eq!((w[0].line, w[0].column), (33, 8));
            // A tool library's cutter is not a register: with tool 1's diameter given, the
            // path stays the centre's (taking the cutter's radius compensated the wear path a
            // second time, and the concave corner could not be reached).
            let mut rec = Recorder::default();
            let options = GcodeOptions::default().with_tool_diameter(1, 25.4);
            read_gcode_file(&path, &options, &mut rec).unwrap();
            assert!(count(&rec, is_arc) > 0);
            let x34 = rec.events.iter().find_map(|(l, e)| match e {
                Canon::Feed { end } if *l == 34 => Some(end.x),
                _ => None,
            });
            assert!(x34.is_some_and(|x| (x - 3.5).abs() < 1e-9), "{x34:?}");
        } else {
            r.unwrap_or_else(|e| panic!("{name}: {e}"));
            assert!(count(&rec, |e| is_feed(e) || is_arc(e)) > 0, "{name} cuts");
        }
    }
    assert!(seen >= 7, "found the shared files");
}

#[test]
fn spiral_is_800_polar_moves_ending_at_the_centre() {
    // LinuxCNC's nc_files/spiral.ngc, written out here: the polar move is on line 9.
    let spiral = "g20 g64 g90\ns3400 m3\n\ng0 z1\ng0 x2 y0\ng1 z-.1 f24\n\n\
                  o100 repeat [800]\ng91 g1 @-.0025 ^4.5\no100 endrepeat\n\ng90 g0 z1\nm2\n";
    let rec = read("spiral.ngc", spiral);
    let feeds: Vec<_> = rec
        .events
        .iter()
        .filter_map(|(l, e)| match e {
            Canon::Feed { end } => Some((*l, *end)),
            _ => None,
        })
        .collect();
    // `g1 z-.1` then 800 moves of `g91 g1 @-.0025 ^4.5` from (2, 0) inches.
    assert_eq!(feeds.len(), 801);
    assert!(feeds[1..].iter().all(|(l, _)| *l == 9));
    for (k, (_, end)) in feeds[1..].iter().enumerate() {
        let k = k as f64 + 1.0;
        let r = (2.0 - 0.0025 * k) * 25.4;
        let th = (4.5 * k).to_radians();
        assert!(
            (end.x - r * th.cos()).abs() < 1e-9 && (end.y - r * th.sin()).abs() < 1e-9,
            "move {k}: {end:?}"
        );
        assert!((end.z + 0.1 * 25.4).abs() < 1e-12);
    }
    // 800 × 0.0025 in = 2 in: the spiral ends at the centre, after exactly ten turns.
    let last = feeds[800].1;
    assert!(last.x.abs() < 1e-9 && last.y.abs() < 1e-9, "{last:?}");
    assert_eq!(count(&rec, is_traverse), 3);
    assert!(matches!(rec.events.last().unwrap().1, Canon::ProgramEnd));
}

#[test]
fn camotics_programs_count_their_moves() {
    for name in [
        "camotics_heart.ngc",
        "camotics_heart_cutout.ngc",
        "camotics_wave.gcode",
    ] {
        let Some(text) = text(name) else {
            return;
        };
        let rec = read(name, &text);
        assert_eq!(
            count(&rec, is_traverse),
            lines_starting(&text, &["G0 "]),
            "{name} G0"
        );
        assert_eq!(
            count(&rec, is_feed),
            lines_starting(&text, &["G1 "]),
            "{name} G1"
        );
        assert_eq!(
            count(&rec, is_arc),
            lines_starting(&text, &["G2 ", "G3 "]),
            "{name} arcs"
        );
        // The only things these programs do that swarf does not act on: a missing M2/M30, and
        // the CAMotics habit of selecting the tool with a lone `T` (taken as loaded, reported).
        assert!(
            rec.warnings
                .iter()
                .all(|w| w.message.contains("M2/M30")
                    || w.message.contains("not loaded with M6 yet")),
            "{name}: {:?}",
            rec.warnings
        );
        let lone_t = text.lines().any(|l| l.trim().starts_with('T'));
        assert_eq!(
            rec.events
                .iter()
                .any(|(_, e)| matches!(e, Canon::ToolChange { .. })),
            lone_t || text.contains("M6"),
            "{name}"
        );
    }
}

#[test]
fn heart_uses_named_parameters() {
    let Some(text) = text("camotics_heart.ngc") else {
        return;
    };
    let rec = read("camotics_heart.ngc", &text);
    // `G1 Z#<z_cut> F#<drill_speed>` after `#<z_cut> = -1`: the first plunge is to Z-1 at 50.
    let first_feed = rec.events.iter().find_map(|(_, e)| match e {
        Canon::Feed { end } => Some(*end),
        _ => None,
    });
    assert_eq!(first_feed.unwrap().z, -1.0);
    assert!(rec.events.iter().any(|(_, e)| *e == Canon::FeedRate(50.0)));
    // The arcs close the heart: the last arc of the first pass ends where the pass started.
    let first_traverse_xy = rec
        .events
        .iter()
        .filter_map(|(_, e)| match e {
            Canon::Traverse { end } => Some(*end),
            _ => None,
        })
        .nth(1)
        .unwrap();
    assert!((first_traverse_xy.x + 1.531938).abs() < 1e-12);
}

#[test]
fn boat_five_axis_warns_on_m_codes_and_switches_feed_modes() {
    let Some(text) = text("linuxcnc_boat-xyzac.ngc") else {
        return;
    };
    let rec = read("linuxcnc_boat-xyzac.ngc", &text);
    let warned = |s: &str| rec.warnings.iter().any(|w| w.message.contains(s));
    assert!(warned("M428"), "{:?}", rec.warnings);
    assert!(warned("M429"));
    assert!(warned("M8"));
    assert!(warned("M9"));
    assert_eq!(
        count(&rec, |e| *e
            == Canon::FeedMode(swarf_path::FeedMode::InverseTime)),
        lines_starting(&text, &["G93"])
    );
    // Rotary words arrive in degrees, untouched.
    let max_c = rec
        .events
        .iter()
        .filter_map(|(_, e)| match e {
            Canon::Feed { end } | Canon::Traverse { end } => Some(end.c.abs()),
            _ => None,
        })
        .fold(0.0, f64::max);
    assert!(max_c > 10.0);
    assert!(matches!(rec.events.last().unwrap().1, Canon::ProgramEnd));
}

#[test]
fn haas_program_up_to_cutter_compensation() {
    // The part of the Haas program before G41 reads fine: check its moves by hand.
    let Some(text) = text("nx_haas_vf3_testpart.ptp") else {
        return;
    };
    let head: String = text.lines().take(31).map(|l| format!("{l}\n")).collect();
    let mut rec = Recorder::default();
    read_gcode(&head, "haas-head", &GcodeOptions::default(), &mut rec).unwrap();
    // The program has no G20/G21, so it is read in the initial units (mm).
    // G2X2.5Y-.5I-1.J0. from (3.5, .5): centre (2.5, .5), clockwise quarter.
    let arc = rec.events.iter().find(|(_, e)| is_arc(e)).unwrap();
    let Canon::Arc {
        end,
        center,
        rotation,
        ..
    } = arc.1
    else {
        unreachable!()
    };
    assert_eq!(arc.0, 17);
    assert!((center[0] - 2.5).abs() < 1e-12 && (center[1] - 0.5).abs() < 1e-12);
    assert!((end.x - 2.5).abs() < 1e-12 && (end.y + 0.5).abs() < 1e-12);
    assert_eq!(rotation, -1);
    // `G28G91Z0.`: through the current point, then Z to the G28 position (machine 0).
    let g28: Vec<_> = rec
        .events
        .iter()
        .filter(|(l, e)| *l == 25 && is_traverse(e))
        .collect();
    assert_eq!(g28.len(), 2);
    let Canon::Traverse { end } = g28[1].1 else {
        unreachable!()
    };
    assert_eq!(end.z, 0.0);
    assert_eq!(end.x, 0.0, "X stays where the tool was (X0 after G1X0.)");
}
