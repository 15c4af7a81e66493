//! The engagement does not depend on how many threads compute it: every location's sections
//! (the samples, the probes, the integration, the stock's cut) gather their results in order.
//! Checked on pools of one, two and three threads, to the last bit of every field, on a
//! finishing raster beside uncut walls and on a 5-axis sweep.

mod common;

use common::*;
use swarf_engage::{EngageOptions, Engagement};
use swarf_tool::Cutter;

fn on_threads(
    threads: usize,
    text: &str,
    file: &str,
    max: [f64; 3],
    cutter: &Cutter,
) -> Vec<Engagement> {
    swarf_testdata::on_threads(threads, || {
        let mut stock = block([0.0, 0.0, 0.0], max, 0.1);
        run(
            &program(text, file),
            cutter.clone(),
            &mut stock,
            EngageOptions::default().with_step(0.7),
        )
    })
}

fn assert_same_for_every_thread_count(text: &str, file: &str, max: [f64; 3], cutter: Cutter) {
    let one = on_threads(1, text, file, max, &cutter);
    assert!(
        one.iter().filter(|e| e.area_mm2 > 1.0).count() > 10,
        "{file} engages"
    );
    for threads in [2, 3] {
        let many = on_threads(threads, text, file, max, &cutter);
        assert_eq!(one.len(), many.len());
        for (a, b) in one.iter().zip(&many) {
            // `==` on every field, and the area's bits (`==` would let −0 pass for +0).
            assert!(a == b, "{file}, {threads} threads, location {}", a.location);
            assert_eq!(a.area_mm2.to_bits(), b.area_mm2.to_bits());
        }
    }
}

#[test]
fn a_finishing_raster_engages_the_same_on_one_two_and_three_threads() {
    assert_same_for_every_thread_count(
        &swarf_engage::bench::finishing_gcode(60),
        "finish.ngc",
        [120.0, 120.0, 50.0],
        Cutter::ball(10.0).unwrap(),
    );
}

#[test]
fn a_five_axis_sweep_engages_the_same_on_one_two_and_three_threads() {
    // The tool axis turns by 20° while the tip crosses the block.
    let text =
        "UNITS/MM\nRAPID\nGOTO/-6,20,42,0,0,1\nFEDRAT/600\nGOTO/34,20,42,0.34202,0,0.93969\n";
    assert_same_for_every_thread_count(
        text,
        "sweep.apt",
        [40.0, 40.0, 45.0],
        Cutter::bull(10.0, 2.0).unwrap(),
    );
}
