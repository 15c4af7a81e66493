//! A LinuxCNC machine configuration (its INI file): the settings in it that change what a
//! program does.
//!
//! LinuxCNC reads a program with the machine's INI in hand; the same program can move
//! differently on two machines. What swarf takes from it ([`GcodeOptions::with_linuxcnc_ini`]):
//!
//! | section, name | effect |
//! |---|---|
//! | `[RS274NGC] SUBROUTINE_PATH` | folders (`:`-separated, relative to the INI's) searched for `o<name> call` files |
//! | `[RS274NGC] RS274NGC_STARTUP_CODE` | G-code run before the program, as LinuxCNC's task runs it at start-up |
//! | `[RS274NGC] INI_VARS` (default 1) | `#<_ini[section]name>` reads the INI's numbers, read-only |
//! | `[RS274NGC] DISABLE_FANUC_STYLE_SUB` | `M98`, `M99` and bare `O123` labels are errors |
//! | `[RS274NGC] CENTER_ARC_RADIUS_TOLERANCE_INCH`, `_MM` | the arc end-radius tolerances |
//! | `[EMCIO] TOOL_CHANGE_QUILL_UP` | `M6` first rapids Z up to machine Z0 |
//! | `[EMCIO] TOOL_CHANGE_AT_G30` | `M6` first rapids to the G30 position (#5181–#5186) |
//! | `[EMCIO] TOOL_CHANGE_WITH_SPINDLE_ON` | `M6` leaves the spindle turning (by default it stops it) |
//! | `[TRAJ] LINEAR_UNITS` | the machine's units: a program's units before its G20/G21, and the offset parameters' |
//! | `[EMCIO] TOOL_TABLE` | the tool table (read by `swarf-job` when no tools are given) |
//!
//! The file is read as LinuxCNC's `IniFile` reads it: `[SECTION]` headers, `NAME = VALUE`
//! lines (the first of a repeated name counts), `#` and `;` comment lines, a `\` at a line's
//! end continuing the value; names and sections as written (LinuxCNC's are upper case, and
//! `#<_ini[…]…>` looks them up in upper case).

use std::path::{Path, PathBuf};

use super::{ArcTolerance, GcodeOptions};
use crate::{PathError, PathErrorKind, SourcePos, Units};

/// One `NAME = VALUE` of the file.
#[derive(Clone, Debug, PartialEq)]
struct Entry {
    section: String,
    name: String,
    value: String,
    line: u32,
}

/// A LinuxCNC INI file, parsed (see the module's documentation for what swarf uses).
#[derive(Clone, Debug, PartialEq)]
pub struct LinuxCncIni {
    /// The file, as given: error messages name it, relative paths in it start from its folder.
    pub path: PathBuf,
    entries: Vec<Entry>,
}

/// What `M6` does besides changing the tool, from `[EMCIO]`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ToolChangeMoves {
    /// `TOOL_CHANGE_QUILL_UP`: rapid Z to machine Z0 first.
    pub quill_up: bool,
    /// `TOOL_CHANGE_AT_G30`: rapid to the G30 position first.
    pub at_g30: bool,
    /// `TOOL_CHANGE_WITH_SPINDLE_ON`: the spindle keeps turning (else `M6` stops it).
    pub with_spindle_on: bool,
}

impl LinuxCncIni {
    /// Reads and parses the INI file at `path`.
    ///
    /// # Errors
    /// [`PathErrorKind::Io`] when it cannot be read.
    pub fn read(path: &Path) -> Result<Self, PathError> {
        let text = std::fs::read(path).map_err(|e| {
            PathError::new(
                SourcePos {
                    file: path.display().to_string(),
                    line: 0,
                    column: 0,
                },
                PathErrorKind::Io,
                format!("cannot read the INI file: {e}"),
                "",
                "",
            )
        })?;
        Ok(Self::parse(&crate::load::decode_text(text), path))
    }

    /// Parses INI text; `path` is where it came from. Lines that are neither a section, a
    /// `NAME = VALUE` nor a comment are ignored, as LinuxCNC ignores them.
    pub fn parse(text: &str, path: &Path) -> Self {
        let mut entries = Vec::new();
        let mut section = String::new();
        let mut lines = text.lines().enumerate();
        while let Some((i, line)) = lines.next() {
            let t = line.trim().trim_start_matches('\u{feff}');
            if t.is_empty() || t.starts_with('#') || t.starts_with(';') {
                continue;
            }
            if let Some(rest) = t.strip_prefix('[') {
                if let Some(end) = rest.find(']') {
                    section = rest[..end].trim().to_string();
                }
                continue;
            }
            let Some((name, value)) = t.split_once('=') else {
                continue;
            };
            let mut value = value.trim().to_string();
            while let Some(v) = value.strip_suffix('\\') {
                value = v.trim_end().to_string();
                match lines.next() {
                    Some((_, more)) => {
                        value.push(' ');
                        value.push_str(more.trim());
                    }
                    None => break,
                }
            }
            entries.push(Entry {
                section: section.clone(),
                name: name.trim().to_string(),
                value,
                line: i as u32 + 1,
            });
        }
        Self {
            path: path.to_path_buf(),
            entries,
        }
    }

    fn entry(&self, section: &str, name: &str) -> Option<&Entry> {
        self.entries
            .iter()
            .find(|e| e.section == section && e.name == name)
    }

    /// The value of `name` in `[section]` (the first, when repeated).
    pub fn get(&self, section: &str, name: &str) -> Option<&str> {
        self.entry(section, name).map(|e| e.value.as_str())
    }

    /// The number `name` in `[section]` holds; `None` when absent or not a number.
    pub fn number(&self, section: &str, name: &str) -> Option<f64> {
        self.get(section, name)?
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
    }

    /// The value `#<_ini[section]name>` reads (`key` as the program wrote it, lower case: it is
    /// looked up in upper case, as LinuxCNC does); `None` when the INI has no such number.
    pub fn parameter(&self, key: &str) -> Option<f64> {
        let rest = key.get(5..)?;
        let (section, name) = rest.split_once(']')?;
        if !key[..5].eq_ignore_ascii_case("_ini[") || name.is_empty() {
            return None;
        }
        self.number(&section.to_ascii_uppercase(), &name.to_ascii_uppercase())
    }

    /// Whether `#<_ini[…]>` reads the INI (`[RS274NGC] INI_VARS`, on unless set off).
    pub fn ini_vars(&self) -> bool {
        self.flag("RS274NGC", "INI_VARS")
            .ok()
            .flatten()
            .unwrap_or(true)
    }

    /// A yes/no setting (`1`/`0`, `TRUE`/`FALSE`, `YES`/`NO`, `ON`/`OFF`); `Ok(None)` when absent.
    fn flag(&self, section: &str, name: &str) -> Result<Option<bool>, PathError> {
        let Some(e) = self.entry(section, name) else {
            return Ok(None);
        };
        match e.value.to_ascii_uppercase().as_str() {
            "1" | "TRUE" | "YES" | "ON" => Ok(Some(true)),
            "0" | "FALSE" | "NO" | "OFF" => Ok(Some(false)),
            _ => Err(self.bad(e, "1 or 0 (TRUE/FALSE, YES/NO, ON/OFF)")),
        }
    }

    fn positive(&self, section: &str, name: &str) -> Result<Option<f64>, PathError> {
        let Some(e) = self.entry(section, name) else {
            return Ok(None);
        };
        match e.value.parse::<f64>() {
            Ok(v) if v.is_finite() && v > 0.0 => Ok(Some(v)),
            _ => Err(self.bad(e, "a positive number")),
        }
    }

    fn bad(&self, e: &Entry, expected: &str) -> PathError {
        PathError::new(
            SourcePos {
                file: self.path.display().to_string(),
                line: e.line,
                column: 1,
            },
            PathErrorKind::Semantic,
            format!("bad [{}] {} in the INI file", e.section, e.name),
            e.value.clone(),
            expected,
        )
    }

    /// The machine's linear units (`[TRAJ] LINEAR_UNITS`: `mm`, `metric`, `inch`, `in`,
    /// `imperial`, or the units' length in mm, 1 or 25.4); `Ok(None)` when not stated.
    ///
    /// # Errors
    /// Another value, at its line.
    pub fn linear_units(&self) -> Result<Option<Units>, PathError> {
        let Some(e) = self.entry("TRAJ", "LINEAR_UNITS") else {
            return Ok(None);
        };
        let v = e.value.to_ascii_lowercase();
        match v.as_str() {
            "mm" | "metric" | "millimeter" | "millimetre" => Ok(Some(Units::Mm)),
            "inch" | "in" | "imperial" => Ok(Some(Units::Inch)),
            _ => match v.parse::<f64>() {
                Ok(x) if (x - 1.0).abs() < 1e-9 => Ok(Some(Units::Mm)),
                Ok(x) if (x - 25.4).abs() < 1e-9 => Ok(Some(Units::Inch)),
                _ => Err(self.bad(e, "mm or inch")),
            },
        }
    }

    /// What `M6` does besides changing the tool.
    ///
    /// # Errors
    /// A setting that is not yes or no, at its line.
    pub fn tool_change(&self) -> Result<ToolChangeMoves, PathError> {
        Ok(ToolChangeMoves {
            quill_up: self.flag("EMCIO", "TOOL_CHANGE_QUILL_UP")?.unwrap_or(false),
            at_g30: self.flag("EMCIO", "TOOL_CHANGE_AT_G30")?.unwrap_or(false),
            with_spindle_on: self
                .flag("EMCIO", "TOOL_CHANGE_WITH_SPINDLE_ON")?
                .unwrap_or(false),
        })
    }

    /// Whether Fanuc-style subprograms are refused (`[RS274NGC] DISABLE_FANUC_STYLE_SUB`).
    pub fn fanuc_subs_disabled(&self) -> bool {
        self.flag("RS274NGC", "DISABLE_FANUC_STYLE_SUB")
            .ok()
            .flatten()
            .unwrap_or(false)
    }

    /// The start-up G-code and where it is written (`[RS274NGC] RS274NGC_STARTUP_CODE`).
    pub fn startup_code(&self) -> Option<(&str, SourcePos)> {
        let e = self.entry("RS274NGC", "RS274NGC_STARTUP_CODE")?;
        (!e.value.trim().is_empty()).then(|| {
            (
                e.value.as_str(),
                SourcePos {
                    file: self.path.display().to_string(),
                    line: e.line,
                    column: 0,
                },
            )
        })
    }

    /// A path the INI names, relative to the INI's folder unless absolute.
    pub fn resolve(&self, p: &str) -> PathBuf {
        let p = Path::new(p.trim());
        if p.is_absolute() {
            p.to_path_buf()
        } else {
            self.path.parent().unwrap_or(Path::new("")).join(p)
        }
    }

    /// The tool table it names (`[EMCIO] TOOL_TABLE`), resolved.
    pub fn tool_table(&self) -> Option<PathBuf> {
        self.get("EMCIO", "TOOL_TABLE")
            .filter(|t| !t.trim().is_empty())
            .map(|t| self.resolve(t))
    }
}

impl GcodeOptions {
    /// Reads programs as the machine `ini` configures (see [`LinuxCncIni`]), by LinuxCNC's
    /// rules unless [`Self::dialect`] is already set: its subroutine path is searched, its arc tolerances and machine units apply (the units as
    /// [`Self::initial_units`] and [`Self::parameter_units`]; a caller that has the user's own
    /// units sets them afterwards), and [`Self::ini`] keeps it for the rest.
    ///
    /// # Errors
    /// A setting with a value LinuxCNC would not take, at its line of the INI.
    pub fn with_linuxcnc_ini(mut self, ini: LinuxCncIni) -> Result<Self, PathError> {
        if let Some(dirs) = ini.get("RS274NGC", "SUBROUTINE_PATH") {
            for d in dirs.split(':').filter(|d| !d.trim().is_empty()) {
                self.subroutine_path.push(ini.resolve(d));
            }
        }
        let mut tol: ArcTolerance = self.arc_radius_tolerance;
        if let Some(v) = ini.positive("RS274NGC", "CENTER_ARC_RADIUS_TOLERANCE_INCH")? {
            tol.abs_inch = v;
        }
        if let Some(v) = ini.positive("RS274NGC", "CENTER_ARC_RADIUS_TOLERANCE_MM")? {
            tol.abs_mm = v;
        }
        self.arc_radius_tolerance = tol;
        if let Some(u) = ini.linear_units()? {
            self.initial_units = u;
            self.parameter_units = Some(u);
        }
        // A program run under a LinuxCNC machine's INI is read by LinuxCNC's rules (a
        // dialect given before or after this wins).
        self.dialect.get_or_insert(super::GcodeDialect::LinuxCnc);
        ini.tool_change()?;
        ini.flag("RS274NGC", "INI_VARS")?;
        ini.flag("RS274NGC", "DISABLE_FANUC_STYLE_SUB")?;
        self.ini = Some(ini);
        Ok(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const INI: &str =
        "# a machine\n[EMC]\nDEBUG = 0\n\n[RS274NGC]\nSUBROUTINE_PATH = subs:../lib\n\
        RS274NGC_STARTUP_CODE = G17 G20 \\\n   G40 G90\nINI_VARS = 1\n\n[VARS]\nTOOLCHANGE_X = 10\n\
        TOOLCHANGE_X = 11\nNAME = text\n[EMCIO]\nTOOL_CHANGE_QUILL_UP = 1\nTOOL_TABLE = tool.tbl\n\
        [TRAJ]\nLINEAR_UNITS = inch\n";

    #[test]
    fn reads_what_linuxcnc_reads() {
        let ini = LinuxCncIni::parse(INI, Path::new("/m/mill.ini"));
        assert_eq!(ini.parameter("_ini[vars]toolchange_x"), Some(10.0));
        assert_eq!(ini.parameter("_ini[vars]name"), None);
        assert_eq!(ini.parameter("_ini[nosuch]toolchange_x"), None);
        assert_eq!(ini.parameter("_ini[vars]"), None);
        let (code, pos) = ini.startup_code().unwrap();
        assert_eq!(code, "G17 G20 G40 G90");
        assert_eq!(pos.line, 7);
        assert!(ini.tool_change().unwrap().quill_up);
        assert!(!ini.tool_change().unwrap().at_g30);
        assert_eq!(ini.tool_table(), Some(PathBuf::from("/m/tool.tbl")));
        assert_eq!(ini.linear_units().unwrap(), Some(Units::Inch));
        let o = GcodeOptions::default().with_linuxcnc_ini(ini).unwrap();
        assert_eq!(
            o.subroutine_path,
            vec![PathBuf::from("/m/subs"), PathBuf::from("/m/../lib")]
        );
        assert_eq!(o.initial_units, Units::Inch);
        assert_eq!(o.parameter_units, Some(Units::Inch));
    }

    #[test]
    fn a_bad_setting_names_its_line() {
        let ini = LinuxCncIni::parse("[EMCIO]\nTOOL_CHANGE_AT_G30 = maybe\n", Path::new("m.ini"));
        let e = GcodeOptions::default().with_linuxcnc_ini(ini).unwrap_err();
        assert_eq!(e.pos.to_string(), "m.ini:2:1");
        assert!(e.message.contains("TOOL_CHANGE_AT_G30"), "{e}");
        let ini = LinuxCncIni::parse("[TRAJ]\nLINEAR_UNITS = furlong\n", Path::new("m.ini"));
        assert!(GcodeOptions::default().with_linuxcnc_ini(ini).is_err());
    }
}
