//! A large 5-axis CL program of the kind CAM systems write: a 10 mm bull-nose (r = 2) finishing
//! the wavy surface of the `cut` bench with the tool axis along the surface normal tilted 10°
//! towards the feed, 0.5 mm `GOTO/`s, 0.6 mm step-over, a retract, a reorienting rapid and a
//! plunge between passes. Simulated on a 120 × 120 × 50 mm block at h = 0.2 mm with the default
//! chordal tolerance (0.001 mm), as `swarf simulate` runs it.
//!
//! `SWARF_BENCH_TOOL=flat`: the same path with a 10 mm flat end mill touching the surface with
//! its bottom edge (a flat end mill is cut as fixed-axis pieces whose count is first order in
//! the tolerance, each answered by the tilted slab's closed form, `swarf-sweep/src/swept/
//! tilted.rs`; the bull-nose as exact instances).
//! `SWARF_BENCH_MOVES` (default 20,000) feed moves; `SWARF_BENCH_RUNS` (default 3) runs, median
//! reported; `SWARF_BENCH_EXHAUSTIVE=1` turns the front test off (`TriDexel::set_exhaustive`:
//! every ray a cut may reach is queried, for timing the test); the program is also written to `target/five_axis_finish.apt` so the command line
//! can be timed on it:
//! `swarf simulate --program target/five_axis_finish.apt --stock box:0,0,0,120,120,50
//! --resolution 0.2`.

use std::fmt::Write as _;
use std::time::Instant;

use swarf_geom::math::Vec3;
use swarf_path::load::{read_program_str, ReadOptions};
use swarf_path::{Machine, MoveKind};
use swarf_stock::{simulate, SimOptions, TriDexel};
use swarf_tool::{Cutter, ToolSet};

/// Height of the finished surface and its gradient.
fn surface(x: f64, y: f64) -> (f64, f64, f64) {
    let z = 40.0 + 3.0 * (x / 12.0).sin() * (y / 15.0).cos();
    let zx = 3.0 / 12.0 * (x / 12.0).cos() * (y / 15.0).cos();
    let zy = -3.0 / 15.0 * (x / 12.0).sin() * (y / 15.0).sin();
    (z, zx, zy)
}

/// Tip and axis of a bull-nose (diameter `d`, corner `r`) touching the surface at `(x, y)`
/// with its axis along the normal tilted by `lead` radians towards the feed `f`.
fn pose(x: f64, y: f64, f: Vec3, d: f64, r: f64, lead: f64) -> (Vec3, Vec3) {
    let (z, zx, zy) = surface(x, y);
    let p = Vec3::new(x, y, z);
    let n = Vec3::new(-zx, -zy, 1.0).normalize();
    let a = (n + f * lead.tan()).normalize();
    // The contact lies on the corner torus: its spine point is r along the normal, and the
    // axis passes (d/2 - r) from it, against the normal's part across the axis.
    let spine = p + n * r;
    let w = (-n + a * n.dot(a)).normalize();
    (spine - w * (0.5 * d - r) - a * r, a)
}

/// The CL program: `n` feed moves of a 10 mm cutter with corner radius `r` (0: flat).
fn program_text(n: usize, r: f64) -> String {
    let (d, lead) = (10.0, 10f64.to_radians());
    let mut t = format!("PARTNO/FIVE AXIS FINISH\nCUTTER/{d},{r}\nSPINDL/10000\n");
    let goto = |t: &mut String, (p, a): (Vec3, Vec3)| {
        writeln!(
            t,
            "GOTO/{:.4},{:.4},{:.4},{:.6},{:.6},{:.6}",
            p.x, p.y, p.z, a.x, a.y, a.z
        )
        .unwrap();
    };
    let (seg, step_over) = (0.5, 0.6);
    let per_pass = (110.0 / seg) as usize;
    let (mut y, mut moves, mut pass) = (5.0, 0, 0);
    while moves < n {
        let fwd = pass % 2 == 0;
        let f = if fwd { Vec3::X } else { -Vec3::X };
        let x_at = |i: usize| {
            if fwd {
                5.0 + i as f64 * seg
            } else {
                115.0 - i as f64 * seg
            }
        };
        let (p0, a0) = pose(x_at(0), y, f, d, r, lead);
        t += "RAPID\n";
        goto(&mut t, (p0 + a0 * 15.0, a0));
        t += "FEDRAT/2000\n";
        goto(&mut t, (p0, a0));
        moves += 1;
        for i in 1..=per_pass {
            if moves >= n {
                break;
            }
            goto(&mut t, pose(x_at(i), y, f, d, r, lead));
            moves += 1;
        }
        // Retract along the axis.
        let (pe, ae) = pose(x_at(per_pass), y, f, d, r, lead);
        t += "RAPID\n";
        goto(&mut t, (pe + ae * 15.0, ae));
        y += step_over;
        pass += 1;
    }
    t
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    if let Some(p) = swarf_testdata::host::probe_unless_asked_not_to() {
        println!("{p}");
    }
    let n: usize = std::env::var("SWARF_BENCH_MOVES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(20_000);
    let runs: usize = std::env::var("SWARF_BENCH_RUNS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(3);
    let exhaustive = std::env::var_os("SWARF_BENCH_EXHAUSTIVE").is_some();
    let flat = std::env::var("SWARF_BENCH_TOOL").is_ok_and(|t| t == "flat");
    let (cutter, name) = if flat {
        (Cutter::flat(10.0).unwrap(), "flat d = 10")
    } else {
        (Cutter::bull(10.0, 2.0).unwrap(), "bull-nose d = 10 r = 2")
    };
    let h = 0.2;
    let text = program_text(n, if flat { 0.0 } else { 2.0 });
    let out = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target");
    if std::fs::create_dir_all(&out).is_ok() {
        let _ = std::fs::write(out.join("five_axis_finish.apt"), &text);
    }
    let program = read_program_str(
        &text,
        "five_axis_finish.apt",
        Machine::three_axis(),
        &ReadOptions::default(),
    )
    .expect("the generated program reads");
    let feeds = program
        .moves
        .iter()
        .filter(|m| !matches!(m.kind, MoveKind::Rapid))
        .count();
    let tools = ToolSet::single(cutter);
    let opts = SimOptions::default();
    let mut times = Vec::new();
    let mut last = None;
    for _ in 0..runs {
        let mut stock = TriDexel::from_box(Vec3::ZERO, Vec3::new(120.0, 120.0, 50.0), h).unwrap();
        stock.set_exhaustive(exhaustive);
        let t = Instant::now();
        let rep = simulate(&program, &tools, &mut stock, &opts).expect("the program simulates");
        times.push(t.elapsed().as_secs_f64());
        last = Some(rep);
    }
    let rep = last.expect("at least one run");
    let med = median(times.clone());
    println!(
        "5-axis CL finish: {} moves ({feeds} feed), {name}, h = {h} mm, \
         tolerance {} mm",
        program.moves.len(),
        rep.chordal_tolerance_mm
    );
    println!(
        "  median {med:.2} s over {runs} runs {times:.2?}; {} 5-axis moves cut as {} sub-moves \
         ({:.1} per move), largest bound {:.2e} mm; removed {:.0} mm³",
        rep.five_axis_moves,
        rep.five_axis_sub_moves,
        rep.five_axis_sub_moves as f64 / rep.five_axis_moves.max(1) as f64,
        rep.five_axis_error_bound_mm,
        rep.removed_volume_mm3
    );
    println!(
        "  {:.1} µs per move, {} rays tested, {} ray updates",
        1e6 * med / program.moves.len() as f64,
        rep.rays_tested,
        rep.ray_updates
    );
}
