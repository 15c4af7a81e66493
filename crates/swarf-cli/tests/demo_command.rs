//! `swarf demo`: the built-in job runs end to end and its mesh is the simulated solid.
mod common;
use common::*;

#[test]
fn demo_simulates_and_writes_a_closed_mesh_of_the_final_stock() {
    let dir = swarf_testdata::scratch_dir("demo-test");
    let _ = std::fs::remove_dir_all(&dir);
    let o = swarf(&["demo", "--out", dir.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j = json(&o);
    let sim = &j["simulation"];
    assert!(
        sim["removed_volume_mm3"].as_f64().unwrap() > 20_000.0,
        "{j}"
    );
    assert_eq!(sim["rapid_collisions"], 0, "{j}");
    assert_eq!(sim["holder_collisions"], 0, "{j}");
    assert_eq!(
        j["program"]["undefined_tools"],
        serde_json::json!([]),
        "{j}"
    );
    for f in [
        "stock.stl",
        "stock.glb",
        "moves.csv",
        "summary.json",
        "canonical.txt",
        "demo.ngc",
        "report.html",
    ] {
        assert!(dir.join(f).is_file(), "{f} missing");
    }
    // The report shows the demo's figures as its JSON prints them, the gouges linked to lines.
    let page = std::fs::read_to_string(dir.join("report.html")).unwrap();
    let gouge = format!("{}", j["gouge"]["max_gouge_mm"]);
    assert!(
        page.contains("gouge.max_gouge_mm") && page.contains(&gouge),
        "{gouge}"
    );
    assert!(page.contains("demo/demo.ngc"));
    let mesh = swarf_io::read_stl(&dir.join("stock.stl")).unwrap();
    assert!(mesh.is_closed());
    let final_volume = sim["final_volume_mm3"].as_f64().unwrap();
    let rel = (mesh.volume() - final_volume).abs() / final_volume;
    assert!(
        rel < 2e-3,
        "mesh volume {} vs dexel volume {final_volume}",
        mesh.volume()
    );
}
