//! Atomic file output: every writer of this crate writes a temporary file beside the target and
//! renames it over the target only once everything is written and flushed, so a reader (or a
//! user pressing Ctrl-C) never sees a half-written file. A failed write removes its temporary.

use crate::error::IoError;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

static COUNTER: AtomicU64 = AtomicU64::new(0);

/// Prefix of the temporary files (`.<file name>.swarf-tmp-<pid>-<n>`), so that stray ones
/// (after a crash) are recognisable.
pub const TEMP_MARKER: &str = ".swarf-tmp-";

/// Most bytes of the file's name a temporary's name repeats.
const TEMP_NAME_PART: usize = 200;

/// A fresh temporary path beside `path`.
pub(crate) fn temp_path(path: &Path) -> PathBuf {
    let mut name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "out".to_string());
    // Short enough that the temporary's name fits where the file's own does (255 bytes on
    // most file systems): a 240-byte name was refused for its temporary's.
    if name.len() > TEMP_NAME_PART {
        let mut end = TEMP_NAME_PART;
        while !name.is_char_boundary(end) {
            end -= 1;
        }
        name.truncate(end);
    }
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let tmp = format!(".{name}{TEMP_MARKER}{}-{n}", std::process::id());
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir.join(tmp),
        _ => PathBuf::from(tmp),
    }
}

/// Whether [`write_atomic`] could write `path` now: a temporary beside it is made and removed
/// (a command that writes a file last checks before its work, not after).
///
/// # Errors
/// The folder does not exist or takes no new file, named by `path`.
pub fn check_writable(path: &Path) -> Result<(), IoError> {
    let tmp = temp_path(path);
    File::create(&tmp).map_err(|e| IoError::io(path, e))?;
    let _ = std::fs::remove_file(&tmp);
    // The name itself (too long for the file system?), where no file holds it yet: one that
    // does is renamed over, which the folder allows.
    if std::fs::symlink_metadata(path).is_err() {
        File::create_new(path).map_err(|e| IoError::io(path, e))?;
        let _ = std::fs::remove_file(path);
    }
    Ok(())
}

/// Writes `path` atomically: `body` writes into a buffered temporary file in the same folder,
/// which is flushed, synced and renamed over `path`. On any error the temporary is removed
/// and `path` is left as it was.
pub fn write_atomic<F>(path: &Path, body: F) -> Result<(), IoError>
where
    F: FnOnce(&mut BufWriter<File>) -> std::io::Result<()>,
{
    let tmp = temp_path(path);
    let result = (|| {
        // (Named by the file asked for: the temporary's name means nothing to the user.)
        let file = File::create(&tmp).map_err(|e| IoError::io(path, e))?;
        write_synced(file, path, body)?;
        std::fs::rename(&tmp, path).map_err(|e| IoError::io(path, e))
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// Writes `body` into `file` (the temporary of `target`, which errors name) through a buffer,
/// then flushes and syncs it.
pub(crate) fn write_synced<F>(file: File, target: &Path, body: F) -> Result<(), IoError>
where
    F: FnOnce(&mut BufWriter<File>) -> std::io::Result<()>,
{
    let mut w = BufWriter::new(file);
    body(&mut w).map_err(|e| IoError::io(target, e))?;
    w.flush().map_err(|e| IoError::io(target, e))?;
    let file = w
        .into_inner()
        .map_err(|e| IoError::io(target, e.into_error()))?;
    file.sync_all().map_err(|e| IoError::io(target, e))
}
