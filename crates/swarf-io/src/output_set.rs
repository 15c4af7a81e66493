//! A set of output files written together or not at all, within a size limit stated before
//! anything is written.
//!
//! A command that writes several files (a machined part as STL and glb, a CSV, a summary) must
//! not leave half a set behind when the third file fails — nor fill a disk with a 2 GB STL
//! nobody asked for. [`OutputSet`]:
//! 1. [`OutputSet::check_sizes`]: the caller states each file's estimated size before writing;
//!    a total over the limit is refused with [`IoError::TooLarge`], naming every file's size;
//! 2. [`OutputSet::write`]: each file is written to a temporary beside its target
//!    (`.<name>.swarf-tmp-…`), flushed and synced ([`OutputSet::write_all`]: several side by
//!    side, one thread each);
//! 3. [`OutputSet::commit`]: only once every file was written are they all renamed into place.
//!    A set dropped before its commit (an error, a panic) removes its temporaries and leaves
//!    every target as it was.
//!
//! ```
//! use std::io::Write;
//! use swarf_io::OutputSet;
//! let dir = std::env::temp_dir().join(format!("swarf-io-set-doc-{}", std::process::id()));
//! let mut set = OutputSet::new(&dir, 1 << 20).unwrap();
//! set.check_sizes(&[("a.txt", 2), ("b.txt", 2)]).unwrap();
//! set.write("a.txt", |w| w.write_all(b"a\n")).unwrap();
//! assert!(!dir.join("a.txt").exists(), "nothing appears before the commit");
//! set.write("b.txt", |w| w.write_all(b"b\n")).unwrap();
//! set.commit().unwrap();
//! assert_eq!(std::fs::read_to_string(dir.join("b.txt")).unwrap(), "b\n");
//! assert!(OutputSet::new(&dir, 3).unwrap().check_sizes(&[("a.txt", 2), ("b.txt", 2)]).is_err());
//! std::fs::remove_dir_all(&dir).unwrap();
//! ```

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// Output sets renaming their files into place right now, in this process.
static COMMITTING: AtomicUsize = AtomicUsize::new(0);

/// True while some output set of this process renames its files into place: a process that
/// ended then (a Ctrl-C handler's exit) could leave old and new files mixed, or old ones moved
/// aside, so a handler waits for the commit instead.
pub fn committing() -> bool {
    COMMITTING.load(Ordering::SeqCst) > 0
}

/// Counts a commit in progress for its lifetime.
struct Committing;

impl Committing {
    fn begin() -> Self {
        COMMITTING.fetch_add(1, Ordering::SeqCst);
        Committing
    }
}

impl Drop for Committing {
    fn drop(&mut self) {
        COMMITTING.fetch_sub(1, Ordering::SeqCst);
    }
}

use crate::atomic::{temp_path, write_synced};
use crate::error::IoError;

/// Default limit on the bytes one set of outputs may take: 2 GB.
pub const DEFAULT_MAX_OUTPUT_BYTES: u64 = 2_000_000_000;

/// Bytes of a binary STL of `triangles` triangles (80-byte header, count, 50 bytes each).
pub fn stl_size(triangles: u64) -> u64 {
    84 + 50 * triangles
}

/// Files written together; see the [module documentation](self).
#[derive(Debug)]
pub struct OutputSet {
    dir: PathBuf,
    max_bytes: u64,
    /// (temporary, target) of the files written so far.
    staged: Vec<(PathBuf, PathBuf)>,
    /// Subfolders and the name prefixes of the files in them that are this command's (see
    /// [`OutputSet::owns_files`]).
    owned: Vec<(PathBuf, &'static [&'static str])>,
    /// Files of the command's own ([`OutputSet::owns_file`]).
    owned_files: Vec<PathBuf>,
    /// Set when the set is to stop (see [`OutputSet::stop_when`]).
    stop: Option<&'static AtomicBool>,
}

impl OutputSet {
    /// A set of files in `dir` (created at the first write) of at most `max_bytes` in all.
    ///
    /// # Errors
    /// [`IoError::Io`] when `dir` exists and is not a folder.
    pub fn new(dir: &Path, max_bytes: u64) -> Result<Self, IoError> {
        if dir.exists() && !dir.is_dir() {
            return Err(IoError::io(
                dir,
                std::io::Error::other("exists and is not a folder"),
            ));
        }
        Ok(Self {
            dir: dir.to_path_buf(),
            max_bytes,
            staged: Vec::new(),
            owned: Vec::new(),
            owned_files: Vec::new(),
            stop: None,
        })
    }

    /// From now on, once `flag` is set (by a Ctrl-C handler), the next file the set starts, or
    /// its commit, fails with [`IoError::Stopped`] and the set leaves nothing behind: a long
    /// write of several meshes stops between files rather than running to its end.
    pub fn stop_when(&mut self, flag: &'static AtomicBool) {
        self.stop = Some(flag);
    }

    fn check_stop(&self) -> Result<(), IoError> {
        match self.stop {
            Some(f) if f.load(Ordering::SeqCst) => Err(IoError::Stopped {
                dir: self.dir.clone(),
            }),
            _ => Ok(()),
        }
    }

    /// Declares the PNG files of subfolder `rel` (of the set's folder) whose names start with
    /// one of `prefixes` the command's own: at the commit, those the set did not write are
    /// removed, so that a folder of plots reused from an earlier run holds this run's plots
    /// only (a map of a location this run did not draw would otherwise sit beside them and
    /// end up in reports). Every other file — the user's own, another run's temporaries — is
    /// left.
    pub fn owns_files(&mut self, rel: &str, prefixes: &'static [&'static str]) {
        self.owned.push((self.dir.join(rel), prefixes));
    }

    /// Declares file `rel` (of the set's folder, any kind) the command's own: at the commit it
    /// is removed if the set did not write it (a result this run does not make, such as
    /// `standard.json` without `--standard`, would otherwise outlive the run that made it).
    pub fn owns_file(&mut self, rel: &str) {
        self.owned_files.push(self.dir.join(rel));
    }

    /// The folder the files go to.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Checks the estimated sizes (bytes) of the files about to be written against the limit.
    ///
    /// # Errors
    /// [`IoError::TooLarge`] naming each file's size when the total exceeds the limit.
    pub fn check_sizes(&self, files: &[(&str, u64)]) -> Result<(), IoError> {
        let total = files.iter().fold(0u64, |t, (_, b)| t.saturating_add(*b));
        if total <= self.max_bytes {
            return Ok(());
        }
        let list = files
            .iter()
            .map(|(name, b)| format!("{name} {}", human_bytes(*b)))
            .collect::<Vec<_>>()
            .join(", ");
        Err(IoError::TooLarge {
            dir: self.dir.clone(),
            what: format!("{} ({list})", human_bytes(total)),
            limit: human_bytes(self.max_bytes),
        })
    }

    /// Writes file `name` of the set to its temporary (flushed and synced); it appears under its
    /// name at [`OutputSet::commit`].
    ///
    /// # Errors
    /// [`IoError::Io`] naming the file.
    pub fn write<F>(&mut self, name: &str, body: F) -> Result<(), IoError>
    where
        F: FnOnce(&mut BufWriter<File>) -> std::io::Result<()>,
    {
        let (file, target) = self.stage(name)?;
        write_synced(file, &target, body)
    }

    /// Writes the files `files` of the set (name, body) side by side, each on its own thread
    /// (large meshes are encoded and synced at once), as [`OutputSet::write`] writes one.
    ///
    /// # Errors
    /// As [`OutputSet::write`]: the first file's error in `files` order.
    pub fn write_all(&mut self, files: Vec<(&str, FileBody<'_>)>) -> Result<(), IoError> {
        let mut staged = Vec::with_capacity(files.len());
        for (name, body) in files {
            let (file, target) = self.stage(name)?;
            staged.push((file, target, body));
        }
        let results: Vec<Result<(), IoError>> = std::thread::scope(|scope| {
            let running: Vec<_> = staged
                .into_iter()
                .map(|(file, target, body)| scope.spawn(move || write_synced(file, &target, body)))
                .collect();
            running
                .into_iter()
                .map(|h| match h.join() {
                    Ok(r) => r,
                    Err(panic) => std::panic::resume_unwind(panic),
                })
                .collect()
        });
        results.into_iter().collect()
    }

    /// Registers the temporary of file `name` (so that a failure from here on removes it) and
    /// creates it; returns it and the target path.
    fn stage(&mut self, name: &str) -> Result<(File, PathBuf), IoError> {
        self.check_stop()?;
        let target = self.dir.join(name);
        if target.is_dir() {
            return Err(IoError::io(
                &target,
                std::io::Error::other("a folder has the output's name"),
            ));
        }
        if let Some(parent) = target.parent() {
            // (A file in the way of the output's folder: said so, not "File exists".)
            if let Some(file) = parent.ancestors().find(|a| a.is_file()) {
                return Err(IoError::io(
                    file,
                    std::io::Error::other("a file has the name of the output's folder"),
                ));
            }
            std::fs::create_dir_all(parent).map_err(|e| IoError::io(parent, e))?;
        }
        let tmp = temp_path(&target);
        self.staged.push((tmp.clone(), target.clone()));
        let file = File::create(&tmp).map_err(|e| IoError::io(&target, e))?;
        Ok((file, target))
    }

    /// Writes `bytes` as file `name` of the set (see [`OutputSet::write`]).
    ///
    /// # Errors
    /// As [`OutputSet::write`].
    pub fn write_bytes(&mut self, name: &str, bytes: &[u8]) -> Result<(), IoError> {
        self.write(name, |w| w.write_all(bytes))
    }

    /// Renames every file written into place. Files the targets replace are first moved aside
    /// and put back if a rename fails, so that either every target is new or none is.
    ///
    /// # Errors
    /// [`IoError::Io`] for the first rename that fails; [`IoError::Stopped`] when asked to
    /// stop (nothing renamed).
    pub fn commit(mut self) -> Result<(), IoError> {
        let _committing = Committing::begin();
        self.check_stop()?;
        let staged = std::mem::take(&mut self.staged);
        // Old files moved aside: (backup, target).
        let mut aside: Vec<(PathBuf, PathBuf)> = Vec::new();
        // Targets renamed into place so far.
        let mut placed: Vec<PathBuf> = Vec::new();
        let mut result = Ok(());
        for (_, target) in &staged {
            if target.is_file() {
                let backup = temp_path(target);
                match std::fs::rename(target, &backup) {
                    Ok(()) => aside.push((backup, target.clone())),
                    Err(e) => {
                        result = Err(IoError::io(target, e));
                        break;
                    }
                }
            }
        }
        if result.is_ok() {
            for (tmp, target) in &staged {
                match std::fs::rename(tmp, target) {
                    Ok(()) => placed.push(target.clone()),
                    Err(e) => {
                        result = Err(IoError::io(target, e));
                        break;
                    }
                }
            }
        }
        if result.is_err() {
            for target in &placed {
                let _ = std::fs::remove_file(target);
            }
            for (tmp, _) in &staged {
                let _ = std::fs::remove_file(tmp);
            }
            for (backup, target) in &aside {
                let _ = std::fs::rename(backup, target);
            }
        } else {
            for (backup, _) in &aside {
                let _ = std::fs::remove_file(backup);
            }
            for path in &self.owned_files {
                if path.is_file() && !placed.contains(path) {
                    let _ = std::fs::remove_file(path);
                }
            }
            for (folder, prefixes) in &self.owned {
                let Ok(entries) = std::fs::read_dir(folder) else {
                    continue;
                };
                for path in entries.flatten().map(|e| e.path()) {
                    let name = path
                        .file_name()
                        .map(|n| n.to_string_lossy().into_owned())
                        .unwrap_or_default();
                    let ours =
                        name.ends_with(".png") && prefixes.iter().any(|p| name.starts_with(p));
                    if ours && path.is_file() && !placed.contains(&path) {
                        let _ = std::fs::remove_file(&path);
                    }
                }
            }
        }
        result
    }
}

/// What writes one file of a set, for [`OutputSet::write_all`].
pub type FileBody<'a> = Box<dyn FnOnce(&mut BufWriter<File>) -> std::io::Result<()> + Send + 'a>;

impl Drop for OutputSet {
    fn drop(&mut self) {
        for (tmp, _) in &self.staged {
            let _ = std::fs::remove_file(tmp);
        }
    }
}

/// Bytes in words: `812 B`, `3.4 MB`, `1.80 GB` (decimal units).
pub fn human_bytes(b: u64) -> String {
    let f = b as f64;
    if f >= 1e9 {
        format!("{:.2} GB", f / 1e9)
    } else if f >= 1e6 {
        format!("{:.1} MB", f / 1e6)
    } else if f >= 1e3 {
        format!("{:.1} kB", f / 1e3)
    } else {
        format!("{b} B")
    }
}
