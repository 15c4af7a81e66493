//! `swarf engage` end to end: a full slot with a flat end mill, its files and their numbers.

mod common;

use common::{json, stderr, swarf};

#[test]
fn full_slot_files_and_figures() {
    let dir = swarf_testdata::scratch_dir("engage-cli");
    let prog = dir.join("slot.ngc");
    std::fs::write(&prog, "G21 G90\nG0 Z5\nG0 X-10 Y10\nG0 Z-5\nG1 X50 F600\n").unwrap();
    let out = dir.join("out");
    let o = swarf(&[
        "engage",
        "--stock",
        "box:0,0,-10,40,20,0",
        "--program",
        prog.to_str().unwrap(),
        "--tool",
        "flat:d=10",
        "--map-at",
        "30",
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = json(&o);
    assert_eq!(s["locations"], 60);
    let exact = std::f64::consts::PI * 5.0 * 5.0;
    let max = s["max_area_mm2"].as_f64().unwrap();
    assert!((max - exact).abs() / exact < 0.005, "{max}");
    // Removed: the slot 40 × 10 × 5 through the block (ray grid h = 0.1: exact here).
    let v = s["removed_volume_mm3"].as_f64().unwrap();
    assert!((v - 2000.0).abs() < 1.0, "{v}");
    let csv = std::fs::read_to_string(out.join("engagement.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next().unwrap(),
        "location,move,file,line,s,x,y,z,i,j,k,area_mm2,ap_mm,phi_entry_deg,phi_exit_deg,removed_mm3,mrr_mm3_min"
    );
    let row: Vec<&str> = lines.nth(30).unwrap().split(',').collect();
    assert_eq!(row[0], "30");
    assert!((row[5].parse::<f64>().unwrap() - 21.0).abs() < 1e-9);
    let entry: f64 = row[13].parse().unwrap();
    let exit: f64 = row[14].parse().unwrap();
    assert!(
        entry.abs() < 0.5 && (exit - 180.0).abs() < 0.5,
        "{entry} {exit}"
    );
    let discs = std::fs::read_to_string(out.join("discs.csv")).unwrap();
    assert!(discs.starts_with("location,z_mm,phi_start_deg,phi_end_deg\n"));
    assert_eq!(discs.lines().filter(|l| l.starts_with("30,")).count(), 50);
    for f in ["largest.png", "location_30.png", "area.png", "mrr.png"] {
        let bytes = std::fs::read(out.join("maps").join(f)).unwrap();
        assert!(bytes.starts_with(b"\x89PNG"), "{f}");
    }
    // Bad options are errors that say what is expected.
    let o = swarf(&[
        "engage",
        "--stock",
        "box:0,0,-10,40,20,0",
        "--program",
        prog.to_str().unwrap(),
        "--tool",
        "flat:d=10",
        "--dphi",
        "-1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        stderr(&o).contains("--dphi must be between 0.01 and 30 degrees"),
        "{}",
        stderr(&o)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_ramp_draws_the_bottom_face_map() {
    let dir = swarf_testdata::scratch_dir("engage-ramp");
    let prog = dir.join("ramp.ngc");
    std::fs::write(&prog, "G21 G90\nG0 X5 Y10 Z2\nG1 X30 Z-4 F300\n").unwrap();
    let out = dir.join("out");
    let o = swarf(&[
        "engage",
        "--stock",
        "box:0,0,-10,40,20,0",
        "--program",
        prog.to_str().unwrap(),
        "--tool",
        "bull:d=10,r=2",
        "--map-at",
        "20",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    for f in ["maps/largest_bottom.png", "maps/location_20_bottom.png"] {
        assert!(out.join(f).is_file(), "{f}");
    }
    let bottom = std::fs::read_to_string(out.join("bottom.csv")).unwrap();
    assert!(bottom.lines().count() > 10, "{bottom}");
}

#[test]
fn outputs_are_written_as_a_set_or_not_at_all() {
    // `maps` already exists as a file: the maps cannot be written, so nothing may be.
    let dir = swarf_testdata::scratch_dir("engage-set");
    let prog = dir.join("slot.ngc");
    std::fs::write(&prog, "G21 G90\nG0 X-10 Y10 Z-5\nG1 X50 F600\n").unwrap();
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join("maps"), "in the way").unwrap();
    let o = swarf(&[
        "engage",
        "--stock",
        "box:0,0,-10,40,20,0",
        "--program",
        prog.to_str().unwrap(),
        "--tool",
        "flat:d=10",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    for f in ["engagement.csv", "discs.csv", "summary.json"] {
        assert!(!out.join(f).exists(), "{f} written although the set failed");
    }
}
