//! The adaptive sampling (each sample's side guessed from its nearest ray, the probe only
//! around the side changes, grown until the guesses no longer touch the boundary) gives the
//! same engagement as probing every sample, on programs that exercise every kind of boundary:
//! slots, walls, arcs, a ramp, a plate only a shank reaches, 3+2, a 5-axis sweep, a finishing
//! raster over a wavy surface, and 5 cutter shapes. (Probing only the first ring of samples
//! around the guessed boundary, without the growth, fails it.)

mod common;

use common::*;
use swarf_engage::{EngageOptions, Engagement};
use swarf_tool::Cutter;

fn both(
    text: &str,
    file: &str,
    min: [f64; 3],
    max: [f64; 3],
    cutter: Cutter,
) -> (Vec<Engagement>, Vec<Engagement>) {
    let p = program(text, file);
    let mut fast_stock = block(min, max, 0.1);
    let mut slow_stock = block(min, max, 0.1);
    let t = std::time::Instant::now();
    let fast = run(
        &p,
        cutter.clone(),
        &mut fast_stock,
        EngageOptions::default().with_step(0.7),
    );
    let t_fast = t.elapsed().as_secs_f64();
    let t = std::time::Instant::now();
    let slow = run(
        &p,
        cutter,
        &mut slow_stock,
        EngageOptions::default()
            .with_step(0.7)
            .with_exhaustive(true),
    );
    println!(
        "{file}: adaptive {t_fast:.3} s, exhaustive {:.3} s",
        t.elapsed().as_secs_f64()
    );
    (fast, slow)
}

fn same(fast: &[Engagement], slow: &[Engagement], what: &str) {
    assert_eq!(fast.len(), slow.len(), "{what}");
    let mut engaged = 0;
    for (a, b) in fast.iter().zip(slow) {
        let tol = 1e-9 * b.area_mm2.max(1.0);
        assert!(
            (a.area_mm2 - b.area_mm2).abs() <= tol,
            "{what} location {}: {} vs {}",
            a.location,
            a.area_mm2,
            b.area_mm2
        );
        assert!(
            (a.ap_mm - b.ap_mm).abs() <= 1e-9,
            "{what} location {}",
            a.location
        );
        assert_eq!(
            a.discs.len(),
            b.discs.len(),
            "{what} location {}",
            a.location
        );
        for (x, y) in a
            .discs
            .iter()
            .zip(&b.discs)
            .chain(a.bottom.iter().zip(&b.bottom))
        {
            assert_eq!(x.at_mm, y.at_mm);
            assert_eq!(
                x.intervals.len(),
                y.intervals.len(),
                "{what} location {} z {}",
                a.location,
                x.at_mm
            );
            for (p, q) in x.intervals.iter().zip(&y.intervals) {
                assert!(
                    (p.start_deg - q.start_deg).abs() < 1e-9
                        && (p.end_deg - q.end_deg).abs() < 1e-9
                );
            }
        }
        engaged += usize::from(b.is_engaged());
    }
    println!(
        "{what}: {} locations, {engaged} engaged, identical",
        fast.len()
    );
    assert!(engaged > 0, "{what}: nothing engaged, nothing compared");
}

/// Name, program, stock corners, cutter.
type Case = (&'static str, String, [f64; 3], [f64; 3], Cutter);

#[test]
fn adaptive_sampling_changes_nothing() {
    let block_min = [0.0, 0.0, -10.0];
    let cases: Vec<Case> = vec![
        (
            "slot",
            "G21 G90\nG0 X-10 Y10 Z-5\nG1 X50 F600\n".into(),
            block_min,
            [40.0, 20.0, 0.0],
            Cutter::flat(10.0).unwrap(),
        ),
        (
            "wall",
            "G21 G90\nG0 X-10 Y0 Z-5\nG1 X50 F600\n".into(),
            [0.0, 3.0, -10.0],
            [40.0, 20.0, 0.0],
            Cutter::bull(10.0, 2.0).unwrap(),
        ),
        (
            "arc",
            "G21 G90\nG0 X-12 Y10 Z-4\nG1 X0 F600\nG2 X20 Y10 I10 J0\nG3 X40 Y10 I10 J0\n".into(),
            block_min,
            [40.0, 20.0, 0.0],
            Cutter::ball(8.0).unwrap(),
        ),
        (
            "ramp",
            "G21 G90\nG0 X-5 Y10 Z1\nG1 X25 Z-2 F600\n".into(),
            block_min,
            [30.0, 20.0, 0.0],
            Cutter::bull(10.0, 2.0).unwrap(),
        ),
        (
            "taper",
            "G21 G90\nG0 X-10 Y10 Z-3\nG1 X50 Y14 Z-4 F600\n".into(),
            block_min,
            [40.0, 20.0, 0.0],
            Cutter::taper_ball(6.0, 5.0).unwrap(),
        ),
        (
            "plunge",
            "G21 G90\nG0 X20 Y10 Z2\nG1 Z-4 F100\nG1 X30\n".into(),
            block_min,
            [40.0, 20.0, 0.0],
            Cutter::flat(10.0).unwrap(),
        ),
        // A plate 0.25 mm thick that only the shank's circles reach (the ball's equator at its
        // underside): the samples the column map lets go unguessed (`ColumnTops`) must not
        // include them — with a margin 0.8 mm short it does, and nothing is engaged.
        (
            "plate at the shank",
            "G21 G90\nG0 X-10 Y10 Z-5.25\nG1 X50 F600\n".into(),
            [0.0, 0.0, -0.25],
            [40.0, 20.0, 0.0],
            Cutter::ball(10.0).unwrap(),
        ),
    ];
    for (name, text, min, max, cutter) in cases {
        let (fast, slow) = both(&text, &format!("{name}.ngc"), min, max, cutter);
        same(&fast, &slow, name);
    }
    // 3+2 and a 5-axis sweep (the axis turning while the tip moves).
    let t = 20f64.to_radians();
    let (i, k) = (t.sin(), t.cos());
    let tilted = format!(
        "UNITS/MM\nRAPID\nGOTO/20,-20,20,{i},0,{k}\nRAPID\nGOTO/20,-20,-3,{i},0,{k}\nFEDRAT/600\nGOTO/20,60,-3,{i},0,{k}\n"
    );
    let (fast, slow) = both(
        &tilted,
        "tilted.apt",
        block_min,
        [40.0, 40.0, 0.0],
        Cutter::flat(10.0).unwrap(),
    );
    same(&fast, &slow, "3+2");
    let sweep = "UNITS/MM\nRAPID\nGOTO/-6,20,-2,0,0,1\nFEDRAT/600\nGOTO/8,20,-2,0.1,0,0.9949874\n";
    let (fast, slow) = both(
        sweep,
        "sweep.apt",
        block_min,
        [20.0, 40.0, 0.0],
        Cutter::ball(10.0).unwrap(),
    );
    same(&fast, &slow, "5-axis");
    // A finishing raster over a wavy surface, after a roughing pass left steps.
    let text = swarf_engage::bench::finishing_gcode(80);
    let (fast, slow) = both(
        &text,
        "finish.ngc",
        [0.0, 0.0, 0.0],
        [120.0, 120.0, 50.0],
        Cutter::ball(10.0).unwrap(),
    );
    same(&fast, &slow, "finishing raster");
}
