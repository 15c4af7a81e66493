//! Aras (2008) Table 5.2 reproduced: which pieces of the generic cutter have kinematically
//! feasible engagement sets CWE_K of positive area, over the feed-angle ranges of Table 5.1,
//! and Propositions 5.1/5.2 (ascending and horizontal motions engage the front face only,
//! descending ones the back face too).

mod common;

use swarf_geom::math::Vec3;
use swarf_sweep::{
    aras_angles, feasible_contact, feed_range, motion_class, Feasibility, FeedRange, MotionClass,
    MotionState, PieceRole,
};

/// Table 5.2: (range, upper cone, corner torus, lower cone), true = CWE_K, false = { }.
const TABLE_5_2: [(FeedRange, bool, bool, bool); 9] = [
    (FeedRange::F1, false, false, false),
    (FeedRange::F2, true, true, false),
    (FeedRange::F3, true, true, false),
    (FeedRange::F4, true, true, true),
    (FeedRange::F5, true, true, true),
    (FeedRange::B1, true, true, true),
    (FeedRange::B2, true, true, true),
    (FeedRange::B3, true, true, true),
    (FeedRange::B4, true, true, true),
];

/// Feed angles (degrees) in each range for Aras angles α, β (degrees): the boundary itself for
/// the point ranges, three interior angles for the open ones.
fn angles(range: FeedRange, a: f64, b: f64) -> Vec<f64> {
    let open = |lo: f64, hi: f64| {
        vec![
            lo + 0.01 * (hi - lo),
            0.5 * (lo + hi),
            hi - 0.01 * (hi - lo),
        ]
    };
    match range {
        FeedRange::F1 => vec![b],
        FeedRange::F2 => open(b, a),
        FeedRange::F3 => vec![a],
        FeedRange::F4 => open(a, 90.0),
        FeedRange::F5 => vec![90.0],
        FeedRange::B1 => open(90.0, 180.0 - a),
        FeedRange::B2 => vec![180.0 - a],
        FeedRange::B3 => open(180.0 - a, 180.0 - b),
        FeedRange::B4 => vec![180.0 - b],
        _ => unreachable!(),
    }
}

#[test]
fn table_5_2_is_reproduced() {
    let cutter = common::generic();
    let pieces = cutter.pieces();
    let (alpha, beta) = aras_angles(pieces).unwrap();
    assert!((alpha.to_degrees() - 70.0).abs() < 1e-9 && (beta.to_degrees() - 10.0).abs() < 1e-9);
    let (a, b) = (alpha.to_degrees(), beta.to_degrees());
    for (range, upper, torus, lower) in TABLE_5_2 {
        for psi in angles(range, a, b) {
            let p = psi.to_radians();
            assert_eq!(feed_range(p, alpha, beta, 1e-9), range, "ψ = {psi}");
            // Any direction across the axis: the table must not depend on it.
            for phase in [0.0f64, 1.0, 2.5] {
                let f = Vec3::new(p.sin() * phase.cos(), p.sin() * phase.sin(), p.cos()) * 250.0;
                let st = MotionState::translation(Vec3::new(3.0, -2.0, 7.0), Vec3::Z, f);
                let eng = feasible_contact(pieces, &st, 129);
                let has = |role| {
                    eng.iter()
                        .filter(|e| e.role == role)
                        .any(|e| e.feasibility == Feasibility::Area)
                };
                let row = (
                    has(PieceRole::UpperCone),
                    has(PieceRole::Corner),
                    has(PieceRole::LowerCone),
                );
                assert_eq!(row, (upper, torus, lower), "{range:?} ψ = {psi}°: {eng:#?}");
                // Propositions 5.1 and 5.2.
                let class = motion_class(&st, 1e-9);
                // The top cap closes the cutting part under the shank: not a cutting surface.
                let cutting = || {
                    eng.iter()
                        .filter(|e| e.role != PieceRole::Top && e.feasibility == Feasibility::Area)
                };
                let back = cutting().any(|e| e.back);
                let front = cutting().any(|e| e.front);
                match class {
                    MotionClass::Ascending | MotionClass::Horizontal => {
                        assert!(!back, "{range:?} ψ = {psi}°: CWE_K on the back face");
                        assert_eq!(front, upper || torus || lower);
                    }
                    MotionClass::Descending => assert!(back && front, "{range:?} ψ = {psi}°"),
                    other => panic!("{other:?}"),
                }
            }
        }
    }
}

#[test]
fn excluded_ranges_and_degenerate_faces() {
    let cutter = common::generic();
    let (alpha, beta) = aras_angles(cutter.pieces()).unwrap();
    let p = 0.5 * beta;
    assert_eq!(feed_range(p, alpha, beta, 1e-9), FeedRange::BelowF1);
    // ψ < β: nothing can engage (the side's top circle leads, Aras).
    let st = MotionState::translation(Vec3::ZERO, Vec3::Z, Vec3::new(p.sin(), 0.0, p.cos()));
    assert!(feasible_contact(cutter.pieces(), &st, 65)
        .iter()
        .all(|e| e.role == PieceRole::Top || e.feasibility != Feasibility::Area));
    // A flat end mill in horizontal motion: the bottom slides on the floor it leaves.
    let flat = swarf_tool::Cutter::flat(10.0).unwrap();
    let st = MotionState::translation(Vec3::ZERO, Vec3::Z, Vec3::X);
    let eng = feasible_contact(flat.pieces(), &st, 33);
    let bottom = eng.iter().find(|e| e.role == PieceRole::Bottom).unwrap();
    assert_eq!(bottom.feasibility, Feasibility::Sliding);
    let side = eng.iter().find(|e| e.role == PieceRole::UpperCone).unwrap();
    assert!(side.feasibility == Feasibility::Area && side.front && !side.back);
    // A plunge: the bottom engages, the cylinder slides.
    let st = MotionState::translation(Vec3::ZERO, Vec3::Z, -Vec3::Z);
    let eng = feasible_contact(flat.pieces(), &st, 33);
    assert_eq!(
        eng.iter()
            .find(|e| e.role == PieceRole::Bottom)
            .unwrap()
            .feasibility,
        Feasibility::Area
    );
    assert_eq!(
        eng.iter()
            .find(|e| e.role == PieceRole::UpperCone)
            .unwrap()
            .feasibility,
        Feasibility::Sliding
    );
    // 5-axis: classified apart.
    let st = MotionState::new(Vec3::ZERO, Vec3::Z, Vec3::X, Vec3::Y);
    assert_eq!(motion_class(&st, 1e-9), MotionClass::FiveAxis);
}
