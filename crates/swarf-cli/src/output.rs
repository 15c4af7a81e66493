//! Writing results: JSON to stdout, files written whole or not at all.

use std::io::Write;
use std::path::Path;

use anyhow::{Context, Result};

use std::sync::atomic::{AtomicBool, Ordering};

static STOP: AtomicBool = AtomicBool::new(false);
static LISTENING: AtomicBool = AtomicBool::new(false);

/// Installs the one Ctrl-C handler of the process (first thing in `main`, before any input is
/// read). While a long run listens ([`listen_for_stop`]), Ctrl-C only asks it to stop
/// ([`stop_requested`]): the computation ends with an error, and so does the writing of the
/// outputs, before the next file (every output set stops then, [`output_set`]), and an HTML
/// report is not begun; a set cut short leaves nothing. A second Ctrl-C, or one while not
/// listening, ends the process at once, as it would without a handler (exit 130) — except
/// while an output set renames its files into place ([`swarf_io::output_set::committing`]),
/// which would leave old and new files mixed: that one is taken as a request to stop.
pub(crate) fn install_stop_handler() {
    // If it cannot be installed, Ctrl-C keeps its default meaning.
    let _ = ctrlc::set_handler(|| {
        let again = STOP.swap(true, Ordering::SeqCst);
        if (again || !LISTENING.load(Ordering::SeqCst)) && !swarf_io::output_set::committing() {
            std::process::exit(130);
        }
    });
}

/// An error naming `what` was not written once Ctrl-C asked the run to stop.
pub(crate) fn bail_if_stopped(what: &str) -> Result<()> {
    if stop_requested() {
        anyhow::bail!("stopped by Ctrl-C before {what} was written");
    }
    Ok(())
}

/// From now on Ctrl-C asks this run to stop instead of ending the process (called before any
/// input is read, so a Ctrl-C while the input is read counts too).
pub(crate) fn listen_for_stop() {
    LISTENING.store(true, Ordering::SeqCst);
}

/// With `SWARF_READY_FILE=PATH` in the environment, creates the file once Ctrl-C has its final
/// meaning for this run (handler installed and, for long runs, listening), for scripts and tests
/// that send the signal: one sent earlier could still end the process with exit 130.
pub(crate) fn announce_ready() {
    if let Some(path) = std::env::var_os("SWARF_READY_FILE") {
        let _ = std::fs::write(path, b"ready\n");
    }
}

/// True once Ctrl-C was pressed while listening.
pub(crate) fn stop_requested() -> bool {
    STOP.load(Ordering::SeqCst)
}

/// A progress bar over `moves` moves on stderr, drawn only on a terminal (nothing when piped).
pub(crate) fn moves_bar(moves: usize) -> indicatif::ProgressBar {
    use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
    let bar =
        ProgressBar::with_draw_target(Some(moves as u64), ProgressDrawTarget::stderr_with_hz(10));
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} moves  {elapsed} (eta {eta})")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar
}

/// The observer the CLI gives a long library run over a program's moves: it moves a
/// [`moves_bar`] and asks the run to stop once Ctrl-C was pressed ([`stop_requested`]).
pub(crate) struct MovesProgress {
    bar: indicatif::ProgressBar,
}

impl MovesProgress {
    /// A bar over `moves` moves.
    pub(crate) fn new(moves: usize) -> Self {
        Self {
            bar: moves_bar(moves),
        }
    }

    /// Clears the bar (when the run is over, stopped or not).
    pub(crate) fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

impl swarf_geom::Observer for MovesProgress {
    fn progress(&self, done: u64, _total: u64) -> std::ops::ControlFlow<()> {
        self.bar.set_position(done);
        if stop_requested() {
            std::ops::ControlFlow::Break(())
        } else {
            std::ops::ControlFlow::Continue(())
        }
    }
}

static STDOUT_GONE: AtomicBool = AtomicBool::new(false);

static STDOUT_FAILED: std::sync::Mutex<Option<String>> = std::sync::Mutex::new(None);

/// Writes one line of a command's text output on stdout (the [`say!`] macro). A reader that
/// closed the pipe (`swarf path p.nc | head -3`) ends the printing, not the run: the later
/// lines are dropped, the output files are still written and the exit status is the run's.
/// (`println!` panics there.) Any other error writing stdout (a full disk) ends the printing
/// too, and the run then fails with it ([`stdout_failure`]).
pub(crate) fn say_line(args: std::fmt::Arguments<'_>) {
    if STDOUT_GONE.load(Ordering::Relaxed) {
        return;
    }
    let mut out = std::io::stdout().lock();
    if let Err(e) = out.write_fmt(args).and_then(|()| out.write_all(b"\n")) {
        STDOUT_GONE.store(true, Ordering::Relaxed);
        if e.kind() != std::io::ErrorKind::BrokenPipe {
            if let Ok(mut f) = STDOUT_FAILED.lock() {
                *f = Some(e.to_string());
            }
        }
    }
}

/// Why the text output could not be written, other than a closed pipe: the run's result is
/// on stdout, so the run fails.
pub(crate) fn stdout_failure() -> Option<String> {
    STDOUT_FAILED.lock().ok().and_then(|f| f.clone())
}

/// `println!` for a command's text output, through [`say_line`].
macro_rules! say {
    () => {
        $crate::output::say_line(format_args!(""))
    };
    ($($arg:tt)*) => {
        $crate::output::say_line(format_args!($($arg)*))
    };
}
pub(crate) use say;

/// Prints a value as pretty JSON on stdout.
pub(crate) fn print_json<T: serde::Serialize>(value: &T) -> Result<()> {
    let mut out = std::io::stdout().lock();
    serde_json::to_writer_pretty(&mut out, value).context("writing JSON to stdout")?;
    writeln!(out).context("writing to stdout")?;
    Ok(())
}

/// A number with `decimals` decimals, trailing zeros dropped and no negative zero, as a user
/// would type it back (a chamfer's 5 computed as 4.999999999999999 reads 5 at ten).
pub(crate) fn trimmed(v: f64, decimals: usize) -> String {
    let s = format!("{v:.decimals$}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".to_string()
    } else {
        s.to_string()
    }
}

/// Writes `bytes` to `path` whole or not at all (a temporary file and a rename).
pub(crate) fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    swarf_io::write_atomic(path, |w| w.write_all(bytes))
        .with_context(|| format!("writing {}", path.display()))
}

/// The default of `--max-output-mb`: [`swarf_io::DEFAULT_MAX_OUTPUT_BYTES`] in MB.
pub(crate) const DEFAULT_MAX_OUTPUT_MB: u64 = swarf_io::DEFAULT_MAX_OUTPUT_BYTES / 1_000_000;

/// The files of one command, written together or not at all, `max_output_mb` MB in all.
pub(crate) fn output_set(dir: &Path, max_output_mb: u64) -> Result<swarf_io::OutputSet> {
    let mut set = swarf_io::OutputSet::new(dir, max_output_mb.saturating_mul(1_000_000))
        .context("the output folder")?;
    set.stop_when(&STOP);
    Ok(set)
}

/// A hidden folder beside an output folder, for library writers that take paths (maps, meshes):
/// what they write there is moved into the output folder as one set by [`Staging::commit`], and
/// the folder is removed whatever happens.
pub(crate) struct Staging {
    path: std::path::PathBuf,
    /// Plots and files of the command's own, removed at the commit where this run did not
    /// write them ([`swarf_io::OutputSet::owns_files`], [`swarf_io::OutputSet::owns_file`]).
    owned_plots: Vec<(&'static str, &'static [&'static str])>,
    owned_files: Vec<&'static str>,
}

impl Staging {
    /// A fresh staging folder for `dir`.
    pub(crate) fn for_dir(dir: &Path) -> Result<Self> {
        let name = dir
            .file_name()
            .map_or_else(|| "out".into(), |n| n.to_string_lossy().into_owned());
        let parent = match dir.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => std::path::PathBuf::from("."),
        };
        let path = parent.join(format!(".{name}.swarf-staging-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&path);
        std::fs::create_dir_all(&path).with_context(|| format!("creating {}", path.display()))?;
        Ok(Self {
            path,
            owned_plots: Vec::new(),
            owned_files: Vec::new(),
        })
    }

    /// PNG files of subfolder `rel` named with one of `prefixes` are the command's own.
    pub(crate) fn owns_plots(&mut self, rel: &'static str, prefixes: &'static [&'static str]) {
        self.owned_plots.push((rel, prefixes));
    }

    /// File `rel` is the command's own.
    pub(crate) fn owns_file(&mut self, rel: &'static str) {
        self.owned_files.push(rel);
    }

    /// The staging folder.
    pub(crate) fn path(&self) -> &Path {
        &self.path
    }

    /// Moves every file written into the staging folder into `dir` as one set (sizes checked
    /// against `max_output_mb`).
    pub(crate) fn commit(self, dir: &Path, max_output_mb: u64) -> Result<()> {
        let mut set = output_set(dir, max_output_mb)?;
        for &(rel, prefixes) in &self.owned_plots {
            set.owns_files(rel, prefixes);
        }
        for rel in &self.owned_files {
            set.owns_file(rel);
        }
        let mut stack = vec![self.path.clone()];
        while let Some(d) = stack.pop() {
            for e in std::fs::read_dir(&d).with_context(|| format!("reading {}", d.display()))? {
                let p = e?.path();
                if p.is_dir() {
                    stack.push(p);
                    continue;
                }
                let rel = p.strip_prefix(&self.path).unwrap_or(&p);
                let name = rel.to_string_lossy().replace('\\', "/");
                let bytes =
                    std::fs::read(&p).with_context(|| format!("reading {}", p.display()))?;
                set.write_bytes(&name, &bytes)?;
            }
        }
        set.commit()?;
        Ok(())
    }
}

impl Drop for Staging {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.path);
    }
}

/// Checks the estimated sizes of the files about to be written; the error says how to get
/// smaller files or a larger limit.
pub(crate) fn check_sizes(set: &swarf_io::OutputSet, files: &[(&str, u64)]) -> Result<()> {
    set.check_sizes(files).map_err(|e| {
        anyhow::anyhow!(
            "{e}: give a coarser --resolution, or raise the limit with --max-output-mb N"
        )
    })
}

/// A CSV field, quoted when it holds a comma, a quote or a line break.
pub(crate) fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// The summary with the surface's [`Caveats`](swarf_surface::Caveats) as keys of its own
/// (`skipped_faces`, `untrimmed_faces`, `unapplied_placements`, each with its notes).
pub(crate) fn with_caveats(
    mut v: serde_json::Value,
    caveats: &swarf_surface::Caveats,
) -> Result<serde_json::Value> {
    if let (serde_json::Value::Object(c), Some(obj)) =
        (serde_json::to_value(caveats)?, v.as_object_mut())
    {
        obj.extend(c);
    }
    Ok(v)
}

/// A line on stderr for each kind of caveat, saying what it means for `what` (the command's
/// results).
pub(crate) fn caveats_said(caveats: &swarf_surface::Caveats, what: &str) {
    if caveats.skipped_faces > 0 {
        eprintln!(
            "warning: {} face(s) of the surface were not read (skipped_faces): the {what} \
             take no account of them",
            caveats.skipped_faces
        );
    }
    if caveats.untrimmed_faces > 0 {
        eprintln!(
            "warning: {} face(s) were used on their whole surface, their trim not read \
             (untrimmed_faces): the {what} near them may answer to surface outside the face",
            caveats.untrimmed_faces
        );
    }
    if caveats.unapplied_placements > 0 {
        eprintln!(
            "warning: {} assembly placement(s) were not applied (unapplied_placements): the \
             parts they place may be misplaced",
            caveats.unapplied_placements
        );
    }
}
