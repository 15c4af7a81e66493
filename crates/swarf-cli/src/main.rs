//! The `swarf` command line: argument parsing and printing over the swarf libraries.
//!
//! Exit status: 0 on success, 1 on bad input (the message names file, line and column), 2 on a
//! usage error (clap's own exit code).

mod alloc;
mod cli;
mod commands;
mod output;

use clap::{Parser, Subcommand};

/// swarf: a virtual-machining engine for multi-axis CNC milling.
///
/// Units: millimetres and degrees everywhere (inch programs are converted on input).
#[derive(Debug, Parser)]
#[command(name = "swarf", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Describe a cutter given by a tool spec (flat:d=12, ball:d=10, bull:d=16,r=2,
    /// taper-ball:d=6,taper=3, taper-flat:d=10,taper=5, chamfer:d=10,angle=90,
    /// drill:d=8,angle=118, apt:D,R,E,F,ALPHA,BETA,H).
    Tool(commands::tool::ToolArgs),
    /// Read a G-code, APT CL, Heidenhain or Sinumerik program and summarise its motion.
    Path(commands::path::PathArgs),
    /// Simulate a program on a tri-dexel stock: removed volume, collisions, the machined part.
    Simulate(commands::simulate::SimulateArgs),
    /// The largest gouge- and interference-free cutter at every CC point of a compound surface
    /// (3-, 4- and 5-axis).
    Toolsize(commands::toolsize::ToolsizeArgs),
    /// The cutter–workpiece engagement at every cutter location of a program: engaged angles per
    /// axial disc, area, axial depth, entry/exit angles, removal rate.
    Engage(commands::engage::EngageArgs),
    /// Cutting forces, torque and power at every cutter location of a program (mechanistic
    /// model on the engagement), with force-versus-angle curves.
    Forces(commands::forces::ForcesArgs),
    /// Force-limited feed scheduling: a feed per move that keeps the peak force, torque or
    /// power under a limit, written back into the program (only feed words change).
    Schedule(commands::schedule::ScheduleArgs),
    /// Write the swept envelope of a program's feed moves (whole tool) as STL and glb.
    Envelope(commands::envelope::EnvelopeArgs),
    /// Check a program against the part surface: every point and every stretch of motion where
    /// the cutter gouges or the tool interferes, and how deep (certified).
    Gouge(commands::gouge::GougeArgs),
    /// Simulate a program and compare the machined part with the design part: gouge and excess
    /// regions with depth, area, volume and the program lines that cut them, a deviation map.
    Verify(commands::verify::VerifyArgs),
    /// Run the built-in demo job.
    Demo(commands::demo::DemoArgs),
    /// Assemble one self-contained HTML report from a command's output folder (summary.json,
    /// PNG plots, STL meshes, defects.csv or violations.csv).
    Report(commands::report::ReportArgs),
}

fn main() {
    output::install_stop_handler();
    let cli = Cli::parse();
    // The runs that poll for Ctrl-C between moves stop cleanly (no output written); the
    // others end at once, as without a handler.
    if matches!(
        cli.command,
        Command::Simulate(_)
            | Command::Verify(_)
            | Command::Engage(_)
            | Command::Forces(_)
            | Command::Schedule(_)
    ) {
        output::listen_for_stop();
    }
    output::announce_ready();
    let result = match cli.command {
        Command::Tool(args) => commands::tool::run(&args),
        Command::Path(args) => commands::path::run(&args),
        Command::Simulate(args) => commands::simulate::run(&args),
        Command::Toolsize(args) => commands::toolsize::run(&args),
        Command::Envelope(args) => commands::envelope::run(&args),
        Command::Engage(args) => commands::engage::run(&args),
        Command::Forces(args) => commands::forces::run(&args),
        Command::Schedule(args) => commands::schedule::run(&args),
        Command::Gouge(args) => commands::gouge::run(&args),
        Command::Verify(args) => commands::verify::run(&args),
        Command::Demo(args) => commands::demo::run(&args),
        Command::Report(args) => commands::report::run(&args),
    };
    // Text the run could not print (a full disk) is its result lost: a failure.
    let result = result.and_then(|()| match output::stdout_failure() {
        Some(e) => Err(anyhow::anyhow!("writing to stdout: {e}")),
        None => Ok(()),
    });
    if let Err(e) = result {
        // A closed pipe (`swarf path x --json | head`) is the reader's choice, not an error.
        let broken_pipe = e.chain().any(|c| {
            let kind = c
                .downcast_ref::<std::io::Error>()
                .map(std::io::Error::kind)
                .or_else(|| c.downcast_ref::<serde_json::Error>()?.io_error_kind());
            kind == Some(std::io::ErrorKind::BrokenPipe)
        });
        if broken_pipe {
            std::process::exit(0);
        }
        // `{:#}` prints the whole context chain on one line: "reading X: X:3:7: message".
        eprintln!("swarf: error: {e:#}");
        let usage = e.chain().any(|c| c.is::<cli::UsageError>());
        std::process::exit(if usage { 2 } else { 1 });
    }
}
