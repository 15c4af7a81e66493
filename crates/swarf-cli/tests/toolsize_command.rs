//! `swarf toolsize`: the CSV and summary contract on the analytic STEP sphere.
mod common;
use common::*;

#[test]
fn inside_of_the_step_sphere_admits_a_ball_of_its_radius() {
    let dir = std::env::temp_dir().join(format!("swarf-toolsize-{}", std::process::id()));
    let o = swarf(&[
        "toolsize",
        "--surface",
        &shared("step/llnl_revolved_sphere.step"),
        "--cutter",
        "ball",
        "--flip",
        "--grid",
        "9",
        "--out",
        dir.to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j = json(&o);
    for k in [
        "points",
        "bounded_points",
        "min_radius_mm",
        "median_radius_mm",
        "max_radius_mm",
        "evaluations_per_point",
        "elapsed_s",
    ] {
        assert!(j.get(k).is_some(), "{k}: {j}");
    }
    assert!(
        (j["max_radius_mm"].as_f64().unwrap() - 5.0).abs() < 1e-6,
        "{j}"
    );
    let csv = std::fs::read_to_string(dir.join("toolsize.csv")).unwrap();
    let mut rows = csv.lines();
    assert_eq!(
        rows.next().unwrap(),
        "patch,u,v,x,y,z,nx,ny,nz,radius_mm,limit_x,limit_y,limit_z,limit"
    );
    // Every reachable point of the lower half (normal pointing up into the sphere) gets 5.
    let mut checked = 0;
    for r in rows {
        let f: Vec<&str> = r.split(',').collect();
        let (z, nz) = (
            f[5].parse::<f64>().unwrap(),
            f[8].parse::<f64>().unwrap_or(0.0),
        );
        if z < -1.0 && nz > 0.2 {
            let radius: f64 = f[9].parse().unwrap();
            assert!((radius - 5.0).abs() < 1e-6, "{r}");
            checked += 1;
        }
    }
    assert!(checked > 10);
    // From the convex outside nothing limits a ball.
    let o = swarf(&[
        "toolsize",
        "--surface",
        &shared("step/llnl_revolved_sphere.step"),
        "--cutter",
        "ball",
        "--grid",
        "5",
        "--out",
        dir.to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let csv = std::fs::read_to_string(dir.join("toolsize.csv")).unwrap();
    assert!(
        csv.lines()
            .skip(1)
            .any(|r| r.split(',').nth(9) == Some("inf")),
        "{csv}"
    );
}
