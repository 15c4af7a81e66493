//! What swarf says about hobby-CAM programs (Fusion, Vectric, Mach3 posts, hand edits): each
//! message names the word or character it is about, with its column, and the way out.

use swarf_path::canon::Recorder;
use swarf_path::gcode::{read_gcode, GcodeDialect, GcodeOptions};
use swarf_path::{PathError, PathErrorKind};

fn read(src: &str, opts: &GcodeOptions) -> Result<Recorder, PathError> {
    let mut rec = Recorder::default();
    read_gcode(src, "h.nc", opts, &mut rec)?;
    Ok(rec)
}

#[test]
fn an_invisible_character_is_named_not_read_as_the_end_of_the_line() {
    for (ch, shown) in [
        ('\u{a0}', "U+00A0 (no-break space)"),
        ('\u{c}', "U+000C (form feed)"),
        ('\u{200b}', "U+200B (zero-width space)"),
    ] {
        let e = read(
            &format!("G21 G90\nG0 X1{ch}Y2\nM30\n"),
            &GcodeOptions::default(),
        )
        .unwrap_err();
        // Column 6: after `G0 X1`, counted in characters.
        assert_eq!((e.pos.line, e.pos.column), (2, 6), "{e}");
        assert_eq!(e.found, shown, "{e}");
    }
}

#[test]
fn scientific_notation_is_an_error_at_the_number() {
    for (line, column, text) in [
        ("G1 X1e3 F100", 5, "1e3"),
        ("G1 X1.5E-2 F100", 5, "1.5e-2"),
        ("G1 Y-2e+1 F100", 5, "-2e+1"),
    ] {
        let e = read(&format!("G21 G90\n{line}\nM30\n"), &GcodeOptions::default()).unwrap_err();
        assert_eq!(
            (e.kind, e.pos.line, e.pos.column),
            (PathErrorKind::Syntax, 2, column),
            "{line}: {e}"
        );
        assert!(
            e.message
                .contains(&format!("`{text}` is scientific notation")),
            "{line}: {e}"
        );
    }
    // An E word after a blank is a word (warned as unused), not a number's exponent.
    let rec = read("G21 G90\nG1 X1 E3 F100\nM30\n", &GcodeOptions::default()).unwrap();
    assert!(rec
        .warnings
        .iter()
        .any(|w| w.message.contains("E3 ignored")));
}

#[test]
fn mach3_circular_pockets_are_named() {
    for code in ["G12", "G13"] {
        let e = read(
            &format!("G21 G90\nG0 X10 Y10 Z1\nG1 Z-1 F100\n{code} I5\nM30\n"),
            &GcodeOptions::default(),
        )
        .unwrap_err();
        assert_eq!((e.pos.line, e.pos.column), (4, 1), "{e}");
        assert!(
            e.message
                .contains("Mach3's circular pocket G12/G13 is not read")
                && e.message.contains("G2/G3 full circles"),
            "{e}"
        );
    }
}

#[test]
fn a_tool_loaded_later_is_not_said_never_to_be_loaded() {
    let rec = read(
        "G21G90\nT1\nG0X1\nM6\nG0X2\nM30\n",
        &GcodeOptions::default(),
    )
    .unwrap();
    let w: Vec<_> = rec
        .warnings
        .iter()
        .filter(|w| w.message.contains("T1 was selected"))
        .collect();
    assert_eq!(w.len(), 1, "{:?}", rec.warnings);
    assert_eq!((w[0].line, w[0].column), (3, 1), "{w:?}");
    assert!(
        w[0].message.contains("not loaded with M6 yet at this move")
            && !w[0].message.contains("never"),
        "{w:?}"
    );
}

#[test]
fn a_fanuc_d_register_warning_names_the_linuxcnc_way() {
    let src = "%\nO1001\nG21 G90\nT1 M6\nG0 X-5. Y0. Z5.\nG1 Z-1. F300.\nG41 D1 X0. Y0.\n\
               G1 X20.\nG40 X30. Y30.\nM30\n%\n";
    let rec = read(src, &GcodeOptions::default()).unwrap();
    let w = rec
        .warnings
        .iter()
        .find(|w| w.message.contains("register D1"))
        .expect("the register warning");
    assert_eq!((w.line, w.column), (7, 5), "{w:?}");
    assert!(
        w.message.contains(
            "--dialect linuxcnc reads D1 as tool 1, whose radius --tool or --tools gives"
        ),
        "{w:?}"
    );
    // And so it does: with tool 1 of diameter 6, the first cut runs at y = 3.
    let opts = GcodeOptions::default()
        .with_dialect(GcodeDialect::LinuxCnc)
        .with_tool_diameter(1, 6.0);
    let rec = read(src, &opts).unwrap();
    let ys: Vec<f64> = rec
        .events
        .iter()
        .filter_map(|(_, e)| match e {
            swarf_path::Canon::Feed { end } => Some(end.y),
            _ => None,
        })
        .collect();
    assert!(ys.iter().any(|y| (y - 3.0).abs() < 1e-9), "{ys:?}");
}

#[test]
fn the_dialect_warning_names_the_cue_its_line_shows() {
    let fanuc_warning = |src: &str| {
        let rec = read(src, &GcodeOptions::default()).unwrap();
        rec.warnings
            .into_iter()
            .find(|w| w.message.starts_with("read by Fanuc rules"))
            .expect("the dialect warning")
    };
    // Vectric's Mach3 header: G80 beside G00 in one block.
    let w = fanuc_warning("(VECTRIC)\nG00G21G17G90G40G49G80\nG0 X1\nM30\n");
    assert_eq!(w.line, 2, "{w:?}");
    assert!(
        w.message
            .contains("this line shows G80 with G0/G1/G2/G3 in one block"),
        "{w:?}"
    );
    let w = fanuc_warning("%\nO1001\nG21 G90\nG0 X1\nM30\n%\n");
    assert_eq!(w.line, 2, "{w:?}");
    assert!(
        w.message
            .contains("this line shows a bare program number, O1001"),
        "{w:?}"
    );
    let w = fanuc_warning("G21 G90\nG4 P500\nM30\n");
    assert!(w.message.contains("a dwell P without a point"), "{w:?}");
    // No fixed list of every cue.
    assert!(!w.message.contains("M98/M99, Macro B"), "{w:?}");
}

/// The straight moves' end points.
fn ends(rec: &Recorder) -> Vec<[f64; 3]> {
    rec.events
        .iter()
        .filter_map(|(_, e)| match e {
            swarf_path::Canon::Traverse { end } | swarf_path::Canon::Feed { end } => {
                Some([end.x, end.y, end.z])
            }
            _ => None,
        })
        .collect()
}

#[test]
fn code_after_the_programs_end_is_said_not_read() {
    // Two programs joined, each closed by `%`, or after M30: a control stops at the end, so the
    // second is not read — said once, at the end, with the count of code lines (it was silent:
    // "removed 0 mm³" and no word).
    for (text, line, n) in [
        (
            "%\nG21 G90\nG0 X1\n%\n%\nG21 G90\nG0 X50\nG1 Z-5 F100\nM30\n%\n",
            4,
            4,
        ),
        (
            "G21 G90\nG0 X1\nM30\nG0 X50 (second)\nG1 Z-5 F100\nM30\n",
            3,
            3,
        ),
        ("G21 G0 X1\n%\nG0 X5\n", 2, 1),
    ] {
        let rec = read(text, &GcodeOptions::default()).unwrap();
        assert_eq!(ends(&rec), [[1.0, 0.0, 0.0]], "{text}");
        let w: Vec<_> = rec
            .warnings
            .iter()
            .filter(|w| w.message.contains("after the program's end"))
            .collect();
        assert_eq!(w.len(), 1, "{:?}", rec.warnings);
        assert_eq!(w[0].line, line, "{:?}", w[0]);
        assert!(w[0].message.starts_with(&format!("{n} line")), "{:?}", w[0]);
    }
    // Two Fanuc programs joined (each with its number): the second's four code lines.
    let joined = "%\nO1001\nG21 G90\nG0 X1\nM30\n%\n%\nO1002 (SECOND)\nG21 G90\nG0 X50\n\
        G1 Z-5 F100\nM30\n%\n";
    let rec = read(joined, &GcodeOptions::default()).unwrap();
    let w: Vec<_> = rec
        .warnings
        .iter()
        .filter(|w| w.message.contains("after the program's end"))
        .collect();
    assert_eq!(w.len(), 1, "{:?}", rec.warnings);
    assert!(w[0].message.starts_with("4 lines"), "{:?}", w[0]);
    // Subprograms after the end (Fanuc's, LinuxCNC's) and comments are not code left unread.
    for text in [
        "O1\nG21 G90\nM98 P2\nM30\n(the subprogram)\nO2\nG0 X3\nM99\n%\n",
        "G21 G90\nG0 X1\nM2\no<s> sub\nG0 X2\no<s> endsub\n(end)\n",
        // Haas: an M97 local subprogram, N-numbered blocks after M30 up to its M99.
        "O0001\nG21 G90 G0 X0 Y0 Z0\nM97 P100 L2\nM30\nN100 G91 G0 Z1.\nM99\n",
    ] {
        let rec = read(text, &GcodeOptions::default()).unwrap();
        assert!(
            rec.warnings
                .iter()
                .all(|w| !w.message.contains("after the program's end")),
            "{text}: {:?}",
            rec.warnings
        );
    }
}

#[test]
fn a_probing_move_is_read_with_the_tool_staying_where_it_is() {
    // A touch-off block at the top of a hobby program: the probe trips somewhere above its
    // programmed end, which only the machine knows. The tool stays (a move to Z-10 would plunge
    // through the touch plate), the offset set from there is applied, and a warning says so.
    // (The whole program was refused: "probing is not simulated".)
    let text = "G21 G90\nG0 X0 Y0 Z5\nG38.2 Z-10 F50\nG10 L20 P1 Z0\nG0 Z5\nG0 X10\nM30\n";
    let rec = read(text, &GcodeOptions::default()).unwrap();
    // Z0 set at the start point (machine Z5): Z5 is machine Z10, in the new frame 5.
    assert_eq!(
        ends(&rec),
        [[0.0, 0.0, 5.0], [0.0, 0.0, 5.0], [10.0, 0.0, 5.0]]
    );
    let w: Vec<_> = rec
        .warnings
        .iter()
        .filter(|w| w.message.starts_with("G38.2"))
        .collect();
    assert_eq!(w.len(), 1, "{:?}", rec.warnings);
    assert_eq!((w[0].line, w[0].column), (3, 1), "{:?}", w[0]);
    // The probe's result parameters read where the tool stands, in program units.
    let rec = read(
        "G20 G90\nG0 X1 Y2 Z0.5\nG38.2 Z-1 F5\n(debug,#5061 #5062 #5063 #5070)\nM30\n",
        &GcodeOptions::default(),
    )
    .unwrap();
    assert_eq!(rec.messages(), ["1.000000 2.000000 0.500000 1.000000"]);
    // LinuxCNC's refusals stay.
    for (text, what, line) in [
        (
            "G21 G90\nG0 X0 Y0 Z5\nG41.1 D2\nG38.2 Z-10 F50\nM30\n",
            "cutter radius compensation",
            4,
        ),
        ("G21 G90\nG0 X0 Y0 Z5\nG38.3 Z-10\nM30\n", "zero feed", 3),
        (
            "G21 G90\nG0 X0 Y0 Z5\nG38.2 Z-10 A5 F50\nM30\n",
            "rotary axes",
            3,
        ),
        ("G21 G90\nG0 X0 Y0 Z5\nG38.2 F50\nM30\n", "all missing", 3),
        ("G21 G90\nG0 X0 Y0 Z5\nG38.2 Z5 F50\nM30\n", "too close", 3),
        ("G21 G90\nG0 X0 Y0 Z5\nG38.4 Z5 F50\nM30\n", "too close", 3),
    ] {
        let e = read(text, &GcodeOptions::default()).unwrap_err();
        assert!(e.to_string().contains(what), "{e}");
        assert_eq!(e.pos.line, line, "{e}");
    }
    // rs274 2.9 probes any distance, and G38.3/G38.5 (which may fail to trip) none at all
    // (swarf refused anything under 0.254 mm: LinuxCNC's smartprobe.ngc stopped at line 39).
    for text in [
        "G21 G90\nG0 X0 Y0 Z5\nG38.2 Z4.9999 F50\nM30\n",
        "G20 G90\nG0 X0 Y0 Z1\nG38.5 Z1 F5\nG38.5 Z1.005\nM30\n",
        "G21 G90\nG0 X0 Y0 Z5\nG38.3 Z5 F50\nM30\n",
    ] {
        read(text, &GcodeOptions::default()).unwrap_or_else(|e| panic!("{text}: {e}"));
    }
}
