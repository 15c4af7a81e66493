//! `swarf envelope`: outputs and the swept volume of a plunge against its closed form.
mod common;
use common::*;

#[test]
fn plunge_sweeps_the_tool_plus_a_cylinder() {
    let dir = swarf_testdata::scratch_dir("envelope");
    let prog = dir.join("plunge.ngc");
    std::fs::write(&prog, "G21 G90\nG0 X0 Y0 Z10\nG1 Z0 F300\nM30\n").unwrap();
    let out = dir.join("out");
    let o = swarf(&[
        "envelope",
        "--program",
        prog.to_str().unwrap(),
        "--tool",
        "ball:d=6",
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j = json(&o);
    assert_eq!(j["closed"], true, "{j}");
    // The whole tool (a 3 mm hemisphere under a cylinder up to 30 mm: `swarf tool ball:d=6`)
    // swept 10 mm along its own axis: 2/3·π·27 + π·9·27 + π·9·10.
    let exact = std::f64::consts::PI * (18.0 + 243.0 + 90.0);
    let v = j["volume_mm3"].as_f64().unwrap();
    assert!((v - exact).abs() / exact < 5e-3, "{v} vs {exact}");
    for f in ["envelope.stl", "envelope.glb"] {
        assert!(out.join(f).is_file(), "{f}");
    }
    let mesh = swarf_io::read_stl(&out.join("envelope.stl")).unwrap();
    assert!(mesh.is_closed());
}

/// `--merge-planar`: the same solid in a fraction of the triangles. A line of a flat end mill
/// along X sweeps a slab with round ends: its top, bottom and sides are planes and its ends'
/// side is a cylinder along Z (columns of cells, one plane each).
#[test]
fn merged_coplanar_triangles_keep_the_solid() {
    let dir = swarf_testdata::scratch_dir("envelope-merge");
    let prog = dir.join("line.ngc");
    std::fs::write(&prog, "G21 G90\nG0 X0 Y0 Z0\nG1 X12 F300\nM30\n").unwrap();
    let prog = prog.to_str().unwrap();
    let args = [
        "envelope",
        "--program",
        prog,
        "--tool",
        "flat:d=6",
        "--resolution",
        "0.2",
    ];
    let run = |merge: bool| {
        let out = dir.join(if merge { "merged" } else { "plain" });
        let flag: &[&str] = if merge { &["--merge-planar"] } else { &[] };
        run_mesh(&args, &out, flag, "envelope.stl")
    };
    let (plain, plain_mesh) = run(false);
    let (merged, merged_mesh) = run(true);
    assert_eq!(merged["closed"], true, "{merged}");
    assert_eq!(
        merged["triangles_before_merge"], plain["triangles"],
        "{merged}"
    );
    assert!(plain.get("triangles_before_merge").is_none(), "{plain}");
    let (n0, n1) = (
        plain["triangles"].as_u64().unwrap(),
        merged["triangles"].as_u64().unwrap(),
    );
    assert!(n1 * 20 < n0, "{n1} of {n0} triangles");
    // The same solid: the volumes agree to within 10⁻⁶ mm over the surface (as written, f32).
    let (v0, v1) = (plain_mesh.volume(), merged_mesh.volume());
    assert!((v0 - v1).abs() < 1e-6 * v0, "{v0} vs {v1}");
}

/// `--simplify MM` (0.001 by default): 2 × 2 × 2 blocks of cells merged where the envelope is
/// smooth — a quarter of the triangles on a ball's line, the vertices still on the exact
/// envelope, the volume within the chord of a block over the surface; `--simplify 0` keeps every
/// cell; a tolerance that is neither 0 nor a positive number is refused.
#[test]
fn merged_blocks_of_cells_keep_the_envelope() {
    let dir = swarf_testdata::scratch_dir("envelope-simplify");
    let prog = dir.join("line.ngc");
    std::fs::write(&prog, "G21 G90\nG0 X0 Y0 Z0\nG1 X12 Y5 F300\nM30\n").unwrap();
    let prog = prog.to_str().unwrap();
    let h = 0.2;
    let hs = h.to_string();
    let args = [
        "envelope",
        "--program",
        prog,
        "--tool",
        "ball:d=10",
        "--resolution",
        &hs,
    ];
    let (plain, plain_mesh) = run_mesh(
        &args,
        &dir.join("plain"),
        &["--simplify", "0"],
        "envelope.stl",
    );
    let (merged, merged_mesh) = run_mesh(
        &args,
        &dir.join("merged"),
        &["--simplify", "0.01"],
        "envelope.stl",
    );
    // The default merges too, within 0.001 mm: fewer blocks than within 0.01.
    let (default, _) = run_mesh(&args, &dir.join("default"), &[], "envelope.stl");
    let blocks = |j: &serde_json::Value| j["merged_blocks"].as_u64().unwrap();
    assert!(
        blocks(&default) > 0 && blocks(&default) < blocks(&merged),
        "{default}"
    );
    assert_eq!(merged["closed"], true, "{merged}");
    assert!(merged["merged_blocks"].as_u64().unwrap() > 0, "{merged}");
    assert!(plain.get("merged_blocks").is_none(), "{plain}");
    let (n0, n1) = (
        plain["triangles"].as_u64().unwrap(),
        merged["triangles"].as_u64().unwrap(),
    );
    assert!(n1 * 10 < n0 * 4, "{n1} of {n0} triangles");
    // Every vertex moved onto the envelope (counted before the f32 repair, which may merge one
    // into another).
    assert!(merged["exact_vertices"].as_u64().unwrap() >= merged_mesh.vertices.len() as u64);
    // Inscribed chords of blocks 2h√3 wide on the ball's radius 5.
    let chord = (2.0 * h * 3f64.sqrt()).powi(2) / 40.0;
    let (v0, v1) = (plain_mesh.volume(), merged_mesh.volume());
    assert!((v0 - v1).abs() < chord * plain_mesh.area(), "{v0} vs {v1}");
    // Written as one argument and as two (a negative number is still the flag's value).
    for (bad, joined) in [("-0.1", true), ("-1", true), ("-1", false), ("nan", true)] {
        let mut all = args.to_vec();
        let out = dir.join("bad");
        let flag = format!("--simplify={bad}");
        all.extend(["--out", out.to_str().unwrap()]);
        if joined {
            all.push(&flag);
        } else {
            all.extend(["--simplify", bad]);
        }
        let o = swarf(&all);
        assert!(!o.status.success(), "--simplify {bad}");
        assert!(
            stderr(&o).contains("--simplify must be 0 (every cell) or a positive number of mm"),
            "{}",
            stderr(&o)
        );
        assert!(!out.exists(), "nothing written for --simplify {bad}");
    }
}

/// A ray spacing coarser than half the cutter's diameter is refused, as by the simulating
/// commands (`--resolution 100` wrote a "closed" 12-triangle box of an eighth of the volume).
#[test]
fn a_resolution_coarser_than_the_cutter_is_refused() {
    let dir = temp_dir("envelope-coarse");
    let prog = dir.join("line.ngc");
    std::fs::write(&prog, "G21 G90\nG0 X0 Y0 Z5\nG1 Z0 F100\nG1 X20\nM30\n").unwrap();
    let out = dir.join("out");
    let o = swarf(&[
        "envelope",
        "--program",
        prog.to_str().unwrap(),
        "--tool",
        "flat:d=10",
        "--resolution",
        "100",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("coarser than half the smallest cutter"),
        "{}",
        stderr(&o)
    );
    assert!(!out.exists());
    let o = swarf(&[
        "demo",
        "--resolution",
        "1000",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(!out.exists());
}
