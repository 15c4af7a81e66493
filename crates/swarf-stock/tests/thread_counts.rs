//! The stock a simulation leaves, and every figure it reports, do not depend on how many threads
//! cut it: a move's rays are cut in order whoever takes their row, and the figures are summed in
//! row order (`TriDexel::subtract_moves`). Checked bit for bit on pools of one, two and three
//! threads, for batched straight moves, an arc cut on its own and 5-axis moves cut as tool
//! instances and pieces.

use std::fmt::Write as _;
use swarf_geom::math::Vec3;
use swarf_path::load::{read_program_str, ReadOptions};
use swarf_path::{Machine, Program};
use swarf_stock::{simulate, SimOptions, SimulationReport, TriDexel};
use swarf_tool::{Cutter, ToolSet};

/// The `i`-th x of pass `pass` of a zig-zag from x = 2 to 38 mm, 1 mm apart.
fn zigzag(pass: usize, i: usize) -> f64 {
    if pass % 2 == 0 {
        2.0 + i as f64
    } else {
        38.0 - i as f64
    }
}

/// Reads a program (G-code or APT by `file`'s extension) on a 3-axis machine.
fn read(text: &str, file: &str) -> Program {
    read_program_str(text, file, Machine::three_axis(), &ReadOptions::default()).unwrap()
}

/// A ball's raster of short straight moves (cut in batches), a plunge and a full circle (cut
/// move by move).
fn three_axis() -> Program {
    let mut t = String::from("G21 G90\nG0 X2 Y3 Z25\nG1 Z14 F600\n");
    for pass in 0..6 {
        let y = 3.0 + 4.0 * pass as f64;
        for i in 0..=36 {
            let x = zigzag(pass, i);
            let z = 14.0 + 1.5 * (x / 6.0).sin() * (y / 5.0).cos();
            writeln!(t, "G1 X{x:.3} Y{y:.3} Z{z:.4}").unwrap();
        }
    }
    t += "G0 Z25\nG0 X20 Y15\nG1 Z10\nG1 X28\nG2 X28 Y15 I-8 J0\nG0 Z25\n";
    read(&t, "threads.ngc")
}

/// A bull-nose's CL path whose axis leans back and forth along it: every feed move is a
/// 5-axis move.
fn five_axis() -> Program {
    let mut t =
        String::from("PARTNO/THREADS\nCUTTER/10,2\nSPINDL/10000\nRAPID\nGOTO/2,4,30,0,0,1\n");
    for pass in 0..3 {
        let y = 4.0 + 7.0 * pass as f64;
        for i in 0..=36 {
            let x = zigzag(pass, i);
            let lean = 0.25 * (x / 5.0 + pass as f64).sin();
            let a = Vec3::new(lean.sin(), 0.1 * lean.cos(), lean.cos()).normalize();
            let z = 12.0 + (x / 7.0).cos();
            writeln!(
                t,
                "GOTO/{x:.3},{y:.3},{z:.4},{:.6},{:.6},{:.6}",
                a.x, a.y, a.z
            )
            .unwrap();
        }
    }
    read(&t, "threads.apt")
}

/// Simulates `program` on a fresh block in a pool of `threads`; returns the report and, family
/// by family, every interval as `[ray index, enter, exit]` (the coordinates' bits).
fn run(
    program: &Program,
    cutter: Cutter,
    threads: usize,
) -> (SimulationReport, Vec<Vec<[u64; 3]>>) {
    swarf_testdata::on_threads(threads, || {
        let mut stock = TriDexel::from_box(Vec3::ZERO, Vec3::new(40.0, 30.0, 20.0), 0.2).unwrap();
        let tools = ToolSet::single(cutter);
        let report = simulate(program, &tools, &mut stock, &SimOptions::default()).unwrap();
        let rays = (0..3)
            .map(|k| {
                let fam = stock.family(k);
                let (nu, nv) = fam.dims();
                (0..nv)
                    .flat_map(|j| (0..nu).map(move |i| (i, j)))
                    .flat_map(|(i, j)| {
                        let ray = (j * nu + i) as u64;
                        fam.ray(i, j)
                            .iter()
                            .map(move |iv| [ray, iv.enter.to_bits(), iv.exit.to_bits()])
                    })
                    .collect()
            })
            .collect();
        (report, rays)
    })
}

fn assert_same_for_every_thread_count(program: &Program, cutter: Cutter) {
    let (one, one_rays) = run(program, cutter.clone(), 1);
    assert!(one.removed_volume_mm3 > 100.0, "the program cuts: {one:?}");
    for threads in [2, 3] {
        let (many, many_rays) = run(program, cutter.clone(), threads);
        let first_change = one
            .removed_per_move_mm3
            .iter()
            .zip(&many.removed_per_move_mm3)
            .position(|(a, b)| a.to_bits() != b.to_bits());
        assert_eq!(
            first_change.map(|m| (m, one.removed_per_move_mm3[m], many.removed_per_move_mm3[m])),
            None,
            "{threads} threads: (move, removed on one thread, removed on these)"
        );
        assert_eq!(one.ray_updates, many.ray_updates, "{threads} threads");
        assert_eq!(one.rays_tested, many.rays_tested, "{threads} threads");
        assert_eq!(
            one.five_axis_sub_moves, many.five_axis_sub_moves,
            "{threads} threads"
        );
        assert_eq!(
            one.final_volume_mm3.to_bits(),
            many.final_volume_mm3.to_bits(),
            "{threads} threads"
        );
        for k in 0..3 {
            assert!(
                one_rays[k] == many_rays[k],
                "{threads} threads: the rays of family {k} differ"
            );
        }
    }
}

#[test]
fn a_three_axis_simulation_is_the_same_on_one_two_and_three_threads() {
    assert_same_for_every_thread_count(&three_axis(), Cutter::ball(6.0).unwrap());
}

#[test]
fn a_five_axis_simulation_is_the_same_on_one_two_and_three_threads() {
    let program = five_axis();
    assert!(program.moves.iter().any(|m| program.is_five_axis(m)));
    assert_same_for_every_thread_count(&program, Cutter::bull(10.0, 2.0).unwrap());
}
