//! `swarf path PROGRAM`: the summary and canonical-output contracts.
mod common;
use common::*;

const SUMMARY_KEYS: [&str; 11] = [
    "moves",
    "rapid_moves",
    "feed_moves",
    "arc_moves",
    "feed_length_mm",
    "rapid_length_mm",
    "bbox_min",
    "bbox_max",
    "tools",
    "warnings",
    "machining_time_s",
];

#[test]
fn summary_has_every_contract_key_for_every_shared_program() {
    let Some(files) = swarf_testdata::paths([
        "gcode/camotics_heart.ngc",
        "gcode/camotics_heart_cutout.ngc",
        "gcode/camotics_wave.gcode",
        "gcode/linuxcnc_boat-xyzac.ngc",
        "gcode/linuxcnc_interp_g17-g99-g81.ngc",
        "gcode/linuxcnc_spiral.ngc",
        "apt/nx_1_KONTUR_NAR_40_N2.cls",
        "apt/swcam_Paralelipipedo.apt",
    ]) else {
        return;
    };
    for f in files {
        let f = f.display().to_string();
        let o = swarf(&["path", &f, "--json"]);
        assert!(o.status.success(), "{f}: {}", stderr(&o));
        let j = json(&o);
        for k in SUMMARY_KEYS {
            assert!(j.get(k).is_some(), "{f}: key {k} missing in {j}");
        }
        assert!(j["moves"].as_u64().unwrap() > 0, "{f}");
    }
}

#[test]
fn canonical_output_matches_linuxcnc_interpreter() {
    let Some([ngc, expected]) = swarf_testdata::paths([
        "gcode/linuxcnc_interp_g17-g99-g81.ngc",
        "gcode/linuxcnc_interp_g17-g99-g81.expected",
    ]) else {
        return;
    };
    let o = swarf(&["path", ngc.to_str().unwrap(), "--canonical"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let expected = std::fs::read_to_string(expected).unwrap();
    let want: Vec<&str> = expected
        .lines()
        .filter(|l| {
            l.contains("STRAIGHT_TRAVERSE(")
                || l.contains("STRAIGHT_FEED(")
                || l.contains("ARC_FEED(")
        })
        .collect();
    let out = stdout(&o);
    let got: Vec<&str> = out.lines().collect();
    assert_eq!(got, want);
}

#[test]
fn spiral_summary_is_worked_out_independently() {
    // The spiral of LinuxCNC's nc_files/spiral.ngc, written here (G20): G0 Z1; G0 X2 Y0;
    // G1 Z-.1 F24; then 800 incremental polar moves `G91 G1 @-.0025 ^4.5` in an O-word repeat:
    // in G91 LinuxCNC adds @ to the current distance from the origin and ^ to the current
    // angle, so point k is (2 - 0.0025 k) at 4.5 k degrees.
    let dir = temp_dir("spiral");
    let program = dir.join("spiral.ngc");
    std::fs::write(
        &program,
        "G20 G90 G17\nG0 Z1\nG0 X2 Y0\nG1 Z-.1 F24\no100 repeat [800]\n  G91 G1 @-.0025 ^4.5\n\
         o100 endrepeat\nG90 G0 Z1\nM2\n",
    )
    .unwrap();
    let o = swarf(&["path", program.to_str().unwrap(), "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j = json(&o);
    assert_eq!(j["feed_moves"].as_u64(), Some(801), "{j}");
    assert_eq!(j["rapid_moves"].as_u64(), Some(3), "{j}");
    assert_eq!(j["arc_moves"].as_u64(), Some(0), "{j}");
    let p = |k: f64| {
        let (r, a) = (2.0 - 0.0025 * k, (4.5 * k).to_radians());
        (r * a.cos(), r * a.sin())
    };
    let mut feed = 1.1;
    for k in 1..=800 {
        let (a, b) = (p(k as f64 - 1.0), p(k as f64));
        feed += (b.0 - a.0).hypot(b.1 - a.1);
    }
    let feed_mm = feed * 25.4;
    let got = j["feed_length_mm"].as_f64().unwrap();
    assert!((got - feed_mm).abs() < 1e-6 * feed_mm, "{got} vs {feed_mm}");
    // 24 in/min over the whole feed path.
    let t = feed / 24.0 * 60.0;
    assert!(
        (j["machining_time_s"].as_f64().unwrap() - t).abs() < 1e-6 * t,
        "{j}"
    );
    assert!(
        (j["bbox_max"][0].as_f64().unwrap() - 50.8).abs() < 1e-9,
        "{j}"
    );
    assert!(
        (j["bbox_max"][2].as_f64().unwrap() - 25.4).abs() < 1e-9,
        "{j}"
    );
    assert!(
        (j["bbox_min"][2].as_f64().unwrap() + 2.54).abs() < 1e-9,
        "{j}"
    );
}

/// A Fanuc (Haas) program's `G41 … D1` offsets by the control's register D1: without a tool
/// table the path is read as the tool centre's (CAM wear compensation), with a warning naming
/// the line; a LinuxCNC program, whose tool table gives the diameters, still stops there.
#[test]
fn cutter_compensation_without_its_offset() {
    let Some(ptp) = shared("gcode/nx_haas_vf3_testpart.ptp") else {
        return;
    };
    let o = swarf(&["path", &ptp, "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j = json(&o);
    let w: Vec<&serde_json::Value> = j["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|w| w["message"].as_str().unwrap().contains("register D1"))
        .collect();
    assert_eq!(w.len(), 1, "{j}");
    assert_eq!(
        (w[0]["line"].as_u64(), w[0]["column"].as_u64()),
        (Some(33), Some(8))
    );
    let dir = temp_dir("path-comp");
    let p = dir.join("comp.ngc");
    std::fs::write(
        &p,
        "G21 G90\nG0 X-10 Y-10\nG41 D1 G1 X0 Y0 F100\nX20\nG40 X30\nM30\n",
    )
    .unwrap();
    let o = swarf(&["path", p.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    let e = stderr(&o);
    assert!(
        e.contains("comp.ngc:3:5:") && e.contains("compensation"),
        "{e}"
    );
}

#[test]
fn malformed_program_names_file_line_and_column() {
    let dir = swarf_testdata::scratch_dir("cli-test");
    let p = dir.join("bad.ngc");
    std::fs::write(&p, "G21 G90\nG1 X1.2.3 F100\n").unwrap();
    let o = swarf(&["path", p.to_str().unwrap(), "--json"]);
    assert_eq!(o.status.code(), Some(1));
    let e = stderr(&o);
    assert!(e.contains("bad.ngc:2:"), "{e}");
    let missing = dir.join("missing.ngc");
    let o = swarf(&["path", missing.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("missing.ngc"));
}

#[test]
fn camotics_project_supplies_tools_and_workpiece() {
    let Some([ngc, project]) =
        swarf_testdata::paths(["gcode/camotics_heart.ngc", "gcode/camotics_heart.camotics"])
    else {
        return;
    };
    let o = swarf(&[
        "path",
        ngc.to_str().unwrap(),
        "--tools",
        project.to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j = json(&o);
    assert_eq!(
        j["workpiece"]["min"],
        serde_json::json!([-40.0, -40.0, -12.7]),
        "{j}"
    );
    assert_eq!(
        j["workpiece"]["max"],
        serde_json::json!([40.0, 40.0, 0.0]),
        "{j}"
    );
    // Tool 1 is a 0.1 in ball nose in the project.
    let t1 = &j["tool_definitions"]["1"]["cutter"];
    assert!(
        (t1["diameter_mm"].as_f64().unwrap() - 2.54).abs() < 1e-9,
        "{j}"
    );
    assert_eq!(t1["kind"], "ball", "{j}");
}

#[test]
fn the_program_may_be_given_as_every_other_command_takes_it() {
    // `swarf path --program FILE` is `swarf path FILE`; both at once, or neither, is an error.
    let dir = temp_dir("path_program_option");
    let file = dir.join("p.ngc");
    std::fs::write(&file, "G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F100\nG1 X10\nM2\n").unwrap();
    let f = file.to_str().unwrap();
    let positional = swarf(&["path", f, "--json"]);
    let option = swarf(&["path", "--program", f, "--json"]);
    assert!(positional.status.success(), "{}", stderr(&positional));
    assert!(option.status.success(), "{}", stderr(&option));
    assert_eq!(json(&positional), json(&option));
    for args in [vec!["path", f, "--program", f], vec!["path", "--json"]] {
        let o = swarf(&args);
        assert!(!o.status.success(), "{args:?} should be refused");
        let err = stderr(&o).to_lowercase();
        assert!(err.contains("program"), "{args:?}: {err}");
    }
}

/// A program named without a folder (`swarf path prog.ngc`, run where it is) finds its
/// subroutine files beside it, as one named with its folder does.
#[test]
fn a_program_named_without_its_folder_finds_its_subroutine_files() {
    let dir = temp_dir("path_bare_name");
    std::fs::write(
        dir.join("main.ngc"),
        "G21 G90\nG0 X0 Y0 Z5\no<side> call [7]\nM2\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("side.ngc"),
        "o<side> sub\nG1 X#1 F100\no<side> endsub\n",
    )
    .unwrap();
    for name in ["main.ngc", dir.join("main.ngc").to_str().unwrap()] {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_swarf"))
            .args(["path", name, "--json"])
            .current_dir(&dir)
            .output()
            .unwrap();
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        assert_eq!(json(&o)["feed_length_mm"], 7.0, "{name}");
    }
}

/// A CAMotics project with an automatic workpiece: `swarf path --json` states the box made from
/// the program (here with no margin: the slot's own box), as `swarf simulate` takes it.
#[test]
fn a_camotics_automatic_workpiece_is_stated() {
    let dir = temp_dir("path_camotics_auto");
    let prog = dir.join("slot.ngc");
    std::fs::write(
        &prog,
        "G21 G90\nT1 M6\nM3 S1000\nG0 X0 Y0 Z5\nG1 Z-4 F100\nG1 X10\nG0 Z5\nM2\n",
    )
    .unwrap();
    let project = dir.join("p.camotics");
    std::fs::write(
        &project,
        r#"{"units":"metric","tools":{"1":{"units":"metric","shape":"cylindrical","length":20,"diameter":6}},"workpiece":{"automatic":true,"margin":0}}"#,
    )
    .unwrap();
    let o = swarf(&[
        "path",
        prog.to_str().unwrap(),
        "--tools",
        project.to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let w = &json(&o)["workpiece"];
    assert_eq!(w["min"], serde_json::json!([-3.0, -3.0, -4.0]), "{w}");
    assert_eq!(w["max"], serde_json::json!([13.0, 3.0, 0.0]), "{w}");
    assert_eq!(w["automatic"], true, "{w}");
}

/// A reader that closes the pipe early (`swarf path p.nc | head -1`) ends the printing, not the
/// run: no panic (`println!` panicked, exit 101), exit status 0, nothing on stderr.
#[test]
fn a_closed_stdout_is_not_an_error() {
    let dir = temp_dir("path-closed-pipe");
    let prog = dir.join("p.nc");
    std::fs::write(&prog, "G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F100\nG1 X10\nM30\n").unwrap();
    for extra in [&[][..], &["--json"], &["--canonical"]] {
        let mut args = vec!["path", prog.to_str().unwrap()];
        args.extend_from_slice(extra);
        let (status, err) = swarf_into_closed_pipe(&args);
        assert!(status.success(), "{extra:?}: {status}, {err}");
        assert!(err.is_empty(), "{extra:?}: {err}");
    }
}

/// What the tool library's reader left out is told on stderr (it was kept in the table and
/// never shown): here an indexed tool and the null tool's row.
#[test]
fn a_tool_library_s_warnings_are_printed() {
    let dir = temp_dir("path-table-warnings");
    let prog = dir.join("p.nc");
    std::fs::write(&prog, "G21 G90\nT1 M6\nG0 X0 Y0 Z5\nG1 Z-1 F100\nM30\n").unwrap();
    let table = dir.join("TOOL.T");
    std::fs::write(
        &table,
        "BEGIN TOOL .T MM\nT    NAME     L      R\n0    NULL     +0     +0\n\
         1    MILL     +60    +3\n1.1  MILL_B   +60    +3\n[END]\n",
    )
    .unwrap();
    let o = swarf(&[
        "path",
        prog.to_str().unwrap(),
        "--tools",
        table.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("swarf: warning:") && err.contains("indexed tool 1.1 left out"),
        "{err}"
    );
    assert!(err.contains("define no cutter"), "{err}");
}

/// Text that cannot be written for another reason than a closed pipe (a full disk) is the
/// result lost: the run fails (it ended with success after a warning).
#[test]
fn a_full_stdout_fails_the_run() {
    let full = std::path::Path::new("/dev/full");
    if !full.exists() {
        return;
    }
    let dir = temp_dir("path-full");
    let prog = dir.join("p.nc");
    std::fs::write(&prog, "G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F100\nM30\n").unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_swarf"))
        .args(["path", prog.to_str().unwrap()])
        .stdout(std::fs::OpenOptions::new().write(true).open(full).unwrap())
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("writing to stdout"), "{}", stderr(&o));
}

#[test]
fn canonical_output_keeps_printed_lines_and_says_its_warnings_on_stderr() {
    // rs274 writes `(print,…)` text among the calls; a reader's warning is no call, so it
    // goes to stderr (it went nowhere).
    let dir = temp_dir("canonical_print");
    let ngc = dir.join("p.ngc");
    std::fs::write(&ngc, "G21 F100\n(print,hello x=#<_x>)\n/G1 X1\nG1 X2\nM2\n").unwrap();
    let o = swarf(&[
        "path",
        ngc.to_str().unwrap(),
        "--canonical",
        "--block-delete",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        stdout(&o).lines().collect::<Vec<_>>(),
        [
            "hello x=0.000000",
            " N..... STRAIGHT_FEED(2.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)"
        ]
    );
    assert!(
        stderr(&o).contains("p.ngc:3:1: warning: line skipped"),
        "{}",
        stderr(&o)
    );
    // Without --block-delete the line is read, as rs274 reads it, and said.
    let o = swarf(&["path", ngc.to_str().unwrap(), "--canonical"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        stdout(&o).lines().filter(|l| l.contains("FEED(")).count(),
        2
    );
    assert!(
        stderr(&o).contains("p.ngc:3:1: warning: line read"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn the_warnings_before_an_error_are_said_with_it() {
    // A Fanuc macro alarm stops the program: the warnings up to it (the dialect, the system
    // variable read as 0) explain it, in either output.
    let dir = temp_dir("path_error_warnings");
    let nc = dir.join("sv.nc");
    std::fs::write(&nc, "O1\nG21 G90\n#1=#2001\n#3000=12 (BROKEN TOOL)\nM30\n").unwrap();
    for extra in [&["--canonical"][..], &[][..]] {
        let mut args = vec!["path", nc.to_str().unwrap()];
        args.extend_from_slice(extra);
        let o = swarf(&args);
        assert!(!o.status.success());
        let e = stderr(&o);
        assert!(e.contains("sv.nc:3: warning: system variable #2001"), "{e}");
        assert!(e.contains("macro alarm 3012"), "{e}");
    }
}
