//! `swarf tool SPEC --json`: the contract of the tool command.
mod common;
use common::*;

#[test]
fn flat_end_mill_reports_its_apt_parameters() {
    let o = swarf(&["tool", "flat:d=12", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j = json(&o);
    assert_eq!(j["diameter_mm"].as_f64(), Some(12.0), "{j}");
    assert_eq!(j["corner_radius_mm"].as_f64(), Some(0.0), "{j}");
}

#[test]
fn ball_end_mill_has_corner_radius_half_the_diameter() {
    let o = swarf(&["tool", "ball:d=10,flutes=2,helix=30", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j = json(&o);
    assert_eq!(j["corner_radius_mm"].as_f64(), Some(5.0), "{j}");
    assert_eq!(j["flutes"].as_u64(), Some(2), "{j}");
    assert_eq!(j["helix_deg"].as_f64(), Some(30.0), "{j}");
}

#[test]
fn bad_spec_is_bad_input_with_exit_1() {
    let o = swarf(&["tool", "bull:d=16,r=9"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("r"), "{}", stderr(&o));
    let o = swarf(&["tool", "flat:d=-3"]);
    assert_eq!(o.status.code(), Some(1));
    let o = swarf(&["tool", "spoon:d=3"]);
    assert_eq!(o.status.code(), Some(1));
}

#[test]
fn usage_error_exits_2() {
    let o = swarf(&["tool"]);
    assert_eq!(o.status.code(), Some(2));
    let o = swarf(&["frobnicate"]);
    assert_eq!(o.status.code(), Some(2));
}
