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
