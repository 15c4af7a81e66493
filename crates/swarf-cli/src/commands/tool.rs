//! `swarf tool SPEC`: describe a cutter.

use anyhow::{Context, Result};
use swarf_tool::Cutter;

use crate::cli::ToolArgs;
use crate::output::print_json;

pub(crate) fn run(args: &ToolArgs) -> Result<()> {
    let cutter =
        Cutter::from_spec(&args.spec).with_context(|| format!("tool spec `{}`", args.spec))?;
    let d = cutter.describe();
    if args.json {
        return print_json(&d);
    }
    let a = &d.apt;
    println!("{} ({})", d.spec, d.kind.spec_name());
    println!(
        "  APT CUTTER/{}, {}, {}, {}, {}, {}, {}",
        a.diameter_mm,
        a.corner_radius_mm,
        a.corner_center_radial_mm,
        a.corner_center_height_mm,
        a.bottom_angle_deg,
        a.side_angle_deg,
        a.height_mm
    );
    println!(
        "  {} flutes, helix {}°, flute length {} mm, shank Ø{} mm, overall length {} mm",
        d.flutes, d.helix_deg, d.flute_length_mm, d.shank_diameter_mm, d.overall_length_mm
    );
    for p in &d.pieces {
        println!(
            "  {:<12} {:<8} z {:>9.4} .. {:<9.4} radius {:.4} .. {:.4}",
            p.role, p.shape, p.z_min_mm, p.z_max_mm, p.radius_start_mm, p.radius_end_mm
        );
    }
    Ok(())
}
