//! Engagement against closed-form answers: 10 mm cutters, stock top at z = 0, the default
//! settings (dz = 0.1 mm, dφ = 1°) and ray spacing h = 0.1 mm. Targets: area within 0.5 %,
//! entry and exit angles within 0.5°.

mod common;

use std::f64::consts::PI;

use common::*;
use swarf_engage::EngageOptions;
use swarf_tool::Cutter;

const H: f64 = 0.1;
const R: f64 = 5.0;

#[test]
fn up_milling_beside_a_wall() {
    // Material on +y_L (the feed is +X, y_L = +Y) from y = R − a_e: up-milling, a_e = 2, a_p = 5.
    let locs = run_in_block(
        "G21 G90\nG0 X-10 Y0 Z-5\nG1 X50 F600\n",
        "up.ngc",
        [0.0, 3.0, -10.0],
        [40.0, 20.0, 0.0],
        Cutter::flat(10.0).unwrap(),
    );
    let exit = (1.0f64 - 2.0 / R).acos();
    let e = at(&locs, [20.0, 0.0, -5.0]);
    check(e, R * exit * 5.0, 0.0, exit.to_degrees(), 0.005, 0.5);
    assert!((e.ap_mm - 5.0).abs() < 0.01, "{}", e.ap_mm);
    // 53.13° and 0°.
    assert!((exit.to_degrees() - 53.130_102).abs() < 1e-5);
}

#[test]
fn down_milling_beside_a_wall() {
    let locs = run_in_block(
        "G21 G90\nG0 X-10 Y0 Z-5\nG1 X50 F600\n",
        "down.ngc",
        [0.0, -20.0, -10.0],
        [40.0, -3.0, 0.0],
        Cutter::flat(10.0).unwrap(),
    );
    let entry = 180.0 - (1.0f64 - 2.0 / R).acos().to_degrees();
    let e = at(&locs, [20.0, 0.0, -5.0]);
    check(
        e,
        R * (1.0f64 - 2.0 / R).acos() * 5.0,
        entry,
        180.0,
        0.005,
        0.5,
    );
    assert!((entry - 126.869_898).abs() < 1e-5);
}

#[test]
fn full_slot_with_a_flat_end_mill() {
    let locs = run_in_block(
        "G21 G90\nG0 X-10 Y10 Z-5\nG1 X50 F600\n",
        "slot.ngc",
        [0.0, 0.0, -10.0],
        [40.0, 20.0, 0.0],
        Cutter::flat(10.0).unwrap(),
    );
    let e = at(&locs, [20.0, 10.0, -5.0]);
    check(e, PI * R * 5.0, 0.0, 180.0, 0.005, 0.5);
    // Discs: every disc below the top is engaged 0°–180°; the bottom face grazes the floor.
    assert_eq!(e.discs.len(), 50);
    assert!(e.bottom.is_empty());
    for d in &e.discs {
        assert_eq!(d.intervals.len(), 1);
        assert!(d.intervals[0].start_deg < 0.5 && (d.intervals[0].end_deg - 180.0).abs() < 0.5);
    }
    // MRR = a_e·a_p·F = 10 · 5 · 600 mm³/min, removed per 1 mm step = 50 mm³.
    assert!(rel(e.removed_mm3, 50.0) < 0.01, "{}", e.removed_mm3);
    assert!(rel(e.mrr_mm3_min, 30_000.0) < 0.01, "{}", e.mrr_mm3_min);
}

/// Locations close together — a fine `--step`, a short last segment — see the slot as far
/// apart ones do: each is taken against the stock cut at least `lag_mm` back, so the front is
/// in the material by a chip the stock resolves. (Against the stock cut at the location
/// before, 0.01 mm back, the front within 7° of where it starts was a chip thinner than the
/// stock's uncertainty, taken for a rub: 72.7 mm², entry 6.0°, exit 174.0°; at 0.05 mm, 1°.)
/// The removed volumes are still the steps' own: 10 mm wide, 5 deep.
#[test]
fn locations_close_together_see_the_whole_front() {
    let p = program(
        "G21 G90\nG0 X-10 Y10 Z-5\nG1 X10 F600\nG1 X10.3\nG1 X10.31\nG1 X20\n",
        "close.ngc",
    );
    for step in [0.05, 0.01] {
        let mut stock = block([0.0, 0.0, -10.0], [40.0, 20.0, 0.0], 0.1);
        let opts = EngageOptions::default().with_step(step);
        let locs = run(&p, Cutter::flat(10.0).unwrap(), &mut stock, opts);
        let (mut seen, mut removed, mut travelled) = (0, 0.0, 0.0);
        for w in locs.windows(2) {
            let (a, e) = (&w[0], &w[1]);
            if !(5.5..=15.0).contains(&e.tip.x) || e.move_index != a.move_index && a.s < 1.0 {
                continue;
            }
            seen += 1;
            check(e, PI * R * 5.0, 0.0, 180.0, 1e-4, 0.01);
            // The steps' volumes are those of the Z rays their footprints pass (0.05 mm³ a
            // ray, 5 mm deep): the sum is the slot's.
            (removed, travelled) = (removed + e.removed_mm3, travelled + e.tip.x - a.tip.x);
        }
        assert!(
            rel(removed, 50.0 * travelled) < 2e-3,
            "{removed} over {travelled} mm"
        );
        assert!(seen > 150, "step {step}: {seen}");
    }
}

/// Coarse discs and angles still place a planar boundary exactly: the probe measures distances
/// out to the samples' spacing before it clamps them (at its default 4h = 0.4 mm, a 5 mm slot
/// read 5.054 mm deep at 0.75 mm discs and 4.9 mm at 0.7 mm discs with h = 0.05). The area of
/// coarse cells loses the corners where the tangency ends the engaged region (−0.8 % at 1 mm
/// discs; within 1e-9 at the default 0.1 mm).
#[test]
fn coarse_discs_and_angles_place_a_slot_floor_and_a_wall_exactly() {
    let p = program("G21 G90\nG0 X-10 Y10 Z-5\nG1 X50 F600\n", "slot.ngc");
    for (h, dz) in [(0.1, 0.75), (0.05, 0.7), (0.1, 1.0)] {
        let mut stock = block([0.0, 0.0, -10.0], [40.0, 20.0, 0.0], h);
        let opts = EngageOptions::default().with_dz(dz);
        let locs = run(&p, Cutter::flat(10.0).unwrap(), &mut stock, opts);
        let e = at(&locs, [20.0, 10.0, -5.0]);
        assert!(
            (e.ap_mm - 5.0).abs() < 1e-3,
            "h {h}, dz {dz}: ap {}",
            e.ap_mm
        );
        assert!(rel(e.area_mm2, PI * R * 5.0) < 0.015, "{}", e.area_mm2);
    }
    // Down-milling beside a wall at 10° steps: the entry within 0.2° (128.7° at 20°).
    let p = program("G21 G90\nG0 X-10 Y0 Z-5\nG1 X50 F600\n", "down.ngc");
    let mut stock = block([0.0, -20.0, -10.0], [40.0, -3.0, 0.0], H);
    let opts = EngageOptions::default().with_dphi(10.0);
    let locs = run(&p, Cutter::flat(10.0).unwrap(), &mut stock, opts);
    let e = at(&locs, [20.0, 0.0, -5.0]);
    let entry = 180.0 - (1.0f64 - 2.0 / R).acos().to_degrees();
    assert!(
        (e.phi_entry_deg.unwrap() - entry).abs() < 0.2,
        "{:?}",
        e.phi_entry_deg
    );
}

#[test]
fn a_slot_entering_and_leaving_the_block() {
    // The slot above, from outside the block to beyond it. With the tip at x = c the front
    // half-circle (x = c + R·sin φ) lies in the block for R·sin φ ≥ −c when entering, and for
    // R·sin φ ≤ 40 − c when leaving: φ from asin(−c/R) to 180° − asin(−c/R), or 0° to
    // asin((40 − c)/R) and its mirror about 90°; each φ engaged over the whole a_p = 5. Near
    // the block's edges (within a ray spacing of two faces) the rays meet no sheet whole: the
    // axial depth there is still the top face's.
    let locs = run_in_block(
        "G21 G90\nG0 Z10\nG0 X-10 Y10\nG0 Z-5\nG1 X50 F600\n",
        "through.ngc",
        [0.0, 0.0, -10.0],
        [40.0, 20.0, 0.0],
        Cutter::flat(10.0).unwrap(),
    );
    let mut checked = 0;
    for e in &locs {
        let c = e.tip.x;
        let span = if c < R {
            PI - 2.0 * (-c / R).clamp(0.0, 1.0).asin()
        } else {
            2.0 * ((40.0 - c) / R).clamp(0.0, 1.0).asin()
        };
        // Not where the cutter only touches the block (a line of contact).
        if (c + R).abs() < 0.05 || (c - 40.0).abs() < 0.05 || span == 0.0 {
            continue;
        }
        let area = R * span * 5.0;
        println!(
            "c {c:.3} area {:.4} exact {area:.4} ap {:.6}",
            e.area_mm2, e.ap_mm
        );
        assert!(
            rel(e.area_mm2, area) < 0.005,
            "c = {c}: area {} vs {area}",
            e.area_mm2
        );
        assert!((e.ap_mm - 5.0).abs() < 2e-3, "c = {c}: a_p {}", e.ap_mm);
        if c < 0.0 {
            let entry = (-c / R).asin().to_degrees();
            let (a, b) = (e.phi_entry_deg.unwrap(), e.phi_exit_deg.unwrap());
            assert!((a - entry).abs() < 0.1, "c = {c}: entry {a} vs {entry}");
            assert!((b - (180.0 - entry)).abs() < 0.1, "c = {c}: exit {b}");
        }
        checked += 1;
    }
    assert!(checked >= 12, "{checked} locations checked");
}

#[test]
fn a_second_pass_beside_a_slot() {
    // A slot 5 deep at y = 10, then a pass 3 deep at y = 16: the material the second pass
    // meets lies beyond the first slot's wall y = 15, from y = 16 + R·cos φ ≥ 15, i.e. φ up
    // to acos(−1/5) = 101.54°, over a_p = 3 (the corner of its engagement is the edge of
    // the wall and the top, where the rays over the slot end on its floor, 5 mm down).
    let locs = run_in_block(
        "G21 G90\nG0 Z10\nG0 X-10 Y10\nG0 Z-5\nG1 X50 F600\nG0 Z10\nG0 X-10 Y16\nG0 Z-3\nG1 X50\n",
        "second.ngc",
        [0.0, 0.0, -10.0],
        [40.0, 30.0, 0.0],
        Cutter::flat(10.0).unwrap(),
    );
    let exit = (-1.0f64 / R).acos();
    let mut checked = 0;
    for e in locs
        .iter()
        .filter(|e| e.tip.y > 15.0 && (1.0..=34.0).contains(&e.tip.x))
    {
        check(e, R * exit * 3.0, 0.0, exit.to_degrees(), 0.005, 0.1);
        assert!(
            (e.ap_mm - 3.0).abs() < 2e-3,
            "x = {}: a_p {}",
            e.tip.x,
            e.ap_mm
        );
        checked += 1;
    }
    assert!(checked >= 30, "{checked} locations checked");
}

#[test]
fn ball_end_mill_slot_at_depth_3() {
    // The front half of the spherical zone of height d = 3 under the top: π·R·d.
    let locs = run_in_block(
        "G21 G90\nG0 X-10 Y10 Z-3\nG1 X50 F600\n",
        "ball.ngc",
        [0.0, 0.0, -10.0],
        [40.0, 20.0, 0.0],
        Cutter::ball(10.0).unwrap(),
    );
    let e = at(&locs, [20.0, 10.0, -3.0]);
    check(e, PI * R * 3.0, 0.0, 180.0, 0.005, 0.5);
    assert!((e.ap_mm - 3.0).abs() < 0.01, "{}", e.ap_mm);
}

#[test]
fn flat_end_mill_plunging() {
    // The whole bottom disc π·R², nothing on the side (it slides along its own wall).
    let locs = run_in_block(
        "G21 G90\nG0 X20 Y10 Z2\nG1 Z-4 F100\n",
        "plunge.ngc",
        [0.0, 0.0, -10.0],
        [40.0, 20.0, 0.0],
        Cutter::flat(10.0).unwrap(),
    );
    assert_eq!(locs.len(), 6);
    for e in &locs[3..] {
        println!("z {} area {} discs {}", e.tip.z, e.area_mm2, e.discs.len());
        assert!(rel(e.area_mm2, PI * R * R) < 0.005, "{}", e.area_mm2);
        assert!(e.discs.is_empty());
        assert!(e.ap_mm.abs() < 1e-12);
        // The plunge: the tip moves along the axis, x_L falls back to +X.
        assert!((e.x_l - swarf_geom::math::Vec3::X).length() < 1e-12);
    }
    // Above the top nothing is engaged.
    assert_eq!(locs[0].area_mm2, 0.0);
    assert!(locs[0].phi_entry_deg.is_none());
}

#[test]
fn ball_and_drill_plunging_along_their_axis() {
    // A feasible set that ends at a joint of the profile: plunging along its axis, a ball end
    // mill is engaged on its whole lower hemisphere, 2πR², up to its equator (a_p = R) — the
    // cylinder above slides along its own wall (f = 0) — a bull-nose on its bottom and its
    // torus, and a 118° drill on its whole point cone, π·R·R/sin 59°, up to the cone's top
    // (a_p = R/tan 59°). The locations a millimetre
    // apart: the material at each lies below the cutter's position a millimetre up, which
    // holds none of those surfaces.
    let half = 59f64.to_radians();
    // A bull-nose (corner radius 2): its flat bottom π·e² (e = 3) and its quarter torus
    // 2π·r·(e·π/2 + r), up to the torus's top (a_p = r).
    let (e, r) = (3.0, 2.0);
    for (cutter, area, ap) in [
        (Cutter::ball(10.0).unwrap(), 2.0 * PI * R * R, R),
        (
            Cutter::bull(10.0, r).unwrap(),
            PI * e * e + 2.0 * PI * r * (e * PI / 2.0 + r),
            r,
        ),
        (
            Cutter::drill(10.0, 118.0).unwrap(),
            PI * R * R / half.sin(),
            R / half.tan(),
        ),
    ] {
        let locs = run_in_block(
            "G21 G90\nG0 X20 Y10 Z2\nG1 Z-9 F100\n",
            "plunge.ngc",
            [0.0, 0.0, -20.0],
            [40.0, 20.0, 0.0],
            cutter,
        );
        for e in locs.iter().filter(|e| e.tip.z <= -6.0) {
            println!(
                "z {} area {} (exact {area}) ap {} (exact {ap})",
                e.tip.z, e.area_mm2, e.ap_mm
            );
            assert!(rel(e.area_mm2, area) < 1e-3, "{} vs {area}", e.area_mm2);
            assert!((e.ap_mm - ap).abs() < 1e-6, "{} vs {ap}", e.ap_mm);
        }
    }
}

#[test]
fn circular_arc_around_a_boss() {
    // A boss of radius 22 finished to 20 by a 10 mm flat end mill whose centre runs CCW on a
    // circle of radius 25 (Aras fig. 6.42): the boss centre is on +y_L at distance 25, so the
    // cutter is engaged from 0° to φ with cos φ = (R² + 25² − 22²)/(2·R·25), constant along
    // the arc away from its start.
    let p = program(
        "G21 G90\nG0 X35 Y0 Z-5\nG1 X25 F600\nG3 X25 Y0 I-25 J0\n",
        "boss.ngc",
    );
    let mut stock = swarf_stock::TriDexel::from_cylinder(0.0, 0.0, -10.0, 22.0, 10.0, H).unwrap();
    let locs = run(
        &p,
        Cutter::flat(10.0).unwrap(),
        &mut stock,
        EngageOptions::default(),
    );
    let exit = ((R * R + 625.0 - 484.0) / (2.0 * R * 25.0)).acos();
    let area = R * exit * 5.0;
    let on_arc: Vec<_> = locs.iter().filter(|e| e.move_index == 2).collect();
    assert!(on_arc.len() > 100);
    // Away from the start (where the cut began) and the end (where it meets it again).
    let steady = &on_arc[20..on_arc.len() - 20];
    for e in steady {
        check(e, area, 0.0, exit.to_degrees(), 0.005, 0.5);
        // The README's figure: the angles within 0.02° at h = 0.1 — taken on a disc of the
        // wall's height, not the one under the top face whose exit reads 0.13° late.
        check(e, area, 0.0, exit.to_degrees(), 0.005, 0.02);
    }
}

#[test]
fn tilted_flat_end_mill_on_a_plane() {
    // 3+2: the axis tilted 20° about Y, feeding along +Y with the tip 3 mm under the top. The
    // side point at angle φ and height z is under the plane while
    // z < (d − R·sin t·cos φ)/cos t, which is > 0 on the whole front half (d > R sin t), so the
    // area is ∫₀^π R·(d − R sin t cos φ)/cos t dφ = π·R·d/cos t; the bottom grazes (f = 0).
    let t = 20f64.to_radians();
    let (i, k) = (t.sin(), t.cos());
    let text = format!(
        "UNITS/MM\nRAPID\nGOTO/20,-20,20,{i},0,{k}\nRAPID\nGOTO/20,-20,-3,{i},0,{k}\nFEDRAT/600\nGOTO/20,60,-3,{i},0,{k}\n"
    );
    let locs = run_in_block(
        &text,
        "tilted.apt",
        [0.0, 0.0, -10.0],
        [40.0, 40.0, 0.0],
        Cutter::flat(10.0).unwrap(),
    );
    let e = at(&locs, [20.0, 20.0, -3.0]);
    check(e, PI * R * 3.0 / t.cos(), 0.0, 180.0, 0.005, 0.5);
    let top = (3.0 + R * t.sin()) / t.cos();
    assert!((e.ap_mm - top).abs() < 0.02, "{} vs {top}", e.ap_mm);
    assert!(e.bottom.is_empty());
}

#[test]
fn bull_nose_ramp() {
    // Ramping down along +X at tan γ = 0.1 into a flat stock: the flat bottom (radius e = 3) is
    // wholly engaged; on the corner torus f = sin ψ sin φ cos γ + cos ψ sin γ > 0 on the
    // φ-measure π + 2·asin(min(1, cot ψ tan γ)) of each parallel ψ; the cylinder is engaged on
    // its front half up to the top (tip at z = −3: from z = 2 to 3).
    let locs = run_in_block(
        "G21 G90\nG0 X-5 Y10 Z1\nG1 X55 Z-5 F600\n",
        "ramp.ngc",
        [0.0, 0.0, -10.0],
        [50.0, 20.0, 0.0],
        Cutter::bull(10.0, 2.0).unwrap(),
    );
    let e = at(&locs, [35.0, 10.0, -3.0]);
    let (ee, r, tg) = (3.0, 2.0, 0.1f64);
    let n = 200_000;
    let mut torus = 0.0;
    for q in 0..n {
        let psi = (q as f64 + 0.5) / n as f64 * PI / 2.0;
        let c = (tg / psi.tan()).min(1.0);
        torus += (ee + r * psi.sin()) * r * (PI + 2.0 * c.asin()) * (PI / 2.0 / n as f64);
    }
    let cylinder = PI * R * (e.tip.z.abs() - 2.0);
    let bottom = PI * ee * ee;
    let exact = bottom + torus + cylinder;
    println!(
        "tip {:?}: area {} exact {exact} (bottom {bottom}, torus {torus}, cylinder {cylinder}), ap {}",
        e.tip, e.area_mm2, e.ap_mm
    );
    assert!(rel(e.area_mm2, exact) < 0.005);
    assert!((e.ap_mm - e.tip.z.abs()).abs() < 0.01);
    assert!(!e.bottom.is_empty());
}

#[test]
fn constant_engagement_is_smooth_along_a_straight_cut() {
    // Up-milling at a_e = 2 sampled every 0.37 mm (locations fall anywhere between rays): the
    // area must not flicker with the ray grid.
    let p = program("G21 G90\nG0 X-10 Y0 Z-5\nG1 X50 F600\n", "smooth.ngc");
    let mut stock = block([0.0, 3.0, -10.0], [40.0, 20.0, 0.0], H);
    let locs = run(
        &p,
        Cutter::flat(10.0).unwrap(),
        &mut stock,
        EngageOptions::default().with_step(0.37),
    );
    let areas: Vec<f64> = locs
        .iter()
        .filter(|e| e.tip.x > 6.0 && e.tip.x < 34.0)
        .map(|e| e.area_mm2)
        .collect();
    assert!(areas.len() > 70);
    let (lo, hi) = areas
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), &x| (a.min(x), b.max(x)));
    let mean = areas.iter().sum::<f64>() / areas.len() as f64;
    println!("spread {:.4} % of {mean}", 100.0 * (hi - lo) / mean);
    assert!((hi - lo) / mean < 0.005);
}

/// Every location of a steady turn of the helix of radius `a` (locations every `step` mm, at
/// least `min_locations` of them) round a hole of radius `hole` (0: none) against
/// [`helical_bore`]: the area within 0.2 % (the target
/// is 0.5 %; counting the rubs as engagement puts it 0.34–0.40 % high), the exit at 180°
/// within 0.5°, the entry within `entry_deg`, the bottom engaged, and the axial depth the
/// band's, a turn's pitch, within 0.2 mm. The side touches the walls the turns before cut, at
/// φ = 0° and 180°: a rub, not engagement (`run.rs`: `Rub`). Where it meets the floor the turn
/// before left, in the corner between that floor and the outer wall, the X and Y rays' sheets
/// smooth the corner over a ray spacing, and the disc above the floor is found engaged over the
/// last degrees before 180°: the depth reads 1.04–1.15 mm.
fn check_helix_turn(a: f64, step: f64, hole: f64, min_locations: usize, entry_deg: f64) {
    let turn = helix_turn(a, step, hole, H, EngageOptions::default());
    assert!(turn.len() > min_locations, "{} locations", turn.len());
    for (e, drop) in &turn {
        let (area, entry, ap) = helical_bore(R, a, 1.0, *drop, 0.05, hole);
        check(e, area, entry, 180.0, 0.002, entry_deg);
        assert!(!e.bottom.is_empty());
        assert!(
            e.ap_mm >= ap - 0.01 && e.ap_mm < ap + 0.2,
            "ap {} vs {ap}",
            e.ap_mm
        );
    }
}

#[test]
fn helical_groove() {
    // The helix (radius 7) wider than the tool: a groove between radii 2 and 12. The band is
    // 0.80–1 mm high all over the front half, so every disc under it is engaged from 0° to
    // 180°.
    check_helix_turn(7.0, 1.0, 0.0, 40, 0.5);
}

#[test]
fn helical_bore_enlarging_a_hole() {
    // Aras fig. 6.13 itself: the helix (radius 3) inside the tool's radius, enlarging a hole
    // of radius 4 drilled along its axis to a bore of radius 8. The side is in the air while
    // it is inside the hole (|q| < 4, up to φ = arccos(0.6) = 53.13°), then under the turn
    // before's floor, 0.5 mm high there: every disc under it is entered at the hole's wall,
    // where the side crosses it — well conditioned, unlike the bore from solid below. The
    // bottom is engaged outside the hole: the disc less its lens with the hole.
    // Measured: the area within 0.18 %, the entry within 0.12°. (It read 0.63° early at 3 of
    // the 38 locations, where the sample a degree before the crossing lies 7 µm inside the hole
    // and 50 µm under the turn before's floor, which runs 12 µm under a row of X rays: those
    // rays end on the floor 0.3 mm further on, the rays below on the wall, and the four were
    // a step — no family measured the wall, and the nearest rays voted the sample into the
    // material. The wall is now measured from the pair of rays below:
    // `probe::tests::beside_a_wall_whose_rays_above_end_on_a_floor_further_on_the_wall_is_measured`.)
    check_helix_turn(3.0, 0.5, 4.0, 30, 0.5);
}

#[test]
fn helical_bore_from_solid() {
    // As Aras fig. 6.13 without the hole: the helix (radius 3) inside the tool's radius, a
    // bore of radius 8 from solid. The band is 0 at φ = 0 (the side point nearest the axis, which the tool always
    // covers) but for the drop since the location before, and a turn's pitch at 180°.
    // Locations every 0.5 mm, so that the drop (0.027 mm) lies under the lowest disc
    // (0.05 mm): that disc is engaged from where the band reaches it, 3.61°.
    //
    // There the entry angle is ill-conditioned: the band rises only 0.8 mm per radian, so
    // 0.5° is 7 µm of height, and the floor it rises from is the turn before's, cut last
    // where the always-covered core ends — a surface whose height goes as the square root of
    // the distance from that circle, which the rays' bilinear sheets follow to a few µm.
    // Measured: the entry within 1.61° at h = 0.1 and 0.63° at h = 0.05 (tests/convergence.rs),
    // the area and the exit within the target.
    check_helix_turn(3.0, 0.5, 0.0, 30, 2.0);
}

/// Slots whose depth is no multiple of half a disc: the band between the last circle in the
/// material and the first above it is engaged up to where the top face crosses it, not to
/// the nearest eighth of the band (0.33 mm was engaged as 0.325 mm, −1.5 % of the area).
#[test]
fn slot_depths_between_the_discs() {
    for (cutter, depths) in [
        (Cutter::flat(10.0).unwrap(), [0.13, 0.33, 0.37, 3.33]),
        (Cutter::ball(10.0).unwrap(), [0.13, 1.23, 2.87, 3.33]),
    ] {
        for d in depths {
            let locs = run_in_block(
                &format!("G21 G90\nG0 X-10 Y10 Z-{d}\nG1 X50 F600\n"),
                "depth.ngc",
                [0.0, 0.0, -10.0],
                [40.0, 20.0, 0.0],
                cutter.clone(),
            );
            let e = at(&locs, [20.0, 10.0, -d]);
            // π·R·d: the front half of the cylinder's side, or of the sphere's zone.
            assert!(rel(e.area_mm2, PI * R * d) < 1e-4, "{d}: {}", e.area_mm2);
            assert!((e.ap_mm - d).abs() < 1e-3, "{d}: {}", e.ap_mm);
        }
    }
}

/// A pointed cutter whose point stands on the stock's top face (a rounding below it) touches
/// nothing: not engaged, no area, no depth — it summed 10⁻¹⁶ mm² of cells and counted as
/// engaged with no angle to show. The next location, 1.5 mm deep, is.
#[test]
fn a_point_on_the_top_face_is_not_engaged() {
    for spec in ["drill:d=8,angle=118", "chamfer:d=10,angle=90"] {
        let p = program("G21 G90\nG0 X20 Y10 Z5\nG1 Z-1.5 F100\n", "point.ngc");
        let mut stock = block([0.0, 0.0, -10.0], [40.0, 20.0, 0.0], 0.1);
        let opts = EngageOptions::default().with_step(5.0);
        let locs = run(&p, Cutter::from_spec(spec).unwrap(), &mut stock, opts);
        assert_eq!(locs.len(), 2, "{spec}");
        assert!(locs[0].tip.z.abs() < 1e-12, "{spec}: {}", locs[0].tip.z);
        let e = &locs[0];
        assert!(
            !e.is_engaged() && e.area_mm2 == 0.0 && e.ap_mm == 0.0,
            "{spec}: {e:?}"
        );
        assert!(e.phi_entry_deg.is_none() && e.discs.is_empty(), "{spec}");
        assert!(
            locs[1].is_engaged() && (locs[1].ap_mm - 1.5).abs() < 1e-3,
            "{spec}"
        );
    }
}
