//! What the user reads for bad input: no silent drops, no Rust internals, every message once,
//! and the stock or program that cannot be used named with what was expected.
mod common;
use common::*;

/// A one-line program in a folder of its own; its path.
fn program(name: &str, text: &str) -> String {
    let p = temp_dir(name).join(format!("{name}.ngc"));
    std::fs::write(&p, text).unwrap();
    p.display().to_string()
}

/// The system's words for a missing file (they differ between systems).
fn not_found(path: &std::path::Path) -> String {
    std::fs::read(path).unwrap_err().to_string()
}

/// `command` on the 10 × 10 × 5 mm block with `program`, then `more`.
fn on_block<'a>(command: &'a str, program: &'a str, more: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec![
        command,
        "--stock",
        "box:0,0,-5,10,10,0",
        "--program",
        program,
    ];
    args.extend_from_slice(more);
    args
}

fn no_internals(e: &str) {
    for bad in [
        "Some(",
        "None",
        "GcodeOptions",
        "18446744073709551615",
        "panicked",
    ] {
        assert!(!e.contains(bad), "{bad:?} in {e}");
    }
}

#[test]
fn a_bad_tool_spec_is_said_once() {
    let o = swarf(&["tool", "bull:d=16,r=9"]);
    assert_eq!(o.status.code(), Some(1));
    let e = stderr(&o);
    assert_eq!(
        e.matches("corner radius r = 9 mm is too large").count(),
        1,
        "{e}"
    );
    no_internals(&e);
}

#[test]
fn a_negative_resolution_says_it_must_be_positive() {
    let p = program("negres", "G21 G90 G0 X0 Y0 Z5\nG1 Z-1 F100\nG1 X5\nM2\n");
    for args in [
        &[
            "simulate",
            "--stock",
            "box:0,0,-5,10,10,0",
            "--program",
            &p,
            "--tool",
            "flat:d=6",
            "--resolution",
            "-1",
        ][..],
        &[
            "simulate",
            "--stock",
            "box:0,0,-5,10,10,0",
            "--program",
            &p,
            "--tool",
            "flat:d=6",
            "--tolerance",
            "-0.5",
        ][..],
    ] {
        let o = swarf(args);
        let e = stderr(&o);
        assert_ne!(o.status.code(), Some(0), "{e}");
        assert!(e.contains("must be a positive"), "{e}");
        assert!(!e.contains("unexpected argument"), "{e}");
    }
}

#[test]
fn a_huge_stock_is_an_error_not_a_panic() {
    let p = program("hugestock", "G21 G90 G0 X0 Y0 Z5\nG1 Z-1 F100\nG1 X5\nM2\n");
    let o = swarf(&[
        "simulate",
        "--stock",
        "box:0,0,-1e30,1,1,0",
        "--program",
        &p,
        "--tool",
        "flat:d=6",
    ]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(e.contains("machine range"), "{e}");
    no_internals(&e);
}

#[test]
fn absurd_coordinates_are_an_error_at_their_position() {
    let p = program(
        "absurd",
        &format!("G21 G90 G0 X0 Y0 Z5\nG1 X1{} F100\nM2\n", "0".repeat(300)),
    );
    for cmd in [
        &["path", &p, "--json"][..],
        &[
            "simulate",
            "--stock",
            "box:0,0,-5,10,10,0",
            "--program",
            &p,
            "--tool",
            "flat:d=6",
        ][..],
    ] {
        let o = swarf(cmd);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(1), "{e}");
        assert!(
            e.contains("absurd.ngc:2:4") && e.contains("machine range"),
            "{e}"
        );
    }
}

#[test]
fn a_loop_limit_message_speaks_the_users_language() {
    let p = program("endless", "G21 G90\no1 while [1]\no1 endwhile\nM2\n");
    let o = swarf(&["path", &p]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(e.contains("loop iterations"), "{e}");
    no_internals(&e);
}

#[test]
fn a_zero_feed_is_said_on_stderr_too() {
    let dir = temp_dir("fedrat0");
    let p = dir.join("f0.apt");
    std::fs::write(&p, "UNITS/MM\nFEDRAT/0\nGOTO/0,0,5\nGOTO/10,0,5\nFINI\n").unwrap();
    // In the JSON (under "notes") and in the text summary alike, stderr says it.
    for args in [
        &["path", p.to_str().unwrap(), "--json"][..],
        &["path", p.to_str().unwrap()][..],
    ] {
        let o = swarf(args);
        assert!(o.status.success(), "{}", stderr(&o));
        let e = stderr(&o);
        assert!(
            e.contains("note: 1 feed move(s) without a usable feed rate"),
            "{args:?}: {e}"
        );
    }
}

#[test]
fn a_linuxcnc_tool_with_a_negative_diameter_is_an_error_at_its_line() {
    let dir = temp_dir("tbl");
    let tbl = dir.join("tools.tbl");
    std::fs::write(&tbl, "T1 P1 D6 Z50\nT2 P2 D-1 Z0\n").unwrap();
    let p = program(
        "tbl-program",
        "G21 G90 T1 M6\nG0 X0 Y0 Z5\nG1 Z-1 F100\nM2\n",
    );
    let o = swarf(&["path", &p, "--tools", tbl.to_str().unwrap()]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(
        e.contains("tools.tbl:2:8") && e.contains("a diameter (D) of 0 or more"),
        "{e}"
    );
    // A D0 probe is left out, the table serves, and the summary says why the probe is not
    // defined when the program loads it.
    std::fs::write(&tbl, "T1 P1 D6 Z50\nT2 P2 D0 Z0 ;probe\n").unwrap();
    let p = program(
        "tbl-probe",
        "G21 G90 T1 M6\nG0 X0 Y0 Z5\nG1 Z-1 F100\nT2 M6\nG0 Z10\nM2\n",
    );
    let o = swarf(&["path", &p, "--tools", tbl.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout).to_string();
    assert!(
        out.contains("T2: left out of the tool library (") && out.contains("T2 has no diameter"),
        "{out}"
    );
}

#[test]
fn an_open_stock_mesh_that_encloses_nothing_is_an_error() {
    let dir = temp_dir("openmesh");
    let stl = dir.join("open.stl");
    // A box missing its +X face: rays along X find no way out.
    std::fs::write(
        &stl,
        boxes_stl(&[[[0.0, 0.0, -10.0], [20.0, 20.0, 0.0]]], 2),
    )
    .unwrap();
    let p = program(
        "openmesh-program",
        "G21 G90 G0 X5 Y5 Z5\nG1 Z-1 F100\nG1 X10\nM2\n",
    );
    let o = swarf(&[
        "simulate",
        "--stock",
        stl.to_str().unwrap(),
        "--allow-open-mesh",
        "--program",
        &p,
        "--tool",
        "flat:d=6",
        "--json",
    ]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(e.contains("encloses no material"), "{e}");
}

#[test]
fn a_missing_program_and_an_output_that_is_a_file_are_said_once() {
    let p = program("outfile", "G21 G90 G0 X0 Y0 Z5\nG1 Z-1 F100\nG1 X5\nM2\n");
    let missing = std::path::Path::new(&p).with_file_name("missing.ngc");
    let o = swarf(&on_block(
        "simulate",
        missing.to_str().unwrap(),
        &["--tool", "flat:d=6"],
    ));
    assert_eq!(o.status.code(), Some(1));
    let e = stderr(&o);
    // Named as a whole file (no line 0), the reason once.
    assert!(
        e.contains(&format!("{}: cannot read the program", missing.display())),
        "{e}"
    );
    assert_eq!(e.matches(&not_found(&missing)).count(), 1, "{e}");
    // An output folder that is a file.
    let o = swarf(&on_block(
        "engage",
        &p,
        &["--tool", "flat:d=6", "--out", &p],
    ));
    assert_eq!(o.status.code(), Some(1));
    let e = stderr(&o);
    assert_eq!(e.matches("exists and is not a folder").count(), 1, "{e}");
    assert_eq!(e.matches(p.as_str()).count(), 1, "{e}");
    no_internals(&e);
}

#[test]
fn each_unreadable_input_file_is_named_once() {
    let p = program("files", "G21 G90 G0 X0 Y0 Z5\nG1 Z-1 F100\nG1 X5\nM2\n");
    let dir = std::path::Path::new(&p).parent().unwrap().to_path_buf();
    let file = |name: &str, text: &str| {
        let f = dir.join(name);
        std::fs::write(&f, text).unwrap();
        f.display().to_string()
    };
    let machine = file("m.toml", "garbage = [\n");
    let missing = |name: &str| dir.join(name).display().to_string();
    let (table, surface) = (missing("t.tbl"), missing("s.json"));
    let gone = not_found(&dir.join("t.tbl"));
    let material = file("al.toml", "ktc 12\n");
    let cases: Vec<(Vec<&str>, String, &str)> = vec![
        (
            on_block(
                "simulate",
                &p,
                &["--tool", "flat:d=6", "--machine", &machine],
            ),
            machine.clone(),
            "TOML parse error",
        ),
        (
            on_block("simulate", &p, &["--tools", &table]),
            table.clone(),
            gone.as_str(),
        ),
        (
            vec![
                "toolsize",
                "--surface",
                &surface,
                "--cutter",
                "ball",
                "--out",
                "x",
            ],
            surface.clone(),
            gone.as_str(),
        ),
        (
            on_block(
                "forces",
                &p,
                &[
                    "--tool",
                    "flat:d=6,flutes=2",
                    "--coefficients",
                    &material,
                    "--out",
                    "x",
                ],
            ),
            material.clone(),
            "(a material file is TOML",
        ),
    ];
    for (args, name, why) in cases {
        let o = swarf(&args);
        assert_eq!(o.status.code(), Some(1), "{args:?}");
        let e = stderr(&o);
        assert_eq!(e.matches(name.as_str()).count(), 1, "{e}");
        assert_eq!(e.matches(why).count(), 1, "{e}");
        assert!(!e.contains("found expected") && !e.contains(":0:"), "{e}");
        no_internals(&e);
    }
}

/// A CAMotics project with a spheroid (a shape swarf cannot model) still serves its other
/// tools; a program that loads the spheroid is refused, the message naming the tool, its
/// place in the project and why.
#[test]
fn a_camotics_spheroid_refuses_only_the_program_that_uses_it() {
    let dir = temp_dir("camotics_spheroid");
    let project = dir.join("p.camotics");
    std::fs::write(
        &project,
        "{\"units\": \"metric\", \"tools\": {\n\
         \"1\": {\"shape\": \"CYLINDRICAL\", \"length\": 20, \"diameter\": 4},\n\
         \"3\": {\"shape\": \"spheroid\", \"length\": 10, \"diameter\": 6}}}\n",
    )
    .unwrap();
    let project = project.display().to_string();
    let run = |tool: &str| {
        let p = program(
            &format!("camotics_spheroid_t{tool}"),
            &format!("G21 G90\nT{tool} M6\nG0 X2 Y5 Z5\nG1 Z-1 F100\nG1 X8\nM2\n"),
        );
        swarf(&on_block("simulate", &p, &["--tools", &project, "--json"]))
    };
    let o = run("1");
    assert!(o.status.success(), "{}", stderr(&o));
    let o = run("3");
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("the program uses tool 3, which the tool library defines but swarf cannot use")
            && e.contains(
                "p.camotics:3:1: tool 3 is a spheroid (an ellipsoid 6 mm wide, 10 mm long)"
            ),
        "{e}"
    );
    no_internals(&e);
}
