//! Readers (and the JSON writer) of compound surfaces: swarf JSON, STEP AP203/AP214, IGES.
//!
//! Every reader converts lengths to millimetres, never panics on malformed input, and reports
//! errors with the line and column (or IGES record) where they were found.

mod failure;
pub mod iges;
pub mod json;
pub mod step;

pub use failure::{IgesBoundary, TrimFailure};

use std::fmt;
use std::path::{Path, PathBuf};

use crate::compound::{CompoundSurface, ReadNote};
use crate::surface::NurbsError;

/// A surface file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// swarf's JSON.
    Json,
    /// STEP (ISO 10303-21).
    Step,
    /// IGES 5.3.
    Iges,
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Format::Json => "JSON",
            Format::Step => "STEP",
            Format::Iges => "IGES",
        })
    }
}

impl Format {
    /// The format a file name's extension names (`.json`; `.step`, `.stp`, `.p21`; `.igs`,
    /// `.iges`), case-insensitive.
    pub fn from_path(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "json" => Some(Format::Json),
            "step" | "stp" | "p21" => Some(Format::Step),
            "igs" | "iges" => Some(Format::Iges),
            _ => None,
        }
    }
}

/// Why a surface file could not be read.
///
/// A cause that is part of a message is not also its [`std::error::Error::source`] (fields
/// named `reason`, not `source`): the CLI prints an error's whole chain, and would say it twice.
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    /// The file could not be read. (The errors of a file leave it to the caller to name it,
    /// once: a parser's do not know it.)
    #[error("cannot read")]
    Io {
        /// The path.
        path: PathBuf,
        /// The OS error.
        #[source]
        source: std::io::Error,
    },
    /// The extension names no supported format.
    #[error("unknown surface file type (expected .json, .step, .stp, .p21, .igs or .iges)")]
    UnknownFormat {
        /// The path.
        path: PathBuf,
    },
    /// Malformed text: what was found where, and what was expected.
    #[error("{format} line {line}, column {column}: {message}")]
    Syntax {
        /// The format.
        format: Format,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// Found / expected.
        message: String,
    },
    /// Well-formed text that does not make a valid surface.
    #[error("{format} line {line}: {entity}: {reason}")]
    Surface {
        /// The format.
        format: Format,
        /// 1-based line where the entity starts.
        line: usize,
        /// The entity (`#55`, `D3`, `patch "floor"`).
        entity: String,
        /// What is wrong with it. Part of the message and not a separate source: the CLI
        /// prints an error's chain and would say it twice.
        reason: NurbsError,
    },
    /// Well-formed text with an inconsistent or missing entity.
    #[error("{format} line {line}: {entity}: {message}")]
    Entity {
        /// The format.
        format: Format,
        /// 1-based line where the entity starts.
        line: usize,
        /// The entity.
        entity: String,
        /// What is wrong.
        message: String,
    },
    /// The file holds no surface this crate reads.
    #[error("{format}: no supported surface in the file{detail}")]
    Empty {
        /// The format.
        format: Format,
        /// What was skipped, if anything (starts with "; ").
        detail: String,
    },
}

/// Read a compound surface from a file, choosing the reader by extension. Patches record the
/// path in their [`crate::PatchSource`]. The errors do not name the file (the parsers' cannot
/// know it): the caller names it, once.
pub fn read_file(path: &Path) -> Result<CompoundSurface, ReadError> {
    let format = Format::from_path(path).ok_or_else(|| ReadError::UnknownFormat {
        path: path.to_path_buf(),
    })?;
    let bytes = std::fs::read(path).map_err(|source| ReadError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    // IGES columns are bytes: decoded as UTF-8 first, an accent in a Latin-1 Start section
    // would no longer be one column.
    let mut s = match format {
        Format::Iges => iges::parse_bytes(&bytes)?,
        _ => parse(format, &String::from_utf8_lossy(&bytes))?,
    };
    let name = path.display().to_string();
    for p in &mut s.patches {
        p.source.file = Some(name.clone());
    }
    Ok(s)
}

/// Parse text in the given format.
///
/// ```
/// use swarf_surface::io::{parse, Format};
/// use swarf_surface::{ParametricSurface, ReadNote, Surface};
/// // A STEP file with one sphere of radius 5 and no units: millimetres are assumed.
/// let step = "ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n\
///     #1=CARTESIAN_POINT('',(0.,0.,0.));\n#2=DIRECTION('',(0.,0.,1.));\n\
///     #3=DIRECTION('',(1.,0.,0.));\n#4=AXIS2_PLACEMENT_3D('',#1,#2,#3);\n\
///     #5=SPHERICAL_SURFACE('ball',#4,5.);\nENDSEC;\nEND-ISO-10303-21;\n";
/// let part = parse(Format::Step, step)?;
/// assert_eq!(part.patches.len(), 1);
/// assert!(matches!(part.patches[0].surface, Surface::Sphere(_)));
/// assert!((part.patches[0].surface.point(0.0, 0.0).length() - 5.0).abs() < 1e-12);
/// assert!(part.notes.contains(&ReadNote::UnitsAssumed));
/// // Malformed text names where it went wrong.
/// let e = parse(Format::Step, "ISO-10303-21;\nDATA;\n#1=A(1,2;\nENDSEC;").unwrap_err();
/// assert!(e.to_string().starts_with("STEP line 3, column 9:"), "{e}");
/// # Ok::<(), swarf_surface::io::ReadError>(())
/// ```
pub fn parse(format: Format, text: &str) -> Result<CompoundSurface, ReadError> {
    match format {
        Format::Json => json::parse(text),
        Format::Step => step::parse(text),
        Format::Iges => iges::parse(text),
    }
}

/// How far (mm) a trimming curve's sample may lie off its surface and still bound it: 1e-4 of
/// the surface's size plus 0.01 mm (CAD edges commonly lie 1e-3 to 1e-2 mm off their faces),
/// or the accuracy the file declares (STEP's `UNCERTAINTY_MEASURE_WITH_UNIT`, IGES's minimum
/// resolution) when that is coarser — at most a hundredth of the size.
pub(crate) fn on_surface_tolerance(size: f64, declared: f64) -> f64 {
    let own = 1e-4 * size + 1e-2;
    if declared.is_finite() && declared > own {
        declared.min(1e-2 * size).max(own)
    } else {
        own
    }
}

/// `; skipped: …` listing what a reader skipped, for [`ReadError::Empty`].
pub(crate) fn skipped_detail(skipped: &[ReadNote]) -> String {
    let list: Vec<String> = skipped.iter().map(ToString::to_string).collect();
    format!("; skipped: {}", list.join("; "))
}

pub(crate) use swarf_geom::text::line_col;

/// A point in a patch's parameters, `[u, v]`.
type Uv = [f64; 2];

/// Most points of one trim's loops (a patch or face); a trim that needs more is not honoured.
const MAX_TRIM_POINTS: usize = 200_000;
/// Halvings of one initial step when sampling a trimming curve.
const MAX_HALVINGS: u32 = 12;
/// Grid searches (for a Newton seed on a B-spline surface) one trimmed patch or face may make.
const MAX_GRID_SEARCHES: usize = 256;
