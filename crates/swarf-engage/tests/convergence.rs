//! The engagement's error against exact values as the ray spacing `h` and the angular sampling
//! `dφ` shrink, on the analytic cases whose boundary is curved (a plane's is exact at any
//! spacing): the table in the README's `swarf engage` section is this test's output
//! (`cargo test -p swarf-engage --release --test convergence -- --nocapture`).

mod common;

use std::f64::consts::PI;

use common::*;
use swarf_engage::{EngageOptions, Engagement};
use swarf_stock::TriDexel;
use swarf_tool::Cutter;

const R: f64 = 5.0;

/// A case: its largest (area, angle) errors at a ray spacing and options.
type Case = fn(f64, EngageOptions) -> (f64, f64);

/// The largest area error (relative) and angle error (degrees) over some locations, each
/// with its exact (area, entry, exit).
fn worst(cases: &[(&Engagement, (f64, f64, f64))]) -> (f64, f64) {
    let d = |x: f64, y: f64| ((x - y + 180.0).rem_euclid(360.0) - 180.0).abs();
    cases
        .iter()
        .fold((0.0f64, 0.0f64), |(wa, wd), (e, (area, entry, exit))| {
            let (a, b) = (e.phi_entry_deg.unwrap(), e.phi_exit_deg.unwrap());
            (
                wa.max(rel(e.area_mm2, *area)),
                wd.max(d(a, *entry)).max(d(b, *exit)),
            )
        })
}

/// A boss of radius 22 finished to 20 by a 10 mm flat end mill on a CCW circle of radius 25
/// (`analytic_cases.rs`): engaged from 0° to acos((R² + 25² − 22²)/(2·R·25)), 5 mm high.
fn boss(h: f64, opts: EngageOptions) -> (f64, f64) {
    let p = program(
        "G21 G90\nG0 X35 Y0 Z-5\nG1 X25 F600\nG3 X25 Y0 I-25 J0\n",
        "boss.ngc",
    );
    let mut stock = TriDexel::from_cylinder(0.0, 0.0, -10.0, 22.0, 10.0, h).unwrap();
    let locs = run(
        &p,
        Cutter::flat(10.0).unwrap(),
        &mut stock,
        opts.with_step(2.0),
    );
    let exit = ((R * R + 625.0 - 484.0) / (2.0 * R * 25.0)).acos();
    let on_arc: Vec<_> = locs.iter().filter(|e| e.move_index == 2).collect();
    let steady = &on_arc[10..on_arc.len() - 10];
    let cases: Vec<_> = steady
        .iter()
        .map(|e| (*e, (R * exit * 5.0, 0.0, exit.to_degrees())))
        .collect();
    worst(&cases)
}

/// A 10 mm ball end mill's slot 3 mm deep: the front half of the spherical zone, π·R·d,
/// engaged from 0° to 180°.
fn ball_slot(h: f64, opts: EngageOptions) -> (f64, f64) {
    let p = program("G21 G90\nG0 X-10 Y10 Z-3\nG1 X50 F600\n", "ball.ngc");
    let mut stock = block([0.0, 0.0, -10.0], [40.0, 20.0, 0.0], h);
    let locs = run(&p, Cutter::ball(10.0).unwrap(), &mut stock, opts);
    let steady: Vec<_> = locs
        .iter()
        .filter(|e| e.tip.x >= 10.0 && e.tip.x <= 30.0)
        .map(|e| (e, (PI * R * 3.0, 0.0, 180.0)))
        .collect();
    worst(&steady)
}

/// The helical bore from solid of `analytic_cases.rs` (helix radius 3, 1 mm per turn,
/// locations every 0.5 mm).
fn bore(h: f64, opts: EngageOptions) -> (f64, f64) {
    let turn = helix_turn(3.0, 0.5, 0.0, h, opts);
    let cases: Vec<_> = turn
        .iter()
        .map(|(e, drop)| {
            let (area, entry, _) = helical_bore(R, 3.0, 1.0, *drop, 0.05, 0.0);
            (e, (area, entry, 180.0))
        })
        .collect();
    worst(&cases)
}

#[test]
fn errors_shrink_with_the_ray_spacing_and_the_angular_sampling() {
    let settings = [(0.2, 1.0), (0.1, 1.0), (0.05, 1.0), (0.1, 2.0), (0.1, 0.5)];
    // Each case, and whether its error must shrink with dφ too: the bore's does not, its entry
    // angle being the rays' — the floor the band rises from (`analytic_cases.rs`).
    let cases: [(&str, Case, bool); 3] = [
        ("arc around a boss (flat, curved wall)", boss, true),
        ("ball slot, depth 3 (sphere)", ball_slot, true),
        ("helical bore from solid (flat)", bore, false),
    ];
    println!("| case | h = 0.2, dφ = 1° | h = 0.1, dφ = 1° (defaults) | h = 0.05, dφ = 1° | h = 0.1, dφ = 2° | h = 0.1, dφ = 0.5° |");
    println!("|---|---|---|---|---|---|");
    for (name, case, by_dphi) in cases {
        let errors: Vec<(f64, f64)> = settings
            .iter()
            .map(|&(h, dphi)| case(h, EngageOptions::default().with_dphi(dphi)))
            .collect();
        let cells: Vec<String> = errors
            .iter()
            .map(|(a, d)| format!("{:.3} %, {:.2}°", 100.0 * a, d))
            .collect();
        println!("| {name} | {} |", cells.join(" | "));
        // Converging: the finer setting of each series no worse than the coarser one, where
        // the coarser error is above what rounding and the other parameters leave.
        let floor = (2e-4, 0.02);
        let series: &[(usize, usize)] = if by_dphi {
            &[(2, 0), (4, 3)]
        } else {
            &[(2, 0)]
        };
        for &(fine, coarse) in series {
            let (f, c) = (errors[fine], errors[coarse]);
            assert!(
                f.0 <= c.0.max(floor.0) && f.1 <= c.1.max(floor.1),
                "{name}: {:?} at {:?} against {:?} at {:?}",
                f,
                settings[fine],
                c,
                settings[coarse]
            );
        }
    }
}
