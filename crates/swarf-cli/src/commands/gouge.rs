//! `swarf gouge`: where a program's cutter gouges the part surface or the tool interferes with
//! the part or the check geometry, and how deep (`DIR/violations.csv`, `DIR/points.csv`,
//! `DIR/summary.json`).

use crate::output::say;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context, Result};
use clap::Args;
use swarf_io::OutputSet;
use swarf_path::Program;
use swarf_plan::gouge::{
    check_program_observed, GougeOptions, GougeReport, GougeSummary, GougeSurface,
};
use swarf_surface::{CompoundSurface, PreparedSurface};

use crate::cli::SetupArgs;
use crate::commands::tools::{defined_tools, load_job};
use crate::output::{check_sizes, output_set, print_json, DEFAULT_MAX_OUTPUT_MB};

/// `swarf gouge`.
#[derive(Debug, Args)]
pub(crate) struct GougeArgs {
    /// The part surface: swarf JSON, STEP or IGES (its orientation does not matter here: any
    /// surface point inside the tool is a violation).
    #[arg(long)]
    pub(crate) surface: PathBuf,
    /// The program: G-code, APT CL, Heidenhain conversational or Sinumerik.
    #[arg(long, value_name = "FILE")]
    pub(crate) program: PathBuf,
    /// Check geometry (fixtures, clamps, neighbouring parts) as a closed STL mesh: any part of
    /// the tool reaching into it is interference.
    #[arg(long)]
    pub(crate) check: Option<PathBuf>,
    /// Where the part file (and the --check mesh, exported with it) lies in the program's
    /// frame, when CAD exported it elsewhere: `X,Y,Z` moves it by that much (mm); `X,Y,Z,RZ`
    /// or `X,Y,Z,RX,RY,RZ` first turns it by those degrees about the X, Y and Z axes through
    /// its origin, in that order.
    #[arg(long, value_name = "X,Y,Z[,RZ]", value_parser = crate::cli::parse_part_at, allow_hyphen_values = true)]
    pub(crate) part_at: Option<swarf_geom::RigidMotion>,
    /// Cutters, tool library, machine and units.
    #[command(flatten)]
    pub(crate) setup: SetupArgs,
    /// Depths at or below this are touching, not gouging, mm.
    #[arg(allow_negative_numbers = true, long, value_name = "MM", default_value_t = GougeOptions::DEFAULT.tolerance)]
    pub(crate) tolerance: f64,
    /// Where violations start and end along a move is located to this much tool travel, mm.
    #[arg(allow_negative_numbers = true, long, value_name = "MM", default_value_t = GougeOptions::DEFAULT.resolution)]
    pub(crate) resolution: f64,
    /// Output folder (created if missing).
    #[arg(long)]
    pub(crate) out: PathBuf,
    /// Also write one self-contained HTML report here (inputs, tools, the part surface, the
    /// toolpath and the violations as markers in 3-D, violations linked to their lines, the
    /// summary's figures).
    #[arg(long, value_name = "FILE.html")]
    pub(crate) report: Option<PathBuf>,
    /// Print the JSON summary (the default prints a short report).
    #[arg(long)]
    pub(crate) json: bool,
}

pub(crate) fn run(args: &GougeArgs) -> Result<()> {
    crate::commands::report::prepare(args.report.as_deref())?;
    let t0 = Instant::now();
    let mut surface = swarf_surface::io::read_file(&args.surface)
        .with_context(|| format!("reading {}", args.surface.display()))?;
    if let Some(m) = &args.part_at {
        surface = surface
            .moved(m)
            .map_err(|why| anyhow::anyhow!("{}: placing it: {why}", args.surface.display()))?;
    }
    if surface.patches.is_empty() {
        bail!("{}: no surface patches", args.surface.display());
    }
    for note in &surface.notes {
        eprintln!("note: {note}");
    }
    let mut prep = PreparedSurface::new(&surface);
    if let Some(path) = &args.check {
        let mut mesh = swarf_io::read_stl(path)?;
        if let Some(m) = &args.part_at {
            for v in &mut mesh.vertices {
                *v = m.apply_point(*v);
            }
        }
        prep = prep.with_check_mesh(&path.display().to_string(), &mesh)?;
    }
    let job = load_job(&args.setup, &args.program)?;
    let tools = defined_tools(&job)?;
    let program = &job.program;
    let opts = GougeOptions {
        resolution: args.resolution,
        ..GougeOptions::DEFAULT.with_tolerance(args.tolerance)
    };
    let gs = GougeSurface::new(&prep);
    // Ctrl-C ends `swarf gouge` at once (it does not listen for a stop), so the observer only
    // draws the bar.
    let progress = crate::output::MovesProgress::new(program.moves.len());
    let report = check_program_observed(&gs, program, tools, &opts, &progress)
        .with_context(|| format!("checking {}", args.program.display()));
    progress.finish();
    let report = report?;
    let summary = report.summary(
        &surface,
        &opts,
        program.moves.len(),
        t0.elapsed().as_secs_f64(),
    );
    let mut set = output_set(&args.out, DEFAULT_MAX_OUTPUT_MB)?;
    write_outputs(&mut set, "", &surface, program, &report, &summary)?;
    set.commit()?;
    if let Some(path) = &args.report {
        let resolved = tools.resolved();
        write_report(path, args, &surface, program, resolved, &report, &summary)?;
    }
    if args.json {
        return print_json(&summary);
    }
    say!(
        "{} points, {} moves ({} sub-moves): {} gouging moves (deepest {:.4} mm), {} interfering \
         moves (deepest {:.4} mm), tolerance {} mm, {:.2} s{}",
        summary.points,
        summary.moves,
        summary.sub_moves,
        summary.gouging_moves,
        summary.max_gouge_mm,
        summary.interfering_moves,
        summary.max_interference_mm,
        summary.tolerance_mm,
        summary.elapsed_s,
        match (
            summary.caveats.skipped_faces,
            summary.caveats.unapplied_placements,
            summary.caveats.untrimmed_faces,
            summary.unresolved_searches,
        ) {
            (0, 0, 0, 0) => String::new(),
            (0, 0, 0, _) => " (some searches ran out of budget: see unresolved_searches)".into(),
            (0, 0, n, _) => format!(
                " (not certified: {n} face(s) were checked on their whole surface, their trim \
                 not read: a violation there may lie outside the face, see untrimmed_faces)"
            ),
            (0, n, _, _) => format!(
                " (not certified: {n} assembly placement(s) of the surface were not applied, \
                 see unapplied_placements)"
            ),
            (n, _, _, _) => format!(
                " (not certified: {n} face(s) of the surface were not read, see skipped_faces)"
            ),
        }
    );
    for v in report.violations.iter().take(20) {
        say!(
            "  line {:>6}: {:<12} {:<7} {:.4} mm at s = {:.3} ({:.3}..{:.3}){}",
            v.line,
            v.kind.as_str(),
            v.part.as_str(),
            v.depth,
            v.s_deepest,
            v.s_start,
            v.s_end,
            if v.rapid { " rapid" } else { "" }
        );
    }
    if report.violations.len() > 20 {
        say!(
            "  … {} more in {}",
            report.violations.len() - 20,
            args.out.join("violations.csv").display()
        );
    }
    Ok(())
}

/// Writes `violations.csv`, `points.csv` and `summary.json` into `dir` (created if missing).
pub(crate) fn write_outputs(
    set: &mut OutputSet,
    prefix: &str,
    surface: &CompoundSurface,
    program: &Program,
    report: &GougeReport,
    summary: &GougeSummary,
) -> Result<()> {
    let mut violations = Vec::new();
    report
        .write_violations_csv(surface, &program.files, &mut violations)
        .context("formatting violations.csv")?;
    let mut points = Vec::new();
    report
        .write_points_csv(surface, &program.files, &mut points)
        .context("formatting points.csv")?;
    let json = serde_json::to_vec_pretty(summary).context("encoding the summary")?;
    let names = ["violations.csv", "points.csv", "summary.json"].map(|n| format!("{prefix}{n}"));
    check_sizes(
        set,
        &[
            (&names[0], violations.len() as u64),
            (&names[1], points.len() as u64),
            (&names[2], json.len() as u64),
        ],
    )?;
    set.write_bytes(&names[0], &violations)?;
    set.write_bytes(&names[1], &points)?;
    set.write_bytes(&names[2], &json)?;
    Ok(())
}

/// Grid points per patch side of the surface drawn on the report page.
const REPORT_GRID: usize = 24;

/// `--report FILE.html`: the part surface, the toolpath, every violation (at its deepest
/// surface point) linked to its line, the summary's figures.
fn write_report(
    path: &Path,
    args: &GougeArgs,
    surface: &CompoundSurface,
    program: &Program,
    resolved: &std::collections::BTreeMap<u32, swarf_tool::ResolvedTool>,
    report: &GougeReport,
    summary: &GougeSummary,
) -> Result<()> {
    use crate::commands::report as page;
    let tools = page::resolved_tools(resolved);
    let mesh = swarf_surface::tessellate(surface, REPORT_GRID, &swarf_surface::Tolerances::DEFAULT);
    let rows = report.violations.iter().map(|v| {
        let file = program
            .files
            .get(usize::from(v.file))
            .cloned()
            .unwrap_or_default();
        let row = swarf_io::html::DefectRow {
            cells: vec![
                v.move_index.to_string(),
                format!("{file}:{}", v.line),
                v.kind.as_str().to_string(),
                v.part.as_str().to_string(),
                format!("{:.4}", v.depth),
                format!("{:.3}", v.s_deepest),
                if v.rapid { "rapid" } else { "feed" }.to_string(),
            ],
            line: Some((file, v.line)),
        };
        let colour = if v.kind.as_str() == "gouge" {
            [0.85, 0.05, 0.05]
        } else {
            [0.9, 0.55, 0.0]
        };
        (row, Some((v.point, colour)))
    });
    let mut r = page::program_page("swarf gouge", &args.program, program, &tools)?
        .with_input("surface", args.surface.display().to_string())
        .with_mesh("part surface", mesh.mesh)
        .with_rows(
            &["move", "line", "kind", "part", "depth mm", "s", "motion"],
            rows,
        )
        .with_sources(&page::sources(program))
        .with_summary(
            serde_json::to_value(summary)?,
            &[
                "max_gouge_mm",
                "gouging_moves",
                "max_interference_mm",
                "interfering_moves",
                "tolerance_mm",
                "points",
                "moves",
                "certified",
                "skipped_faces",
                "untrimmed_faces",
                "unapplied_placements",
            ],
        );
    if let Some(check) = &args.check {
        r = r.with_input("check geometry", check.display().to_string());
    }
    if report.violations.len() > swarf_io::html::MAX_ROWS {
        r = r.with_input(
            "note",
            format!(
                "{} violations; the first {} are listed, all are in violations.csv",
                report.violations.len(),
                swarf_io::html::MAX_ROWS
            ),
        );
    }
    page::write(&r, path)
}
