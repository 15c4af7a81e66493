//! `swarf tool SPEC`: describe a cutter.

use crate::output::say;
use anyhow::{Context, Result};
use clap::Args;
use swarf_tool::Cutter;

use crate::output::print_json;

/// `swarf tool`.
#[derive(Debug, Args)]
pub(crate) struct ToolArgs {
    /// The tool spec, e.g. `bull:d=16,r=2,flutes=4,helix=35`.
    pub(crate) spec: String,
    /// Print JSON (the default output is a short human-readable description).
    #[arg(long)]
    pub(crate) json: bool,
}

pub(crate) fn run(args: &ToolArgs) -> Result<()> {
    let cutter =
        Cutter::from_spec(&args.spec).with_context(|| format!("tool spec `{}`", args.spec))?;
    let d = cutter.describe();
    if args.json {
        return print_json(&d);
    }
    let a = &d.apt;
    say!("{} ({})", d.spec, d.kind.spec_name());
    // Ten decimals (the JSON keeps every digit).
    let n = |x: f64| crate::output::trimmed(x, 10);
    say!(
        "  APT CUTTER/{}, {}, {}, {}, {}, {}, {}",
        n(a.diameter_mm),
        n(a.corner_radius_mm),
        n(a.corner_center_radial_mm),
        n(a.corner_center_height_mm),
        n(a.bottom_angle_deg),
        n(a.side_angle_deg),
        n(a.height_mm)
    );
    let default = if d.flutes_given {
        ""
    } else {
        " (default; swarf forces needs flutes=N)"
    };
    say!(
        "  {} flutes{default}, helix {}°, flute length {} mm, shank Ø{} mm, overall length {} mm",
        d.flutes,
        d.helix_deg,
        d.flute_length_mm,
        d.shank_diameter_mm,
        d.overall_length_mm
    );
    for p in &d.pieces {
        say!(
            "  {:<12} {:<8} z {:>9.4} .. {:<9.4} radius {:.4} .. {:.4}",
            p.role,
            p.shape,
            p.z_min_mm,
            p.z_max_mm,
            p.radius_start_mm,
            p.radius_end_mm
        );
    }
    Ok(())
}
