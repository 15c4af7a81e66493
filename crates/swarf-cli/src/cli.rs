//! The command-line grammar. Names here are a contract: options may be added, not renamed.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};

/// swarf: a virtual-machining engine for multi-axis CNC milling.
///
/// Units: millimetres and degrees everywhere (inch programs are converted on input).
#[derive(Debug, Parser)]
#[command(name = "swarf", version, about, long_about = None)]
pub(crate) struct Cli {
    #[command(subcommand)]
    pub(crate) command: Command,
}

#[derive(Debug, Subcommand)]
pub(crate) enum Command {
    /// Describe a cutter given by a tool spec (flat:d=12, ball:d=10, bull:d=16,r=2,
    /// taper-ball:d=6,taper=3, taper-flat:d=10,taper=5, chamfer:d=10,angle=90,
    /// drill:d=8,angle=118, apt:D,R,E,F,ALPHA,BETA,H).
    Tool(ToolArgs),
    /// Read a G-code or APT CL program and summarise its motion.
    Path(PathArgs),
    /// Simulate a program on a tri-dexel stock: removed volume, collisions, the machined part.
    Simulate(SimulateArgs),
    /// The largest gouge- and interference-free cutter at every CC point of a compound surface
    /// (3-, 4- and 5-axis).
    Toolsize(crate::commands::toolsize::ToolsizeArgs),
    /// The cutter–workpiece engagement at every cutter location of a program: engaged angles per
    /// axial disc, area, axial depth, entry/exit angles, removal rate.
    Engage(crate::commands::engage::EngageArgs),
    /// Cutting forces, torque and power at every cutter location of a program (mechanistic
    /// model on the engagement), with force-versus-angle curves.
    Forces(crate::commands::forces::ForcesArgs),
    /// Force-limited feed scheduling: a feed per move that keeps the peak force, torque or
    /// power under a limit, written back into the program (only feed words change).
    Schedule(crate::commands::schedule::ScheduleArgs),
    /// Write the swept envelope of a program's feed moves (whole tool) as STL and glb.
    Envelope(crate::commands::envelope::EnvelopeArgs),
    /// Check a program against the part surface: every point and every stretch of motion where
    /// the cutter gouges or the tool interferes, and how deep (certified).
    Gouge(crate::commands::gouge::GougeArgs),
    /// Simulate a program and compare the machined part with the design part: gouge and excess
    /// regions with depth, area, volume and the program lines that cut them, a deviation map.
    Verify(crate::commands::verify::VerifyArgs),
    /// Run the built-in demo job.
    Demo(DemoArgs),
    /// Assemble one self-contained HTML report from a command's output folder (summary.json,
    /// PNG plots, STL meshes, defects.csv or violations.csv).
    Report(crate::commands::report::ReportArgs),
}

#[derive(Debug, Args)]
pub(crate) struct ToolArgs {
    /// The tool spec, e.g. `bull:d=16,r=2,flutes=4,helix=35`.
    pub(crate) spec: String,
    /// Print JSON (the default output is a short human-readable description).
    #[arg(long)]
    pub(crate) json: bool,
}

/// Length unit for tool tables that do not state their own (LinuxCNC `.tbl`).
#[derive(Clone, Copy, Debug, ValueEnum)]
pub(crate) enum TableUnits {
    /// Millimetres.
    Mm,
    /// Inches.
    Inch,
}

/// What every command that reads a program needs besides the program: which cutter each tool
/// is, the machine's kinematics and the program's initial units.
#[derive(Debug, Args)]
pub(crate) struct SetupArgs {
    /// One cutter for every tool the program uses.
    #[arg(long, value_name = "SPEC")]
    pub(crate) tool: Option<String>,
    /// Tool library: swarf TOML, LinuxCNC .tbl or CAMotics .camotics.
    #[arg(long, value_name = "FILE")]
    pub(crate) tools: Option<PathBuf>,
    /// Units of a LinuxCNC .tbl tool table.
    #[arg(long, value_enum, default_value = "mm")]
    pub(crate) table_units: TableUnits,
    /// Machine kinematics: a built-in name (3axis, 4axis-a, 4axis-b, table-ac, table-bc,
    /// head-ac, head-bc, head-table-ac, head-table-bc; add -tcp for TCP) or a TOML file.
    #[arg(long, value_name = "FILE|NAME", default_value = "3axis")]
    pub(crate) machine: String,
    /// Length units before the program's first G20/G21.
    #[arg(long, value_enum, default_value = "mm")]
    pub(crate) initial_units: TableUnits,
    /// A folder searched for `name.ngc` when the program calls a subroutine it does not define
    /// (after the program's own folder; LinuxCNC's SUBROUTINE_PATH). May be repeated.
    #[arg(long, value_name = "DIR")]
    pub(crate) subroutine_path: Vec<PathBuf>,
    /// Read G-code as this control does (default: decided from the program).
    #[arg(long, value_enum)]
    pub(crate) dialect: Option<Dialect>,
    /// Most moves a program may make: reading stops with an error at the first move over it,
    /// which bounds the memory the moves take (about 300 bytes each). Default 4000000;
    /// `swarf path` keeps no moves and has no limit unless this is given.
    #[arg(long, value_name = "N")]
    pub(crate) max_moves: Option<u64>,
}

impl SetupArgs {
    /// The job options these arguments give; `max_moves` when `--max-moves` is not given.
    pub(crate) fn job_options(&self, max_moves: u64) -> swarf_job::JobOptions {
        let units = |u: TableUnits| match u {
            TableUnits::Mm => (swarf_path::Units::Mm, swarf_tool::LengthUnit::Mm),
            TableUnits::Inch => (swarf_path::Units::Inch, swarf_tool::LengthUnit::Inch),
        };
        swarf_job::JobOptions {
            machine: self.machine.clone(),
            tool: self.tool.clone(),
            tools: self.tools.clone(),
            table_units: units(self.table_units).1,
            initial_units: units(self.initial_units).0,
            subroutine_dirs: self.subroutine_path.clone(),
            dialect: self.dialect.map(|d| match d {
                Dialect::Linuxcnc => swarf_path::gcode::GcodeDialect::LinuxCnc,
                Dialect::Fanuc => swarf_path::gcode::GcodeDialect::Fanuc,
            }),
            max_moves: self.max_moves.unwrap_or(max_moves),
        }
    }
}

/// The G-code dialects.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub(crate) enum Dialect {
    /// LinuxCNC (RS274/NGC).
    Linuxcnc,
    /// Fanuc 0i/30i-M style.
    Fanuc,
}

#[derive(Debug, Args)]
pub(crate) struct PathArgs {
    /// The program: G-code (.ngc .nc .gcode .tap .ptp …) or APT CL (.apt .cls .cl).
    pub(crate) program: PathBuf,
    /// Cutters, tool library, machine and units.
    #[command(flatten)]
    pub(crate) setup: SetupArgs,
    /// Print the JSON summary.
    #[arg(long, conflicts_with = "canonical")]
    pub(crate) json: bool,
    /// Print the motion as LinuxCNC canonical calls (program units, four decimals).
    #[arg(long)]
    pub(crate) canonical: bool,
}

#[derive(Debug, Args)]
pub(crate) struct SimulateArgs {
    /// The stock: `box:X0,Y0,Z0,X1,Y1,Z1`, `cyl:CX,CY,Z0,R,H` (axis +Z) or a closed STL file.
    /// Default: the workpiece a CAMotics project (--tools FILE.camotics) states.
    #[arg(long, value_name = "SPEC|FILE.stl")]
    pub(crate) stock: Option<String>,
    /// The program: G-code or APT CL.
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
    /// Print the JSON summary (the default output is a short human-readable report).
    #[arg(long)]
    pub(crate) json: bool,
}

#[derive(Debug, Args)]
pub(crate) struct DemoArgs {
    /// Where to write the machined part (stock.stl, stock.glb), moves.csv, summary.json, the
    /// program, its tool library and its canonical motion.
    #[arg(long, value_name = "DIR", default_value = "swarf-demo")]
    pub(crate) out: PathBuf,
    /// Largest total size of the files written, MB (estimated before anything is written).
    #[arg(long, value_name = "MB", default_value_t = crate::output::DEFAULT_MAX_OUTPUT_MB)]
    pub(crate) max_output_mb: u64,
    /// Ray spacing of the stock, mm.
    #[arg(
        allow_negative_numbers = true,
        long,
        value_name = "H",
        default_value_t = 0.25
    )]
    pub(crate) resolution: f64,
}
