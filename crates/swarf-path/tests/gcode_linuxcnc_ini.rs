//! G-code under a LinuxCNC machine configuration (`--ini`, [`LinuxCncIni`]) and the reader
//! details LinuxCNC 2.9's own `tests/interp` folders check beyond the shared set: every
//! expected listing is what the real `rs274 -g -i FILE` (Debian's LinuxCNC 2.9, `-t` a tool
//! table in inches, `INI_FILE_NAME` set) printed for the program above it (its motion calls and
//! `MESSAGE`s), written in; where rs274 stopped with an error its message is quoted.

use std::path::Path;

mod common;

use common::{canonical, listing as lines};
use swarf_path::gcode::{read_gcode, GcodeOptions, LinuxCncIni};
use swarf_path::{PathError, Units};

fn canon(src: &str, ini: Option<&str>) -> (String, Option<PathError>) {
    let mut opts = GcodeOptions::default();
    if let Some(text) = ini {
        let ini = LinuxCncIni::parse(text, Path::new("machine.ini"));
        opts = opts.with_linuxcnc_ini(ini).unwrap();
    }
    // The standalone rs274 keeps its offset parameters in inches.
    canonical(src, &opts.with_parameter_units(Units::Inch))
}

#[track_caller]
fn same(src: &str, ini: Option<&str>, expected: &str) {
    let (out, err) = canon(src, ini);
    assert!(err.is_none(), "{err:?}");
    assert_eq!(out, lines(expected));
}

/// `[EMCIO] TOOL_CHANGE_QUILL_UP` and `TOOL_CHANGE_AT_G30`: M6 rapids Z up to machine Z0 (the
/// controlled point's, here with a G54 Z offset of −0.25 in), then to the G30 position, before
/// the change (convert_tool_change).
#[test]
fn m6_moves_as_the_ini_says() {
    let ini = "[EMCIO]\nTOOL_CHANGE_QUILL_UP = 1\nTOOL_CHANGE_AT_G30 = 1\n";
    let src = "G20 G90\nG0 X1 Y2 Z3\nG30.1\nG10 L2 P1 X0.5 Z-0.25\nG0 X4 Y5 Z-1\nM3 S1000\n\
               T1 M6\nG0 X0\nM2\n";
    same(
        src,
        Some(ini),
        "N..... STRAIGHT_TRAVERSE(1.0000, 2.0000, 3.0000, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_TRAVERSE(4.0000, 5.0000, -1.0000, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_TRAVERSE(4.0000, 5.0000, 0.2500, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_TRAVERSE(0.5000, 2.0000, 3.2500, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_TRAVERSE(0.0000, 2.0000, 3.2500, 0.0000, 0.0000, 0.0000)",
    );
    // Without the INI, M6 moves nothing.
    same(
        src,
        None,
        "N..... STRAIGHT_TRAVERSE(1.0000, 2.0000, 3.0000, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_TRAVERSE(4.0000, 5.0000, -1.0000, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_TRAVERSE(0.0000, 5.0000, -1.0000, 0.0000, 0.0000, 0.0000)",
    );
}

/// M6 stops the spindle (rs274 prints STOP_SPINDLE_TURNING at every change) unless the INI's
/// `TOOL_CHANGE_WITH_SPINDLE_ON`: a program that cuts after M6 without M3 cuts with it stopped.
#[test]
fn m6_stops_the_spindle_unless_the_ini_keeps_it_on() {
    use swarf_path::canon::Recorder;
    use swarf_path::Canon;
    let src = "G21 G90\nM3 S1000\nT1 M6\nG1 X1 F100\nM2\n";
    let spindle_after_m6 = |ini: Option<&str>| {
        let mut opts = GcodeOptions::default();
        if let Some(t) = ini {
            opts = opts
                .with_linuxcnc_ini(LinuxCncIni::parse(t, Path::new("m.ini")))
                .unwrap();
        }
        let mut rec = Recorder::default();
        read_gcode(src, "t.ngc", &opts, &mut rec).unwrap();
        let change = rec
            .events
            .iter()
            .position(|(_, e)| matches!(e, Canon::ToolChange { .. }))
            .unwrap();
        rec.events[..change]
            .iter()
            .rev()
            .find_map(|(_, e)| match e {
                Canon::Spindle { dir, .. } => Some(*dir),
                _ => None,
            })
            .unwrap()
    };
    assert_eq!(spindle_after_m6(None), swarf_path::SpindleDir::Stopped);
    assert_eq!(
        spindle_after_m6(Some("[EMCIO]\nTOOL_CHANGE_WITH_SPINDLE_ON = 1\n")),
        swarf_path::SpindleDir::Clockwise
    );
}

/// `#<_ini[section]name>` reads the INI's numbers (section and name looked up in upper case),
/// read-only; DISABLE_FANUC_STYLE_SUB refuses M98.
#[test]
fn ini_values_and_disabled_fanuc_subs() {
    let ini = "[RS274NGC]\nDISABLE_FANUC_STYLE_SUB = 1\n[VARS]\nDEPTH = -0.125\nSAFE = 0.5\n";
    same(
        "G20 G90\nG0 X0 Y0 Z#<_ini[vars]safe>\nG1 Z#<_ini[VARS]depth> F10\n\
         (debug,depth #<_ini[vars]depth>)\nM2\n",
        Some(ini),
        "N..... STRAIGHT_TRAVERSE(0.0000, 0.0000, 0.5000, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_FEED(0.0000, 0.0000, -0.1250, 0.0000, 0.0000, 0.0000)
         N..... MESSAGE(\"depth -0.125000\")",
    );
    // rs274: "DISABLE_FANUC_STYLE_SUB set in INI file, but found m98" at `M98 P1`.
    let (_, err) = canon("G20\nM98 P1\nM2\nO1\nG0 X1\nM99\n", Some(ini));
    let err = err.unwrap();
    assert_eq!(err.pos.line, 2, "{err}");
    assert!(err.message.contains("DISABLE_FANUC_STYLE_SUB"), "{err}");
    // A main program's M99 is its loop, which the setting leaves alone (rs274 checks it in
    // a call only): the pass sets nothing, so reading ends there.
    let (_, err) = canon("G20\nG0 X1\nM99\n", Some(ini));
    assert!(err.is_none(), "{err:?}");
    // rs274 (tests/interp/iniparam-failassign): "Cannot assign to read-only parameter".
    let (_, err) = canon("#<_ini[vars]safe> = 3\nM2\n", Some(ini));
    assert!(err.unwrap().message.contains("read-only"));
    // A name the INI lacks is not defined (rs274: "Named parameter … not defined").
    let (_, err) = canon("G0 X#<_ini[vars]nosuch>\nM2\n", Some(ini));
    let err = err.unwrap();
    assert!(
        err.message.contains("not a number of the INI file"),
        "{err}"
    );
    // INI_VARS = 0: not read, and the error says why.
    let (_, err) = canon(
        "G0 X#<_ini[vars]safe>\nM2\n",
        Some("[RS274NGC]\nINI_VARS = 0\n[VARS]\nSAFE = 0.5\n"),
    );
    assert!(err.unwrap().message.contains("INI_VARS = 0"));
    // Without an INI, swarf says what it lacks.
    let (_, err) = canon("G0 X#<_ini[vars]safe>\nM2\n", None);
    assert!(err.unwrap().message.contains("INI"));
}

/// The INI's start-up code runs before the program, as LinuxCNC's task runs it: `G20` there
/// makes a program that states no units read in inches. (Not rs274's: the standalone
/// interpreter runs no start-up code.)
#[test]
fn the_startup_code_runs_first() {
    let ini = "[RS274NGC]\nRS274NGC_STARTUP_CODE = G17 G20 G40 G49 G54 G80 G90 G94\n";
    let src = "(debug,#<_imperial>)\nG0 X1\nM2\n";
    same(
        src,
        Some(ini),
        "N..... MESSAGE(\"1.000000\")
         N..... STRAIGHT_TRAVERSE(1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
    );
    let (_, err) = canon(src, None);
    assert!(err.is_none());
    let (out, _) = canon(src, None);
    assert!(out.contains("MESSAGE(\"0.000000\")"), "{out}");
    let ini = "[RS274NGC]\nRS274NGC_STARTUP_CODE = G17 G21 G99.5\n";
    let (_, err) = canon("G0 X1\nM2\n", Some(ini));
    let err = err.unwrap();
    assert_eq!(err.pos.file, "machine.ini");
    assert_eq!(err.pos.line, 2, "{err}");
    assert!(err.message.contains("STARTUP_CODE"), "{err}");
}

/// `EXISTS[#n]` on numbered parameters (in range exists, out of range is 0), an O number read
/// from a parameter (`o#<n> call`), and G80 beside another motion code, which yields to it in
/// either order (tests/interp/exists, oword-bug315-p2; read_g).
#[test]
fn exists_computed_o_numbers_and_g80_beside_a_motion() {
    same(
        "G21 G90\n#1 = 5\n#2 = 99999\nG0 X[EXISTS[#1]] Y[EXISTS[##2]] Z[EXISTS[#<nope>]]\n\
         #<n> = 100\no#<n> call [2]\nM2\no100 sub\nG0 X#1\no100 endsub\n",
        None,
        "N..... STRAIGHT_TRAVERSE(1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_TRAVERSE(2.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
    );
    // (Under LinuxCNC's rules: `G80 G0` alone would be read as a Fanuc post's habit.)
    same(
        "G21 G90\n(debug,linuxcnc)\nG0 X1 Y1 Z1\nG80 G0\nG81 G80 X2 Y2 Z-1 R1 F100\nG80 G1 X3\nM3 S500\nT2 M6\n\
         G0 X0\nM2\n",
        None,
        "N..... MESSAGE(\"linuxcnc\")
         N..... STRAIGHT_TRAVERSE(1.0000, 1.0000, 1.0000, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_TRAVERSE(1.0000, 1.0000, 1.0000, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_TRAVERSE(2.0000, 2.0000, 1.0000, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_FEED(2.0000, 2.0000, -1.0000, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_TRAVERSE(2.0000, 2.0000, 1.0000, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_FEED(3.0000, 2.0000, 1.0000, 0.0000, 0.0000, 0.0000)
         N..... STRAIGHT_TRAVERSE(0.0000, 2.0000, 1.0000, 0.0000, 0.0000, 0.0000)",
    );
}

/// G10 L11: tool P's offsets set so that the current position reads the given values in
/// G59.3 (the touch-off fixture), G92 left out (tests/interp/g10/g10-l11: "length should be
/// -3" with G59.3's Z at -27 and the controlled point at machine Z −30).
#[test]
fn g10_l11_touches_off_against_the_fixture() {
    same(
        "G20\nG10 L2 P1 X1 Y2 Z-3\nG10 L2 P9 X25 Y26 Z-27\nG54\nG0 G53 Z-30\nG10 L11 P1 Z0\n\
         T1 M6\n(debug,#5403)\nG92 X33 Y44 Z55\nG10 L11 P1 Z1\n(debug,#5403)\nM2\n",
        None,
        "N..... STRAIGHT_TRAVERSE(-1.0000, -2.0000, -27.0000, 0.0000, 0.0000, 0.0000)
         N..... MESSAGE(\"-3.000000\")
         N..... MESSAGE(\"-4.000000\")",
    );
}
