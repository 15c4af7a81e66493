//! `swarf demo`: the built-in job — a 100 × 80 × 20 mm block, a roughing and a 3-D finishing
//! program written for it, and their tool library, all embedded in the binary — read, simulated
//! on a tri-dexel stock, and written out as a mesh and a summary.

use std::path::Path;

use anyhow::{bail, Context, Result};
use serde::Serialize;
use swarf_path::canonical::CanonicalPrinter;
use swarf_path::load::{read_program_str, stream_program, ReadOptions};
use swarf_path::Machine;
use swarf_stock::{simulate, MeshOptions, SimOptions, StockSpec};
use swarf_tool::table::parse_toml_library;

use crate::cli::DemoArgs;
use crate::commands::path::PathReport;
use crate::commands::simulate::{tools_for, write_outputs, SimulateSummary};
use crate::output::{print_json, write_atomic};

/// The demo program (LinuxCNC G-code with parameters, loops, conditionals and arcs).
const PROGRAM: &str = include_str!("../../demo/demo.ngc");
/// Its tool library (swarf TOML).
const TOOLS: &str = include_str!("../../demo/tools.toml");
/// The block the program was written for: top face at Z0, origin at its front-left corner.
const STOCK: &str = "box:0,0,-20,100,80,0";

#[derive(Serialize)]
struct DemoReport<'a> {
    stock: &'static str,
    program: &'a PathReport,
    simulation: &'a SimulateSummary,
    out_dir: String,
}

pub(crate) fn run(args: &DemoArgs) -> Result<()> {
    if !(args.resolution > 0.0 && args.resolution.is_finite()) {
        bail!(
            "--resolution must be a positive number of mm, got {}",
            args.resolution
        );
    }
    let options = ReadOptions::default();
    let table = parse_toml_library(TOOLS, "demo/tools.toml")?;
    let program = read_program_str(PROGRAM, "demo/demo.ngc", Machine::three_axis(), &options)?;
    let path_report = PathReport::new(&program, None, Some(&table))?;
    let tools = tools_for(&program, None, Some(&table))?;
    let mut stock = StockSpec::parse(STOCK)?.build(args.resolution, MeshOptions::default())?;
    let report = simulate(&program, &tools, &mut stock, &SimOptions::default())?;
    let summary = SimulateSummary::new(&report);

    let dir = &args.out;
    write_outputs(dir, &program, &stock, &report, &summary)?;
    write_sources(dir, &options)?;
    print_json(&DemoReport {
        stock: STOCK,
        program: &path_report,
        simulation: &summary,
        out_dir: dir.display().to_string(),
    })
}

/// The program, its tool library and its LinuxCNC canonical motion, beside the results.
fn write_sources(dir: &Path, options: &ReadOptions) -> Result<()> {
    write_atomic(&dir.join("demo.ngc"), PROGRAM.as_bytes())?;
    write_atomic(&dir.join("tools.toml"), TOOLS.as_bytes())?;
    let mut printer = CanonicalPrinter::new(Vec::new());
    stream_program(PROGRAM, "demo/demo.ngc", options, &mut printer)?;
    let canonical = printer.finish().context("printing the canonical motion")?;
    write_atomic(&dir.join("canonical.txt"), &canonical)
}
