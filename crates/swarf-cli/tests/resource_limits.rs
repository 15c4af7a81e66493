//! The resource-limit harness: hostile inputs (huge coordinates, endless loops with moves, very
//! long programs, tiny resolutions with `--out`) run under a 2 GB address-space limit and end
//! with exit 1 and a clear message — never a panic (101) or an allocation abort (134) — or, for
//! the commands that stream, succeed within the limit.
//!
//! The workspace forbids unsafe code, so the limit is set by the shell (`ulimit -v`) that then
//! executes `swarf`.
mod common;
use common::*;

use std::io::Write;
use std::process::{Command, Output};

/// Address-space limit, KiB (about 2 GB).
const LIMIT_KIB: u64 = 2_000_000;

/// Runs `swarf` with the arguments under the address-space limit.
fn limited(args: &[&str]) -> Output {
    Command::new("sh")
        .arg("-c")
        .arg(format!("ulimit -v {LIMIT_KIB}; exec \"$0\" \"$@\""))
        .arg(env!("CARGO_BIN_EXE_swarf"))
        .args(args)
        .output()
        .expect("sh runs")
}

/// Exit 1 with `needles` in the message, no panic, no abort.
fn refused(o: &Output, needles: &[&str]) {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(1), "status {:?}: {e}", o.status);
    // (Warnings given before the error may come first: `swarf path` prints them.)
    assert!(e.lines().any(|l| l.starts_with("swarf: error: ")), "{e}");
    assert!(
        !e.contains("panicked") && !e.contains("memory allocation"),
        "{e}"
    );
    for n in needles {
        assert!(e.contains(n), "{n:?} not in {e}");
    }
}

/// `text` as `name` in a folder of its own; its path.
fn program(dir: &str, name: &str, text: &str) -> String {
    let p = temp_dir(dir).join(name);
    std::fs::write(&p, text).unwrap();
    p.display().to_string()
}

const ENDLESS: &str = "G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F600\no100 while [1]\nG1 X10\nG1 X0\n\
                       o100 endwhile\nM30\n";

#[test]
fn an_endless_loop_with_moves_stops_at_the_move_limit_under_2_gb() {
    let p = program("rl-endless", "endless.ngc", ENDLESS);
    let stock = "box:-10,-10,-5,20,10,0";
    for cmd in ["simulate", "envelope"] {
        let mut args = vec![cmd, "--program", &p, "--tool", "flat:d=6"];
        if cmd == "simulate" {
            args.extend(["--stock", stock]);
        } else {
            args.extend(["--out", "/nonexistent-swarf-out"]);
        }
        let o = limited(&args);
        refused(
            &o,
            &["endless.ngc:5", "more than 4000000 moves", "--max-moves N"],
        );
    }
    // A lower limit says so at once.
    let o = limited(&[
        "simulate",
        "--stock",
        stock,
        "--program",
        &p,
        "--tool",
        "flat:d=6",
        "--max-moves",
        "1000",
    ]);
    refused(&o, &["endless.ngc:5", "more than 1000 moves"]);
}

#[test]
fn swarf_path_streams_an_endless_loop_until_the_iteration_limit() {
    let p = program("rl-path-endless", "endless.ngc", ENDLESS);
    for extra in [&[][..], &["--json"], &["--canonical"]] {
        let mut args = vec!["path", p.as_str()];
        args.extend_from_slice(extra);
        let o = limited(&args);
        refused(&o, &["endless.ngc:7", "more than 10000000 loop iterations"]);
    }
    let o = limited(&["path", &p, "--max-moves", "50"]);
    refused(
        &o,
        &["endless.ngc:5", "more than 50 moves", "--max-moves N"],
    );
}

#[test]
fn swarf_path_summarises_six_million_moves_under_2_gb() {
    // Kept whole, six million moves take 1.9 GB (2.6 GB of vector capacity): over the limit.
    let dir = temp_dir("rl-long");
    let path = dir.join("long.ngc");
    let mut f = std::io::BufWriter::new(std::fs::File::create(&path).unwrap());
    writeln!(f, "G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F600").unwrap();
    for i in 0..3_000_000u32 {
        writeln!(f, "X{} Y1\nX{} Y0", i % 100, i % 100 + 1).unwrap();
    }
    writeln!(f, "M30").unwrap();
    drop(f);
    let p = path.display().to_string();
    let o = limited(&["path", &p, "--json"]);
    assert!(o.status.success(), "{:?}: {}", o.status, stderr(&o));
    let j = json(&o);
    assert_eq!(j["moves"], 6_000_002);
    assert_eq!(j["feed_moves"], 6_000_001);
    // The programs that keep their moves stop at the move limit instead.
    let o = limited(&[
        "simulate",
        "--stock",
        "box:-10,-10,-5,120,10,0",
        "--program",
        &p,
        "--tool",
        "flat:d=6",
    ]);
    refused(&o, &["long.ngc:", "more than 4000000 moves"]);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn huge_coordinates_are_refused_under_2_gb() {
    let p = program(
        "rl-huge",
        "huge.ngc",
        "G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F100\nG1 X1000000000000\nG1 X[10 ** 300]\nM30\n",
    );
    for cmd in [
        &["path", p.as_str()][..],
        &[
            "simulate",
            "--stock",
            "box:0,0,-5,10,10,0",
            "--program",
            &p,
            "--tool",
            "flat:d=6",
        ],
    ] {
        refused(&limited(cmd), &["huge.ngc:4", "machine range"]);
    }
    let line = program(
        "rl-line",
        "line.ngc",
        "G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F100\nG1 X5\nM30\n",
    );
    for stock in ["box:0,0,-1e30,1,1,0", "box:-1e5,-1e5,-1e5,1e5,1e5,0"] {
        let o = limited(&[
            "simulate",
            "--stock",
            stock,
            "--program",
            &line,
            "--tool",
            "flat:d=6",
        ]);
        refused(&o, &["stock"]);
    }
}

#[test]
fn a_tiny_resolution_with_out_is_refused_before_anything_is_written() {
    // At 0.02 mm the machined slot's mesh would be 2.3 GB of STL and 0.8 GB of glb.
    let p = program(
        "rl-tiny",
        "slot.ngc",
        "G21 G90\nG0 X10 Y20 Z5\nG1 Z-3 F200\nG1 X50\nG0 Z5\nM30\n",
    );
    let out = temp_dir("rl-tiny-out").join("out");
    let o = limited(&[
        "simulate",
        "--stock",
        "box:0,0,-20,60,40,0",
        "--program",
        &p,
        "--tool",
        "flat:d=10",
        "--resolution",
        "0.02",
        "--out",
        out.to_str().unwrap(),
    ]);
    refused(
        &o,
        &[
            "the outputs would take 3.11 GB (stock.stl 2.29 GB, stock.glb 824.4 MB",
            "more than the limit of 2.00 GB; nothing was written",
            "--max-output-mb",
        ],
    );
    assert!(!out.exists(), "nothing written, not even the folder");
    // A lower limit refuses a set the default would let through.
    let o = limited(&[
        "simulate",
        "--stock",
        "box:0,0,-20,60,40,0",
        "--program",
        &p,
        "--tool",
        "flat:d=10",
        "--resolution",
        "0.25",
        "--out",
        out.to_str().unwrap(),
        "--max-output-mb",
        "1",
    ]);
    refused(&o, &["more than the limit of 1.0 MB"]);
    assert!(!out.exists());
}

#[test]
fn tiny_resolutions_of_envelope_and_demo_are_refused_under_2_gb() {
    let p = program(
        "rl-tiny-env",
        "slot.ngc",
        "G21 G90\nG0 X10 Y20 Z5\nG1 Z-3 F200\nG1 X50\nG0 Z5\nM30\n",
    );
    let out = temp_dir("rl-tiny-env-out").join("out");
    let o = limited(&[
        "envelope",
        "--program",
        &p,
        "--tool",
        "flat:d=10",
        "--resolution",
        "0.01",
        "--out",
        out.to_str().unwrap(),
    ]);
    refused(&o, &["envelope lattice would hold", "coarser resolution"]);
    assert!(!out.exists());
    let o = limited(&[
        "demo",
        "--resolution",
        "0.02",
        "--out",
        out.to_str().unwrap(),
    ]);
    refused(&o, &["stock.stl 6.39 GB", "nothing was written"]);
    assert!(!out.exists());
}

#[test]
fn an_endless_loop_that_warns_at_every_iteration_ends_under_2_gb() {
    // Before: ten million copies of the M8 warning (1.6 GB), then an allocation abort.
    let p = program(
        "rl-warn",
        "warn.ngc",
        "G21 G90\no100 while [1]\nM8\nG1 X1 F100\nG1 X0\no100 endwhile\nM30\n",
    );
    let o = limited(&["path", &p]);
    refused(&o, &["warn.ngc:6", "more than 10000000 loop iterations"]);
}

#[test]
fn absurd_grids_and_resolutions_of_toolsize_and_gouge_are_refused_under_2_gb() {
    let d = temp_dir("rl-plan");
    let o = limited(&["demo", "--out", d.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let f = |n: &str| d.join(n).display().to_string();
    // Before: a 320 GB allocation and an abort.
    let o = limited(&[
        "toolsize",
        "--surface",
        &f("floor.json"),
        "--cutter",
        "ball",
        "--grid",
        "100000",
        "--out",
        &f("ts"),
    ]);
    refused(
        &o,
        &[
            "--grid 100000 gives 10000000000 grid points",
            "give a smaller --grid",
        ],
    );
    // Before: bisection of every gouging stretch down to 1e-7 mm, for hours.
    let o = limited(&[
        "gouge",
        "--surface",
        &f("floor.json"),
        "--program",
        &f("demo.ngc"),
        "--tools",
        &f("tools.toml"),
        "--resolution",
        "0.0000001",
        "--out",
        &f("check"),
    ]);
    refused(
        &o,
        &[
            "5767.4 mm of tool travel",
            "more than 1e7",
            "coarser resolution",
        ],
    );
    assert!(!d.join("ts").exists() && !d.join("check").exists());
    let _ = std::fs::remove_dir_all(&d);
}
