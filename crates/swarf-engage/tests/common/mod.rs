//! Helpers shared by the engagement tests: read a program, run it, pick a location.
#![allow(dead_code)]

use swarf_engage::{EngageOptions, Engagement, Engager};
use swarf_geom::math::Vec3;
use swarf_path::load::{read_program_str, ReadOptions};
use swarf_path::{Machine, Program};
use swarf_stock::TriDexel;
use swarf_tool::{Cutter, ToolSet};

/// Reads a program (G-code or APT by the file name's extension) on a 3-axis machine.
pub(crate) fn program(text: &str, file: &str) -> Program {
    read_program_str(text, file, Machine::three_axis(), &ReadOptions::default()).unwrap()
}

/// A box stock.
pub(crate) fn block(min: [f64; 3], max: [f64; 3], h: f64) -> TriDexel {
    TriDexel::from_box(Vec3::from(min), Vec3::from(max), h).unwrap()
}

/// Every location of `program` run with `cutter` on `stock`.
pub(crate) fn run(
    program: &Program,
    cutter: Cutter,
    stock: &mut TriDexel,
    opts: EngageOptions,
) -> Vec<Engagement> {
    let tools = ToolSet::single(cutter);
    Engager::new(program, &tools, stock, opts)
        .unwrap()
        .map(Result::unwrap)
        .collect()
}

/// Every location of the program `text` (file name `file`) with `cutter` in the block from
/// `min` to `max` at the tests' ray spacing of 0.1 mm, default options.
pub(crate) fn run_in_block(
    text: &str,
    file: &str,
    min: [f64; 3],
    max: [f64; 3],
    cutter: Cutter,
) -> Vec<Engagement> {
    let p = program(text, file);
    let mut stock = block(min, max, 0.1);
    run(&p, cutter, &mut stock, EngageOptions::default())
}

/// The location whose tip is nearest to `p`.
pub(crate) fn at(locations: &[Engagement], p: [f64; 3]) -> &Engagement {
    let p = Vec3::from(p);
    locations
        .iter()
        .min_by(|a, b| (a.tip - p).length().total_cmp(&(b.tip - p).length()))
        .unwrap()
}

/// Relative error.
pub(crate) fn rel(got: f64, want: f64) -> f64 {
    (got - want).abs() / want.abs()
}

/// Asserts the area within `rel_tol`, the angles within `deg_tol` and prints them.
pub(crate) fn check(e: &Engagement, area: f64, entry: f64, exit: f64, rel_tol: f64, deg_tol: f64) {
    let (a, b) = (e.phi_entry_deg.unwrap(), e.phi_exit_deg.unwrap());
    println!(
        "area {:.5} (exact {area:.5}, {:.3} %), entry {a:.4}° (exact {entry:.4}°), exit {b:.4}° (exact {exit:.4}°), ap {:.4}",
        e.area_mm2,
        100.0 * rel(e.area_mm2, area),
        e.ap_mm
    );
    assert!(
        rel(e.area_mm2, area) < rel_tol,
        "area {} vs {area}",
        e.area_mm2
    );
    let d = |x: f64, y: f64| ((x - y + 180.0).rem_euclid(360.0) - 180.0).abs();
    assert!(d(a, entry) < deg_tol, "entry {a} vs {entry}");
    assert!(d(b, exit) < deg_tol, "exit {b} vs {exit}");
}

/// The steady engagement of a flat end mill of radius `r` whose centre runs a CCW helix of
/// radius `a` about the Z axis, `pitch` lower per turn, at a location `drop` lower than the one
/// before, enlarging a hole of radius `hole` drilled along the axis (0: into solid stock):
/// (area, entry angle on the disc at `z_disc` in degrees, axial depth).
///
/// The centre at angle θ is `a·ĉ(θ)`; the side point at immersion φ is
/// `q = a·ĉ + r·(sin φ·t̂ − cos φ·ĉ)` (x_L = t̂ the feed, y_L = −ĉ), `|q|² = a² + r² −
/// 2ar·cos φ` from the axis. On the front half (0 < φ < π, where f ∝ sin φ > 0) q enters the
/// tool's disc now; the disc holds q while the centre's angle is within α of q's, `cos α =
/// (|q|² + a² − r²)/(2a|q|) = (a − r cos φ)/|q|`, so q was last inside it a turn ago less 2α,
/// when the bottom was `pitch·(1 − α/π)` higher — unless the location before held it (near
/// φ = 0 when a < r, where α → π), whose bottom was `drop` higher. The side is in the
/// material over the larger of the two, where `|q|` is outside the hole. The bottom disc is in
/// the material wherever it is outside the hole (it was last cut higher up): the disc less its
/// lens with the hole. `|q|` and the band both grow from φ = 0 to φ = π, so a disc is engaged
/// from where both have reached it.
pub(crate) fn helical_bore(
    r: f64,
    a: f64,
    pitch: f64,
    drop: f64,
    z_disc: f64,
    hole: f64,
) -> (f64, f64, f64) {
    use std::f64::consts::PI;
    let radius = |phi: f64| (a * a + r * r - 2.0 * a * r * phi.cos()).sqrt();
    let band = |phi: f64| {
        let q = radius(phi);
        if q < hole {
            return 0.0;
        }
        let c = ((a - r * phi.cos()) / q).clamp(-1.0, 1.0);
        (pitch * (1.0 - c.acos() / PI)).max(drop)
    };
    let n = 200_000;
    let side: f64 = (0..n)
        .map(|q| r * band((q as f64 + 0.5) / n as f64 * PI) * PI / n as f64)
        .sum();
    let (mut lo, mut hi) = (0.0, PI);
    if band(0.0) >= z_disc {
        hi = 0.0;
    } else {
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if band(mid) < z_disc {
                lo = mid;
            } else {
                hi = mid;
            }
        }
    }
    (
        PI * r * r - lens(r, hole, a) + side,
        hi.to_degrees(),
        band(PI),
    )
}

/// The area common to two discs of radii `r` and `s` whose centres are `d` apart.
pub(crate) fn lens(r: f64, s: f64, d: f64) -> f64 {
    use std::f64::consts::PI;
    if s <= 0.0 || d >= r + s {
        return 0.0;
    }
    if d <= (r - s).abs() {
        return PI * r.min(s).powi(2);
    }
    let part = |x: f64, y: f64| x * x * ((d * d + x * x - y * y) / (2.0 * d * x)).acos();
    let kite = 0.5 * ((-d + r + s) * (d + r - s) * (d - r + s) * (d + r + s)).sqrt();
    part(r, s) + part(s, r) - kite
}

/// Every location of the fourth of four turns of a 10 mm flat end mill on a CCW helix of
/// radius `a` about the Z axis, 1 mm per turn, locations every `step` mm, into a block whose
/// top is at z = 0 with a hole of radius `hole` drilled through it along the axis (0: none),
/// rays `h` apart (on the fourth turn the tip is 2.5–3.5 mm deep and the turn before wholly
/// under the top: the engagement is steady); each with how much lower it is than the location
/// before.
pub(crate) fn helix_turn(
    a: f64,
    step: f64,
    hole: f64,
    h: f64,
    opts: EngageOptions,
) -> Vec<(Engagement, f64)> {
    let mut text = format!("G21 G90\nG0 X{a} Y0 Z0.5\n");
    for turn in 1..=4 {
        text += &format!("G3 X{a} Y0 Z{} I{} J0 F600\n", 0.5 - turn as f64, -a);
    }
    let p = program(&text, "helix.ngc");
    let w = a + 7.0;
    let b = swarf_geom::Aabb::new(Vec3::new(-w, -w, -10.0), Vec3::new(w, w, 0.0));
    // The block's rays, exact: along Z outside the hole, across it beside it.
    let mut stock = TriDexel::from_fn(b, h, |k, cu, cv, d| {
        let mut q = [0.0; 3];
        (q[(k + 1) % 3], q[(k + 2) % 3]) = (cu, cv);
        let mut push = |enter: f64, exit: f64| d.push(swarf_stock::Interval { enter, exit });
        if k == 2 {
            if q[0].hypot(q[1]) >= hole {
                push(-10.0, 0.0);
            }
            return;
        }
        let across = q[1 - k];
        if across.abs() < hole {
            let half = (hole * hole - across * across).sqrt();
            push(-w, -half);
            push(half, w);
        } else {
            push(-w, w);
        }
    })
    .unwrap();
    let locs = run(
        &p,
        Cutter::flat(10.0).unwrap(),
        &mut stock,
        opts.with_step(step),
    );
    // Each location is taken against the stock cut up to the location before, or up to
    // `lag_mm` of travel back where that is nearer: its drop is from there (the turns are
    // helices √((2πa)² + 1) long, 1 mm of pitch).
    let turn_length = (std::f64::consts::TAU * a).hypot(1.0);
    let travel = |e: &Engagement| (e.move_index as f64 + e.s) * turn_length;
    locs.windows(2)
        .filter(|w| w[1].move_index == 4)
        .map(|w| {
            let back = (travel(&w[1]) - travel(&w[0])).max(opts.lag_mm);
            (w[1].clone(), back / turn_length)
        })
        .collect()
}
