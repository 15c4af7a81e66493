//! The 3-axis map: the CSV contract of `swarf toolsize` (exact header, `inf`, `0`, empty
//! radius where the normal is undefined, patch names or indices) and the JSON summary keys;
//! certified and PSO agree on a simple part.

use swarf_geom::math::Vec3;
use swarf_plan::size::map::CSV_HEADER;
use swarf_plan::size::{allowable_map, CutterFamily, MapOptions, Solver};
use swarf_surface::{CompoundSurface, NurbsSurface, Patch, Surface};

fn bilinear(p00: Vec3, p10: Vec3, p01: Vec3, p11: Vec3) -> NurbsSurface {
    NurbsSurface::new(
        1,
        1,
        vec![0.0, 0.0, 1.0, 1.0],
        vec![0.0, 0.0, 1.0, 1.0],
        &[vec![p00, p01], vec![p10, p11]],
        None,
    )
    .unwrap()
}

fn part() -> CompoundSurface {
    let floor = bilinear(
        Vec3::new(-10.0, -10.0, 0.0),
        Vec3::new(10.0, -10.0, 0.0),
        Vec3::new(-10.0, 10.0, 0.0),
        Vec3::new(10.0, 10.0, 0.0),
    );
    let wall = bilinear(
        Vec3::new(10.0, -10.0, 0.0),
        Vec3::new(10.0, 10.0, 0.0),
        Vec3::new(10.0, -10.0, 5.0),
        Vec3::new(10.0, 10.0, 5.0),
    );
    // A patch collapsed onto a line: no normal anywhere.
    let needle = bilinear(
        Vec3::new(-20.0, 0.0, 0.0),
        Vec3::new(-15.0, 0.0, 0.0),
        Vec3::new(-20.0, 0.0, 0.0),
        Vec3::new(-15.0, 0.0, 0.0),
    );
    let mut f = Patch::new(Surface::Nurbs(floor));
    f.name = Some("floor".into());
    let mut w = Patch::new(Surface::Nurbs(wall));
    w.flipped = true; // the cutter comes from −x
    CompoundSurface::new(vec![f, w, Patch::new(Surface::Nurbs(needle))])
}

#[test]
fn csv_rows_and_summary() {
    let part = part();
    let ccs = part.grid(3);
    let map = allowable_map(&part, &CutterFamily::flat(), &ccs, &MapOptions::default());
    let mut out = Vec::new();
    map.write_csv(&part, &mut out).unwrap();
    let text = String::from_utf8(out).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "patch,u,v,x,y,z,nx,ny,nz,radius_mm,limit_x,limit_y,limit_z,limit,certified"
    );
    assert_eq!(
        CSV_HEADER,
        "patch,u,v,x,y,z,nx,ny,nz,radius_mm,limit_x,limit_y,limit_z,limit"
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    // Numbers are compared as numbers: the CSV writes shortest round-trip text.
    let num = |s: &str| s.parse::<f64>().unwrap_or(f64::NAN);
    assert_eq!(rows.len(), 27);
    assert!(rows.iter().all(|r| r.len() == 15));
    // Every solved point of the certified solver carries its certificate; the needle's
    // (no normal, nothing solved) is empty.
    assert!(
        rows.iter()
            .all(|r| r[14] == if r[0] == "2" { "" } else { "true" }),
        "{rows:?}"
    );
    // Floor centre (0, 0, 0): the wall at 10 mm limits, by interference.
    let centre = rows
        .iter()
        .find(|r| r[0] == "floor" && num(r[1]) == 0.5 && num(r[2]) == 0.5)
        .unwrap();
    let radius: f64 = centre[9].parse().unwrap();
    assert!((radius - 10.0).abs() < 1e-6, "{centre:?}");
    assert_eq!(centre[13], "interference");
    assert_eq!(num(centre[10]), 10.0);
    // On the floor at the wall's foot: 0 (a flat end mill's bottom cannot reach into the
    // corner it stands in: the wall is right there).
    let foot = rows
        .iter()
        .find(|r| r[0] == "floor" && num(r[1]) == 1.0 && num(r[2]) == 0.5)
        .unwrap();
    let radius: f64 = foot[9].parse().unwrap();
    assert!(radius < 2e-3, "{foot:?}");
    // The wall's own points: nothing limits a flat end mill standing beside it: inf, no limit.
    let wall_mid = rows
        .iter()
        .find(|r| r[0] == "1" && r[1] == "0.5" && r[2] == "0.5")
        .unwrap();
    assert_eq!(wall_mid[9], "inf");
    assert_eq!(&wall_mid[10..14], &["", "", "", ""]);
    // The needle: no normal, empty radius.
    let needle: Vec<_> = rows.iter().filter(|r| r[0] == "2").collect();
    assert_eq!(needle.len(), 9);
    assert!(
        needle.iter().all(|r| r[6].is_empty() && r[9].is_empty()),
        "{needle:?}"
    );

    let s = map.summary();
    assert_eq!(s.points, 27);
    let json = serde_json::to_value(&s).unwrap();
    for key in [
        "points",
        "bounded_points",
        "unreachable_points",
        "min_radius_mm",
        "median_radius_mm",
        "max_radius_mm",
        "uncertified_points",
        "evaluations_per_point",
        "elapsed_s",
    ] {
        assert!(json.get(key).is_some(), "missing {key}");
    }
    assert_eq!(json.as_object().unwrap().len(), 9);
    assert_eq!(s.uncertified_points, 0);
}

#[test]
fn pso_agrees_with_certified_and_is_reproducible() {
    let part = part();
    let ccs = part
        .points(&[(0, 0.5, 0.5), (0, 0.2, 0.7), (0, 0.9, 0.1)])
        .unwrap();
    let cert = allowable_map(&part, &CutterFamily::flat(), &ccs, &MapOptions::default());
    let opts = MapOptions {
        solver: Solver::Pso,
        ..MapOptions::default()
    };
    let a = allowable_map(&part, &CutterFamily::flat(), &ccs, &opts);
    let b = allowable_map(&part, &CutterFamily::flat(), &ccs, &opts);
    for ((c, p), q) in cert.points.iter().zip(&a.points).zip(&b.points) {
        let (c, p, q) = (
            c.radius_mm.unwrap(),
            p.radius_mm.unwrap(),
            q.radius_mm.unwrap(),
        );
        assert_eq!(p, q, "PSO is seeded: same result twice");
        assert!(p >= c - 1e-7 && p - c < 1e-3, "pso {p} vs certified {c}");
    }
    // The swarm proves nothing: every point it solved is uncertified.
    assert_eq!(a.summary().uncertified_points, 3);
    assert_eq!(cert.summary().uncertified_points, 0);
}
