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
//! The file is read as LinuxCNC's `IniFile` reads it, value by value: a value is looked for
//! after the first line that starts (after blanks) with `[SECTION]` and before the next line
//! starting with `[`; its line starts with the name, then a blank or `=`; the value is what
//! follows the `=`, blanks trimmed (a `#` or `;` after it is part of it); a `\` at a line's end
//! joins the next line to it as it is. Names and sections are compared as written (LinuxCNC's
//! are upper case, and `#<_ini[…]…>` looks them up in upper case). A yes/no setting is an
//! integer (non-zero: yes), as LinuxCNC converts it; `#INCLUDE file` lines, which LinuxCNC's
//! launcher expands, are expanded by [`LinuxCncIni::read`], and a path starting with `~` is in
//! the home folder.

use std::path::{Path, PathBuf};

use super::{ArcTolerance, GcodeOptions};
use crate::{PathError, PathErrorKind, SourcePos, Units};

/// One line of the file (continuations joined) and where it starts.
#[derive(Clone, Debug, PartialEq)]
struct Line {
    text: String,
    /// Index into [`LinuxCncIni::files`].
    file: usize,
    line: u32,
}

/// A value found: its text and where.
struct Found<'a, 'b> {
    value: &'a str,
    at: &'a Line,
    section: &'b str,
    name: &'b str,
}

/// A LinuxCNC INI file, parsed (see the module's documentation for what swarf uses).
#[derive(Clone, Debug, PartialEq)]
pub struct LinuxCncIni {
    /// The file, as given: error messages name it, relative paths in it start from its folder.
    pub path: PathBuf,
    /// The file and those it includes, in order of inclusion.
    files: Vec<PathBuf>,
    lines: Vec<Line>,
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

/// Deepest nesting of `#INCLUDE` (a file including itself ends there).
const MAX_INCLUDE_DEPTH: usize = 8;

/// `~` or `~/…` in the home folder (LinuxCNC's `TildeExpansion`); other paths as written.
fn tilde(p: &str) -> PathBuf {
    let p = p.trim();
    match (p.strip_prefix('~'), std::env::var_os("HOME")) {
        (Some(rest), Some(home)) if rest.is_empty() || rest.starts_with('/') => {
            PathBuf::from(home).join(rest.trim_start_matches('/'))
        }
        _ => PathBuf::from(p),
    }
}

impl LinuxCncIni {
    /// Reads and parses the INI file at `path`, its `#INCLUDE`s expanded.
    ///
    /// # Errors
    /// [`PathErrorKind::Io`] when it or a file it includes cannot be read (an include names
    /// the line that asks for it).
    pub fn read(path: &Path) -> Result<Self, PathError> {
        let text = crate::load::read_text_of(path, "the INI file")?;
        let mut ini = Self::parse(&text, path);
        ini.expand_includes(0)?;
        Ok(ini)
    }

    /// Parses INI text; `path` is where it came from. Nothing in it is an error by itself:
    /// LinuxCNC looks values up and ignores the rest. `#INCLUDE` lines are left as they are.
    pub fn parse(text: &str, path: &Path) -> Self {
        let mut ini = Self {
            path: path.to_path_buf(),
            files: vec![path.to_path_buf()],
            lines: Vec::new(),
        };
        ini.lines = Self::lines_of(text, 0);
        ini
    }

    fn lines_of(text: &str, file: usize) -> Vec<Line> {
        let mut out: Vec<Line> = Vec::new();
        let mut open: Option<Line> = None;
        for (i, raw) in text.lines().enumerate() {
            let raw = raw.strip_prefix('\u{feff}').unwrap_or(raw);
            let (body, more) = match raw.strip_suffix('\\') {
                Some(b) => (b, true),
                None => (raw, false),
            };
            let line = match open.take() {
                Some(mut l) => {
                    l.text.push_str(body);
                    l
                }
                None => Line {
                    text: body.to_string(),
                    file,
                    line: i as u32 + 1,
                },
            };
            if more {
                open = Some(line);
            } else {
                out.push(line);
            }
        }
        out.extend(open);
        out
    }

    /// Expands `#INCLUDE file` lines (relative to the including file's folder), as LinuxCNC's
    /// launcher does before anything reads the INI.
    fn expand_includes(&mut self, depth: usize) -> Result<(), PathError> {
        let Some(i) = self
            .lines
            .iter()
            .position(|l| l.text.trim_start().starts_with("#INCLUDE"))
        else {
            return Ok(());
        };
        let at = self.lines[i].clone();
        let name = at.text.trim_start()["#INCLUDE".len()..].trim();
        let from = self.files[at.file].parent().unwrap_or(Path::new(""));
        let target = {
            let t = tilde(name);
            if t.is_absolute() {
                t
            } else {
                from.join(t)
            }
        };
        let pos = SourcePos {
            file: self.files[at.file].display().to_string(),
            line: at.line,
            column: 1,
        };
        if depth >= MAX_INCLUDE_DEPTH {
            return Err(PathError::new(
                pos,
                PathErrorKind::Limit,
                format!("#INCLUDE nested deeper than {MAX_INCLUDE_DEPTH} files"),
                at.text.trim(),
                "",
            ));
        }
        let text = std::fs::read(&target).map_err(|e| {
            PathError::new(
                pos,
                PathErrorKind::Io,
                format!("cannot read the included file {}: {e}", target.display()),
                at.text.trim(),
                "a file beside the INI",
            )
        })?;
        self.files.push(target);
        let included = Self::lines_of(&crate::load::decode_text(text), self.files.len() - 1);
        self.lines.splice(i..=i, included);
        self.expand_includes(depth + 1)
    }

    /// The value of `name` in `[section]`, found as `IniFile::Find` finds it.
    fn find<'a, 'b>(&'a self, section: &'b str, name: &'b str) -> Option<Found<'a, 'b>> {
        let header = format!("[{section}]");
        let start = self
            .lines
            .iter()
            .position(|l| l.text.trim_start().starts_with(&header))?;
        for l in &self.lines[start + 1..] {
            let t = l.text.trim_start();
            if t.starts_with('[') {
                return None;
            }
            let Some(rest) = t.strip_prefix(name) else {
                continue;
            };
            if !rest.starts_with([' ', '\t', '\r', '=']) {
                continue;
            }
            let (_, value) = rest.split_once('=')?;
            return Some(Found {
                value: value.trim_start().trim_end_matches([' ', '\t', '\r']),
                at: l,
                section,
                name,
            });
        }
        None
    }

    /// The value of `name` in `[section]`, as LinuxCNC finds it.
    pub fn get(&self, section: &str, name: &str) -> Option<&str> {
        self.find(section, name).map(|f| f.value)
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

    /// Whether `#<_ini[…]>` reads the INI (`[RS274NGC] INI_VARS`, on unless set to 0).
    pub fn ini_vars(&self) -> bool {
        self.flag("RS274NGC", "INI_VARS")
            .ok()
            .flatten()
            .unwrap_or(true)
    }

    /// A yes/no setting, an integer as LinuxCNC converts it (non-zero: yes); `Ok(None)` when
    /// absent.
    ///
    /// # Errors
    /// A value that is not an integer (LinuxCNC would ignore it and keep its default, so
    /// `TRUE` there means no: an error here says so).
    fn flag(&self, section: &str, name: &str) -> Result<Option<bool>, PathError> {
        let Some(f) = self.find(section, name) else {
            return Ok(None);
        };
        match f.value.parse::<i64>() {
            Ok(v) => Ok(Some(v != 0)),
            Err(_) => Err(self.bad(
                &f,
                "an integer, 1 or 0 (LinuxCNC reads nothing else here and would keep its default)",
            )),
        }
    }

    /// An arc tolerance, within LinuxCNC's bounds (`min` up to its default `max`).
    fn tolerance(&self, name: &str, min: f64, max: f64) -> Result<Option<f64>, PathError> {
        let Some(f) = self.find("RS274NGC", name) else {
            return Ok(None);
        };
        match f.value.parse::<f64>() {
            Ok(v) if (min..=max).contains(&v) => Ok(Some(v)),
            _ => Err(self.bad(
                &f,
                &format!(
                    "a number from {min} to {max:.6} (LinuxCNC refuses others and keeps {max:.6})"
                ),
            )),
        }
    }

    fn bad(&self, f: &Found<'_, '_>, expected: &str) -> PathError {
        PathError::new(
            self.pos(f.at),
            PathErrorKind::Semantic,
            format!("bad [{}] {} in the INI file", f.section, f.name),
            f.value,
            expected,
        )
    }

    fn pos(&self, l: &Line) -> SourcePos {
        SourcePos {
            file: self.files[l.file].display().to_string(),
            line: l.line,
            column: 1,
        }
    }

    /// The machine's linear units (`[TRAJ] LINEAR_UNITS`: `mm`, `metric`, `in`, `inch`,
    /// `imperial`, or units per mm, 1 or 1/25.4, as LinuxCNC's map has them); `Ok(None)` when
    /// not stated.
    ///
    /// # Errors
    /// Another value, at its line.
    pub fn linear_units(&self) -> Result<Option<Units>, PathError> {
        let Some(f) = self.find("TRAJ", "LINEAR_UNITS") else {
            return Ok(None);
        };
        let v = f.value.to_ascii_lowercase();
        let per_mm = match v.as_str() {
            "mm" | "metric" => 1.0,
            "in" | "inch" | "imperial" => 1.0 / 25.4,
            _ => v.parse::<f64>().unwrap_or(f64::NAN),
        };
        if (per_mm - 1.0).abs() < 1e-6 {
            Ok(Some(Units::Mm))
        } else if (per_mm * 25.4 - 1.0).abs() < 1e-4 {
            Ok(Some(Units::Inch))
        } else {
            Err(self.bad(&f, "mm or inch (or units per mm: 1 or 0.03937)"))
        }
    }

    /// What `M6` does besides changing the tool.
    ///
    /// # Errors
    /// A setting that is not an integer, at its line.
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
        let f = self.find("RS274NGC", "RS274NGC_STARTUP_CODE")?;
        (!f.value.trim().is_empty()).then(|| {
            let mut pos = self.pos(f.at);
            pos.column = 0;
            (f.value, pos)
        })
    }

    /// A path the INI names, relative to the INI's folder unless absolute (`~`: the home
    /// folder).
    pub fn resolve(&self, p: &str) -> PathBuf {
        let p = tilde(p);
        if p.is_absolute() {
            p
        } else {
            self.path.parent().unwrap_or(Path::new("")).join(p)
        }
    }

    /// The tool table it names (`[EMCIO] TOOL_TABLE`), resolved, and where it names it.
    pub fn tool_table(&self) -> Option<(PathBuf, SourcePos)> {
        let f = self.find("EMCIO", "TOOL_TABLE")?;
        (!f.value.trim().is_empty()).then(|| (self.resolve(f.value), self.pos(f.at)))
    }
}

impl GcodeOptions {
    /// Reads programs as the machine `ini` configures (see [`LinuxCncIni`]), by LinuxCNC's
    /// rules unless [`Self::dialect`] is already set: its subroutine path is searched, its arc
    /// tolerances and machine units apply (the units as [`Self::initial_units`] and
    /// [`Self::parameter_units`]; a caller that has the user's own units sets them
    /// afterwards), and [`Self::ini`] keeps it for the rest.
    ///
    /// # Errors
    /// A setting with a value LinuxCNC would not take, at its line of the INI.
    pub fn with_linuxcnc_ini(mut self, ini: LinuxCncIni) -> Result<Self, PathError> {
        if let Some(dirs) = ini.get("RS274NGC", "SUBROUTINE_PATH") {
            for d in dirs.split(':').filter(|d| !d.trim().is_empty()) {
                self.subroutine_path.push(ini.resolve(d));
            }
        }
        // LinuxCNC's bounds (interp_internal.hh): at least the minimum, at most the default.
        let mut tol: ArcTolerance = self.arc_radius_tolerance;
        let d = ArcTolerance::LINUXCNC;
        if let Some(v) = ini.tolerance("CENTER_ARC_RADIUS_TOLERANCE_INCH", 0.00004, d.abs_inch)? {
            tol.abs_inch = v;
        }
        if let Some(v) = ini.tolerance("CENTER_ARC_RADIUS_TOLERANCE_MM", 0.001, d.abs_mm)? {
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
        "# a machine\n[EMC]\nDEBUG = 0\n\n[RS274NGC]\nSUBROUTINE_PATH = subs:../lib:~/nc\n\
        RS274NGC_STARTUP_CODE = G17 G20 \\\n G40 G90\nINI_VARS = 1\n\n[VARS]\nTOOLCHANGE_X = 10\n\
        TOOLCHANGE_X = 11\nNAME = text\nJOINED = 1\\\n3\nWITH_NOTE = 4 # mm\n[EMCIO]\n\
        TOOL_CHANGE_QUILL_UP = 2\nTOOL_TABLE = tool.tbl\n[TRAJ]\nLINEAR_UNITS = inch\n\
        [EMCIO]\nTOOL_CHANGE_AT_G30 = 1\n";

    #[test]
    fn reads_what_linuxcnc_reads() {
        let ini = LinuxCncIni::parse(INI, Path::new("/m/mill.ini"));
        assert_eq!(ini.parameter("_ini[vars]toolchange_x"), Some(10.0));
        assert_eq!(ini.parameter("_ini[vars]name"), None);
        assert_eq!(ini.parameter("_ini[nosuch]toolchange_x"), None);
        assert_eq!(ini.parameter("_ini[vars]"), None);
        // A continuation joins the next line as it is (inivar prints 13); a note after a
        // value is part of it, so no number.
        assert_eq!(ini.parameter("_ini[vars]joined"), Some(13.0));
        assert_eq!(ini.parameter("_ini[vars]with_note"), None);
        let (code, pos) = ini.startup_code().unwrap();
        assert_eq!(code, "G17 G20  G40 G90");
        assert_eq!((pos.line, pos.column), (7, 0));
        // Any non-zero integer is yes; only the first [EMCIO] counts.
        assert!(ini.tool_change().unwrap().quill_up);
        assert!(!ini.tool_change().unwrap().at_g30);
        assert_eq!(ini.tool_table().unwrap().0, PathBuf::from("/m/tool.tbl"));
        assert_eq!(ini.linear_units().unwrap(), Some(Units::Inch));
        let o = GcodeOptions::default().with_linuxcnc_ini(ini).unwrap();
        assert_eq!(
            o.subroutine_path[..2],
            [PathBuf::from("/m/subs"), PathBuf::from("/m/../lib")]
        );
        if let Some(home) = std::env::var_os("HOME") {
            assert_eq!(o.subroutine_path[2], PathBuf::from(home).join("nc"));
        }
        assert_eq!(o.initial_units, Units::Inch);
        assert_eq!(o.parameter_units, Some(Units::Inch));
        // Units per mm, as LinuxCNC's map gives them.
        let per_mm = |v: &str| {
            LinuxCncIni::parse(&format!("[TRAJ]\nLINEAR_UNITS = {v}\n"), Path::new("m.ini"))
                .linear_units()
        };
        assert_eq!(per_mm("1").unwrap(), Some(Units::Mm));
        assert_eq!(per_mm("0.03937").unwrap(), Some(Units::Inch));
        assert!(per_mm("25.4").is_err());
    }

    #[test]
    fn a_bad_setting_names_its_line() {
        let ini = LinuxCncIni::parse("[EMCIO]\nTOOL_CHANGE_AT_G30 = TRUE\n", Path::new("m.ini"));
        let e = GcodeOptions::default().with_linuxcnc_ini(ini).unwrap_err();
        assert_eq!(e.pos.to_string(), "m.ini:2:1");
        assert!(e.message.contains("TOOL_CHANGE_AT_G30"), "{e}");
        let ini = LinuxCncIni::parse("[TRAJ]\nLINEAR_UNITS = furlong\n", Path::new("m.ini"));
        assert!(GcodeOptions::default().with_linuxcnc_ini(ini).is_err());
        // Arc tolerances within LinuxCNC's bounds only.
        for v in ["0.5", "0.0005"] {
            let t = format!("[RS274NGC]\nCENTER_ARC_RADIUS_TOLERANCE_MM = {v}\n");
            let ini = LinuxCncIni::parse(&t, Path::new("m.ini"));
            assert!(
                GcodeOptions::default().with_linuxcnc_ini(ini).is_err(),
                "{v}"
            );
        }
        let t = "[RS274NGC]\nCENTER_ARC_RADIUS_TOLERANCE_MM = 0.002\n";
        let o = GcodeOptions::default()
            .with_linuxcnc_ini(LinuxCncIni::parse(t, Path::new("m.ini")))
            .unwrap();
        assert_eq!(o.arc_radius_tolerance.abs_mm, 0.002);
    }

    #[test]
    fn includes_are_expanded() {
        let dir = std::env::temp_dir().join(format!("swarf-ini-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("inc")).unwrap();
        std::fs::write(dir.join("m.ini"), "[EMC]\n#INCLUDE inc/traj.inc\n[EMCIO]\n").unwrap();
        std::fs::write(dir.join("inc/traj.inc"), "[TRAJ]\nLINEAR_UNITS = inch\n").unwrap();
        std::fs::write(dir.join("loop.ini"), "#INCLUDE loop.ini\n").unwrap();
        let ini = LinuxCncIni::read(&dir.join("m.ini")).unwrap();
        let looped = LinuxCncIni::read(&dir.join("loop.ini"));
        let missing = LinuxCncIni::read(&dir.join("none.ini"));
        std::fs::remove_dir_all(&dir).ok();
        assert_eq!(ini.linear_units().unwrap(), Some(Units::Inch));
        assert_eq!(looped.unwrap_err().kind, PathErrorKind::Limit);
        assert_eq!(missing.unwrap_err().kind, PathErrorKind::Io);
    }
}
