//! LinuxCNC's rules for parameters that swarf read otherwise: read-only parameters cannot be
//! assigned (numbered #5400–#5413 and #5420–#5428, and the predefined named ones), DEBUG
//! messages are not printed while #5599 is 0, and neither `#<_feed>` nor the tool's
//! parameters (#5401–#5410) change when G20/G21 change the program's units.

use swarf_path::canon::Recorder;
use swarf_path::gcode::{read_gcode, GcodeOptions};
use swarf_path::{PathError, PathErrorKind, Units};

fn read(src: &str, opts: &GcodeOptions) -> Result<Recorder, PathError> {
    let mut rec = Recorder::default();
    read_gcode(src, "p.ngc", opts, &mut rec)?;
    Ok(rec)
}

#[test]
fn read_only_parameters_cannot_be_assigned() {
    for (line, column, name) in [
        ("#5420=7", 1, "#5420"),
        ("#5400=4", 1, "#5400"),
        ("G0 #5413=1", 4, "#5413"),
        ("#5428 = 2", 1, "#5428"),
        ("#1=2 #[5400+10]=1", 6, "#5410"),
        ("#<_x>=3", 1, "#<_x>"),
        ("#<_motion_mode>=3", 1, "#<_motion_mode>"),
    ] {
        let e = read(&format!("G21\n{line}\nM2\n"), &GcodeOptions::default()).unwrap_err();
        assert_eq!(
            (e.kind, e.pos.line, e.pos.column),
            (PathErrorKind::Semantic, 2, column),
            "{line}: {e}"
        );
        assert!(
            e.message.contains(name) && e.message.contains("read-only"),
            "{line}: {e}"
        );
    }
    // Those a program may set: #5399, #5414–#5419, #5599, its own globals, `_value`.
    let rec = read(
        "G21\n#5399=1\n#5414=2\n#5419=3\n#5599=1\n#<_mine>=4\n#<_value>=5\n\
         (debug,#5399 #5414 #5419 #<_mine> #<_value>)\nM2\n",
        &GcodeOptions::default(),
    )
    .unwrap();
    assert_eq!(
        rec.messages(),
        ["1.000000 2.000000 3.000000 4.000000 5.000000"]
    );
}

#[test]
fn debug_messages_wait_for_5599() {
    let rec = read(
        "G21\n(debug,shown first)\n#5599=0\n(debug,hidden)\n(print,p)\n(msg,m)\n#5599=1\n\
         (debug,shown)\nM2\n",
        &GcodeOptions::default(),
    )
    .unwrap();
    assert_eq!(rec.messages(), ["shown first", "p", "m", "shown"]);
    // It reads 1 at the start, as LinuxCNC's default.
    let rec = read("G21\n(debug,#5599)\nM2\n", &GcodeOptions::default()).unwrap();
    assert_eq!(rec.messages(), ["1.000000"]);
}

#[test]
fn units_do_not_change_the_feed_or_the_tools_parameters() {
    // F100 in mm: after G20 the feed parameter still reads the F word's 100.
    let rec = read(
        "G21 F100\nG20\n(debug,#<_feed>)\nG21\n(debug,#<_feed>)\nM2\n",
        &GcodeOptions::default(),
    )
    .unwrap();
    assert_eq!(rec.messages(), ["100.000000", "100.000000"]);
    // A tool of radius 0.1 in and length 1 in, set in inches on an inch machine: #5410
    // reads its diameter 0.2 and #5403 its length 1, in G20 and in G21 alike.
    let inch = GcodeOptions::default().with_parameter_units(Units::Inch);
    let src = "G20 F10\nG10 L1 P1 R0.1 Z1\nT1 M6 G43\n(debug,#5410 #5403)\nG21\n(debug,#5410 #5403)\nM2\n";
    let want = format!("{:.6} {:.6}", 2.0 * 0.1, 1.0);
    assert_eq!(read(src, &inch).unwrap().messages(), [want.clone(), want]);
    // On a mm machine the same tool reads 5.08 and 25.4, in both units.
    let want = format!("{:.6} {:.6}", 2.0 * 0.1 * 25.4, 25.4);
    assert_eq!(
        read(src, &GcodeOptions::default()).unwrap().messages(),
        [want.clone(), want]
    );
}
