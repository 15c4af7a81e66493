//! `swarf simulate`: the summary contract, outputs and bad input.
mod common;
use common::*;
use std::f64::consts::PI;

fn temp_dir(name: &str) -> std::path::PathBuf {
    swarf_testdata::fresh_scratch_dir(&format!("sim-{name}"))
}

#[test]
fn flat_slot_removes_its_exact_volume_and_writes_outputs() {
    let dir = temp_dir("slot");
    let prog = dir.join("slot.ngc");
    // A 10 mm flat end mill, 3 mm deep, from X10 to X50 across a 60 x 40 x 20 block: a
    // stadium-shaped slot of 40 x 10 plus two half discs, 3 mm deep.
    std::fs::write(
        &prog,
        "G21 G90\nG0 X10 Y20 Z5\nG1 Z-3 F200\nG1 X50\nG0 Z5\nM30\n",
    )
    .unwrap();
    let out = dir.join("out");
    let o = swarf(&[
        "simulate",
        "--stock",
        "box:0,0,-20,60,40,0",
        "--program",
        prog.to_str().unwrap(),
        "--tool",
        "flat:d=10",
        "--resolution",
        "0.1",
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j = json(&o);
    for k in [
        "stock_volume_mm3",
        "removed_volume_mm3",
        "final_volume_mm3",
        "moves",
        "rays",
        "intervals",
        "rapid_collisions",
        "holder_collisions",
        "elapsed_s",
    ] {
        assert!(j.get(k).is_some(), "{k} missing: {j}");
    }
    let exact = 3.0 * (40.0 * 10.0 + std::f64::consts::PI * 25.0);
    let got = j["removed_volume_mm3"].as_f64().unwrap();
    assert!((got - exact).abs() / exact < 0.002, "{got} vs {exact}");
    assert_eq!(j["rapid_collisions"], 0);
    let csv = std::fs::read_to_string(out.join("moves.csv")).unwrap();
    let mut lines = csv.lines();
    assert!(lines.next().unwrap().starts_with("move,line,removed_mm3"));
    assert_eq!(lines.count(), j["moves"].as_u64().unwrap() as usize);
}

#[test]
fn the_mesh_measures_a_slot_the_z_rays_cannot() {
    // A 6.35 mm slot 2 mm deep right across a 40 x 40 x 10 block, its walls at y = 16.855 and
    // 23.205, between the Z rays (h = 0.1): the Z family counts 63 rays across it (6.3 mm,
    // −0.8 %), the mesh, whose wall vertices come from the Y rays' exact ends, 6.35 mm.
    let dir = temp_dir("meshvol");
    let prog = dir.join("slot.ngc");
    std::fs::write(
        &prog,
        "G21 G90\nG0 X-10 Y20.03 Z5\nG1 Z-2 F300\nG1 X50\nG0 Z5\nM2\n",
    )
    .unwrap();
    let out = dir.join("out");
    let args = |out: Option<&std::path::Path>| {
        let mut a = vec![
            "simulate".to_string(),
            "--stock".into(),
            "box:0,0,-10,40,40,0".into(),
            "--program".into(),
            prog.to_str().unwrap().into(),
            "--tool".into(),
            "flat:d=6.35".into(),
            "--resolution".into(),
            "0.1".into(),
            "--json".into(),
        ];
        if let Some(o) = out {
            a.extend(["--out".into(), o.to_str().unwrap().into()]);
        }
        a
    };
    let run = |a: Vec<String>| {
        let a: Vec<&str> = a.iter().map(String::as_str).collect();
        let o = swarf(&a);
        assert!(o.status.success(), "{}", stderr(&o));
        json(&o)
    };
    let j = run(args(Some(&out)));
    let exact = 40.0 * 40.0 * 10.0 - 40.0 * 6.35 * 2.0;
    let z = j["final_volume_mm3"].as_f64().unwrap();
    let mesh = j["final_mesh_volume_mm3"].as_f64().unwrap();
    assert!((z - exact).abs() > 3.0, "{z} vs {exact}");
    assert!((mesh - exact).abs() < 1e-6, "{mesh} vs {exact}");
    let written: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(written["final_mesh_volume_mm3"].as_f64(), Some(mesh));
    // Without a mesh there is no mesh volume.
    assert!(run(args(None)).get("final_mesh_volume_mm3").is_none());
}

#[test]
fn outputs_are_written_as_a_set_or_not_at_all() {
    let dir = temp_dir("set");
    let prog = dir.join("slot.ngc");
    std::fs::write(
        &prog,
        "G21 G90\nG0 X10 Y20 Z5\nG1 Z-3 F200\nG1 X50\nG0 Z5\nM30\n",
    )
    .unwrap();
    let out = dir.join("out");
    // A folder named like the third output: the run fails and no output appears.
    std::fs::create_dir_all(out.join("moves.csv")).unwrap();
    let run = || {
        swarf(&[
            "simulate",
            "--stock",
            "box:0,0,-20,60,40,0",
            "--program",
            prog.to_str().unwrap(),
            "--tool",
            "flat:d=10",
            "--out",
            out.to_str().unwrap(),
        ])
    };
    let o = run();
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("moves.csv"), "{}", stderr(&o));
    let left: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(left, ["moves.csv"], "no stock.stl/glb, no temporary");
    std::fs::remove_dir(out.join("moves.csv")).unwrap();
    let o = run();
    assert!(o.status.success(), "{}", stderr(&o));
    let mut names: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        ["moves.csv", "stock.glb", "stock.stl", "summary.json"]
    );
    // The glb is indexed: each vertex of the mesh once (flat normals left to the viewer).
    let glb = swarf_io::read_glb(&out.join("stock.glb")).unwrap();
    let stl = swarf_io::read_stl(&out.join("stock.stl")).unwrap();
    let prim = &glb.root.meshes[0].primitives[0];
    let positions = prim
        .attributes
        .iter()
        .find(|(k, _)| format!("{k:?}").contains("Positions"))
        .unwrap()
        .1;
    let count = glb.root.accessors[positions.value()].count.0;
    assert_eq!(count, stl.vertices.len() as u64);
    assert!(
        3 * (stl.triangles.len() as u64) > 5 * count,
        "{count} vertices"
    );
}

#[test]
fn rapid_into_the_stock_is_reported_with_its_line() {
    let dir = temp_dir("rapid");
    let prog = dir.join("crash.ngc");
    std::fs::write(&prog, "G21 G90\nG0 X10 Y10 Z5\nG0 Z-2\nG0 Z5\nM30\n").unwrap();
    let o = swarf(&[
        "simulate",
        "--stock",
        "box:0,0,-10,20,20,0",
        "--program",
        prog.to_str().unwrap(),
        "--tool",
        "ball:d=6",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j = json(&o);
    assert_eq!(j["rapid_collisions"], 1, "{j}");
    assert_eq!(j["collisions"][0]["line"], 3, "{j}");
    assert!(j["removed_volume_mm3"].as_f64().unwrap() > 0.0);
}

/// A feed move that cuts after M5 (or before any S word) crashes on the machine: counted in the
/// summary and warned of with its line and volume (6 × 2 × 20 = 240 mm³ of slot); the same
/// slot with the spindle running is neither.
#[test]
fn cutting_with_the_spindle_stopped_is_reported() {
    let dir = temp_dir("spindle");
    for (name, m5, count) in [("m5.ngc", "M5\n", 1), ("on.ngc", "", 0)] {
        let prog = dir.join(name);
        let text =
            format!("G21 G90\nS1000 M3\nG0 X-10 Y10 Z5\nG1 Z-2 F300\n{m5}G1 X30\nG0 Z5\nM2\n");
        std::fs::write(&prog, text).unwrap();
        let o = swarf(&[
            "simulate",
            "--stock",
            "box:0,0,-10,20,20,0",
            "--program",
            prog.to_str().unwrap(),
            "--tool",
            "flat:d=6",
            "--resolution",
            "0.25",
            "--json",
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let j = json(&o);
        assert_eq!(j["cut_without_spindle"], count, "{j}");
        let e = stderr(&o);
        assert_eq!(e.contains("spindle stopped"), count == 1, "{e}");
        if count == 1 {
            assert!(e.contains("m5.ngc:6") && e.contains("240.000 mm³"), "{e}");
        }
    }
}

#[test]
fn bad_input_is_exit_1_with_a_clear_message() {
    let dir = temp_dir("bad");
    let prog = dir.join("p.ngc");
    std::fs::write(&prog, "G21 G90\nT3 M6\nG1 X1 F100\nM30\n").unwrap();
    let p = prog.to_str().unwrap();
    let o = swarf(&[
        "simulate",
        "--stock",
        "box:0,0,0,1,1",
        "--program",
        p,
        "--tool",
        "flat:d=3",
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("column"), "{}", stderr(&o));
    // No stock at all: a usage error, exit 2 like clap's own.
    let o = swarf(&["simulate", "--program", p, "--tool", "flat:d=3"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--stock"), "{}", stderr(&o));
    let o = swarf(&["simulate", "--stock", "box:0,0,0,5,5,5", "--program", p]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("tool 3"), "{}", stderr(&o));
    let open = dir.join("open.stl");
    std::fs::write(
        &open,
        "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n",
    )
    .unwrap();
    let o = swarf(&[
        "simulate",
        "--stock",
        open.to_str().unwrap(),
        "--program",
        p,
        "--tool",
        "flat:d=3",
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("open edge"), "{}", stderr(&o));
}

#[cfg(unix)]
#[test]
fn ctrl_c_stops_the_run_and_writes_nothing() {
    let dir = temp_dir("ctrlc");
    let prog = dir.join("long.ngc");
    let mut text = String::from("G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F1000\n");
    for i in 0..400_000 {
        let t = f64::from(i);
        text.push_str(&format!(
            "G1 X{:.3} Y{:.3}\n",
            50.0 + 40.0 * (t * 0.01).sin(),
            50.0 + 40.0 * (t * 0.013).cos()
        ));
    }
    std::fs::write(&prog, text).unwrap();
    let out = dir.join("out");
    // The binary says when its handler is in place: the signal is sent after that, never
    // before (which would kill it), and not after a guessed delay.
    let ready = dir.join("ready");
    let child = std::process::Command::new(env!("CARGO_BIN_EXE_swarf"))
        .args(["simulate", "--stock", "box:0,0,-10,100,100,0", "--program"])
        .arg(&prog)
        .args(["--tool", "ball:d=6", "--resolution", "0.2", "--out"])
        .arg(&out)
        .env("SWARF_READY_FILE", &ready)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let t0 = std::time::Instant::now();
    while !ready.exists() {
        assert!(t0.elapsed().as_secs() < 60, "the binary never became ready");
        std::thread::yield_now();
    }
    let kill = std::process::Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("stopped by Ctrl-C"), "{}", stderr(&o));
    assert!(!out.exists(), "nothing may be written after Ctrl-C");
}

/// `--merge-planar`: the machined part's mesh in a fraction of the triangles, closed, its
/// volume the summary's final volume as before. A slot through a block: every face a plane.
#[test]
fn merged_stock_mesh_is_the_same_part_in_few_triangles() {
    let dir = temp_dir("merge");
    let prog = dir.join("slot.ngc");
    std::fs::write(
        &prog,
        "G21 G90\nG0 X-10 Y20 Z5\nG1 Z-4 F300\nG1 X70\nG0 Z5\nM30\n",
    )
    .unwrap();
    let prog = prog.to_str().unwrap();
    let args = [
        "simulate",
        "--stock",
        "box:0,0,-20,60,40,0",
        "--program",
        prog,
        "--tool",
        "flat:d=10",
        "--resolution",
        "0.25",
    ];
    let run = |merge: bool| {
        let out = dir.join(if merge { "merged" } else { "plain" });
        let flag: &[&str] = if merge { &["--merge-planar"] } else { &[] };
        run_mesh(&args, &out, flag, "stock.stl")
    };
    let (plain, plain_mesh) = run(false);
    let (merged, merged_mesh) = run(true);
    assert_eq!(plain["final_volume_mm3"], merged["final_volume_mm3"]);
    // A block with a slot through it: 10 faces, each one polygon.
    assert!(
        merged_mesh.triangles.len() <= 30,
        "{} triangles (unmerged {})",
        merged_mesh.triangles.len(),
        plain_mesh.triangles.len()
    );
    let exact = 60.0 * 40.0 * 20.0 - 60.0 * 10.0 * 4.0;
    // `--simplify`: blocks of cells merged on the flat faces and along the sharp edges.
    let (simplified, simplified_mesh) = run_mesh(
        &args,
        &dir.join("simplified"),
        &["--simplify", "0.001"],
        "stock.stl",
    );
    assert_eq!(plain["final_volume_mm3"], simplified["final_volume_mm3"]);
    assert!(
        simplified_mesh.triangles.len() * 10 < plain_mesh.triangles.len() * 4,
        "{} of {} triangles",
        simplified_mesh.triangles.len(),
        plain_mesh.triangles.len()
    );
    for m in [&plain_mesh, &merged_mesh, &simplified_mesh] {
        assert!(
            (m.volume() - exact).abs() < 1e-3,
            "{} vs {exact}",
            m.volume()
        );
    }
}

#[test]
fn a_ray_spacing_coarser_than_the_cutter_is_refused() {
    // A 10 mm slot at 30 mm spacing removed nothing (and at 1000 mm a quarter of the block):
    // refused before anything is built; a merely coarse spacing runs with a note.
    let dir = temp_dir("coarse");
    let prog = dir.join("slot.ngc");
    std::fs::write(
        &prog,
        "G21 G90\nG0 X0 Y10 Z5\nG1 Z-5 F100\nG1 X40 F300\nM30\n",
    )
    .unwrap();
    let run = |h: &str| {
        swarf(&[
            "simulate",
            "--stock",
            "box:-20,-10,-20,60,30,0",
            "--program",
            prog.to_str().unwrap(),
            "--tool",
            "flat:d=10",
            "--resolution",
            h,
        ])
    };
    let o = run("30");
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("coarser than half"), "{}", stderr(&o));
    let o = run("2");
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("note: --resolution 2 mm is coarse"),
        "{}",
        stderr(&o)
    );
}

/// An APT drilling cycle is drilled: two 10 mm holes 5 mm deep (a flat end mill, so each a
/// cylinder of π·5²·5 mm³), one `GOTO/` each, and nothing else removed.
#[test]
fn apt_drilling_cycle_removes_its_holes() {
    let dir = temp_dir("apt-cycle");
    let prog = dir.join("holes.cls");
    std::fs::write(
        &prog,
        "UNITS/MM\nFEDRAT/MMPM,400\nGOTO/0,0,30\n\
         CYCLE/DRILL,FEDTO,-5,RAPTO,2,RTRCTO,AUTO,MMPM,100\n\
         GOTO/15,20,0,0,0,1\nGOTO/45,20,0\nCYCLE/OFF\nGOTO/0,0,30\nFINI\n",
    )
    .unwrap();
    simulate_removes(
        &prog,
        "box:0,0,-20,60,40,0",
        "flat:d=10",
        2.0 * PI * 25.0 * 5.0,
    );
}

/// A hole drilled on a tilted working plane (G68.2 … J30, G53.1): a 6 mm flat end mill 10 mm
/// deep along the plane's Z from the block's top at (30, 30, 0). Along the tool's axis the
/// top plane is at t = −tan 30°·v across the cutter's disc (v the feature's Y), so the hole's
/// volume is ∫(10 − tan 30°·v) dA = 10·π·3² (the v term cancels over the disc).
#[test]
fn a_hole_on_a_tilted_working_plane_removes_its_exact_volume() {
    let dir = temp_dir("g68-2");
    let prog = dir.join("tilted.nc");
    std::fs::write(
        &prog,
        "G21 G90 G17\nG0 X30 Y30 Z50\nG68.2 X30 Y30 Z0 I0 J30 K0\nG53.1\nG0 X0 Y0 Z5\n\
         G1 Z-10 F100\nG0 Z20\nG69\nG0 Z80\nM30\n",
    )
    .unwrap();
    simulate_removes(&prog, "box:0,0,-30,60,60,0", "flat:d=6", 10.0 * PI * 9.0);
}

/// Simulates `prog` on `stock` with `tool` at h = 0.1: it runs, collides with nothing in rapid
/// and removes `exact` mm³ within 0.5 %.
fn simulate_removes(prog: &std::path::Path, stock: &str, tool: &str, exact: f64) {
    let o = swarf(&[
        "simulate",
        "--stock",
        stock,
        "--program",
        prog.to_str().unwrap(),
        "--tool",
        tool,
        "--resolution",
        "0.1",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j = json(&o);
    let got = j["removed_volume_mm3"].as_f64().unwrap();
    assert!((got - exact).abs() / exact < 0.005, "{got} vs {exact}");
    assert_eq!(j["rapid_collisions"], 0);
}

/// A CAMotics project whose workpiece is automatic: the stock is made from the program as
/// CAMotics makes it (the cutting moves' tool box, top at Z0, grown by the margin), named in a
/// note. With no margin it is the slot's own box, so the whole of it is removed: a 10 × 6
/// stadium plus two half discs of radius 3, 4 mm deep.
#[test]
fn a_camotics_automatic_workpiece_is_made_from_the_program() {
    let dir = temp_dir("camotics-auto");
    let prog = dir.join("slot.ngc");
    std::fs::write(
        &prog,
        "G21 G90\nT1 M6\nM3 S1000\nG0 X0 Y0 Z5\nG1 Z-4 F100\nG1 X10\nG0 Z5\nM2\n",
    )
    .unwrap();
    let project = dir.join("p.camotics");
    let write_project = |margin: f64| {
        std::fs::write(
            &project,
            format!(
                r#"{{"units":"metric","tools":{{"1":{{"units":"metric","shape":"cylindrical","length":20,"diameter":6}}}},"workpiece":{{"automatic":true,"margin":{margin}}}}}"#
            ),
        )
        .unwrap();
    };
    let run = || {
        swarf(&[
            "simulate",
            "--program",
            prog.to_str().unwrap(),
            "--tools",
            project.to_str().unwrap(),
            "--resolution",
            "0.1",
            "--json",
        ])
    };
    write_project(0.0);
    let o = run();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("stock box:-3,-3,-4,13,3,0"),
        "{}",
        stderr(&o)
    );
    let j = json(&o);
    let exact = 4.0 * (10.0 * 6.0 + std::f64::consts::PI * 9.0);
    let removed = j["removed_volume_mm3"].as_f64().unwrap();
    assert!(
        (removed - exact).abs() < 0.005 * exact,
        "{removed} vs {exact}"
    );
    let stock = j["stock_volume_mm3"].as_f64().unwrap();
    assert!((stock - 16.0 * 6.0 * 4.0).abs() < 1e-6, "{stock}");
    // 50 %: 8, 3 and 2 mm more on each side, none on top.
    write_project(50.0);
    let o = run();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("stock box:-11,-6,-6,21,6,0"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_heidenhain_program_is_simulated_in_its_blank() {
    let dir = temp_dir("heidenhain");
    let prog = dir.join("SLOT.H");
    // A 6 mm slot 4 mm deep, 10 mm long, in a 40 × 20 × 10 mm blank given as its least corner
    // and the incremental size.
    std::fs::write(
        &prog,
        "0 BEGIN PGM SLOT MM\n1 BLK FORM 0.1 Z X-20 Y-10 Z-10\n2 BLK FORM 0.2 IX+40 IY+20 IZ+10\n\
         3 TOOL CALL 1 Z S1000 F100\n4 L X+0 Y+0 Z+5 R0 FMAX M3\n5 L Z-4\n6 L X+10\n\
         7 L Z+5 FMAX\n8 END PGM SLOT MM\n",
    )
    .unwrap();
    let o = swarf(&[
        "simulate",
        "--program",
        prog.to_str().unwrap(),
        "--tool",
        "flat:d=6",
        "--resolution",
        "0.1",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("stock box:-20,-10,-10,20,10,0 (the program's BLK FORM)"),
        "{}",
        stderr(&o)
    );
    let j = json(&o);
    let stock = j["stock_volume_mm3"].as_f64().unwrap();
    assert!((stock - 8000.0).abs() < 1e-6, "{stock}");
    let exact = 4.0 * (10.0 * 6.0 + PI * 9.0);
    let removed = j["removed_volume_mm3"].as_f64().unwrap();
    assert!(
        (removed - exact).abs() < 0.005 * exact,
        "{removed} vs {exact}"
    );
}

#[test]
fn a_sinumerik_program_is_simulated() {
    let dir = temp_dir("sinumerik");
    let prog = dir.join("SLOT.MPF");
    // The same 6 mm slot, 4 mm deep and 10 mm long, as a Siemens post writes it: the depth
    // through R parameters, the move with an incremental coordinate.
    std::fs::write(
        &prog,
        "; slot\nN10 G40 G17 G710 G94 G90\nN20 T=\"FLAT_6\"\nN30 M6\nN40 G0 G54 X0 Y0 Z5 S1000 M3\n\
         N50 R1=-4\nN60 G1 Z=R1 F100\nN70 X=IC(10)\nN80 G0 SUPA Z5 D0\nN90 M30\n",
    )
    .unwrap();
    let o = swarf(&[
        "simulate",
        "--program",
        prog.to_str().unwrap(),
        "--stock",
        "box:-20,-10,-10,20,10,0",
        "--tool",
        "flat:d=6",
        "--resolution",
        "0.1",
        "--home",
        "0,0,0",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j = json(&o);
    let exact = 4.0 * (10.0 * 6.0 + PI * 9.0);
    let removed = j["removed_volume_mm3"].as_f64().unwrap();
    assert!(
        (removed - exact).abs() < 0.005 * exact,
        "{removed} vs {exact}"
    );
}

#[test]
fn a_heidenhain_tool_table_gives_the_named_tools() {
    let dir = temp_dir("heidenhain-tool-t");
    let table = dir.join("TOOL.T");
    std::fs::write(
        &table,
        "BEGIN TOOL    .T     MM\n\
         T    NAME                L           R           R2          LCUTS   CUT  TYP\n\
         0    NULLWERKZEUG        +0          +0          +0          +0      0    MILL\n\
         2    BALL_D6             +60         +3          +3          +12     2    BALL\n\
         [END]\n",
    )
    .unwrap();
    let prog = dir.join("P.H");
    // A 6 mm ball plunged 3 mm deep (a half sphere) and moved 10 mm (a half cylinder).
    std::fs::write(
        &prog,
        "0 BEGIN PGM P MM\n1 BLK FORM 0.1 Z X-20 Y-10 Z-10\n2 BLK FORM 0.2 X+20 Y+10 Z+0\n\
         3 TOOL CALL \"ball_d6\" Z S1000 F100\n4 L X+0 Y+0 Z+5 R0 FMAX M3\n5 L Z-3\n6 L X+10\n\
         7 L Z+5 FMAX\n8 END PGM P MM\n",
    )
    .unwrap();
    let o = swarf(&[
        "simulate",
        "--program",
        prog.to_str().unwrap(),
        "--tools",
        table.to_str().unwrap(),
        "--resolution",
        "0.1",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let removed = json(&o)["removed_volume_mm3"].as_f64().unwrap();
    let exact = 2.0 / 3.0 * PI * 27.0 + 10.0 * PI * 9.0 / 2.0;
    assert!(
        (removed - exact).abs() < 0.005 * exact,
        "{removed} vs {exact}"
    );
}

/// With its stdout closed (`swarf simulate … | head -1`), a run still writes its files and ends
/// with status 0: the closed pipe only ends the printing.
#[test]
fn a_closed_stdout_still_gets_the_files_written() {
    let dir = temp_dir("simulate-closed-pipe");
    let prog = dir.join("p.nc");
    std::fs::write(&prog, "G21 G90\nG0 X5 Y5 Z5\nG1 Z-2 F100\nG1 X30\nM30\n").unwrap();
    let out = dir.join("out");
    let (status, err) = swarf_into_closed_pipe(&[
        "simulate",
        "--stock",
        "box:0,0,-10,40,20,0",
        "--program",
        prog.to_str().unwrap(),
        "--tool",
        "flat:d=6",
        "--resolution",
        "0.5",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(status.success(), "{status}, {err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(out.join("summary.json").is_file(), "{err}");
}

/// A chordal tolerance far below an arc's rounding needs more chords than any cut can take:
/// the arc is refused with its line (the chord count was infinite: a capacity overflow on a
/// worker, and the process spun for ever).
#[test]
fn an_arc_below_its_rounding_is_refused_not_hung() {
    let dir = temp_dir("simulate-tiny-tolerance");
    let prog = dir.join("circ.ngc");
    std::fs::write(
        &prog,
        "G21 G90\nG0 X5 Y10 Z5\nG1 Z-2 F300\nG2 X5 Y10 I10 J0 P2\nG0 Z5\nM30\n",
    )
    .unwrap();
    let p = prog.to_str().unwrap();
    for cmd in [
        vec![
            "simulate",
            "--stock",
            "box:0,0,-10,40,20,0",
            "--tolerance",
            "1e-300",
        ],
        vec!["envelope", "--tolerance", "1e-300"],
    ] {
        let out = dir.join(cmd[0]);
        let mut args = cmd.clone();
        args.extend([
            "--program",
            p,
            "--tool",
            "flat:d=4",
            "--resolution",
            "0.5",
            "--out",
            out.to_str().unwrap(),
        ]);
        let o = swarf(&args);
        assert_eq!(o.status.code(), Some(1), "{cmd:?}: {}", stderr(&o));
        let e = stderr(&o);
        assert!(
            e.contains("(line 4)") && e.contains("chords"),
            "{cmd:?}: {e}"
        );
        assert!(!e.contains("panicked"), "{e}");
    }
}

/// A tool nothing defines is named with the line where it first moves.
#[test]
fn an_undefined_tool_is_named_with_its_line() {
    let dir = temp_dir("simulate-undefined-tool");
    let prog = dir.join("ut.ngc");
    std::fs::write(&prog, "G21 G90\nT5 M6\nG0 X0 Y0 Z5\nG1 Z-1 F100\nM30\n").unwrap();
    let table = dir.join("tools.tbl");
    std::fs::write(&table, "T1 P1 D6 ;flat\n").unwrap();
    let o = swarf(&[
        "simulate",
        "--stock",
        "box:-10,-10,-5,10,10,0",
        "--program",
        prog.to_str().unwrap(),
        "--tools",
        table.to_str().unwrap(),
        "--resolution",
        "0.5",
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("ut.ngc:3: the program uses tool 5, which nothing defines"),
        "{e}"
    );
}

#[test]
fn a_program_that_never_reaches_the_stock_is_said() {
    // A slot at X100–150 beside a block at X0–40: nothing removed, said (it was silent).
    let dir = temp_dir("outside");
    let prog = dir.join("outside.ngc");
    std::fs::write(
        &prog,
        "G21 G90\nG0 X100 Y10 Z5\nG1 Z-3 F200\nG1 X150\nG0 Z5\nM30\n",
    )
    .unwrap();
    let run = |stock: &str| {
        swarf(&[
            "simulate",
            "--stock",
            stock,
            "--program",
            prog.to_str().unwrap(),
            "--tool",
            "flat:d=6",
            "--resolution",
            "0.5",
            "--json",
        ])
    };
    let o = run("box:0,0,-10,40,20,0");
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(json(&o)["removed_volume_mm3"].as_f64(), Some(0.0));
    assert!(
        stderr(&o).contains("no move removed material"),
        "{}",
        stderr(&o)
    );
    // Where it cuts, no such word.
    let o = run("box:90,0,-10,160,20,0");
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("no move removed"), "{}", stderr(&o));
}
