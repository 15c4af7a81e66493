//! `swarf demo`: the built-in job — a roughing and a 3-D finishing program for a 100 × 80 ×
//! 20 mm block, with its tool library, embedded in the binary.

use std::path::Path;

use anyhow::{Context, Result};
use swarf_path::canonical::CanonicalPrinter;
use swarf_path::load::{read_program_str, stream_program, ReadOptions};
use swarf_path::Machine;
use swarf_tool::table::parse_toml_library;

use crate::cli::DemoArgs;
use crate::commands::path::PathReport;
use crate::output::{print_json, write_atomic};

/// The demo program (LinuxCNC G-code with parameters, loops, conditionals and arcs).
const PROGRAM: &str = include_str!("../../demo/demo.ngc");
/// Its tool library (swarf TOML).
const TOOLS: &str = include_str!("../../demo/tools.toml");

pub(crate) fn run(args: &DemoArgs) -> Result<()> {
    let options = ReadOptions::default();
    let table = parse_toml_library(TOOLS, "demo/tools.toml")?;
    let program = read_program_str(PROGRAM, "demo/demo.ngc", Machine::three_axis(), &options)?;
    let report = PathReport::new(&program, None, Some(&table))?;
    if let Some(dir) = &args.out {
        write_outputs(dir, &report, &options)?;
    }
    print_json(&report)
}

fn write_outputs(dir: &Path, report: &PathReport, options: &ReadOptions) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    write_atomic(&dir.join("demo.ngc"), PROGRAM.as_bytes())?;
    write_atomic(&dir.join("tools.toml"), TOOLS.as_bytes())?;
    let mut printer = CanonicalPrinter::new(Vec::new());
    stream_program(PROGRAM, "demo/demo.ngc", options, &mut printer)?;
    write_atomic(&dir.join("canonical.txt"), &printer.finish()?)?;
    let mut json = serde_json::to_vec_pretty(report)?;
    json.push(b'\n');
    write_atomic(&dir.join("summary.json"), &json)
}
