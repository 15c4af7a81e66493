//! Tool tables: numbered cutters read from swarf's TOML library, LinuxCNC `.tbl` files,
//! CAMotics `.camotics` projects and Heidenhain `TOOL.T` tables (one file per format).
//!
//! Every reader returns a [`ToolTable`] or a [`TableError`] carrying the file name, line and
//! column, what was found and what was expected. Readers never panic; assumptions they make
//! (a LinuxCNC table has no shape information, so its tools are taken as flat end mills) are
//! listed in [`ToolTable::warnings`].

mod camotics;
mod heidenhain;
mod linuxcnc;
mod toml_lib;

pub use camotics::parse_camotics;
pub use heidenhain::parse_heidenhain;
pub use linuxcnc::parse_linuxcnc;
pub use toml_lib::parse_toml_library;

use crate::cutter::Cutter;
use crate::error::TableError;
use std::collections::BTreeMap;
use std::path::Path;
use swarf_geom::Aabb;

/// Length unit of a file that does not state its own.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LengthUnit {
    /// Millimetres.
    Mm,
    /// Inches (25.4 mm).
    Inch,
}

impl LengthUnit {
    /// Millimetres per unit.
    pub fn to_mm(self) -> f64 {
        match self {
            LengthUnit::Mm => 1.0,
            LengthUnit::Inch => 25.4,
        }
    }
}

/// One tool of a table.
#[derive(Clone, Debug, PartialEq)]
pub struct ToolEntry {
    /// The cutter (mm).
    pub cutter: Cutter,
    /// Free text from the file (may be empty).
    pub description: String,
    /// The tool's name, where the table gives one (a Heidenhain `TOOL CALL "NAME"` or a
    /// Sinumerik `T="NAME"` finds the tool by it).
    pub name: Option<String>,
    /// The tool's offsets where the table gives them (a LinuxCNC `.tbl`'s `X Y Z A B C`
    /// words: X Y Z in mm, A B C in degrees; Z is the tool length): what G43 applies.
    pub offsets: Option<[f64; 6]>,
    /// The tool's pocket where the table gives it (a LinuxCNC `.tbl`'s `P`).
    pub pocket: Option<u32>,
}

/// Numbered tools, and the workpiece bounds when the file gives them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ToolTable {
    /// Tools by number.
    pub tools: BTreeMap<u32, ToolEntry>,
    /// Workpiece bounds in mm (CAMotics projects with `"automatic": false`).
    pub workpiece: Option<Aabb>,
    /// A CAMotics project with `"automatic": true`: the workpiece is made from the program's
    /// cutting moves (`swarf_job::automatic_workpiece`), grown by this margin, per cent of its
    /// size.
    pub automatic_workpiece: Option<f64>,
    /// Assumptions made while reading, one sentence each.
    pub warnings: Vec<String>,
    /// Tools the file defines but swarf cannot model (a CAMotics spheroid), by number: why,
    /// naming file, line and column. They are not in [`ToolTable::tools`]; a program that
    /// uses one is refused with this text, and the rest of the table serves.
    pub left_out: BTreeMap<u32, String>,
    /// Of the tools left out, those whose offsets and pocket the file still gives (a LinuxCNC
    /// `.tbl` line with no diameter or `D0`: a probe, or LinuxCNC's own `T99999 … Z+0.1`):
    /// what G43 and `#<_current_pocket>` read, as for the others. Their diameter is 0, as
    /// LinuxCNC takes it.
    pub left_out_offsets: BTreeMap<u32, (Option<[f64; 6]>, Option<u32>)>,
}

impl ToolTable {
    /// Reads a table, choosing the format by extension: `.toml`, `.tbl` (LinuxCNC, in
    /// `tbl_unit`), `.camotics`, `.t` (Heidenhain `TOOL.T`).
    pub fn read(path: &Path, tbl_unit: LengthUnit) -> Result<ToolTable, TableError> {
        let file = path.display().to_string();
        // (Bytes that are not UTF-8 — a Latin-1 description — are replaced, one character
        // each: the columns of a fixed-width table stay where they are.)
        let bytes = std::fs::read(path).map_err(|e| TableError::Io {
            file: file.clone(),
            message: e.to_string(),
        })?;
        let text = String::from_utf8_lossy(&bytes).into_owned();
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .as_deref()
        {
            Some("toml") => parse_toml_library(&text, &file),
            Some("tbl") => parse_linuxcnc(&text, &file, tbl_unit),
            Some("camotics") => parse_camotics(&text, &file),
            Some("t") => parse_heidenhain(&text, &file),
            other => Err(TableError::Parse {
                file,
                line: 0,
                column: 0,
                found: format!("extension {:?}", other.unwrap_or("")),
                expected: "a .toml, .tbl, .camotics or .t (Heidenhain TOOL.T) tool table".into(),
            }),
        }
    }
}

pub(crate) use swarf_geom::text::line_col;
