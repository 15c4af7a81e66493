//! Cutter radius compensation leaves the programmed contour as the wall: random convex bosses
//! programmed with G41 (the tool outside, the contour clockwise), simulated with the tool's
//! diameter from the tool table, remove exactly the band between the contour and its offset by
//! the tool's diameter — for a convex polygon of perimeter P, `(P·2r + π·(2r)²)·depth` — within
//! the ray grid's error. The entry is made above the stock and the cutter plunges on the first
//! edge, where the path runs straight on.

mod common;

use std::f64::consts::{PI, TAU};

use common::Lcg;

use swarf_geom::math::Vec3;
use swarf_path::gcode::GcodeOptions;
use swarf_path::load::{read_program_str, ReadOptions};
use swarf_path::Machine;
use swarf_stock::{simulate, SimOptions, TriDexel};
use swarf_tool::{Cutter, ToolSet};

#[test]
fn g41_leaves_the_programmed_contour_as_the_wall() {
    let (r, depth, c) = (3.0f64, 4.0f64, [25.0f64, 25.0f64]);
    let mut rng = Lcg(41);
    for case in 0..5 {
        // A convex polygon: 5–8 vertices at sorted random angles, radius 8–12 about c.
        let n = 5 + (rng.next_f64() * 4.0) as usize;
        let mut angles: Vec<f64> = (0..n).map(|_| rng.next_f64() * TAU).collect();
        angles.sort_by(f64::total_cmp);
        let rad = 8.0 + 4.0 * rng.next_f64();
        // Clockwise (decreasing angle): the left of the motion is outside.
        let poly: Vec<[f64; 2]> = angles
            .iter()
            .rev()
            .map(|a| [c[0] + rad * a.cos(), c[1] + rad * a.sin()])
            .collect();
        let perimeter: f64 = (0..n)
            .map(|i| {
                let (p, q) = (poly[i], poly[(i + 1) % n]);
                (q[0] - p[0]).hypot(q[1] - p[1])
            })
            .sum();
        // Start in the middle of the first edge, entering along its outward normal from above.
        let (p0, p1) = (poly[0], poly[1]);
        let mid = [(p0[0] + p1[0]) / 2.0, (p0[1] + p1[1]) / 2.0];
        let e = [p1[0] - p0[0], p1[1] - p0[1]];
        let len = e[0].hypot(e[1]);
        let out = [-e[1] / len, e[0] / len]; // left of the edge: outside for a clockwise contour
        let from = [mid[0] + 12.0 * out[0], mid[1] + 12.0 * out[1]];
        // The plunge is made a quarter of the edge on, where the path runs straight on: a
        // plunge at the entry's concave corner leaves it no move to cut back (LinuxCNC 2.9's
        // rs274 refuses that program: "straight feed in concave corner cannot be reached by
        // the tool without gouging", as swarf does since its compensation follows it).
        let q0 = [mid[0] + 0.25 * e[0], mid[1] + 0.25 * e[1]];
        let mut text = format!(
            "G21 G90 G17 F500 T1 M6\nG0 X{:.6} Y{:.6} Z5\nG41 D1\nG1 X{:.6} Y{:.6}\n\
             G1 X{:.6} Y{:.6}\nG1 Z{}\n",
            from[0], from[1], mid[0], mid[1], q0[0], q0[1], -depth
        );
        for q in poly.iter().skip(1).chain(std::iter::once(&poly[0])) {
            text += &format!("G1 X{:.6} Y{:.6}\n", q[0], q[1]);
        }
        text += &format!(
            "G1 X{:.6} Y{:.6}\nG1 Z5\nG40 G1 X{:.6} Y{:.6}\nM2\n",
            q0[0], q0[1], from[0], from[1]
        );
        let opts = ReadOptions {
            gcode: GcodeOptions::default().with_tool_diameter(1, 2.0 * r),
            ..ReadOptions::default()
        };
        let program = read_program_str(&text, "boss.ngc", Machine::three_axis(), &opts).unwrap();
        let mut stock =
            TriDexel::from_box(Vec3::new(0.0, 0.0, -depth), Vec3::new(50.0, 50.0, 0.0), 0.1)
                .unwrap();
        let tools = ToolSet::single(Cutter::flat(2.0 * r).unwrap());
        let report = simulate(&program, &tools, &mut stock, &SimOptions::default()).unwrap();
        let d = 2.0 * r;
        let exact = (perimeter * d + PI * d * d) * depth;
        let err = (report.removed_volume_mm3 - exact) / exact;
        println!(
            "case {case}: {n} vertices, removed {:.3} mm³, exact {exact:.3} ({:.3} %)",
            report.removed_volume_mm3,
            100.0 * err
        );
        assert!(
            err.abs() < 0.003,
            "case {case}: {} vs {exact}",
            report.removed_volume_mm3
        );
    }
}
