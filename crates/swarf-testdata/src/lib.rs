//! Test support shared by the swarf crates (a dev-dependency only; never published).
//!
//! **Third-party test data.** Some tests read real programs, meshes and surfaces written by
//! others (`gcode/`, `apt/`, `stl/`, `step/`, `iges/`, listed with their sources and licences in
//! the data set's `MANIFEST.md`). Their licences do not allow committing them, so they live
//! outside the repository, in the folder named by the environment variable `SWARF_TEST_DATA`
//! (a relative path is taken from the workspace root), by default `../shared/data` beside the
//! workspace. A test asks for its files with [`path`] or [`paths`]: where they are missing it
//! gets `None` after one line on stderr,
//!
//! ```text
//! skipped: path_command::shared_programs needs gcode/linuxcnc_spiral.ngc from SWARF_TEST_DATA (…)
//! ```
//!
//! so a fresh clone passes its suite and says what it did not run; `grep -c '^skipped: '` on the
//! suite's stderr counts the skipped tests. The line is written straight to the process's
//! stderr, past the test harness's output capture, so it is printed for passing tests too. With
//! `SWARF_REQUIRE_TEST_DATA=1` a missing file fails the test instead (CI sets it where the data
//! is meant to be present, so a moved folder cannot turn into silent skips).
//!
//! **Fixtures written by code.** [`fixtures`] holds small inputs the tests need in every
//! checkout (a STEP sphere), written here rather than copied from third parties.
//!
//! **Scratch folders.** [`scratch_dir`] gives a test its own folder under the system's
//! temporary directory (named by the test's tag and the process id).
//!
//! **Property tests.** [`proptest_config`] is proptest's default configuration except that a
//! failing case is printed (with the line to add to the test's `.proptest-regressions` file)
//! instead of written into the source tree, so a failing run leaves no untracked file; the
//! committed regression files are still read and their cases run first.
//!
//! **The machine's state.** [`host::probe`] measures how long a read from memory and a
//! dependent multiply-add take right now; the benchmarks print it beside their figures, since
//! the shared machines they run on change from hour to hour.
//!
//! ```no_run
//! let Some(file) = swarf_testdata::path("gcode/linuxcnc_spiral.ngc") else {
//!     return; // the skip line is printed
//! };
//! let text = std::fs::read_to_string(file).unwrap();
//! # let _ = text;
//! ```

pub mod fixtures;
pub mod host;

use std::fmt::Debug;
use std::io::Write as _;
use std::path::{Path, PathBuf};

use proptest::test_runner::{
    Config as ProptestConfig, FailurePersistence, FileFailurePersistence, PersistedSeed,
};

/// The environment variable naming the third-party test data folder.
pub const DATA_ENV: &str = "SWARF_TEST_DATA";

/// The environment variable that turns a missing data file into a test failure.
pub const REQUIRE_ENV: &str = "SWARF_REQUIRE_TEST_DATA";

/// The data folder when [`DATA_ENV`] is not set, relative to the workspace root.
pub const DEFAULT_DATA: &str = "../shared/data";

/// The workspace root (the folder of the top `Cargo.toml`).
#[must_use]
pub fn workspace_root() -> PathBuf {
    let here = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    here.canonicalize().unwrap_or(here)
}

/// A folder of the system's temporary directory for one test, `swarf-{tag}-{process id}`,
/// created (with its parents) if it is not there; what it holds is left as it is. The folders
/// of the same tag that earlier test processes left (their process no longer runs) are removed
/// first, so repeated runs keep at most one run's scratch (some tests write meshes of a
/// hundred megabytes; a day of runs filled a disk).
///
/// # Panics
/// When it cannot be created.
#[must_use]
pub fn scratch_dir(tag: &str) -> PathBuf {
    let tmp = std::env::temp_dir();
    remove_stale(&tmp, &format!("swarf-{tag}-"));
    let dir = tmp.join(format!("swarf-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// [`scratch_dir`], emptied first.
///
/// # Panics
/// When it cannot be created.
#[must_use]
pub fn fresh_scratch_dir(tag: &str) -> PathBuf {
    let dir = scratch_dir(tag);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Removes the folders `{prefix}{pid}` of `tmp` whose process is gone (on Linux, where
/// `/proc` tells; elsewhere none) and that nothing has touched for an hour: a run in another
/// PID namespace sharing `/tmp` (a container) has processes this one cannot see, and its
/// folders are being written.
fn remove_stale(tmp: &Path, prefix: &str) {
    let proc = Path::new("/proc/self");
    if !proc.exists() {
        return;
    }
    let Ok(entries) = std::fs::read_dir(tmp) else {
        return;
    };
    let me = std::process::id();
    for e in entries.flatten() {
        let name = e.file_name();
        let Some(pid) = name
            .to_str()
            .and_then(|n| n.strip_prefix(prefix))
            .and_then(|p| p.parse::<u32>().ok())
        else {
            continue;
        };
        let idle = e
            .metadata()
            .and_then(|m| m.modified())
            .is_ok_and(|t| t.elapsed().is_ok_and(|d| d.as_secs() > 3600));
        if pid != me && idle && !Path::new(&format!("/proc/{pid}")).exists() {
            let _ = std::fs::remove_dir_all(e.path());
        }
    }
}

/// The configured data folder: `SWARF_TEST_DATA` (relative to the workspace root) or
/// [`DEFAULT_DATA`]; canonical when it exists. It may not exist.
#[must_use]
pub fn data_root() -> PathBuf {
    let rel = std::env::var_os(DATA_ENV).unwrap_or_else(|| DEFAULT_DATA.into());
    let dir = workspace_root().join(rel);
    dir.canonicalize().unwrap_or(dir)
}

/// The file or folder `rel` of the data folder; `None`, after printing why the calling test
/// skips, when it is not there.
///
/// # Panics
/// When it is missing and `SWARF_REQUIRE_TEST_DATA` is set.
#[must_use]
pub fn path(rel: &str) -> Option<PathBuf> {
    paths([rel]).map(|[p]| p)
}

/// The files or folders `rels` of the data folder, all of them, or `None` after one printed
/// line naming those missing.
///
/// # Panics
/// When one is missing and `SWARF_REQUIRE_TEST_DATA` is set.
#[must_use]
pub fn paths<const N: usize>(rels: [&str; N]) -> Option<[PathBuf; N]> {
    let root = data_root();
    match locate(&root, rels) {
        Ok(found) => Some(found),
        Err(missing) => {
            let line = skip_line(&test_name(), &missing, &root);
            if std::env::var_os(REQUIRE_ENV).is_some_and(|v| !v.is_empty() && v != "0") {
                panic!("{REQUIRE_ENV} is set and the test data is missing: {line}");
            }
            // One write, straight to the process's stderr: not captured by the test harness
            // and not interleaved with another test's line.
            let _ = std::io::stderr().lock().write_all(line.as_bytes());
            None
        }
    }
}

/// `root/rel` for every `rel`, or the ones that do not exist.
fn locate<const N: usize>(root: &Path, rels: [&str; N]) -> Result<[PathBuf; N], Vec<String>> {
    let found = rels.map(|r| root.join(r));
    let missing: Vec<String> = rels
        .iter()
        .zip(&found)
        .filter(|(_, p)| !p.exists())
        .map(|(r, _)| (*r).to_string())
        .collect();
    if missing.is_empty() {
        Ok(found)
    } else {
        Err(missing)
    }
}

/// The line printed for a skipped test.
fn skip_line(test: &str, missing: &[String], root: &Path) -> String {
    let why = if root.is_dir() {
        format!("not in {}", root.display())
    } else {
        format!("{} does not exist", root.display())
    };
    format!(
        "skipped: {test} needs {} from {DATA_ENV} ({why}; set {DATA_ENV} to the folder of \
         swarf's third-party test data)\n",
        missing.join(", ")
    )
}

/// `binary::test` for the running test: the test harness names each test's thread after it.
fn test_name() -> String {
    let binary = std::env::current_exe()
        .ok()
        .and_then(|p| p.file_stem().map(|s| s.to_string_lossy().into_owned()))
        .map(|s| match s.rsplit_once('-') {
            // Cargo appends `-<hash>` to test binaries.
            Some((name, hash)) if hash.chars().all(|c| c.is_ascii_hexdigit()) => name.to_string(),
            _ => s,
        })
        .unwrap_or_else(|| "test".into());
    match std::thread::current().name() {
        Some(t) if t != "main" => format!("{binary}::{t}"),
        _ => binary,
    }
}

/// Runs `f` in a pool of its own with `threads` threads (for tests that a result does not
/// depend on how many threads compute it).
pub fn on_threads<R: Send>(threads: usize, f: impl FnOnce() -> R + Send) -> R {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool")
        .install(f)
}

/// Proptest's default configuration with `cases` cases, reading the committed regression
/// files but never writing one: a failing case is printed on stderr with the line that keeps
/// it (see the crate documentation).
#[must_use]
pub fn proptest_config(cases: u32) -> ProptestConfig {
    ProptestConfig {
        cases,
        failure_persistence: Some(Box::new(ReadOnlyRegressions::default())),
        ..ProptestConfig::default()
    }
}

/// Failure persistence that reads the `.proptest-regressions` file beside a test (as proptest
/// does by default) and prints new failures instead of writing them.
#[derive(Debug, Clone, PartialEq)]
struct ReadOnlyRegressions(FileFailurePersistence);

impl Default for ReadOnlyRegressions {
    fn default() -> Self {
        Self(FileFailurePersistence::SourceParallel(
            "proptest-regressions",
        ))
    }
}

impl FailurePersistence for ReadOnlyRegressions {
    fn load_persisted_failures2(&self, source_file: Option<&'static str>) -> Vec<PersistedSeed> {
        self.0.load_persisted_failures2(source_file)
    }

    fn save_persisted_failure2(
        &mut self,
        source_file: Option<&'static str>,
        seed: PersistedSeed,
        shrunken_value: &dyn Debug,
    ) {
        let line = format!(
            "proptest failure (not saved: a test run writes nothing into the source tree): to \
             replay it first on every run, add the line\n    {seed} # shrinks to \
             {shrunken_value:?}\nto the .proptest-regressions file of {}\n",
            source_file.unwrap_or("the test")
        );
        let _ = std::io::stderr().lock().write_all(line.as_bytes());
    }

    fn box_clone(&self) -> Box<dyn FailurePersistence> {
        Box::new(self.clone())
    }

    fn eq(&self, other: &dyn FailurePersistence) -> bool {
        other
            .as_any()
            .downcast_ref::<Self>()
            .is_some_and(|o| o == self)
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn present_files_are_found_and_missing_ones_named() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let [a, b] = locate(root, ["Cargo.toml", "src/lib.rs"]).unwrap();
        assert!(a.is_file() && b.is_file());
        let missing = locate(root, ["Cargo.toml", "no/such.ngc", "nor.stl"]).unwrap_err();
        assert_eq!(missing, ["no/such.ngc", "nor.stl"]);
    }

    #[test]
    fn the_skip_line_names_the_test_the_file_and_the_variable() {
        let line = skip_line(
            "path_command::spiral",
            &["gcode/x.ngc".into()],
            Path::new("/nowhere/shared/data"),
        );
        assert!(line.starts_with("skipped: path_command::spiral needs gcode/x.ngc from SWARF_TEST_DATA (/nowhere/shared/data does not exist;"), "{line}");
        assert!(
            line.ends_with(")\n") && line.matches('\n').count() == 1,
            "{line}"
        );
    }

    #[test]
    fn the_test_name_is_the_binary_and_the_thread() {
        let name = test_name();
        assert!(
            name.starts_with("swarf_testdata::")
                && name.ends_with("the_test_name_is_the_binary_and_the_thread"),
            "{name}"
        );
    }

    #[test]
    fn failures_are_printed_not_written() {
        let dir = crate::scratch_dir("testdata");
        std::fs::create_dir_all(dir.join("src")).unwrap();
        std::fs::write(dir.join("src/lib.rs"), "").unwrap();
        let source: &'static str =
            Box::leak(dir.join("src/t.rs").display().to_string().into_boxed_str());
        let mut p = ReadOnlyRegressions::default();
        let seed = p.load_persisted_failures2(Some(source));
        assert!(seed.is_empty());
        let s: PersistedSeed =
            "cc 8fbcf589e93c8b7fea7e61755be31ac17554e4a0675fc4e3c9d3151c24c4e1c9"
                .parse()
                .unwrap();
        p.save_persisted_failure2(Some(source), s, &"x");
        let left: Vec<_> = walk(&dir);
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(left, [dir.join("src/lib.rs")], "nothing written");
    }

    fn walk(d: &Path) -> Vec<PathBuf> {
        let mut out = Vec::new();
        for e in std::fs::read_dir(d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                out.extend(walk(&p));
            } else {
                out.push(p);
            }
        }
        out
    }
}
