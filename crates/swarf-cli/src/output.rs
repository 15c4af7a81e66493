//! Writing results: JSON to stdout, files written whole or not at all.

use std::io::Write;
use std::path::Path;

use anyhow::{Context, Result};

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

/// Prints a value as pretty JSON on stdout.
pub(crate) fn print_json<T: serde::Serialize>(value: &T) -> Result<()> {
    let mut out = std::io::stdout().lock();
    serde_json::to_writer_pretty(&mut out, value).context("writing JSON to stdout")?;
    writeln!(out).context("writing to stdout")?;
    Ok(())
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
    swarf_io::OutputSet::new(dir, max_output_mb.saturating_mul(1_000_000))
        .with_context(|| format!("creating {}", dir.display()))
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
