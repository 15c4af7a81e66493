//! Self-intersecting sweeps are reported, not silently meshed: the envelope of an arc tighter
//! than the tool and of a 5-axis swing about a point inside the tool folds into its own sweep;
//! wide arcs, straight lines and gentle 5-axis moves do not.

mod common;

use swarf_envelope::{envelope, EnvelopeOptions};
use swarf_sweep::fold_check;
use swarf_tool::Cutter;

#[test]
fn arcs_tighter_than_the_tool_fold() {
    let ball = Cutter::ball(10.0).unwrap();
    let tight = common::gcode("G21 G90\nG0 X0 Y0 Z0\nG1 X0 F100\nG2 X4 Y0 I2 J0\n");
    let hit = fold_check(&tight, 2, &ball).expect("radius 2 arc with a radius 5 ball folds");
    assert_eq!((hit.move_index, hit.line), (2, 4));
    assert!(
        hit.fold_ratio < 0.0 && hit.message.contains("test.ngc:4"),
        "{hit:?}"
    );
    let wide = common::gcode("G21 G90\nG0 X0 Y0 Z0\nG1 X0 F100\nG2 X60 Y0 I30 J0\n");
    assert_eq!(fold_check(&wide, 2, &ball), None);
    let line = common::gcode("G21 G90\nG0 X0 Y0 Z0\nG1 X30 Y4 Z-2 F100\n");
    assert_eq!(fold_check(&line, 1, &ball), None);
}

#[test]
fn five_axis_swing_about_a_point_inside_the_ball_folds_and_is_reported() {
    let ball = Cutter::ball(10.0).unwrap();
    // Pivot on the axis between the tip and the ball's centre (2.5 mm up): the centre swings
    // on a circle of radius 2.5 mm, tighter than the 5 mm ball.
    let (zp, phi) = (2.5, 40f64.to_radians());
    let swing = common::apt(&format!(
        "GOTO/0,0,0,0,0,1\nGOTO/{},0,{},{},0,{}\n",
        -zp * phi.sin(),
        zp - zp * phi.cos(),
        phi.sin(),
        phi.cos()
    ));
    let hit = fold_check(&swing, 0, &ball).expect("a swing about a point inside the ball folds");
    assert!(hit.fold_ratio < 0.0 && hit.piece == "sphere", "{hit:?}");
    // The envelope is still the exact union (closed mesh), and the report names the move.
    let env = envelope(
        &swing,
        &common::tools(&ball),
        0..1,
        &EnvelopeOptions::default()
            .with_resolution(0.6)
            .with_tolerance(0.05),
    )
    .unwrap();
    assert!(env.mesh.is_closed());
    assert_eq!(env.report.self_intersections.len(), 1);
    assert_eq!(env.report.self_intersections[0].move_index, 0);
    // The same turn about a pivot 10 mm below the tip (centre path radius 15 mm) does not fold.
    let zp = -10.0;
    let wide = common::apt(&format!(
        "GOTO/0,0,0,0,0,1\nGOTO/{},0,{},{},0,{}\n",
        -zp * phi.sin(),
        zp - zp * phi.cos(),
        phi.sin(),
        phi.cos()
    ));
    assert_eq!(fold_check(&wide, 0, &ball), None);
    // Nor does a gentle lean while feeding forward.
    let flat = Cutter::flat(6.0).unwrap();
    let gentle = common::apt("GOTO/0,0,0,0,0,1\nGOTO/40,0,0,0.0998334,0,0.9950042\n");
    assert_eq!(fold_check(&gentle, 0, &flat), None);
    assert_eq!(fold_check(&gentle, 0, &ball), None);
}
