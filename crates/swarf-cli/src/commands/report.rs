//! `--report FILE.html` on the commands that run a program or size a tool, and `swarf report
//! --from DIR`: the CLI collects what a command has (program, tools, stock, meshes, plots,
//! summary) into a [`swarf_io::html::Report`], which builds and writes the page.

use crate::output::say;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::Args;
use swarf_io::html::{Report, ToolEntry};
use swarf_path::Program;
use swarf_tool::Cutter;

/// Points per tool profile drawn on the page.
const PROFILE_SAMPLES: usize = 120;
/// Chords per arc in the drawn toolpath.
const ARC_CHORDS: usize = 8;

/// A page titled `title` with the program's summary and its file as inputs, its toolpath in the
/// 3-D view, and the tools `tools` (number, description, cutter) drawn.
pub(crate) fn program_page(
    title: &str,
    file: &Path,
    program: &Program,
    tools: &[(u32, String, &Cutter)],
) -> Result<Report> {
    let summary = serde_json::to_value(swarf_path::summarize(program))?;
    let mut r = Report::new(title)
        .with_input("program", file.display().to_string())
        .with_json_inputs("program", &summary);
    r.scene.paths = program.tip_polylines(ARC_CHORDS);
    r.tools = tools
        .iter()
        .map(|(n, d, c)| ToolEntry {
            number: *n,
            description: d.clone(),
            profile: c.half_profile(PROFILE_SAMPLES),
        })
        .collect();
    Ok(r)
}

/// The tools a tool set gives the program, each described by its cutter's spec (the pages of
/// `engage`, `forces` and `schedule` have always shown the spec, not the library's
/// description that [`resolved_tools`] shows).
pub(crate) fn program_tools<'a>(
    program: &Program,
    tools: &'a swarf_tool::ToolSet,
) -> Vec<(u32, String, &'a Cutter)> {
    let mut used: Vec<u32> = program.tools.clone();
    used.extend(program.moves.iter().map(|m| m.tool));
    used.sort_unstable();
    used.dedup();
    used.into_iter()
        .filter_map(|n| {
            let c = tools.get(n)?;
            Some((n, c.spec(), c))
        })
        .collect()
}

/// Resolved tools with their descriptions (the library's, or the cutter's spec).
pub(crate) fn resolved_tools(
    resolved: &std::collections::BTreeMap<u32, swarf_tool::ResolvedTool>,
) -> Vec<(u32, String, &Cutter)> {
    resolved
        .iter()
        .map(|(n, r)| {
            let d = if r.description.is_empty() {
                r.cutter.spec()
            } else {
                r.description.clone()
            };
            (*n, d, &r.cutter)
        })
        .collect()
}

/// The text of the program's files (for the lines a page links to), decoded as the readers
/// decode them (UTF-16, Latin-1: [`swarf_path::load::read_text`]); unreadable ones are left
/// out.
pub(crate) fn sources(program: &Program) -> Vec<(String, String)> {
    program
        .files
        .iter()
        .filter_map(|f| {
            swarf_path::load::read_text(Path::new(f))
                .ok()
                .map(|t| (f.clone(), t))
        })
        .collect()
}

/// Makes `--report`'s folder, as `--out` makes its own, before any work: a report that could
/// not be written must stop the run before the output set is written, not after.
pub(crate) fn prepare(path: Option<&Path>) -> Result<()> {
    // An HTML page, named so: `--report job.ngc` (or the run's own summary.json) replaced
    // the file with the page, and exited 0.
    if let Some(p) = path {
        let html = p
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case("html") || e.eq_ignore_ascii_case("htm"));
        if !html {
            anyhow::bail!(
                "--report {}: give a file ending in .html (the page replaces the file it is \
                 written to)",
                p.display()
            );
        }
        if p.is_dir() {
            anyhow::bail!("--report {}: a folder, not a file", p.display());
        }
    }
    let Some(path) = path else {
        return Ok(());
    };
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("making the report's folder {}", dir.display()))?;
    }
    // A folder that takes no file (read-only) fails here, not after the run.
    swarf_io::atomic::check_writable(path).context("--report")
}

/// Writes the page (not once Ctrl-C asked the run to stop: the outputs written before it
/// stand, the page is left out).
pub(crate) fn write(report: &Report, path: &Path) -> Result<()> {
    crate::output::bail_if_stopped("the report")?;
    report
        .write(path)
        .with_context(|| format!("writing the report {}", path.display()))
}

/// `swarf report`.
#[derive(Debug, Args)]
pub(crate) struct ReportArgs {
    /// A command's output folder (`--out DIR` of simulate, engage, forces, toolsize, gouge,
    /// verify): its summary.json, PNG plots, STL meshes and defects.csv / violations.csv.
    #[arg(long, value_name = "DIR")]
    pub(crate) from: PathBuf,
    /// The page to write (default: DIR/report.html).
    #[arg(long, value_name = "FILE.html")]
    pub(crate) out: Option<PathBuf>,
}

pub(crate) fn run(args: &ReportArgs) -> Result<()> {
    let page = Report::from_dir(&args.from)
        .with_context(|| format!("reading the output folder {}", args.from.display()))?;
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| args.from.join("report.html"));
    // The page goes beside the results, never over one of them (`--out D/summary.json` left
    // a folder that could not be reported again).
    if let (Ok(dir), Some(Ok(parent))) = (
        args.from.canonicalize(),
        out.parent()
            .map(|p| {
                if p.as_os_str().is_empty() {
                    std::path::Path::new(".")
                } else {
                    p
                }
            })
            .map(std::path::Path::canonicalize),
    ) {
        let html = out
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case("html") || e.eq_ignore_ascii_case("htm"));
        if parent.starts_with(&dir) && out.exists() && !html {
            anyhow::bail!(
                "--out {} would replace one of the results in {}: give an .html file",
                out.display(),
                args.from.display()
            );
        }
    }
    write(&page, &out)?;
    say!("{}", out.display());
    Ok(())
}
