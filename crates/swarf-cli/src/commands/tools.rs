//! What the commands that read a program share: the [`Job`] their setup options name, its
//! errors with the option that fixes them, and the tools they require.

use std::path::Path;

use anyhow::Result;
use swarf_job::{Job, JobError, JobSetup};
use swarf_path::limit::DEFAULT_MAX_MOVES;
use swarf_tool::ToolSet;

use crate::cli::SetupArgs;

/// A job error, with the option that raises the move limit named when that limit stopped the
/// reading.
pub(crate) fn job_error(e: JobError) -> anyhow::Error {
    match e {
        JobError::MoveLimit(e) => anyhow::anyhow!("{e}; --max-moves N raises the limit"),
        e => e.into(),
    }
}

/// Loads the machine and cutter sources `setup` names.
pub(crate) fn load_job_setup(setup: &SetupArgs) -> Result<JobSetup> {
    load_job_setup_with(setup, DEFAULT_MAX_MOVES)
}

/// [`load_job_setup`] with a move limit of `max_moves`. What the tool library's reader left
/// out or changed (a row without a radius, an indexed tool, a length that does not fit) is
/// told on stderr, one `swarf: warning:` line each: a tool the program then calls is
/// undefined, and the line says why.
pub(crate) fn load_job_setup_with(setup: &SetupArgs, max_moves: u64) -> Result<JobSetup> {
    let job = JobSetup::load(&setup.job_options(max_moves)).map_err(job_error)?;
    // (Each warning names the file and line itself; a long table's first few stand for the
    // rest.)
    if let Some(table) = &job.table {
        const SHOWN: usize = 5;
        for w in table.warnings.iter().take(SHOWN) {
            eprintln!("swarf: warning: {w}");
        }
        if table.warnings.len() > SHOWN {
            eprintln!(
                "swarf: warning: … and {} more about the tool library",
                table.warnings.len() - SHOWN
            );
        }
    }
    Ok(job)
}

/// Reads `program` as `setup` says (machine, units, cutters) and resolves its tools. What the
/// reader did not act on or read by assumption (units never stated, a compensation register
/// taken as zero, a cutter redefined) is told on stderr, the first few warnings and a count —
/// `swarf path` lists them all: a simulation that hid them would look as sure as one that
/// read every word.
pub(crate) fn load_job(setup: &SetupArgs, program: &Path) -> Result<Job> {
    let job = load_job_setup(setup)?.read(program).map_err(job_error)?;
    const SHOWN: usize = 5;
    let warnings = &job.program.warnings;
    for w in warnings.iter().take(SHOWN) {
        eprintln!("swarf: {w}");
    }
    if warnings.len() > SHOWN {
        eprintln!(
            "swarf: … and {} more warnings about the program (`swarf path {}` lists them all)",
            warnings.len() - SHOWN,
            program.display()
        );
    }
    Ok(job)
}

/// The tools of `job`, every one the program uses required to be defined: the error says how
/// to define the first one missing (and why the library left it out, when it did).
pub(crate) fn defined_tools(job: &Job) -> Result<&ToolSet> {
    if let Some(&n) = job.undefined_tools.first() {
        // Where the tool first moves: the line to look at (a rapid before the first tool
        // change moves tool 0).
        let p = &job.program;
        let at = p
            .moves
            .iter()
            .find(|m| m.tool == n)
            .map(|m| {
                let file = p.files.get(usize::from(m.file)).map_or("", String::as_str);
                format!("{file}:{}: ", m.line)
            })
            .unwrap_or_default();
        // A tool the library defines but swarf cannot model (a CAMotics spheroid): its why.
        if let Some(why) = job.setup.table.as_ref().and_then(|t| t.left_out.get(&n)) {
            anyhow::bail!(
                "{at}the program uses tool {n}, which the tool library defines but swarf cannot \
                 use ({why}): give --tool SPEC for every tool, or a library whose tool {n} swarf \
                 can model"
            );
        }
        if n == 0 {
            anyhow::bail!(
                "{at}the program moves before it loads a tool (tool 0), which nothing defines: \
                 give --tool SPEC (the cutter of every tool, tool 0 too), or --tools FILE with a \
                 tool 0 (the spindle's cutter at the start)"
            );
        }
        anyhow::bail!(
            "{at}the program uses tool {n}, which nothing defines: give --tool SPEC for every \
             tool, or --tools FILE with tool {n}"
        );
    }
    Ok(&job.tools)
}

/// Refuses a ray spacing `h` (mm) coarser than half the smallest cutter's diameter: cuts of that
/// cutter would fall between the rays (a 10 mm slot at `--resolution 30` removed nothing, at
/// 1000 a quarter of the stock), and the result would be noise, not a simulation. A spacing
/// over a tenth of the diameter only gets a note.
pub(crate) fn check_resolution(tools: &ToolSet, h: f64) -> Result<()> {
    let Some(d) = tools
        .resolved()
        .values()
        .map(|t| &t.cutter)
        .chain(tools.fallback())
        .map(swarf_tool::Cutter::max_diameter)
        .reduce(f64::min)
    else {
        return Ok(());
    };
    if h > 0.5 * d {
        anyhow::bail!(
            "--resolution {h} mm is coarser than half the smallest cutter's diameter ({d} mm): \
             its cuts would fall between the rays; give at most {:.3} mm (a tenth of it for \
             volumes within a few per cent)",
            0.5 * d
        );
    }
    if h > 0.1 * d {
        eprintln!(
            "note: --resolution {h} mm is coarse for the smallest cutter (Ø{d} mm): volumes and \
             walls are resolved to about a ray spacing"
        );
    }
    Ok(())
}
