//! What `path`, `simulate` and `demo` share: the machine, the reader options, and which cutter
//! each tool number of a program is.

use std::collections::BTreeMap;
use std::path::Path;

use anyhow::{Context, Result};
use swarf_path::gcode::GcodeOptions;
use swarf_path::load::ReadOptions;
use swarf_path::{Machine, Program, Units};
use swarf_tool::{Cutter, LengthUnit, ToolSet, ToolTable};

use crate::cli::{SetupArgs, TableUnits};

/// A built-in machine name, or a TOML machine file when the argument names an existing file.
pub(crate) fn load_machine(arg: &str) -> Result<Machine> {
    let p = Path::new(arg);
    if p.is_file() {
        Machine::from_file(p).with_context(|| format!("machine file {arg}"))
    } else {
        Machine::from_name(arg).with_context(|| format!("machine `{arg}`"))
    }
}

/// Reader options for programs whose units before the first G20/G21 are `initial`.
pub(crate) fn read_options(initial: TableUnits) -> ReadOptions {
    ReadOptions {
        gcode: GcodeOptions::default().with_initial_units(match initial {
            TableUnits::Mm => Units::Mm,
            TableUnits::Inch => Units::Inch,
        }),
        ..ReadOptions::default()
    }
}

/// A program read through the machine of `setup`, with the cutter sources it names.
pub(crate) struct Setup {
    pub(crate) program: Program,
    pub(crate) single: Option<Cutter>,
    pub(crate) table: Option<ToolTable>,
}

/// Reads `program` as `setup` says (machine, initial units) and loads `--tool`/`--tools`.
pub(crate) fn load_setup(setup: &SetupArgs, program: &Path) -> Result<Setup> {
    let machine = load_machine(&setup.machine)?;
    let program =
        swarf_path::load::read_program(program, machine, &read_options(setup.initial_units))?;
    let (single, table) = load_tool_sources(
        setup.tool.as_deref(),
        setup.tools.as_deref(),
        setup.table_units,
    )?;
    Ok(Setup {
        program,
        single,
        table,
    })
}

/// `--tool SPEC` and `--tools FILE`, read.
pub(crate) fn load_tool_sources(
    spec: Option<&str>,
    table: Option<&Path>,
    units: TableUnits,
) -> Result<(Option<Cutter>, Option<ToolTable>)> {
    let single = spec
        .map(|s| Cutter::from_spec(s).with_context(|| format!("tool spec `{s}`")))
        .transpose()?;
    let unit = match units {
        TableUnits::Mm => LengthUnit::Mm,
        TableUnits::Inch => LengthUnit::Inch,
    };
    let table = table
        .map(|t| ToolTable::read(t, unit).with_context(|| format!("tool table {}", t.display())))
        .transpose()?;
    Ok((single, table))
}

pub(crate) use swarf_tool::{ResolvedTool, ToolSource};

/// Each tool number `program` uses (tool 0 when it never loads one), resolved to a cutter by
/// [`ToolSet::resolve`]: `single` for all, else the table, else the program's own `CUTTER/`.
/// Numbers nothing defines are returned apart.
pub(crate) fn resolve_tools(
    program: &Program,
    single: Option<&Cutter>,
    table: Option<&ToolTable>,
) -> Result<(BTreeMap<u32, ResolvedTool>, Vec<u32>)> {
    let mut used: Vec<u32> = program.tools.clone();
    if program.moves.iter().any(|m| m.tool == 0) && !used.contains(&0) {
        used.insert(0, 0);
    }
    let (set, undefined) = ToolSet::resolve(&used, &program.cutter_definitions, single, table)?;
    Ok((set.resolved().clone(), undefined))
}

/// The [`ToolSet`] of every tool the program uses, each required to be defined.
pub(crate) fn tool_set(
    program: &Program,
    single: Option<&Cutter>,
    table: Option<&ToolTable>,
) -> Result<ToolSet> {
    Ok(resolve_all(program, single, table)?
        .into_iter()
        .fold(ToolSet::default(), |set, (n, r)| {
            set.with(n, r.cutter, r.source)
        }))
}

/// [`resolve_tools`], requiring every tool the program uses to be defined: the error says how
/// to define the first one missing.
pub(crate) fn resolve_all(
    program: &Program,
    single: Option<&Cutter>,
    table: Option<&ToolTable>,
) -> Result<BTreeMap<u32, ResolvedTool>> {
    let (resolved, undefined) = resolve_tools(program, single, table)?;
    if let Some(n) = undefined.first() {
        anyhow::bail!(
            "the program uses tool {n}, which nothing defines: give --tool SPEC for every tool, \
             or --tools FILE with tool {n}"
        );
    }
    Ok(resolved)
}
