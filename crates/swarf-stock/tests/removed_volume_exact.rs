//! Removed volume against exact formulas (slots, groove, ramp, plunges, helical bore), and the
//! convergence of the error as the resolution h halves.

mod common;

use common::{gcode, rel};
use std::f64::consts::PI;
use swarf_geom::math::Vec3;
use swarf_stock::{simulate, SimOptions, TriDexel};
use swarf_sweep::ToolShape;
use swarf_tool::{Cutter, ToolSet};

const TOP: f64 = 10.0;

/// Stock for the G-code programs, clear of the origin where they start.
fn bore_stock(h: f64) -> TriDexel {
    TriDexel::from_box(Vec3::new(10.0, 0.0, 0.0), Vec3::new(30.0, 20.0, TOP), h).unwrap()
}

fn stock(h: f64) -> TriDexel {
    TriDexel::from_box(Vec3::ZERO, Vec3::new(40.0, 20.0, TOP), h).unwrap()
}

/// Removed volume of straight moves through `tips` (axis +Z).
fn removed(cutter: &Cutter, tips: &[Vec3], h: f64) -> f64 {
    let mut s = stock(h);
    let v0 = s.volume();
    let tool = ToolShape::new(cutter);
    for w in tips.windows(2) {
        let c = s.cut_linear(&tool, w[0], w[1], Vec3::Z);
        assert_eq!(
            c.non_cutting.removed_length, [0.0; 3],
            "the shank must stay clear"
        );
    }
    v0 - s.volume()
}

/// Slot of length `l` and depth `dp` by a horizontal move of a cutter with profile radius
/// `rho(z)`: `l·∫2ρ dz + ∫πρ² dz` over `[0, dp]` (the swept cross-section plus the two half
/// solids of revolution at the ends).
struct Scenario {
    name: &'static str,
    cutter: Cutter,
    tips: Vec<Vec3>,
    exact: f64,
}

fn scenarios() -> Vec<Scenario> {
    let (x0, x1, y) = (8.03, 31.97, 10.01);
    let l = x1 - x0;
    let mut v = Vec::new();
    // Flat end mill slot: a stadium times the depth.
    let (r, dp) = (3.0, 3.0);
    v.push(Scenario {
        name: "flat slot d6 x3",
        cutter: Cutter::flat(2.0 * r).unwrap(),
        tips: vec![Vec3::new(x0, y, TOP - dp), Vec3::new(x1, y, TOP - dp)],
        exact: (l * 2.0 * r + PI * r * r) * dp,
    });
    // Ball-end groove, depth ≤ R: circular segment along the groove plus one spherical cap.
    let (r, dp) = (5.0f64, 4.0f64);
    let seg = r * r * ((r - dp) / r).acos() - (r - dp) * (2.0 * r * dp - dp * dp).sqrt();
    v.push(Scenario {
        name: "ball groove d10 x4",
        cutter: Cutter::ball(2.0 * r).unwrap(),
        tips: vec![Vec3::new(x0, y, TOP - dp), Vec3::new(x1, y, TOP - dp)],
        exact: l * seg + PI * dp * dp * (3.0 * r - dp) / 3.0,
    });
    // Bull-nose slot d12 r2 (e = 4), depth 5 ≥ r.
    let (d, rc, dp) = (12.0f64, 2.0f64, 5.0f64);
    let e = d / 2.0 - rc;
    let int_rho = e * rc + PI * rc * rc / 4.0 + d / 2.0 * (dp - rc);
    let int_rho2 = e * e * rc
        + e * PI * rc * rc / 2.0
        + 2.0 * rc.powi(3) / 3.0
        + (d / 2.0).powi(2) * (dp - rc);
    v.push(Scenario {
        name: "bull slot d12 r2 x5",
        cutter: Cutter::bull(d, rc).unwrap(),
        tips: vec![Vec3::new(x0, y, TOP - dp), Vec3::new(x1, y, TOP - dp)],
        exact: l * 2.0 * int_rho + PI * int_rho2,
    });
    // Ramp with a flat end mill from the surface down to dp over l: dp·(l·R + π·R²)
    // (at x the floor is at the deepest position the tool reached within reach of x).
    let (r, dp) = (3.0, 3.0);
    v.push(Scenario {
        name: "flat ramp d6 3/24",
        cutter: Cutter::flat(2.0 * r).unwrap(),
        tips: vec![Vec3::new(x0, y, TOP), Vec3::new(x1, y, TOP - dp)],
        exact: dp * (l * r + PI * r * r),
    });
    // Flat plunge along the axis: a cylinder.
    let (r, dp) = (3.0, 5.0);
    v.push(Scenario {
        name: "flat plunge d6 x5",
        cutter: Cutter::flat(2.0 * r).unwrap(),
        tips: vec![
            Vec3::new(20.02, y, TOP + 2.0),
            Vec3::new(20.02, y, TOP - dp),
        ],
        exact: PI * r * r * dp,
    });
    // Drilled hole with a 118° point: cylinder plus cone.
    let (r, dp) = (3.0, 7.0);
    let f = r * (31.0f64).to_radians().tan();
    v.push(Scenario {
        name: "drill 118 d6 x7",
        cutter: Cutter::drill(2.0 * r, 118.0).unwrap(),
        tips: vec![
            Vec3::new(20.02, y, TOP + 2.0),
            Vec3::new(20.02, y, TOP - dp),
        ],
        exact: PI * r * r * (dp - f) + PI * r * r * f / 3.0,
    });
    v
}

#[test]
fn removed_volume_matches_exact_formulas_and_converges() {
    println!(
        "{:<22} {:>12} {:>10} {:>10} {:>10}",
        "scenario", "exact mm3", "h=0.4", "h=0.2", "h=0.1"
    );
    for sc in scenarios() {
        let errs: Vec<f64> = [0.4, 0.2, 0.1]
            .iter()
            .map(|&h| rel(removed(&sc.cutter, &sc.tips, h), sc.exact))
            .collect();
        println!(
            "{:<22} {:>12.3} {:>9.4}% {:>9.4}% {:>9.4}%",
            sc.name,
            sc.exact,
            100.0 * errs[0],
            100.0 * errs[1],
            100.0 * errs[2]
        );
        assert!(
            errs[2] < 0.002,
            "{}: error {:.4}% at h = 0.1 (bound 0.2 %)",
            sc.name,
            100.0 * errs[2]
        );
        assert!(
            errs[2] <= errs[0] || errs[2] < 1e-4,
            "{}: the error does not shrink with h: {errs:?}",
            sc.name
        );
    }
}

#[test]
fn helical_bore_by_arcs() {
    // Ø6 flat end mill on a helix of radius 3 about (20, 10): four turns down to 4 mm, then a
    // full circle at the bottom. The bore has radius 6 and no core.
    let p = gcode(
        "G21 G90 G17\nG0 Z30\nG0 X23 Y10\nG0 Z11\nG1 Z10 F300\nG3 X23 Y10 Z6 I-3 J0 P4\nG3 X23 Y10 I-3 J0\nG0 Z30\nM30\n",
    );
    let exact = PI * 36.0 * 4.0;
    let tools = ToolSet::single(Cutter::flat(6.0).unwrap());
    for h in [0.2, 0.1] {
        let mut s = bore_stock(h);
        let opts = SimOptions::default();
        let r = simulate(&p, &tools, &mut s, &opts).unwrap();
        let err = rel(r.removed_volume_mm3, exact);
        println!(
            "helical bore h={h}: removed {:.3} mm3, exact {exact:.3}, error {:.4}%",
            r.removed_volume_mm3,
            100.0 * err
        );
        assert_eq!(
            r.chordal_tolerance_mm,
            swarf_stock::DEFAULT_CHORDAL_TOLERANCE_MM
        );
        assert!(r.rapid_collisions.is_empty() && r.holder_collisions.is_empty());
        // Grid error plus the chords' under-cut (≤ tolerance × wall area = 0.03 %).
        assert!(err < 0.002, "h = {h}: error {:.4}%", 100.0 * err);
        // Per-move volumes add up to the total.
        let sum: f64 = r.removed_per_move_mm3.iter().sum();
        assert!(
            (sum - r.removed_volume_mm3).abs() < 1e-6 * exact,
            "{sum} vs {}",
            r.removed_volume_mm3
        );
    }
}

#[test]
fn coarse_chords_undercut_by_at_most_the_tolerance() {
    // With a 0.05 mm chordal tolerance the bore is smaller, by at most tolerance × wall area.
    let p = gcode("G21 G90 G17\nG0 Z30\nG0 X23 Y10\nG0 Z11\nG1 Z6 F300\nG3 X23 Y10 I-3 J0\nM30\n");
    let tools = ToolSet::single(Cutter::flat(6.0).unwrap());
    let run = |tol: f64| {
        let mut s = bore_stock(0.1);
        simulate(
            &p,
            &tools,
            &mut s,
            &SimOptions::default().with_chordal_tolerance(tol),
        )
        .unwrap()
    };
    let fine = run(1e-4);
    let coarse = run(0.05);
    assert_eq!(coarse.chordal_tolerance_mm, 0.05);
    let under = fine.removed_volume_mm3 - coarse.removed_volume_mm3;
    let wall = 2.0 * PI * 6.0 * 4.0;
    println!("under-cut {under:.4} mm3, bound {:.4}", 0.05 * wall);
    assert!(under >= -1e-6 && under <= 0.05 * wall, "{under}");
    assert!(under > 0.0, "coarse chords should under-cut visibly");
}

#[test]
fn error_shrinks_as_h_halves() {
    // The single-position errors above fluctuate with how the boundary falls between ray
    // centres; averaged over several sub-cell placements the trend is clear.
    let cutter = Cutter::ball(10.0).unwrap();
    let (r, dp) = (5.0f64, 4.0f64);
    let seg = r * r * ((r - dp) / r).acos() - (r - dp) * (2.0 * r * dp - dp * dp).sqrt();
    let l = 20.0;
    let exact = l * seg + PI * dp * dp * (3.0 * r - dp) / 3.0;
    let offsets = [0.0, 0.137, 0.291, 0.377];
    let mut table = Vec::new();
    for h in [0.4, 0.2, 0.1, 0.05] {
        let mean: f64 = offsets
            .iter()
            .map(|&o| {
                let a = Vec3::new(10.0 + o, 10.0 + 0.7 * o, TOP - dp);
                rel(removed(&cutter, &[a, a + Vec3::new(l, 0.0, 0.0)], h), exact)
            })
            .sum::<f64>()
            / offsets.len() as f64;
        println!("ball groove, h = {h:<5} mean |error| {:.5}%", 100.0 * mean);
        table.push(mean);
    }
    assert!(table[3] < 0.5 * table[0], "no convergence: {table:?}");
    assert!(table[2] < 0.001, "{table:?}");
}

/// Area of the convex polygon `poly` (in the YZ plane, `(y, z)`) below the height `top`
/// (Sutherland–Hodgman against one line, then the shoelace formula).
fn area_below(poly: &[(f64, f64)], top: f64) -> f64 {
    let mut clipped = Vec::new();
    for (i, &p) in poly.iter().enumerate() {
        let q = poly[(i + 1) % poly.len()];
        if p.1 <= top {
            clipped.push(p);
        }
        if (p.1 < top) != (q.1 < top) {
            let t = (top - p.1) / (q.1 - p.1);
            clipped.push((p.0 + t * (q.0 - p.0), top));
        }
    }
    let n = clipped.len();
    0.5 * (0..n)
        .map(|i| {
            let (a, b) = (clipped[i], clipped[(i + 1) % n]);
            a.0 * b.1 - b.0 * a.1
        })
        .sum::<f64>()
        .abs()
}

#[test]
fn tilted_axis_slots_3_plus_2() {
    // A flat and a ball end mill with the axis tilted 25° in the YZ plane, moving along X right
    // through the block (3+2 machining; the tilted slab's closed form and a ball's capsule).
    // The move is ⊥ the axis, so the sweep's section across the block is the cutter's shadow
    // along X: a rectangle 2R wide along the axis for the cylinder, with a disc of radius R
    // at the ball's centre — the half of it below the cylinder entirely under the top here.
    // Removed: the block's length times the shadow's area under the top.
    let (r, theta) = (3.0f64, 25f64.to_radians());
    let (a, n) = ((theta.sin(), theta.cos()), (theta.cos(), -theta.sin()));
    let axis = Vec3::new(0.0, a.0, a.1);
    let at = |c: (f64, f64), s: f64, t: f64| (c.0 + s * a.0 + t * n.0, c.1 + s * a.1 + t * n.1);
    let rect =
        |c: (f64, f64), len: f64| [at(c, 0.0, -r), at(c, 0.0, r), at(c, len, r), at(c, len, -r)];
    let fl = 15.0;
    // (name, spec, depth, the round end's radius: 0 flat, r ball, 1.5 bull-nose)
    let cases = [
        ("flat d6 tilted 25°", "flat:d=6,flute-length=15", 3.0, 0.0),
        ("ball d6 tilted 25°", "ball:d=6,flute-length=15", 7.0, r),
        (
            "bull d6 r1.5 tilted 25°",
            "bull:d=6,r=1.5,flute-length=15",
            4.0,
            1.5,
        ),
    ];
    for (name, spec, dp, rc) in cases {
        let tip = (10.0, TOP - dp);
        // The shadow of a solid of revolution across its axis is its meridian section: the
        // rectangle less the squares' corners outside the corner arcs (a ball's: half a disc).
        let shadow = if rc == r {
            let c = at(tip, r, 0.0);
            assert!(c.1 + r < TOP, "the ball's lower half lies under the top");
            area_below(&rect(c, fl - r), TOP) + 0.5 * PI * r * r
        } else {
            let corners_top = at(tip, rc, r).1.max(at(tip, rc, -r).1);
            assert!(corners_top < TOP, "the corners lie under the top");
            area_below(&rect(tip, fl), TOP) - 2.0 * (1.0 - PI / 4.0) * rc * rc
        };
        let exact = 40.0 * shadow;
        let cutter = Cutter::from_spec(spec).unwrap();
        let tool = ToolShape::new(&cutter);
        for h in [0.2, 0.1] {
            let mut s = stock(h);
            let v0 = s.volumes();
            let from = Vec3::new(-10.0, tip.0, tip.1);
            let cut = s.cut_linear(&tool, from, from + Vec3::new(60.0, 0.0, 0.0), axis);
            assert_eq!(
                cut.non_cutting.removed_length, [0.0; 3],
                "{name}: shank clear"
            );
            // Each ray family's estimate: the X rays run along the move (across the axis),
            // the Y and Z rays across it at a slant.
            let v1 = s.volumes();
            let errs: [f64; 3] = std::array::from_fn(|k| rel(v0[k] - v1[k], exact));
            println!(
                "{name}, h = {h}: removed (X, Y, Z rays) {:.3} / {:.3} / {:.3} mm3, exact {exact:.3}, error {:.4} / {:.4} / {:.4} %",
                v0[0] - v1[0],
                v0[1] - v1[1],
                v0[2] - v1[2],
                100.0 * errs[0],
                100.0 * errs[1],
                100.0 * errs[2]
            );
            for (k, err) in errs.iter().enumerate() {
                assert!(
                    *err < 0.002,
                    "{name}, h = {h}, family {k}: error {:.4}%",
                    100.0 * err
                );
            }
        }
    }
}
