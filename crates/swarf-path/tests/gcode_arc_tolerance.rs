//! LinuxCNC's arc end-radius tolerance (`arc_data_ijk`): an arc is rejected when its end radius
//! differs from its start radius by more than 100 × the absolute tolerance, or by more than the
//! absolute tolerance *and* 0.1 % — the absolute tolerance being 2 × 0.001 × √2 in or
//! 2 × 0.01 × √2 mm. LinuxCNC's `good-arc` tests sit at 0.99 of each limit; the same programs at
//! 1.01 of it must fail.

use swarf_path::canon::Recorder;
use swarf_path::gcode::{read_gcode, GcodeOptions};

fn read(src: &str) -> Result<(), swarf_path::PathError> {
    read_gcode(
        src,
        "arc.ngc",
        &GcodeOptions::default(),
        &mut Recorder::default(),
    )
}

#[test]
fn arcs_at_099_of_the_tolerance_pass_and_at_101_fail() {
    for (units, x, i, dev, scale) in [
        // small: only the absolute tolerance counts (the relative error is above 0.1 %).
        ("g21", 50.0, 25.0, -0.01, 1.0),
        ("g20", 5.0, 2.5, -0.001, 1.0),
        // big: the end radius is off by nearly 100 × the absolute tolerance, under 0.1 %.
        ("g21", 6000.0, 3000.0, 0.01, 100.0),
        ("g20", 600.0, 300.0, 0.001, 100.0),
    ] {
        for (k, ok) in [(0.99, true), (1.01, false)] {
            let src = format!(
                "{units}\nf1\ng0x0y0z0\ng2 x{x} y0 i[{i} + [{scale} * [{dev} * {k} * sqrt[2]]]]\nm2\n"
            );
            let r = read(&src);
            assert_eq!(r.is_ok(), ok, "{src}: {r:?}");
            if let Err(e) = r {
                assert!(e.message.contains("radius to end of arc differs"), "{e}");
            }
        }
    }
}
