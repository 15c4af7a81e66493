//! The interpreter proper: modal state, and the execution of one block in LinuxCNC's order of
//! execution (feed mode, F, S, T, M6, spindle, coolant, dwell, plane, units, tool length,
//! coordinate system, distance mode, retract mode, G10/G28/G30/G92, motion, stop).
//!
//! All lengths are kept in millimetres; program values are scaled on input (`scale` is 25.4
//! under G20). Positions are in the current coordinate system, as LinuxCNC's canon calls
//! receive them; machine position = program position + active G5x offset + G92 offset.

use std::borrow::Cow;
use std::collections::HashMap;
use std::rc::Rc;

use swarf_geom::math::{Vec3, MACHINE_RANGE_MM};

use super::arcs::{center_r, check_ijk, r_tolerance_mm};
use super::block::{self, group, Block};
use super::comp::Comp;
use super::dialect::Dialect;
use super::expr::ParamRead;
use super::lexer::{column_of, normalize, skip_line_number, split_line, LineBuf};
use super::params::{Params, Target};
use super::stack::{Ctl, Cursor, Frame, Kw, ScanHit};
use super::{Fault, GcodeDialect, GcodeOptions, Res, Span};
use crate::limit::{move_limit_message, MoveLimit};
use crate::{
    Axes, Canon, CanonSink, FeedMode, MessageKind, PathError, PathErrorKind, Plane, SourcePos,
    SpindleDir, Units, Warning, WorkPlane,
};

/// Letters of the six axes, in X Y Z A B C order.
pub(crate) const AXIS_LETTERS: [u8; 6] = *b"xyzabc";

/// A coordinate swarf accepts: finite and within [`MACHINE_RANGE_MM`] of the origin (mm for
/// X Y Z, degrees for A B C).
fn in_machine_range(v: f64) -> bool {
    v.is_finite() && v.abs() <= MACHINE_RANGE_MM
}

/// The error for coordinate `v` of axis `name` out of the machine range, at `span`.
fn out_of_range(span: Span, what: &str, v: f64, unit: &str) -> Fault {
    Fault::new(
        PathErrorKind::Semantic,
        span,
        format!(
            "{what} {v:e} {unit} is beyond the machine range of ±{MACHINE_RANGE_MM:e} {unit} \
             (or not a finite number)"
        ),
        format!("a coordinate within ±{MACHINE_RANGE_MM:e} {unit}"),
    )
}

/// Mask of the axis words (X Y Z A B C and the polar `@` `^`).
fn axis_mask() -> u32 {
    let mut m = 0;
    for c in *b"xyzabc@^" {
        m |= 1 << block::slot(c);
    }
    m
}

/// Canned-cycle values that persist between blocks of the same cycle (LinuxCNC's `cycle_*`).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct CycleMemory {
    /// R word as given (mm; incremental programs keep the increment).
    pub(crate) r: f64,
    /// Bottom word (Z in G17) as given, mm.
    pub(crate) cc: f64,
    /// Dwell, seconds.
    pub(crate) p: f64,
    /// Peck increment, mm.
    pub(crate) q: f64,
    /// G87's I, J and K words as given (along the plane's axes and its normal), mm.
    pub(crate) back_bore: [f64; 3],
}

/// Modes that change no motion, kept for LinuxCNC's predefined named parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ReadOnlyState {
    /// The cutter compensation code × 10 (400, 410, 411, 420, 421).
    pub(crate) ccomp: u16,
    /// The tool in the spindle (M6, M61), and the tool the last T word selected.
    pub(crate) loaded_tool: u32,
    pub(crate) selected_tool: Option<u32>,
    pub(crate) mist: bool,
    pub(crate) flood: bool,
    /// Feed override, speed override, adaptive feed, feed hold (M48–M53).
    pub(crate) overrides: [bool; 4],
    /// G96 constant surface speed.
    pub(crate) css: bool,
    /// A tool length offset is on (G43, G43.1, G43.2; off after G49).
    pub(crate) tlo_on: bool,
    /// mm per program unit when the feed was set: `#<_feed>` reads the feed as the F word
    /// gave it (LinuxCNC's `settings->feed_rate`, which G20/G21 do not convert).
    pub(crate) feed_scale: f64,
}

impl Default for ReadOnlyState {
    fn default() -> Self {
        Self {
            ccomp: 400,
            loaded_tool: 0,
            selected_tool: None,
            mist: false,
            flood: false,
            // rs274 2.9 starts with feed hold enabled (synch reads
            // GET_EXTERNAL_FEED_HOLD_ENABLE, 1): `#<_feed_hold>` reads 1 until M53 P0.
            overrides: [true, true, false, true],
            css: false,
            tlo_on: false,
            feed_scale: 1.0,
        }
    }
}

/// The interpreter state for one program run.
pub(crate) struct Interp<'t, 's> {
    /// The text and name of the file being executed.
    pub(crate) text: Rc<str>,
    pub(crate) file: Rc<str>,
    /// Every file read: the program, then subroutine files (`o<name> call` of `name.ngc`).
    pub(crate) files: Vec<(Rc<str>, Rc<str>)>,
    /// Which of `files` is being executed.
    pub(crate) cur_file: u32,
    pub(crate) opts: &'t GcodeOptions,
    /// The caller's sink behind the move limit.
    pub(crate) sink: MoveLimit<'s>,
    /// Where reading continues.
    pub(crate) at: Cursor,
    /// The line being executed (events carry it) and where it starts.
    pub(crate) cur_line: u32,
    pub(crate) cur_start: usize,
    pub(crate) units: Units,
    /// mm per program unit.
    pub(crate) scale: f64,
    pub(crate) absolute: bool,
    pub(crate) arc_absolute: bool,
    pub(crate) plane: Plane,
    pub(crate) feed_mode: FeedMode,
    /// mm/min (G94), mm/rev (G95) or 1/min (G93).
    pub(crate) feed: f64,
    /// Active motion mode (G code × 10); `None` after G80.
    pub(crate) motion: Option<u16>,
    /// G99: retract to R; G98: retract to the old level.
    pub(crate) retract_r: bool,
    pub(crate) cycle: CycleMemory,
    /// The initial level of the canned-cycle mode in effect (along the plane's normal, program
    /// coordinates, mm), set by the mode's first block (`cycles`): G91's R counts from it and
    /// G98 returns to it, under Fanuc rules and LinuxCNC's (rs274 2.9's `cycle_il`) alike.
    pub(crate) initial_level: Option<f64>,
    pub(crate) rpm: f64,
    pub(crate) dir: SpindleDir,
    pub(crate) tool: u32,
    /// A tool has been loaded (M6, or assumed at the first motion after a lone T word).
    tool_loaded: bool,
    /// Current position, program coordinates, mm / degrees.
    pub(crate) p: [f64; 6],
    /// Active coordinate system, 1 (G54) … 9 (G59.3).
    pub(crate) coord: usize,
    /// The coordinate system table (parameters 5221…), mm.
    pub(crate) g5x_table: [[f64; 6]; 9],
    /// The G5x offset in effect (loaded from the table when the system is selected).
    pub(crate) off: [f64; 6],
    /// The XY rotation of each coordinate system (G10 L2 R, parameters 5230, 5250, …), degrees.
    pub(crate) rot_table: [f64; 9],
    /// Fanuc's additional work offsets (G54.1 P1–P300, Haas G154) the program set with
    /// `G10 L20 Pn`, mm: a control's others are in its table, not in the program.
    pub(crate) ext_table: std::collections::BTreeMap<u16, [f64; 6]>,
    /// The additional work offset in effect (G54.1 Pn), in place of system [`Self::coord`].
    pub(crate) ext_coord: Option<u16>,
    /// The XY rotation in effect, degrees.
    pub(crate) rot: f64,
    /// The G92 offset in effect.
    pub(crate) g92: [f64; 6],
    /// The stored G92 offset (parameters 5211–5216) and whether it is applied (5210).
    pub(crate) g92_saved: [f64; 6],
    pub(crate) g92_flag: f64,
    /// G28 and G30 positions, machine coordinates, mm.
    pub(crate) homes: [[f64; 6]; 2],
    /// Tool offsets by tool number (G10 L1/L10, parameters 5401–5406 of the loaded tool),
    /// machine frame, mm / degrees; a tool not listed has none.
    pub(crate) tool_table: std::collections::BTreeMap<u32, [f64; 6]>,
    /// Tool radii set by the program (G10 L1/L10/L11 R), mm: they win over the tool table's
    /// diameters for cutter compensation and parameter 5410.
    pub(crate) tool_radii: std::collections::BTreeMap<u32, f64>,
    /// Fanuc: the last D and H words (#4107, #4111).
    pub(crate) last_dh: [Option<f64>; 2],
    /// Fanuc: system variables read that swarf does not model, to be told after the line
    /// (reads happen where the interpreter is borrowed immutably), and those told.
    pub(crate) sysvar_pending: std::cell::RefCell<Vec<usize>>,
    pub(crate) sysvar_told: Vec<usize>,
    /// Fanuc: system variables (#1000 and up) the program assigned: reading them back gives
    /// what it stored, nothing to tell.
    pub(crate) sysvar_written: Vec<usize>,
    /// Fanuc's wear offsets set by `G10 L11`/`L13`, by (length register, number), mm: they
    /// are included in the register's offset ([`Self::tool_table`]'s Z for H, [`Self::tool_radii`]
    /// for D), kept apart so that a later L10/L12 (geometry) keeps them.
    pub(crate) register_wear: std::collections::BTreeMap<(bool, u32), f64>,
    /// Fanuc D registers cutter compensation used without knowing their offset (told once
    /// each).
    pub(crate) comp_registers_told: Vec<u32>,
    /// M codes that change nothing swarf models, told once each.
    pub(crate) m_ignored_told: Vec<u16>,
    /// The tool length offset in effect (G43, G43.1; G49 clears it), machine frame. swarf's
    /// programs are tool-tip programs, so it moves no tip; it shifts the position the program
    /// reads (parameters 5420–5425, incremental words) as LinuxCNC's does.
    pub(crate) tlo: [f64; 6],
    pub(crate) params: Params,
    pub(crate) ctl: Vec<Ctl>,
    pub(crate) frames: Vec<Frame>,
    pub(crate) subs: HashMap<Vec<u8>, Cursor>,
    pub(crate) labels: Option<HashMap<u64, Cursor>>,
    /// Where each `N` number's line starts (Haas `M97 P<n>`), made at the first call.
    pub(crate) line_numbers: Option<HashMap<u64, Cursor>>,
    /// Fanuc Macro B's GOTO targets, per program (its file and where it starts): every line
    /// numbered `N n`, in order.
    pub(crate) goto_index: HashMap<(u32, usize), HashMap<u64, Vec<Cursor>>>,
    /// Results of forward scans for O-words, by start position and keyword set.
    pub(crate) scan_cache: HashMap<(u32, usize, u32), ScanHit>,
    pub(crate) iterations: u64,
    /// How many times M99 restarted the main program.
    pub(crate) main_passes: u64,
    /// Whether any file read has an M2/M30, and how many files had been read then.
    pub(crate) files_have_end: Option<(usize, bool)>,
    /// The position and offsets when the current pass of the main program began.
    pub(crate) pass_control: Option<super::control::PassControl>,
    /// Where each `N` number's line of the main program starts (Fanuc's `M99 P<n>`).
    pub(crate) main_line_numbers: Option<HashMap<u64, Cursor>>,
    pub(crate) ended: bool,
    pub(crate) tape: bool,
    pub(crate) seen_code: bool,
    /// Set when a false `if` jumps to an `elseif`, whose condition must then be tested.
    pub(crate) if_probe: bool,
    /// rs274's `doing_break`: set by a `break` it reads (also one it passes while skipping a
    /// `while` or `repeat` of that name), cleared only by the end of a `do` loop, which then
    /// does not loop back (see `control.rs`).
    pub(crate) doing_break: bool,
    /// The INI's M6 settings, and whether it refuses Fanuc subprograms and gives
    /// `#<_ini[…]>` (read once: M98/M99 and parameter reads may run in long loops).
    pub(crate) tool_change: super::ToolChangeMoves,
    pub(crate) fanuc_subs_off: bool,
    ini_vars: bool,
    /// `#<_ini[…]>` values looked up so far (rs274 caches them too).
    ini_values: std::cell::RefCell<HashMap<String, Option<f64>>>,
    /// A tool change in the block being read: the position is re-read after it
    /// ([`Self::comp_resync_after_change`]).
    pub(crate) resync_after_block: bool,
    /// The O names an `if`, `while`, `do` or `repeat` used at each call level, and where:
    /// rs274 refuses one name for two of them in a level (its O-word offset table).
    pub(crate) o_labels: HashMap<(usize, Vec<u8>), (Kw, Cursor)>,
    pub(crate) skip_buf: LineBuf,
    /// Read by Fanuc's rules (see [`GcodeDialect`]).
    pub(crate) fanuc: bool,
    /// The first line showing a Fanuc habit and the first showing something only LinuxCNC
    /// reads, when the dialect was detected (`None`: given).
    dialect_cues: Option<(Option<u32>, Option<u32>)>,
    /// Warnings raised where the line's text is not at hand, with the code index they point
    /// at: reported once the block has run.
    pub(crate) later: Vec<(usize, String)>,
    /// A line skipped by block delete has been reported.
    deleted_warned: bool,
    /// A Fanuc reference return to the default home has been reported.
    home_warned: bool,
    /// A G43 H with no tool table entry has been reported.
    tlo_warned: bool,
    /// Fanuc `G43.5` (tool centre point control, type 2) is on: a straight move's I J K are the
    /// tool's direction.
    tcp_vector: bool,
    /// Cutter compensation was just turned off (G40): the next move must be straight.
    pub(crate) arc_not_allowed: bool,
    /// A G53 move with no work offset in effect has been reported.
    g53_warned: bool,
    /// Fanuc: a length or angle written without a decimal point has been reported.
    point_warned: bool,
    /// The program stated its units (G20/G21, or G70/G71 read as them), or was told at its
    /// first move that it had not.
    units_stated: bool,
    /// Fanuc: the group 01 motion (G0–G3 × 10) that resumes after G80.
    pub(crate) group1: u16,
    /// Fanuc G68: the centre (X, Y, mm) and angle (degrees) of the coordinate rotation.
    pub(crate) g68: Option<([f64; 2], f64)>,
    /// G68.2: the tilted working plane program positions are given in.
    pub(crate) tilt: Option<WorkPlane>,
    /// The modal state M70/M73 saved, per call level (`modal`).
    pub(crate) saved_modal: Vec<super::modal::Saved>,
    /// A probing move (G38.x) was reported.
    pub(crate) probe_warned: bool,
    /// G69 cancelled a plane G53.1 had turned the tool to: the next block with rotary words
    /// hands the tool axis back to the machine ([`Canon::MachineAxis`]).
    pub(crate) held_axis: bool,
    /// Fanuc Macro B loops open (`macro_b`).
    pub(crate) macro_loops: Vec<super::macro_b::MacroLoop>,
    /// Where reading goes on after each Macro B loop's `END m`, by the file and start of its
    /// `WHILE` line (`macro_b`).
    pub(crate) loop_ends: HashMap<(u32, usize), Cursor>,
    /// State only LinuxCNC's predefined named parameters read (`#<_ccomp>`, `#<_mist>`, …).
    pub(crate) read_only: ReadOnlyState,
    /// Fanuc G51: the centre (mm) and factor of each axis of the scaling.
    pub(crate) g51: Option<([f64; 3], [f64; 3])>,
    /// The last G5's second control point (a G5 without I J mirrors it).
    pub(crate) g5_last: Option<[f64; 2]>,
    /// An open G5.2 NURBS: its control points and order, and where it starts.
    pub(crate) nurbs: Option<(Vec<[f64; 3]>, u32)>,
    pub(crate) nurbs_start: [f64; 2],
    /// Cutter radius compensation.
    pub(crate) comp: Comp,
    /// The warning about LinuxCNC's tapping axes outside G17 was given.
    pub(crate) tap_quirk_warned: bool,
}

impl<'t, 's> Interp<'t, 's> {
    pub(crate) fn new(
        text: &str,
        file: &str,
        opts: &'t GcodeOptions,
        sink: &'s mut dyn CanonSink,
    ) -> Self {
        let text = super::without_bom(text);
        // Detected once: the dialect and, when detected, the lines that decided it.
        let (fanuc, dialect_cues) = match opts.dialect {
            Some(d) => (d == GcodeDialect::Fanuc, None),
            None => {
                let (d, fanuc_at, linuxcnc_at) = GcodeDialect::detect_with_cues(text);
                (d == GcodeDialect::Fanuc, Some((fanuc_at, linuxcnc_at)))
            }
        };
        let (text, file): (Rc<str>, Rc<str>) = (Rc::from(text), Rc::from(file));
        Self {
            fanuc,
            dialect_cues,
            later: Vec::new(),
            deleted_warned: false,
            home_warned: false,
            tlo_warned: false,
            tcp_vector: false,
            arc_not_allowed: false,
            g53_warned: false,
            point_warned: false,
            units_stated: false,
            group1: 0,
            g68: None,
            tilt: None,
            saved_modal: Vec::new(),
            read_only: ReadOnlyState::default(),
            macro_loops: Vec::new(),
            loop_ends: HashMap::new(),
            held_axis: false,
            probe_warned: false,
            g51: None,
            g5_last: None,
            nurbs: None,
            nurbs_start: [0.0; 2],
            files: vec![(file.clone(), text.clone())],
            cur_file: 0,
            text,
            file,
            opts,
            sink: MoveLimit::new(sink, opts.max_moves),
            at: Cursor {
                pos: 0,
                line: 0,
                file: 0,
            },
            cur_line: 0,
            cur_start: 0,
            units: opts.initial_units,
            scale: opts.initial_units.mm_per_unit(),
            absolute: true,
            arc_absolute: false,
            plane: Plane::XY,
            feed_mode: FeedMode::PerMinute,
            feed: 0.0,
            // Fanuc powers on in G0; LinuxCNC needs a motion code first.
            motion: fanuc.then_some(0),
            // LinuxCNC's interpreter starts in G99 (`Interp::init`: retract to the R plane; Axis
            // shows G99 at start-up); a Fanuc control powers on in G98.
            retract_r: !fanuc,
            cycle: CycleMemory::default(),
            initial_level: None,
            rpm: 0.0,
            dir: SpindleDir::Stopped,
            tool: 0,
            tool_loaded: false,
            p: [0.0; 6],
            coord: 1,
            g5x_table: [[0.0; 6]; 9],
            off: [0.0; 6],
            rot_table: [0.0; 9],
            ext_table: std::collections::BTreeMap::new(),
            ext_coord: None,
            rot: 0.0,
            g92: [0.0; 6],
            g92_saved: [0.0; 6],
            g92_flag: 0.0,
            homes: [[0.0; 6]; 2],
            tool_table: std::collections::BTreeMap::new(),
            tool_radii: std::collections::BTreeMap::new(),
            register_wear: std::collections::BTreeMap::new(),
            last_dh: [None; 2],
            sysvar_pending: std::cell::RefCell::new(Vec::new()),
            sysvar_told: Vec::new(),
            sysvar_written: Vec::new(),
            comp_registers_told: Vec::new(),
            m_ignored_told: Vec::new(),
            tlo: [0.0; 6],
            params: Params::linuxcnc_or_fanuc(fanuc),
            ctl: Vec::new(),
            frames: Vec::new(),
            subs: HashMap::new(),
            labels: None,
            line_numbers: None,
            goto_index: HashMap::new(),
            scan_cache: HashMap::new(),
            iterations: 0,
            main_passes: 0,
            files_have_end: None,
            pass_control: None,
            main_line_numbers: None,
            ended: false,
            tape: false,
            seen_code: false,
            if_probe: false,
            doing_break: false,
            tool_change: opts
                .ini
                .as_ref()
                .and_then(|i| i.tool_change().ok())
                .unwrap_or_default(),
            fanuc_subs_off: opts.ini.as_ref().is_some_and(|i| i.fanuc_subs_disabled()),
            ini_vars: opts.ini.as_ref().is_some_and(|i| i.ini_vars()),
            ini_values: std::cell::RefCell::new(HashMap::new()),
            resync_after_block: false,
            o_labels: HashMap::new(),
            skip_buf: LineBuf::default(),
            comp: Comp::default(),
            tap_quirk_warned: false,
        }
    }

    /// Reads the whole program.
    pub(crate) fn run(mut self) -> Result<(), PathError> {
        if let Some((d, line)) = Dialect::detect(&self.text, 200) {
            let raw = super::lexer::lines(&self.text)
                .nth(line as usize - 1)
                .unwrap_or("");
            return Err(PathError::new(
                SourcePos {
                    file: self.file.to_string(),
                    line,
                    column: 1,
                },
                PathErrorKind::Unsupported,
                match d {
                    Dialect::Heidenhain => format!(
                        "this is a {d} program, read here as G-code (swarf reads Heidenhain \
                         programs through its own reader, which format detection chooses)"
                    ),
                    _ => format!(
                        "this is a {d} program, read here as G-code (swarf reads RS274/NGC \
                         (LinuxCNC), Fanuc-style G-code, Heidenhain conversational and Sinumerik \
                         programs, each through its own reader, which format detection chooses)"
                    ),
                },
                raw.trim(),
                "RS274/NGC G-code",
            ));
        }
        if let Some((fanuc_at, linuxcnc_at)) = self.dialect_cues {
            // Which rules the program is read by, and the line that decided it.
            let message = match (fanuc_at, linuxcnc_at) {
                (Some(f), None) => {
                    let line = super::lexer::lines(&self.text)
                        .nth(f as usize - 1)
                        .unwrap_or("");
                    let cue = GcodeDialect::fanuc_cue(line)
                        .unwrap_or_else(|| "a Fanuc habit".to_string());
                    Some(format!(
                        "read by Fanuc rules: this line shows {cue}, and no line has anything \
                         only LinuxCNC reads; --dialect linuxcnc reads it by LinuxCNC's"
                    ))
                }
                (Some(_), Some(l)) => Some(format!(
                    "read by LinuxCNC rules although this line shows a Fanuc habit: line {l} has \
                     something only LinuxCNC reads (o<name>, #<name>, a ; comment, (debug,…), \
                     (print,…)); --dialect fanuc reads it by Fanuc's"
                )),
                _ => None,
            };
            if let (Some(message), Some(line)) = (message, fanuc_at) {
                self.sink.warn(Warning {
                    file: self.file.to_string(),
                    line,
                    column: 1,
                    message,
                });
            }
        }
        // The tool table's offsets, which G10 L1/L10/L11 replace.
        self.tool_table = self.opts.tool_offsets.clone();
        // The tool starts at the machine's home (its origin unless given).
        let mut start = [0.0; 6];
        if let Some(home) = self.opts.home {
            for h in &mut self.homes {
                h[..3].copy_from_slice(&home);
            }
            start[..3].copy_from_slice(&home);
        }
        if self.fanuc {
            // Fanuc: the local and common variables are vacant until assigned (the
            // parameters given set theirs).
            self.params.start_vacant();
        }
        for &(n, v) in &self.opts.parameters {
            if (1..=super::expr::MAX_PARAM).contains(&n) {
                self.set_numbered(n, v);
            }
        }
        if self.g92_flag != 0.0 {
            // LinuxCNC applies a G92 offset stored in the parameters at start-up.
            self.g92 = self.g92_saved;
        }
        // And the active system's (G54's) offsets and rotation from them.
        self.off = self.g5x_table[self.coord - 1];
        self.rot = self.rot_table[self.coord - 1];
        // Where that is in the frame the parameters set, as LinuxCNC reads its position back
        // after setting the offsets (the move builder re-expresses it alike).
        self.p = self.program_of(&start, &self.off, &self.g92, self.rot);
        self.emit(Canon::Units(self.units));
        self.emit_offsets();
        if start != [0.0; 6] {
            self.emit(Canon::SetPosition(Axes::from_array(self.p)));
        }
        self.emit(Canon::Plane(Plane::XY));
        if self.fanuc {
            // Fanuc's (and Haas's) feed over linear and rotary axes together.
            self.emit(Canon::RotaryFeedCombined(true));
        }
        self.pass_control = Some(super::control::PassControl::of(&self));
        let mut lb = LineBuf::default();
        let mut blk = Block::default();
        let startup = self.opts.ini.as_ref().and_then(|i| i.startup_code());
        if let Some((code, pos)) = startup.map(|(c, p)| (c.to_string(), p)) {
            // LinuxCNC's task runs the INI's start-up code before each program.
            if let Err(f) = self.exec_line(&code, &mut lb, &mut blk) {
                let mut e = self.to_error(f, &code, &lb);
                e.pos.file = pos.file;
                e.pos.line = pos.line;
                // (A column would count within the code, not the INI's line.)
                e.pos.column = 0;
                e.message = format!("{} (in the INI's RS274NGC_STARTUP_CODE)", e.message);
                return Err(e);
            }
        }
        loop {
            if self.at.file != self.cur_file {
                self.enter_file(self.at.file);
            }
            if self.ended || self.at.pos >= self.text.len() {
                break;
            }
            let text = self.text.clone();
            let start = self.at.pos;
            let (raw, next) = split_line(&text, start);
            self.at = Cursor {
                pos: next,
                line: self.at.line + 1,
                file: self.cur_file,
            };
            self.cur_line = self.at.line;
            self.cur_start = start;
            let mut result = self.exec_line(raw, &mut lb, &mut blk);
            if std::mem::take(&mut self.resync_after_block) {
                self.comp_resync_after_change();
            }
            if self.fanuc {
                self.tell_unmodelled_reads();
            }
            if result.is_ok() && self.sink.over {
                result = Err(self.move_limit_fault());
            }
            if let Err(f) = result {
                return Err(self.to_error(f, raw, &lb));
            }
        }
        self.comp_flush();
        if self.sink.over {
            // A compensated move held back for its corner, made at the end.
            let pos = SourcePos {
                file: self.file.to_string(),
                line: self.cur_line,
                column: 0,
            };
            return Err(crate::limit::move_limit_error(pos, "", self.sink.max()));
        }
        if !self.ended {
            if !self.frames.is_empty() {
                return Err(PathError::new(
                    SourcePos {
                        file: self.file.to_string(),
                        line: self.at.line,
                        column: 0,
                    },
                    PathErrorKind::Semantic,
                    "the file ends inside a subroutine call",
                    "",
                    "`endsub`, `return` or `M99`",
                ));
            }
            self.warn_at(0, "the program has no M2/M30 end".to_string());
        } else if self.frames.is_empty() {
            let n = self.code_after_end();
            if n > 0 {
                self.warn_at(
                    0,
                    format!(
                        "{n} line{} with code after the program's end here {} not read (a \
                         control stops at M2/M30 or the closing `%`; join programs without them)",
                        if n == 1 { "" } else { "s" },
                        if n == 1 { "is" } else { "are" }
                    ),
                );
            }
        }
        self.sink.finish();
        Ok(())
    }

    /// Lines with code after the program's end in its main file that no control would run:
    /// those of programs joined after it, not those of its subprograms (a Fanuc `O…`/`:…`
    /// program that returns with M99, a LinuxCNC `o… sub` … `endsub`, a Haas M97 local
    /// subprogram — `N…` blocks after M30 up to an M99).
    fn code_after_end(&self) -> usize {
        let Some(rest) = self.text.get(self.at.pos..) else {
            return 0;
        };
        // The code lines of the program being scanned, and whether it is a subprogram.
        let mut block: Option<(usize, bool)> = None;
        let mut total = 0;
        // Code lines outside any numbered program since the last M99 there (which makes them
        // a local subprogram, not code left over).
        let mut loose = 0;
        let done = |b: Option<(usize, bool)>, total: &mut usize| {
            if let Some((n, false)) = b {
                *total += n;
            }
        };
        let mut lb = LineBuf::default();
        for line in super::lexer::lines(rest) {
            // The reader's own lexer: comments and blanks out, lower case. (A line it cannot
            // read is code all the same.)
            let code: &[u8] = match normalize(line, &mut lb) {
                Ok(()) => &lb.code,
                Err(_) => b"?",
            };
            let program_number = matches!(code.first(), Some(b'o' | b':'))
                && code.len() > 1
                && code[1..].iter().all(u8::is_ascii_digit);
            match code.first() {
                None | Some(b'%') => {}
                Some(b'o') if code.ends_with(b"endsub") => {
                    block = block.map(|(n, _)| (n, true));
                    done(block.take(), &mut total);
                }
                Some(b'o') if code.ends_with(b"sub") => {
                    total += std::mem::take(&mut loose);
                    done(block.take(), &mut total);
                    block = Some((0, true));
                }
                _ if program_number => {
                    total += std::mem::take(&mut loose);
                    done(block.take(), &mut total);
                    block = Some((0, false));
                }
                _ => match &mut block {
                    Some((n, sub)) => {
                        *n += 1;
                        *sub |= code.windows(3).any(|w| w == b"m99");
                    }
                    None if code.windows(3).any(|w| w == b"m99") => loose = 0,
                    None => loose += 1,
                },
            }
        }
        done(block, &mut total);
        total + loose
    }

    /// Turns an internal fault on the current line into a [`PathError`].
    fn to_error(&self, f: Fault, raw: &str, lb: &LineBuf) -> PathError {
        let (a, b) = match f.span {
            Span::Line => (0, raw.len()),
            Span::Code(x, y) => lb.raw_range(x, y, raw.len()),
            Span::Raw(x, y) => (x.min(raw.len()), y.min(raw.len())),
        };
        let column = if f.span == Span::Line {
            0
        } else {
            column_of(raw, a)
        };
        let found = found_text(raw.get(a..b).unwrap_or(""));
        let (kind, message) = match (f.kind, Dialect::of_line(raw)) {
            (PathErrorKind::Syntax, Some(d)) => (
                PathErrorKind::Unsupported,
                format!(
                    "{} (this line is written for {d}, which swarf does not read)",
                    f.message
                ),
            ),
            _ => (f.kind, f.message),
        };
        PathError::new(
            SourcePos {
                file: self.file.to_string(),
                line: self.cur_line,
                column,
            },
            kind,
            message,
            found,
            f.expected,
        )
    }

    #[inline]
    pub(crate) fn emit(&mut self, e: Canon<'_>) {
        let moves = matches!(
            e,
            Canon::Traverse { .. } | Canon::Feed { .. } | Canon::Arc { .. }
        );
        if !self.tool_loaded && self.tool != 0 && moves {
            self.assume_prepared_tool_loaded();
        }
        if !self.units_stated && (moves || matches!(e, Canon::Spline { .. })) {
            self.units_not_stated();
        }
        // (A change of units is no motion: rs274 makes it at once, and the moves held behind
        // a compensated one print in the new units.)
        if self.comp.queue.is_empty() && self.comp.held_none() || matches!(e, Canon::Units(_)) {
            self.sink.emit(self.cur_line, &e);
        } else {
            // Behind a compensated move waiting for its corner.
            self.comp.queue.push((self.cur_line, e.to_owned_event()));
        }
    }

    /// Programs for CAMotics, GRBL and many hobby controllers select the tool with a lone `T`
    /// word and never say M6. Rather than simulate with no cutter, the prepared tool is taken as
    /// loaded when the first motion comes, and the assumption is reported.
    #[cold]
    fn assume_prepared_tool_loaded(&mut self) {
        self.tool_loaded = true;
        let tool = self.tool;
        self.read_only.loaded_tool = tool;
        self.sink.emit(self.cur_line, &Canon::ToolChange { tool });
        // Told after the block, at its first word (a column), as the block's own warnings.
        self.later.push((
            0,
            format!(
                "T{tool} was selected but not loaded with M6 yet at this move (it is assumed \
                 to be in the spindle)"
            ),
        ));
    }

    /// A program that moves before it says G20 or G21 is read in the initial units, which are
    /// the machine's on a control and a command-line option here: said once, at the first move,
    /// naming the units and the option.
    #[cold]
    fn units_not_stated(&mut self) {
        self.units_stated = true;
        let units = match self.opts.initial_units {
            Units::Mm => "mm",
            Units::Inch => "inches",
        };
        let whence = if self.opts.ini.is_some() {
            "the machine's (the INI's LINEAR_UNITS, or --initial-units)"
        } else {
            "the initial units (--initial-units, mm by default)"
        };
        self.warn_at(
            0,
            format!(
                "the program does not state its units (no G20 or G21 before its first move): \
                 it is read in {units}, {whence}"
            ),
        );
    }

    /// Fanuc: the first length or angle word written as a whole number without a decimal point
    /// (`X1000`, not `X0`, `X1000.` or `X#1`) is reported once. swarf reads it as that many
    /// units, as a control set for calculator-type input does; a Fanuc control with its
    /// default least-increment input (parameter DPI = 0) reads that many least increments
    /// (0.001 mm, 0.0001 in, 0.001°). Words that are no length or angle are not: a cycle's
    /// repeat count K, a controller mode's Q/R, G04's X (a time), G51's I J K (factors).
    fn warn_without_point(&mut self, b: &Block, lb: &LineBuf, dwell_x: bool) {
        if !self.fanuc || self.point_warned || b.no_point == 0 {
            return;
        }
        let mode = b.g(group::MOTION).or(self.motion);
        let cycle = matches!(mode, Some(730 | 740 | 810..=860 | 880 | 890));
        let m_q = b.m_other[..b.n_other]
            .iter()
            .any(|&(m, _)| m == 61 || (62..=68).contains(&m));
        for c in *b"xyzabcijkrq" {
            if !b.without_point(c) || b.val[block::slot(c)] == 0.0 {
                continue;
            }
            let not_length = match c {
                b'x' => dwell_x,
                b'q' | b'r' if b.n_modes > 0 => true,
                b'q' => m_q,
                b'k' if cycle => true,
                b'i' | b'j' | b'k' => {
                    let g435 = self.tcp_vector || b.g(group::TOOL_LENGTH) == Some(435);
                    b.g(group::SCALING) == Some(510) || (g435 && matches!(mode, Some(0 | 10)))
                }
                _ => false,
            };
            if not_length {
                continue;
            }
            let angle = matches!(c, b'a' | b'b' | b'c')
                || (c == b'r' && b.g(group::ROTATION) == Some(680))
                || (matches!(c, b'i' | b'j' | b'k') && b.g(group::ROTATION) == Some(682));
            let v = b.val[block::slot(c)];
            let (read, fanuc) = match (angle, self.units) {
                (true, _) => (format!("{v}°"), format!("{:.3}°", v * 0.001)),
                (false, Units::Mm) => (format!("{v} mm"), format!("{:.3} mm", v * 0.001)),
                (false, Units::Inch) => (format!("{v} in"), format!("{:.4} in", v * 0.0001)),
            };
            self.point_warned = true;
            self.warn_code(
                lb,
                b.at[block::slot(c)] as usize,
                format!(
                    "{}{v} has no decimal point: read as {read} (calculator-type input); a \
                     Fanuc control set for least-increment input (DPI=0) reads {fanuc} — check \
                     the program",
                    char::from(c.to_ascii_uppercase())
                ),
            );
            return;
        }
    }

    pub(crate) fn emit_offsets(&mut self) {
        // A Fanuc G68 rotation is stated as part of the G92 offset and the XY rotation.
        let (g92, rot) = self.effective_frame(&self.g92, self.rot);
        let e = Canon::Offsets {
            index: self.coord as u8,
            g5x: Axes::from_array(self.off),
            g92: Axes::from_array(g92),
        };
        self.emit(e);
        self.emit(Canon::XyRotation(rot));
    }

    /// Continues in file `index` of [`Self::files`], and says so to the sink.
    fn enter_file(&mut self, index: u32) {
        let (name, text) = self.files[index as usize].clone();
        self.cur_file = index;
        self.text = text;
        self.file = name.clone();
        self.emit(Canon::SourceFile(Cow::Borrowed(&name)));
    }

    /// A warning at raw byte offset `byte` of the current line (0: the whole line).
    pub(crate) fn warn_at(&mut self, column: u32, message: String) {
        self.sink.warn(Warning {
            file: self.file.to_string(),
            line: self.cur_line,
            column,
            message,
        });
    }

    fn warn_code(&mut self, lb: &LineBuf, code_at: usize, message: String) {
        let raw_at = lb.offs.get(code_at).map_or(0, |&o| o as usize);
        let text = self.text.clone();
        let raw = split_line(&text, self.cur_start).0;
        self.warn_at(column_of(raw, raw_at), message);
    }

    /// The error for a line that made a move over [`GcodeOptions::max_moves`].
    fn move_limit_fault(&self) -> Fault {
        let (message, expected) = move_limit_message(self.sink.max());
        Fault::new(PathErrorKind::Limit, Span::Line, message, expected)
    }

    /// Counts one backward jump (loop iteration, call, repeat).
    pub(crate) fn count_iteration(&mut self, span: Span) -> Res<()> {
        if self.sink.over {
            // A loop that made a move over the limit stops at once.
            return Err(self.move_limit_fault());
        }
        self.iterations += 1;
        if self.iterations > self.opts.max_loop_iterations {
            return Err(Fault::new(
                PathErrorKind::Limit,
                span,
                format!(
                    "more than {} loop iterations, calls and repeats: the program may never end \
                     (the reader's limit on iterations)",
                    self.opts.max_loop_iterations
                ),
                "",
            ));
        }
        Ok(())
    }

    /// The line's comments, in order: `(ABORT,…)` ends the program with its message, active
    /// comments (`MSG`, `DEBUG`, `PRINT`, `LOG`…) are messages with parameters substituted,
    /// the others plain comments. LinuxCNC keeps a line's last comment only (rs274 prints
    /// `MESSAGE("second")` alone for `(msg,first) (msg,second)`).
    fn comments(&mut self, raw: &str, lb: &LineBuf) -> Res<()> {
        let first = if self.fanuc {
            0
        } else {
            lb.comments.len().saturating_sub(1)
        };
        for &(a, b) in &lb.comments[first..] {
            let text = &raw[a as usize..b as usize];
            // LinuxCNC's `(ABORT,…)`: the program stops here with the message as its error.
            if let Some((head, body)) = comment_head(text) {
                if head.eq_ignore_ascii_case("abort") {
                    return Err(Fault::new(
                        PathErrorKind::Semantic,
                        Span::Raw(a as usize, b as usize),
                        format!("the program aborts: {}", self.substitute_parameters(body)),
                        "",
                    ));
                }
            }
            let event = match active_comment(text) {
                // LinuxCNC prints no DEBUG message while #5599 is 0 (its default is 1).
                Some((MessageKind::Debug, _)) if !self.fanuc && self.params.num[5599] == 0.0 => {
                    continue
                }
                Some((kind, body)) => Canon::Message {
                    kind,
                    text: if kind == MessageKind::Msg {
                        Cow::Borrowed(body)
                    } else {
                        Cow::Owned(self.substitute_parameters(body))
                    },
                },
                None => Canon::Comment(Cow::Borrowed(text)),
            };
            self.sink.emit(self.cur_line, &event);
        }
        Ok(())
    }

    fn exec_line(&mut self, raw: &str, lb: &mut LineBuf, blk: &mut Block) -> Res<()> {
        normalize(raw, lb)?;
        if lb.deleted {
            let skip = self.opts.block_delete;
            if !std::mem::replace(&mut self.deleted_warned, true) {
                self.warn_at(
                    1,
                    if skip {
                        "line skipped: block delete (`/`) is on (--block-delete; first such \
                         line)"
                    } else {
                        "line read: it starts with `/` (block delete), and the switch is off, \
                         as LinuxCNC's starts (first such line; --block-delete skips them)"
                    }
                    .into(),
                );
            }
            if skip {
                return Ok(());
            }
        }
        if is_grbl_command(&lb.code) {
            return self.grbl_command(lb);
        }
        if lb.code.first() == Some(&b'%') {
            // Tape markers: the first opens the program, the next one ends it.
            if self.tape || self.seen_code {
                self.ended = true;
            }
            self.tape = true;
            return Ok(());
        }
        if lb.code.is_empty() {
            return self.comments(raw, lb);
        }
        self.seen_code = true;
        let o_at = skip_line_number(&lb.code);
        if lb.code.get(o_at) == Some(&b'o') {
            self.comments(raw, lb)?;
            return self.exec_oword(lb, o_at);
        }
        if self.fanuc && is_macro_b(&lb.code[o_at..]) {
            self.comments(raw, lb)?;
            return self.exec_macro_b(lb, o_at);
        }
        block::parse(lb, blk, &*self, self.fanuc)?;
        // Parameters assigned on the line take effect once all of it was read, before its
        // comments: `#1=5 (DEBUG,#1)` prints 5, as LinuxCNC copies a line's assignments into
        // its table before executing the block.
        for &(t, v) in &blk.assigns[..blk.n_assigns] {
            match t {
                Target::Num(n) if self.fanuc && n >= 1000 => {
                    self.fanuc_system_write(raw, lb, n, v)?
                }
                Target::Num(n) => self.set_numbered(n, v),
                Target::Named(x, y) => {
                    let name = std::str::from_utf8(&lb.code[x as usize..y as usize]).unwrap_or("");
                    self.params.set_named(name, v);
                }
            }
        }
        self.comments(raw, lb)?;

        let spindle_words = blk.has(b's') || blk.m_spindle.is_some();
        if let Some((n, at)) = blk.spindle.filter(|&(n, _)| n > 0 && spindle_words) {
            // One spindle is simulated: the others' speeds and turns are read as its own.
            self.later.push((
                at as usize,
                format!(
                    "${n}: spindle {n} selected; swarf simulates one spindle, and this block's \
                     spindle words (S, M3, M4, M5) are read as its own"
                ),
            ));
        }
        self.execute(blk, lb)?;
        for (at, message) in std::mem::take(&mut self.later) {
            self.warn_code(lb, at, message);
        }
        Ok(())
    }

    /// A GRBL system command ([`is_grbl_command`]): a line for GRBL itself, not
    /// G-code. Those that do not move the tool are skipped with a warning; a jog, and a homing
    /// cycle once the program has moved (it ends wherever the machine's switches are), are
    /// refused, since skipping them would change the motion.
    fn grbl_command(&mut self, lb: &LineBuf) -> Res<()> {
        let code = &lb.code[..];
        let span = Span::Code(0, code.len());
        if code.starts_with(b"$j=") {
            return Err(Fault::new(
                PathErrorKind::Unsupported,
                span,
                "a GRBL jog command ($J=…) moves the machine: it is not read",
                "G0/G1 moves",
            ));
        }
        let homing = code.starts_with(b"$h") && code[2..].iter().all(|c| b"xyzabc".contains(c));
        if homing && (self.sink.moves() > 0 || !self.comp.queue.is_empty()) {
            return Err(Fault::new(
                PathErrorKind::Unsupported,
                span,
                "a GRBL homing cycle ($H) after the program has moved: where it leaves the tool \
                 depends on the machine's switches",
                "`$H` before the first move (where it is skipped), or G28/G53 moves",
            ));
        }
        let shown = String::from_utf8_lossy(&code[..code.len().min(24)]).to_ascii_uppercase();
        let why = if homing {
            "the program starts at the machine's home (--home) anyway"
        } else {
            "a GRBL system command does not move the tool"
        };
        self.warn_code(lb, 0, format!("`{shown}` skipped: {why}"));
        Ok(())
    }

    /// A dwell time `v` given by word `c` (G4's P or X, a canned cycle's P), in seconds. Fanuc:
    /// a number without a decimal point counts milliseconds (`G04 P500`, `G82 … P500`; Haas
    /// reads `P0.5` as seconds); LinuxCNC: seconds.
    pub(crate) fn dwell_seconds(&self, b: &Block, c: u8, v: f64) -> f64 {
        if self.fanuc && b.without_point(c) {
            v / 1000.0
        } else {
            v
        }
    }

    /// Program units → mm for axis `i` (rotary axes stay in degrees).
    #[inline]
    pub(crate) fn mm_from_units(&self, i: usize, v: f64) -> f64 {
        if i < 3 {
            v * self.scale
        } else {
            v
        }
    }

    #[inline]
    pub(crate) fn to_units(&self, i: usize, v: f64) -> f64 {
        if i < 3 {
            v / self.scale
        } else {
            v
        }
    }

    /// Numbered parameter with LinuxCNC's views onto the offset tables, in program units.
    pub(crate) fn get_numbered(&self, n: usize) -> f64 {
        match n {
            5161..=5166 => self.to_param_units(n - 5161, self.homes[0][n - 5161]),
            5181..=5186 => self.to_param_units(n - 5181, self.homes[1][n - 5181]),
            5210 => self.g92_flag,
            5211..=5216 => self.to_param_units(n - 5211, self.g92_saved[n - 5211]),
            5220 => self.coord as f64,
            5221..=5386 if (n - 5221) % 20 < 6 => {
                let (k, i) = ((n - 5221) / 20, (n - 5221) % 20);
                self.to_param_units(i, self.g5x_table[k][i])
            }
            5230..=5390 if (n - 5230) % 20 == 0 => self.rot_table[(n - 5230) / 20],
            5420..=5425 => self.to_units(n - 5420, self.p[n - 5420]),
            // The machine position (G53 coordinates) of the controlled point: a tool length
            // offset that moves nothing leaves it alone.
            5021..=5026 => self.to_units(
                n - 5021,
                self.controlled()[n - 5021] - self.g53_origin()[n - 5021],
            ),
            5400 => f64::from(self.read_only.loaded_tool),
            // The tool's offsets and diameter, as LinuxCNC's tool table keeps them (in the
            // machine's units, `PROGRAM_TO_USER_LEN`: G20/G21 do not change what they read).
            5401..=5406 => {
                let e = self
                    .tool_table
                    .get(&self.read_only.loaded_tool)
                    .copied()
                    .unwrap_or([0.0; 6]);
                self.to_param_units(n - 5401, e[n - 5401])
            }
            5407..=5409 | 5411..=5413 => 0.0,
            5410 => self.to_param_units(
                0,
                self.tool_diameter(self.read_only.loaded_tool)
                    .unwrap_or(0.0),
            ),
            _ => self.params.num[n],
        }
    }

    /// Sets numbered parameter `n`. A plain parameter stores `v` as it is (a Fanuc vacant
    /// variable's value too); a view onto the control's state takes a vacant one as 0.
    pub(crate) fn set_numbered(&mut self, n: usize, v: f64) {
        let (plain, v) = (v, super::expr::number(v));
        match n {
            5161..=5166 => self.homes[0][n - 5161] = self.mm_from_param_units(n - 5161, v),
            5181..=5186 => self.homes[1][n - 5181] = self.mm_from_param_units(n - 5181, v),
            5210 => self.g92_flag = v,
            5211..=5216 => self.g92_saved[n - 5211] = self.mm_from_param_units(n - 5211, v),
            5221..=5386 if (n - 5221) % 20 < 6 => {
                let (k, i) = ((n - 5221) / 20, (n - 5221) % 20);
                self.g5x_table[k][i] = self.mm_from_param_units(i, v);
            }
            5230..=5390 if (n - 5230) % 20 == 0 => self.rot_table[(n - 5230) / 20] = v,
            // Read-only views: the machine position, the active system, the tool, the position.
            5021..=5026 | 5220 | 5400..=5413 | 5420..=5428 => {}
            // An O-word call's arguments are its own, put back when it returns.
            1..=super::params::N_ARGS if self.frames.iter().any(|f| f.fanuc.is_none()) => {
                self.params.num[n] = plain
            }
            _ => self.params.set_num(n, plain),
        }
    }

    /// mm → the units of the offset parameters (LinuxCNC keeps them in the machine's units,
    /// whatever G20/G21 says).
    fn to_param_units(&self, i: usize, v: f64) -> f64 {
        if i < 3 {
            v / self.opts.parameter_units().mm_per_unit()
        } else {
            v
        }
    }

    fn mm_from_param_units(&self, i: usize, v: f64) -> f64 {
        if i < 3 {
            v * self.opts.parameter_units().mm_per_unit()
        } else {
            v
        }
    }

    /// The machine position of program position `p`: the G92 offset, the XY rotation, the
    /// G5x offset (LinuxCNC's canon layer).
    pub(crate) fn machine_of(&self, p: &[f64; 6]) -> [f64; 6] {
        let (g92, rot) = self.effective_frame(&self.g92, self.rot);
        let p = self.untilted(p);
        let q: [f64; 6] = std::array::from_fn(|i| p[i] + g92[i]);
        let q = rotate_xy(q, rot);
        std::array::from_fn(|i| q[i] + self.off[i])
    }

    /// Program position `p` in the untilted program frame (G68.2's origin plus its axes
    /// times `p`; rotary words as they are).
    pub(crate) fn untilted(&self, p: &[f64; 6]) -> [f64; 6] {
        let Some(w) = &self.tilt else { return *p };
        let q = Vec3::from_array(w.origin) + w.matrix() * Vec3::new(p[0], p[1], p[2]);
        [q.x, q.y, q.z, p[3], p[4], p[5]]
    }

    /// [`Self::untilted`] inverted.
    fn tilted(&self, q: &[f64; 6]) -> [f64; 6] {
        let Some(w) = &self.tilt else { return *q };
        let p = w.matrix().transpose() * (Vec3::new(q[0], q[1], q[2]) - Vec3::from_array(w.origin));
        [p.x, p.y, p.z, q[3], q[4], q[5]]
    }

    /// The program position of machine position `m` under offsets `off`, `g92` and rotation
    /// `rot` (degrees).
    pub(crate) fn program_of(
        &self,
        m: &[f64; 6],
        off: &[f64; 6],
        g92: &[f64; 6],
        rot: f64,
    ) -> [f64; 6] {
        let (g92, rot) = self.effective_frame(g92, rot);
        let q: [f64; 6] = std::array::from_fn(|i| m[i] - off[i]);
        let q = rotate_xy(q, -rot);
        self.tilted(&std::array::from_fn(|i| q[i] - g92[i]))
    }

    /// The tool tip's machine position (swarf's positions are the tip's).
    pub(crate) fn machine(&self) -> [f64; 6] {
        self.machine_of(&self.p)
    }

    /// The controlled point's machine position, LinuxCNC's machine position: the tip's plus
    /// the tool length offset in effect ([`Self::tlo`]). G53, G28/G30 and G28.1/G30.1 work
    /// with it.
    pub(crate) fn controlled(&self) -> [f64; 6] {
        let m = self.machine();
        std::array::from_fn(|i| m[i] + self.tlo[i])
    }

    /// The tip's program position when the controlled point is at machine position `m`
    /// (LinuxCNC subtracts the tool offset along with the work and G92 offsets).
    pub(crate) fn program_of_controlled(&self, m: &[f64; 6]) -> [f64; 6] {
        let tip: [f64; 6] = std::array::from_fn(|i| m[i] - self.tlo[i]);
        self.program_of(&tip, &self.off, &self.g92, self.rot)
    }

    /// Where G53's zero is in swarf's machine frame (the work frame with no offsets): the home
    /// when one is given, for the whole program — machine zero is the home (reference point)
    /// on Fanuc, Haas, GRBL and Mach3 controls, and G92, G10 and G54–G59 move the work's zero,
    /// not the machine's; else the origin, as LinuxCNC's usual `HOME = 0`.
    pub(crate) fn g53_origin(&self) -> [f64; 6] {
        let mut o = [0.0; 6];
        if let Some(h) = self.opts.home {
            o[..3].copy_from_slice(&h);
        }
        o
    }

    /// Changes the offsets in effect keeping the machine position, and says so.
    fn set_offsets(&mut self, off: [f64; 6], g92: [f64; 6]) {
        self.set_frame(off, g92, self.rot);
    }

    /// Changes the offsets and the XY rotation in effect keeping the machine position.
    /// Under cutter compensation the tool's point and the held move are re-expressed too.
    pub(crate) fn set_frame(&mut self, off: [f64; 6], g92: [f64; 6], rot: f64) {
        let m = self.machine();
        let comp_points = self.comp_points();
        let old = (self.off, self.g92, self.rot);
        self.off = off;
        self.g92 = g92;
        self.rot = rot;
        self.p = self.program_of(&m, &off, &g92, rot);
        if let Some(pts) = comp_points {
            self.comp_reframe(pts, old);
        }
        self.emit_offsets();
    }

    /// Fanuc's tool centre point control (G43.4/G43.5) on or off: the sink re-expresses the
    /// position where the tool stands, and the program position follows it.
    fn tool_centre_point(&mut self, on: bool) {
        let before = self.sink.position();
        self.emit(Canon::ToolCentrePoint(on));
        crate::reader_core::follow_sink(&mut self.p, before, self.sink.position());
    }

    /// What LinuxCNC's `M6` does before the change (convert_tool_change): the spindle stops
    /// (unless the INI's `TOOL_CHANGE_WITH_SPINDLE_ON`), Z rapids up to machine Z0
    /// (`TOOL_CHANGE_QUILL_UP`), then every axis to the G30 position (`TOOL_CHANGE_AT_G30`).
    /// Whether it moved (from the programmed point, as rs274's moves start).
    fn tool_change_moves(&mut self) -> bool {
        let how = self.tool_change;
        // Before the first change the spindle holds no tool: the moves up are made with the
        // one being loaded (they cut nothing), not with tool 0, which nothing defines.
        if !self.tool_loaded && (how.quill_up || how.at_g30) {
            self.tool_loaded = true;
            self.emit(Canon::ToolChange { tool: self.tool });
        }
        if !how.with_spindle_on {
            self.dir = SpindleDir::Stopped;
            self.emit(Canon::Spindle {
                rpm: self.rpm,
                dir: SpindleDir::Stopped,
            });
        }
        if how.quill_up {
            let mut m = self.controlled();
            m[2] = self.g53_origin()[2];
            let up = self.program_of_controlled(&m);
            self.p[2] = up[2];
            self.emit(Canon::Traverse {
                end: Axes::from_array(self.p),
            });
        }
        if how.at_g30 {
            self.p = self.program_of_controlled(&self.homes[1]);
            self.emit(Canon::Traverse {
                end: Axes::from_array(self.p),
            });
        }
        how.quill_up || how.at_g30
    }

    /// Puts tool length offset `t` in effect: the controlled point stays where it is, so the
    /// program position reads the offset's change less.
    pub(crate) fn set_tlo(&mut self, t: [f64; 6]) {
        let m = self.machine();
        let moved: [f64; 6] = std::array::from_fn(|i| m[i] - (t[i] - self.tlo[i]));
        self.tlo = t;
        self.p = self.program_of(&moved, &self.off, &self.g92, self.rot);
    }

    /// A Fanuc system variable assigned: `#3000 = n (MESSAGE)` is a macro alarm (the program
    /// stops: an error here), `#3006 = n (MESSAGE)` a stop with a message (the operator
    /// restarts it: a warning), the others stored (reading them back gives the value).
    fn fanuc_system_write(&mut self, raw: &str, lb: &LineBuf, n: usize, v: f64) -> Res<()> {
        let message = lb
            .comments
            .first()
            .map_or("", |&(a, b)| raw[a as usize..b as usize].trim());
        let at = find_code(&lb.code, format!("#{n}").as_bytes());
        if n == 3000 || n == 3006 {
            let v = super::expr::number(v);
            if n == 3000 {
                return Err(Fault::new(
                    PathErrorKind::Semantic,
                    at.map_or(Span::Line, |i| Span::Code(i, i + 5)),
                    format!(
                        "macro alarm {} ({}): #3000={v} stops the program here",
                        3000.0 + v,
                        if message.is_empty() {
                            "no message"
                        } else {
                            message
                        }
                    ),
                    "",
                ));
            }
            self.later.push((
                at.unwrap_or(0),
                format!(
                    "#3006={v} ({message}): the control stops here until cycle start is \
                     pressed; read on"
                ),
            ));
            return Ok(());
        }
        if !self.sysvar_written.contains(&n) {
            self.sysvar_written.push(n);
        }
        self.set_numbered(n, v);
        Ok(())
    }

    /// The block's effects, its parameter assignments already made ([`Interp::exec_line`]).
    fn execute(&mut self, b: &Block, lb: &LineBuf) -> Res<()> {
        if self.fanuc {
            for (k, c) in [b'd', b'h'].into_iter().enumerate() {
                if let Some(v) = b.get(c) {
                    self.last_dh[k] = Some(v);
                }
            }
        }
        if let Some(g) = b.g(group::FEED_MODE) {
            let m = match g {
                930 => FeedMode::InverseTime,
                940 => FeedMode::PerMinute,
                _ => FeedMode::PerRevolution,
            };
            // LinuxCNC's convert_feed_mode forgets the feed rate at every G94 and G95, even
            // in that mode already (not at G93, whose moves each carry their F); a Fanuc control
            // when the mode changes.
            let forget = if self.fanuc() {
                m != self.feed_mode
            } else {
                m != FeedMode::InverseTime
            };
            if forget {
                self.feed = 0.0;
            }
            if m != self.feed_mode {
                self.feed_mode = m;
                self.emit(Canon::FeedMode(m));
            }
        }
        if let Some(f) = b.get(b'f') {
            if f < 0.0 {
                return Err(Fault::semantic(b.span(b'f'), "negative feed rate"));
            }
            // The units the F word is read in: LinuxCNC sets the feed before the block's
            // G20/G21 takes effect (rs274's order), a Fanuc control reads the whole block in
            // the units it selects.
            let block_units = b
                .g(group::UNITS)
                .map(|g| if g == 200 { Units::Inch } else { Units::Mm });
            let scale =
                match block_units {
                    Some(u) if self.fanuc() => u.mm_per_unit(),
                    Some(u) if u != self.units && self.feed_mode != FeedMode::InverseTime => {
                        let at = match b.span(b'f') {
                            Span::Code(a, _) => a,
                            _ => 0,
                        };
                        self.warn_code(
                            lb,
                            at,
                            format!(
                            "F read in {} before this block's {} (LinuxCNC sets the feed first; a \
                             Fanuc control reads it in the new units): give F on a later line",
                            if self.units == Units::Inch { "inches" } else { "millimetres" },
                            if u == Units::Inch { "G20" } else { "G21" }
                        ),
                        );
                        self.scale
                    }
                    _ => self.scale,
                };
            self.feed = if self.feed_mode == FeedMode::InverseTime {
                f
            } else {
                f * scale
            };
            self.read_only.feed_scale = scale;
            self.emit(Canon::FeedRate(self.feed));
        }
        if let Some(s) = b.get(b's') {
            if s < 0.0 {
                return Err(Fault::semantic(b.span(b's'), "negative spindle speed"));
            }
            self.rpm = s;
            if b.m_spindle.is_none() {
                self.emit(Canon::Spindle {
                    rpm: self.rpm,
                    dir: self.dir,
                });
            }
        }
        if let Some(t) = b.get(b't') {
            if t < 0.0 || t.fract() != 0.0 || t > f64::from(u32::MAX) {
                return Err(Fault::new(
                    PathErrorKind::Semantic,
                    b.span(b't'),
                    "bad tool number",
                    "a non-negative integer",
                ));
            }
            self.tool = t as u32;
            self.read_only.selected_tool = Some(self.tool);
        }
        if b.m6 {
            if self.comp.on() {
                return Err(Fault::semantic(
                    Span::Line,
                    "cannot change tools with cutter radius compensation on",
                ));
            }
            if !self.fanuc {
                // (After the block: a move in it starts from the programmed point.)
                self.resync_after_block = !self.tool_change_moves();
            }
            self.tool_loaded = true;
            self.read_only.loaded_tool = self.tool;
            self.emit(Canon::ToolChange { tool: self.tool });
        }
        if let Some(m) = b.m_spindle {
            self.dir = match m {
                3 => SpindleDir::Clockwise,
                4 => SpindleDir::CounterClockwise,
                _ => SpindleDir::Stopped,
            };
            self.emit(Canon::Spindle {
                rpm: self.rpm,
                dir: self.dir,
            });
        }
        for &(m, at) in &b.m_other[..b.n_other] {
            // (A Fanuc control's M61 without Q is the machine builder's own code.)
            if m == 61 && (!self.fanuc || b.has(b'q')) {
                // M61 Q<n>: the tool in the spindle is now tool n, without a change.
                let q = b
                    .get(b'q')
                    .filter(|q| *q >= 0.0 && q.fract() == 0.0 && *q <= f64::from(u32::MAX));
                let Some(q) = q else {
                    return Err(Fault::new(
                        PathErrorKind::Semantic,
                        Span::Code(at as usize, at as usize + 3),
                        "M61 needs a tool number Q",
                        "Q<tool number>",
                    ));
                };
                // The selected tool (a later bare M6 loads it) stays as it is.
                self.tool_loaded = true;
                self.read_only.loaded_tool = q as u32;
                self.emit(Canon::ToolChange { tool: q as u32 });
                continue;
            }
            // (Also under Fanuc rules: LinuxCNC programs with M98 subprograms read by them.)
            let ro = &mut self.read_only;
            let p_on = b.get(b'p') != Some(0.0);
            match m {
                7 => ro.mist = true,
                8 => ro.flood = true,
                9 => (ro.mist, ro.flood) = (false, false),
                48 | 49 => (ro.overrides[0], ro.overrides[1]) = (m == 48, m == 48),
                50..=53 => ro.overrides[usize::from(m - 50)] = p_on,
                _ => {}
            }
            if (70..=73).contains(&m) {
                self.modal_save_restore(m, Span::Code(at as usize, at as usize + 3))?;
                continue;
            }
            let what = match m {
                7 => "M7 (mist coolant on)".to_string(),
                8 => "M8 (flood coolant on)".to_string(),
                9 => "M9 (coolant off)".to_string(),
                19 => "M19 (spindle orientation)".to_string(),
                10 | 12 if self.fanuc => format!("M{m} (rotary axis brake clamp)"),
                11 | 13 if self.fanuc => format!("M{m} (rotary axis brake unclamp)"),
                29 if self.fanuc => "M29 (rigid tapping mode)".to_string(),
                48..=53 => format!("M{m} (override control)"),
                61 => "M61 without Q".to_string(),
                62..=65 => format!("M{m} (digital output)"),
                66 => "M66 (wait on input)".to_string(),
                67 | 68 => format!("M{m} (analog output)"),
                100..=199 => format!("M{m} (user-defined M code)"),
                _ => format!("M{m} (unknown M code)"),
            };
            // Told at its first use only (a post's M8/M9 around every operation said the same
            // thing a dozen times).
            if !self.m_ignored_told.contains(&m) {
                self.m_ignored_told.push(m);
                self.warn_code(
                    lb,
                    at as usize,
                    format!(
                        "{what} ignored: it does not move the tool (the first M{m}; later ones \
                         are not reported)"
                    ),
                );
            }
        }
        for &(g, at) in &b.modes[..b.n_modes] {
            let (what, why) = block::fanuc_mode(g).unwrap_or_default();
            self.warn_code(
                lb,
                at as usize,
                format!("{} ({what}) ignored: {why}", block::g_name(g)),
            );
        }
        if b.fine_boring {
            self.warn_code(
                lb,
                b.g_at[group::MOTION] as usize,
                "G76 (fine boring) read as G86: the shift away from the wall (Q) before the \
                 retract is not simulated"
                    .into(),
            );
        }
        let nonmodal = b.g(group::NON_MODAL);
        // Fanuc: `G04 X1.5` dwells (X is the time, not an axis).
        let dwell_x = self.fanuc && nonmodal == Some(40) && !b.has(b'p') && b.has(b'x');
        self.warn_without_point(b, lb, dwell_x);
        if nonmodal == Some(40) {
            let c = if dwell_x { b'x' } else { b'p' };
            let p = b.get(c).ok_or_else(|| {
                Fault::new(
                    PathErrorKind::Semantic,
                    b.g_span(group::NON_MODAL),
                    "G4 needs a P word",
                    if self.fanuc {
                        "P<milliseconds> or X<seconds>"
                    } else {
                        "P<seconds>"
                    },
                )
            })?;
            if p < 0.0 {
                return Err(Fault::semantic(b.span(c), "negative dwell time"));
            }
            self.emit(Canon::Dwell(self.dwell_seconds(b, c, p)));
        }
        if let Some(g) = b.g(group::PLANE) {
            if self.comp.on() {
                return Err(Fault::semantic(
                    b.g_span(group::PLANE),
                    "cannot change planes with cutter radius compensation on",
                ));
            }
            self.plane = match g {
                170 => Plane::XY,
                180 => Plane::XZ,
                _ => Plane::YZ,
            };
            self.emit(Canon::Plane(self.plane));
        }
        let mut axes_used_by_nonmotion = dwell_x || b.mirror_cancel;
        if let Some(g) = b.g(group::UNITS) {
            // LinuxCNC 2.9 changes units under compensation (convert_length_units scales the
            // radius and the held moves; swarf keeps them in mm); Fanuc controls refuse.
            if self.comp.on() && self.fanuc {
                return Err(Fault::semantic(
                    b.g_span(group::UNITS),
                    "cannot change units with cutter radius compensation on",
                ));
            }
            let units = if g == 200 { Units::Inch } else { Units::Mm };
            self.units_stated = true;
            if let Some((code, at, _)) = b.units_synonym {
                if units != self.units {
                    self.warn_code(
                        lb,
                        at as usize,
                        format!(
                            "{} read as {} ({}), as Mach3 and older controls read it",
                            block::g_name(code),
                            block::g_name(g),
                            if g == 200 { "inch" } else { "millimetres" }
                        ),
                    );
                }
            }
            self.units = units;
            self.scale = self.units.mm_per_unit();
            self.emit(Canon::Units(self.units));
        }
        if let Some(g) = b.g(group::CUTTER_COMP) {
            self.comp_mode(b, g)?;
            self.read_only.ccomp = g;
        }
        if let Some(g) = b.g(group::SCALING) {
            self.scaling(b, g)?;
            axes_used_by_nonmotion |= g == 510;
        }
        if let Some(g) = b.g(group::ROTATION) {
            self.rotation(b, g)?;
            axes_used_by_nonmotion |= g == 680 || g == 682;
        }
        match b.g(group::TOOL_LENGTH) {
            Some(g @ (430 | 434 | 435 | 2340)) => {
                // Fanuc's tool centre point control is a mode of the program: G43.4 / G43.5
                // (Haas G234) turn it on, a plain G43 (or G49, below) off.
                if self.fanuc {
                    self.tool_centre_point(g != 430);
                }
                self.tcp_vector = self.fanuc && g == 435;
                let tool = match b.get(b'h') {
                    Some(h) if h >= 0.0 && h.fract() == 0.0 && h <= f64::from(u32::MAX) => h as u32,
                    _ => self.read_only.loaded_tool,
                };
                let entry = self.tool_table.get(&tool).copied();
                if entry.is_none() && b.get(b'h').is_some() && !self.tlo_warned {
                    // Once: X Y Z are tool-tip positions whatever the length, so the offset
                    // only shows in the position parameters and the next incremental move.
                    self.tlo_warned = true;
                    self.warn_code(
                        lb,
                        b.at[block::slot(b'h')] as usize,
                        format!(
                            "G43 H{tool}: the tool table gives no offset for tool {tool}, so the \
                             tool length offset is taken as 0 (the tool tip goes where X Y Z say \
                             all the same; the first such G43, others are not reported)"
                        ),
                    );
                }
                let t = entry.unwrap_or([0.0; 6]);
                self.read_only.tlo_on = true;
                self.set_tlo(t);
                self.emit(Canon::ToolLengthOffset(t[2]));
            }
            Some(431) => {
                // G43.1: the offset along each axis given (Z for a mill; X and Z on a lathe),
                // the others kept as they are (LinuxCNC starts from the offset in effect).
                if !AXIS_LETTERS.iter().any(|&c| b.has(c)) {
                    return Err(Fault::new(
                        PathErrorKind::Semantic,
                        b.g_span(group::TOOL_LENGTH),
                        "G43.1 needs an axis word",
                        "Z<offset> (or X Y A B C)",
                    ));
                }
                axes_used_by_nonmotion = true;
                let mut t = self.tlo;
                for (i, &c) in AXIS_LETTERS.iter().enumerate() {
                    if let Some(v) = b.get(c) {
                        t[i] = if i < 3 { v * self.scale } else { v };
                    }
                }
                self.read_only.tlo_on = true;
                self.set_tlo(t);
                self.emit(Canon::ToolLengthOffset(t[2]));
            }
            Some(432) => {
                // G43.2: an offset added to the one in effect — tool H's, or the axis words'.
                if b.has(b'h') && AXIS_LETTERS.iter().any(|&c| b.has(c)) {
                    return Err(Fault::new(
                        PathErrorKind::Semantic,
                        b.g_span(group::TOOL_LENGTH),
                        "G43.2 with both H and axis words",
                        "G43.2 H<tool> or G43.2 with axis words",
                    ));
                }
                let add = match b.get(b'h') {
                    Some(h) if h >= 0.0 && h.fract() == 0.0 && h <= f64::from(u32::MAX) => self
                        .tool_table
                        .get(&(h as u32))
                        .copied()
                        .unwrap_or([0.0; 6]),
                    Some(_) => {
                        return Err(Fault::new(
                            PathErrorKind::Semantic,
                            b.span(b'h'),
                            "bad tool number in G43.2 H",
                            "a non-negative integer",
                        ))
                    }
                    None => {
                        axes_used_by_nonmotion = true;
                        std::array::from_fn(|i| {
                            b.get(AXIS_LETTERS[i])
                                .map_or(0.0, |v| self.mm_from_units(i, v))
                        })
                    }
                };
                let t: [f64; 6] = std::array::from_fn(|i| self.tlo[i] + add[i]);
                self.read_only.tlo_on = true;
                self.set_tlo(t);
                self.emit(Canon::ToolLengthOffset(t[2]));
            }
            Some(_) => {
                self.read_only.tlo_on = false;
                self.set_tlo([0.0; 6]);
                self.emit(Canon::ToolLengthOffset(0.0));
                if self.fanuc {
                    self.tool_centre_point(false);
                }
                self.tcp_vector = false;
            }
            None => {}
        }
        if b.g(group::COORD).is_some() && self.comp.on() {
            // LinuxCNC's `convert_coordinate_system`.
            return Err(Fault::semantic(
                b.g_span(group::COORD),
                "cannot change coordinate systems with cutter radius compensation on",
            ));
        }
        if let Some(g) = b.g(group::COORD).filter(|&g| self.is_extended_select(b, g)) {
            self.select_extended(b, g, lb)?;
        } else if let Some(g) = b.g(group::COORD) {
            let idx = match g {
                591 => 7,
                592 => 8,
                593 => 9,
                _ => (g / 10 - 53) as usize,
            };
            self.coord = idx;
            self.ext_coord = None;
            let off = self.g5x_table[idx - 1];
            self.set_frame(off, self.g92, self.rot_table[idx - 1]);
        }
        if let Some(g) = b.g(group::SPINDLE_MODE) {
            self.read_only.css = g == 960;
        }
        if b.g(group::SPINDLE_MODE) == Some(960) {
            self.warn_code(
                lb,
                b.g_at[group::SPINDLE_MODE] as usize,
                "G96 constant surface speed is not simulated: S is taken as rpm".to_string(),
            );
        }
        if let Some(g) = b.g(group::DISTANCE) {
            self.absolute = g == 900;
        }
        if let Some(g) = b.g(group::ARC_DISTANCE) {
            self.arc_absolute = g == 901;
        }
        if let Some(g) = b.g(group::RETRACT) {
            self.retract_r = g == 990;
        }
        if b.mask & (1 << block::slot(b'u') | 1 << block::slot(b'v') | 1 << block::slot(b'w')) != 0
        {
            let c = [b'u', b'v', b'w']
                .into_iter()
                .find(|&c| b.has(c))
                .unwrap_or(b'u');
            return Err(Fault::new(
                PathErrorKind::Unsupported,
                b.span(c),
                "U, V and W axes are not simulated",
                "X Y Z A B C axis words",
            ));
        }
        // A block turning a rotary axis after G69 (a G28 B0 C0 unwind included) hands the tool
        // axis back to the machine.
        if self.held_axis && (b.has(b'a') || b.has(b'b') || b.has(b'c')) {
            self.held_axis = false;
            self.emit(Canon::MachineAxis);
        }
        // (Fanuc's G10 L20 sets an additional offset to the values given, as L2 does.)
        let position_setting = matches!(nonmodal, Some(280 | 300 | 520 | 920))
            || (nonmodal == Some(100) && b.get(b'l') == Some(20.0) && !self.fanuc);
        if self.tilt.is_some() && position_setting {
            return Err(Fault::new(
                PathErrorKind::Unsupported,
                b.g_span(group::NON_MODAL),
                "G28, G30, G52, G92 and G10 L20 are not read in a tilted working plane (G68.2)",
                "G69 first",
            ));
        }
        if matches!(nonmodal, Some(520 | 920..=923)) && self.comp.on() {
            // LinuxCNC's `convert_axis_offsets` (G52, G92, G92.1, G92.2, G92.3): the tool and
            // the programmed contour would be in different frames.
            return Err(Fault::semantic(
                b.g_span(group::NON_MODAL),
                "cannot change axis offsets with cutter radius compensation on",
            ));
        }
        match nonmodal {
            Some(100) => {
                self.g10(b)?;
                axes_used_by_nonmotion = true;
            }
            Some(531) => self.g53_1(b)?,
            Some(280 | 300) => {
                if self.comp.on() {
                    return Err(Fault::semantic(
                        b.g_span(group::NON_MODAL),
                        "cannot use G28 or G30 with cutter radius compensation on",
                    ));
                }
                self.home(b, usize::from(nonmodal == Some(300)))?;
                axes_used_by_nonmotion = true;
            }
            Some(281 | 301) => {
                let k = usize::from(nonmodal == Some(301));
                self.homes[k] = self.controlled();
            }
            Some(920) => {
                self.g92(b)?;
                axes_used_by_nonmotion = true;
            }
            Some(520) => {
                // G52: a local origin, kept in LinuxCNC's G92 offset (parameters 5210–5219).
                let mut g = self.g92;
                for (i, &c) in AXIS_LETTERS.iter().enumerate() {
                    if let Some(v) = b.get(c) {
                        g[i] = self.mm_from_units(i, v);
                    }
                }
                self.g92_saved = g;
                self.g92_flag = 1.0;
                self.set_offsets(self.off, g);
                axes_used_by_nonmotion = true;
            }
            Some(921) => {
                self.g92_saved = [0.0; 6];
                self.g92_flag = 0.0;
                self.set_offsets(self.off, [0.0; 6]);
            }
            Some(922) => {
                self.g92_flag = 0.0;
                self.set_offsets(self.off, [0.0; 6]);
            }
            Some(923) => {
                self.g92_flag = 1.0;
                self.set_offsets(self.off, self.g92_saved);
            }
            _ => {}
        }
        self.warn_unused_words(b, lb, nonmodal)?;
        self.motion_step(b, lb, nonmodal == Some(530), axes_used_by_nonmotion)?;
        match b.m_stop {
            Some(0 | 1 | 60) => {
                let m = b.m_stop.unwrap_or(0);
                self.warn_code(
                    lb,
                    b.m_stop_at as usize,
                    format!("M{m} (program pause) ignored: the simulation runs on"),
                );
            }
            Some(_) => {
                self.comp_flush();
                self.emit(Canon::ProgramEnd);
                self.ended = true;
                return Ok(());
            }
            None => {}
        }
        if b.m98 || b.m97 {
            self.m98(b)?;
        } else if b.m99 {
            self.m99(b)?;
        }
        Ok(())
    }

    /// Words that mean nothing in their block (an I without an arc, an E, an H without G43)
    /// are reported, never silently dropped: they often betray a program written for another
    /// machine or a post-processor bug.
    ///
    /// Under LinuxCNC's rules an R word nothing uses is an error, as rs274's check_other_codes
    /// has it ("R word with no g code that uses it": an `R3` alone in a canned cycle's mode, a
    /// `G0 X1 R2`).
    fn warn_unused_words(&mut self, b: &Block, lb: &LineBuf, nonmodal: Option<u16>) -> Res<()> {
        let has_axes = b.mask & axis_mask() != 0;
        let mode = b
            .g(group::MOTION)
            .or(if has_axes { self.motion } else { None });
        let arc = matches!(mode, Some(20 | 30));
        let cycle = matches!(mode, Some(730 | 740 | 810..=890));
        let g10 = nonmodal == Some(100);
        let comp_d = b.g(group::CUTTER_COMP).is_some_and(|g| g != 400);
        for c in *b"eijkrqplhd" {
            if !b.has(c) {
                continue;
            }
            let used = match c {
                // The words of a controller-mode code left out (G05.1 Q1, G187 P1 E0.01), and
                // of the I/O M codes (M62 P0, M66 P0 L3 Q5, M67 E0 Q2.5).
                b'p' | b'q' | b'e' | b'r' if b.n_modes > 0 => true,
                b'p' | b'q' | b'e' | b'l'
                    if b.m_other[..b.n_other]
                        .iter()
                        .any(|&(m, _)| (62..=68).contains(&m)) =>
                {
                    true
                }
                // The arguments of a user M code (LinuxCNC's M100–M199 P Q) and of the override
                // switches (M50 P0).
                b'p' | b'q'
                    if b.m_other[..b.n_other]
                        .iter()
                        .any(|&(m, _)| (100..=199).contains(&m) || (50..=53).contains(&m)) =>
                {
                    true
                }
                // Spindle orientation: M19 R (angle) Q (time out) P (direction).
                b'r' | b'q' | b'p' if b.m_other[..b.n_other].iter().any(|&(m, _)| m == 19) => true,
                b'q' if b.fine_boring => true,
                b'q' if b.m_other[..b.n_other].iter().any(|&(m, _)| m == 61) => true,
                b'i' | b'j' | b'k' => {
                    // Fanuc reads an arc's centre words in its plane only, and none beside R.
                    let normal = b"ijk"[self.plane.axes().2];
                    let dropped = self.fanuc && (c == normal || b.has(b'r'));
                    (arc && !dropped)
                        || b.g(group::ROTATION) == Some(682)
                        || (self.fanuc && cycle && c == b'k')
                        || matches!(mode, Some(50 | 51 | 870))
                        || (c == b'k' && matches!(mode, Some(330 | 331)))
                        || (c == b'i' && mode == Some(331))
                        || b.g(group::SCALING) == Some(510)
                        || (self.tcp_vector
                            && matches!(b.g(group::MOTION).or(self.motion), Some(0 | 10)))
                }
                b'r' => arc || cycle || g10 || b.g(group::ROTATION) == Some(680),
                // (G64 P Q: LinuxCNC's blending and naive CAM tolerances.)
                b'q' => matches!(mode, Some(50 | 730 | 830)) || b.g(group::PATH) == Some(640),
                b'p' => {
                    arc || cycle
                        || b.g(group::COORD)
                            .is_some_and(|g| self.is_extended_select(b, g))
                        || b.g(group::ROTATION) == Some(682)
                        || matches!(mode, Some(50 | 52))
                        || b.g(group::SCALING) == Some(510)
                        || g10
                        || nonmodal == Some(40)
                        || b.m98
                        || b.m97
                        || b.m99
                        || b.g(group::PATH) == Some(640)
                }
                b'l' => cycle || g10 || b.m98 || b.m97 || mode == Some(52),
                b'h' => matches!(b.g(group::TOOL_LENGTH), Some(430 | 432 | 434 | 435 | 2340)),
                // (G96 D: the maximum spindle speed.)
                b'd' => comp_d || b.g(group::SPINDLE_MODE) == Some(960),
                _ => false,
            };
            if !used {
                let at = b.at[block::slot(c)] as usize;
                let value = b.val[block::slot(c)];
                // (G64 P R: newer LinuxCNC's planner tolerance, which LinuxCNC's own interpreter
                // tests use; rs274 2.9 refuses it, swarf ignores it.)
                if c == b'r'
                    && !self.fanuc
                    && !matches!(b.g(group::CUTTER_COMP), Some(411 | 421))
                    && b.g(group::PATH) != Some(640)
                {
                    return Err(Fault::new(
                        PathErrorKind::Semantic,
                        Span::Code(at, at + 1),
                        format!("R{value} with no G code that uses it"),
                        "G2/G3 (radius), a canned cycle with axis words (retract level), G10",
                    ));
                }
                self.warn_code(
                    lb,
                    at,
                    format!(
                        "{}{value} ignored: it has no meaning in this block",
                        char::from(c.to_ascii_uppercase())
                    ),
                );
            }
        }
        Ok(())
    }

    fn motion_step(&mut self, b: &Block, lb: &LineBuf, g53: bool, axes_taken: bool) -> Res<()> {
        let mut explicit = b.g(group::MOTION);
        let has_axes = b.mask & axis_mask() != 0;
        if self.fanuc && (explicit == Some(800) || b.g80_too) {
            // Fanuc: G80 cancels the cycle (group 09); the group 01 motion resumes.
            self.motion = Some(self.group1);
            if explicit == Some(800) {
                explicit = None;
            }
        }
        if let Some(m @ (0 | 10 | 20 | 30)) = explicit {
            self.group1 = m;
        }
        if self.fanuc && axes_taken && matches!(explicit, Some(0 | 10)) {
            // Fanuc: the group 00 code (`G00 G91 G28 Z0.`) takes the axis words; the group 01
            // code only becomes the modal motion.
            self.motion = explicit;
            return Ok(());
        }
        if axes_taken && has_axes && explicit.is_some_and(|m| m != 800) {
            return Err(Fault::semantic(
                b.g_span(group::MOTION),
                "a motion G code and G10/G28/G30/G92/G43.1 both want the axis words of this line",
            ));
        }
        // (G43.5: I J K alone turn the tool where it stands, in G0 or G1.)
        let turn_only = self.tcp_vector
            && !has_axes
            && !axes_taken
            && matches!(self.motion, Some(0 | 10))
            && [b'i', b'j', b'k'].iter().any(|&c| b.has(c));
        let mode = match explicit {
            Some(m) => Some(m),
            None if turn_only => self.motion,
            None if has_axes && !axes_taken => match self.motion {
                Some(m) => Some(m),
                None => {
                    let c = b"xyzabc@^"
                        .iter()
                        .copied()
                        .find(|&c| b.has(c))
                        .unwrap_or(b'x');
                    return Err(Fault::new(
                        PathErrorKind::Semantic,
                        b.span(c),
                        "axis words without a motion G code to use them (G80 is in effect; a \
                         Fanuc control would move with the last G0–G3: --dialect fanuc reads the \
                         program so)",
                        "G0, G1, G2, G3 or a canned cycle",
                    ));
                }
            },
            None => None,
        };
        // Fanuc: G53 positions at rapid whatever the modal motion (G1, G2, a cycle), which
        // stays for the next block; LinuxCNC moves it with G0 or G1 and refuses the others.
        let mode = if self.fanuc && g53 && has_axes {
            Some(0)
        } else {
            mode
        };
        if g53 && !matches!(mode, Some(0 | 10)) {
            return Err(Fault::semantic(
                b.g_span(group::NON_MODAL),
                "G53 needs G0 or G1",
            ));
        }
        if g53 && !self.absolute {
            return Err(Fault::semantic(
                b.g_span(group::NON_MODAL),
                "G53 cannot be used in incremental mode (G91)",
            ));
        }
        if has_axes && mode != Some(50) {
            self.g5_last = None;
        }
        if self.nurbs.is_some() && !matches!(mode, Some(52 | 53) | None) {
            return Err(Fault::semantic(
                b.g_span(group::MOTION),
                "a NURBS (G5.2) must be closed with G5.3 before another motion",
            ));
        }
        let old_motion = self.motion;
        if let Some(m) = explicit {
            self.motion = (m != 800).then_some(m);
        }
        match mode {
            None | Some(800) => {
                if mode == Some(800) && has_axes && !axes_taken {
                    return Err(Fault::semantic(
                        b.g_span(group::MOTION),
                        "G80 with axis words",
                    ));
                }
            }
            Some(0 | 10) => {
                // Under G43.5 a straight move's I J K give the tool's direction in the workpiece
                // frame (an omitted one is 0; none at all keeps the direction), and I J K alone
                // turn the tool where it stands.
                let vector = self.tcp_vector && [b'i', b'j', b'k'].iter().any(|&c| b.has(c));
                if vector {
                    let v = [b'i', b'j', b'k'].map(|c| b.get(c).unwrap_or(0.0));
                    if v.iter().all(|&x| x == 0.0) {
                        return Err(Fault::semantic(
                            b.span(b'i'),
                            "G43.5 tool direction I J K is the zero vector",
                        ));
                    }
                    self.emit(Canon::ToolAxis(v));
                    // A later rotary word hands the axis back to the machine.
                    self.held_axis = true;
                }
                // LinuxCNC moves on a block that states G0 or G1 without axis words: a move of
                // length zero (rs274 prints its STRAIGHT_TRAVERSE / STRAIGHT_FEED), which keeps
                // the canonical calls in step with LinuxCNC's; a Fanuc control only sets the
                // mode.
                let bare = !has_axes
                    && !vector
                    && !self.fanuc
                    && explicit.is_some()
                    && !self.comp.moving()
                    && !g53;
                if has_axes || vector || bare {
                    self.arc_not_allowed = false;
                    let end = if has_axes {
                        self.find_ends(b, g53)?
                    } else {
                        self.p
                    };
                    if g53
                        && !self.g53_warned
                        && self.opts.home.is_none()
                        && self.off == [0.0; 6]
                        && self.g92 == [0.0; 6]
                    {
                        // Programs move to machine positions (`G53 G0 Z0.`, Carbide Create's
                        // `G53G0Z-5.`) meaning "up, out of the way" on their machine.
                        self.g53_warned = true;
                        self.later.push((
                            b.g_at[group::NON_MODAL] as usize,
                            "G53 moves in machine coordinates, whose origin is the machine's \
                             home; without --home X,Y,Z (mm, e.g. above the part) that is the \
                             work origin, so X Y Z go to the work's coordinates (the first such \
                             G53 move; others are not reported)"
                                .into(),
                        ));
                    }
                    if self.comp.moving() {
                        if g53 {
                            return Err(Fault::semantic(
                                b.g_span(group::NON_MODAL),
                                "cannot use G53 with cutter radius compensation on",
                            ));
                        }
                        if mode == Some(10) {
                            self.check_move_feed(b)?;
                        }
                        return self.comp_move(b, end, mode == Some(0), None);
                    }
                    let end_axes = Axes::from_array(end);
                    if mode == Some(0) {
                        self.emit(Canon::Traverse { end: end_axes });
                    } else {
                        self.check_move_feed(b)?;
                        self.emit(Canon::Feed { end: end_axes });
                    }
                    self.p = end;
                }
            }
            Some(m @ (20 | 30)) => {
                if self.arc_not_allowed && has_axes {
                    return Err(Fault::new(
                        PathErrorKind::Semantic,
                        b.g_span(group::MOTION),
                        "the move just after cutter compensation is turned off (G40) must be \
                         straight: it takes the tool from its compensated position to the \
                         programmed contour",
                        "G0 or G1",
                    ));
                }
                self.arc(b, m == 20)?
            }
            Some(m @ (330 | 331)) => {
                if has_axes {
                    self.spindle_synchronised(b, m == 331)?;
                }
            }
            Some(m @ 382..=385) if has_axes => self.probe(b, lb, m)?,
            Some(382..=385) if explicit.is_some() => {
                return Err(Fault::semantic(
                    b.g_span(group::MOTION),
                    "X, Y, and Z words all missing with G38.2",
                ))
            }
            Some(382..=385) => {}
            Some(m @ (50..=53)) => {
                if m == 52 && explicit == Some(52) {
                    self.nurbs_start = [self.p[0], self.p[1]];
                }
                self.spline(b, m, explicit == Some(m))?;
            }
            Some(m) => self.cycle(b, m, old_motion)?,
        }
        Ok(())
    }

    /// `G38.2`–`G38.5`: a probing move, which stops where the probe trips — a place only the
    /// machine knows. The tool stays where it is (the trip point is unknown, and a move to the
    /// programmed end would plunge into the touch plate or the part), with a warning at the first
    /// one; offsets a program sets from the probed position (`G10 L20`, `G92`) are set from the
    /// start point. LinuxCNC's refusals are kept: under cutter compensation, in inverse time, at
    /// zero feed.
    fn probe(&mut self, b: &Block, lb: &LineBuf, m: u16) -> Res<()> {
        let span = b
            .g(group::MOTION)
            .map_or(Span::Line, |_| b.g_span(group::MOTION));
        if self.read_only.ccomp != 400 {
            return Err(Fault::semantic(
                span,
                "Cannot probe with cutter radius compensation on",
            ));
        }
        if self.feed_mode == FeedMode::InverseTime {
            return Err(Fault::semantic(
                span,
                "Cannot probe in inverse time feed mode",
            ));
        }
        if self.feed <= 0.0 {
            return Err(Fault::semantic(span, "Cannot probe with zero feed rate"));
        }
        if let Some(&c) = b"abc".iter().find(|&&c| b.has(c)) {
            return Err(Fault::semantic(
                b.span(c),
                "Cannot move rotary axes during probing",
            ));
        }
        if b"xyz".iter().all(|&c| !b.has(c)) {
            return Err(Fault::semantic(
                span,
                "X, Y, and Z words all missing with G38.2",
            ));
        }
        let end = self.find_ends(b, false)?;
        let d: f64 = (0..3)
            .map(|i| (end[i] - self.p[i]).powi(2))
            .sum::<f64>()
            .sqrt();
        // As rs274 2.9: only a probe that must trip (G38.2, G38.4) refuses to stand still; any
        // length will do otherwise (LinuxCNC's smartprobe.ngc probes from where it stands
        // with G38.5).
        if d == 0.0 && matches!(m, 382 | 384) {
            return Err(Fault::semantic(
                span,
                "Start point too close to probe point",
            ));
        }
        // The probe's result, #5061–#5069 in the program's units and frame, and #5070 (it
        // tripped): where the tool stands.
        for i in 0..9 {
            let v = match i {
                0..=2 => self.p[i] / self.scale,
                3..=5 => self.p[i],
                _ => 0.0,
            };
            self.params.set_num(5061 + i, v);
        }
        self.params.set_num(5070, 1.0);
        if !self.probe_warned {
            self.probe_warned = true;
            let at = match span {
                Span::Code(x, _) => x,
                _ => 0,
            };
            self.warn_code(
                lb,
                at,
                format!(
                    "G38.{}: the probe's trip point is unknown, so the tool stays where it is \
                     and #5061-#5069 read its position there (offsets the program then sets \
                     from the probed position, G10 L20 or G92, are set from here; the first \
                     probing move, others are not reported)",
                    m - 380
                ),
            );
        }
        Ok(())
    }

    /// `G33` (motion K per spindle revolution: threading, tapping with a floating holder) and
    /// `G33.1` (rigid tapping: over the hole at the current Z if X/Y move it, down at K per
    /// revolution, the spindle reversed, back out to where the tap started, at `I` times the
    /// speed if given), as LinuxCNC moves them. The feed is K × S: the moves are made in [`FeedMode::SpindleSynchronised`], then
    /// the program's feed mode and rate are restored.
    fn spindle_synchronised(&mut self, b: &Block, rigid: bool) -> Res<()> {
        let g = if rigid { "G33.1" } else { "G33" };
        let gspan = b
            .g(group::MOTION)
            .map_or(Span::Line, |_| b.g_span(group::MOTION));
        // Fanuc writes the lead as F (`G33 Z-10. F1.5`), LinuxCNC as K.
        let word = if !b.has(b'k') && self.fanuc && b.has(b'f') {
            b'f'
        } else {
            b'k'
        };
        let k = b.get(word).ok_or_else(|| {
            Fault::new(
                PathErrorKind::Semantic,
                gspan,
                format!(
                    "{g} without K (F under Fanuc rules), the distance travelled per spindle \
                     revolution"
                ),
                "K > 0",
            )
        })?;
        if k <= 0.0 || !k.is_finite() {
            return Err(Fault::new(
                PathErrorKind::Semantic,
                b.span(word),
                format!("{g} with K{k}"),
                "K > 0 (distance per spindle revolution)",
            ));
        }
        if self.dir == SpindleDir::Stopped || self.rpm <= 0.0 {
            return Err(Fault::semantic(
                gspan,
                format!("{g} with the spindle stopped: its motion follows the spindle (M3/M4 and S first)"),
            ));
        }
        if self.comp.on() {
            return Err(Fault::semantic(
                gspan,
                format!("cannot use {g} with cutter radius compensation on"),
            ));
        }
        let speed_up = match b.get(b'i') {
            Some(i) if rigid && (i <= 0.0 || !i.is_finite()) => {
                return Err(Fault::new(
                    PathErrorKind::Semantic,
                    b.span(b'i'),
                    format!("G33.1 with I{i}"),
                    "I > 0 (the retract's spindle speed multiplier)",
                ))
            }
            Some(i) if rigid => i,
            _ => 1.0,
        };
        let end = self.find_ends(b, false)?;
        if rigid {
            self.emit(Canon::RigidTap {
                end: Axes::from_array(end),
            });
        }
        if rigid && (end[0] != self.p[0] || end[1] != self.p[1]) {
            // LinuxCNC goes over the hole first (a traverse at the current Z) and taps along Z.
            let mut over = self.p;
            over[0] = end[0];
            over[1] = end[1];
            self.emit(Canon::Traverse {
                end: Axes::from_array(over),
            });
            self.p = over;
        }
        let start = self.p;
        self.emit(Canon::FeedMode(FeedMode::SpindleSynchronised));
        self.emit(Canon::FeedRate(self.mm_from_units(2, k)));
        self.emit(Canon::Feed {
            end: Axes::from_array(end),
        });
        if rigid {
            let (rpm, dir) = (self.rpm, self.dir);
            let back = match dir {
                SpindleDir::Clockwise => SpindleDir::CounterClockwise,
                _ => SpindleDir::Clockwise,
            };
            self.emit(Canon::Spindle {
                rpm: rpm * speed_up,
                dir: back,
            });
            self.emit(Canon::Feed {
                end: Axes::from_array(start),
            });
            self.emit(Canon::Spindle { rpm, dir });
        } else {
            self.p = end;
        }
        self.emit(Canon::FeedMode(self.feed_mode));
        self.emit(Canon::FeedRate(self.feed));
        Ok(())
    }

    /// The G93 rule (F on every feed block) and the zero-feed rule.
    pub(crate) fn check_feed(&self, b: &Block) -> Res<()> {
        let span = b
            .g(group::MOTION)
            .map_or(Span::Line, |_| b.g_span(group::MOTION));
        match self.feed_mode {
            FeedMode::InverseTime if !b.has(b'f') => Err(Fault::new(
                PathErrorKind::Semantic,
                span,
                "F word missing on a feed move in inverse time mode (G93)",
                "F on every G1/G2/G3 line under G93",
            )),
            FeedMode::PerMinute | FeedMode::PerRevolution if self.feed <= 0.0 => Err(Fault::new(
                PathErrorKind::Semantic,
                span,
                "feed move with zero feed rate",
                "an F word",
            )),
            _ => Ok(()),
        }
    }

    /// The zero-feed rules of a G1 or arc move: [`Self::check_feed`], and under G95 LinuxCNC's
    /// "Cannot feed with zero spindle speed in feed per rev mode" (convert_straight,
    /// convert_arc: the S word, whether the spindle turns or not).
    pub(crate) fn check_move_feed(&self, b: &Block) -> Res<()> {
        self.check_feed(b)?;
        if !self.fanuc && self.feed_mode == FeedMode::PerRevolution && self.rpm == 0.0 {
            let span = b
                .g(group::MOTION)
                .map_or(Span::Line, |_| b.g_span(group::MOTION));
            return Err(Fault::new(
                PathErrorKind::Semantic,
                span,
                "cannot feed with zero spindle speed in feed per rev mode (G95)",
                "an S word",
            ));
        }
        Ok(())
    }

    /// The end point of a straight or arc move (LinuxCNC's `find_ends`), including the polar
    /// words `@` (radius) and `^` (angle, degrees) in the XY plane.
    pub(crate) fn find_ends(&self, b: &Block, g53: bool) -> Res<[f64; 6]> {
        let mut e = self.p;
        let g53_origin = self.g53_origin();
        for (i, &c) in AXIS_LETTERS.iter().enumerate() {
            if let Some(v) = b.get(c) {
                let v = self.mm_from_units(i, v);
                e[i] = if g53 {
                    // Machine coordinates: converted below, with the rotation.
                    v + g53_origin[i]
                } else if self.absolute {
                    self.scaled_position(i, v)
                } else {
                    self.p[i] + self.scaled_length(i, v)
                };
            }
        }
        if g53 {
            // The given axes in machine coordinates (of the controlled point: the tool length
            // offset is subtracted, as LinuxCNC's `find_ends`), the others where the machine is.
            let mut m = self.controlled();
            for (i, &c) in AXIS_LETTERS.iter().enumerate() {
                if b.has(c) {
                    m[i] = e[i];
                }
            }
            e = self.program_of_controlled(&m);
        }
        if b.has(b'@') || b.has(b'^') {
            if b.has(b'x') || b.has(b'y') {
                let c = if b.has(b'x') { b'x' } else { b'y' };
                return Err(Fault::semantic(
                    b.span(c),
                    "X or Y cannot be used with polar coordinates (@ ^)",
                ));
            }
            if g53 {
                return Err(Fault::semantic(
                    b.g_span(group::NON_MODAL),
                    "polar coordinates cannot be used with G53",
                ));
            }
            let (x, y) = (self.p[0], self.p[1]);
            let (r, th) = if self.absolute {
                (
                    b.get(b'@').map_or_else(|| x.hypot(y), |r| r * self.scale),
                    b.get(b'^').map_or_else(|| y.atan2(x), f64::to_radians),
                )
            } else {
                if x == 0.0 && y == 0.0 {
                    let c = if b.has(b'@') { b'@' } else { b'^' };
                    return Err(Fault::semantic(
                        b.span(c),
                        "incremental motion with polar coordinates is indeterminate at the origin",
                    ));
                }
                (
                    x.hypot(y) + b.get(b'@').map_or(0.0, |r| r * self.scale),
                    y.atan2(x) + b.get(b'^').map_or(0.0, f64::to_radians),
                )
            };
            e[0] = r * th.cos();
            e[1] = r * th.sin();
        }
        if let Some(i) = e.iter().position(|&v| !in_machine_range(v)) {
            // The word that put it there, when the block has one (else offsets or polar words).
            let letter = AXIS_LETTERS[i];
            let span = if b.has(letter) {
                b.span(letter)
            } else if i < 2 && (b.has(b'@') || b.has(b'^')) {
                b.span(if b.has(b'@') { b'@' } else { b'^' })
            } else {
                Span::Line
            };
            let what = format!("the end point's {}", (letter as char).to_ascii_uppercase());
            return Err(out_of_range(
                span,
                &what,
                e[i],
                if i < 3 { "mm" } else { "°" },
            ));
        }
        Ok(e)
    }

    fn arc(&mut self, b: &Block, cw: bool) -> Res<()> {
        let (fi, si, ni) = self.plane.axes();
        let names = ["X", "Y", "Z"];
        let offs = [b'i', b'j', b'k'];
        let gspan = b
            .g(group::MOTION)
            .map_or(Span::Line, |_| b.g_span(group::MOTION));
        let polar = b.has(b'@') || b.has(b'^');
        // An arc with its centre and no end point in the plane is a full circle (Fanuc, and
        // LinuxCNC's `G2 I.5 J.5` of its 3dtest.ngc); the R form needs its end point.
        let full_circle = !b.has(b'r') && (b.has(offs[fi]) || b.has(offs[si]));
        if !(b.has(AXIS_LETTERS[fi]) || b.has(AXIS_LETTERS[si]) || polar || full_circle) {
            return Err(Fault::new(
                PathErrorKind::Semantic,
                gspan,
                format!(
                    "{} and {} words missing for an arc in the {}{} plane",
                    names[fi], names[si], names[fi], names[si]
                ),
                format!("{} or {}", names[fi], names[si]),
            ));
        }
        let end = self.find_ends(b, false)?;
        self.check_move_feed(b)?;
        // swarf's cap on the turns: the repeat limit (and what the canon's count holds).
        let cap = self.opts.max_repeat.min(i32::MAX as u64);
        let turns = match b.get(b'p') {
            None => 1,
            Some(p) if p >= 1.0 && p.fract() == 0.0 && p <= cap as f64 => p as i32,
            Some(p) if p >= 1.0 && p.fract() == 0.0 => {
                return Err(Fault::new(
                    PathErrorKind::Limit,
                    b.span(b'p'),
                    format!("arc with P{p} turns, more than swarf's cap of {cap} turns"),
                    format!("P ≤ {cap} (the repeat limit)"),
                ))
            }
            Some(_) => {
                return Err(Fault::new(
                    PathErrorKind::Semantic,
                    b.span(b'p'),
                    "bad number of arc turns",
                    "P, a positive integer",
                ))
            }
        };
        let start2 = [self.p[fi], self.p[si]];
        let end2 = [end[fi], end[si]];
        let k = self.arc_scale(gspan)?;
        // A compensation entry arc ending no farther than the radius from the tool.
        self.comp_entry_arc_checks(gspan, end2)?;
        let center = if let Some(r) = b.get(b'r') {
            // (Fanuc: R wins, the centre words are reported unused.)
            if let Some(&c) = offs.iter().find(|&&c| b.has(c) && !self.fanuc) {
                return Err(Fault::semantic(
                    b.span(c),
                    "an arc cannot have both R and I/J/K words",
                ));
            }
            self.comp_r_check(b.span(b'r'), r * self.scale * k, cw)?;
            center_r(
                start2,
                end2,
                r * self.scale * k,
                cw,
                r_tolerance_mm(self.units),
            )
            .map_err(|m| Fault::semantic(b.span(b'r'), m))?
        } else {
            if b.has(offs[ni]) && !self.fanuc {
                return Err(Fault::semantic(
                    b.span(offs[ni]),
                    format!(
                        "{} word given for an arc in the {}{} plane",
                        (offs[ni] as char).to_ascii_uppercase(),
                        names[fi],
                        names[si]
                    ),
                ));
            }
            if !b.has(offs[fi]) && !b.has(offs[si]) {
                let (a, c) = (
                    (offs[fi] as char).to_ascii_uppercase(),
                    (offs[si] as char).to_ascii_uppercase(),
                );
                return Err(Fault::new(
                    PathErrorKind::Semantic,
                    gspan,
                    format!(
                        "{a} and {c} words missing for an arc in the {}{} plane",
                        names[fi], names[si]
                    ),
                    format!("{a}/{c} (centre) or R (radius)"),
                ));
            }
            let oi = b.get(offs[fi]).unwrap_or(0.0) * self.scale;
            let oj = b.get(offs[si]).unwrap_or(0.0) * self.scale;
            let c = if self.arc_absolute {
                // A centre word left out stands for the start's coordinate (LinuxCNC takes the
                // current position for it under G90.1, as 0 is the offset under G91.1).
                [
                    if b.has(offs[fi]) {
                        self.scaled_position(fi, oi)
                    } else {
                        start2[0]
                    },
                    if b.has(offs[si]) {
                        self.scaled_position(si, oj)
                    } else {
                        start2[1]
                    },
                ]
            } else {
                [start2[0] + k * oi, start2[1] + k * oj]
            };
            let tol = self.opts.arc_radius_tolerance;
            for (k, &ck) in c.iter().enumerate() {
                if !in_machine_range(ck) {
                    let letter = [offs[fi], offs[si]][k];
                    let span = if b.has(letter) { b.span(letter) } else { gspan };
                    return Err(out_of_range(span, "the arc centre's coordinate", ck, "mm"));
                }
            }
            check_ijk(start2, end2, c, tol.abs_in_mm(self.units), tol.relative)
                .map_err(|m| Fault::semantic(gspan, m))?;
            c
        };
        if let Some(&ck) = center.iter().find(|&&v| !in_machine_range(v)) {
            let span = if b.has(b'r') { b.span(b'r') } else { gspan };
            return Err(out_of_range(span, "the arc centre's coordinate", ck, "mm"));
        }
        let rotation = if cw { -turns } else { turns };
        if self.comp.moving() {
            return self.comp_move(b, end, false, Some((center, rotation)));
        }
        self.emit(Canon::Arc {
            end: Axes::from_array(end),
            center,
            rotation,
            plane: self.plane,
        });
        self.p = end;
        Ok(())
    }

    fn g10(&mut self, b: &Block) -> Res<()> {
        let span = b.g_span(group::NON_MODAL);
        let l = b.get(b'l').ok_or_else(|| {
            Fault::new(
                PathErrorKind::Semantic,
                span,
                "G10 needs an L word",
                "L1, L2, L10, L11 or L20",
            )
        })?;
        if self.fanuc && matches!(l as i64, 10..=13) && l.fract() == 0.0 {
            return self.g10_fanuc_register(b, l as u8);
        }
        if l == 1.0 || l == 10.0 || l == 11.0 {
            return self.g10_tool(b, l as u8);
        }
        if l != 2.0 && l != 20.0 {
            return Err(Fault::new(
                PathErrorKind::Unsupported,
                b.span(b'l'),
                format!("G10 L{l} is not supported"),
                if self.fanuc {
                    "L2, L10 to L13 or L20"
                } else {
                    "L1, L2, L10, L11 or L20"
                },
            ));
        }
        if l == 20.0 && self.fanuc {
            return self.g10_l20_fanuc(b);
        }
        let p = b.get(b'p').unwrap_or(0.0);
        if !(0.0..=9.0).contains(&p) || p.fract() != 0.0 {
            return Err(Fault::new(
                PathErrorKind::Semantic,
                b.span(b'p'),
                "bad coordinate system number",
                "P0 to P9",
            ));
        }
        if l == 20.0 && b.has(b'r') {
            // convert_setup: "R not allowed in G10 L20".
            return Err(Fault::semantic(b.span(b'r'), "R not allowed in G10 L20"));
        }
        let k = if p == 0.0 { self.coord } else { p as usize };
        let mut t = self.g5x_table[k - 1];
        // R: the system's XY rotation (kept when not given).
        let rot = b.get(b'r').unwrap_or(self.rot_table[k - 1]);
        if l == 2.0 {
            for (i, &c) in AXIS_LETTERS.iter().enumerate() {
                if let Some(v) = b.get(c) {
                    t[i] = self.mm_from_units(i, v);
                }
            }
        } else {
            // L20: make the current position read the given values in system k.
            let m = self.machine();
            let mut q = self.program_of(&m, &t, &self.g92, rot);
            for (i, &c) in AXIS_LETTERS.iter().enumerate() {
                if let Some(v) = b.get(c) {
                    q[i] = self.mm_from_units(i, v);
                }
            }
            let r: [f64; 6] = rotate_xy(std::array::from_fn(|i| q[i] + self.g92[i]), rot);
            t = std::array::from_fn(|i| m[i] - r[i]);
        }
        self.g5x_table[k - 1] = t;
        self.rot_table[k - 1] = rot;
        if k == self.coord && self.ext_coord.is_none() {
            // rs274's convert_setup moves the current point into the changed system without
            // the G92 offset: unrotated by the old rotation, the old offset added, the new one
            // taken off, rotated by the new one. Where the rotation changes under a G92
            // offset that is not where the tool stands (find_current_in_system, G92 and
            // G54–G59.3 keep the offset inside the rotation); rs274's later moves start from
            // it, and so do swarf's.
            let lcnc = (!self.fanuc && rot != self.rot && self.g92 != [0.0; 6]).then(|| {
                let q = rotate_xy(self.p, self.rot);
                let q: [f64; 6] = std::array::from_fn(|i| q[i] + self.off[i] - t[i]);
                rotate_xy(q, -rot)
            });
            self.set_frame(t, self.g92, rot);
            if let Some(p) = lcnc {
                self.p = p;
            }
        }
        Ok(())
    }

    /// Fanuc's `G10 L20 Pn X Y Z`: additional work offset n (1–300, selected by `G54.1 Pn`)
    /// takes the given values, as G10 L2 sets G54–G59 (an axis not given keeps its value; G54
    /// is untouched). LinuxCNC's L20 (the current position reads the values) is another code.
    fn g10_l20_fanuc(&mut self, b: &Block) -> Res<()> {
        let n = self.extended_number(b, "G10 L20")?;
        let mut t = self.ext_table.get(&n).copied().unwrap_or([0.0; 6]);
        for (i, &c) in AXIS_LETTERS.iter().enumerate() {
            if let Some(v) = b.get(c) {
                t[i] = self.mm_from_units(i, v);
            }
        }
        self.ext_table.insert(n, t);
        if self.ext_coord == Some(n) {
            self.set_frame(t, self.g92, 0.0);
        }
        Ok(())
    }

    /// The additional work offset number of `what`'s P word: 1–300, as a Fanuc control has
    /// (Haas: 1–99).
    fn extended_number(&self, b: &Block, what: &str) -> Res<u16> {
        match b.get(b'p') {
            Some(p) if (1.0..=300.0).contains(&p) && p.fract() == 0.0 => Ok(p as u16),
            p => Err(Fault::new(
                PathErrorKind::Semantic,
                if p.is_some() {
                    b.span(b'p')
                } else {
                    b.g_span(group::NON_MODAL)
                },
                format!("{what} needs the additional work offset's number in P"),
                "P1 to P300",
            )),
        }
    }

    /// Whether the block's coordinate system code `g` selects a Fanuc additional work offset:
    /// G54.1 and G154 do, and so does Fanuc's `G54 Pn` when no other code of the block takes
    /// the P (a dwell, a subprogram call, G10, a cycle's dwell).
    fn is_extended_select(&self, b: &Block, g: u16) -> bool {
        if !self.fanuc {
            return false;
        }
        match g {
            541 | 1540 => true,
            540 => {
                let p_elsewhere = b.m98
                    || b.m97
                    || b.m99
                    || b.n_modes > 0
                    || b.g(group::NON_MODAL).is_some()
                    || matches!(b.g(group::MOTION), Some(730 | 740 | 810..=890))
                    || matches!(self.motion, Some(730 | 740 | 810..=890) if b.mask & axis_mask() != 0);
                b.has(b'p') && !p_elsewhere
            }
            _ => false,
        }
    }

    /// `G54.1 Pn` (`G54 Pn`, Haas `G154 Pn`): additional work offset n in effect, when the
    /// program set it (G10 L20 Pn); one it did not set has its values in the control's table
    /// only, so the current offset stays, with a warning.
    fn select_extended(&mut self, b: &Block, g: u16, lb: &LineBuf) -> Res<()> {
        let name = block::g_name(g);
        let at = b.g_at[group::COORD] as usize;
        if g != 540 && !b.has(b'p') {
            self.warn_code(
                lb,
                at,
                format!(
                    "{name} without P (additional work offset) ignored: which offset is not \
                     said, so the current work offset stays"
                ),
            );
            return Ok(());
        }
        let n = self.extended_number(b, &name)?;
        let Some(off) = self.ext_table.get(&n).copied() else {
            self.warn_code(
                lb,
                at,
                format!(
                    "{name} P{n} (additional work offset {n}) ignored: its values are not in \
                     the program (no G10 L20 P{n} before it), so the current work offset stays"
                ),
            );
            return Ok(());
        };
        self.ext_coord = Some(n);
        self.set_frame(off, self.g92, 0.0);
        Ok(())
    }

    /// G10 L1 (set tool P's offsets to the given values), L10 (set them so that the current
    /// position, with them in effect, reads the given values) and L11 (likewise in G59.3, the
    /// touch-off fixture's system, without G92), as LinuxCNC's convert_setup_tool: offsets are
    /// kept in the machine frame, the given values are in the destination system's (its XY
    /// rotation applies), and an axis not given keeps its offset.
    fn g10_tool(&mut self, b: &Block, l: u8) -> Res<()> {
        let relative = l != 1;
        let p = b.get(b'p').unwrap_or(-1.0);
        if !(p >= 1.0 && p.fract() == 0.0 && p <= f64::from(u32::MAX)) {
            return Err(Fault::new(
                PathErrorKind::Semantic,
                if b.has(b'p') {
                    b.span(b'p')
                } else {
                    b.g_span(group::NON_MODAL)
                },
                "G10 L1/L10/L11 needs the tool number in P",
                "P<tool number ≥ 1>",
            ));
        }
        let tool = p as u32;
        let entry = self.tool_table.get(&tool).copied().unwrap_or([0.0; 6]);
        // The position without the offset in effect, in the destination system
        // (find_current_in_system_without_tlo), and that system's rotation.
        let (without, rot): ([f64; 6], f64) = if l == 11 {
            let c = self.controlled();
            let fixture = self.g5x_table[8];
            (
                rotate_xy(
                    std::array::from_fn(|i| c[i] - fixture[i]),
                    -self.rot_table[8],
                ),
                self.rot_table[8],
            )
        } else {
            let back = rotate_xy(self.tlo, -self.rot);
            (std::array::from_fn(|i| self.p[i] + back[i]), self.rot)
        };
        let mut e = if relative {
            rotate_xy(entry, -rot)
        } else {
            entry
        };
        for (i, &c) in AXIS_LETTERS.iter().enumerate() {
            if let Some(v) = b.get(c) {
                let v = self.mm_from_units(i, v);
                e[i] = if relative { without[i] - v } else { v };
            }
        }
        let e = if relative { rotate_xy(e, rot) } else { e };
        self.tool_table.insert(tool, e);
        self.g10_tool_radius(b)
    }

    /// Fanuc's (memory C) and Haas's offset registers: `G10 L10 Pn R` sets length register Hn's
    /// geometry, L11 its wear, L12 radius register Dn's geometry, L13 its wear (G91: R is added
    /// to the value). A register's offset is its geometry plus its wear: what `G43 Hn` (the
    /// length, kept as the tool table's Z) and `G41/G42 Dn` (the radius) use.
    fn g10_fanuc_register(&mut self, b: &Block, l: u8) -> Res<()> {
        let span = b.g_span(group::NON_MODAL);
        let p = match b.get(b'p') {
            Some(p) if p >= 1.0 && p.fract() == 0.0 && p <= f64::from(u32::MAX) => p as u32,
            p => {
                return Err(Fault::new(
                    PathErrorKind::Semantic,
                    if p.is_some() { b.span(b'p') } else { span },
                    format!("G10 L{l} needs the offset register's number in P"),
                    "P<register number ≥ 1>",
                ))
            }
        };
        let r = match b.get(b'r') {
            Some(r) if r.is_finite() => self.mm_from_units(0, r),
            r => {
                return Err(Fault::new(
                    PathErrorKind::Semantic,
                    if r.is_some() { b.span(b'r') } else { span },
                    format!("G10 L{l} needs the offset's value in R"),
                    "R<offset>",
                ))
            }
        };
        let length = l <= 11;
        let wear = l == 11 || l == 13;
        let old_total = if length {
            self.tool_table.get(&p).map_or(0.0, |e| e[2])
        } else {
            self.tool_radii.get(&p).copied().unwrap_or(0.0)
        };
        let old_wear = self.register_wear.get(&(length, p)).copied().unwrap_or(0.0);
        let old_geometry = old_total - old_wear;
        let (geometry, wear_value) = match (wear, self.absolute) {
            (false, true) => (r, old_wear),
            (false, false) => (old_geometry + r, old_wear),
            (true, true) => (old_geometry, r),
            (true, false) => (old_geometry, old_wear + r),
        };
        self.register_wear.insert((length, p), wear_value);
        let total = geometry + wear_value;
        if length {
            self.tool_table.entry(p).or_insert([0.0; 6])[2] = total;
        } else {
            self.tool_radii.insert(p, total);
        }
        Ok(())
    }

    /// The `R` of G10 L1/L10/L11: tool P's radius, which cutter compensation then uses.
    fn g10_tool_radius(&mut self, b: &Block) -> Res<()> {
        let (Some(r), Some(p)) = (b.get(b'r'), b.get(b'p')) else {
            return Ok(());
        };
        let good_p = p >= 1.0 && p.fract() == 0.0 && p <= f64::from(u32::MAX);
        if !(r.is_finite() && r >= 0.0 && good_p) {
            return Err(Fault::new(
                PathErrorKind::Semantic,
                b.span(b'r'),
                format!("G10 tool radius R{r} for P{p}"),
                "R ≥ 0 and P a tool number ≥ 1",
            ));
        }
        self.tool_radii.insert(p as u32, self.mm_from_units(0, r));
        Ok(())
    }

    /// Tool `tool`'s pocket in the tool table, else its number (tool 0: pocket 0, the
    /// spindle).
    fn pocket_of(&self, tool: u32) -> u32 {
        if tool == 0 {
            return 0;
        }
        self.opts.tool_pockets.get(&tool).copied().unwrap_or(tool)
    }

    /// Tool `tool`'s diameter, mm: set by G10 R, else the tool table's, else the one cutter
    /// given for every tool.
    pub(crate) fn tool_diameter(&self, tool: u32) -> Option<f64> {
        self.tool_radii
            .get(&tool)
            .map(|r| 2.0 * r)
            .or_else(|| self.opts.tool_diameters.get(&tool).copied())
            .or(self.opts.default_tool_diameter)
    }

    fn g92(&mut self, b: &Block) -> Res<()> {
        if b.mask & axis_mask() == 0 {
            return Err(Fault::new(
                PathErrorKind::Semantic,
                b.g_span(group::NON_MODAL),
                "G92 needs axis words",
                "X Y Z A B C",
            ));
        }
        let mut g = self.g92;
        for (i, &c) in AXIS_LETTERS.iter().enumerate() {
            if let Some(v) = b.get(c) {
                g[i] = self.p[i] + self.g92[i] - self.mm_from_units(i, v);
            }
        }
        self.g92_saved = g;
        self.g92_flag = 1.0;
        self.set_offsets(self.off, g);
        Ok(())
    }

    /// G28/G30: traverse through the given intermediate point, then to the stored position
    /// for the given axes (all axes when none is given).
    fn home(&mut self, b: &Block, k: usize) -> Res<()> {
        if self.opts.home.is_none() && self.homes[k] == [0.0; 6] && !self.home_warned {
            // A reference return means "up, out of the way" (Fanuc/Haas `G28 G91 Z0.`, and
            // the Fusion, Mach3 and LinuxCNC posts' alike); machine zero here is the work origin,
            // so it would cut or collide there.
            self.home_warned = true;
            self.later.push((
                b.g_at[group::NON_MODAL] as usize,
                "reference return to machine zero, which is the work origin here (swarf knows no \
                 work offsets): give the machine's home with --home X,Y,Z (mm, e.g. above the part)"
                    .into(),
            ));
        }
        // The stored position is the controlled point's (LinuxCNC's `convert_home`).
        let home = self.program_of_controlled(&self.homes[k]);
        if b.mask & axis_mask() == 0 {
            // LinuxCNC moves through the current point (a move of length zero), then home.
            self.emit(Canon::Traverse {
                end: Axes::from_array(self.p),
            });
            self.emit(Canon::Traverse {
                end: Axes::from_array(home),
            });
            self.p = home;
            return Ok(());
        }
        let mid = self.find_ends(b, false)?;
        self.emit(Canon::Traverse {
            end: Axes::from_array(mid),
        });
        let mut end = mid;
        for (i, &c) in AXIS_LETTERS.iter().enumerate() {
            if b.has(c) {
                end[i] = home[i];
            }
        }
        self.emit(Canon::Traverse {
            end: Axes::from_array(end),
        });
        self.p = end;
        Ok(())
    }
}

impl Interp<'_, '_> {
    /// Whether Fanuc's system variable `n` is one of LinuxCNC's parameters that swarf keeps
    /// and Fanuc numbers alike: the machine position (#5021–#5026) and the work offsets G54–G59
    /// (#5221–#5226, #5241–#5246 …). LinuxCNC's others in that range (G28/G30 positions, G92,
    /// the tool at #5400…) mean something else on a Fanuc or Haas control (Haas's #5401… are
    /// tool timers): read, they are warned about as any system variable swarf does not model.
    fn modelled_view(n: usize) -> bool {
        (5021..=5026).contains(&n) || (5221..=5346).contains(&n) && (n - 5221) % 20 < 6
    }

    /// Fanuc's system variables read from the interpreter's state, in program units: the
    /// modal G code of each group (#4001–#4016, e.g. 1 for G01, 54.1 for G54.1), the last
    /// D F H S T (#4107 #4109 #4111 #4119 #4120), the block end position and the current
    /// position in the work coordinates (#5001–#5006, #5041–#5046: the same, as swarf reads
    /// no block ahead). `None`: not one of these.
    fn fanuc_system(&self, n: usize) -> Option<f64> {
        let axis = |i: usize| self.to_units(i, self.p[i]);
        let g = |code: u16| Some(f64::from(code) / 10.0);
        match n {
            4001 => g(self.group1),
            4002 => g(match self.plane {
                Plane::XY => 170,
                Plane::XZ => 180,
                Plane::YZ => 190,
            }),
            4003 => g(if self.absolute { 900 } else { 910 }),
            4005 => g(match self.feed_mode {
                FeedMode::InverseTime => 930,
                FeedMode::PerMinute => 940,
                FeedMode::PerRevolution | FeedMode::SpindleSynchronised => 950,
            }),
            4006 => g(if self.units == Units::Inch { 200 } else { 210 }),
            4007 => g(self.read_only.ccomp),
            4008 => g(if self.read_only.tlo_on { 430 } else { 490 }),
            4009 => g(self
                .motion
                .filter(|m| matches!(m, 730 | 740 | 810..=890))
                .unwrap_or(800)),
            4010 => g(if self.retract_r { 990 } else { 980 }),
            4011 => g(if self.g51.is_some() { 510 } else { 500 }),
            4012 => g(670),
            4013 => g(if self.read_only.css { 960 } else { 970 }),
            4014 => g(match (self.ext_coord, self.coord) {
                (Some(_), _) => 541,
                (None, k @ 1..=6) => 530 + 10 * k as u16,
                (None, k) => 590 + k as u16 - 6,
            }),
            4016 => g(if self.g68.is_some() || self.tilt.is_some() {
                680
            } else {
                690
            }),
            4107 => Some(self.last_dh[0].unwrap_or(0.0)),
            4109 => Some(if self.feed_mode == FeedMode::InverseTime {
                self.feed
            } else {
                self.feed / self.scale
            }),
            4111 => Some(self.last_dh[1].unwrap_or(0.0)),
            4119 => Some(self.rpm),
            4120 => Some(f64::from(
                self.read_only
                    .selected_tool
                    .unwrap_or(self.read_only.loaded_tool),
            )),
            5001..=5006 => Some(axis(n - 5001)),
            5041..=5046 => Some(axis(n - 5041)),
            _ => None,
        }
    }

    /// Says once each system variable read that swarf does not model (it read 0, or what
    /// the program stored in it).
    fn tell_unmodelled_reads(&mut self) {
        let pending = std::mem::take(&mut *self.sysvar_pending.borrow_mut());
        for n in pending {
            if self.sysvar_told.contains(&n) {
                continue;
            }
            self.sysvar_told.push(n);
            self.warn_at(
                0,
                format!(
                    "system variable #{n} is the control's and swarf does not model it: read \
                     as 0 (if the program's motion depends on it, the simulation may differ \
                     from the machine's)"
                ),
            );
        }
    }
}

impl ParamRead for Interp<'_, '_> {
    fn fanuc(&self) -> bool {
        self.fanuc
    }

    fn numbered(&self, n: usize) -> f64 {
        if self.fanuc && n >= 1000 {
            if let Some(v) = self.fanuc_system(n) {
                return v;
            }
            if !Self::modelled_view(n) && !self.sysvar_written.contains(&n) {
                let mut pending = self.sysvar_pending.borrow_mut();
                if !pending.contains(&n) {
                    pending.push(n);
                }
            }
        }
        self.get_numbered(n)
    }
    fn named(&self, name: &str) -> Option<f64> {
        match name {
            // LinuxCNC starts with no value returned.
            "_value" | "_value_returned" => Some(self.params.get_named(name).unwrap_or(0.0)),
            _ => self
                .system_parameter(name)
                .or_else(|| self.params.get_named(name)),
        }
    }
    fn read_only_named(&self, name: &str) -> bool {
        self.system_parameter(name).is_some()
    }
    fn ini_file(&self) -> Option<(&std::path::Path, bool)> {
        self.opts
            .ini
            .as_ref()
            .map(|i| (i.path.as_path(), self.ini_vars))
    }
}

impl Interp<'_, '_> {
    /// LinuxCNC's predefined named parameters (read-only; `_value` and `_value_returned`,
    /// which O-word returns set, are not among them).
    fn system_parameter(&self, name: &str) -> Option<f64> {
        let flag = |b: bool| Some(f64::from(u8::from(b)));
        let ro = &self.read_only;
        match name {
            // rs274 caches an INI value as a global, read-only parameter.
            n if n.starts_with("_ini[") => {
                let ini = self.opts.ini.as_ref().filter(|_| self.ini_vars)?;
                *self
                    .ini_values
                    .borrow_mut()
                    .entry(n.to_string())
                    .or_insert_with(|| ini.parameter(n))
            }
            "_x" => Some(self.to_units(0, self.p[0])),
            "_y" => Some(self.to_units(1, self.p[1])),
            "_z" => Some(self.to_units(2, self.p[2])),
            "_abs_x" | "_abs_y" | "_abs_z" | "_abs_a" | "_abs_b" | "_abs_c" => {
                let i = AXIS_LETTERS
                    .iter()
                    .position(|&c| c == name.as_bytes()[5])
                    .unwrap_or(0);
                // The controlled point's: rs274 adds the tool length offset (NP_ABS_Z).
                Some(self.to_units(i, self.controlled()[i]))
            }
            "_a" => Some(self.p[3]),
            "_b" => Some(self.p[4]),
            "_c" => Some(self.p[5]),
            "_metric" => flag(self.units == Units::Mm),
            "_imperial" => flag(self.units == Units::Inch),
            "_absolute" => flag(self.absolute),
            "_incremental" => flag(!self.absolute),
            // As the F word gave it: G20/G21 convert the position, not the feed.
            "_feed" => Some(if self.feed_mode == FeedMode::InverseTime {
                self.feed
            } else {
                self.feed / ro.feed_scale
            }),
            "_rpm" => Some(self.rpm),
            "_current_tool" => Some(f64::from(ro.loaded_tool)),
            // rs274 2.9's setup starts with selected_tool 0 (its pocket -1).
            "_selected_tool" => Some(ro.selected_tool.map_or(0.0, f64::from)),
            // The pockets of those tools in the tool table (a tool the table does not list:
            // its own number; no tool loaded: 0, none selected: -1).
            "_current_pocket" => Some(f64::from(self.pocket_of(ro.loaded_tool))),
            "_selected_pocket" => Some(
                ro.selected_tool
                    .map_or(-1.0, |t| f64::from(self.pocket_of(t))),
            ),
            "_line" => Some(f64::from(self.cur_line)),
            "_u" | "_v" | "_w" | "_abs_u" | "_abs_v" | "_abs_w" => Some(0.0),
            "_motion_mode" => Some(f64::from(self.motion.unwrap_or(800))),
            "_plane" => Some(match self.plane {
                Plane::XY => 170.0,
                Plane::XZ => 180.0,
                Plane::YZ => 190.0,
            }),
            "_ccomp" => Some(f64::from(ro.ccomp)),
            "_inverse_time" => flag(self.feed_mode == FeedMode::InverseTime),
            "_units_per_minute" => flag(self.feed_mode == FeedMode::PerMinute),
            "_units_per_rev" => flag(self.feed_mode == FeedMode::PerRevolution),
            "_coord_system" => Some(match self.coord {
                c @ 1..=6 => 530.0 + 10.0 * c as f64,
                c => 584.0 + c as f64,
            }),
            "_tool_offset" => flag(ro.tlo_on),
            // G99 retracts to the R plane, G98 to the level before the cycle.
            "_retract_r_plane" => flag(self.retract_r),
            "_retract_old_z" => flag(!self.retract_r),
            "_spindle_rpm_mode" => flag(!ro.css),
            "_spindle_css_mode" => flag(ro.css),
            "_ijk_absolute_mode" => flag(self.arc_absolute),
            "_lathe_diameter_mode" => flag(false),
            "_lathe_radius_mode" => flag(true),
            "_spindle_on" => flag(self.dir != SpindleDir::Stopped),
            "_spindle_cw" => flag(self.dir == SpindleDir::Clockwise),
            "_mist" => flag(ro.mist),
            "_flood" => flag(ro.flood),
            "_feed_override" => flag(ro.overrides[0]),
            "_speed_override" => flag(ro.overrides[1]),
            "_adaptive_feed" => flag(ro.overrides[2]),
            "_feed_hold" => flag(ro.overrides[3]),
            "_call_level" => Some(self.frames.len() as f64),
            "_remap_level" | "_task" => Some(0.0),
            // The LinuxCNC whose interpreter swarf follows (2.9, its tests and nc_files): a
            // program may check it (`roparams.ngc`), rs274 2.9 reads 2.9 and 0.
            "_vmajor" => Some(2.9),
            "_vminor" => Some(0.0),
            _ => None,
        }
    }
}

/// What an error found, for its message: the text, trimmed; an invisible character (a
/// no-break space, a form feed, a zero-width space…) shown by its code point and name, where
/// trimming would have left nothing ("found end of line").
fn found_text(s: &str) -> String {
    let t = s.trim_matches([' ', '\t']);
    let Some(ch) = t.chars().next() else {
        return String::new();
    };
    let name = match ch {
        '\u{a0}' => Some("no-break space"),
        '\u{c}' => Some("form feed"),
        '\u{b}' => Some("vertical tab"),
        '\u{200b}' => Some("zero-width space"),
        '\u{feff}' => Some("zero-width no-break space, a byte-order mark"),
        '\u{202f}' => Some("narrow no-break space"),
        '\u{2007}' => Some("figure space"),
        '\u{3000}' => Some("ideographic space"),
        '\u{2000}'..='\u{200a}' => Some("a typographic space"),
        '\u{ad}' => Some("soft hyphen"),
        c if c.is_control() => Some("a control character"),
        c if c.is_whitespace() => Some("a space character"),
        _ => None,
    };
    match name {
        Some(n) => format!("U+{:04X} ({n})", u32::from(ch)),
        None => t.trim().to_string(),
    }
}

/// Where `needle` first appears in normalised code.
fn find_code(code: &[u8], needle: &[u8]) -> Option<usize> {
    code.windows(needle.len()).position(|w| w == needle)
}

/// `v` with its X and Y turned by `deg` degrees counter-clockwise about Z.
pub(crate) fn rotate_xy(mut v: [f64; 6], deg: f64) -> [f64; 6] {
    if deg != 0.0 {
        let (s, c) = deg.to_radians().sin_cos();
        let (x, y) = (v[0], v[1]);
        v[0] = c * x - s * y;
        v[1] = s * x + c * y;
    }
    v
}

/// The keyword of an active comment and the text after its comma, by LinuxCNC's rule
/// (`convert_comment`): blanks before the keyword are skipped, none may stand between it and
/// the comma (`( msg,…)` is a message, `(msg ,…)` a plain comment).
fn comment_head(text: &str) -> Option<(&str, &str)> {
    let t = text.trim_start_matches([' ', '\t']);
    let (head, body) = t.split_once(',')?;
    (!head.is_empty() && head.bytes().all(|c| c.is_ascii_alphabetic())).then_some((head, body))
}

/// LinuxCNC's active comments: `(MSG,…)`, `(DEBUG,…)`, `(PRINT,…)` (any case, see
/// [`comment_head`]), and the text after the comma.
fn active_comment(text: &str) -> Option<(MessageKind, &str)> {
    let (head, body) = comment_head(text)?;
    let kind = match head {
        h if h.eq_ignore_ascii_case("msg") => MessageKind::Msg,
        h if h.eq_ignore_ascii_case("debug") => MessageKind::Debug,
        h if h.eq_ignore_ascii_case("print") => MessageKind::Print,
        _ => return None,
    };
    Some((kind, body))
}

impl Interp<'_, '_> {
    /// A `(DEBUG,…)`/`(PRINT,…)` text with `#123` and `#<name>` replaced by their values as
    /// LinuxCNC 2.9 prints them: six decimals, or as the last format word before them in the
    /// comment says — `%d` none, `%f` four, `%.Nf` N (one digit) — which prints nothing
    /// itself; any other `%` is text (a `%.` not so read loses its `%`, as in rs274). An
    /// undefined name prints `######`.
    fn substitute_parameters(&self, text: &str) -> String {
        let mut out = String::with_capacity(text.len() + 16);
        let mut decimals = 6usize;
        let mut rest = text;
        while let Some(i) = rest.find(['#', '%']) {
            out.push_str(&rest[..i]);
            let after = &rest[i + 1..];
            if rest.as_bytes()[i] == b'%' {
                let b = after.as_bytes();
                let (d, used) = match b {
                    [b'd', ..] => (Some(0), 1),
                    [b'f', ..] => (Some(4), 1),
                    [b'.', n @ b'0'..=b'9', b'f', ..] => (Some(usize::from(n - b'0')), 3),
                    _ => (None, 0),
                };
                match d {
                    Some(d) => decimals = d,
                    // (rs274 drops the `%` of a `%.` it cannot read: `%.12f` prints `.12f`.)
                    None if b.first() == Some(&b'.') => {}
                    None => out.push('%'),
                }
                rest = &after[used..];
                continue;
            }
            if let Some(named) = after.strip_prefix('<') {
                if let Some(j) = named.find('>') {
                    let name: String = named[..j]
                        .chars()
                        .filter(|c| !c.is_whitespace())
                        .map(|c| c.to_ascii_lowercase())
                        .collect();
                    match self.named(&name) {
                        Some(v) => {
                            out.push_str(&format!("{:.*}", decimals, super::expr::number(v)))
                        }
                        None => out.push_str("######"),
                    }
                    rest = &named[j + 1..];
                    continue;
                }
            } else {
                let digits = after.bytes().take_while(u8::is_ascii_digit).count();
                if let Some(n) = after[..digits]
                    .parse::<usize>()
                    .ok()
                    .filter(|n| (1..=super::expr::MAX_PARAM).contains(n))
                {
                    let v = super::expr::number(self.get_numbered(n));
                    out.push_str(&format!("{v:.decimals$}"));
                    rest = &after[digits..];
                    continue;
                }
            }
            out.push('#');
            rest = after;
        }
        out.push_str(rest);
        out
    }
}

/// Whether normalised code (spaces out, lower case) starts with a Fanuc Macro B control word:
/// `WHILE[`, `IF[`, `GOTO<n>`, `END<n>` (a G-code word never starts so).
pub(crate) fn is_macro_b(code: &[u8]) -> bool {
    let digit_after = |w: &[u8]| {
        code.strip_prefix(w)
            .is_some_and(|r| r.first().is_some_and(u8::is_ascii_digit))
    };
    code.starts_with(b"while[")
        || code.starts_with(b"if[")
        || digit_after(b"goto")
        || code.starts_with(b"goto#")
        || code.starts_with(b"goto[")
        || digit_after(b"end")
}

/// Whether a normalised line (lower case, no spaces) is one of GRBL's own commands: `$$`, `$#`,
/// `$G`, `$I`, `$N`, `$C`, `$X`, `$H` (optionally with axis letters), `$SLP`, `$RST=…`,
/// `$N<digit>=…`, `$<digits>=<number>` or a jog `$J=…`. Other lines starting with `$` are
/// G-code (LinuxCNC 2.8+'s spindle-select word, in any order: `$1 M3 S1000`) and are read as
/// such.
fn is_grbl_command(code: &[u8]) -> bool {
    let Some(rest) = code.strip_prefix(b"$") else {
        return false;
    };
    let number = |t: &[u8]| {
        let t = t
            .strip_prefix(b"-")
            .or_else(|| t.strip_prefix(b"+"))
            .unwrap_or(t);
        let digits = t.iter().filter(|c| c.is_ascii_digit()).count();
        let points = t.iter().filter(|&&c| c == b'.').count();
        digits > 0 && points <= 1 && digits + points == t.len()
    };
    match rest {
        b"$" | b"#" | b"g" | b"i" | b"n" | b"c" | b"x" | b"slp" => true,
        [b'h', axes @ ..] => axes.iter().all(|c| b"xyzabc".contains(c)),
        _ if rest.starts_with(b"rst=") || rest.starts_with(b"j=") => true,
        [b'n', d, b'=', ..] if d.is_ascii_digit() => true,
        _ => match rest.iter().position(|&c| c == b'=') {
            Some(eq) => {
                eq > 0 && rest[..eq].iter().all(u8::is_ascii_digit) && number(&rest[eq + 1..])
            }
            None => false,
        },
    }
}
