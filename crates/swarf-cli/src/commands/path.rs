//! `swarf path PROGRAM`: read a program and print its summary or its canonical motion.

use crate::output::say;
use std::collections::BTreeMap;
use std::io::BufWriter;
use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use serde::Serialize;
use swarf_job::{Job, JobSetup};
use swarf_path::canonical::CanonicalPrinter;
use swarf_path::load::read_text;
use swarf_path::summary::{SummaryOptions, SummarySink};
use swarf_path::{summarize, ProgramSummary};
use swarf_tool::{CutterDescription, ToolSet, ToolSource};

use crate::cli::SetupArgs;
use crate::commands::tools::{job_error, load_job_setup_with};
use crate::output::print_json;

/// `swarf path`.
#[derive(Debug, Args)]
pub(crate) struct PathArgs {
    /// The program: G-code (.ngc .nc .gcode .tap .ptp …), APT CL (.apt .cls .cl), Heidenhain
    /// conversational (a file starting with BEGIN PGM, whatever its extension: .h, .ptp, .nc) or Sinumerik (.mpf .spf).
    #[arg(
        value_name = "PROGRAM",
        required_unless_present = "program_option",
        conflicts_with = "program_option"
    )]
    pub(crate) program: Option<PathBuf>,
    /// The program, given as every other command takes it (the same as PROGRAM).
    #[arg(long = "program", value_name = "FILE", id = "program_option")]
    pub(crate) program_option: Option<PathBuf>,
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

/// The `--json` output: the summary's keys, plus the cutters the tools resolve to.
#[derive(Serialize)]
pub(crate) struct PathReport {
    #[serde(flatten)]
    summary: ProgramSummary,
    /// Tool number → the cutter used for it (from --tool, --tools or the program's CUTTER/).
    tool_definitions: BTreeMap<u32, ToolReport>,
    /// Tool numbers the program uses that nothing defines.
    undefined_tools: Vec<u32>,
    /// Workpiece bounds stated by the tool table (CAMotics projects), mm; absent otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    workpiece: Option<Workpiece>,
    /// Why the tool library left out the undefined tools it names (for the human summary).
    #[serde(skip)]
    left_out: BTreeMap<u32, String>,
}

#[derive(Serialize)]
struct Workpiece {
    min: [f64; 3],
    max: [f64; 3],
    /// Made from the program, as CAMotics makes an automatic workpiece (only written when so).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    automatic: bool,
}

#[derive(Serialize)]
struct ToolReport {
    source: ToolSource,
    description: String,
    cutter: CutterDescription,
}

pub(crate) fn run(args: &PathArgs) -> Result<()> {
    // Both outputs stream: no move is kept, so no move limit is needed unless one is given
    // (the loop limits still end a program that never ends).
    let mut setup = load_job_setup_with(&args.setup, u64::MAX)?;
    let program = args
        .program
        .as_ref()
        .or(args.program_option.as_ref())
        .context("no program given")?;
    setup.search_program_folder(program);
    let text = read_text(program)?;
    let file = program.display().to_string();

    if args.canonical {
        let stdout = std::io::stdout().lock();
        let mut printer = CanonicalPrinter::new(BufWriter::new(stdout))
            .with_machine(setup.machine.clone(), &file);
        let read = setup.stream(&text, &file, &mut printer);
        // The reader's warnings are no canonical call: on stderr, after the calls (those up to
        // an error too, which they may explain).
        let warnings = printer.warnings().to_vec();
        let written = printer.finish();
        for w in &warnings {
            eprintln!("{w}");
        }
        read.map_err(job_error)?;
        written.context("writing to stdout")?;
        return Ok(());
    }

    let mut sink = SummarySink::new(setup.machine.clone(), &file, &SummaryOptions::default());
    if let Err(e) = setup.stream(&text, &file, &mut sink) {
        // The warnings up to the error, which they may explain.
        for w in &sink.finish().program.warnings {
            eprintln!("{w}");
        }
        return Err(job_error(e));
    }
    drop(text);
    let streamed = sink.finish();
    let (tools, undefined) = setup
        .resolve(&streamed.program, streamed.tool_zero_moved)
        .map_err(job_error)?;
    let automatic = automatic_margin(&setup).and_then(|margin| {
        swarf_job::automatic_workpiece_of(&streamed.feed_tip_bounds_by_tool, &tools, margin)
    });
    let report = PathReport::from_parts(streamed.summary, &tools, undefined, &setup, automatic);
    // What the summary leaves out or approximates (feed moves at F0 left out of the time…)
    // is said on stderr too, not only inside the JSON.
    for note in &report.summary.notes {
        eprintln!("note: {note}");
    }
    if args.json {
        return print_json(&report);
    }
    report.print_human();
    Ok(())
}

impl PathReport {
    /// The summary of `job`'s program with the cutters its tools resolve to (`--tool` for
    /// all, else the library, else the program's own `CUTTER/`).
    pub(crate) fn new(job: &Job) -> Self {
        let automatic = automatic_margin(&job.setup)
            .and_then(|margin| swarf_job::automatic_workpiece(&job.program, &job.tools, margin));
        Self::from_parts(
            summarize(&job.program),
            &job.tools,
            job.undefined_tools.clone(),
            &job.setup,
            automatic,
        )
    }

    /// The report of a program summarised already, with its resolved `tools`, the tool numbers
    /// nothing defines and the setup it was read with (for the workpiece a CAMotics project
    /// states).
    fn from_parts(
        summary: ProgramSummary,
        tools: &ToolSet,
        undefined_tools: Vec<u32>,
        setup: &JobSetup,
        automatic: Option<swarf_geom::Aabb>,
    ) -> Self {
        let tool_definitions = tools
            .resolved()
            .iter()
            .map(|(n, r)| {
                let report = ToolReport {
                    source: r.source,
                    description: r.description.clone(),
                    cutter: r.cutter.describe(),
                };
                (*n, report)
            })
            .collect();
        let stated = setup.table.as_ref().and_then(|t| t.workpiece);
        let workpiece = stated
            .map(|b| (b, false))
            .or(automatic.map(|b| (b, true)))
            .map(|(b, automatic)| Workpiece {
                min: b.min.to_array(),
                max: b.max.to_array(),
                automatic,
            });
        let left_out = setup
            .table
            .as_ref()
            .map(|t| t.left_out.clone())
            .unwrap_or_default();
        Self {
            summary,
            tool_definitions,
            undefined_tools,
            workpiece,
            left_out,
        }
    }

    pub(crate) fn print_human(&self) {
        print_human(
            &self.summary,
            &self.tool_definitions,
            &self.undefined_tools,
            &self.left_out,
        );
    }
}

fn print_human(
    s: &ProgramSummary,
    tools: &BTreeMap<u32, ToolReport>,
    undefined: &[u32],
    left_out: &BTreeMap<u32, String>,
) {
    say!(
        "{} moves: {} rapid, {} feed ({} arcs)",
        s.moves,
        s.rapid_moves,
        s.feed_moves,
        s.arc_moves
    );
    say!("feed length  {:.3} mm", s.feed_length_mm);
    say!("rapid length {:.3} mm", s.rapid_length_mm);
    if let (Some(lo), Some(hi)) = (s.bbox_min, s.bbox_max) {
        say!(
            "tool tip box X {:.3} .. {:.3}  Y {:.3} .. {:.3}  Z {:.3} .. {:.3} mm",
            lo[0],
            hi[0],
            lo[1],
            hi[1],
            lo[2],
            hi[2]
        );
    }
    // Whole seconds, rounded once, so that both forms agree.
    let t = s.machining_time_s.round() as u64;
    say!(
        "machining time {t} s ({}:{:02}:{:02})",
        t / 3600,
        t / 60 % 60,
        t % 60
    );
    if s.dwell_time_s > 0.0 {
        say!("dwells {:.1} s", s.dwell_time_s);
    }
    for (n, r) in tools {
        say!("T{n}: {} ({:?})", r.cutter.spec, r.source);
    }
    for n in undefined {
        match left_out.get(n) {
            Some(why) => say!("T{n}: left out of the tool library ({why})"),
            None => say!("T{n}: not defined (give --tool or --tools)"),
        }
    }
    for w in &s.warnings {
        say!("{w}");
    }
}

/// The margin of a CAMotics project's automatic workpiece, when the tool library is one.
fn automatic_margin(setup: &JobSetup) -> Option<f64> {
    setup.table.as_ref().and_then(|t| t.automatic_workpiece)
}
