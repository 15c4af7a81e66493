//! The reader options every program command takes: `--subroutine-path`, `--dialect`, and the
//! tool diameters cutter compensation reads from `--tools` (or `--tool` for every tool).

mod common;

use std::path::PathBuf;

use common::{json, stderr, swarf};

fn dir(name: &str) -> PathBuf {
    let d = swarf_testdata::scratch_dir(&format!("readopts-{name}"));
    d
}

#[test]
fn subroutines_are_found_on_the_subroutine_path() {
    let d = dir("sub");
    let lib = d.join("lib");
    std::fs::create_dir_all(&lib).unwrap();
    std::fs::write(
        lib.join("square.ngc"),
        "o<square> sub\nG1 X#1 F100\nG1 Y#1\no<square> endsub\nM2\n",
    )
    .unwrap();
    let prog = d.join("main.ngc");
    std::fs::write(&prog, "G21 G90\nG0 X0 Y0 Z1\no<square> call [10]\nM2\n").unwrap();
    let p = prog.to_str().unwrap();
    let o = swarf(&["path", p, "--json"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("square"), "{}", stderr(&o));
    let o = swarf(&[
        "path",
        p,
        "--subroutine-path",
        lib.to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(json(&o)["feed_moves"], 2);
}

#[test]
fn the_dialect_can_be_forced() {
    // Axis words after G80 with no motion code: a Fanuc control moves them with the last
    // G0–G3; LinuxCNC refuses them ("cannot use axis values with G80").
    let d = dir("dialect");
    let prog = d.join("cycle.nc");
    std::fs::write(
        &prog,
        "G21 G90 G17\nG0 X0 Y0 Z5\nG81 X0 Y0 Z-1 R1 F100\nX10\nG80\nX20\nM30\n",
    )
    .unwrap();
    let p = prog.to_str().unwrap();
    let o = swarf(&["path", p, "--dialect", "fanuc", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = swarf(&["path", p, "--dialect", "linuxcnc", "--json"]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let o = swarf(&["path", p, "--dialect", "heidenhain"]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn compensation_takes_the_diameter_from_the_tools() {
    let d = dir("comp");
    let prog = d.join("comp.ngc");
    // A 20 mm square contour with G41 D7: the compensated tip path is offset by the radius.
    std::fs::write(
        &prog,
        "G21 G90 F100 T7 M6\nG0 X10 Y5\nG41 D7\nG1 Y0\nX20\nY20\nX0\nY0\nX10\nG40\nG1 Y5\nM2\n",
    )
    .unwrap();
    let p = prog.to_str().unwrap();
    let o = swarf(&["path", p, "--json"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("diameter of tool 7"), "{}", stderr(&o));
    let lib = d.join("tools.toml");
    std::fs::write(&lib, "[[tool]]\nnumber = 7\nspec = \"flat:d=6\"\n").unwrap();
    let bbox = |args: &[&str]| {
        let mut a = vec!["path", p, "--json"];
        a.extend_from_slice(args);
        let o = swarf(&a);
        assert!(o.status.success(), "{}", stderr(&o));
        let j = json(&o);
        (
            j["feed_bbox_min"][0].as_f64().unwrap(),
            j["feed_bbox_max"][0].as_f64().unwrap(),
        )
    };
    // G41 keeps the tool left of the path: inside this counter-clockwise square, by the radius.
    let (lo, hi) = bbox(&["--tools", lib.to_str().unwrap()]);
    assert!(
        (lo - 3.0).abs() < 1e-9 && (hi - 17.0).abs() < 1e-9,
        "{lo} {hi}"
    );
    let (lo, hi) = bbox(&["--tool", "flat:d=4"]);
    assert!(
        (lo - 2.0).abs() < 1e-9 && (hi - 18.0).abs() < 1e-9,
        "{lo} {hi}"
    );
}

/// `--ini`: a LinuxCNC machine's INI gives the subroutine path, the machine's units (a program
/// without G20/G21 is read in its inches), the tool table (when no --tool/--tools) and the M6
/// moves (TOOL_CHANGE_QUILL_UP: a rapid up to machine Z0 before the change).
#[test]
fn a_linuxcnc_ini_sets_up_the_machine() {
    let d = dir("ini");
    std::fs::create_dir_all(d.join("lib")).unwrap();
    std::fs::write(
        d.join("m.ini"),
        "[RS274NGC]\nSUBROUTINE_PATH = lib\n[EMCIO]\nTOOL_TABLE = tools.tbl\n\
         TOOL_CHANGE_QUILL_UP = 1\n[TRAJ]\nLINEAR_UNITS = inch\n",
    )
    .unwrap();
    std::fs::write(d.join("tools.tbl"), "T1 P1 D0.25 Z1 ;quarter inch\n").unwrap();
    std::fs::write(
        d.join("lib").join("sq.ngc"),
        "o<sq> sub\nG1 X1 F10\nY1\no<sq> endsub\n",
    )
    .unwrap();
    let prog = d.join("p.ngc");
    std::fs::write(&prog, "G0 X0 Y0 Z-0.5\nT1 M6\nG0 Z0.1\no<sq> call\nM2\n").unwrap();
    let p = prog.to_str().unwrap();
    let ini = d.join("m.ini");
    let o = swarf(&["path", p, "--ini", ini.to_str().unwrap(), "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j = json(&o);
    // 1 in by 1 in, in inches; rapids 0.5 in down, 0.5 in up (quill up), 0.1 in up.
    assert!(
        (j["feed_length_mm"].as_f64().unwrap() - 50.8).abs() < 1e-9,
        "{j}"
    );
    assert!(
        (j["rapid_length_mm"].as_f64().unwrap() - 1.1 * 25.4).abs() < 1e-9,
        "{j}"
    );
    // The table's T1 is a quarter inch.
    assert!(stderr(&o).contains("6.35 mm"), "{}", stderr(&o));
    // --initial-units wins over the machine's.
    let o = swarf(&[
        "path",
        p,
        "--ini",
        ini.to_str().unwrap(),
        "--initial-units",
        "mm",
        "--json",
    ]);
    assert!((json(&o)["feed_length_mm"].as_f64().unwrap() - 2.0).abs() < 1e-9);
    // The first M6's quill-up rapid is the new tool's (the spindle held none): simulate runs.
    let sim = d.join("sim.ngc");
    std::fs::write(
        &sim,
        "G20 G90\nT1 M6\nG0 X0 Y0 Z0.1\nG1 Z-0.05 F10\nX0.5\nM2\n",
    )
    .unwrap();
    let out = d.join("sim_out");
    let o = swarf(&[
        "simulate",
        "--stock",
        "box:-5,-5,-5,20,5,0",
        "--program",
        sim.to_str().unwrap(),
        "--ini",
        ini.to_str().unwrap(),
        "--resolution",
        "0.5",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    // CL data is the CAM system's: the machine's inches do not apply to it.
    let apt = d.join("a.apt");
    std::fs::write(
        &apt,
        "CUTTER/6\nFROM/0,0,5\nFEDRAT/100\nGOTO/10,0,5\nFINI\n",
    )
    .unwrap();
    let o = swarf(&[
        "path",
        apt.to_str().unwrap(),
        "--ini",
        ini.to_str().unwrap(),
        "--json",
    ]);
    assert!((json(&o)["feed_length_mm"].as_f64().unwrap() - 10.0).abs() < 1e-9);
    // A bad setting names the INI's line.
    std::fs::write(d.join("bad.ini"), "[EMCIO]\nTOOL_CHANGE_AT_G30 = maybe\n").unwrap();
    let bad = d.join("bad.ini");
    let o = swarf(&["path", p, "--ini", bad.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("bad.ini:2:1"), "{}", stderr(&o));
}
