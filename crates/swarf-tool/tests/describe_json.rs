//! The JSON description printed by `swarf tool SPEC --json`.

use swarf_tool::Cutter;

#[test]
fn bull_nose_description() {
    let c = Cutter::from_spec("bull:d=16,r=2,flutes=4").unwrap();
    let v: serde_json::Value = serde_json::to_value(c.describe()).unwrap();
    assert_eq!(v["kind"], "bull");
    assert_eq!(v["diameter_mm"], 16.0);
    assert_eq!(v["corner_radius_mm"], 2.0);
    assert_eq!(v["corner_center_radial_mm"], 6.0);
    assert_eq!(v["corner_center_height_mm"], 2.0);
    assert_eq!(v["bottom_angle_deg"], 0.0);
    assert_eq!(v["side_angle_deg"], 0.0);
    assert_eq!(v["height_mm"], 48.0);
    assert_eq!(v["flutes"], 4);
    assert_eq!(v["helix_deg"], 30.0);
    assert_eq!(v["max_diameter_mm"], 16.0);
    assert_eq!(v["tip_to_corner_center_mm"], 2.0);
    assert!(v["holder"].is_null());
    let roles: Vec<&str> = v["pieces"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["role"].as_str().unwrap())
        .collect();
    assert_eq!(roles, ["bottom_disc", "corner", "side", "top_cap"]);
    let corner = &v["pieces"][1];
    assert_eq!(corner["shape"], "torus");
    assert_eq!(corner["arc_radius_mm"], 2.0);
    assert_eq!(corner["arc_center_mm"], serde_json::json!([6.0, 2.0]));
    assert_eq!(corner["radius_start_mm"], 6.0);
    assert!((corner["z_max_mm"].as_f64().unwrap() - 2.0).abs() < 1e-15);
    assert_eq!(v["pieces"][3]["cutting"], false);
    assert!(v["spec"].as_str().unwrap().starts_with("bull:d=16,r=2"));
}
