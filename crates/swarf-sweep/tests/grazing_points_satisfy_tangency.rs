//! Grazing points of every piece type satisfy N·V = 0 to 1e-12 relative and lie on the cutter
//! surface, under random 3-axis, 3+2 and 5-axis (ω ≠ 0) motions; and the closed forms find every
//! root that a dense scan of the tangency function finds.

mod common;

use common::{cutters, Rng};
use swarf_geom::math::Vec3;
use swarf_sweep::fold::{piece_distance, whole_tool_pieces};
use swarf_sweep::grazing::Local;
use swarf_sweep::{grazing_points, tangency, Harmonic, MotionState};
use swarf_tool::{AnyPiece, Piece};

fn motions(rng: &mut Rng) -> Vec<(&'static str, MotionState)> {
    let mut v = Vec::new();
    for _ in 0..12 {
        let tip = Vec3::new(
            rng.range(-50.0, 50.0),
            rng.range(-50.0, 50.0),
            rng.range(-20.0, 20.0),
        );
        let speed = rng.range(0.1, 100.0);
        // 3-axis: vertical axis, any feed direction.
        v.push((
            "3-axis",
            MotionState::translation(tip, Vec3::Z, rng.unit() * speed),
        ));
        // 3+2: tilted fixed axis.
        let mut a = rng.unit();
        a.z = a.z.abs() + 0.3;
        v.push(("3+2", MotionState::translation(tip, a, rng.unit() * speed)));
        // 5-axis: turning axis.
        let w = rng.unit().cross(a.normalize()) * rng.range(0.05, 2.0);
        v.push(("5-axis", MotionState::new(tip, a, rng.unit() * speed, w)));
    }
    v
}

#[test]
fn grazing_points_are_on_the_surface_with_zero_tangency() {
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let mut counted = [0usize; 5];
    for (name, cutter) in cutters() {
        let pieces = whole_tool_pieces(&cutter);
        let reach = cutter.overall_length().hypot(cutter.max_diameter());
        for (kind, st) in motions(&mut rng) {
            let scale = st.v_tip.length() + st.omega.length() * reach;
            let set = grazing_points(&pieces, &st, 33);
            for g in &set.points {
                let f = tangency(&st, g.point, g.normal);
                assert!(
                    f.abs() <= 1e-12 * scale,
                    "{name} {kind} piece {} ({}): N·V = {f:e}, scale {scale}",
                    g.piece,
                    pieces[g.piece].shape_name()
                );
                assert!((g.normal.length() - 1.0).abs() < 1e-12);
                let d = piece_distance(&pieces[g.piece], st.tip, st.axis, g.point);
                assert!(
                    d.abs() < 1e-11 * reach,
                    "{name} {kind}: {d:e} off the surface"
                );
                // Inside the piece's own band.
                let z = (g.point - st.tip).dot(st.axis);
                let (z0, z1) = pieces[g.piece].z_range();
                assert!(
                    z >= z0 - 1e-9 && z <= z1 + 1e-9,
                    "{name} {kind}: z {z} not in [{z0}, {z1}]"
                );
                let slot = match pieces[g.piece] {
                    AnyPiece::Disc(_) => 0,
                    AnyPiece::Cone(_) => 1,
                    AnyPiece::Cylinder(_) => 2,
                    AnyPiece::Torus(_) => 3,
                    AnyPiece::Sphere(_) => 4,
                };
                counted[slot] += 1;
            }
        }
    }
    assert!(
        counted.iter().all(|&c| c > 100),
        "every piece type exercised: {counted:?}"
    );
}

/// On every parallel of the canal (cone, sphere) and pipe (cylinder) pieces, the closed form
/// gives exactly as many points as the tangency changes sign on a dense scan.
#[test]
fn closed_forms_find_every_root() {
    let mut rng = Rng(42);
    for (name, cutter) in cutters() {
        let pieces = cutter.pieces();
        for (kind, st) in motions(&mut rng) {
            let set = grazing_points(pieces, &st, 17);
            let local = Local::of(&st);
            for (i, p) in pieces.iter().enumerate() {
                if !matches!(
                    p,
                    AnyPiece::Cone(_) | AnyPiece::Sphere(_) | AnyPiece::Cylinder(_)
                ) {
                    continue;
                }
                for j in 0..17 {
                    let s = j as f64 / 16.0;
                    let pp = p.profile_point(s);
                    if pp.x <= 0.0 {
                        continue;
                    }
                    let h = Harmonic::on_parallel(pp, p.profile_normal(s), local.v, local.w);
                    let n = 3_000;
                    let changes = (0..n)
                        .filter(|&q| {
                            let t0 = std::f64::consts::TAU * q as f64 / n as f64;
                            let t1 = std::f64::consts::TAU * (q + 1) as f64 / n as f64;
                            h.eval(t0).signum() != h.eval(t1).signum()
                        })
                        .count();
                    let found = set
                        .points
                        .iter()
                        .filter(|g| g.piece == i && (g.s - s).abs() < 1e-12)
                        .count();
                    // A touch (double root) may show as 0 changes; the scan cannot see it.
                    let touch = (h.max().abs().min(h.min().abs())) < 1e-6 * h.a.hypot(h.b);
                    if !touch {
                        assert_eq!(found, changes, "{name} {kind} piece {i} s {s}: {h:?}");
                    }
                }
            }
        }
    }
}

#[test]
fn plunge_makes_whole_parallels_graze_on_the_cylinder() {
    let c = swarf_tool::Cutter::flat(10.0).unwrap();
    let st = MotionState::translation(Vec3::ZERO, Vec3::Z, -Vec3::Z * 5.0);
    let set = grazing_points(c.pieces(), &st, 9);
    let cyl = c
        .pieces()
        .iter()
        .position(|p| matches!(p, AnyPiece::Cylinder(_)))
        .unwrap();
    assert_eq!(set.whole.iter().filter(|w| w.0 == cyl).count(), 9);
    // The bottom rim is the whole grazing set of the bottom: every sampled rim point.
    assert!(set.points.iter().filter(|g| g.edge).count() >= 9);
}
