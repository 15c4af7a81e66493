//! The G-code reader: RS274/NGC as LinuxCNC's interpreter (rs274ngc) reads it, plus the common
//! Fanuc forms (`M98 P.. L..` / `M99` subprograms, `O1234` labels).
//!
//! [`read_gcode`] streams over the program text line by line and hands each canonical event to
//! a [`CanonSink`]; it never keeps the program's motion. Positions in the events are in the
//! program's current coordinate system (work offsets are stated by [`Canon::Offsets`]
//! events, not applied), lengths in millimetres (inch programs are converted), angles in degrees
//! — the conventions of LinuxCNC's canon layer, so [`crate::canonical`] can print the events in
//! the exact form LinuxCNC's interpreter tests use.
//!
//! The modules follow the way a line is read:
//! `lexer` strips comments and spaces, `expr` evaluates numbers, parameters and bracketed
//! expressions, `block` collects the words of one block into fixed slots, `interp` executes a
//! block in LinuxCNC's order of execution, with `arcs` and `cycles` for circular moves and
//! canned cycles, `control` runs O-word control flow and subprograms over the reading cursor
//! and control stack of `stack` (which `interp` keeps: `control` extends the interpreter,
//! `interp` never reaches into `control`), `params` holds the numbered and named parameters
//! and `dialect` recognises programs for other controllers.
//!
//! # Language
//! * Motion: G0 G1 G2 G3 (I/J/K or R centres, full circles, helices, `P` turns), polar `@` `^`,
//!   G53, G28/G30 (+ G28.1/G30.1), canned cycles G73 G74 G81–G89 with G98/G99 and `L`
//!   (`cycles`), splines G5 G5.1 G5.2/G5.3 (`splines`, [`Canon::Spline`]).
//! * Cutter radius compensation G40 G41 G42 G41.1 G42.1 in G17/G18 (`comp`), radii from
//!   [`GcodeOptions::tool_diameters`].
//! * State: G17–G19, G20/G21, G90/G91, G90.1/G91.1, G93/G94/G95, G54–G59.3, G10 L2/L20 with R
//!   ([`Canon::XyRotation`]) (Fanuc: G10 L20 sets the additional offsets G54.1 P1–P300, also
//!   `G54 P`, Haas `G154 P`), G52, G92/G92.1/G92.2/G92.3, G43/G43.1/G49 (reported, positions not
//!   shifted: tool-tip programs), G61/G61.1/G64, G96/G97, G4, F S T M3 M4 M5 M6 M2 M30 (M0 M1
//!   M60 M7 M8 M9 and every other M code: warnings); Fanuc G68/G69 and G51/G50, and the
//!   tilted working plane G68.2/G53.1 ([`Canon::WorkPlane`]) (`frames`).
//! * Parameters `#1`–`#5601` (5161–5386 are views onto the G28/G30 positions and offsets,
//!   5401–5410 onto the loaded tool's offsets and diameter, in
//!   [`GcodeOptions::parameter_units`]; 5400–5413 and 5420–5428 read-only; 5021–5026 the machine position and 5420–5425 the
//!   position, in program units), `#<local>`, `#<_global>`, `#<_x>`, `#<_abs_x>` … and
//!   `#<_value>`/`#<_value_returned>`; bracketed expressions with LinuxCNC's operators,
//!   precedence and functions.
//! * O-words: `sub`/`endsub`/`call`/`return` (arguments `#1`–`#30`, return values), `o[expr]
//!   call`, subroutine files on [`GcodeOptions::subroutine_path`], `while`, `do`/`while`,
//!   `repeat`, `if`/`elseif`/`else`/`endif`, `break`, `continue`; Fanuc `M98 P L`/`M99` and
//!   Custom Macro B (`WHILE`/`DO`/`END`, `IF … GOTO`, `IF … THEN`, `GOTO`: `macro_b`), with
//!   its vacant variables: `#0` always, the locals #1–#33 and commons #100–#199, #500–#999
//!   until assigned (the others read 0, as in LinuxCNC). A word whose value is one is not
//!   written (`G1 X#110 Y20.` moves Y alone), a plain copy keeps it vacant (`#2=#1`), an
//!   operator, function, sign or bracket reads it as 0 (`#1*5`, `[#1]`), `EQ`/`NE` tell it
//!   from 0 (`#1 EQ #0` holds only when #1 is vacant), `GE GT LE LT` take it as 0, and
//!   `#0=…` is an error. Under LinuxCNC's rules nothing is vacant: an unset parameter is 0
//!   and `#0` is out of range.
//! * Comments in parentheses become [`Canon::Comment`], `(MSG,…)`/`(DEBUG,…)`/`(PRINT,…)`
//!   [`Canon::Message`]; `;` comments, `N` numbers, `/` block delete and `%` tape markers are
//!   understood; GRBL's `$` lines are skipped (or refused where they move the machine).
//! * Dialect: LinuxCNC or Fanuc rules where they differ ([`GcodeDialect`]).
//!
//! What is deliberately not simulated (lathe threading G76, probing, U V W axes, Siemens
//! programs) is rejected with [`PathErrorKind::Unsupported`] (Heidenhain programs have their
//! own reader, [`crate::heidenhain`], which [`crate::load`] chooses);
//! harmless codes swarf does not act on (coolant, overrides, user M codes) become warnings.
//!
//! ```
//! use swarf_path::{gcode, canon::Recorder, Canon};
//! let mut rec = Recorder::default();
//! gcode::read_gcode("G20 G0 X1\nG1 Y2 F10\nM2\n", "demo.ngc", &gcode::GcodeOptions::default(), &mut rec)?;
//! let feeds: Vec<_> = rec.events.iter().filter(|(_, e)| matches!(e, Canon::Feed { .. })).collect();
//! assert_eq!(feeds.len(), 1);
//! if let Canon::Feed { end } = &feeds[0].1 { assert!((end.y - 50.8).abs() < 1e-12) }
//! # Ok::<(), swarf_path::PathError>(())
//! ```

mod arcs;
mod block;
mod comp;
mod control;
mod cycles;
pub(crate) mod dialect;
mod expr;
mod frames;
mod ini;
mod interp;
pub(crate) mod lexer;
mod macro_b;
mod modal;
mod params;
mod splines;
mod stack;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::{CanonSink, PathError, PathErrorKind, SourcePos, Units};

#[cfg(doc)]
use crate::Canon;

pub use dialect::Dialect;
pub use ini::{LinuxCncIni, ToolChangeMoves};

/// How far the radius at the end of a centre-format arc may differ from the radius at its
/// start, LinuxCNC's rule: an arc is rejected when the absolute difference exceeds
/// `100 × abs`, or when it exceeds `abs` *and* the relative difference exceeds `relative`.
///
/// The defaults are LinuxCNC's `CENTER_ARC_RADIUS_TOLERANCE_INCH` (2 × 0.001 × √2 in),
/// `CENTER_ARC_RADIUS_TOLERANCE_MM` (2 × 0.01 × √2 mm) and `SPIRAL_RELATIVE_TOLERANCE` (0.001):
/// its `good-arc` tests move the centre of an arc by 0.99 of the tolerance along both axes
/// (0.00099 × √2 in, 0.0099 × √2 mm) and must be accepted.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArcTolerance {
    /// Absolute tolerance for inch programs, inches.
    pub abs_inch: f64,
    /// Absolute tolerance for millimetre programs, mm.
    pub abs_mm: f64,
    /// Relative tolerance (difference over the larger radius).
    pub relative: f64,
}

impl ArcTolerance {
    /// LinuxCNC's values.
    pub const LINUXCNC: Self = Self {
        abs_inch: 2.0 * 0.001 * std::f64::consts::SQRT_2,
        abs_mm: 2.0 * 0.01 * std::f64::consts::SQRT_2,
        relative: 0.001,
    };

    /// The absolute tolerance in mm for a program in `units`.
    pub fn abs_in_mm(&self, units: Units) -> f64 {
        match units {
            Units::Mm => self.abs_mm,
            Units::Inch => self.abs_inch * 25.4,
        }
    }
}

impl Default for ArcTolerance {
    fn default() -> Self {
        Self::LINUXCNC
    }
}

/// Options of the G-code reader. Every limit exists so that a hostile or broken program ends
/// quickly with [`PathErrorKind::Limit`] instead of hanging or exhausting memory.
#[derive(Clone, Debug, PartialEq)]
pub struct GcodeOptions {
    /// Length units in effect before the program's first G20/G21 (LinuxCNC: the machine's).
    pub initial_units: Units,
    /// Most backward jumps in one run: loop iterations (`while`, `do`, `repeat`), subroutine
    /// calls, `M98`/`M99` repeats, canned-cycle repeats and pecks all count.
    pub max_loop_iterations: u64,
    /// Most motion statements (rapids, feeds, arcs, splines; a canned cycle makes several):
    /// the limit that bounds the memory of a consumer that keeps the moves, default
    /// [`DEFAULT_MAX_MOVES`](crate::limit::DEFAULT_MAX_MOVES). `u64::MAX` for consumers that
    /// stream. See [`crate::limit`].
    pub max_moves: u64,
    /// Deepest nesting of subroutine calls (O-word `call` and `M98`).
    pub max_call_depth: usize,
    /// Largest count one `repeat`, `L` word or `M98 L` may ask for.
    pub max_repeat: u64,
    /// Arc end-radius tolerance.
    pub arc_radius_tolerance: ArcTolerance,
    /// When true, lines starting with `/` are skipped (the block-delete switch on); by default
    /// they are read, as LinuxCNC's rs274 reads them (its switch starts off), with a warning at
    /// the first.
    pub block_delete: bool,
    /// Tool diameters by tool number, mm: what cutter radius compensation (`G41`/`G42`, with
    /// `D<tool>` or the loaded tool) offsets by. LinuxCNC takes them from its tool table.
    pub tool_diameters: BTreeMap<u32, f64>,
    /// Tool offsets by tool number (X Y Z mm, A B C degrees, machine frame): the tool table's
    /// (LinuxCNC `.tbl` `X Y Z A B C` words; Z is the tool length), what `G43`/`G43 H` apply
    /// and #5401–#5406 read, as entries `G10 L1` sets (which replace them).
    pub tool_offsets: BTreeMap<u32, [f64; 6]>,
    /// Tool pockets by tool number (a LinuxCNC `.tbl`'s `P`): what `#<_current_pocket>` and
    /// `#<_selected_pocket>` read (a tool not listed: its own number, 0 for none).
    pub tool_pockets: BTreeMap<u32, u32>,
    /// Tool numbers by name (upper case), from a tool library that names its tools: what a
    /// Heidenhain `TOOL CALL "NAME"` or a Sinumerik `T="NAME"` loads.
    pub tool_names: BTreeMap<String, u32>,
    /// The diameter of a tool [`Self::tool_diameters`] does not list, mm (one cutter given for
    /// every tool); `None`: such a tool is an error when compensation needs it.
    pub default_tool_diameter: Option<f64>,
    /// Folders searched, after the program's own, for `name.ngc` when `o<name> call` names a
    /// subroutine the program does not define (LinuxCNC's `SUBROUTINE_PATH`).
    pub subroutine_path: Vec<PathBuf>,
    /// Units of the stored offset parameters (#5161–#5186, #5211–#5216, #5221–#5386) and of
    /// the loaded tool's offsets and diameter (#5401–#5410): LinuxCNC
    /// keeps them in the machine's units (its INI's `LINEAR_UNITS`) whatever G20/G21 say.
    /// `None`: [`Self::initial_units`].
    pub parameter_units: Option<Units>,
    /// Numbered parameters set before the program starts (LinuxCNC's parameter file, `.var`),
    /// in [`Self::parameter_units`] for the offset parameters. A G92 offset stored there with
    /// #5210 set is in effect from the start, as in LinuxCNC.
    pub parameters: Vec<(usize, f64)>,
    /// Read the program as LinuxCNC or as a Fanuc control does; `None`: decided from the
    /// program ([`GcodeDialect::detect`]).
    pub dialect: Option<GcodeDialect>,
    /// The machine's home, mm, in machine coordinates (the work frame with every offset zero):
    /// where the tool stands when the program starts and where G28 and G30 return to (their
    /// stored positions, #5161–#5163 and #5181–#5183, unless the parameters set them). `None`:
    /// the origin, as LinuxCNC starts with zero parameters — which puts a Fanuc/Haas
    /// program's reference return (`G28 G91 Z0.`) on the work's Z0. Given, it is also the origin
    /// of the positions G53 moves to (and of #5021–#5026) for the whole program, whatever work
    /// offsets and G92 it sets (machine zero is the home on Fanuc, Haas, GRBL and Mach3
    /// controls): `G53 G0 Z0.` goes to the home's Z. G53, G28/G30 and the stored positions
    /// are those of the controlled point, as in LinuxCNC: under a tool length offset the tip
    /// ends that length below (`G53 G0 Z0.` with a 10 mm tool under G43: the tip at the home's
    /// Z − 10).
    pub home: Option<[f64; 3]>,
    /// The LinuxCNC machine configuration the program runs under ([`Self::with_linuxcnc_ini`]):
    /// its start-up code runs first, `#<_ini[section]name>` reads its numbers, and its
    /// `[EMCIO]` tool-change settings and `DISABLE_FANUC_STYLE_SUB` apply. `None`: LinuxCNC's
    /// defaults (M6 stops the spindle and moves nothing).
    pub ini: Option<LinuxCncIni>,
}

/// The controller whose rules a G-code program is read by, where LinuxCNC and Fanuc differ.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GcodeDialect {
    /// LinuxCNC (RS274/NGC): G80 is a motion code (it cannot share a block with G0/G1) and
    /// after it axis words need a new motion code.
    LinuxCnc,
    /// Fanuc (0i/30i-M style): canned cycles are their own modal group, so G80 and G0/G1 share
    /// a block (the cycle is cancelled and the motion applies) and after G80 the last G0–G3
    /// (G0 at power-on) moves the axes; `M98 P` with more than four digits carries the repeat
    /// count in front of the program number (`M98 P30010` runs O0010 three times).
    Fanuc,
}

impl GcodeDialect {
    /// The dialect of a program: Fanuc when its first lines show Fanuc habits (a bare `O1234`
    /// program number, `M98`/`M99`, `G80` sharing a block with `G0`/`G1`, a Macro B `WHILE`,
    /// `IF`, `GOTO` or `END`, Fanuc's own codes `G05.1 Q`, G43.4, G43.5, G54.1 and Haas's G154,
    /// a G04/G82 dwell `P` in milliseconds — no decimal point, 100 or more: `G4 P1` is an
    /// ordinary LinuxCNC dwell of a second, `G04 P500` is not) and nothing only
    /// LinuxCNC reads (`o<name>`, O-word keywords, `#<name>`, a `;` comment, `(debug,…)`,
    /// `(print,…)` and LinuxCNC's other active comments: LinuxCNC runs `M98`/`M99` programs
    /// too); LinuxCNC otherwise.
    pub fn detect(text: &str) -> Self {
        Self::detect_with_cues(text).0
    }

    /// [`GcodeDialect::detect`], with the first line showing a Fanuc habit and the first
    /// showing something only LinuxCNC reads (1-based), when there are such lines.
    pub fn detect_with_cues(text: &str) -> (Self, Option<u32>, Option<u32>) {
        let (mut fanuc_at, mut linuxcnc_at) = (None, None);
        for (index, line) in lexer::lines(text).take(2000).enumerate() {
            let (fanuc, linuxcnc) = Self::line_cues(line);
            let n = index as u32 + 1;
            if fanuc && fanuc_at.is_none() {
                fanuc_at = Some(n);
            }
            if linuxcnc && linuxcnc_at.is_none() {
                linuxcnc_at = Some(n);
            }
        }
        let dialect = if fanuc_at.is_some() && linuxcnc_at.is_none() {
            GcodeDialect::Fanuc
        } else {
            GcodeDialect::LinuxCnc
        };
        (dialect, fanuc_at, linuxcnc_at)
    }

    /// Whether one line shows a Fanuc habit, and whether it shows something only LinuxCNC
    /// reads.
    fn line_cues(line: &str) -> (bool, bool) {
        let (fanuc, linuxcnc) = Self::line_cue_names(line);
        (fanuc.is_some(), linuxcnc)
    }

    /// The Fanuc habit line `line` shows, named for the dialect warning (`None`: none).
    pub(crate) fn fanuc_cue(line: &str) -> Option<String> {
        Self::line_cue_names(line).0
    }

    /// [`Self::line_cues`] with the Fanuc habit named.
    fn line_cue_names(line: &str) -> (Option<String>, bool) {
        let (mut fanuc, mut linuxcnc) = (None, false);
        {
            if linuxcnc_comment(line) {
                linuxcnc = true;
            }
            let code: String = line
                .split(';')
                .next()
                .unwrap_or("")
                .chars()
                .filter(|c| !c.is_whitespace())
                .collect::<String>()
                .to_ascii_lowercase();
            let code = match code.find('(') {
                Some(i) => code[..i].to_string(),
                None => code,
            };
            let body = code
                .trim_start_matches('/')
                .strip_prefix('n')
                .map_or(code.trim_start_matches('/'), |r| {
                    r.trim_start_matches(|c: char| c.is_ascii_digit() || c == '.')
                });
            if body.contains("#<") || body.starts_with("o<") {
                linuxcnc = true;
            } else if let Some(rest) = body.strip_prefix('o') {
                let after = rest.trim_start_matches(|c: char| c.is_ascii_digit());
                if after.len() < rest.len() {
                    if after.is_empty() {
                        fanuc = Some(format!("a bare program number, {}", body.to_uppercase()));
                    } else {
                        linuxcnc = true;
                    }
                }
            }
            // M words by number: M980 or M999 is no M98/M99 (M098 is).
            let m98_99 = body.match_indices('m').any(|(i, _)| {
                let num: String = body[i + 1..]
                    .chars()
                    .take_while(|c| c.is_ascii_digit() || *c == '.')
                    .collect();
                num.parse::<f64>().is_ok_and(|m| m == 98.0 || m == 99.0)
            });
            if m98_99 {
                fanuc = Some("M98/M99, Fanuc's subprogram call and return".into());
            } else if interp::is_macro_b(body.as_bytes()) {
                fanuc = Some("a Custom Macro B statement".into());
            }
            // The G numbers of the block.
            let gs: Vec<f64> = body
                .match_indices('g')
                .filter_map(|(i, _)| {
                    let num: String = body[i + 1..]
                        .chars()
                        .take_while(|c| c.is_ascii_digit() || *c == '.')
                        .collect();
                    num.parse().ok()
                })
                .collect();
            let g80_with_motion = gs.contains(&80.0)
                && gs
                    .iter()
                    .any(|&g| matches!(g as u32, 0..=3) && g.fract() == 0.0);
            let has = |code: f64| gs.iter().any(|&g| (g - code).abs() < 1e-9);
            let own_code = has(43.4)
                || has(43.5)
                || has(54.1)
                || has(154.0)
                || (has(5.1) && body.contains('q'));
            let dwell_ms =
                (has(4.0) || has(82.0)) && p_without_point(body).is_some_and(|p| p >= 100);
            if g80_with_motion {
                fanuc = Some(
                    "G80 with G0/G1/G2/G3 in one block, a Fanuc post's habit (LinuxCNC reads \
                     it too, the other code winning)"
                        .into(),
                );
            } else if own_code {
                fanuc = Some("a Fanuc-only code (G43.4, G43.5, G54.1, G154 or G5.1 Q)".into());
            } else if dwell_ms {
                fanuc = Some("a dwell P without a point, in milliseconds".into());
            }
        }
        (fanuc, linuxcnc)
    }
}

/// Whether a line holds a comment only LinuxCNC reads: a `;` comment with text (a Fanuc
/// program has no `;` but as an end-of-block mark at the end of a line), or an active comment
/// of LinuxCNC's own (`(debug,…)`, `(print,…)`, `(log…)`, `(probeopen …)`).
fn linuxcnc_comment(line: &str) -> bool {
    let mut depth = 0u32;
    for (i, c) in line.char_indices() {
        match c {
            '(' => {
                depth += 1;
                let rest = line[i + 1..].trim_start().to_ascii_lowercase();
                let active = [
                    "debug,",
                    "print,",
                    "log,",
                    "logopen,",
                    "logappend,",
                    "logclose",
                ]
                .iter()
                .chain(&["probeopen", "probeclose"])
                .any(|k| rest.starts_with(k));
                if depth == 1 && active {
                    return true;
                }
            }
            ')' => depth = depth.saturating_sub(1),
            ';' if depth == 0 => return !line[i + 1..].trim().is_empty(),
            _ => {}
        }
    }
    false
}

/// The value of the first `P` word of a block's code (lower case, no spaces) written as a
/// whole number without a decimal point, if there is one.
fn p_without_point(body: &str) -> Option<u64> {
    body.match_indices('p').find_map(|(i, _)| {
        let num: String = body[i + 1..]
            .chars()
            .take_while(|c| c.is_ascii_digit() || *c == '.')
            .collect();
        if num.contains('.') {
            None
        } else {
            num.parse().ok()
        }
    })
}

impl Default for GcodeOptions {
    fn default() -> Self {
        Self {
            initial_units: Units::Mm,
            max_loop_iterations: 10_000_000,
            max_moves: crate::limit::DEFAULT_MAX_MOVES,
            max_call_depth: 64,
            max_repeat: 1_000_000,
            arc_radius_tolerance: ArcTolerance::LINUXCNC,
            block_delete: false,
            tool_diameters: BTreeMap::new(),
            tool_offsets: BTreeMap::new(),
            tool_pockets: BTreeMap::new(),
            tool_names: BTreeMap::new(),
            default_tool_diameter: None,
            subroutine_path: Vec::new(),
            parameter_units: None,
            home: None,
            parameters: Vec::new(),
            dialect: None,
            ini: None,
        }
    }
}

impl GcodeOptions {
    /// Sets [`Self::initial_units`].
    pub fn with_initial_units(mut self, units: Units) -> Self {
        self.initial_units = units;
        self
    }
    /// Sets [`Self::max_loop_iterations`].
    pub fn with_max_loop_iterations(mut self, n: u64) -> Self {
        self.max_loop_iterations = n;
        self
    }
    /// Sets [`Self::max_moves`].
    pub fn with_max_moves(mut self, n: u64) -> Self {
        self.max_moves = n;
        self
    }
    /// Sets [`Self::max_call_depth`].
    pub fn with_max_call_depth(mut self, n: usize) -> Self {
        self.max_call_depth = n;
        self
    }
    /// Sets [`Self::max_repeat`].
    pub fn with_max_repeat(mut self, n: u64) -> Self {
        self.max_repeat = n;
        self
    }
    /// Sets [`Self::arc_radius_tolerance`].
    pub fn with_arc_radius_tolerance(mut self, tol: ArcTolerance) -> Self {
        self.arc_radius_tolerance = tol;
        self
    }
    /// Sets tool `tool`'s offsets in [`Self::tool_offsets`] (X Y Z mm, A B C degrees).
    pub fn with_tool_offsets(mut self, tool: u32, offsets: [f64; 6]) -> Self {
        self.tool_offsets.insert(tool, offsets);
        self
    }
    /// Sets tool `tool`'s pocket in [`Self::tool_pockets`].
    pub fn with_tool_pocket(mut self, tool: u32, pocket: u32) -> Self {
        self.tool_pockets.insert(tool, pocket);
        self
    }
    /// Sets [`Self::home`].
    pub fn with_home(mut self, home: [f64; 3]) -> Self {
        self.home = Some(home);
        self
    }
    /// Sets [`Self::block_delete`].
    pub fn with_block_delete(mut self, on: bool) -> Self {
        self.block_delete = on;
        self
    }
    /// The units the offset parameters are kept in.
    pub fn parameter_units(&self) -> Units {
        self.parameter_units.unwrap_or(self.initial_units)
    }
    /// Sets [`Self::parameter_units`].
    pub fn with_parameter_units(mut self, units: Units) -> Self {
        self.parameter_units = Some(units);
        self
    }
    /// Adds numbered parameter `n` = `v` to [`Self::parameters`].
    pub fn with_parameter(mut self, n: usize, v: f64) -> Self {
        self.parameters.push((n, v));
        self
    }
    /// Sets [`Self::dialect`].
    pub fn with_dialect(mut self, dialect: GcodeDialect) -> Self {
        self.dialect = Some(dialect);
        self
    }
    /// Adds a folder to [`Self::subroutine_path`].
    pub fn with_subroutine_dir(mut self, dir: impl Into<PathBuf>) -> Self {
        self.subroutine_path.push(dir.into());
        self
    }
    /// With the diameter of every tool not in [`Self::tool_diameters`], mm.
    pub fn with_default_tool_diameter(mut self, diameter_mm: f64) -> Self {
        self.default_tool_diameter = Some(diameter_mm);
        self
    }
    /// Adds tool `tool`'s diameter (mm) to [`Self::tool_diameters`].
    pub fn with_tool_diameter(mut self, tool: u32, diameter_mm: f64) -> Self {
        self.tool_diameters.insert(tool, diameter_mm);
        self
    }
}

/// Reads a G-code program and hands its canonical events to `sink`, in program order.
///
/// `file_name` is only used in error positions and warnings. The first events state the
/// initial state as LinuxCNC does: units, zero offsets (G54 active), plane XY. Reading stops at
/// M2/M30 (which emit [`Canon::ProgramEnd`]), at a closing `%`, or at the end of the text.
///
/// # Errors
/// A [`PathError`] with the file, 1-based line and column, the text found and what was
/// expected, for the first line that cannot be read or executed.
pub fn read_gcode(
    text: &str,
    file_name: &str,
    options: &GcodeOptions,
    sink: &mut dyn CanonSink,
) -> Result<(), PathError> {
    interp::Interp::new(text, file_name, options, sink).run()
}

/// `text` without the UTF-8 byte order mark some Windows editors and posts put first (an
/// invisible character that would otherwise be the first line's first word).
pub(crate) fn without_bom(text: &str) -> &str {
    text.strip_prefix('\u{feff}').unwrap_or(text)
}

/// Reads the G-code file at `path` (see [`read_gcode`]), decoded by
/// [`decode_text`](crate::load::decode_text): UTF-16 with a byte-order mark, else UTF-8 with
/// bytes that are not UTF-8 (Latin-1 comments from old post-processors) replaced.
///
/// # Errors
/// [`PathErrorKind::Io`] when the file cannot be read; otherwise as [`read_gcode`].
pub fn read_gcode_file(
    path: impl AsRef<Path>,
    options: &GcodeOptions,
    sink: &mut dyn CanonSink,
) -> Result<(), PathError> {
    let path = path.as_ref();
    let name = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| {
        PathError::new(
            SourcePos {
                file: name.clone(),
                line: 0,
                column: 0,
            },
            PathErrorKind::Io,
            format!("cannot read the file: {e}"),
            "",
            "",
        )
    })?;
    let text = crate::load::decode_text(bytes);
    read_gcode(&text, &name, options, sink)
}

/// Where inside the current line an internal error lies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Span {
    /// The whole line.
    Line,
    /// Indices `[start, end)` into the normalised code of the line (see [`lexer::LineBuf`]).
    Code(usize, usize),
    /// Byte offsets `[start, end)` into the raw line.
    Raw(usize, usize),
}

/// An error inside the reader before it is placed in the file: what the line-level driver
/// turns into a [`PathError`].
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Fault {
    pub(crate) kind: PathErrorKind,
    pub(crate) span: Span,
    pub(crate) message: String,
    pub(crate) expected: String,
}

impl Fault {
    pub(crate) fn new(
        kind: PathErrorKind,
        span: Span,
        message: impl Into<String>,
        expected: impl Into<String>,
    ) -> Self {
        Self {
            kind,
            span,
            message: message.into(),
            expected: expected.into(),
        }
    }
    pub(crate) fn syntax(
        span: Span,
        message: impl Into<String>,
        expected: impl Into<String>,
    ) -> Self {
        Self::new(PathErrorKind::Syntax, span, message, expected)
    }
    pub(crate) fn semantic(span: Span, message: impl Into<String>) -> Self {
        Self::new(PathErrorKind::Semantic, span, message, "")
    }
}

/// Result of the reader's internal steps.
pub(crate) type Res<T> = Result<T, Fault>;
