//! `swarf toolsize --standard`: the extra CSV column, `standard.json`, the `standard` key of the
//! summary, and the maps written on every run (inside the 5 mm STEP sphere).
mod common;
use common::*;

#[test]
fn standard_cutters_inside_the_step_sphere() {
    let sphere = sphere_step(&temp_dir("toolsize-std-sphere"), 5.0);
    let dir = swarf_testdata::scratch_dir("toolsize-std");
    let _ = std::fs::remove_dir_all(&dir);
    let o = swarf(&[
        "toolsize",
        "--surface",
        &sphere,
        "--cutter",
        "ball",
        "--flip",
        "--grid",
        "9",
        "--standard",
        "12.7,10,6.35",
        "--out",
        dir.to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j = json(&o);
    assert!(j.get("max_radius_mm").is_some(), "{j}");
    let s = &j["standard"];
    // The ball of the sphere's radius fits everywhere it reaches: the 10 mm cutter, alone.
    assert_eq!(s["suggested_mm"], serde_json::json!([10.0]), "{s}");
    let total = s["total_area_mm2"].as_f64().unwrap();
    assert!(
        (total - 4.0 * std::f64::consts::PI * 25.0).abs() < 1e-6,
        "{total}"
    );
    let cutters = s["cutters"].as_array().unwrap();
    assert_eq!(cutters.len(), 3);
    assert_eq!(cutters[0]["fits_share"].as_f64(), Some(0.0)); // 12.7 mm never fits
    let fits10 = cutters[1]["fits_share"].as_f64().unwrap();
    assert!(fits10 > 0.3 && fits10 < 0.7, "{fits10}");
    assert_eq!(cutters[1]["finishes_share"].as_f64(), Some(fits10));
    let file: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("standard.json")).unwrap()).unwrap();
    assert_eq!(&file, s);
    let csv = std::fs::read_to_string(dir.join("toolsize.csv")).unwrap();
    let mut rows = csv.lines();
    assert_eq!(
        rows.next().unwrap(),
        "patch,u,v,x,y,z,nx,ny,nz,radius_mm,limit_x,limit_y,limit_z,limit,certified,standard_d_mm"
    );
    for r in rows {
        let f: Vec<&str> = r.split(',').collect();
        let want = match f[9].parse::<f64>() {
            Ok(x) if x >= 5.0 - 1e-6 => "10.0",
            Ok(x) if x >= 3.175 - 1e-6 => "6.35",
            _ => "",
        };
        assert_eq!(f[15], want, "{r}");
    }
    assert!(dir.join("maps/patch_0.png").is_file());
    assert!(dir.join("maps/standard_patch_0.png").is_file());
    assert!(dir.join("part.glb").is_file());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A folder reused without `--standard` keeps this run's results only: the earlier run's
/// `standard.json` and standard-cutter maps are removed, a map of a patch this run does not
/// have is removed, the user's own files stay.
#[test]
fn a_reused_folder_holds_this_run_s_results_only() {
    let sphere = sphere_step(&temp_dir("toolsize-reuse-sphere"), 5.0);
    let dir = temp_dir("toolsize-reuse");
    let run = |standard: bool| {
        let mut args = vec![
            "toolsize",
            "--surface",
            &sphere,
            "--cutter",
            "ball",
            "--flip",
            "--grid",
            "5",
            "--out",
            dir.to_str().unwrap(),
        ];
        if standard {
            args.extend(["--standard", "10,6"]);
        }
        let o = swarf(&args);
        assert!(o.status.success(), "{}", stderr(&o));
    };
    run(true);
    assert!(dir.join("standard.json").is_file());
    let maps = dir.join("maps");
    std::fs::write(maps.join("patch_gone.png"), b"old").unwrap();
    std::fs::write(maps.join("mine.png"), b"user").unwrap();
    run(false);
    assert!(!dir.join("standard.json").exists());
    let names: Vec<String> = std::fs::read_dir(&maps)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(
        names.iter().all(|n| !n.starts_with("standard_patch_")),
        "{names:?}"
    );
    assert!(!names.contains(&"patch_gone.png".to_string()), "{names:?}");
    assert!(names.contains(&"mine.png".to_string()), "{names:?}");
    assert!(names.iter().any(|n| n.starts_with("patch_")), "{names:?}");
}
