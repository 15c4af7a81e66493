//! Every program in the third-party data folder (`SWARF_TEST_DATA`; the tests skip, saying so,
//! without it) that a machine could run simulates without error on a stock covering its
//! bounding box; the one the reader refuses by design fails as documented.
//!
//! Stock: the workpiece a CAMotics project states, else a box over the feed moves' tip bounding
//! box in X and Y, from 1 mm below the lowest feed point up to the top surface: z = 0 when the
//! feeds cross it (the CAM habit of work zero on top), else half-way up the feed range (a CL file
//! in machine coordinates). Tools: the project's table, the program's own `CUTTER/`/`TLDATA/`,
//! or the tool its comments name. Resolution and 5-axis tolerance keep the test short.
//!
//! Besides "no error": material is removed, the final volume is the initial minus the removed,
//! every collision names a move of the program with its source line (rapid collisions only on
//! rapids), and a stock raised above the heart program's clearance plane reports its rapids, by
//! line, as plunging into the material.

use std::path::Path;
use std::time::Instant;
use swarf_geom::math::Vec3;
use swarf_path::load::{read_program, ReadOptions};
use swarf_path::{summarize, Machine, MoveKind, Program};
use swarf_stock::{simulate, SimOptions, SimulationReport, TriDexel};
use swarf_tool::{Cutter, LengthUnit, ToolSet, ToolSource, ToolTable};

/// The data files the tests read.
const FILES: [&str; 9] = [
    "gcode/camotics_heart.camotics",
    "gcode/camotics_heart.ngc",
    "gcode/camotics_heart_cutout.ngc",
    "gcode/camotics_wave.gcode",
    "gcode/linuxcnc_boat-xyzac.ngc",
    "gcode/linuxcnc_interp_g17-g99-g81.ngc",
    "gcode/linuxcnc_spiral.ngc",
    "apt/nx_1_KONTUR_NAR_40_N2.cls",
    "apt/swcam_Paralelipipedo.apt",
];

/// The data file `rel` (present once [`swarf_testdata::paths`] found [`FILES`]).
fn path(rel: &str) -> String {
    swarf_testdata::data_root().join(rel).display().to_string()
}

fn read(rel: &str, machine: &str) -> Program {
    read_program(
        Path::new(&path(rel)),
        Machine::from_name(machine).unwrap(),
        &ReadOptions::default(),
    )
    .unwrap_or_else(|e| panic!("{rel}: {e}"))
}

/// The stock box for `p` (see the module documentation).
fn stock_box(p: &Program) -> (Vec3, Vec3) {
    let s = summarize(p);
    let (lo, hi) = (
        Vec3::from_array(s.feed_bbox_min.unwrap()),
        Vec3::from_array(s.feed_bbox_max.unwrap()),
    );
    let top = if lo.z < 0.0 && hi.z > 0.0 {
        0.0
    } else {
        0.5 * (lo.z + hi.z)
    };
    (
        Vec3::new(lo.x, lo.y, lo.z - 1.0),
        Vec3::new(hi.x, hi.y, top),
    )
}

/// The program's own cutter definitions (APT `CUTTER/`, `TLDATA/`), by tool number.
fn program_tools(p: &Program) -> ToolSet {
    let mut tools = ToolSet::default();
    for (n, [d, r, e, f, a, b, h]) in &p.cutter_definitions {
        let c = Cutter::apt(*d, *r, *e, *f, *a, *b, *h).unwrap();
        tools = tools.with(*n, c, ToolSource::Program);
    }
    tools
}

/// Checks a report against its program and prints its figures.
fn check(name: &str, p: &Program, r: &SimulationReport, tol: f64) {
    println!(
        "{name:<40} moves {:>5} 5-axis {:>5} (sub-moves {:>6}, bound {:.4} mm) removed {:>12.1} mm³ of {:>12.1}, rapid collisions {}, holder collisions {}, {:.2} s",
        r.moves,
        r.five_axis_moves,
        r.five_axis_sub_moves,
        r.five_axis_error_bound_mm,
        r.removed_volume_mm3,
        r.stock_volume_mm3,
        r.rapid_collisions.len(),
        r.holder_collisions.len(),
        r.elapsed_s
    );
    assert_eq!(r.moves, p.moves.len());
    assert!(r.removed_volume_mm3 > 0.0, "{name} cuts");
    assert!(r.final_volume_mm3 <= r.stock_volume_mm3);
    assert!(
        (r.stock_volume_mm3 - r.removed_volume_mm3 - r.final_volume_mm3).abs()
            <= 1e-9 * r.stock_volume_mm3
    );
    assert!(r.five_axis_error_bound_mm <= tol);
    for c in r.rapid_collisions.iter().chain(&r.holder_collisions) {
        let m = &p.moves[c.move_index];
        assert!(c.line >= 1 && c.line == m.line, "{name}: {c:?}");
        assert_eq!(c.file, p.files[m.file as usize], "{name}");
        // (The volume counts the Z rays only: a graze seen by X or Y rays alone reads 0.)
        assert!(c.volume_mm3 >= 0.0);
    }
    for c in &r.rapid_collisions {
        assert!(
            matches!(p.moves[c.move_index].kind, MoveKind::Rapid),
            "{name}: {c:?}"
        );
    }
}

fn run(
    name: &str,
    p: &Program,
    tools: &ToolSet,
    lo: Vec3,
    hi: Vec3,
    h: f64,
    tol: f64,
) -> SimulationReport {
    let mut stock = TriDexel::from_box(lo, hi, h).unwrap();
    let opts = SimOptions::default().with_chordal_tolerance(tol);
    let r = simulate(p, tools, &mut stock, &opts).unwrap_or_else(|e| panic!("{name}: {e}"));
    check(name, p, &r, tol);
    r
}

#[test]
fn every_shared_program_simulates() {
    if swarf_testdata::paths(FILES).is_none()
        || swarf_testdata::path("gcode/nx_haas_vf3_testpart.ptp").is_none()
    {
        return;
    }
    let t0 = Instant::now();
    // The CAMotics heart project: its tools and workpiece, heart.ngc then cutout.ngc on one
    // stock, as the project runs them.
    let project = ToolTable::read(
        Path::new(&path("gcode/camotics_heart.camotics")),
        LengthUnit::Mm,
    )
    .unwrap();
    let mut heart_tools = ToolSet::default();
    for (n, entry) in &project.tools {
        heart_tools = heart_tools.with(*n, entry.cutter.clone(), ToolSource::Table);
    }
    let wp = project.workpiece.unwrap();
    let mut stock = TriDexel::from_box(wp.min, wp.max, 0.4).unwrap();
    let opts = SimOptions::default();
    let mut removed = 0.0;
    for rel in [
        "gcode/camotics_heart.ngc",
        "gcode/camotics_heart_cutout.ngc",
    ] {
        let p = read(rel, "3axis");
        let r = simulate(&p, &heart_tools, &mut stock, &opts).unwrap();
        check(rel, &p, &r, opts.chordal_tolerance);
        removed += r.removed_volume_mm3;
    }
    // The cut-out goes through the 12.7 mm plate (to z = −13) with a 1/16" cutter.
    assert!(removed > 1000.0, "{removed}");

    // (file, machine, tools, resolution mm, 5-axis tolerance mm)
    let others: [(&str, &str, Option<Cutter>, f64, f64); 6] = [
        // tplang wave surface: a ball end mill (the program names tool 3 only).
        (
            "gcode/camotics_wave.gcode",
            "3axis",
            Some(Cutter::ball(6.0).unwrap()),
            0.5,
            0.001,
        ),
        // The LinuxCNC XYZAC table-rotary-tilting demo under TCP (M428): A tilts the table
        // about X, C turns the part on it; "T1 = 10.0 dia. ENDMILL". 1315 simultaneous moves:
        // a 0.01 mm bound (1/50 of a cell) keeps it to about 5 s.
        (
            "gcode/linuxcnc_boat-xyzac.ngc",
            "table-ac-tcp",
            Some(Cutter::flat(10.0).unwrap()),
            0.5,
            0.01,
        ),
        // Canned drilling cycles in inches: a 1/4" twist drill.
        (
            "gcode/linuxcnc_interp_g17-g99-g81.ngc",
            "3axis",
            Some(Cutter::drill(6.35, 118.0).unwrap()),
            1.0,
            0.001,
        ),
        // An engraved spiral in inches: a 1/8" flat end mill.
        (
            "gcode/linuxcnc_spiral.ngc",
            "3axis",
            Some(Cutter::flat(3.175).unwrap()),
            0.5,
            0.001,
        ),
        // NX CLSF outside contour, over 2 m long: its own TLDATA/MILL face mill, coarse rays.
        ("apt/nx_1_KONTUR_NAR_40_N2.cls", "3axis", None, 2.0, 0.001),
        // SolidWorks CAM APT with its own CUTTER/ (an 8 mm flat end mill).
        ("apt/swcam_Paralelipipedo.apt", "3axis", None, 0.5, 0.001),
    ];
    for (rel, machine, cutter, h, tol) in others {
        let p = read(rel, machine);
        let tools = match &cutter {
            Some(c) => ToolSet::single(c.clone()),
            None => program_tools(&p),
        };
        let (lo, hi) = stock_box(&p);
        let r = run(rel, &p, &tools, lo, hi, h, tol);
        if rel.contains("boat") {
            // Its retracts go straight up in Z with the axis tilted (up to 75°): the tool's
            // side grazes the walls it just cut, reported by line.
            for c in &r.rapid_collisions {
                println!(
                    "  rapid collision: line {}, {:.2e} mm³",
                    c.line, c.volume_mm3
                );
            }
            // The boat is cut with the axis turning: the simultaneous moves are cut, not refused.
            let five = p.moves.iter().filter(|m| p.is_five_axis(m)).count();
            assert!(five > 1000, "{five}");
            assert_eq!(r.five_axis_moves, five);
            assert!(r.five_axis_sub_moves >= five as u64);
        }
    }

    // Cutter radius compensation on a Haas (Fanuc) control offsets by the D register, which is
    // the control's: without a tool table the NX post's `G41 X3.5 D1` is read as the tool
    // centre's path (wear compensation, as the post wrote it: its "PLANAR WITH COMP" operation
    // repeats the coordinates of "PLANAR NOCOMP"), with a warning at the D word.
    let p = read_program(
        Path::new(&path("gcode/nx_haas_vf3_testpart.ptp")),
        Machine::three_axis(),
        &ReadOptions::default(),
    )
    .unwrap();
    let w: Vec<_> = p
        .warnings
        .iter()
        .filter(|w| w.message.contains("register D1"))
        .collect();
    assert_eq!(w.len(), 1, "{:?}", p.warnings);
    assert_eq!((w[0].line, w[0].column), (33, 8));
    let ends = |lines: std::ops::RangeInclusive<u32>| -> Vec<[f64; 3]> {
        p.moves
            .iter()
            .filter(|m| lines.contains(&m.line))
            .map(|m| m.end.tip.to_array())
            .collect()
    };
    let (plain, comp) = (ends(15..=18), ends(34..=37));
    assert_eq!(plain.len(), 4);
    assert_eq!(plain, comp);
    println!("all shared programs: {:.1} s", t0.elapsed().as_secs_f64());
}

#[test]
fn rapids_into_a_raised_stock_are_reported_by_line() {
    // The heart program rapids at its clearance plane z = 5 and down to it; a plate whose top
    // is at z = 6 puts every one of those rapids inside the material.
    let rel = "gcode/camotics_heart.ngc";
    if swarf_testdata::path(rel).is_none() {
        return;
    }
    let p = read(rel, "3axis");
    let text = std::fs::read_to_string(path(rel)).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let tools = ToolSet::single(Cutter::ball(2.54).unwrap());
    let r = run(
        "heart, plate top raised to z = 6",
        &p,
        &tools,
        Vec3::new(-40.0, -40.0, -12.7),
        Vec3::new(40.0, 40.0, 6.0),
        0.5,
        0.001,
    );
    // The first rapid rises from the origin, inside the raised plate, to z = 5 (line 8), the
    // next crosses it at z = 5 (line 13); later rapids partly run through what earlier ones
    // and the plunges cleared. Every report is a G0 block of the file.
    let reported: Vec<u32> = r.rapid_collisions.iter().map(|c| c.line).collect();
    assert!(reported.starts_with(&[8, 13]), "{reported:?}");
    for c in &r.rapid_collisions {
        let src = lines[c.line as usize - 1].trim_start();
        assert!(src.starts_with("G0"), "line {}: {src}", c.line);
    }
    let by_rapids: f64 = r.rapid_collisions.iter().map(|c| c.volume_mm3).sum();
    assert!(by_rapids > 50.0, "{by_rapids}");
}
