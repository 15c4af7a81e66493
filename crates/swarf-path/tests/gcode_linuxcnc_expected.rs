//! The canonical motion printed for LinuxCNC's own interpreter test programs equals, byte for
//! byte, the motion lines of the `.expected` output LinuxCNC produced (third-party data from
//! `SWARF_TEST_DATA`: the test skips, saying so, without it).

use swarf_path::canonical::CanonicalPrinter;
use swarf_path::gcode::{read_gcode, GcodeOptions};

fn motion_lines(expected: &str) -> String {
    expected
        .lines()
        .filter(|l| {
            l.starts_with(" N..... STRAIGHT_TRAVERSE(")
                || l.starts_with(" N..... STRAIGHT_FEED(")
                || l.starts_with(" N..... ARC_FEED(")
        })
        .map(|l| format!("{l}\n"))
        .collect()
}

#[test]
fn g17_g99_g81_canned_cycles_match_linuxcnc() {
    let name = "linuxcnc_interp_g17-g99-g81";
    let Some([ngc, expected]) = swarf_testdata::paths([
        format!("gcode/{name}.ngc").as_str(),
        format!("gcode/{name}.expected").as_str(),
    ]) else {
        return;
    };
    let ngc = std::fs::read_to_string(ngc).unwrap();
    let expected = std::fs::read_to_string(expected).unwrap();
    let mut printer = CanonicalPrinter::new(Vec::new());
    read_gcode(
        &ngc,
        "g17-g99-g81.ngc",
        &GcodeOptions::default(),
        &mut printer,
    )
    .unwrap();
    let got = String::from_utf8(printer.finish().unwrap()).unwrap();
    let want = motion_lines(&expected);
    assert!(
        want.lines().count() > 30,
        "the expected file has the motion lines"
    );
    assert_eq!(got, want);
}
