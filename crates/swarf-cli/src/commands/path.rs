//! `swarf path PROGRAM`: read a program and print its summary or its canonical motion.

use std::collections::BTreeMap;
use std::io::BufWriter;

use anyhow::{Context, Result};
use serde::Serialize;
use swarf_path::canonical::CanonicalPrinter;
use swarf_path::load::{read_text, stream_program};
use swarf_path::summary::{SummaryOptions, SummarySink};
use swarf_path::{summarize, Program, ProgramSummary};
use swarf_tool::{Cutter, CutterDescription, ToolTable};

use crate::cli::PathArgs;
use crate::commands::tools::{
    load_machine, load_tool_sources, read_options, reader_error, resolve_used_tools, ToolSource,
};
use crate::output::print_json;

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
}

#[derive(Serialize)]
struct Workpiece {
    min: [f64; 3],
    max: [f64; 3],
}

#[derive(Serialize)]
struct ToolReport {
    source: ToolSource,
    description: String,
    cutter: CutterDescription,
}

pub(crate) fn run(args: &PathArgs) -> Result<()> {
    let machine = load_machine(&args.setup.machine)?;
    let (single, table) = load_tool_sources(
        args.setup.tool.as_deref(),
        args.setup.tools.as_deref(),
        args.setup.table_units,
    )?;
    let mut options = read_options(&args.setup, single.as_ref(), table.as_ref());
    if args.setup.max_moves.is_none() {
        // Both outputs stream: no move is kept, so no move limit is needed (the loop limits
        // still end a program that never ends).
        options.gcode.max_moves = u64::MAX;
        options.apt.max_moves = u64::MAX;
    }
    let text = read_text(&args.program)?;
    let file = args.program.display().to_string();

    if args.canonical {
        let stdout = std::io::stdout().lock();
        let mut printer = CanonicalPrinter::new(BufWriter::new(stdout));
        stream_program(&text, &file, &options, &mut printer)
            .map_err(|e| reader_error(e, &options))?;
        printer.finish().context("writing to stdout")?;
        return Ok(());
    }

    let mut sink = SummarySink::new(machine, &file, &SummaryOptions::default());
    stream_program(&text, &file, &options, &mut sink).map_err(|e| reader_error(e, &options))?;
    drop(text);
    let streamed = sink.finish();
    let report = PathReport::from_summary(
        streamed.summary,
        &streamed.program,
        streamed.tool_zero_moved,
        single.as_ref(),
        table.as_ref(),
    )?;
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
    /// Summarises `program` and resolves each tool number it uses to a cutter: `single` for
    /// all, else the table, else the program's own `CUTTER/` definition.
    pub(crate) fn new(
        program: &Program,
        single: Option<&Cutter>,
        table: Option<&ToolTable>,
    ) -> Result<Self> {
        let tool_zero_moved = program.moves.iter().any(|m| m.tool == 0);
        Self::from_summary(summarize(program), program, tool_zero_moved, single, table)
    }

    /// The report of a program summarised already (`program`'s moves are not read:
    /// `tool_zero_moved` says whether a move was made with no tool loaded).
    pub(crate) fn from_summary(
        summary: ProgramSummary,
        program: &Program,
        tool_zero_moved: bool,
        single: Option<&Cutter>,
        table: Option<&ToolTable>,
    ) -> Result<Self> {
        let (resolved, undefined_tools) =
            resolve_used_tools(program, tool_zero_moved, single, table)?;
        let tool_definitions = resolved
            .into_iter()
            .map(|(n, r)| {
                let report = ToolReport {
                    source: r.source,
                    description: r.description,
                    cutter: r.cutter.describe(),
                };
                (n, report)
            })
            .collect();
        let workpiece = table.and_then(|t| t.workpiece).map(|b| Workpiece {
            min: b.min.to_array(),
            max: b.max.to_array(),
        });
        Ok(Self {
            summary,
            tool_definitions,
            undefined_tools,
            workpiece,
        })
    }

    pub(crate) fn print_human(&self) {
        print_human(&self.summary, &self.tool_definitions, &self.undefined_tools);
    }
}

fn print_human(s: &ProgramSummary, tools: &BTreeMap<u32, ToolReport>, undefined: &[u32]) {
    println!(
        "{} moves: {} rapid, {} feed ({} arcs)",
        s.moves, s.rapid_moves, s.feed_moves, s.arc_moves
    );
    println!("feed length  {:.3} mm", s.feed_length_mm);
    println!("rapid length {:.3} mm", s.rapid_length_mm);
    if let (Some(lo), Some(hi)) = (s.bbox_min, s.bbox_max) {
        println!(
            "tool tip box X {:.3} .. {:.3}  Y {:.3} .. {:.3}  Z {:.3} .. {:.3} mm",
            lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]
        );
    }
    let t = s.machining_time_s;
    println!(
        "machining time {:.0} s ({}:{:02}:{:02})",
        t,
        (t / 3600.0) as u64,
        (t / 60.0) as u64 % 60,
        t as u64 % 60
    );
    for (n, r) in tools {
        println!("T{n}: {} ({:?})", r.cutter.spec, r.source);
    }
    for n in undefined {
        println!("T{n}: not defined (give --tool or --tools)");
    }
    for w in &s.warnings {
        println!("{w}");
    }
}
