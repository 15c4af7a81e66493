//! Degenerate and hostile programs: no panic, no runaway, an error that names the line.

mod common;

use common::{block, program};
use swarf_engage::{EngageError, EngageOptions, Engager};
use swarf_tool::{Cutter, ToolSet};

fn engage(text: &str, opts: EngageOptions) -> Result<Vec<swarf_engage::Engagement>, EngageError> {
    let p = program(text, "bad.ngc");
    let mut stock = block([0.0, 0.0, -5.0], [20.0, 20.0, 0.0], 0.25);
    let tools = ToolSet::single(Cutter::flat(6.0).unwrap());
    Engager::new(&p, &tools, &mut stock, opts)?.collect()
}

#[test]
fn an_empty_program_has_no_locations() {
    assert!(engage("", EngageOptions::default()).unwrap().is_empty());
}

#[test]
fn a_zero_length_move_is_one_location_with_nothing_engaged() {
    let locs = engage(
        "G21\nG0 X10 Y10 Z-1\nG1 X10 F100\n",
        EngageOptions::default(),
    )
    .unwrap();
    assert_eq!(locs.len(), 1);
    assert_eq!(locs[0].area_mm2, 0.0);
    assert_eq!(locs[0].removed_mm3, 0.0);
    assert!(locs[0].phi_entry_deg.is_none());
}

#[test]
fn a_step_far_below_the_move_is_refused_at_its_line() {
    let e = engage(
        "G21\nG0 X0 Y10 Z1\nG1 X10 F100\n",
        EngageOptions::default().with_step(1e-9),
    )
    .unwrap_err();
    let msg = e.to_string();
    assert!(
        matches!(e, EngageError::TooManyLocations { line: 3, .. }),
        "{msg}"
    );
    assert!(
        msg.starts_with("bad.ngc:3:") && msg.contains("larger --step"),
        "{msg}"
    );
}

#[test]
fn options_out_of_range_are_refused() {
    for opts in [
        EngageOptions::default().with_step(-1.0),
        EngageOptions::default().with_dz(0.0),
        EngageOptions::default().with_dz(3.0),
        EngageOptions::default().with_dphi(f64::NAN),
        EngageOptions::default().with_chordal_tolerance(0.0),
    ] {
        assert!(matches!(
            engage("G21\nG1 X1 F100\n", opts),
            Err(EngageError::BadOption { .. })
        ));
    }
}

#[test]
fn discs_and_angles_finer_than_memory_allows_are_refused_before_sampling() {
    // Each option alone is in range; together they would ask ≈ 10¹⁰ samples a location.
    let e = engage(
        "G21\nG0 X0 Y10 Z-1\nG1 X10 F100\n",
        EngageOptions::default().with_dz(0.0002).with_dphi(0.01),
    )
    .unwrap_err();
    let msg = e.to_string();
    assert!(matches!(e, EngageError::TooManySamples { .. }), "{msg}");
    assert!(msg.contains("larger --dz or --dphi"), "{msg}");
    // Fine but affordable: accepted.
    assert!(engage(
        "G21\nG0 X0 Y10 Z-1\nG1 X1 F100\n",
        EngageOptions::default().with_dz(0.01).with_dphi(0.1),
    )
    .is_ok());
}
