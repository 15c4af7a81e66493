//! `swarf verify`: simulate a program, then compare the machined part with the design part
//! (`DIR/defects.csv`, `DIR/deviation.glb`, `DIR/summary.json`).

use crate::output::say;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context, Result};
use clap::Args;
use serde::Serialize;
use swarf_io::{GlbOptions, Shading};
use swarf_path::Program;
use swarf_stock::SimOptions;
use swarf_verify::{
    deviation_mesh, html_report, verify, Design, Legend, MeshDesign, Region, ReportInputs,
    SurfaceDesign, Verification, VerifyOptions,
};

use crate::cli::SetupArgs;
use crate::commands::simulate::{
    build_stock, positive_mm, simulate_with_progress, SimulateSummary,
};
use crate::commands::tools::{defined_tools, load_job};
use crate::output::{csv_field, print_json, write_atomic};

/// `swarf verify`.
#[derive(Debug, Args)]
pub(crate) struct VerifyArgs {
    /// The stock: `box:X0,Y0,Z0,X1,Y1,Z1`, `cyl:CX,CY,Z0,R,H` (axis +Z) or a closed STL file.
    /// Default: the workpiece a CAMotics project (--tools FILE.camotics) states.
    #[arg(long, value_name = "SPEC|FILE.stl")]
    pub(crate) stock: Option<String>,
    /// The program: G-code, APT CL, Heidenhain conversational or Sinumerik.
    #[arg(long, value_name = "FILE")]
    pub(crate) program: PathBuf,
    /// Cutters, tool library, machine and units.
    #[command(flatten)]
    pub(crate) setup: SetupArgs,
    /// The design part: a closed STL mesh, or surfaces (swarf JSON, STEP, IGES) whose normals
    /// point to the outside (the side the cutter comes from).
    #[arg(long, value_name = "FILE")]
    pub(crate) design: PathBuf,
    /// Reverse the orientation of every surface of a JSON/STEP/IGES design.
    #[arg(long)]
    pub(crate) flip: bool,
    /// Where the design file lies in the program's frame, when CAD exported it elsewhere:
    /// `X,Y,Z` moves it by that much (mm); `X,Y,Z,RZ` or `X,Y,Z,RX,RY,RZ` first turns it by
    /// those degrees about the X, Y and Z axes through its origin, in that order.
    #[arg(long, value_name = "X,Y,Z[,RZ]", value_parser = crate::cli::parse_part_at, allow_hyphen_values = true)]
    pub(crate) part_at: Option<swarf_geom::RigidMotion>,
    /// Ray spacing of the tri-dexel stock, mm.
    #[arg(
        long,
        value_name = "H",
        default_value_t = 0.25,
        allow_negative_numbers = true
    )]
    pub(crate) resolution: f64,
    /// Gouge tolerance: material removed deeper than this inside the part is a gouge, mm.
    #[arg(long, value_name = "T", default_value_t = swarf_verify::DEFAULT_GOUGE_TOLERANCE_MM, allow_negative_numbers = true)]
    pub(crate) tolerance: f64,
    /// Excess tolerance: material left thicker than this outside the part is excess, mm.
    #[arg(long, value_name = "T2", default_value_t = swarf_verify::DEFAULT_EXCESS_TOLERANCE_MM, allow_negative_numbers = true)]
    pub(crate) excess_tolerance: f64,
    /// Largest distance between an arc or a 5-axis motion and what is cut for it, mm.
    #[arg(long, value_name = "T", default_value_t = swarf_stock::DEFAULT_CHORDAL_TOLERANCE_MM, allow_negative_numbers = true)]
    pub(crate) chordal_tolerance: f64,
    /// Deviation at the ends of deviation.glb's colour scale, mm (default: the larger of the
    /// deepest gouge and the thickest excess, at least twice the tolerance).
    #[arg(long, value_name = "MM", allow_negative_numbers = true)]
    pub(crate) color_range: Option<f64>,
    /// Build the stock from an STL mesh even if it is not closed.
    #[arg(long)]
    pub(crate) allow_open_mesh: bool,
    /// Also write one self-contained HTML report here (3-D view, deviation histogram, figures,
    /// defects linked to the program's lines; opens offline).
    #[arg(long, value_name = "FILE.html")]
    pub(crate) report: Option<PathBuf>,
    /// Output folder (created if missing).
    #[arg(long, value_name = "DIR")]
    pub(crate) out: PathBuf,
    /// Print the JSON summary (the default prints a short report).
    #[arg(long)]
    pub(crate) json: bool,
}

/// `summary.json`. The first eight keys are the contract; the rest may grow.
#[derive(Serialize)]
struct VerifySummary<'a> {
    max_gouge_mm: f64,
    max_excess_mm: f64,
    gouge_regions: usize,
    excess_regions: usize,
    /// Material left outside the part, mm³ (`volume_method` says how it was measured).
    excess_volume_mm3: f64,
    tolerance_mm: f64,
    /// Rapid and holder collisions of the simulation.
    collisions: usize,
    elapsed_s: f64,
    excess_tolerance_mm: f64,
    /// Part material missing, mm³.
    gouge_volume_mm3: f64,
    /// `z-rays` (exact pieces of stock ∖ part along the Z rays: a solid design) or
    /// `surface-integral` (∫ |deviation| dA over the regions: a surface design).
    volume_method: &'static str,
    /// Design material above or below the stock's box over its footprint, mm³ (Z rays; null
    /// for a surface design): not compared, as the stock never held it.
    design_outside_stock_mm3: Option<f64>,
    /// The design's box reaches beyond the stock's (another frame, or fixtures in the file).
    design_beyond_stock_box: bool,
    ends_checked: u64,
    ends_unmatched: u64,
    gouge_ends: u64,
    excess_ends: u64,
    resolution_mm: [f64; 3],
    design: String,
    verify_elapsed_s: f64,
    legend: &'a Legend,
    simulation: &'a SimulateSummary,
    regions: &'a [Region],
    histogram: &'a swarf_verify::Histogram,
    /// What the design's reader could not carry over (a surface design; empty for a mesh):
    /// `skipped_faces`, `untrimmed_faces`, `unapplied_placements` with their notes.
    #[serde(flatten)]
    design_caveats: swarf_surface::Caveats,
}

pub(crate) fn run(args: &VerifyArgs) -> Result<()> {
    crate::commands::report::prepare(args.report.as_deref())?;
    let t0 = Instant::now();
    positive_mm("resolution", args.resolution)?;
    positive_mm("chordal-tolerance", args.chordal_tolerance)?;
    for (name, v) in [
        ("tolerance", args.tolerance),
        ("excess-tolerance", args.excess_tolerance),
    ] {
        if !(v >= 0.0 && v.is_finite()) {
            bail!("--{name} must be a number of mm ≥ 0, got {v}");
        }
    }
    if let Some(r) = args.color_range {
        positive_mm("color-range", r)?;
    }
    // The design first: a bad design file fails before any simulation.
    let (design, design_caveats) = load_design(&args.design, args.flip, args.part_at.as_ref())?;
    crate::output::caveats_said(&design_caveats, "deviations");
    let job = load_job(&args.setup, &args.program)?;
    let tools = defined_tools(&job)?;
    let resolved = tools.resolved();
    let program = &job.program;
    crate::commands::tools::check_resolution(tools, args.resolution)?;
    let mut stock = build_stock(
        args.stock.as_deref(),
        job.setup.table.as_ref(),
        (program, tools),
        args.resolution,
        args.allow_open_mesh,
    )?;
    stock.track_provenance();
    let options = SimOptions::default().with_chordal_tolerance(args.chordal_tolerance);
    let report = simulate_with_progress(program, tools, &mut stock, &options)
        .with_context(|| format!("simulating {}", args.program.display()))?;
    let sim = SimulateSummary::new(&report, program);
    sim.warn_spindle_stopped();
    let vopts = VerifyOptions::default()
        .with_gouge_tolerance(args.tolerance)
        .with_excess_tolerance(args.excess_tolerance);
    let v = verify(&stock, design.as_ref(), Some(program), &vopts)
        .with_context(|| format!("verifying against {}", args.design.display()))?;
    // A comparison of nothing is no pass (a design of no area, or one far from the stock,
    // reported 0 gouges and 0 excess).
    if v.ends_checked == 0 {
        bail!(
            "no ray end of the machined stock was compared with the design {}: it has no \
             surface near the stock (a design of no area, or in another frame: place it with \
             --part-at)",
            args.design.display()
        );
    }
    if v.design_beyond_stock_box {
        let b = design.bounding_box();
        let g = stock.grid();
        let outside = v.design_outside_stock_mm3.map_or(String::new(), |o| {
            format!("; {o:.1} mm³ of it lies above or below the stock")
        });
        eprintln!(
            "warning: the design reaches beyond the stock's box (design {:.3}…{:.3}, {:.3}…{:.3}, \
             {:.3}…{:.3}; stock {:.3}…{:.3}, {:.3}…{:.3}, {:.3}…{:.3}){outside}: what lies \
             outside is not compared. A design in another frame: place it with --part-at; \
             fixtures or a machine exported with the part: leave them out",
            b.min.x,
            b.max.x,
            b.min.y,
            b.max.y,
            b.min.z,
            b.max.z,
            g.min.x,
            g.max.x,
            g.min.y,
            g.max.y,
            g.min.z,
            g.max.z,
        );
    }
    let range = args.color_range.unwrap_or_else(|| {
        v.max_gouge_mm
            .max(v.max_excess_mm)
            .max(2.0 * args.tolerance.max(args.excess_tolerance))
    });
    let (mesh, legend) = deviation_mesh(&stock, design.as_ref(), range);
    // Every output as one set: all of the files, or none.
    let mut set = crate::output::output_set(&args.out, crate::output::DEFAULT_MAX_OUTPUT_MB)?;
    let extras = serde_json::json!({ "swarf_deviation_legend": &legend });
    let options = GlbOptions::default()
        .with_shading(Shading::Smooth)
        .with_extras(extras);
    let glb = swarf_io::glb::GlbFile::new(&mesh, &options).context("encoding deviation.glb")?;
    set.write("deviation.glb", |w| glb.write_to(w))?;
    set.write_bytes("defects.csv", defects_csv(&v, program).as_bytes())?;
    let summary = VerifySummary {
        max_gouge_mm: v.max_gouge_mm,
        max_excess_mm: v.max_excess_mm,
        gouge_regions: v.gouges().count(),
        excess_regions: v.excesses().count(),
        excess_volume_mm3: v.excess_volume(),
        tolerance_mm: args.tolerance,
        collisions: report.rapid_collisions.len() + report.holder_collisions.len(),
        elapsed_s: t0.elapsed().as_secs_f64(),
        excess_tolerance_mm: args.excess_tolerance,
        gouge_volume_mm3: v.gouge_volume(),
        volume_method: v.volume_method(),
        design_outside_stock_mm3: v.design_outside_stock_mm3,
        design_beyond_stock_box: v.design_beyond_stock_box,
        ends_checked: v.ends_checked,
        ends_unmatched: v.ends_unmatched,
        gouge_ends: v.gouge_ends,
        excess_ends: v.excess_ends,
        resolution_mm: v.resolution_mm,
        design: design.describe(),
        verify_elapsed_s: v.elapsed_s,
        legend: &legend,
        simulation: &sim,
        regions: &v.regions,
        histogram: &v.histogram,
        design_caveats,
    };
    let mut json = serde_json::to_vec_pretty(&summary)?;
    json.push(b'\n');
    set.write_bytes("summary.json", &json)?;
    set.commit()?;
    if let Some(path) = &args.report {
        let sources = crate::commands::report::sources(program);
        let text = std::str::from_utf8(&json).context("summary.json is not UTF-8")?;
        let inputs = ReportInputs {
            program,
            sources: &sources,
            inputs: vec![
                ("program".into(), args.program.display().to_string()),
                (
                    "stock".into(),
                    args.stock
                        .clone()
                        .unwrap_or_else(|| "from the tool project".into()),
                ),
                (
                    "design".into(),
                    format!("{} ({})", args.design.display(), design.describe()),
                ),
                ("machine".into(), args.setup.machine.clone()),
                ("resolution".into(), format!("{} mm", args.resolution)),
            ],
            tools: resolved
                .iter()
                .map(|(n, r)| {
                    let d = if r.description.is_empty() {
                        r.cutter.spec()
                    } else {
                        r.description.clone()
                    };
                    (*n, d, &r.cutter)
                })
                .collect(),
            summary: text,
            part: (&mesh, &legend),
        };
        crate::output::bail_if_stopped("the report")?;
        write_atomic(path, html_report(&v, &inputs).as_bytes())?;
    }
    if args.json {
        return print_json(&summary);
    }
    print_human(&v, &summary, &args.out);
    Ok(())
}

/// The design a file holds: a closed STL mesh, or JSON/STEP/IGES surfaces.
fn load_design(
    path: &Path,
    flip: bool,
    at: Option<&swarf_geom::RigidMotion>,
) -> Result<(Box<dyn Design>, swarf_surface::Caveats)> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    if ext == "stl" {
        if flip {
            bail!("--flip applies to surface designs (JSON, STEP, IGES), not to an STL solid");
        }
        let design = MeshDesign::read_stl_at(path, at)?;
        if let Some(note) = design.repairs() {
            eprintln!("note: design {}: {note}", path.display());
        }
        return Ok((Box::new(design), swarf_surface::Caveats::default()));
    }
    if swarf_surface::io::Format::from_path(path).is_none() {
        bail!(
            "design {}: unknown format (expected a closed .stl mesh, or surfaces as .json, \
             .step/.stp or .iges/.igs)",
            path.display()
        );
    }
    let mut surface = swarf_surface::io::read_file(path)
        .with_context(|| format!("reading design {}", path.display()))?;
    for note in &surface.notes {
        eprintln!("note: {note}");
    }
    if flip {
        surface.flip_all();
    }
    if let Some(m) = at {
        surface = surface
            .moved(m)
            .map_err(|why| anyhow::anyhow!("design {}: placing it: {why}", path.display()))?;
    }
    match SurfaceDesign::new(&surface, 0.0) {
        Some(d) => Ok((Box::new(d), surface.caveats())),
        None => bail!("design {}: no surface patches", path.display()),
    }
}

/// `defects.csv`: one row per region (`move`, `file`, `line`: the move that cut its deepest
/// end; empty for stock no move cut).
fn defects_csv(v: &Verification, program: &Program) -> String {
    let mut out = String::from("region,kind,depth_mm,area_mm2,volume_mm3,x,y,z,move,file,line\n");
    for r in &v.regions {
        let (mv, file, line) = match r
            .deepest_move
            .and_then(|i| program.moves.get(i).map(|m| (i, m)))
        {
            Some((i, m)) => (
                i.to_string(),
                program
                    .files
                    .get(usize::from(m.file))
                    .map_or(String::new(), |f| csv_field(f)),
                m.line.to_string(),
            ),
            None => Default::default(),
        };
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{},{},{mv},{file},{line}",
            r.id,
            r.kind.name(),
            r.depth_mm,
            r.area_mm2,
            r.volume_mm3,
            r.deepest.x,
            r.deepest.y,
            r.deepest.z
        );
    }
    out
}

fn print_human(v: &Verification, s: &VerifySummary<'_>, out: &Path) {
    say!(
        "{} gouge regions (deepest {:.4} mm), {} excess regions (thickest {:.4} mm, {:.3} mm³ \
         left), tolerances {} / {} mm, {} ray ends, {} collisions, {:.2} s",
        s.gouge_regions,
        s.max_gouge_mm,
        s.excess_regions,
        s.max_excess_mm,
        s.excess_volume_mm3,
        s.tolerance_mm,
        s.excess_tolerance_mm,
        s.ends_checked,
        s.collisions,
        s.elapsed_s
    );
    for r in v.regions.iter().take(20) {
        // The distinct lines, deepest first (a loop runs one line as many moves).
        let mut lines: Vec<String> = Vec::new();
        for m in &r.moves {
            let l = format!("{}:{}", m.file, m.line);
            if !lines.contains(&l) {
                lines.push(l);
            }
            if lines.len() == 5 {
                break;
            }
        }
        say!(
            "  region {:>4}: {:<6} {:.4} mm, {:.3} mm², {:.4} mm³ at ({:.3}, {:.3}, {:.3}){}",
            r.id,
            r.kind.name(),
            r.depth_mm,
            r.area_mm2,
            r.volume_mm3,
            r.deepest.x,
            r.deepest.y,
            r.deepest.z,
            if lines.is_empty() {
                String::new()
            } else {
                format!("  cut by {}", lines.join(", "))
            }
        );
    }
    if v.regions.len() > 20 {
        say!(
            "  … {} more in {}",
            v.regions.len() - 20,
            out.join("defects.csv").display()
        );
    }
}
