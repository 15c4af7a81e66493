//! Coordinates beyond the machine range (`MACHINE_RANGE_MM`, 10⁶ mm) or not finite are errors at
//! their file:line:column in both readers — never a move with an infinite length that every
//! later stage silently skips.

use swarf_geom::math::MACHINE_RANGE_MM;
use swarf_path::apt::{read_apt, AptOptions};
use swarf_path::canon::Recorder;
use swarf_path::gcode::{read_gcode, GcodeOptions};
use swarf_path::{summarize, MoveBuilder, PathError, PathErrorKind};

fn gcode(src: &str) -> Result<Recorder, PathError> {
    let mut rec = Recorder::default();
    read_gcode(src, "t.ngc", &GcodeOptions::default(), &mut rec)?;
    Ok(rec)
}

fn apt(src: &str) -> Result<Recorder, PathError> {
    let mut rec = Recorder::default();
    read_apt(src, "t.apt", &AptOptions::default(), &mut rec)?;
    Ok(rec)
}

fn at(e: &PathError) -> (u32, u32) {
    (e.pos.line, e.pos.column)
}

fn says_range(e: &PathError) {
    assert_eq!(e.kind, PathErrorKind::Semantic, "{e}");
    let s = e.to_string();
    assert!(s.contains("machine range") && s.contains("1e6"), "{s}");
}

#[test]
fn a_word_of_three_hundred_digits_is_an_error_at_the_word() {
    // `X1` followed by 300 zeros is 1e300: finite, but its feed length overflows to infinity.
    let src = format!("G21 G90 G1 F100\nG1 X1{} Y2\n", "0".repeat(300));
    let e = gcode(&src).unwrap_err();
    says_range(&e);
    assert_eq!(at(&e), (2, 4), "{e}");
    assert!(e.to_string().contains("1e300"), "{e}");
}

#[test]
fn the_range_holds_after_units_increments_and_offsets() {
    // Exactly at the range: accepted, and summarized with a finite length.
    let rec = gcode("G21 G90 G1 X1000000 F100\nM2\n").unwrap();
    assert_eq!(
        rec.events
            .iter()
            .filter(|(_, e)| matches!(e, swarf_path::Canon::Feed { .. }))
            .count(),
        1
    );
    // 50,000 inches is 1.27e6 mm.
    let e = gcode("G20 G90 G1 X50000 F10\n").unwrap_err();
    says_range(&e);
    assert_eq!(at(&e), (1, 12));
    // Incremental moves that add up past it: the word of the block that crosses it.
    let e = gcode("G21 G91 G1 X600000 F100\nY5\nX600000\n").unwrap_err();
    says_range(&e);
    assert_eq!(at(&e), (3, 1));
    // Polar words: the word that put it there.
    let e = gcode("G21 G90 G1 X1 F100\nG1 @2000000 ^45\n").unwrap_err();
    says_range(&e);
    assert_eq!(at(&e), (2, 4), "{e}");
}

#[test]
fn absurd_arc_centres_are_errors_at_their_word() {
    let e = gcode(&format!(
        "G21 G90 G17 F100\nG2 X0 Y0 I1{}\n",
        "0".repeat(40)
    ))
    .unwrap_err();
    says_range(&e);
    assert_eq!(at(&e), (2, 10), "{e}");
    let e = gcode(&format!(
        "G21 G90 G17 F100\nG1 X0 Y0\nG2 X1 Y0 R1{}\n",
        "0".repeat(40)
    ))
    .unwrap_err();
    says_range(&e);
    assert_eq!(at(&e), (3, 10), "{e}");
}

#[test]
fn apt_points_beyond_the_range_are_errors_at_their_field() {
    let e = apt("UNITS/MM\nFEDRAT/100\nGOTO/0,0,5\nGOTO/1e300,0,5\n").unwrap_err();
    says_range(&e);
    assert_eq!(at(&e), (4, 6), "{e}");
    assert_eq!(e.found, "1e300");
    let e = apt("UNITS/MM\nGOTO/0,0,5\nGOTO/0, 2e6 ,5\n").unwrap_err();
    assert_eq!(at(&e), (3, 9), "{e}");
    // Inches: 50,000 in is beyond.
    let e = apt("UNITS/INCHES\nGOTO/0,0,0\nGOTO/0,0,50000\n").unwrap_err();
    says_range(&e);
    assert_eq!(e.found, "50000");
    // An incremental step past it, and a circle centre beyond it.
    let e = apt("GOTO/0,0,0\nGODLTA/900000,0,0\nGODLTA/900000,0,0\n").unwrap_err();
    says_range(&e);
    assert_eq!(e.pos.line, 3);
    let e = apt("GOTO/0,0,0\nCIRCLE/1e7,0,0,0,0,1,1e7\nGOTO/1,0,0\n").unwrap_err();
    says_range(&e);
    assert_eq!(at(&e), (2, 8));
}

#[test]
fn every_length_of_an_accepted_program_is_finite() {
    // The extremes of the range: the longest possible moves, diagonal through the range.
    let r = MACHINE_RANGE_MM;
    let src = format!("G21 G90 G0 X-{r} Y-{r} Z-{r}\nG1 X{r} Y{r} Z{r} F1\nM2\n");
    let mut b = MoveBuilder::new(swarf_path::Machine::three_axis(), "t.ngc");
    read_gcode(&src, "t.ngc", &GcodeOptions::default(), &mut b).unwrap();
    let s = summarize(&b.finish());
    assert!(s.feed_length_mm.is_finite() && s.machining_time_s.is_finite());
    assert!((s.feed_length_mm - 2.0 * r * 3f64.sqrt()).abs() < 1e-6);
}
