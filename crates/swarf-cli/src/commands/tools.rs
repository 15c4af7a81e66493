//! What `path`, `simulate` and `demo` share: the machine, the reader options, and which cutter
//! each tool number of a program is.

use std::collections::BTreeMap;
use std::path::Path;

use anyhow::{Context, Result};
use swarf_path::apt::AptOptions;
use swarf_path::gcode::{GcodeDialect, GcodeOptions};
use swarf_path::limit::{is_move_limit, DEFAULT_MAX_MOVES};
use swarf_path::load::ReadOptions;
use swarf_path::{Machine, PathError, Program, Units};
use swarf_tool::{Cutter, LengthUnit, ToolSet, ToolTable};

use crate::cli::{Dialect, SetupArgs, TableUnits};

/// A built-in machine name, or a TOML machine file when the argument names an existing file.
pub(crate) fn load_machine(arg: &str) -> Result<Machine> {
    let p = Path::new(arg);
    if p.is_file() {
        Machine::from_file(p).with_context(|| format!("machine file {arg}"))
    } else {
        Machine::from_name(arg).with_context(|| format!("machine `{arg}`"))
    }
}

/// Reader options from `setup`: initial units, subroutine folders, dialect, and the tool
/// diameters cutter compensation needs (from the library, or `--tool`'s for every tool).
pub(crate) fn read_options(
    setup: &SetupArgs,
    single: Option<&Cutter>,
    table: Option<&ToolTable>,
) -> ReadOptions {
    let mut gcode = GcodeOptions::default().with_initial_units(match setup.initial_units {
        TableUnits::Mm => Units::Mm,
        TableUnits::Inch => Units::Inch,
    });
    for dir in &setup.subroutine_path {
        gcode = gcode.with_subroutine_dir(dir.clone());
    }
    if let Some(d) = setup.dialect {
        gcode = gcode.with_dialect(match d {
            Dialect::Linuxcnc => GcodeDialect::LinuxCnc,
            Dialect::Fanuc => GcodeDialect::Fanuc,
        });
    }
    match single {
        Some(c) => gcode = gcode.with_default_tool_diameter(c.apt_params().d),
        None => {
            for (n, t) in table.map(|t| &t.tools).into_iter().flatten() {
                gcode = gcode.with_tool_diameter(*n, t.cutter.apt_params().d);
            }
        }
    }
    let max_moves = setup.max_moves.unwrap_or(DEFAULT_MAX_MOVES);
    ReadOptions {
        gcode: gcode.with_max_moves(max_moves),
        apt: AptOptions::default().with_max_moves(max_moves),
        ..ReadOptions::default()
    }
}

/// A reader error, with the option that raises the move limit named when that limit stopped
/// the reading.
pub(crate) fn reader_error(e: PathError, options: &ReadOptions) -> anyhow::Error {
    if is_move_limit(&e, options.gcode.max_moves) || is_move_limit(&e, options.apt.max_moves) {
        anyhow::anyhow!("{e}; --max-moves N raises the limit")
    } else {
        e.into()
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
    let (single, table) = load_tool_sources(
        setup.tool.as_deref(),
        setup.tools.as_deref(),
        setup.table_units,
    )?;
    let options = read_options(setup, single.as_ref(), table.as_ref());
    let program = swarf_path::load::read_program(program, machine, &options)
        .map_err(|e| reader_error(e, &options))?;
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
    let tool_zero_moved = program.moves.iter().any(|m| m.tool == 0);
    resolve_used_tools(program, tool_zero_moved, single, table)
}

/// [`resolve_tools`] for a program whose moves were not kept (`program.moves` is not read):
/// `tool_zero_moved` says whether a move was made with no tool loaded.
pub(crate) fn resolve_used_tools(
    program: &Program,
    tool_zero_moved: bool,
    single: Option<&Cutter>,
    table: Option<&ToolTable>,
) -> Result<(BTreeMap<u32, ResolvedTool>, Vec<u32>)> {
    let mut used: Vec<u32> = program.tools.clone();
    if tool_zero_moved && !used.contains(&0) {
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
