//! `swarf simulate`: run a program on a tri-dexel stock and report what it removed.

use crate::output::say;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use clap::Args;
use serde::Serialize;
use swarf_io::glb::{glb_size_bound, GlbFile};
use swarf_io::output_set::stl_size;
use swarf_io::{write_stl_to, ContourOptions, GlbOptions, OutputSet, Shading};
use swarf_path::{MoveKind, Program};
use swarf_stock::{
    simulate_observed, Collision, MeshOptions, SimOptions, SimulationReport, StockError, StockSpec,
    TriDexel,
};
use swarf_tool::{ToolSet, ToolTable};

use crate::cli::SetupArgs;
use crate::commands::tools::{defined_tools, load_job};
use crate::output::{check_sizes, output_set, print_json};

/// `swarf simulate`.
#[derive(Debug, Args)]
pub(crate) struct SimulateArgs {
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
    /// Ray spacing of the tri-dexel stock, mm.
    #[arg(
        allow_negative_numbers = true,
        long,
        value_name = "H",
        default_value_t = 0.25
    )]
    pub(crate) resolution: f64,
    /// Largest distance between an arc or a 5-axis motion and what is cut for it, mm.
    #[arg(allow_negative_numbers = true, long, value_name = "T", default_value_t = swarf_stock::DEFAULT_CHORDAL_TOLERANCE_MM)]
    pub(crate) tolerance: f64,
    /// Build the stock from an STL mesh even if it is not closed.
    #[arg(long)]
    pub(crate) allow_open_mesh: bool,
    /// Write stock.stl, stock.glb, moves.csv and summary.json here (all four or none).
    #[arg(long, value_name = "DIR")]
    pub(crate) out: Option<PathBuf>,
    /// Largest total size of the files --out writes, MB: their sizes are estimated before
    /// anything is written, and a larger set is refused.
    #[arg(long, value_name = "MB", default_value_t = crate::output::DEFAULT_MAX_OUTPUT_MB)]
    pub(crate) max_output_mb: u64,
    /// Also write one self-contained HTML report here (inputs, tools, the machined stock and
    /// the toolpath in 3-D, collisions linked to their lines, the summary's figures).
    #[arg(long, value_name = "FILE.html")]
    pub(crate) report: Option<PathBuf>,
    /// Merge the stock mesh's coplanar triangles (faces, floors, walls, strips of a cylinder
    /// along a lattice axis) into few, in stock.stl, stock.glb and the report; the vertices
    /// stay where they are, the surface within 10⁻⁶ mm of the unmerged.
    #[arg(long)]
    pub(crate) merge_planar: bool,
    /// Merge each 2 × 2 × 2 block of the stock mesh's cells into one vertex where the
    /// topology stays and the block's crossings lie within MM of the planes that meet at it
    /// (about a quarter of the triangles where the surface is smooth; sharp edges stay). 0,
    /// the default, keeps every cell.
    #[arg(
        allow_negative_numbers = true,
        long,
        value_name = "MM",
        default_value_t = 0.0
    )]
    pub(crate) simplify: f64,
    /// Print the JSON summary (the default output is a short human-readable report).
    #[arg(long)]
    pub(crate) json: bool,
}

/// How the stock's mesh is made for the files: `--merge-planar` and `--simplify`.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct StockMeshOut {
    pub(crate) merge_planar: bool,
    pub(crate) simplify: Option<f64>,
}

impl StockMeshOut {
    /// The flags' values, checked.
    fn of(args: &SimulateArgs) -> Result<Self> {
        Ok(Self {
            merge_planar: args.merge_planar,
            simplify: simplify_mm(args.simplify)?,
        })
    }
}

/// The JSON summary. The first nine keys are a contract; the rest may grow.
#[derive(Serialize)]
pub(crate) struct SimulateSummary {
    stock_volume_mm3: f64,
    removed_volume_mm3: f64,
    final_volume_mm3: f64,
    moves: usize,
    rays: u64,
    intervals: u64,
    /// Number of rapids whose cutting part entered the material.
    rapid_collisions: usize,
    /// Number of moves whose shank or holder entered the material.
    holder_collisions: usize,
    elapsed_s: f64,
    /// Every collision: kind, move index, file, line, volume.
    collisions: Vec<CollisionReport>,
    /// Feed moves that removed material with the spindle stopped (a crash on the machine).
    cut_without_spindle: usize,
    /// Where the first of them is, and what they removed in all (for the warning).
    #[serde(skip)]
    first_without_spindle: Option<(String, u32, f64)>,
    /// Final volume from the X, Y and Z ray families (a cross-check of the discretisation).
    final_volume_xyz_mm3: [f64; 3],
    bytes_per_interval: f64,
    resolution_mm: [f64; 3],
    chordal_tolerance_mm: f64,
    rays_tested: u64,
    ray_updates: u64,
    /// Moves whose tool axis turns (5-axis simultaneous).
    five_axis_moves: usize,
    /// Fixed-axis sub-moves they were cut as.
    five_axis_sub_moves: u64,
    /// Largest proven distance between a 5-axis move's true sweep and what was cut, mm.
    five_axis_error_bound_mm: f64,
    /// With `--out`: the volume of the machined part's closed mesh (`stock.stl`, unmerged
    /// or merged alike), whose vertices lie on exact ray ends of all three families — within
    /// the contouring's error where the Z family's `final_volume_mm3` places a wall parallel to
    /// its rays on the nearest ray.
    #[serde(skip_serializing_if = "Option::is_none")]
    final_mesh_volume_mm3: Option<f64>,
}

/// One collision of a summary's `collisions`: `kind` (`rapid` or `holder`), move index, file,
/// line, volume.
#[derive(Serialize)]
pub(crate) struct CollisionReport {
    pub(crate) kind: &'static str,
    #[serde(flatten)]
    pub(crate) collision: Collision,
}

/// The rapid and holder collisions as one list, in program order.
pub(crate) fn collision_reports(rapid: &[Collision], holder: &[Collision]) -> Vec<CollisionReport> {
    let kinded = |kind, cs: &[Collision]| {
        cs.iter()
            .map(move |c| CollisionReport {
                kind,
                collision: c.clone(),
            })
            .collect::<Vec<_>>()
    };
    let mut collisions = kinded("rapid", rapid);
    collisions.extend(kinded("holder", holder));
    collisions.sort_by_key(|c| c.collision.move_index);
    collisions
}

impl SimulateSummary {
    pub(crate) fn new(r: &SimulationReport, program: &Program) -> Self {
        let collisions = collision_reports(&r.rapid_collisions, &r.holder_collisions);
        let stopped: Vec<(&swarf_path::Move, f64)> = program
            .moves
            .iter()
            .zip(r.removed_per_move_mm3.iter().copied())
            .filter(|(m, v)| {
                !matches!(m.kind, swarf_path::MoveKind::Rapid) && *v > 0.0 && m.spindle_rpm <= 0.0
            })
            .collect();
        let first_without_spindle = stopped.first().map(|(m, _)| {
            let file = program.files.get(usize::from(m.file)).cloned();
            (
                file.unwrap_or_default(),
                m.line,
                stopped.iter().map(|(_, v)| v).sum(),
            )
        });
        Self {
            cut_without_spindle: stopped.len(),
            first_without_spindle,
            stock_volume_mm3: r.stock_volume_mm3,
            removed_volume_mm3: r.removed_volume_mm3,
            final_volume_mm3: r.final_volume_mm3,
            moves: r.moves,
            rays: r.rays,
            intervals: r.intervals,
            rapid_collisions: r.rapid_collisions.len(),
            holder_collisions: r.holder_collisions.len(),
            elapsed_s: r.elapsed_s,
            collisions,
            final_volume_xyz_mm3: r.final_volume_xyz_mm3,
            bytes_per_interval: r.bytes_per_interval,
            resolution_mm: r.resolution_mm,
            chordal_tolerance_mm: r.chordal_tolerance_mm,
            rays_tested: r.rays_tested,
            ray_updates: r.ray_updates,
            five_axis_moves: r.five_axis_moves,
            five_axis_sub_moves: r.five_axis_sub_moves,
            five_axis_error_bound_mm: r.five_axis_error_bound_mm,
            final_mesh_volume_mm3: None,
        }
    }

    /// Warns of the feed moves that cut with the spindle stopped, with the first one's line.
    pub(crate) fn warn_spindle_stopped(&self) {
        if let Some((file, line, volume)) = &self.first_without_spindle {
            eprintln!(
                "swarf: warning: {} feed moves removed {volume:.3} mm³ with the spindle stopped ({}), the first at {file}:{line}",
                self.cut_without_spindle,
                crate::commands::forces::SPINDLE_STOPPED
            );
        }
    }

    fn print_human(&self) {
        say!("stock   {:.3} mm³", self.stock_volume_mm3);
        say!("removed {:.3} mm³", self.removed_volume_mm3);
        say!("final   {:.3} mm³", self.final_volume_mm3);
        say!(
            "{} moves, {} rays, {} intervals, {:.2} s",
            self.moves,
            self.rays,
            self.intervals,
            self.elapsed_s
        );
        for c in &self.collisions {
            say!(
                "{}:{}: {} collision, move {}, {:.3} mm³ removed",
                c.collision.file,
                c.collision.line,
                c.kind,
                c.collision.move_index,
                c.collision.volume_mm3
            );
        }
    }
}

pub(crate) fn run(args: &SimulateArgs) -> Result<()> {
    crate::commands::report::prepare(args.report.as_deref())?;
    positive_mm("resolution", args.resolution)?;
    positive_mm("tolerance", args.tolerance)?;
    let mesh_out = StockMeshOut::of(args)?;
    let job = load_job(&args.setup, &args.program)?;
    let tools = defined_tools(&job)?;
    let program = &job.program;
    crate::commands::tools::check_resolution(tools, args.resolution)?;
    let mut stock = build_stock(
        args.stock.as_deref(),
        job.setup.table.as_ref(),
        (program, tools),
        args.resolution,
        args.allow_open_mesh,
    )?;
    let options = SimOptions::default().with_chordal_tolerance(args.tolerance);
    let report = simulate_with_progress(program, tools, &mut stock, &options)
        .with_context(|| format!("simulating {}", args.program.display()))?;
    let mut summary = SimulateSummary::new(&report, program);
    summary.warn_spindle_stopped();
    // A program that never reaches the stock is more often a wrong stock, offset or unit than
    // an intent.
    let cuts = program
        .moves
        .iter()
        .any(|m| !matches!(m.kind, swarf_path::MoveKind::Rapid));
    if cuts && report.removed_volume_mm3 <= 0.0 {
        eprintln!(
            "swarf: warning: no move removed material: the program never reaches the stock (check \
             --stock, the program's offsets and units)"
        );
    }
    if let Some(dir) = &args.out {
        let mut set = output_set(dir, args.max_output_mb)?;
        write_outputs(&mut set, program, &stock, &report, &mut summary, mesh_out)?;
        set.commit()?;
    }
    if let Some(path) = &args.report {
        write_report(
            path,
            args,
            mesh_out,
            program,
            tools.resolved(),
            &stock,
            &summary,
        )?;
    }
    if args.json {
        print_json(&summary)
    } else {
        summary.print_human();
        Ok(())
    }
}

/// Runs the simulation with a progress bar on a terminal (nothing is drawn when stderr is piped)
/// and stops cleanly on Ctrl-C: the run ends with an error before any output file is written.
pub(crate) fn simulate_with_progress(
    program: &Program,
    tools: &ToolSet,
    stock: &mut TriDexel,
    options: &SimOptions,
) -> Result<SimulationReport> {
    let progress = crate::output::MovesProgress::new(program.moves.len());
    let result = simulate_observed(program, tools, stock, options, &progress);
    progress.finish();
    match result {
        Err(StockError::Cancelled { done }) => {
            bail!(
                "stopped by Ctrl-C after {done} of {} moves; no output written",
                program.moves.len()
            )
        }
        other => Ok(other?),
    }
}

/// A usage error unless `value` (option `--name`) is a positive, finite number of mm.
pub(crate) fn positive_mm(name: &str, value: f64) -> Result<()> {
    if value > 0.0 && value.is_finite() {
        Ok(())
    } else {
        bail!("--{name} must be a positive number of mm, got {value}")
    }
}

/// `--simplify MM`: the contouring's merge tolerance, `None` for 0 (every cell kept).
pub(crate) fn simplify_mm(value: f64) -> Result<Option<f64>> {
    if value == 0.0 {
        Ok(None)
    } else if value > 0.0 && value.is_finite() {
        Ok(Some(value))
    } else {
        bail!("--simplify must be 0 (every cell) or a positive number of mm, got {value}")
    }
}

/// The stock `--stock` gives (or the CAMotics project's workpiece: its bounds, or the
/// automatic one made from `program`'s cutting moves with `tools`) at ray spacing `resolution`.
pub(crate) fn build_stock(
    arg: Option<&str>,
    table: Option<&ToolTable>,
    (program, tools): (&Program, &ToolSet),
    resolution: f64,
    allow_open_mesh: bool,
) -> Result<TriDexel> {
    stock_spec(arg, table, program, tools)?
        .build(
            resolution,
            MeshOptions {
                allow_open: allow_open_mesh,
            },
        )
        .context("building the stock")
}

fn stock_spec(
    arg: Option<&str>,
    table: Option<&ToolTable>,
    program: &Program,
    tools: &ToolSet,
) -> Result<StockSpec> {
    if let Some(s) = arg {
        return StockSpec::parse(s).with_context(|| format!("stock `{s}`"));
    }
    if let Some(b) = table.and_then(|t| t.workpiece) {
        return Ok(StockSpec::Box {
            min: b.min,
            max: b.max,
        });
    }
    if let Some([min, max]) = program.blank {
        eprintln!(
            "swarf: note: stock box:{} (the program's BLK FORM)",
            min.iter()
                .chain(&max)
                .map(|v| crate::output::trimmed(*v, 4))
                .collect::<Vec<_>>()
                .join(",")
        );
        return Ok(StockSpec::Box {
            min: swarf_geom::math::Vec3::from_array(min),
            max: swarf_geom::math::Vec3::from_array(max),
        });
    }
    if let Some(margin) = table.and_then(|t| t.automatic_workpiece) {
        let Some(b) = swarf_job::automatic_workpiece(program, tools, margin) else {
            return Err(crate::cli::UsageError(
                "the CAMotics project's workpiece is automatic, but no feed move of a defined \
                 tool comes within 2 mm of Z0 or below it to make it from: give the stock with \
                 --stock"
                    .into(),
            )
            .into());
        };
        let mm = |v: f64| crate::output::trimmed(v, 4);
        eprintln!(
            "swarf: note: stock box:{},{},{},{},{},{} (the CAMotics project's automatic \
             workpiece: the cutting moves' tool box, top at Z0, grown by {margin} %)",
            mm(b.min.x),
            mm(b.min.y),
            mm(b.min.z),
            mm(b.max.x),
            mm(b.max.y),
            mm(b.max.z)
        );
        return Ok(StockSpec::Box {
            min: b.min,
            max: b.max,
        });
    }
    Err(crate::cli::UsageError(
        "give the stock with --stock box:X0,Y0,Z0,X1,Y1,Z1, cyl:CX,CY,Z0,R,H or FILE.stl".into(),
    )
    .into())
}

/// `moves.csv`: one row per move. The first three columns are a contract.
fn moves_csv(program: &Program, report: &SimulationReport) -> String {
    let mut out = String::from("move,line,removed_mm3,file,kind,tool\n");
    for (i, (m, v)) in program
        .moves
        .iter()
        .zip(&report.removed_per_move_mm3)
        .enumerate()
    {
        let kind = match m.kind {
            MoveKind::Rapid => "rapid",
            MoveKind::Linear => "linear",
            MoveKind::Arc(_) => "arc",
        };
        let file = program
            .files
            .get(usize::from(m.file))
            .map_or("", String::as_str);
        let _ = writeln!(
            out,
            "{i},{},{v},{},{kind},{}",
            m.line,
            crate::output::csv_field(file),
            m.tool
        );
    }
    out
}

/// The machined part's mesh, with blocks of cells merged (`--simplify`) and coplanar
/// triangles merged (`--merge-planar`) when asked.
fn stock_mesh(stock: &TriDexel, options: StockMeshOut) -> swarf_io::TriMesh {
    let (mesh, _) = stock.to_mesh(&ContourOptions::default().with_simplify(options.simplify));
    if options.merge_planar {
        mesh.merge_coplanar().0
    } else {
        mesh
    }
}

/// Writes the machined part (`stock.stl`, `stock.glb`, made as `mesh` says), `moves.csv` and
/// `summary.json` into `set`, after checking their estimated sizes against its limit (the mesh
/// is sized from the stock before it is built, unmerged). The caller commits the set.
pub(crate) fn write_outputs(
    set: &mut OutputSet,
    program: &Program,
    stock: &TriDexel,
    report: &SimulationReport,
    summary: &mut SimulateSummary,
    mesh: StockMeshOut,
) -> Result<()> {
    let (v, t) = stock.mesh_size_estimate();
    let csv = moves_csv(program, report);
    // The summary is written once the mesh gives its volume; sized before with room for it.
    let json_estimate = serde_json::to_vec_pretty(summary)?.len() as u64 + 64;
    let (v, t) = (
        usize::try_from(v).unwrap_or(usize::MAX),
        usize::try_from(t).unwrap_or(usize::MAX),
    );
    check_sizes(
        set,
        &[
            ("stock.stl", stl_size(t as u64)),
            ("stock.glb", glb_size_bound(v, t, false, Shading::Flat)),
            ("moves.csv", csv.len() as u64),
            ("summary.json", json_estimate),
        ],
    )?;
    let mesh = stock_mesh(stock, mesh);
    summary.final_mesh_volume_mm3 = Some(mesh.volume());
    let mut json = serde_json::to_vec_pretty(summary)?;
    json.push(b'\n');
    let glb = GlbFile::new(&mesh, &GlbOptions::default()).context("encoding stock.glb")?;
    set.write_all(vec![
        ("stock.stl", Box::new(|w| write_stl_to(w, &mesh))),
        ("stock.glb", Box::new(|w| glb.write_to(w))),
    ])
    .context("writing the stock's meshes")?;
    drop(glb);
    drop(mesh);
    set.write_bytes("moves.csv", csv.as_bytes())?;
    set.write_bytes("summary.json", &json)?;
    Ok(())
}

/// The contract keys of the summary, shown first on the report page.
const SUMMARY_KEYS: &[&str] = &[
    "stock_volume_mm3",
    "removed_volume_mm3",
    "final_volume_mm3",
    "moves",
    "rays",
    "intervals",
    "rapid_collisions",
    "holder_collisions",
    "elapsed_s",
];

/// `--report FILE.html`: inputs, tools, the machined stock and the toolpath, the collisions
/// linked to their lines, the summary's figures.
fn write_report(
    path: &Path,
    args: &SimulateArgs,
    mesh_out: StockMeshOut,
    program: &Program,
    resolved: &std::collections::BTreeMap<u32, swarf_tool::ResolvedTool>,
    stock: &TriDexel,
    summary: &SimulateSummary,
) -> Result<()> {
    use crate::commands::report;
    let tools = report::resolved_tools(resolved);
    let mesh = stock_mesh(stock, mesh_out);
    let rows = summary.collisions.iter().map(|c| {
        let cl = &c.collision;
        let at = program.moves.get(cl.move_index).map(|m| m.end.tip);
        let row = swarf_io::html::DefectRow {
            cells: vec![
                c.kind.to_string(),
                cl.move_index.to_string(),
                format!("{}:{}", cl.file, cl.line),
                format!("{:.4}", cl.volume_mm3),
            ],
            line: Some((cl.file.clone(), cl.line)),
        };
        (row, at.map(|p| (p, [0.85, 0.05, 0.05])))
    });
    let page = report::program_page("swarf simulate", &args.program, program, &tools)?
        .with_input(
            "stock",
            args.stock
                .clone()
                .unwrap_or_else(|| "from the tool project".into()),
        )
        .with_input("resolution", format!("{} mm", args.resolution))
        .with_mesh("machined stock", mesh)
        .with_rows(&["collision", "move", "line", "volume mm³"], rows)
        .with_sources(&report::sources(program))
        .with_summary(serde_json::to_value(summary)?, SUMMARY_KEYS);
    report::write(&page, path)
}
