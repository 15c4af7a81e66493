//! `swarf toolsize`: the largest gouge- and interference-free cutter at every CC point of a
//! compound surface (3-axis), as `DIR/toolsize.csv` and a JSON summary.

use crate::output::say;
use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use swarf_plan::size::{
    Axes, Axis4Options, Axis5Options, CutterFamily, MapOptions, RotaryAxis, ShankCheck, Solver,
};
use swarf_plan::size::{StandardCutters, StandardOptions, StandardReport, ToolSizeMap};
use swarf_surface::PreparedSurface;
use swarf_tool::FamilySpec;

use crate::output::{print_json, write_atomic};

/// Which solver computes the allowable size.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub(crate) enum SolverArg {
    /// Branch-and-bound with a certificate (the default).
    Certified,
    /// The thesis's particle swarm + Nelder–Mead (seeded, no certificate).
    Pso,
}

/// `swarf toolsize`.
#[derive(Debug, Args)]
pub(crate) struct ToolsizeArgs {
    /// The surface: swarf JSON, STEP or IGES.
    #[arg(long)]
    pub(crate) surface: PathBuf,
    /// Extra check geometry (fixtures, neighbouring parts) as a closed STL mesh: its points
    /// limit the size too, as interference (certified solver only).
    #[arg(long)]
    pub(crate) check: Option<PathBuf>,
    /// The cutter family, its size solved for: `ball`, `ball-side` (with its cylindrical
    /// flutes), `flat`, `bull:r=R`, `taper-ball:taper=T`, `apt:r=R,taper=T,cone=C`
    /// (mm, degrees).
    #[arg(long)]
    pub(crate) cutter: String,
    /// CC points: an N×N iso-parametric grid per patch.
    #[arg(long, default_value_t = 21)]
    pub(crate) grid: usize,
    /// The solver.
    #[arg(long, value_enum, default_value_t = SolverArg::Certified)]
    pub(crate) solver: SolverArg,
    /// Reverse the side the cutter comes from on every patch.
    #[arg(long)]
    pub(crate) flip: bool,
    /// Also check the shank (the cutter's own diameter) above this flute length, mm: where it
    /// reaches into the surface the size is lowered until it is free (limit `interference`).
    #[arg(allow_negative_numbers = true, long)]
    pub(crate) flute_length: Option<f64>,
    /// 4-axis mode: the rotary axis, `X` or `Y`; each point gets the table angle that
    /// maximises the size (CSV column `b_deg`).
    #[arg(long)]
    pub(crate) axis4: Option<String>,
    /// 5-axis mode: `LEAD_MAX,TILT_MAX` in degrees; each point gets the lead and tilt that
    /// maximise the size (CSV columns `lead_deg,tilt_deg`).
    #[arg(long)]
    pub(crate) five_axis: Option<String>,
    /// Standard cutter diameters to select from, mm (`D1,D2,...`): adds the `standard_d_mm`
    /// column, `standard.json` and the `standard` key of the summary.
    #[arg(long)]
    pub(crate) standard: Option<String>,
    /// Output folder (created if missing): `toolsize.csv`, `maps/patch_<name>.png` (colour map
    /// of the radius per patch) and `part.glb` (the part coloured likewise) are written there.
    #[arg(long)]
    pub(crate) out: PathBuf,
    /// Also write one self-contained HTML report here (inputs, the part coloured by allowable
    /// radius in 3-D, the tool-size maps, the summary's figures).
    #[arg(long, value_name = "FILE.html")]
    pub(crate) report: Option<PathBuf>,
    /// Print the JSON summary (the default prints one line).
    #[arg(long)]
    pub(crate) json: bool,
}

/// Parses `--cutter` (the grammar is `swarf_tool::FamilySpec`'s).
fn parse_family(spec: &str) -> Result<CutterFamily> {
    let parsed = FamilySpec::parse(spec).with_context(|| format!("--cutter `{spec}`"))?;
    CutterFamily::from_spec(&parsed).with_context(|| format!("--cutter `{spec}`"))
}

/// Parses `--axis4` / `--five-axis` (at most one; 4/5-axis use the certified solver).
fn parse_axes(args: &ToolsizeArgs) -> Result<Axes> {
    let given = args.axis4.is_some() || args.five_axis.is_some();
    if given && matches!(args.solver, SolverArg::Pso) {
        bail!("--axis4 / --five-axis run the certified solver only (drop --solver pso)");
    }
    match (&args.axis4, &args.five_axis) {
        (Some(_), Some(_)) => bail!("--axis4 and --five-axis exclude each other"),
        (Some(a), None) => {
            let rotary = match a.trim() {
                "X" | "x" => RotaryAxis::X,
                "Y" | "y" => RotaryAxis::Y,
                other => bail!("--axis4 `{other}`: expected X or Y"),
            };
            Ok(Axes::Four(Axis4Options::DEFAULT.with_rotary(rotary)))
        }
        (None, Some(spec)) => {
            let (l, t) = spec
                .split_once(',')
                .with_context(|| format!("--five-axis `{spec}`: expected LEAD_MAX,TILT_MAX"))?;
            let parse = |x: &str| -> Result<f64> {
                x.trim()
                    .parse()
                    .with_context(|| format!("--five-axis `{spec}`: `{x}` is not a number"))
            };
            let o = Axis5Options::DEFAULT.with_limits(parse(l)?, parse(t)?);
            o.validate()
                .with_context(|| format!("--five-axis `{spec}`"))?;
            Ok(Axes::Five(o))
        }
        (None, None) => Ok(Axes::Three),
    }
}

pub(crate) fn run(args: &ToolsizeArgs) -> Result<()> {
    crate::commands::report::prepare(args.report.as_deref())?;
    if args.check.is_some() && matches!(args.solver, SolverArg::Pso) {
        bail!("--check needs --solver certified (the PSO solver samples the surface only)");
    }
    let family = parse_family(&args.cutter)?;
    let standard = args
        .standard
        .as_deref()
        .map(StandardCutters::parse)
        .transpose()
        .context("--standard")?;
    let mut surface = swarf_surface::io::read_file(&args.surface)
        .with_context(|| format!("reading {}", args.surface.display()))?;
    if surface.patches.is_empty() {
        bail!("{}: no surface patches", args.surface.display());
    }
    if args.flip {
        surface.flip_all();
    }
    for note in &surface.notes {
        eprintln!("note: {note}");
    }
    let axes = parse_axes(args)?;
    let opts = MapOptions {
        axes,
        solver: match args.solver {
            SolverArg::Certified => Solver::Certified,
            SolverArg::Pso => Solver::Pso,
        },
        shank: args.flute_length.map(ShankCheck::new),
        ..MapOptions::default()
    };
    if args.grid < 2 {
        bail!(
            "--grid must be at least 2 (the patch's corners), got {}",
            args.grid
        );
    }
    if let Some(l) = args.flute_length.filter(|l| !(l.is_finite() && *l > 0.0)) {
        bail!("--flute-length must be a positive number of mm, got {l}");
    }
    let points = surface.lattice_len(args.grid);
    if points > swarf_surface::compound::MAX_GRID_POINTS {
        bail!(
            "--grid {} gives {points} grid points on {} patch(es), more than {}; give a smaller --grid",
            args.grid,
            surface.patches.len(),
            swarf_surface::compound::MAX_GRID_POINTS
        );
    }
    let ccs = surface.grid(args.grid);
    let mut prep = PreparedSurface::new(&surface);
    if let Some(path) = &args.check {
        let mesh = swarf_io::read_stl(path)?;
        prep = prep.with_check_mesh(&path.display().to_string(), &mesh)?;
    }
    let map = swarf_plan::size::allowable_map_prepared(&surface, &prep, &family, &ccs, &opts);
    // The library writes maps and meshes to paths: into a staging folder, moved into --out as
    // one set at the end (all of the files, or none).
    let mut stage = crate::output::Staging::for_dir(&args.out)?;
    // A folder reused from another run keeps this run's maps and results only.
    stage.owns_plots("maps", &["patch_", "standard_patch_"]);
    stage.owns_file("standard.json");
    let mut csv = Vec::new();
    match &standard {
        Some(c) => c.write_csv(&map, &surface, &mut csv),
        None => map.write_csv(&surface, &mut csv),
    }
    .context("formatting toolsize.csv")?;
    write_atomic(&stage.path().join("toolsize.csv"), &csv)?;
    let standard_report =
        write_standard_and_maps(args, stage.path(), &surface, &map, standard.as_ref())?;
    let summary = map.summary();
    let caveats = surface.caveats();
    let with_standard = |summary: &swarf_plan::size::MapSummary, r: Option<&StandardReport>| {
        crate::output::with_caveats(with_standard(summary, r)?, &caveats)
    };
    // The summary too, as every command's --out holds one (`swarf report --from` reads it).
    let json = serde_json::to_vec_pretty(&with_standard(&summary, standard_report.as_ref())?)
        .context("formatting summary.json")?;
    write_atomic(&stage.path().join("summary.json"), &json)?;
    stage.commit(&args.out, crate::output::DEFAULT_MAX_OUTPUT_MB)?;
    if let Some(path) = &args.report {
        let value = with_standard(&summary, standard_report.as_ref())?;
        write_report(path, args, &surface, &map, value)?;
    }
    if args.json {
        print_json(&with_standard(&summary, standard_report.as_ref())?)?;
    } else {
        // No bounded point: no radius to give (the JSON's null).
        let mm = |r: Option<f64>| r.map_or_else(|| "none".to_string(), |x| format!("{x:.3}"));
        say!(
            "{} points, {} bounded ({} unreachable), radius min {} median {} max {} mm, {:.0} evaluations/point, {:.2} s",
            summary.points,
            summary.bounded_points,
            summary.unreachable_points,
            mm(summary.min_radius_mm),
            mm(summary.median_radius_mm),
            mm(summary.max_radius_mm),
            summary.evaluations_per_point,
            summary.elapsed_s
        );
    }
    crate::output::caveats_said(&caveats, "radii");
    // A face whose trimmed region falls between the grid's rows and columns gets no point: its
    // sizes are not in the map, which only a warning can tell.
    let off_grid = surface.patches_without(&ccs);
    if !off_grid.is_empty() {
        let names: Vec<String> = off_grid
            .iter()
            .take(5)
            .map(|&k| match &surface.patches[k].name {
                Some(n) => format!("patch {k} ({n})"),
                None => format!("patch {k}"),
            })
            .collect();
        eprintln!(
            "warning: {} of {} patches get no grid point on the part at --grid {} ({}{}): a \
             larger --grid samples them",
            off_grid.len(),
            surface.patches.len(),
            args.grid,
            names.join(", "),
            if off_grid.len() > 5 { ", …" } else { "" }
        );
    }
    if summary.uncertified_points > 0 && matches!(args.solver, SolverArg::Certified) {
        eprintln!(
            "warning: at {} of {} points the certified solver ran out of its node budget: their \
             radius is the best it found, not certified (the CSV's `certified` column is false \
             there)",
            summary.uncertified_points, summary.points
        );
    }
    let shank_hits = map
        .points
        .iter()
        .filter(|p| matches!(p.shank, Some(swarf_plan::size::ShankStatus::Limits { .. })))
        .count();
    if shank_hits > 0 {
        eprintln!(
            "note: the shank lowers the allowable size at {shank_hits} points (limit = \
             interference at the shank's point)"
        );
    }
    Ok(())
}

/// Writes `DIR/maps/patch_<label>.png`, `DIR/part.glb` and, with `--standard`,
/// `DIR/maps/standard_patch_<label>.png` and `DIR/standard.json` (the [`StandardReport`], also
/// returned).
fn write_standard_and_maps(
    args: &ToolsizeArgs,
    out: &std::path::Path,
    surface: &swarf_surface::CompoundSurface,
    map: &ToolSizeMap,
    standard: Option<&StandardCutters>,
) -> Result<Option<StandardReport>> {
    let plot = swarf_plan::plot::PlotOptions::default();
    swarf_plan::plot::write_patch_maps(surface, map, args.grid, &out.join("maps"), &plot)?;
    let tol = swarf_surface::Tolerances::DEFAULT;
    swarf_plan::plot::write_part_glb(&out.join("part.glb"), surface, map, args.grid, &tol)?;
    let Some(cutters) = standard else {
        return Ok(None);
    };
    let maps = out.join("maps");
    swarf_plan::plot::write_standard_maps(surface, map, args.grid, cutters, &maps, &plot)?;
    let opts = StandardOptions::default();
    let report = StandardReport::from_grid_map(cutters, surface, map, args.grid, &opts)?;
    let json = serde_json::to_vec_pretty(&report).context("formatting standard.json")?;
    write_atomic(&out.join("standard.json"), &json)?;
    Ok(Some(report))
}

/// The JSON summary with the `standard` key added when there is a report.
fn with_standard(
    summary: &impl serde::Serialize,
    report: Option<&StandardReport>,
) -> Result<serde_json::Value> {
    let mut v = serde_json::to_value(summary)?;
    if let (Some(r), Some(obj)) = (report, v.as_object_mut()) {
        obj.insert("standard".into(), serde_json::to_value(r)?);
    }
    Ok(v)
}

/// `--report FILE.html`: the part coloured by allowable radius, the maps written to
/// `DIR/maps`, the summary's figures.
fn write_report(
    path: &std::path::Path,
    args: &ToolsizeArgs,
    surface: &swarf_surface::CompoundSurface,
    map: &ToolSizeMap,
    summary: serde_json::Value,
) -> Result<()> {
    let tol = swarf_surface::Tolerances::DEFAULT;
    let mesh = swarf_plan::plot::part_mesh(surface, map, args.grid, &tol)
        .context("the part coloured by allowable radius")?;
    let mut page = swarf_io::html::Report::new("swarf toolsize")
        .with_input("surface", args.surface.display().to_string())
        .with_input("cutter family", args.cutter.clone())
        .with_input("grid", format!("{0} × {0} per patch", args.grid))
        .with_mesh("part coloured by allowable radius", mesh)
        .with_pngs_in(&args.out.join("maps"))?
        .with_summary(
            summary,
            &[
                "points",
                "bounded_points",
                "unreachable_points",
                "min_radius_mm",
                "median_radius_mm",
                "max_radius_mm",
            ],
        );
    for (label, value) in [
        (
            "check geometry",
            args.check.as_ref().map(|p| p.display().to_string()),
        ),
        ("4-axis rotary", args.axis4.clone()),
        ("5-axis lead,tilt", args.five_axis.clone()),
        ("standard diameters", args.standard.clone()),
    ] {
        if let Some(v) = value {
            page = page.with_input(label, v);
        }
    }
    crate::commands::report::write(&page, path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cutter_specs() {
        assert_eq!(parse_family("ball").unwrap(), CutterFamily::ball());
        assert_eq!(parse_family("flat").unwrap(), CutterFamily::flat());
        assert_eq!(
            parse_family("bull:r=2").unwrap(),
            CutterFamily::bull(2.0).unwrap()
        );
        assert_eq!(
            parse_family("taper-ball:taper=3").unwrap(),
            CutterFamily::taper_ball(3.0).unwrap()
        );
        assert!(parse_family("bull").is_err());
        assert!(parse_family("ball:r=1").is_err());
        assert!(parse_family("taper-ball:taper=95").is_err());
        assert!(parse_family("drill").is_err());
    }
}
