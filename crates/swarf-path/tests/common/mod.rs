//! Helpers shared by the reader tests.
#![allow(dead_code)]

use swarf_geom::math::Vec3;
use swarf_path::apt::{read_apt, AptOptions};
use swarf_path::canon::Recorder;
use swarf_path::canonical::CanonicalPrinter;
use swarf_path::gcode::{read_gcode, GcodeOptions};
use swarf_path::{Canon, PathError, Program};

/// The events of an APT program that reads.
pub(crate) fn apt_events(text: &str) -> Vec<Canon<'static>> {
    let mut rec = Recorder::default();
    read_apt(text, "t.apt", &AptOptions::default(), &mut rec).unwrap();
    rec.events.into_iter().map(|(_, e)| e).collect()
}

/// The error of an APT program that does not.
pub(crate) fn apt_err(text: &str) -> PathError {
    let mut rec = Recorder::default();
    read_apt(text, "t.apt", &AptOptions::default(), &mut rec).unwrap_err()
}

/// `a` within `tol` of `b` on every axis.
pub(crate) fn close(a: Vec3, b: [f64; 3], tol: f64) -> bool {
    (a.x - b[0]).abs() < tol && (a.y - b[1]).abs() < tol && (a.z - b[2]).abs() < tol
}

/// The tool tip at the end of every move.
pub(crate) fn tips(p: &Program) -> Vec<[f64; 3]> {
    p.moves
        .iter()
        .map(|m| [m.end.tip.x, m.end.tip.y, m.end.tip.z])
        .collect()
}

/// The warnings of a program read by Fanuc rules (a 3-axis machine), as (line, message).
pub(crate) fn fanuc_warnings(src: &str) -> Vec<(u32, String)> {
    use swarf_path::gcode::{GcodeDialect, GcodeOptions};
    use swarf_path::load::{read_program_str, ReadOptions};
    let p = read_program_str(
        src,
        "fanuc.nc",
        swarf_path::Machine::three_axis(),
        &ReadOptions {
            gcode: GcodeOptions::default().with_dialect(GcodeDialect::Fanuc),
            ..ReadOptions::default()
        },
    )
    .unwrap();
    p.warnings
        .into_iter()
        .map(|w| (w.line, w.message))
        .collect()
}

/// swarf's canonical print of G-code `src` read with `opts`, as `swarf path --canonical`
/// prints it, and the error that stopped it, if any.
pub(crate) fn canonical(src: &str, opts: &GcodeOptions) -> (String, Option<PathError>) {
    let mut pr = CanonicalPrinter::new(Vec::new());
    let r = read_gcode(src, "t.ngc", opts, &mut pr);
    let out = String::from_utf8(pr.finish().unwrap()).unwrap();
    (out, r.err())
}

/// An rs274 listing written into a test (one call a line, indented as the test likes) as the
/// canonical printer prints it.
pub(crate) fn listing(expected: &str) -> String {
    expected
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .map(|l| format!(" {l}\n"))
        .collect()
}
