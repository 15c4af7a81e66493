//! `swarf forces` and `swarf schedule` end to end: files, figures against the closed form, the
//! schedule's contract (only feed words change, every location under the limit afterwards,
//! idempotent), and errors.

mod common;

use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use common::{json, stderr, swarf};

const MATERIAL: &str = "name = \"Al7075-T6 (test)\"\nktc = 796\nkrc = 168.8\nkac = 222\nkte = 27.7\nkre = 30.8\nkae = 1.8\nsource = \"test values\"\n";

fn dir(name: &str) -> PathBuf {
    let d = swarf_testdata::scratch_dir(&format!("forces-{name}"));
    d
}

fn write(d: &Path, name: &str, text: &str) -> String {
    let p = d.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}

const SLOT: &str = "G21 G90 G94\nS1000 M3\nG0 X-10 Y10 Z-4\nG1 X50 F400\nG0 Z10\n";

/// `swarf schedule` of `prog` on the 40 × 20 × 10 block with `tool`, the material `mat`, the
/// output `out` and the other arguments `extra` (the limit, feeds, `--json`).
fn schedule(prog: &str, tool: &str, mat: &str, out: &str, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "schedule",
        "--stock",
        "box:0,0,-10,40,20,0",
        "--program",
        prog,
        "--tool",
        tool,
        "--coefficients",
        mat,
        "--out",
        out,
    ];
    args.extend_from_slice(extra);
    swarf(&args)
}

#[test]
fn slot_forces_files_and_figures() {
    let d = dir("slot");
    let prog = write(&d, "slot.ngc", SLOT);
    let mat = write(&d, "al.toml", MATERIAL);
    let out = d.join("out");
    let o = swarf(&[
        "forces",
        "--stock",
        "box:0,0,-10,40,20,0",
        "--program",
        &prog,
        "--tool",
        "flat:d=10,flutes=4,helix=30",
        "--coefficients",
        &mat,
        "--curves-at",
        "25",
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = json(&o);
    for key in [
        "locations",
        "max_force_n",
        "max_torque_nm",
        "max_power_w",
        "mean_power_w",
        "elapsed_s",
    ] {
        assert!(s.get(key).is_some(), "{key}");
    }
    assert_eq!(s["locations"], 60);
    let csv = std::fs::read_to_string(out.join("forces.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next().unwrap(),
        "location,move,file,line,x,y,z,feed_per_tooth_mm,fx_mean_n,fy_mean_n,fz_mean_n,fx_peak_n,fy_peak_n,fz_peak_n,f_peak_n,wx_mean_n,wy_mean_n,wz_mean_n,torque_mean_nm,torque_peak_nm,power_mean_w,power_peak_w"
    );
    // Location 25 (x = 16): a full slot 4 mm deep, c = 0.1 mm: F̄y = N·a·(c·Ktc/4 + Kte/π).
    let row: Vec<f64> = lines
        .nth(25)
        .unwrap()
        .split(',')
        .enumerate()
        .filter(|(i, _)| *i != 2)
        .map(|(_, v)| v.parse().unwrap())
        .collect();
    // (file dropped: columns shift by one after index 1.)
    assert!((row[6] - 0.1).abs() < 1e-12, "feed per tooth {}", row[6]);
    let fy = 4.0 * 4.0 * (0.1 * 796.0 / 4.0 + 27.7 / std::f64::consts::PI);
    assert!((row[8] - fy).abs() < 1e-3 * fy, "{} vs {fy}", row[8]);
    let curves = std::fs::read_to_string(out.join("curves.csv")).unwrap();
    assert_eq!(curves.lines().count(), 1 + 360);
    assert!(curves.starts_with("location,angle_deg,fx_n,fy_n,fz_n,torque_nm\n25,0,"));
    for f in [
        "plots/peak_force.png",
        "plots/torque.png",
        "plots/power.png",
        "plots/curves_location_25.png",
        "summary.json",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
}

#[test]
fn schedule_keeps_every_location_under_the_limit_and_only_touches_feeds() {
    let d = dir("schedule");
    let text = "G21 G90 G94\r\nS1000 M3\r\nG0 X-10 Y10 Z-4\r\nG1 X50 F800 (slot)\r\nG1 Y12\r\nG1 X-10\r\nG0 Z10\r\nG0 X-10 Y0\r\nG1 Z-2 F300\r\nG1 X50 ; light pass\r\nG0 Z10\r\nM30\r\n";
    let prog = write(&d, "job.ngc", text);
    let mat = write(&d, "al.toml", MATERIAL);
    let common = |out: &str, program: &str| -> Vec<String> {
        [
            "--stock",
            "box:0,0,-10,40,20,0",
            "--program",
            program,
            "--tool",
            "flat:d=10,flutes=4,helix=30",
            "--coefficients",
            &mat,
            "--out",
            out,
        ]
        .iter()
        .map(|s| s.to_string())
        .collect()
    };
    let sched = |program: &str, out: &Path| {
        let mut a = vec!["schedule".to_string()];
        a.extend(common(out.to_str().unwrap(), program));
        a.extend(
            [
                "--limit-force",
                "600",
                "--max-feed",
                "1200",
                "--max-step-percent",
                "50",
                "--json",
            ]
            .iter()
            .map(|s| s.to_string()),
        );
        let args: Vec<&str> = a.iter().map(String::as_str).collect();
        swarf(&args)
    };
    let out1 = d.join("job1.ngc");
    let o = sched(&prog, &out1);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = json(&o);
    assert!(s["moves_changed"].as_u64().unwrap() > 0);
    assert!(s["time_after_s"].as_f64().unwrap() > 0.0);
    assert!(s["time_before_s"].as_f64().is_some());
    assert_eq!(s["still_over_limit"].as_array().unwrap().len(), 0);
    // Without --split the summary still counts split moves and added pieces (README): 0.
    assert_eq!(
        (&s["moves_split"], &s["pieces_added"]),
        (&0.into(), &0.into())
    );
    let new = std::fs::read_to_string(&out1).unwrap();
    // Only F words differ: removing them (and the space before an added one) gives the input.
    let strip = |t: &str| -> String {
        t.split("\r\n")
            .map(|l| {
                let mut out = String::new();
                let mut chars = l.chars().peekable();
                while let Some(c) = chars.next() {
                    if c == 'F' {
                        while chars
                            .peek()
                            .is_some_and(|c| c.is_ascii_digit() || *c == '.')
                        {
                            chars.next();
                        }
                        continue;
                    }
                    out.push(c);
                }
                out.trim_end().replace("  ", " ")
            })
            .collect::<Vec<_>>()
            .join("\r\n")
    };
    assert_eq!(strip(&new), strip(text));
    assert_ne!(new, text);
    assert!(new.contains("(slot)") && new.contains("; light pass\r\n"));
    // Every location of the new program at or under the limit (within 1 %).
    let fo = d.join("forces");
    let mut a = vec!["forces".to_string()];
    a.extend(common(fo.to_str().unwrap(), out1.to_str().unwrap()));
    a.push("--json".into());
    let args: Vec<&str> = a.iter().map(String::as_str).collect();
    let o = swarf(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let peak = json(&o)["max_force_n"].as_f64().unwrap();
    assert!(peak <= 606.0, "{peak}");
    // The original exceeds it.
    let fo0 = d.join("forces0");
    let mut a = vec!["forces".to_string()];
    a.extend(common(fo0.to_str().unwrap(), &prog));
    a.push("--json".into());
    let args: Vec<&str> = a.iter().map(String::as_str).collect();
    let before = json(&swarf(&args))["max_force_n"].as_f64().unwrap();
    assert!(before > 700.0, "{before}");
    // Running it again changes nothing.
    let out2 = d.join("job2.ngc");
    let o = sched(out1.to_str().unwrap(), &out2);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(&out2).unwrap(), new);
    assert_eq!(json(&o)["moves_changed"], 0);
}

#[test]
fn schedule_reports_what_even_the_minimum_feed_cannot_fix() {
    let d = dir("over");
    let prog = write(&d, "slot.ngc", SLOT);
    let mat = write(&d, "al.toml", MATERIAL);
    let out = d.join("slow.ngc");
    let o = schedule(
        &prog,
        "flat:d=10,flutes=4,helix=30",
        &mat,
        out.to_str().unwrap(),
        &["--limit-force", "300", "--min-feed", "200", "--json"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let s = json(&o);
    let over = s["still_over_limit"].as_array().unwrap();
    assert_eq!(over.len(), 1);
    assert_eq!(over[0]["line"], 4);
    assert_eq!(over[0]["feed_mm_min"], 200.0);
    assert!(std::fs::read_to_string(&out)
        .unwrap()
        .contains("G1 X50 F200\n"));
}

/// A G33.1 tap's speed is its lead times the spindle speed: the schedule keeps it, reports it
/// over the limit with what would slow it, and still slows the G1 slot beside it.
#[test]
fn schedule_keeps_spindle_synchronised_moves_and_says_so() {
    let d = dir("g33");
    let src =
        "G21 G90 G94\nS1000 M3\nG0 X-10 Y10 Z-4\nG1 X20 F400\nG33.1 Z-8 K1\nG1 X50\nG0 Z10\nM2\n";
    let prog = write(&d, "tap.ngc", src);
    let mat = write(&d, "al.toml", MATERIAL);
    let out = d.join("tap-slow.ngc");
    let o = schedule(
        &prog,
        "flat:d=10,flutes=4,helix=30",
        &mat,
        out.to_str().unwrap(),
        &["--limit-force", "300"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("tap.ngc:5: over the limit at 1000.0 mm/min")
            && stderr(&o).contains("lower S"),
        "{}",
        stderr(&o)
    );
    let text = std::fs::read_to_string(&out).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[4], "G33.1 Z-8 K1", "{text}");
    assert!(
        lines[3].starts_with("G1 X20 F") && lines[3] != "G1 X20 F400",
        "{text}"
    );
}

/// A program that calls a subroutine file (with no moves of its own) is scheduled and read back
/// with the file found beside the program, wherever the output goes.
#[test]
fn schedule_reads_back_a_program_calling_a_subroutine_file() {
    let d = dir("subfile");
    std::fs::create_dir_all(d.join("prog")).unwrap();
    std::fs::create_dir_all(d.join("out")).unwrap();
    let prog = write(
        &d.join("prog"),
        "main.ngc",
        "G21 G90 G94\nS1000 M3\no<setz> call\nG0 X-10 Y10 Z#<_depth>\nG1 X50 F400\nG0 Z10\nM30\n",
    );
    write(
        &d.join("prog"),
        "setz.ngc",
        "o<setz> sub\n#<_depth> = -4\no<setz> endsub\n",
    );
    let mat = write(&d, "al.toml", MATERIAL);
    let out = d.join("out").join("main-s.ngc");
    let o = schedule(
        &prog,
        "flat:d=10,flutes=4,helix=30",
        &mat,
        out.to_str().unwrap(),
        &["--limit-force", "300"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::read_to_string(&out).unwrap().contains("G1 X50 F"));
}

#[test]
fn errors_name_what_is_missing() {
    let d = dir("errors");
    let prog = write(&d, "slot.ngc", SLOT);
    let o_dir = d.join("o");
    let base = [
        "forces",
        "--stock",
        "box:0,0,-10,40,20,0",
        "--program",
        &prog,
        "--out",
        o_dir.to_str().unwrap(),
    ];
    let run = |extra: &[&str]| {
        let mut a: Vec<&str> = base.to_vec();
        a.extend_from_slice(extra);
        swarf(&a)
    };
    let o = run(&["--tool", "flat:d=10", "--material", "ti6al4v"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("no flute count"), "{}", stderr(&o));
    let o = run(&["--tool", "flat:d=10,flutes=3", "--material", "ti6al4v"]);
    assert!(stderr(&o).contains("no rake angle"), "{}", stderr(&o));
    let o = run(&["--tool", "flat:d=10,flutes=3", "--material", "unobtainium"]);
    assert!(stderr(&o).contains("ti6al4v"), "{}", stderr(&o));
    let o = run(&["--tool", "flat:d=10,flutes=3"]);
    assert!(stderr(&o).contains("--material"), "{}", stderr(&o));
    let bad = write(&d, "bad.toml", "name = \"x\"\nktc = 796\nkrc = nope\n");
    let o = run(&["--tool", "flat:d=10,flutes=3", "--coefficients", &bad]);
    assert!(stderr(&o).contains("bad.toml:3:"), "{}", stderr(&o));
    // A predicted material with a rake: works, and names its source.
    let o = run(&[
        "--tool",
        "flat:d=10,flutes=3,rake=12",
        "--material",
        "ti6al4v",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(json(&o)["material_source"]
        .as_str()
        .unwrap()
        .contains("Budak"));
    let o = swarf(&["forces", "--list-materials"]);
    assert!(o.status.success());
    // Disc heights out of range are refused before any work: `--dz 0` ran for ever (the
    // model's edges at that height), `--dz 1e-7` took gigabytes before the check.
    let mat = write(&d, "al.toml", MATERIAL);
    for dz in ["0", "1e-7"] {
        let o = run(&[
            "--tool",
            "flat:d=10,flutes=3",
            "--coefficients",
            &mat,
            "--dz",
            dz,
        ]);
        assert_eq!(o.status.code(), Some(1), "--dz {dz}");
        assert!(stderr(&o).contains("--dz must be"), "{}", stderr(&o));
        let o = schedule(
            &prog,
            "flat:d=10,flutes=4",
            &mat,
            d.join("dz.ngc").to_str().unwrap(),
            &["--limit-force", "100", "--dz", dz],
        );
        assert_eq!(o.status.code(), Some(1), "--dz {dz}");
        assert!(stderr(&o).contains("--dz must be"), "{}", stderr(&o));
    }
    assert!(!d.join("dz.ngc").exists());
    // A schedule over a loop is refused (the rewrite works on straight-line text).
    let looped = write(
        &d,
        "loop.ngc",
        "G21 G90\nS1000 M3\nG0 X-10 Y10 Z-4\n#1 = 0\no100 while [#1 LT 2]\nG1 X50 F400\nG1 X-10\n#1 = [#1 + 1]\no100 endwhile\nM30\n",
    );
    let o = schedule(
        &looped,
        "flat:d=10,flutes=4",
        &mat,
        d.join("x.ngc").to_str().unwrap(),
        &["--limit-power", "100"],
    );
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("loop.ngc:6:"), "{}", stderr(&o));
    assert!(!d.join("x.ngc").exists());
}

#[test]
fn schedule_rewrites_apt_fedrat_records_and_g95_feeds() {
    let d = dir("apt");
    let mat = write(&d, "al.toml", MATERIAL);
    let apt = "PARTNO TEST\nUNITS/MM\nSPINDL/1000,RPM,CLW\nRAPID\nGOTO/-10,10,-4\nFEDRAT/ 800.0000,MMPM\nGOTO/50,10,-4\nGOTO/50,12,-4\nGOTO/-10,12,-4\nRAPID\nGOTO/-10,12,10\nFINI\n";
    let g95 = "G21 G90 G95\nS1000 M3\nG0 X-10 Y10 Z-4\nG1 X50 F0.8\nG0 Z10\n";
    for (name, text, want) in [
        (
            "job.apt",
            apt,
            "FEDRAT/ 434.951,MMPM\nGOTO/50,10,-4\nFEDRAT/ 800,MMPM\nGOTO/50,12,-4\n",
        ),
        ("rev.ngc", g95, "G1 X50 F0.434537\n"),
    ] {
        let prog = write(&d, name, text);
        let out = d.join(format!("s-{name}"));
        let o = schedule(
            &prog,
            "flat:d=10,flutes=4,helix=30",
            &mat,
            out.to_str().unwrap(),
            &["--limit-force", "600"],
        );
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        let new = std::fs::read_to_string(&out).unwrap();
        assert!(new.contains(want), "{name}:\n{new}");
    }
}

/// Small feed numbers — per revolution (G95) in inch, or an inverse time (G93) — are written
/// with six significant digits: with six decimals an inch feed per revolution kept three
/// (F0.000404), read back 1e-3 off, and the schedule stopped with an internal error.
#[test]
fn schedule_writes_small_feed_numbers_to_six_digits() {
    let d = dir("small-feeds");
    let mat = write(&d, "al.toml", MATERIAL);
    let inch =
        "G20 G90 G95\nS10000 M3\nG0 X-0.4 Y0.4 Z0.2\nG0 Z-0.15748031\nG1 X2.0 F0.004\nG0 Z0.4\n";
    let inverse =
        "G21 G90\nS10000 M3\nG0 X-10 Y10 Z5\nG0 Z-4\nG93 G1 X50 F16.6666667\nG94\nG0 Z5\n";
    for (name, text, limit) in [("inch.ngc", inch, "300"), ("inverse.ngc", inverse, "100")] {
        let prog = write(&d, name, text);
        let out = d.join(format!("s-{name}"));
        let o = schedule(
            &prog,
            "flat:d=10,flutes=4,helix=30",
            &mat,
            out.to_str().unwrap(),
            &["--limit-force", limit, "--json"],
        );
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        assert_eq!(json(&o)["moves_changed"], 1, "{name}");
        let new = std::fs::read_to_string(&out).unwrap();
        let line = new
            .lines()
            .find(|l| l.contains(" X50") || l.contains(" X2.0"))
            .unwrap();
        let f = line.split(" F").nth(1).unwrap();
        let significant = f.trim_start_matches(['0', '.']).replace('.', "");
        assert!(significant.len() >= 6, "{name}: {line}");
    }
}

/// A line that also starts the spindle (or sets S, M8, units…) is not split: pieces in front of
/// it would cut before its words took effect — with the spindle still stopped.
#[test]
fn schedule_splits_no_line_with_other_words_and_warns_of_a_stopped_spindle() {
    let d = dir("split-words");
    let mat = write(&d, "al.toml", MATERIAL);
    let text = "G21 G90 G94\nG0 X-10 Y10 Z5\nG0 Z-3\nG1 X50 F1000 M3 S10000\nG0 Z5\nM2\n";
    let prog = write(&d, "m3.ngc", text);
    let out = d.join("m3-s.ngc");
    let o = schedule(
        &prog,
        "flat:d=10,flutes=4,helix=30",
        &mat,
        out.to_str().unwrap(),
        &["--limit-force", "200", "--split", "--step", "2", "--json"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let s = json(&o);
    assert_eq!(s["moves_split"], 0, "{s}");
    assert_eq!(s["engaged_without_spindle"], 0, "{s}");
    let new = std::fs::read_to_string(&out).unwrap();
    assert!(!new.contains("G91"), "{new}");
    // The same cut with the spindle never started: reported, not scheduled away.
    let text = "G21 G90 G94\nG0 X-10 Y10 Z5\nG0 Z-3\nG1 X50 F1000\nG0 Z5\nM2\n";
    let prog = write(&d, "stopped.ngc", text);
    let out = d.join("stopped-s.ngc");
    let o = schedule(
        &prog,
        "flat:d=10,flutes=4,helix=30",
        &mat,
        out.to_str().unwrap(),
        &["--limit-force", "200", "--json"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let s = json(&o);
    assert!(s["engaged_without_spindle"].as_u64().unwrap() > 10, "{s}");
    assert!(
        stderr(&o).contains("spindle stopped") && stderr(&o).contains("stopped.ngc:4"),
        "{}",
        stderr(&o)
    );
    // `forces` names the first line too, and every cause (it blamed the S word alone).
    let o = swarf(&[
        "forces",
        "--stock",
        "box:0,0,-10,40,20,0",
        "--program",
        &prog,
        "--tool",
        "flat:d=10,flutes=4,helix=30",
        "--coefficients",
        &mat,
        "--step",
        "2",
        "--out",
        d.join("f-stopped").to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(e.contains("stopped.ngc:4") && e.contains("M6"), "{e}");
}

/// A `--min-feed` above a programmed feed raises it — faster than programmed, which the
/// schedule otherwise never is: said on stderr.
#[test]
fn a_minimum_feed_above_the_programmed_one_is_said() {
    let d = dir("min-feed");
    let mat = write(&d, "al.toml", MATERIAL);
    let prog = write(&d, "slot.ngc", SLOT);
    let out = d.join("slot-s.ngc");
    let o = schedule(
        &prog,
        "flat:d=10,flutes=4,helix=30",
        &mat,
        out.to_str().unwrap(),
        &["--limit-force", "100000", "--min-feed", "500"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("1 feed moves programmed slower than --min-feed 500"),
        "{}",
        stderr(&o)
    );
    assert!(std::fs::read_to_string(&out)
        .unwrap()
        .contains("G1 X50 F500"));
}

#[test]
fn split_moves_get_their_own_feeds_and_stay_under_the_limit() {
    let d = dir("split");
    let mat = write(&d, "al.toml", MATERIAL);
    // A long pass that runs in the air, then half in a slot, then in solid material.
    let text = "G21 G90 G94\nS1000 M3\nG0 X-10 Y10 Z-4\nG1 X12 F800\nG1 Y14\nG0 Z10\nG0 X-10 Y2\nG1 Z-4\nG1 X50 (half in a pocket, half in solid)\nG0 Z10\nM30\n";
    let prog = write(&d, "split.ngc", text);
    let out = d.join("split-s.ngc");
    let args = |program: &str, o: &Path, extra: &[&str]| -> Vec<String> {
        let mut a: Vec<String> = [
            "--stock",
            "box:0,0,-10,40,20,0",
            "--program",
            program,
            "--tool",
            "flat:d=10,flutes=4,helix=30",
            "--coefficients",
            &mat,
            "--out",
            o.to_str().unwrap(),
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        a.extend(extra.iter().map(|s| s.to_string()));
        a
    };
    let mut a = vec!["schedule".to_string()];
    a.extend(args(
        &prog,
        &out,
        &[
            "--limit-force",
            "500",
            "--max-feed",
            "1500",
            "--split",
            "--json",
        ],
    ));
    let o = swarf(&a.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(o.status.success(), "{}", stderr(&o));
    let s = json(&o);
    assert!(s["moves_split"].as_u64().unwrap() >= 1, "{s}");
    let new = std::fs::read_to_string(&out).unwrap();
    // Every original line is still there, in order, up to its feed word.
    let plain = |l: &str| l.split(" F").next().unwrap().to_string();
    let kept: Vec<String> = new.lines().map(plain).collect();
    let mut at = 0;
    for l in text.lines() {
        at += kept[at..]
            .iter()
            .position(|k| *k == plain(l))
            .unwrap_or_else(|| panic!("{l} lost:\n{new}"));
    }
    assert!(new.contains("G91 G1 X") && new.contains("\nG90\n"), "{new}");
    // The split program stays under the limit (1 %) and is faster than one feed for the move.
    let fo = d.join("forces");
    let mut a = vec!["forces".to_string()];
    a.extend(args(out.to_str().unwrap(), &fo, &["--json"]));
    let o = swarf(&a.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(o.status.success(), "{}", stderr(&o));
    let peak = json(&o)["max_force_n"].as_f64().unwrap();
    assert!(peak <= 505.0, "{peak}");
    let whole = d.join("whole.ngc");
    let mut a = vec!["schedule".to_string()];
    a.extend(args(
        &prog,
        &whole,
        &["--limit-force", "500", "--max-feed", "1500", "--json"],
    ));
    let o = swarf(&a.iter().map(String::as_str).collect::<Vec<_>>());
    let t_whole = json(&o)["time_after_s"].as_f64().unwrap();
    assert!(
        s["time_after_s"].as_f64().unwrap() < t_whole,
        "{s} vs {t_whole}"
    );
}

/// A program whose lines end in a lone `\r` (old Mac editors) is scheduled line for line as the
/// reader numbers it, each line and inserted piece ending in `\r`: the same program as with
/// `\n` ends. Before, the rewrite saw one line and the schedule ended with an internal error
/// ("reads back at").
#[test]
fn schedule_keeps_lone_carriage_return_line_ends() {
    let d = dir("lone-cr");
    let mat = write(&d, "al.toml", MATERIAL);
    let text = "G21 G90 G94\nS1000 M3\nG0 X-10 Y10 Z-4\nG1 X12 F800\nG1 Y14\nG0 Z10\nG0 X-10 Y2\nG1 Z-4\nG1 X50\nG0 Z10\nM30\n";
    let run = |name: &str, text: &str| -> String {
        let prog = write(&d, name, text);
        let out = d.join(format!("s-{name}"));
        let o = schedule(
            &prog,
            "flat:d=10,flutes=4,helix=30",
            &mat,
            out.to_str().unwrap(),
            &["--limit-force", "500", "--max-feed", "1500", "--split"],
        );
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        std::fs::read_to_string(&out).unwrap()
    };
    let lf = run("lf.ngc", text);
    assert!(lf.contains("G91 G1 X"), "{lf}");
    let cr = run("cr.ngc", &text.replace('\n', "\r"));
    assert_eq!(cr, lf.replace('\n', "\r"));
}

/// An APT program drilling with a cycle of its own feed: the holes are engaged (a plunge) and
/// scheduled, the cycle restated before them with the new feed; the read-back check passes.
#[test]
fn schedule_restates_an_apt_drilling_cycle() {
    let d = dir("apt-cycle");
    let prog = write(
        &d,
        "holes.cls",
        "UNITS/MM\nSPINDL/3000,RPM,CLW\nFEDRAT/MMPM,400\nGOTO/0,0,30\n\
         CYCLE/DRILL,FEDTO,-8,RAPTO,2,RTRCTO,AUTO,MMPM,600\nGOTO/10,10,0\nGOTO/30,10,0\n\
         CYCLE/OFF\nFINI\n",
    );
    let mat = write(&d, "al.toml", MATERIAL);
    let out = d.join("holes-s.cls");
    let o = schedule(
        &prog,
        "flat:d=10,flutes=2",
        &mat,
        out.to_str().unwrap(),
        &["--limit-force", "1500", "--max-feed", "2000", "--json"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let s = json(&o);
    assert_eq!(s["still_over_limit"].as_array().unwrap().len(), 0);
    let new = std::fs::read_to_string(&out).unwrap();
    assert!(
        new.contains(
            "MMPM,600\nCYCLE/DRILL,FEDTO,-8,RAPTO,2,RTRCTO,AUTO,MMPM,2000\nGOTO/10,10,0\n"
        ),
        "{new}"
    );
}

#[test]
fn schedule_rewrites_a_heidenhain_program() {
    let d = dir("schedule-heidenhain");
    let text = "0 BEGIN PGM JOB MM\n1 TOOL CALL 1 Z S1000 F800\n2 L X-10 Y+10 Z-4 R0 FMAX M3\n\
                3 L X+50 ; slot\n4 L Z+10 FMAX\n5 END PGM JOB MM\n";
    let prog = write(&d, "JOB.H", text);
    let mat = write(&d, "al.toml", MATERIAL);
    let out = d.join("JOB-scheduled.H");
    let o = schedule(
        &prog,
        "flat:d=10,flutes=4,helix=30",
        &mat,
        out.to_str().unwrap(),
        &["--limit-force", "600", "--json"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let new = std::fs::read_to_string(&out).unwrap();
    // The slot's block gets a slower F before its comment; nothing else changes.
    let line3 = new.lines().nth(3).unwrap();
    let f: f64 = line3
        .strip_prefix("3 L X+50 F")
        .and_then(|r| r.strip_suffix(" ; slot"))
        .unwrap_or_else(|| panic!("{new}"))
        .parse()
        .unwrap();
    assert!(f < 800.0, "{new}");
    let others: Vec<&str> = new
        .lines()
        .enumerate()
        .filter(|(i, _)| *i != 3)
        .map(|(_, l)| l)
        .collect();
    let before: Vec<&str> = text
        .lines()
        .enumerate()
        .filter(|(i, _)| *i != 3)
        .map(|(_, l)| l)
        .collect();
    assert_eq!(others, before);
    // The scheduled program stays under the limit.
    let fo = d.join("forces");
    let o = swarf(&[
        "forces",
        "--stock",
        "box:0,0,-10,40,20,0",
        "--program",
        out.to_str().unwrap(),
        "--tool",
        "flat:d=10,flutes=4,helix=30",
        "--coefficients",
        &mat,
        "--out",
        fo.to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(json(&o)["max_force_n"].as_f64().unwrap() <= 606.0);
}

/// `--out` naming the program itself is refused before anything is computed or written: the
/// source keeps its feeds.
#[test]
fn schedule_never_replaces_its_program() {
    let d = dir("self");
    let prog = write(&d, "slot.ngc", SLOT);
    let mat = write(&d, "al.toml", MATERIAL);
    let same = format!("{}/./slot.ngc", d.display());
    let o = schedule(
        &prog,
        "flat:d=10,flutes=4,helix=30",
        &mat,
        &same,
        &["--limit-force", "300"],
    );
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("is one of the run's inputs"),
        "{}",
        stderr(&o)
    );
    assert_eq!(std::fs::read_to_string(&prog).unwrap(), SLOT);
    // Nor the coefficients it reads.
    let o = schedule(
        &prog,
        "flat:d=10,flutes=4,helix=30",
        &mat,
        &mat,
        &["--limit-force", "300"],
    );
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(&mat).unwrap(), MATERIAL);
}

/// A rapid through the material (line 5: `G0 X20` at Z−4 from x = −8, a 10 mm end mill at
/// y = 10 in the 40 × 20 × 10 block) is reported by `engage`, `forces` and `schedule` as
/// `simulate` reports it — `rapid_collisions`, `collisions` with its line and volume
/// 4·(10·20 + π·5²/2) = 957.08 mm³ — and warned about on stderr; `schedule` says that no feed
/// fixes it. Before, all three were silent (engage's `removed_volume_mm3` 1558 against 600 at
/// the locations).
#[test]
fn a_rapid_through_the_material_is_reported_by_engage_forces_and_schedule() {
    let d = dir("rapidthru");
    let mat = write(&d, "al.toml", MATERIAL);
    let prog = write(
        &d,
        "rapidthru.ngc",
        "G21 G90 G94\nS8000 M3\nG0 X-8 Y10 Z5\nG0 Z-4\nG0 X20\nG1 X35 F1000\nG0 Z5\nM30\n",
    );
    let rapid = 4.0 * (10.0 * 20.0 + PI * 25.0 / 2.0);
    let stock = ["--stock", "box:0,0,-10,40,20,0", "--program", &prog];
    let tool = ["--tool", "flat:d=10,flutes=3"];
    let (eng, frc, sch) = (d.join("eng"), d.join("frc"), d.join("s.ngc"));
    let runs: [(Vec<&str>, &str); 3] = [
        (
            vec!["engage", "--out", eng.to_str().unwrap()],
            "no cutter location",
        ),
        (
            vec![
                "forces",
                "--coefficients",
                &mat,
                "--out",
                frc.to_str().unwrap(),
            ],
            "no forces",
        ),
        (
            vec![
                "schedule",
                "--coefficients",
                &mat,
                "--limit-force",
                "250",
                "--out",
                sch.to_str().unwrap(),
            ],
            "not fixed by feeds",
        ),
    ];
    for (args, note) in runs {
        let mut a = args.clone();
        a.extend(stock);
        a.extend(tool);
        a.push("--json");
        let o = swarf(&a);
        assert!(o.status.success(), "{}", stderr(&o));
        let s = json(&o);
        let err = stderr(&o);
        assert_eq!(s["rapid_collisions"], 1, "{}: {s}", args[0]);
        assert_eq!(s["holder_collisions"], 0, "{}: {s}", args[0]);
        let c = &s["collisions"][0];
        assert_eq!(c["kind"], "rapid");
        assert_eq!(c["line"], 5);
        assert_eq!(c["move_index"], 2);
        let v = c["volume_mm3"].as_f64().unwrap();
        assert!((v - rapid).abs() < 0.005 * rapid, "{}: {v}", args[0]);
        assert!(
            err.contains("rapidthru.ngc:5: a rapid through the material") && err.contains(note),
            "{}: {err}",
            args[0]
        );
    }
}

/// A LinuxCNC `.tbl` cannot hold a flute count: `forces` and `schedule` refuse its tools with a
/// message naming the table and `--flutes`, and take `--flutes N` for them — the forces then
/// equal those of the same cutter given as a spec with `flutes=N`. Before, the message asked
/// for a `flutes = N` the table cannot hold, and there was no other way.
#[test]
fn library_tools_without_a_flute_count_take_the_flutes_option() {
    let d = dir("tbl-flutes");
    let mat = write(&d, "al.toml", MATERIAL);
    let tbl = write(&d, "tools.tbl", "T1 P1 D10 Z+50 ;10mm flat\n");
    let prog = write(
        &d,
        "t1.ngc",
        "G21 G90 G94\nT1 M6\nS1000 M3\nG0 X-10 Y10 Z5\nG0 Z-4\nG1 X50 F400\nG0 Z10\nM30\n",
    );
    let run = |cmd: &str, tools: &[&str], extra: &[&str]| {
        let out = d.join(format!("{cmd}-{}", extra.len()));
        let mut a = vec![
            cmd,
            "--stock",
            "box:0,0,-10,40,20,0",
            "--program",
            &prog,
            "--coefficients",
            &mat,
        ];
        a.extend(tools);
        a.extend(extra);
        let out = out.to_str().unwrap().to_string();
        let mut a: Vec<String> = a.iter().map(|s| s.to_string()).collect();
        a.extend(["--out".to_string(), out, "--json".to_string()]);
        swarf(&a.iter().map(String::as_str).collect::<Vec<_>>())
    };
    for (cmd, extra) in [
        ("forces", vec![]),
        ("schedule", vec!["--limit-force", "300"]),
    ] {
        let o = run(cmd, &["--tools", &tbl], &extra);
        assert_eq!(o.status.code(), Some(1), "{cmd}");
        let err = stderr(&o);
        assert!(
            err.contains("tool 1 (flat Ø10 mm) has no flute count")
                && err.contains(&format!("tool table {tbl}"))
                && err.contains("--flutes N"),
            "{cmd}: {err}"
        );
    }
    let with_option = run("forces", &["--tools", &tbl], &["--flutes", "4"]);
    assert!(with_option.status.success(), "{}", stderr(&with_option));
    let spec = run("forces", &["--tool", "flat:d=10,flutes=4"], &[]);
    let (a, b) = (json(&with_option), json(&spec));
    for key in ["max_force_n", "max_torque_nm", "mean_power_w"] {
        let (x, y) = (a[key].as_f64().unwrap(), b[key].as_f64().unwrap());
        assert!(x > 0.0 && (x - y).abs() <= 1e-9 * y, "{key}: {x} vs {y}");
    }
    // A full slot 4 mm deep, 4 flutes at 0.1 mm a tooth: F̄y = N·a·(c·Ktc/4 + Kte/π), and the
    // peak resultant at least that.
    let fy = 4.0 * 4.0 * (0.1 * 796.0 / 4.0 + 27.7 / PI);
    assert!(a["max_force_n"].as_f64().unwrap() >= fy * (1.0 - 1e-3));
    let s = run(
        "schedule",
        &["--tools", &tbl],
        &["--limit-force", "300", "--flutes", "4"],
    );
    assert!(s.status.success(), "{}", stderr(&s));
}
