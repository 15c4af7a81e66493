//! APT CL data (CLDATA text) reader: the cutter-location files NX (`.cls`), CATIA and
//! SolidWorks CAM (`.apt`) post-processors read.
//!
//! CL data is already tool tip and tool axis in the workpiece frame — there is no machine in
//! it — so [`read_apt`] hands positions on as X Y Z (rotary words zero) and states the tool axis
//! with [`Canon::ToolAxis`]; a [`MoveBuilder`](crate::builder::MoveBuilder) then takes the axis
//! from the program rather than from kinematics.
//!
//! # Records
//! A record is `MAJOR/minor,minor,…` or a bare `MAJOR`. `$$` starts a comment; a line ending in
//! a single `$` continues on the next one (a whole-line comment so ended, as Creo writes its
//! `$$-> CSYS / …, $`, on the lines of numbers after it). Words are case-insensitive.
//!
//! | record | effect |
//! |---|---|
//! | `GOTO/x,y,z[,i,j,k]` | move (feed, or rapid after `RAPID`); new axis when i,j,k given |
//! | `FROM/x,y,z[,i,j,k]` | start position, no move ([`Canon::SetPosition`]) |
//! | `GODLTA/dx,dy,dz` | move by a delta |
//! | `RAPID` | the next motion only is a rapid |
//! | `GOHOME/x,y,z[,i,j,k]` | NX's: a move to that point (rapid after `RAPID`), new axis when i,j,k given |
//! | `GOHOME` | back to the `FROM/` point (a warning when there is none) |
//! | `FEDRAT/f[,MMPM│IPM│MMPR│IPR]` (either order) | feed rate and mode |
//! | `CIRCLE/xc,yc,zc,i,j,k[,r,…][,CLW│CCLW]` | the next `GOTO` is an arc about that centre and axis (a direction word states its sense) |
//! | `CUTTER/d[,r,e,f,α,β,h]`, `TLDATA/MILL,d,r,h[,taper,tip]`, `TLDATA/DRILL,d,r,h,point angle` | [`Canon::CutterDefinition`] (`TLDATA/` as `Reader::tldata` says) |
//! | `LOADTL/n`, `LOAD/TOOL,n` | tool change |
//! | `SPINDL/rpm[,RPM][,CLW│CCW]`, `SPINDL/OFF│ON` | spindle |
//! | `UNITS/MM│INCHES`, `UNIT/…` | units (inch data is converted to mm) |
//! | `CSYS/` 3×4 matrix | applied to the following points (see below) |
//! | `PARTNO`, `PPRINT`, `REMARK`, `TPRINT`, `TOOL PATH`, `INSERT` | comments (`INSERT` also warns); all but `TOOL PATH` may hold any text, with or without the slash (`PPRINT OPERATION : Sweep.1`) |
//! | `TLAXIS/i,j,k` | the tool axis of the following `GOTO`s that give none |
//! | `INDIRV/i,j,k` + `TLON,GOFWD/ (CIRCLE/ xc,yc,zc[,i,j,k],r), ON, (LINE/ …)` | CATIA's arc: from where the tool stands, in the `INDIRV` direction, about the circle's axis (the tool axis when it gives none), to the line (CATIA writes it from the centre to the end; a line through the centre gives the ray towards its far point), at the start's height along the axis |
//! | `CYCLE/DRILL│DEEP│BRKCHP│CSINK│FACE│TAP│BORE│REAM,…`, `CYCLE/OFF`, `CYCLE/ON` | each `GOTO/` until `CYCLE/OFF` drills a hole along the tool axis (see [`cycle`]) |
//! | `FINI` | end of program |
//!
//! `PAINT`, `COOLNT`, `MULTAX`, `SELCTL`, `END-OF-PATH`, `CUTCOM/OFF`, `STOP`, `OPSTOP`,
//! `TOOLNO`, `END`, `REWIND` (CATIA's last record), `MACHIN` (Creo's post-processor name) are
//! accepted silently (they do not change the tool's path). `CUTCOM/LEFT│RIGHT` warns: CL points
//! are normally the compensated cutter path already, and swarf simulates the points as written,
//! not what a controller doing radius compensation would add. `MSYS/` (where the MCS sits in
//! absolute coordinates) warns when it is not the identity: points stay in the first MCS, which
//! is swarf's workpiece frame; the points of an operation under a later, different `MSYS/`
//! (another setup, a 3+2 side face) are mapped into the first MCS, with a warning. `DELAY/t`
//! dwells t seconds, `DELAY/n,REV` n spindle revolutions. `NURBS/`, `KNOT/`, `CNTRL/`, cycles
//! other than the drilling family and APT part-program motion (`GOLFT/`, `GOFWD/`, `PSIS/`,
//! any other `GO…` word) are errors: they make motion swarf does not generate, which a warning
//! would silently drop. Other records are warnings; malformed records are [`PathError`]s.
//!
//! A cutter definition (`CUTTER/`, `TLDATA/`) that differs from the one the current tool has
//! already cut with starts a tool of its own (see [`crate::moves::Program::cutter_definitions`]).
//! Lengths are mm until a `UNITS/` record ([`AptOptions::initial_units`] otherwise); lines may end
//! in LF, CRLF or a lone CR.
//!
//! # Decisions
//! * **The first point.** CL data has no home position: the first `GOTO` (or `FROM`) only places
//!   the tool ([`Canon::SetPosition`]); a file with n `GOTO`s and no `FROM` gives n − 1 moves.
//! * **Arc direction.** `CIRCLE/` gives an axis, and a direction only when it ends in a word
//!   (`CLW`/`CLOCKWISE`, `CCLW`/`COUNTERCLOCKWISE`, as SolidWorks CAM writes); vendors differ. With
//!   [`CircleSense::Auto`] the motion is counter-clockwise about the axis (right-hand rule),
//!   except in NX CLSF files (recognised by `TOOL PATH/`, `TLDATA/`, `MSYS/` or `END-OF-PATH`),
//!   where it is clockwise: NX writes the arc axis equal to the tool axis for clockwise (G2)
//!   arcs. Arcs about ±X, ±Y or ±Z become [`Canon::Arc`]; others [`Canon::ArcAxis`].
//! * **`CSYS/a,b,c,d,e,f,g,h,i,j,k,l`** states a rigid transform whose rows are `[a b c | d]`
//!   … : the following points `p` are local and `M·p + t` is the workpiece frame. It is applied
//!   (with a warning unless it is the identity) when [`AptOptions::apply_csys`] is set (the
//!   default); otherwise points are kept local and it warns.
//! * `GOTO` records with more than six values (NX contact data) use the first six and warn.
//!
//! ```
//! use swarf_path::apt::{read_apt, AptOptions};
//! use swarf_path::canon::Recorder;
//! let text = "UNITS/MM\nFEDRAT/MMPM,500\nGOTO/0,0,5\nGOTO/10,0,5\nFINI\n";
//! let mut rec = Recorder::default();
//! read_apt(text, "demo.apt", &AptOptions::default(), &mut rec).unwrap();
//! assert!(rec.events.iter().any(|(_, e)| matches!(e, swarf_path::Canon::Feed { .. })));
//! ```

use std::borrow::Cow;
use std::path::Path;

use swarf_geom::math::{Mat3, Vec3, MACHINE_RANGE_MM};

use crate::canon::{Axes, Canon, CanonSink, FeedMode, Plane, SpindleDir, Units};
use crate::error::{PathError, PathErrorKind, SourcePos};
use crate::limit::{move_limit_error, MoveLimit};
use crate::Warning;

pub mod cycle;

/// Default tolerance on arc radii (start, end and the `CIRCLE/` radius must agree), mm.
pub const DEFAULT_ARC_TOLERANCE_MM: f64 = 0.01;

/// Which way a `CIRCLE/` turns about its axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum CircleSense {
    /// Decide from the file: clockwise for NX CLSF, counter-clockwise otherwise.
    #[default]
    Auto,
    /// Counter-clockwise about the axis (right-hand rule).
    CounterClockwise,
    /// Clockwise about the axis.
    Clockwise,
}

/// Options of [`read_apt`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AptOptions {
    /// Arc direction convention.
    pub circle_sense: CircleSense,
    /// Apply `CSYS/` matrices to the points that follow.
    pub apply_csys: bool,
    /// Radius tolerance of arcs, mm ([`DEFAULT_ARC_TOLERANCE_MM`]); beyond it a warning.
    pub arc_tolerance_mm: f64,
    /// Most motion records (`GOTO/`, arcs): the limit that bounds the memory of a consumer that
    /// keeps the moves, default [`DEFAULT_MAX_MOVES`](crate::limit::DEFAULT_MAX_MOVES);
    /// `u64::MAX` for consumers that stream. See [`crate::limit`].
    pub max_moves: u64,
    /// Length units before the file's first `UNITS/` record (CL data carries no units unless
    /// it says so; inch files without the record exist).
    pub initial_units: Units,
}

impl Default for AptOptions {
    fn default() -> Self {
        Self {
            circle_sense: CircleSense::Auto,
            apply_csys: true,
            arc_tolerance_mm: DEFAULT_ARC_TOLERANCE_MM,
            max_moves: crate::limit::DEFAULT_MAX_MOVES,
            initial_units: Units::Mm,
        }
    }
}

impl AptOptions {
    /// With another arc direction convention.
    pub fn with_circle_sense(mut self, sense: CircleSense) -> Self {
        self.circle_sense = sense;
        self
    }
    /// Applying `CSYS/` or not.
    pub fn with_apply_csys(mut self, apply: bool) -> Self {
        self.apply_csys = apply;
        self
    }
    /// With another move limit ([`Self::max_moves`]).
    pub fn with_max_moves(mut self, n: u64) -> Self {
        self.max_moves = n;
        self
    }
    /// With other units before the first `UNITS/` record.
    pub fn with_initial_units(mut self, units: Units) -> Self {
        self.initial_units = units;
        self
    }
    /// With another arc radius tolerance, mm.
    pub fn with_arc_tolerance(mut self, tolerance_mm: f64) -> Self {
        self.arc_tolerance_mm = tolerance_mm;
        self
    }
}

/// Reads a CL file from disk; see [`read_apt`].
///
/// # Errors
/// [`PathErrorKind::Io`] when the file cannot be read, else as [`read_apt`].
pub fn read_apt_file(
    path: impl AsRef<Path>,
    options: &AptOptions,
    sink: &mut dyn CanonSink,
) -> Result<(), PathError> {
    let path = path.as_ref();
    let name = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| {
        let pos = SourcePos {
            file: name.clone(),
            line: 0,
            column: 0,
        };
        PathError::new(
            pos,
            PathErrorKind::Io,
            format!("cannot read the file: {e}"),
            "",
            "",
        )
    })?;
    read_apt(&crate::load::decode_text(bytes), &name, options, sink)
}

/// Reads CLDATA text, handing events to `sink`. See the [module documentation](self).
///
/// # Errors
/// The first malformed record: file, line, column, the text found and what was expected.
pub fn read_apt(
    text: &str,
    file_name: &str,
    options: &AptOptions,
    sink: &mut dyn CanonSink,
) -> Result<(), PathError> {
    // Editors on Windows may leave a byte-order mark in front of the first record.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    // Old Mac editors end lines with a lone CR: read as line ends (a file of them was one
    // free-text record: no motion and no warning).
    let text: Cow<'_, str> = if text.contains('\r') && text.replace("\r\n", "").contains('\r') {
        Cow::Owned(text.replace("\r\n", "\n").replace('\r', "\n"))
    } else {
        Cow::Borrowed(text)
    };
    let text = text.as_ref();
    let clockwise = match options.circle_sense {
        CircleSense::Clockwise => true,
        CircleSense::CounterClockwise => false,
        CircleSense::Auto => is_nx_clsf(text),
    };
    let mut r = Reader {
        file: file_name,
        options,
        sink: MoveLimit::new(sink, options.max_moves),
        scale: options.initial_units.mm_per_unit(),
        units_stated: false,
        inch_feed_warned: false,
        msys: None,
        feed_mode: FeedMode::PerMinute,
        feed_unit: None,
        pos: None,
        axis: Vec3::Z,
        axis_stated: false,
        rapid_next: false,
        circle: None,
        csys: None,
        clockwise,
        spindle_rpm: 0.0,
        spindle_dir: SpindleDir::Clockwise,
        extra_goto_warned: false,
        indirv: None,
        program_feed: None,
        cycle: None,
        last_cycle: None,
        from: None,
    };
    let mut record = Record::default();
    // A whole-line comment ending in `$` (Creo: `$$-> CSYS / 1.0, 0.0, …, $`) goes on over the
    // lines of numbers that follow it.
    let mut comment_goes_on = false;
    for (i, raw) in text.split('\n').enumerate() {
        let line_no = u32::try_from(i + 1).unwrap_or(u32::MAX);
        let raw = raw.strip_suffix('\r').unwrap_or(raw);
        let trimmed = raw.trim();
        if std::mem::take(&mut comment_goes_on)
            && trimmed.starts_with(|c: char| c.is_ascii_digit() || "+-.".contains(c))
        {
            comment_goes_on = trimmed.ends_with('$');
            continue;
        }
        if record.text.is_empty() && trimmed.starts_with("$$") {
            comment_goes_on = trimmed.len() > 2 && trimmed.ends_with('$');
            continue;
        }
        let content = match raw.find("$$") {
            Some(k) => &raw[..k],
            None => raw,
        };
        let trimmed = content.trim_end();
        let (body, continues) = match trimmed.strip_suffix('$') {
            Some(b) => (b, true),
            None => (trimmed, false),
        };
        record.push(body, raw, line_no);
        if continues {
            continue;
        }
        let done = std::mem::take(&mut record);
        if is_blank(&done.text) {
            continue;
        }
        let flow = r.record(&done)?;
        r.check_move_limit(&done)?;
        if flow == Flow::Stop {
            r.sink.finish();
            return Ok(());
        }
    }
    if !is_blank(&record.text) {
        r.record(&record)?;
        r.check_move_limit(&record)?;
    }
    // A last record continued (`$`) past the end: the file was cut short (a transfer that
    // stopped), and reads as a shorter program, so it is said. (No FINI alone is not: CAM
    // systems end CL files without one.)
    let last = text
        .split('\n')
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
        .last();
    if let Some((i, l)) = last {
        let code = l.find("$$").map_or(l, |k| &l[..k]).trim_end();
        if code.ends_with('$') {
            r.warn(
                u32::try_from(i + 1).unwrap_or(u32::MAX),
                0,
                "the last record goes on (`$`) past the end of the file: the file may be cut \
                 short"
                    .to_string(),
            );
        }
    }
    r.unused_circle();
    r.sink.finish();
    Ok(())
}

/// A record of nothing but blanks and the Ctrl-Z (0x1a) that DOS tools and DNC senders put at
/// the end of a file.
fn is_blank(text: &str) -> bool {
    text.chars().all(|c| c.is_whitespace() || c == '\u{1a}')
}

/// NX CLSF markers (see the module documentation on arc direction).
fn is_nx_clsf(text: &str) -> bool {
    text.lines().any(|l| {
        let l = l.trim_start().to_ascii_uppercase();
        ["TOOL PATH/", "TLDATA/", "MSYS/", "END-OF-PATH"]
            .iter()
            .any(|m| l.starts_with(m))
    })
}

/// A logical record: the text of one or more physical lines joined, with a map back to them.
#[derive(Default)]
struct Record<'t> {
    text: String,
    /// (offset in `text` where the piece starts, its line number, the whole physical line).
    pieces: Vec<(usize, u32, &'t str)>,
}

impl<'t> Record<'t> {
    /// Appends `body`, a prefix of the physical `line`.
    fn push(&mut self, body: &'t str, line: &'t str, line_no: u32) {
        self.pieces.push((self.text.len(), line_no, line));
        self.text.push_str(body);
    }
    /// Line and 1-based column (in characters) of byte offset `off` in `text`.
    fn locate(&self, off: usize) -> (u32, u32) {
        let Some(&(start, line_no, line)) = self
            .pieces
            .iter()
            .rev()
            .find(|p| p.0 <= off)
            .or(self.pieces.first())
        else {
            return (0, 0);
        };
        let k = off.saturating_sub(start).min(line.len());
        let col = line.char_indices().take_while(|(b, _)| *b < k).count() + 1;
        (line_no, u32::try_from(col).unwrap_or(u32::MAX))
    }
}

/// One comma-separated value of a record, with its offset in the record's text.
#[derive(Clone, Copy)]
struct Field<'a> {
    text: &'a str,
    off: usize,
}

#[derive(PartialEq)]
enum Flow {
    Go,
    Stop,
}

struct PendingCircle {
    center: Vec3,
    /// Unit normal about which the motion is counter-clockwise.
    normal: Vec3,
    radius: Option<f64>,
    line: u32,
    column: u32,
}

struct Reader<'o, 's> {
    file: &'o str,
    options: &'o AptOptions,
    /// The caller's sink behind the move limit.
    sink: MoveLimit<'s>,
    /// mm per program unit.
    scale: f64,
    /// A `UNITS/` record has been read.
    units_stated: bool,
    /// An inch feed in a file without `UNITS/` has been warned about.
    inch_feed_warned: bool,
    /// NX's machine coordinate systems: the first `MSYS/` (origin and axes in absolute
    /// coordinates, mm), which is swarf's workpiece frame, and the map from the current MCS to
    /// it when a later one differs (rotation, translation in mm).
    msys: Option<Msys>,
    feed_mode: FeedMode,
    /// mm per length unit of the last FEDRAT/ mode word (IPM, IPR: 25.4): a FEDRAT/ without
    /// one keeps the mode and its unit, as posts read it. `None` before any: the file's unit.
    feed_unit: Option<f64>,
    /// Current tip (workpiece frame, mm); `None` until the first point.
    pos: Option<Vec3>,
    axis: Vec3,
    axis_stated: bool,
    rapid_next: bool,
    circle: Option<PendingCircle>,
    csys: Option<(Mat3, Vec3)>,
    clockwise: bool,
    spindle_rpm: f64,
    spindle_dir: SpindleDir,
    extra_goto_warned: bool,
    /// The direction `INDIRV/` states for the next `TLON,GOFWD/` circle.
    indirv: Option<Vec3>,
    /// The feed `FEDRAT/` set (mm/min or mm/rev), restored after a cycle's own feed.
    program_feed: Option<f64>,
    /// The canned cycle each `GOTO/` drills a hole of, until `CYCLE/OFF`.
    cycle: Option<cycle::Cycle>,
    /// The last cycle defined, which `CYCLE/ON` restarts.
    last_cycle: Option<cycle::Cycle>,
    /// The `FROM/` point, where `GOHOME` returns.
    from: Option<Vec3>,
}

/// The MCSs of an NX CLSF (see `Reader::msys`).
struct Msys {
    /// The first MCS: axes (columns), origin (mm), and the line that set it.
    first: (Mat3, Vec3, u32),
    /// From the current MCS to the first, when it differs.
    to_first: Option<(Mat3, Vec3)>,
}

/// A point as joint values (X Y Z; rotary words are not used by CL data).
fn axes(p: Vec3) -> Axes {
    Axes {
        x: p.x,
        y: p.y,
        z: p.z,
        ..Axes::default()
    }
}

impl Reader<'_, '_> {
    /// The move-limit error at `record` when it made a move over [`AptOptions::max_moves`].
    fn check_move_limit(&self, record: &Record<'_>) -> Result<(), PathError> {
        if !self.sink.over {
            return Ok(());
        }
        let (line, column) = record.locate(0);
        let pos = SourcePos {
            file: self.file.to_string(),
            line,
            column,
        };
        Err(move_limit_error(pos, &record.text, self.sink.max()))
    }

    fn warn(&mut self, line: u32, column: u32, message: String) {
        self.sink.warn(Warning {
            file: self.file.to_string(),
            line,
            column,
            message,
        });
    }

    fn error(
        &self,
        rec: &Record<'_>,
        off: usize,
        kind: PathErrorKind,
        message: impl Into<String>,
        found: &str,
        expected: &str,
    ) -> PathError {
        let (line, column) = rec.locate(off);
        PathError::new(
            SourcePos {
                file: self.file.to_string(),
                line,
                column,
            },
            kind,
            message,
            found,
            expected,
        )
    }

    fn number(&self, rec: &Record<'_>, f: Field<'_>, what: &str) -> Result<f64, PathError> {
        let t = f.text;
        let ok_chars = !t.is_empty()
            && t.bytes().any(|b| b.is_ascii_digit())
            && t.bytes()
                .all(|b| b.is_ascii_digit() || b"+-.eE".contains(&b));
        match t.parse::<f64>() {
            Ok(v) if ok_chars && v.is_finite() => Ok(v),
            _ => Err(self.error(
                rec,
                f.off,
                PathErrorKind::Syntax,
                format!("{what}: not a number"),
                t,
                "a number",
            )),
        }
    }

    /// Refuses a point (`raw` as written, `p` in the workpiece frame, mm) with a coordinate
    /// beyond [`MACHINE_RANGE_MM`], at the field that holds it.
    fn check_range(
        &self,
        rec: &Record<'_>,
        fields: &[Field<'_>],
        raw: &[f64],
        p: Vec3,
        what: &str,
    ) -> Result<(), PathError> {
        let out = |v: f64| !(v.is_finite() && v.abs() <= MACHINE_RANGE_MM);
        let Some(k) = raw
            .iter()
            .position(|&v| out(v * self.scale))
            .or_else(|| p.to_array().into_iter().position(out))
        else {
            return Ok(());
        };
        let v = if out(raw[k] * self.scale) {
            raw[k] * self.scale
        } else {
            p[k]
        };
        Err(self.error(
            rec,
            fields[k].off,
            PathErrorKind::Semantic,
            format!(
                "{what} coordinate {v:e} mm is beyond the machine range of \
                 ±{MACHINE_RANGE_MM:e} mm"
            ),
            fields[k].text,
            "a coordinate within ±1e6 mm",
        ))
    }

    fn numbers(
        &self,
        rec: &Record<'_>,
        fields: &[Field<'_>],
        what: &str,
    ) -> Result<Vec<f64>, PathError> {
        fields.iter().map(|f| self.number(rec, *f, what)).collect()
    }

    /// A point from program units and the CL frame to the workpiece frame, mm.
    fn point(&self, p: Vec3) -> Vec3 {
        let p = p * self.scale;
        let p = match self.csys {
            Some((m, t)) => m * p + t * self.scale,
            None => p,
        };
        match self.msys.as_ref().and_then(|m| m.to_first) {
            Some((r, t)) => r * p + t,
            None => p,
        }
    }

    fn vector(&self, v: Vec3) -> Vec3 {
        let v = match self.csys {
            Some((m, _)) => m * v,
            None => v,
        };
        match self.msys.as_ref().and_then(|m| m.to_first) {
            Some((r, _)) => r * v,
            None => v,
        }
    }

    fn record(&mut self, rec: &Record<'_>) -> Result<Flow, PathError> {
        let text = rec.text.as_str();
        let lead = text.len() - text.trim_start().len();
        if let Some(k) = text.find('/') {
            let head: String = text[..k]
                .chars()
                .filter(|c| !c.is_whitespace())
                .collect::<String>()
                .to_ascii_uppercase();
            if head == "TLON,GOFWD" {
                return self.gofwd(rec, k + 1).map(|()| Flow::Go);
            }
        }
        let (major_raw, minor, minor_off) = match (text_record(text), text.find('/')) {
            // Free text (`PPRINT OPERATION NAME : Sweep.1`, as CATIA writes it): the first
            // word is the record, whatever the text holds.
            (Some(k), _) => (&text[..k], Some(&text[k..]), k),
            (None, Some(k)) => (&text[..k], Some(&text[k + 1..]), k + 1),
            (None, None) => (text, None, text.len()),
        };
        let major_raw = major_raw.trim();
        if major_raw.is_empty()
            || !major_raw
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || "_- ".contains(c))
        {
            return Err(self.error(
                rec,
                lead,
                PathErrorKind::Syntax,
                "not an APT record",
                major_raw,
                "a major word such as GOTO, FEDRAT or CIRCLE",
            ));
        }
        let major = major_raw.to_ascii_uppercase();
        let (line, column) = rec.locate(lead);
        let fields: Vec<Field<'_>> = match minor {
            None => Vec::new(),
            Some(m) if m.trim().is_empty() => Vec::new(),
            Some(m) => {
                let mut out = Vec::new();
                let mut off = minor_off;
                for piece in m.split(',') {
                    let t = piece.trim();
                    let pad = piece.len() - piece.trim_start().len();
                    out.push(Field {
                        text: t,
                        off: off + pad,
                    });
                    off += piece.len() + 1;
                }
                // Posts end records with a comma (`GOTO/1,2,3,`): the empty field is no field.
                while out.len() > 1 && out.last().is_some_and(|f| f.text.is_empty()) {
                    out.pop();
                }
                out
            }
        };
        let minor_text = minor.unwrap_or("").trim();
        let minor_text = match text_record(text) {
            Some(_) => minor_text.strip_prefix('/').unwrap_or(minor_text).trim(),
            None => minor_text,
        };
        let word = |i: usize| fields.get(i).map(|f| f.text.to_ascii_uppercase());
        match major.as_str() {
            "GOTO" => self.goto(rec, &fields, "GOTO/")?,
            "FROM" => self.goto(rec, &fields, "FROM/")?,
            "GODLTA" => {
                let v = self.numbers(rec, &fields, "GODLTA/")?;
                let d = match v.len() {
                    3 => self.vector(Vec3::new(v[0], v[1], v[2]) * self.scale),
                    // One value: that far along the tool axis (APT's `GODLTA/d`).
                    1 => self.axis * (v[0] * self.scale),
                    _ => {
                        return Err(self.count_error(
                            rec,
                            &fields,
                            minor_off,
                            "GODLTA/",
                            "dx,dy,dz, or one distance along the tool axis",
                        ))
                    }
                };
                let Some(p) = self.pos else {
                    return Err(self.error(
                        rec,
                        lead,
                        PathErrorKind::Semantic,
                        "GODLTA/ before any position is known",
                        major_raw,
                        "a GOTO/ or FROM/ first",
                    ));
                };
                self.check_range(rec, &fields, &v, p + d, "GODLTA/")?;
                self.motion(rec, line, column, p + d, None)?;
            }
            "RAPID" => self.rapid_next = true,
            // NX writes the home itself (`RAPID` then `GOHOME/x,y,z[,i,j,k]`): a move there,
            // never a drilled hole. Only the bare record means the `FROM/` point.
            "GOHOME" if !fields.is_empty() => self.goto(rec, &fields, "GOHOME/")?,
            "GOHOME" => match self.from {
                Some(home) => self.motion(rec, line, column, home, None)?,
                None => self.warn(
                    line,
                    column,
                    "GOHOME without a FROM/ before it ignored: the home is unknown".into(),
                ),
            },
            "FEDRAT" => self.fedrat(rec, &fields, minor_off, line)?,
            "CIRCLE" => {
                // A trailing direction word (SolidWorks CAM: `…,COUNTERCLOCKWISE`) states the
                // sense and overrides the file's convention.
                let mut fields = fields.clone();
                let mut sense = None;
                while let Some(f) = fields.last() {
                    match f.text.to_ascii_uppercase().as_str() {
                        "CLW" | "CW" | "CLOCKWISE" => sense = Some(true),
                        "CCLW" | "CCW" | "COUNTERCLOCKWISE" => sense = Some(false),
                        _ => break,
                    }
                    fields.pop();
                }
                let v = self.numbers(rec, &fields, "CIRCLE/")?;
                if v.len() < 6 {
                    return Err(self.count_error(
                        rec,
                        &fields,
                        minor_off,
                        "CIRCLE/",
                        "xc,yc,zc,i,j,k[,r,…]",
                    ));
                }
                let axis = self.vector(Vec3::new(v[3], v[4], v[5]));
                let Some(axis) = unit(axis) else {
                    return Err(self.error(
                        rec,
                        fields[3].off,
                        PathErrorKind::Semantic,
                        "CIRCLE/ with a zero axis",
                        minor_text,
                        "a non-zero axis vector i,j,k",
                    ));
                };
                let normal = if sense.unwrap_or(self.clockwise) {
                    -axis
                } else {
                    axis
                };
                let center = self.point(Vec3::new(v[0], v[1], v[2]));
                self.check_range(rec, &fields, &v[..3], center, "CIRCLE/")?;
                let radius = v.get(6).map(|r| r * self.scale);
                if self.circle.is_some() {
                    self.warn(
                        line,
                        column,
                        "CIRCLE/ replaces an earlier one not yet used".into(),
                    );
                }
                self.circle = Some(PendingCircle {
                    center,
                    normal,
                    radius,
                    line,
                    column,
                });
            }
            "CUTTER" => {
                let v = self.numbers(rec, &fields, "CUTTER/")?;
                if v.is_empty() || v.len() > 7 {
                    return Err(self.count_error(
                        rec,
                        &fields,
                        minor_off,
                        "CUTTER/",
                        "1 to 7 numbers d,r,e,f,α,β,h",
                    ));
                }
                let mut c = [0.0; 7];
                for (i, x) in v.iter().enumerate() {
                    // α and β are angles; the rest lengths.
                    c[i] = if i == 4 || i == 5 { *x } else { x * self.scale };
                }
                // APT's short forms imply the corner centre: `CUTTER/d` is a flat end mill and
                // `CUTTER/d,r` a toroidal one, e = d/2 − r and f = r. A missing h stays 0,
                // which means "not given" to consumers (they choose a default length).
                if v.len() < 3 {
                    c[2] = 0.5 * c[0] - c[1];
                }
                if v.len() < 4 {
                    c[3] = c[1];
                }
                self.sink.emit(line, &Canon::CutterDefinition(c));
            }
            "TLDATA" => self.tldata(rec, &fields, line, column)?,
            "MULTAX" | "PAINT" | "COOLNT" | "SELCTL" | "END-OF-PATH" | "STOP" | "OPSTOP"
            | "TOOLNO" | "END" | "REWIND" | "MACHIN" => {}
            "INDIRV" => {
                let v = self.numbers(rec, &fields, "INDIRV/")?;
                if v.len() != 3 {
                    return Err(self.count_error(rec, &fields, minor_off, "INDIRV/", "i,j,k"));
                }
                self.indirv = Some(self.vector(Vec3::new(v[0], v[1], v[2])));
            }
            "TLAXIS" => match self.numbers(rec, &fields, "TLAXIS/") {
                Ok(v) if v.len() == 3 => {
                    let Some(a) = unit(self.vector(Vec3::new(v[0], v[1], v[2]))) else {
                        return Err(self.error(
                            rec,
                            minor_off,
                            PathErrorKind::Semantic,
                            "zero tool axis",
                            minor_text,
                            "a non-zero tool axis i,j,k",
                        ));
                    };
                    // The axis of the GOTOs that give none, from the next one on.
                    self.state_axis(line, Some(a));
                }
                // `TLAXIS/NORMAL,…` and other part-program forms: no axis to take.
                _ => self.warn(
                    line,
                    column,
                    format!("TLAXIS/{minor_text} ignored: only TLAXIS/i,j,k states an axis"),
                ),
            },
            "UNITS" | "UNIT" => {
                let u = match word(0).as_deref() {
                    Some("MM" | "MILLIMETERS" | "MILLIMETRES") => Units::Mm,
                    Some("INCHES" | "INCH" | "IN") => Units::Inch,
                    _ => {
                        let f = fields.first().map_or(("", minor_off), |f| (f.text, f.off));
                        return Err(self.error(
                            rec,
                            f.1,
                            PathErrorKind::Syntax,
                            "unknown units",
                            f.0,
                            "MM or INCHES",
                        ));
                    }
                };
                self.scale = u.mm_per_unit();
                self.units_stated = true;
                self.sink.emit(line, &Canon::Units(u));
            }
            "LOADTL" => {
                let f = fields.first().copied().unwrap_or(Field {
                    text: "",
                    off: minor_off,
                });
                let tool = self.tool_number(rec, f)?;
                self.sink.emit(line, &Canon::ToolChange { tool });
            }
            "LOAD" => {
                if word(0).as_deref() != Some("TOOL") || fields.len() < 2 {
                    let f = fields.first().map_or(("", minor_off), |f| (f.text, f.off));
                    return Err(self.error(
                        rec,
                        f.1,
                        PathErrorKind::Syntax,
                        "LOAD/ needs TOOL and a tool number",
                        f.0,
                        "TOOL,n",
                    ));
                }
                let tool = self.tool_number(rec, fields[1])?;
                self.sink.emit(line, &Canon::ToolChange { tool });
            }
            "SPINDL" => self.spindl(rec, &fields, line, column)?,
            "PARTNO" | "PPRINT" | "REMARK" | "TPRINT" | "TOOL PATH" => {
                self.sink
                    .emit(line, &Canon::Comment(Cow::Borrowed(minor_text)));
            }
            "INSERT" => {
                self.sink
                    .emit(line, &Canon::Comment(Cow::Borrowed(minor_text)));
                self.warn(
                    line,
                    column,
                    format!(
                        "INSERT/{minor_text}: controller text passed on verbatim, not interpreted"
                    ),
                );
            }
            "CUTCOM" => match word(0).as_deref() {
                Some("OFF") | None => {}
                Some(side) => self.warn(
                    line,
                    column,
                    format!(
                        "CUTCOM/{side}: the controller is asked to offset the path by the cutter \
                         radius from here; swarf simulates the CL points as written \
                         (uncompensated). CL data is normally the compensated cutter path \
                         already — check the post-processor"
                    ),
                ),
            },
            "MSYS" => self.msys(rec, &fields, minor_off, line, column, minor_text)?,
            "CSYS" => self.csys(rec, &fields, minor_off, line, column)?,
            "TRNTYP" => {
                if word(0).as_deref() != Some("WORLD") {
                    self.warn(line, column, format!("TRNTYP/{minor_text} ignored"));
                }
            }
            "FINI" => {
                self.unused_circle();
                self.sink.emit(line, &Canon::ProgramEnd);
                return Ok(Flow::Stop);
            }
            "DELAY" => self.delay(rec, &fields, minor_off, line)?,
            "CYCLE" => self.cycle_record(rec, &fields, minor_off)?,
            "NURBS" | "KNOT" | "CNTRL" => {
                return Err(self.error(
                    rec,
                    lead,
                    PathErrorKind::Unsupported,
                    "NURBS/ tool paths (KNOT/, CNTRL/ records) are not read, so their motion \
                     would be missing from the simulation",
                    text.trim(),
                    "the path output as GOTO/ points (linearised in the CAM system)",
                ));
            }
            // APT part-program motion (ANSI X3.37: drive, part and check surfaces), and any
            // other motion word: only the APT processor knows where it goes, and a warning
            // would silently drop the motion.
            m if m.starts_with("GO") || m == "PSIS" || m == "INDIRP" => {
                return Err(self.error(
                    rec,
                    lead,
                    PathErrorKind::Unsupported,
                    format!(
                        "`{major_raw}` is an APT part-program motion statement (or an unknown \
                         motion word), not CL data: its motion cannot be read"
                    ),
                    text.trim(),
                    "CL data (GOTO/, GODLTA/, CIRCLE/): run the part program through the APT \
                     processor or the CAM system's CL output first",
                ));
            }
            _ => self.warn(
                line,
                column,
                format!("unknown record `{major_raw}` ignored"),
            ),
        }
        Ok(Flow::Go)
    }

    /// A pending `CIRCLE/` that no `GOTO/` used.
    fn unused_circle(&mut self) {
        if let Some(c) = self.circle.take() {
            self.warn(
                c.line,
                c.column,
                "CIRCLE/ not followed by a GOTO/ before the end: ignored".into(),
            );
        }
    }

    /// `DELAY/t` (seconds) or `DELAY/n,REV` (spindle revolutions).
    fn delay(
        &mut self,
        rec: &Record<'_>,
        fields: &[Field<'_>],
        minor_off: usize,
        line: u32,
    ) -> Result<(), PathError> {
        // The unit word on either side of the time (`DELAY/5,REV`, `DELAY/REV,5`).
        let mut revolutions = None;
        let mut time = None;
        for f in fields {
            match f.text.to_ascii_uppercase().as_str() {
                "REV" | "REVS" if revolutions.is_none() => revolutions = Some(true),
                "SEC" | "SECS" if revolutions.is_none() => revolutions = Some(false),
                w if time.is_none() && !w.chars().all(|c| c.is_ascii_alphabetic()) => {
                    time = Some(f);
                }
                _ => {
                    return Err(self.error(
                        rec,
                        f.off,
                        PathErrorKind::Syntax,
                        "unexpected DELAY/ word",
                        f.text,
                        "a time and REV (revolutions) or SEC (seconds, the default)",
                    ))
                }
            }
        }
        let Some(first) = time else {
            return Err(self.count_error(rec, fields, minor_off, "DELAY/", "a time in seconds"));
        };
        let first = *first;
        let v = self.number(rec, first, "DELAY/")?;
        if v < 0.0 {
            return Err(self.error(
                rec,
                first.off,
                PathErrorKind::Semantic,
                "DELAY/ with a negative time",
                first.text,
                "a time of 0 or more",
            ));
        }
        let revolutions = revolutions.unwrap_or(false);
        let seconds = if !revolutions {
            v
        } else if self.spindle_rpm > 0.0 {
            v * 60.0 / self.spindle_rpm
        } else {
            let (l, c) = rec.locate(first.off);
            self.warn(
                l,
                c,
                format!("DELAY/{v},REV with the spindle stopped: no time counted"),
            );
            0.0
        };
        self.sink.emit(line, &Canon::Dwell(seconds));
        Ok(())
    }

    /// `MSYS/x,y,z,xi,xj,xk,yi,yj,yk`: the MCS's origin and X and Y axes in absolute
    /// coordinates (NX). Points are in the current MCS. The first MCS is swarf's workpiece
    /// frame; the points of an operation under a different MCS (another setup, a 3+2 side
    /// face) are mapped into it: `p₁ = M₁ᵀ(O₂ + M₂·p − O₁)`.
    fn msys(
        &mut self,
        rec: &Record<'_>,
        fields: &[Field<'_>],
        minor_off: usize,
        line: u32,
        column: u32,
        minor_text: &str,
    ) -> Result<(), PathError> {
        let v = self.numbers(rec, fields, "MSYS/")?;
        if v.len() != 9 {
            return Err(self.count_error(
                rec,
                fields,
                minor_off,
                "MSYS/",
                "x,y,z,xi,xj,xk,yi,yj,yk (origin, X axis, Y axis)",
            ));
        }
        let origin = Vec3::new(v[0], v[1], v[2]) * self.scale;
        let axes = unit(Vec3::new(v[3], v[4], v[5])).zip(unit(Vec3::new(v[6], v[7], v[8])));
        let frame = match axes {
            Some((x, y)) if x.dot(y).abs() <= 1e-4 => {
                // Posts print the axes to 6–7 digits: made exactly perpendicular.
                let y = unit(y - x * x.dot(y)).unwrap_or(y);
                Mat3::from_cols(x, y, x.cross(y))
            }
            _ => {
                return Err(self.error(
                    rec,
                    fields[3].off,
                    PathErrorKind::Semantic,
                    "MSYS/ axes that are zero or not perpendicular",
                    minor_text,
                    "two perpendicular axes xi,xj,xk and yi,yj,yk",
                ))
            }
        };
        match &mut self.msys {
            None => {
                let identity = frame.abs_diff_eq(Mat3::IDENTITY, 1e-9) && origin.length() <= 1e-9;
                if !identity {
                    self.warn(
                        line,
                        column,
                        format!(
                            "MSYS/{minor_text}: the MCS sits elsewhere in absolute coordinates; \
                             points are used in the MCS, which is swarf's workpiece frame"
                        ),
                    );
                }
                self.msys = Some(Msys {
                    first: (frame, origin, line),
                    to_first: None,
                });
            }
            Some(m) => {
                let (f1, o1, first_line) = m.first;
                let r = f1.transpose() * frame;
                let t = f1.transpose() * (origin - o1);
                let same = r.abs_diff_eq(Mat3::IDENTITY, 1e-9) && t.length() <= 1e-9;
                m.to_first = (!same).then_some((r, t));
                if !same {
                    self.warn(
                        line,
                        column,
                        format!(
                            "MSYS/{minor_text}: another MCS than the first (line {first_line}): \
                             the points and axes that follow are mapped into the first, \
                             swarf's workpiece frame"
                        ),
                    );
                }
                // The GOTOs of the operation that give no axis have the MCS's Z (NX writes
                // `GOTO/x,y,z` for fixed-axis operations): from the next move on, mapped.
                let z = r * Vec3::Z;
                self.state_axis(line, Some(z));
            }
        }
        Ok(())
    }

    /// CATIA's circular motion, `TLON,GOFWD/ (CIRCLE/ xc,yc,zc[,i,j,k],r), ON, (LINE/ x1,y1,z1,
    /// x2,y2,z2)` after `INDIRV/ i,j,k`: the tool goes forward from where it stands, in the
    /// direction `INDIRV/` gives, along the circle (about the tool axis when the circle gives
    /// none) until it is on the line. CATIA writes the line from the centre to the arc's end,
    /// and a line through the centre, written either way round, is read so (the end is on the
    /// ray from the centre towards its far point); another line ends the arc where the tool
    /// first meets it. The arc is planar: the end is at the start's height along the axis.
    fn gofwd(&mut self, rec: &Record<'_>, minor_off: usize) -> Result<(), PathError> {
        let text = rec.text.as_str();
        let (line, column) = rec.locate(text.len() - text.trim_start().len());
        let upper = text.to_ascii_uppercase();
        // The numbers of `(NAME/ …)` from `from` on, with the offset of the `(`.
        let group = |name: &str, from: usize| -> Option<(usize, Vec<Field<'_>>, usize)> {
            let open = from + upper[from..].find('(')?;
            let head = upper[open + 1..].trim_start();
            if !head.starts_with(name) {
                return None;
            }
            let slash = open + 1 + upper[open + 1..].find('/')?;
            let close = slash + upper[slash..].find(')')?;
            let mut fields = Vec::new();
            let mut off = slash + 1;
            for piece in text[slash + 1..close].split(',') {
                let pad = piece.len() - piece.trim_start().len();
                fields.push(Field {
                    text: piece.trim(),
                    off: off + pad,
                });
                off += piece.len() + 1;
            }
            Some((open, fields, close + 1))
        };
        let form = "(CIRCLE/ xc,yc,zc[,i,j,k],r), ON, (LINE/ x1,y1,z1,x2,y2,z2)";
        let bad = |me: &Self, off: usize, what: &str| {
            me.error(
                rec,
                off,
                PathErrorKind::Syntax,
                format!("TLON,GOFWD/: {what}"),
                text[minor_off.min(text.len())..].trim(),
                form,
            )
        };
        let Some((_, cf, after_circle)) = group("CIRCLE", minor_off) else {
            return Err(bad(self, minor_off, "no (CIRCLE/ …) after the slash"));
        };
        let c = self.numbers(rec, &cf, "CIRCLE/")?;
        if c.len() != 4 && c.len() != 7 {
            return Err(bad(self, cf[0].off, "CIRCLE/ needs 4 or 7 numbers"));
        }
        let Some(k) = upper[after_circle..].find('(') else {
            return Err(bad(self, after_circle, "no (LINE/ …) after the circle"));
        };
        let modifier: String = upper[after_circle..after_circle + k]
            .chars()
            .filter(|c| c.is_ascii_alphabetic())
            .collect();
        if modifier != "ON" {
            return Err(self.error(
                rec,
                after_circle,
                PathErrorKind::Unsupported,
                format!(
                    "TLON,GOFWD/ ending {} the check line is not read; CATIA's circles end ON it",
                    if modifier.is_empty() {
                        "without a modifier"
                    } else {
                        &modifier
                    }
                ),
                text[after_circle..].trim(),
                "ON",
            ));
        }
        let Some((_, lf, _)) = group("LINE", after_circle) else {
            return Err(bad(self, after_circle, "no (LINE/ …) after ON"));
        };
        let l = self.numbers(rec, &lf, "LINE/")?;
        if l.len() != 6 {
            return Err(bad(self, lf[0].off, "LINE/ needs 6 numbers"));
        }
        let Some(start) = self.pos else {
            return Err(self.error(
                rec,
                minor_off,
                PathErrorKind::Semantic,
                "TLON,GOFWD/ before any position is known",
                text.trim(),
                "a GOTO/ or FROM/ first",
            ));
        };
        let Some(dir) = self.indirv.take() else {
            return Err(self.error(
                rec,
                minor_off,
                PathErrorKind::Semantic,
                "TLON,GOFWD/ without an INDIRV/ before it: the direction along the circle is \
                 unknown",
                text.trim(),
                "INDIRV/i,j,k before the circle",
            ));
        };
        let center = self.point(Vec3::new(c[0], c[1], c[2]));
        self.check_range(rec, &cf, &c[..3], center, "CIRCLE/")?;
        let axis = if c.len() == 7 {
            self.vector(Vec3::new(c[3], c[4], c[5]))
        } else {
            self.axis
        };
        let Some(axis) = unit(axis) else {
            return Err(bad(self, cf[3].off, "the circle's axis is zero"));
        };
        let radius = c[c.len() - 1] * self.scale;
        let p1 = self.point(Vec3::new(l[0], l[1], l[2]));
        let p2 = self.point(Vec3::new(l[3], l[4], l[5]));
        self.check_range(rec, &lf, &l[..3], p1, "LINE/")?;
        self.check_range(rec, &lf[3..], &l[3..], p2, "LINE/")?;
        let flat = |v: Vec3| v - axis * axis.dot(v);
        let s = flat(start - center);
        let ccw = axis.cross(s).dot(dir) >= 0.0;
        let n = if ccw { axis } else { -axis };
        let tol = self.options.arc_tolerance_mm.max(1e-9 * radius);
        let (d1, d2) = (flat(p1 - center), flat(p2 - center));
        // The arc is planar: its end is at the start's height along the circle's axis, whatever
        // the heights of the centre and the line.
        let height = axis * axis.dot(start - center);
        let ray = match (d1.length() <= tol, d2.length() <= tol) {
            // A line from the centre (written centre → end or end → centre): the end is on the
            // ray from the centre towards its far point.
            (true, false) => Some(d2),
            (false, true) => Some(d1),
            _ => None,
        };
        let end = if let Some(far) = ray {
            center + far.normalize() * radius + height
        } else {
            // Where the circle meets the line (in the plane), first reached going forward.
            let u = d2 - d1;
            let (a, b, cc) = (u.dot(u), 2.0 * d1.dot(u), d1.dot(d1) - radius * radius);
            let disc = b * b - 4.0 * a * cc;
            if a <= tol * tol || disc < 0.0 {
                return Err(self.error(
                    rec,
                    lf[0].off,
                    PathErrorKind::Semantic,
                    "TLON,GOFWD/: the circle never meets the line",
                    text[minor_off..].trim(),
                    "a LINE/ that crosses the CIRCLE/",
                ));
            }
            let sweep = |q: Vec3| {
                let x = s.normalize_or_zero();
                let y = n.cross(x);
                let t = q.dot(y).atan2(q.dot(x));
                if t <= 1e-9 {
                    t + std::f64::consts::TAU
                } else {
                    t
                }
            };
            let hit = [-1.0, 1.0]
                .map(|sg| d1 + u * ((-b + sg * disc.sqrt()) / (2.0 * a)))
                .into_iter()
                .min_by(|p, q| sweep(*p).total_cmp(&sweep(*q)))
                .unwrap_or(d2);
            center + hit + height
        };
        self.circle = Some(PendingCircle {
            center,
            normal: n,
            radius: Some(radius),
            line,
            column,
        });
        self.motion(rec, line, column, end, None)
    }

    fn count_error(
        &self,
        rec: &Record<'_>,
        fields: &[Field<'_>],
        minor_off: usize,
        what: &str,
        expected: &str,
    ) -> PathError {
        let found = rec.text.get(minor_off..).unwrap_or("").trim();
        let off = fields.first().map_or(minor_off, |f| f.off);
        self.error(
            rec,
            off,
            PathErrorKind::Syntax,
            format!("{what} with {} value(s)", fields.len()),
            found,
            expected,
        )
    }

    fn tool_number(&self, rec: &Record<'_>, f: Field<'_>) -> Result<u32, PathError> {
        let v = self.number(rec, f, "tool number")?;
        if v < 0.0 || v.fract() != 0.0 || v > f64::from(u32::MAX) {
            return Err(self.error(
                rec,
                f.off,
                PathErrorKind::Semantic,
                "bad tool number",
                f.text,
                "a non-negative whole number",
            ));
        }
        Ok(v as u32)
    }

    fn goto(
        &mut self,
        rec: &Record<'_>,
        fields: &[Field<'_>],
        what: &'static str,
    ) -> Result<(), PathError> {
        // `what` is the record: `GOTO/`, `FROM/` (a start, no move) or `GOHOME/` (a move that
        // is no hole of a cycle).
        let from = what == "FROM/";
        let v = self.numbers(rec, fields, what)?;
        let minor_off = fields.first().map_or(rec.text.len(), |f| f.off);
        if !(v.len() == 3 || v.len() >= 6) {
            return Err(self.count_error(rec, fields, minor_off, what, "x,y,z or x,y,z,i,j,k"));
        }
        let (line, column) = rec.locate(minor_off);
        if v.len() > 6 && !self.extra_goto_warned {
            self.extra_goto_warned = true;
            self.warn(
                line,
                column,
                format!("{what} values after the sixth ignored (first such record)"),
            );
        }
        let p = self.point(Vec3::new(v[0], v[1], v[2]));
        self.check_range(rec, fields, &v[..3], p, what)?;
        let axis = if v.len() >= 6 {
            let a = self.vector(Vec3::new(v[3], v[4], v[5]));
            match unit(a) {
                Some(a) => Some(a),
                None => {
                    return Err(self.error(
                        rec,
                        fields[3].off,
                        PathErrorKind::Semantic,
                        "zero tool axis",
                        fields[3].text,
                        "a non-zero tool axis i,j,k",
                    ))
                }
            }
        } else {
            None
        };
        if let ("GOTO/", Some(c)) = (what, self.cycle) {
            self.drill(line, c, p, axis);
            return Ok(());
        }
        if from {
            self.from = Some(p);
        }
        if from || self.pos.is_none() {
            if let Some(c) = self.circle.take() {
                self.warn(
                    c.line,
                    c.column,
                    "CIRCLE/ before the first position ignored".into(),
                );
            }
            self.rapid_next = false;
            self.state_axis(line, axis);
            self.sink.emit(line, &Canon::SetPosition(axes(p)));
            self.pos = Some(p);
            return Ok(());
        }
        self.motion(rec, line, column, p, axis)
    }

    /// Emits the tool axis when it is new (always once, before the first position).
    fn state_axis(&mut self, line: u32, axis: Option<Vec3>) {
        let a = axis.unwrap_or(self.axis);
        if !self.axis_stated || a != self.axis {
            self.axis = a;
            self.axis_stated = true;
            self.sink.emit(line, &Canon::ToolAxis(a.to_array()));
        }
    }

    fn motion(
        &mut self,
        rec: &Record<'_>,
        line: u32,
        column: u32,
        end: Vec3,
        axis: Option<Vec3>,
    ) -> Result<(), PathError> {
        let start = self.pos.unwrap_or(end);
        self.state_axis(line, axis);
        let rapid = std::mem::take(&mut self.rapid_next);
        let Some(c) = self.circle.take() else {
            let e = axes(end);
            let ev = if rapid {
                Canon::Traverse { end: e }
            } else {
                Canon::Feed { end: e }
            };
            self.sink.emit(line, &ev);
            self.pos = Some(end);
            return Ok(());
        };
        if rapid {
            self.warn(
                line,
                column,
                "RAPID before a circular move ignored: the arc is a feed".into(),
            );
        }
        let n = c.normal;
        let r0 = ((start - c.center) - n * n.dot(start - c.center)).length();
        let r1 = ((end - c.center) - n * n.dot(end - c.center)).length();
        if r0 < 1e-9 {
            return Err(self.error(
                rec,
                0,
                PathErrorKind::Semantic,
                format!("arc from CIRCLE/ on line {} starts at its centre", c.line),
                rec.text.trim(),
                "a start point away from the circle's axis",
            ));
        }
        let tol = self.options.arc_tolerance_mm.max(1e-6 * r0);
        let given = c.radius.unwrap_or(r0);
        if (r0 - r1).abs() > tol || (r0 - given).abs() > tol {
            self.warn(
                line,
                column,
                format!(
                    "arc radii disagree beyond {tol} mm: start {r0:.6}, end {r1:.6}, CIRCLE/ \
                     {given:.6} (line {}); the tool spirals from start to end radius",
                    c.line
                ),
            );
        }
        let e = axes(end);
        let principal = [(Plane::YZ, 0), (Plane::XZ, 1), (Plane::XY, 2)]
            .into_iter()
            .find(|&(_, k)| (n[k].abs() - 1.0).abs() < 1e-12);
        let ev = match principal {
            Some((plane, k)) => {
                let (i1, i2, _) = plane.axes();
                Canon::Arc {
                    end: e,
                    center: [c.center[i1], c.center[i2]],
                    rotation: if n[k] > 0.0 { 1 } else { -1 },
                    plane,
                }
            }
            None => Canon::ArcAxis {
                end: e,
                center: c.center.to_array(),
                normal: n.to_array(),
                turns: 1,
            },
        };
        self.sink.emit(line, &ev);
        self.pos = Some(end);
        Ok(())
    }

    fn fedrat(
        &mut self,
        rec: &Record<'_>,
        fields: &[Field<'_>],
        minor_off: usize,
        line: u32,
    ) -> Result<(), PathError> {
        let mut value = None;
        let mut mode = None;
        for f in fields {
            match f.text.to_ascii_uppercase().as_str() {
                "MMPM" => mode = Some((FeedMode::PerMinute, 1.0)),
                "IPM" => mode = Some((FeedMode::PerMinute, 25.4)),
                "MMPR" => mode = Some((FeedMode::PerRevolution, 1.0)),
                "IPR" => mode = Some((FeedMode::PerRevolution, 25.4)),
                _ if value.is_none() => value = Some(self.number(rec, *f, "FEDRAT/")?),
                _ => {
                    return Err(self.error(
                        rec,
                        f.off,
                        PathErrorKind::Syntax,
                        "unexpected FEDRAT/ value",
                        f.text,
                        "MMPM, IPM, MMPR or IPR",
                    ))
                }
            }
        }
        let Some(v) = value else {
            return Err(self.count_error(
                rec,
                fields,
                minor_off,
                "FEDRAT/",
                "a feed rate, e.g. FEDRAT/MMPM,500",
            ));
        };
        if v < 0.0 {
            let f = fields
                .iter()
                .find(|f| {
                    !matches!(
                        f.text.to_ascii_uppercase().as_str(),
                        "MMPM" | "IPM" | "MMPR" | "IPR"
                    )
                })
                .copied()
                .unwrap_or(fields[0]);
            return Err(self.error(
                rec,
                f.off,
                PathErrorKind::Semantic,
                "FEDRAT/ with a negative feed rate",
                f.text,
                "a feed rate of 0 or more",
            ));
        }
        if let Some((_, s)) = mode {
            if s != 1.0 && !self.units_stated && self.scale == 1.0 && !self.inch_feed_warned {
                self.inch_feed_warned = true;
                let (l, c) = rec.locate(minor_off);
                self.warn(
                    l,
                    c,
                    "an inch feed in a file that states no UNITS/: its lengths are read as mm \
                     (give --initial-units inch if the file is in inches)"
                        .into(),
                );
            }
        }
        let (mode, scale) = match mode {
            Some((m, s)) => {
                self.feed_unit = Some(s);
                (m, s)
            }
            None => {
                if self.feed_mode == FeedMode::PerRevolution {
                    let (l, c) = rec.locate(minor_off);
                    self.warn(
                        l,
                        c,
                        "FEDRAT/ without IPM, MMPM, IPR or MMPR read per revolution, the mode of \
                         the FEDRAT/ before it (posts keep the mode until a record states \
                         another)"
                            .into(),
                    );
                }
                (self.feed_mode, self.feed_unit.unwrap_or(self.scale))
            }
        };
        if mode != self.feed_mode {
            self.feed_mode = mode;
            self.sink.emit(line, &Canon::FeedMode(mode));
        }
        self.sink.emit(line, &Canon::FeedRate(v * scale));
        self.program_feed = Some(v * scale);
        Ok(())
    }

    fn spindl(
        &mut self,
        rec: &Record<'_>,
        fields: &[Field<'_>],
        line: u32,
        column: u32,
    ) -> Result<(), PathError> {
        let mut rpm = None;
        let mut dir = self.spindle_dir;
        for f in fields {
            match f.text.to_ascii_uppercase().as_str() {
                "RPM" | "" => {}
                "CLW" => dir = SpindleDir::Clockwise,
                "CCLW" | "CCW" => dir = SpindleDir::CounterClockwise,
                "OFF" => {
                    self.sink.emit(
                        line,
                        &Canon::Spindle {
                            rpm: self.spindle_rpm,
                            dir: SpindleDir::Stopped,
                        },
                    );
                    return Ok(());
                }
                "ON" => {}
                "SFM" | "SMM" => {
                    self.warn(
                        line,
                        column,
                        "SPINDL/ surface speed not supported: spindle unchanged".into(),
                    );
                    return Ok(());
                }
                "RANGE" | "MAXRPM" => break,
                _ if rpm.is_none() => rpm = Some(self.number(rec, *f, "SPINDL/")?),
                _ => {}
            }
        }
        if let Some(r) = rpm {
            self.spindle_rpm = r.abs();
        }
        self.spindle_dir = dir;
        self.sink.emit(
            line,
            &Canon::Spindle {
                rpm: self.spindle_rpm,
                dir,
            },
        );
        Ok(())
    }

    /// NX CLSF's tool record, converted to the APT generic cutter `CUTTER/` makes (d, r, e,
    /// f, α, β, h): an operation that writes no `LOAD/TOOL` must cut with this cutter, not the
    /// previous operation's, so what cannot be converted is an error here.
    ///
    /// * `TLDATA/MILL,D,R,L[,B,A]` (NX's 5-parameter mill as its CLSF writes it: diameter,
    ///   lower radius, length, taper angle B of the side from the axis, tip angle A of the
    ///   bottom from the horizontal). D is taken as the diameter through the lower radius'
    ///   centre (e = D/2 − R): the ball's diameter for NX's ball mill (R = D/2, tapered or
    ///   not, so the ball stays a ball) and the plain diameter of an untapered tool; the
    ///   APT d, where the radius meets the side, is then 2·(e + R·cos B). (Assumption: for a
    ///   tapered tool with 0 < R < D/2 NX's dialog may measure D elsewhere; we have not
    ///   checked it against NX.)
    /// * `TLDATA/DRILL,D,R,L,PA[,…]`: diameter, corner radius, length, point angle (the
    ///   included angle, 118° for a common twist drill), then the flute length, unused. This
    ///   order is NX's drill parameters D, R1, L, PA, FL as we believe its CLSF writes them
    ///   (assumed from NX's tool dialog and posts' output, not from a specification).
    ///
    /// Other tool types (turning, threading…) keep the warning: swarf has no cutter for them.
    fn tldata(
        &mut self,
        rec: &Record<'_>,
        fields: &[Field<'_>],
        line: u32,
        column: u32,
    ) -> Result<(), PathError> {
        let kind = fields
            .first()
            .map(|f| f.text.to_ascii_uppercase())
            .unwrap_or_default();
        let (what, form, least) = match kind.as_str() {
            "MILL" => ("TLDATA/MILL", "MILL,d,r[,h,taper,tip]", 2),
            "DRILL" => ("TLDATA/DRILL", "DRILL,d,r,h,point angle[,…]", 4),
            _ => {
                self.warn(line, column, format!("TLDATA/{kind}: tool type not converted; define it with CUTTER/ or a tool table"));
                return Ok(());
            }
        };
        let v = self.numbers(rec, &fields[1..], what)?;
        if v.len() < least {
            return Err(self.count_error(rec, fields, fields[0].off, "TLDATA/", form));
        }
        let (d, r) = (v[0] * self.scale, v[1] * self.scale);
        let h = v.get(2).map_or(0.0, |h| h * self.scale);
        // The angles, degrees: β the side's from the axis, α the bottom's from the horizontal.
        let (beta, alpha) = if kind == "DRILL" {
            let point = v[3];
            if !(point > 0.0 && point <= 180.0) {
                return Err(self.error(
                    rec,
                    fields[4].off,
                    PathErrorKind::Semantic,
                    "TLDATA/DRILL point angle out of range",
                    fields[4].text,
                    "an included point angle in (0°, 180°] (118 for a twist drill)",
                ));
            }
            (0.0, 90.0 - point / 2.0)
        } else {
            (
                v.get(3).copied().unwrap_or(0.0),
                v.get(4).copied().unwrap_or(0.0),
            )
        };
        if kind == "MILL" {
            // Angles an APT cutter cannot have: a side past the horizontal, a bottom dished
            // upwards (negative tip angle) or steeper than the side it meets.
            let bad = if !(beta > -90.0 && beta < 90.0) {
                Some((4, "a taper angle in (-90°, 90°) from the tool axis"))
            } else if !(0.0..90.0).contains(&alpha) {
                Some((5, "a tip angle in [0°, 90°) from the horizontal"))
            } else if alpha + beta > 90.0 {
                Some((
                    5,
                    "a tip angle plus taper angle of at most 90° (the bottom meets the side)",
                ))
            } else {
                None
            };
            if let Some((i, expected)) = bad {
                return Err(self.error(
                    rec,
                    fields[i].off,
                    PathErrorKind::Semantic,
                    "TLDATA/MILL angle that makes no cutter",
                    fields[i].text,
                    expected,
                ));
            }
        }
        // The corner centre at e from the axis (see above), f above the tip where the bottom
        // through the tip is tangent to the corner: the numbers `CUTTER/` states, which the
        // cutter checks to 0.01 mm.
        let (a, b) = (alpha.to_radians(), beta.to_radians());
        let e = d / 2.0 - r;
        let f = (r + e * a.sin()) / a.cos();
        // NX's 7- and 10-parameter mills go on with the lower radius' centre X1 Y1 (then an
        // upper radius and its centre): read as the 5-parameter mill, which is exact where X1
        // Y1 are the centre D and R imply; otherwise say what is left out.
        if kind == "MILL" && v.len() > 5 {
            let centre = (v[5] * self.scale, v.get(6).map(|y| y * self.scale));
            // (To the printing of a post: the tolerance of the cutter's own check.)
            let off = (centre.0 - e).abs() > 0.01 || centre.1.is_some_and(|y| (y - f).abs() > 0.01);
            let upper = v.len() > 7 && v[7] != 0.0;
            if off || upper {
                self.warn(
                    line,
                    column,
                    format!(
                        "TLDATA/MILL with {} values: read as the 5-parameter mill (D, R, L, \
                         taper, tip angle) whose lower radius' centre is at {:.4} mm from the \
                         axis, {:.4} mm up; the file's centre X1 Y1{} is left out",
                        v.len(),
                        e,
                        f,
                        if upper { " and its upper radius" } else { "" },
                    ),
                );
            }
        }
        let apt_d = 2.0 * (e + r * b.cos());
        self.sink.emit(
            line,
            &Canon::CutterDefinition([apt_d, r, e, f, alpha, beta, h]),
        );
        Ok(())
    }

    fn csys(
        &mut self,
        rec: &Record<'_>,
        fields: &[Field<'_>],
        minor_off: usize,
        line: u32,
        column: u32,
    ) -> Result<(), PathError> {
        let v = self.numbers(rec, fields, "CSYS/")?;
        if v.len() != 12 {
            return Err(self.count_error(
                rec,
                fields,
                minor_off,
                "CSYS/",
                "12 numbers: a 3×4 matrix by rows",
            ));
        }
        let m = Mat3::from_cols(
            Vec3::new(v[0], v[4], v[8]),
            Vec3::new(v[1], v[5], v[9]),
            Vec3::new(v[2], v[6], v[10]),
        );
        let t = Vec3::new(v[3], v[7], v[11]);
        let orthonormal = (m.transpose() * m - Mat3::IDENTITY)
            .to_cols_array()
            .iter()
            .all(|x| x.abs() < 1e-6)
            && (m.determinant() - 1.0).abs() < 1e-6;
        if !orthonormal {
            return Err(self.error(
                rec,
                minor_off,
                PathErrorKind::Semantic,
                "CSYS/ matrix is not a rotation",
                rec.text.get(minor_off..).unwrap_or("").trim(),
                "an orthonormal right-handed 3×3 part",
            ));
        }
        let identity = (m - Mat3::IDENTITY)
            .to_cols_array()
            .iter()
            .all(|x| x.abs() < 1e-12)
            && t == Vec3::ZERO;
        if identity {
            self.csys = None;
        } else if self.options.apply_csys {
            self.csys = Some((m, t));
            self.warn(
                line,
                column,
                "CSYS/ applied: the points that follow are transformed into the workpiece frame"
                    .into(),
            );
        } else {
            self.warn(
                line,
                column,
                "CSYS/ not applied (option): points are kept in the local system".into(),
            );
        }
        Ok(())
    }
}

/// Where the text of a free-text record (`PARTNO`, `PPRINT`, `INSERT`, `REMARK`, `TPRINT`) starts — just
/// after its first word, written with or without a slash —, `None` for other records. Their
/// text is anything (`PPRINT TOOL DIA : 10.0`, `INSERT G0 X0.`), so it must not be read as
/// minor words.
fn text_record(text: &str) -> Option<usize> {
    let lead = text.len() - text.trim_start().len();
    let rest = &text[lead..];
    let end = rest
        .find(|c: char| c.is_whitespace() || c == '/')
        .unwrap_or(rest.len());
    ["PARTNO", "PPRINT", "INSERT", "REMARK", "TPRINT"]
        .iter()
        .any(|w| rest[..end].eq_ignore_ascii_case(w))
        .then_some(lead + end)
}

/// `v` made unit, scaled first by its largest component: a vector written with huge
/// components (`0,0,1e155`) is a direction, whose squared length would overflow. `None` for
/// a zero or non-finite vector.
fn unit(v: Vec3) -> Option<Vec3> {
    let m = v.abs().max_element();
    if !(m > 0.0 && m.is_finite()) {
        return None;
    }
    (v / m).try_normalize()
}
