//! 5-axis moves with answers known in closed form (or by 1-D quadrature of a closed-form
//! integrand), the convergence in the tolerance, and invariants.
//!
//! * A hemispherical ball end mill (cutting part = the lower half ball, no shank) whose centre
//!   sits on the A axis of a rotary table while A turns by θ: in the part frame the tool turns
//!   about its ball centre (the tip follows a circle: no TCP), and the half balls sweep the
//!   ball minus a wedge of dihedral angle π − θ, volume `(4/3)πR³·(π + θ)/(2π)`.
//! * A flat end mill (cutting part only) pivoting about its tip by θ (CL data: fixed tip,
//!   slerped axis): each plane across the pivot axis cuts the rectangle `|x| ≤ c(y), 0 ≤ z ≤ H`
//!   turned about the tip; the union of the turned copies of a star-shaped set about the pivot
//!   has the radial function `max` over the turn, so its area is `½∫ρ_U(ψ)² dψ` and the volume
//!   the integral of that over `y`.
//!
//! The simulated removal may differ from the exact sweep by the tolerance ε times the area of
//! the removed region's boundary (every boundary point is within ε of the true one) plus the ray
//! grid's own error (at most [`GRID_REL`] of the volume at these resolutions, as for the 3-axis
//! cases in `removed_volume_exact.rs`).

use std::f64::consts::PI;
use swarf_geom::math::Vec3;
use swarf_path::{Axes, AxisSource, FeedMode, Machine, Move, MoveKind, Pose, Program};
use swarf_stock::TriDexel;
use swarf_sweep::ToolShape;
use swarf_tool::{Cutter, CutterKind, CutterOptions};

/// Ray grid resolution, mm.
const H: f64 = 0.1;

/// Relative volume error the ray grid itself may contribute at resolution [`H`] (the 3-axis
/// cases of `removed_volume_exact.rs` stay within it at h = 0.1 mm; at a tolerance of 0.0025 mm
/// these two cases come within 0.061 % and 0.006 % of the exact volume).
const GRID_REL: f64 = 0.003;

fn one_move(
    machine: Machine,
    source: AxisSource,
    start: Pose,
    end: Pose,
    j0: Axes,
    j1: Axes,
) -> Program {
    Program {
        moves: vec![Move {
            kind: MoveKind::Linear,
            start,
            end,
            start_joints: j0,
            end_joints: j1,
            feed: 100.0,
            feed_mode: FeedMode::PerMinute,
            spindle_rpm: 1000.0,
            spindle_dir: swarf_path::SpindleDir::Clockwise,
            tool: 1,
            file: 0,
            line: 7,
            axis_source: source,
            tcp: machine.tcp,
            rotary_feed_combined: None,
        }],
        files: vec!["exact".into()],
        machine,
        axis_source: source,
        ..Program::default()
    }
}

/// Only the cutting part: overall length = cutting height.
fn bare(kind: CutterKind, nums: &[f64], h: f64) -> Cutter {
    Cutter::named(
        kind,
        nums,
        &CutterOptions {
            flute_length: Some(h),
            overall_length: Some(h),
            ..CutterOptions::default()
        },
    )
    .unwrap()
}

/// The hemisphere turning about its centre on a table about X: `(program, exact volume,
/// boundary area)`.
fn hemisphere_case(r: f64, theta_deg: f64) -> (Program, Cutter, f64, f64) {
    let mach = Machine::from_name("4axis-a").unwrap();
    // The tip R below the table axis (through the origin): the ball centre is on the axis.
    let j0 = Axes {
        z: -r,
        ..Axes::default()
    };
    let j1 = Axes { a: theta_deg, ..j0 };
    let p = one_move(
        mach.clone(),
        AxisSource::Machine,
        mach.pose(&j0),
        mach.pose(&j1),
        j0,
        j1,
    );
    let th = theta_deg.to_radians();
    let exact = 4.0 / 3.0 * PI * r.powi(3) * (PI + th) / (2.0 * PI);
    // Sphere part plus the two half-disc faces of the wedge.
    let area = 4.0 * PI * r * r * (PI + th) / (2.0 * PI) + PI * r * r;
    (p, bare(CutterKind::Ball, &[2.0 * r], r), exact, area)
}

fn removed(p: &Program, cutter: &Cutter, lo: Vec3, hi: Vec3, h: f64, tol: f64) -> (f64, u64, f64) {
    let mut s = TriDexel::from_box(lo, hi, h).unwrap();
    let v0 = s.volume();
    let cut = s.cut_move(p, 0, &ToolShape::new(cutter), tol).unwrap();
    assert_eq!(cut.non_cutting.removed_length, [0.0; 3], "no shank");
    assert!(cut.error_bound_mm <= tol);
    (v0 - s.volume(), cut.sub_moves, cut.error_bound_mm)
}

#[test]
fn hemisphere_turning_about_its_centre_removes_ball_minus_wedge() {
    let (r, theta) = (5.0, 60.0f64);
    let (p, cutter, exact, area) = hemisphere_case(r, theta);
    assert!(p.is_five_axis(&p.moves[0]));
    let (lo, hi) = (Vec3::splat(-6.0), Vec3::splat(6.0));
    println!("hemisphere R {r} turning {theta}° about its centre: exact {exact:.4} mm³");
    println!(
        "{:>9} {:>6} {:>9} {:>11} {:>9}",
        "tol", "subs", "bound", "removed", "rel err"
    );
    let mut prev: Option<(f64, f64)> = None;
    for tol in [0.04, 0.01] {
        let (v, n, eps) = removed(&p, &cutter, lo, hi, H, tol);
        let rel = (v - exact) / exact;
        println!("{tol:>9} {n:>6} {eps:>9.5} {v:>11.4} {rel:>9.5}");
        assert!(
            (v - exact).abs() <= eps * area + GRID_REL * exact,
            "tol {tol}: removed {v}, exact {exact}"
        );
        // Tightening the tolerance moves the result by less than the two tolerances allow.
        if let Some((v_prev, tol_prev)) = prev {
            assert!(
                (v - v_prev).abs() <= (tol + tol_prev) * area,
                "{v} vs {v_prev}"
            );
        }
        prev = Some((v, tol));
    }
}

/// Area of the union of the rectangle `|x| ≤ c, 0 ≤ z ≤ hh` turned about the origin by every
/// angle in `[0, theta]`, by `½∫ρ_U² dψ` (Simpson, kinks resolved by the fine step).
fn turned_rectangle_area(c: f64, hh: f64, theta: f64) -> f64 {
    let corner = hh.atan2(c);
    let rho = |psi: f64| -> f64 {
        if !(0.0..=PI).contains(&psi) {
            0.0
        } else if psi <= corner || psi >= PI - corner {
            c / psi.cos().abs()
        } else {
            hh / psi.sin()
        }
    };
    let rho_u = |psi: f64| -> f64 {
        let mut m = rho(psi).max(rho(psi - theta));
        for k in [corner, PI - corner] {
            if psi - theta <= k && k <= psi {
                m = m.max(c.hypot(hh));
            }
        }
        m
    };
    let n = 20_000;
    let (a, b) = (0.0, PI + theta);
    let step = (b - a) / n as f64;
    let mut sum = 0.0;
    for i in 0..=n {
        let w = if i == 0 || i == n {
            1.0
        } else if i % 2 == 1 {
            4.0
        } else {
            2.0
        };
        sum += w * rho_u(a + i as f64 * step).powi(2);
    }
    0.5 * sum * step / 3.0
}

#[test]
fn flat_end_mill_pivoting_about_its_tip() {
    let (d, hh, theta_deg) = (6.0, 12.0, 40.0f64);
    let r = d / 2.0;
    let th = theta_deg.to_radians();
    let cutter = bare(CutterKind::Flat, &[d], hh);
    let axis1 = Vec3::new(th.sin(), 0.0, th.cos());
    let p = one_move(
        Machine::three_axis(),
        AxisSource::Program,
        Pose {
            tip: Vec3::ZERO,
            axis: Vec3::Z,
        },
        Pose {
            tip: Vec3::ZERO,
            axis: axis1,
        },
        Axes::default(),
        Axes::default(),
    );
    // Volume: y = r·sin u, c = r·cos u.
    let n = 400;
    let mut exact = 0.0;
    for i in 0..=n {
        let u = -PI / 2.0 + PI * i as f64 / n as f64;
        let w = if i == 0 || i == n {
            1.0
        } else if i % 2 == 1 {
            4.0
        } else {
            2.0
        };
        let c = r * u.cos();
        exact += w * turned_rectangle_area(c, hh, th) * r * u.cos();
    }
    exact *= PI / n as f64 / 3.0;
    // Sanity of the quadrature: no turn gives the cylinder.
    let cyl: f64 = {
        let mut v = 0.0;
        for i in 0..=n {
            let u = -PI / 2.0 + PI * i as f64 / n as f64;
            let w = if i == 0 || i == n {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            v += w * turned_rectangle_area(r * u.cos(), hh, 0.0) * r * u.cos();
        }
        v * PI / n as f64 / 3.0
    };
    assert!((cyl - PI * r * r * hh).abs() < 1e-6 * cyl, "{cyl}");
    // Boundary area, generously: the cylinder's side and ends plus the two sector faces the
    // turn sweeps out of the plane of the axis.
    let area = 2.0 * PI * r * hh + 2.0 * PI * r * r + th * (r * r + hh * hh) * 2.0 + 2.0 * r * hh;
    let (lo, hi) = (Vec3::new(-4.0, -4.0, -3.0), Vec3::new(11.0, 4.0, 13.0));
    println!("flat d {d} h {hh} pivoting {theta_deg}° about its tip: exact {exact:.4} mm³");
    println!(
        "{:>9} {:>6} {:>9} {:>11} {:>9}",
        "tol", "subs", "bound", "removed", "rel err"
    );
    let mut prev: Option<(f64, f64)> = None;
    for tol in [0.05, 0.0125] {
        let (v, nsub, eps) = removed(&p, &cutter, lo, hi, H, tol);
        let rel = (v - exact) / exact;
        println!("{tol:>9} {nsub:>6} {eps:>9.5} {v:>11.4} {rel:>9.5}");
        assert!(
            (v - exact).abs() <= eps * area + GRID_REL * exact,
            "tol {tol}: removed {v}, exact {exact}"
        );
        if let Some((v_prev, tol_prev)) = prev {
            assert!(
                (v - v_prev).abs() <= (tol + tol_prev) * area,
                "{v} vs {v_prev}"
            );
        }
        prev = Some((v, tol));
    }
}

#[test]
fn volume_never_increases_and_a_second_pass_removes_nothing() {
    // Random 5-axis moves on a table-table machine, one after the other on one stock.
    let mach = Machine::from_name("table-bc").unwrap();
    let tool = ToolShape::new(&Cutter::taper_ball(6.0, 5.0).unwrap());
    let mut s = TriDexel::from_box(
        Vec3::new(-10.0, -10.0, -6.0),
        Vec3::new(10.0, 10.0, 2.0),
        0.4,
    )
    .unwrap();
    let mut v = s.volume();
    let mut seed = 7u64;
    let mut rnd = |a: f64, b: f64| {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        a + (b - a) * ((seed >> 11) as f64 / (1u64 << 53) as f64)
    };
    for _ in 0..4 {
        let rot = |b: f64, c: f64| Axes {
            b,
            c,
            ..Axes::default()
        };
        let (r0, r1) = (
            rot(rnd(-30.0, 30.0), rnd(-45.0, 45.0)),
            rot(rnd(-30.0, 30.0), rnd(-45.0, 45.0)),
        );
        let t0 = Vec3::new(rnd(-6.0, 6.0), rnd(-6.0, 6.0), rnd(-3.0, 0.0));
        let t1 = Vec3::new(rnd(-6.0, 6.0), rnd(-6.0, 6.0), rnd(-3.0, 0.0));
        let (j0, j1) = (mach.joints_for_tip(t0, &r0), mach.joints_for_tip(t1, &r1));
        let p = one_move(
            mach.clone(),
            AxisSource::Machine,
            mach.pose(&j0),
            mach.pose(&j1),
            j0,
            j1,
        );
        let cut = s.cut_move(&p, 0, &tool, 0.02).unwrap();
        let v1 = s.volume();
        assert!(v1 <= v + 1e-9 && v1 < v, "{v1} after {v}");
        assert!(cut.sub_moves > 1);
        let again = s.cut_move(&p, 0, &tool, 0.02).unwrap();
        let rem: f64 = again
            .cutting
            .removed_length
            .iter()
            .chain(&again.non_cutting.removed_length)
            .sum();
        assert!(rem <= 1e-9, "second pass removed {rem} mm of ray length");
        v = v1;
    }
}

/// Round tools (ball, bull-nose) turning while they move are cut as exact instances whose
/// spacing is set by a second-order bound (`swarf_sweep::five_axis`, "Instances"): the cuts
/// grow like `1/√T`, where constant-axis pieces (first order) grow like `1/T`. The removal
/// converges, and an instance never cuts outside the true sweep, so a finer tolerance never
/// removes less than a coarser one by more than the coarser one's gap over the boundary.
#[test]
fn round_tools_turning_need_cuts_growing_as_one_over_root_t() {
    let turn = 20f64.to_radians();
    let start = Pose {
        tip: Vec3::new(-1.5, 0.0, 0.0),
        axis: Vec3::Z,
    };
    let end = Pose {
        tip: Vec3::new(1.5, 0.0, 0.0),
        axis: Vec3::new(turn.sin(), 0.0, turn.cos()),
    };
    let p = one_move(
        Machine::three_axis(),
        AxisSource::Program,
        start,
        end,
        Axes::default(),
        Axes::default(),
    );
    let (lo, hi) = (Vec3::new(-12.0, -7.0, -1.0), Vec3::new(12.0, 7.0, 8.0));
    for cutter in [
        Cutter::ball(10.0).unwrap(),
        Cutter::bull(10.0, 2.0).unwrap(),
    ] {
        let block = TriDexel::from_box(lo, hi, 0.2).unwrap();
        let v0 = block.volume();
        let tool = ToolShape::new(&cutter);
        let mut runs = Vec::new();
        for tol in [0.01, 0.001, 0.0001] {
            let mut s = block.clone();
            let cut = s.cut_move(&p, 0, &tool, tol).unwrap();
            assert!(cut.error_bound_mm <= tol);
            runs.push((tol, cut.sub_moves, v0 - s.volume()));
        }
        println!("{cutter:?}: (tol, cuts, removed) {runs:?}");
        for w in runs.windows(2) {
            let ((t0, n0, v0), (_, n1, v1)) = (w[0], w[1]);
            // √10 ≈ 3.2 per decade (the pieces' 10 would fail).
            assert!(n1 as f64 <= 4.5 * n0 as f64, "{cutter:?}: {n0} → {n1} cuts");
            // The boundary of the removal is under 2000 mm² here.
            assert!(v1 >= v0 - t0 * 2000.0, "{cutter:?}: {v0} → {v1}");
        }
    }
}

/// A 5-axis move starting where the last one ended does not cut its first instance again (the
/// last move cut it); every ray ends exactly as when that instance is cut twice.
#[test]
fn the_shared_instance_of_chained_moves_is_cut_once() {
    let tilt = |deg: f64| {
        let t = deg.to_radians();
        Vec3::new(t.sin(), 0.0, t.cos())
    };
    let poses = [
        (Vec3::new(-3.0, 0.0, 0.0), tilt(0.0)),
        (Vec3::new(-1.0, 0.2, 0.3), tilt(8.0)),
        (Vec3::new(1.0, 0.5, 0.1), tilt(15.0)),
        (Vec3::new(3.0, 0.4, -0.2), tilt(12.0)),
    ];
    let mut p = one_move(
        Machine::three_axis(),
        AxisSource::Program,
        Pose {
            tip: poses[0].0,
            axis: poses[0].1,
        },
        Pose {
            tip: poses[1].0,
            axis: poses[1].1,
        },
        Axes::default(),
        Axes::default(),
    );
    for w in poses[1..].windows(2) {
        let mut m = p.moves[0];
        m.start = Pose {
            tip: w[0].0,
            axis: w[0].1,
        };
        m.end = Pose {
            tip: w[1].0,
            axis: w[1].1,
        };
        p.moves.push(m);
    }
    let (lo, hi) = (Vec3::new(-10.0, -7.0, -1.0), Vec3::new(10.0, 7.0, 6.0));
    for cutter in [Cutter::ball(8.0).unwrap(), Cutter::bull(10.0, 2.0).unwrap()] {
        let tool = ToolShape::new(&cutter);
        let mut once = TriDexel::from_box(lo, hi, 0.2).unwrap();
        let mut twice = once.clone();
        let (mut n_once, mut n_twice) = (0, 0);
        for i in 0..p.moves.len() {
            n_once += once.cut_move(&p, i, &tool, 1e-3).unwrap().sub_moves;
            // Uniting nothing forgets the last instance: every move cuts all of its own.
            twice.unite_swept(&[], &[]);
            n_twice += twice.cut_move(&p, i, &tool, 1e-3).unwrap().sub_moves;
        }
        assert!(n_once < n_twice, "{n_once} vs {n_twice} cuts");
        // To the corner walk's tolerance: a move's instances are cut together, each ray's
        // chords joined (`swarf_sweep::InstanceSet`), and which instances share a group shifts
        // with the one skipped; a bull-nose's ends on its corner are walked to within 10⁻¹² mm
        // along the line (`T_TOL`) from wherever the walk starts, so two cuts of the same
        // instances may leave an end up to about twice that apart (8.7·10⁻¹³ mm seen).
        for k in 0..3 {
            let (nu, nv) = once.family(k).dims();
            for j in 0..nv {
                for i in 0..nu {
                    let (a, b) = (once.family(k).ray(i, j), twice.family(k).ray(i, j));
                    let same = a.len() == b.len()
                        && a.iter().zip(b).all(|(x, y)| {
                            (x.enter - y.enter).abs() < 1e-11 && (x.exit - y.exit).abs() < 1e-11
                        });
                    assert!(
                        same,
                        "{:?}: family {k} ray ({i}, {j}): {a:?} against {b:?}",
                        cutter.kind()
                    );
                }
            }
        }
    }
}
