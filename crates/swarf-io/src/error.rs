//! The error type of every reader and writer in this crate.

use std::path::PathBuf;

/// What went wrong while reading or writing a mesh file.
#[derive(Debug, thiserror::Error)]
pub enum IoError {
    /// The operating system refused (open, write, rename…). The reason is part of the message
    /// and not a separate source (the CLI prints an error's chain, and would say it twice):
    /// match on `reason` (e.g. its kind) rather than walking `source()`.
    #[error("{}: {reason}", .path.display())]
    Io {
        /// The file concerned.
        path: PathBuf,
        /// The underlying error.
        reason: std::io::Error,
    },
    /// The file's contents are not what the format requires.
    #[error("{path}: {what} (expected {expected})")]
    Malformed {
        /// The file concerned.
        path: PathBuf,
        /// What was found, with its position (byte offset or line).
        what: String,
        /// What the format requires there.
        expected: String,
    },
    /// The mesh cannot be written as it is (an index out of range, a colour count that does not
    /// match the vertices, too many vertices for the format…).
    #[error("invalid mesh: {0}")]
    InvalidMesh(String),
    /// A set of outputs would exceed its size limit (nothing was written).
    #[error(
        "{dir}: the outputs would take {what}, more than the limit of {limit}; nothing was written"
    )]
    TooLarge {
        /// The folder of the outputs.
        dir: PathBuf,
        /// The estimated total, with each file's part.
        what: String,
        /// The limit.
        limit: String,
    },
    /// The set was asked to stop (Ctrl-C) before its files were in place (nothing was written).
    #[error("{}: stopped before the outputs were in place; nothing was written", .dir.display())]
    Stopped {
        /// The folder of the outputs.
        dir: PathBuf,
    },
    /// JSON (de)serialisation of a glTF document failed.
    #[error("{}: glTF JSON: {reason}", .path.display())]
    Json {
        /// The file concerned.
        path: PathBuf,
        /// The underlying error (in the message, as for [`IoError::Io`]).
        reason: serde_json::Error,
    },
}

impl IoError {
    pub(crate) fn io(path: &std::path::Path, source: std::io::Error) -> Self {
        IoError::Io {
            path: path.to_path_buf(),
            reason: source,
        }
    }

    pub(crate) fn malformed(
        path: &std::path::Path,
        what: impl Into<String>,
        expected: impl Into<String>,
    ) -> Self {
        IoError::Malformed {
            path: path.to_path_buf(),
            what: what.into(),
            expected: expected.into(),
        }
    }
}
