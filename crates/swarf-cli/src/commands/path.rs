//! `swarf path PROGRAM`: read a program and print its summary or its canonical motion.

use std::collections::BTreeMap;
use std::io::BufWriter;
use std::path::Path;

use anyhow::{Context, Result};
use serde::Serialize;
use swarf_path::canonical::CanonicalPrinter;
use swarf_path::gcode::GcodeOptions;
use swarf_path::load::{read_program_str, read_text, stream_program, ReadOptions};
use swarf_path::{summarize, Machine, Program, ProgramSummary, Units};
use swarf_tool::{Cutter, CutterDescription, LengthUnit, ToolTable};

use crate::cli::{PathArgs, TableUnits};
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
    source: &'static str,
    description: String,
    cutter: CutterDescription,
}

pub(crate) fn run(args: &PathArgs) -> Result<()> {
    let machine = load_machine(&args.machine)?;
    let options = ReadOptions {
        gcode: GcodeOptions::default().with_initial_units(match args.initial_units {
            TableUnits::Mm => Units::Mm,
            TableUnits::Inch => Units::Inch,
        }),
        ..ReadOptions::default()
    };
    let text = read_text(&args.program)?;
    let file = args.program.display().to_string();

    if args.canonical {
        let stdout = std::io::stdout().lock();
        let mut printer = CanonicalPrinter::new(BufWriter::new(stdout));
        stream_program(&text, &file, &options, &mut printer)?;
        printer.finish().context("writing to stdout")?;
        return Ok(());
    }

    let program = read_program_str(&text, &file, machine, &options)?;
    let table_unit = match args.table_units {
        TableUnits::Mm => LengthUnit::Mm,
        TableUnits::Inch => LengthUnit::Inch,
    };
    let single = args
        .tool
        .as_deref()
        .map(|s| Cutter::from_spec(s).with_context(|| format!("tool spec `{s}`")))
        .transpose()?;
    let table = args
        .tools
        .as_deref()
        .map(|t| {
            ToolTable::read(t, table_unit).with_context(|| format!("tool table {}", t.display()))
        })
        .transpose()?;
    let report = PathReport::new(&program, single.as_ref(), table.as_ref())?;
    if args.json {
        return print_json(&report);
    }
    report.print_human();
    Ok(())
}

/// A built-in machine name, or a TOML machine file when the argument names an existing file.
pub(crate) fn load_machine(arg: &str) -> Result<Machine> {
    let p = Path::new(arg);
    if p.is_file() {
        Machine::from_file(p).with_context(|| format!("machine file {arg}"))
    } else {
        Machine::from_name(arg).with_context(|| format!("machine `{arg}`"))
    }
}

impl PathReport {
    /// Summarises `program` and resolves each tool number it uses to a cutter: `single` for
    /// all, else the table, else the program's own `CUTTER/` definition.
    pub(crate) fn new(
        program: &Program,
        single: Option<&Cutter>,
        table: Option<&ToolTable>,
    ) -> Result<Self> {
        let (tool_definitions, undefined_tools) = resolve_tools(program, single, table)?;
        let workpiece = table.and_then(|t| t.workpiece).map(|b| Workpiece {
            min: b.min.to_array(),
            max: b.max.to_array(),
        });
        Ok(Self {
            summary: summarize(program),
            tool_definitions,
            undefined_tools,
            workpiece,
        })
    }

    pub(crate) fn print_human(&self) {
        print_human(&self.summary, &self.tool_definitions, &self.undefined_tools);
    }
}

fn resolve_tools(
    program: &Program,
    single: Option<&Cutter>,
    table: Option<&ToolTable>,
) -> Result<(BTreeMap<u32, ToolReport>, Vec<u32>)> {
    let mut used: Vec<u32> = program.tools.clone();
    if used.is_empty() && !program.moves.is_empty() {
        used.push(0);
    }
    let mut defs = BTreeMap::new();
    let mut undefined = Vec::new();
    for n in used {
        let from_program = program
            .cutter_definitions
            .iter()
            .rev()
            .find(|(t, _)| *t == n);
        let report = if let Some(c) = single {
            Some(ToolReport {
                source: "--tool",
                description: String::new(),
                cutter: c.describe(),
            })
        } else if let Some(e) = table.and_then(|t| t.tools.get(&n)) {
            Some(ToolReport {
                source: "--tools",
                description: e.description.clone(),
                cutter: e.cutter.describe(),
            })
        } else if let Some((_, p)) = from_program {
            // h = 0: the program did not say how long the cutting part is; take the
            // library's default for a named cutter (three diameters).
            let h = if p[6] > 0.0 {
                p[6]
            } else {
                (3.0 * p[0]).max(p[3] + p[1])
            };
            let c = Cutter::apt(p[0], p[1], p[2], p[3], p[4], p[5], h)
                .with_context(|| format!("CUTTER/ definition of tool {n} in the program"))?;
            Some(ToolReport {
                source: "program",
                description: String::new(),
                cutter: c.describe(),
            })
        } else {
            None
        };
        match report {
            Some(r) => {
                defs.insert(n, r);
            }
            None => undefined.push(n),
        }
    }
    Ok((defs, undefined))
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
        println!("T{n}: {} ({})", r.cutter.spec, r.source);
    }
    for n in undefined {
        println!("T{n}: not defined (give --tool or --tools)");
    }
    for w in &s.warnings {
        println!("{w}");
    }
}
