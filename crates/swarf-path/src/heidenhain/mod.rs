//! Heidenhain conversational (Klartext) programs, as TNC 426/530/620/640 controls run them,
//! read into the same [`Canon`] events as G-code — the language of most European 5-axis
//! machines and of CAM post-processors written for them.
//!
//! # What is read
//! * `BEGIN PGM name MM|INCH` (inch programs: lengths × 25.4, feeds in 0.1 inch/min × 2.54),
//!   `END PGM`, `BLK FORM` (noted), `*` structure blocks and `;` comments, `~` continuations.
//! * `TOOL CALL n|"name" Z S… F…` (the tool axis letter sets the working plane; a named tool
//!   is numbered in order of first call, and a warning says which number), `TOOL DEF`.
//! * Straight lines `L` (`FMAX` for that block only, `F`, `FAUTO` = the `TOOL CALL` feed,
//!   `FU` per revolution; rotary axes `A B C`; incremental `IX …`), `LN` with a tool vector
//!   `TX TY TZ` (5-axis CAM output; the surface normal `NX NY NZ` only serves 3-D tool
//!   compensation, which is off with zero deltas), circle centre / pole `CC`, arcs `C` (about
//!   `CC`), `CR` (radius `R+` ≤ 180°, `R−` > 180°), `CT` (tangent), polar `LP` and `CP` (with a
//!   linear axis: a helix; `IPA` of several turns). `DR+` is counter-clockwise seen from the
//!   tool axis' positive side.
//! * M functions: spindle (`M3 M4 M5 M13 M14`), end (`M2 M30`), `M91`/`M92` (machine
//!   coordinates: the home given with `--home` is their zero), `M128`/`M129` and `FUNCTION
//!   TCPM` (tool-tip positions, as a `-tcp` machine reads them), `M140 MB` (retract along the
//!   tool axis), `M99`/`M89` (cycle call), `M136`/`M137` (feed in µm per revolution); other M
//!   functions change nothing swarf models and are reported once.
//! * Cycles: 7 datum shift, 10 rotation, 9 dwell, 19 working plane, 32 tolerance (noted),
//!   and the drilling and tapping cycles 200–203, 205–207, 209, 240 and the old 1, 2 and 17,
//!   run at `CYCL CALL`, `CYCL CALL POS`, `M99` and under `M89`. Pocket, contour and
//!   thread-milling cycles are refused: their paths are the control's.
//! * `PLANE SPATIAL`, `EULER`, `VECTOR`, `POINTS`, `RELATIV` and `RESET` (the tool turned to
//!   the plane, as with `TURN`).
//! * Q parameters (`Q`, `QL`, `QR`): formulas (`Q1 = Q2 * SIN(30)`), `FN 0`–`FN 13`, jumps
//!   `FN 9`–`FN 12`, labels and subprograms (`LBL`, `CALL LBL n`, `CALL LBL n REP m`, `LBL 0`),
//!   other program files (`CALL PGM`, searched beside the program and in the subroutine path).
//!
//! Refused with an error naming the word: radius compensation (`RL`, `RR`, `R+`, `R−`),
//! `RND`, `CHF`, `APPR`/`DEP`, FK free contours, `SPL`, `PLANE AXIAL`/`PROJECTED`, mirror
//! images and scaling, patterns. Errors name the file, line and column.

mod cycles;

pub(crate) mod lexer;

use std::collections::HashMap;
use std::path::PathBuf;
use std::rc::Rc;

use crate::gcode::GcodeOptions;
use crate::limit::MoveLimit;
use crate::part_frame::PartFrame;
use crate::reader_core::{self, Contour};
use crate::{
    Canon, CanonSink, FeedMode, PathError, PathErrorKind, Plane, SourcePos, SpindleDir, Warning,
};
use lexer::{Block, Tok, Val};

/// A reader error before it is given its file.
#[derive(Debug)]
pub(crate) struct Fault {
    pub(crate) line: u32,
    pub(crate) col: u32,
    pub(crate) kind: PathErrorKind,
    pub(crate) message: String,
    pub(crate) found: String,
    pub(crate) expected: String,
}

pub(crate) type Res<T> = Result<T, Fault>;

impl Fault {
    fn at(t: &Tok, kind: PathErrorKind, message: impl Into<String>, expected: &str) -> Self {
        Fault {
            line: t.line,
            col: t.col,
            kind,
            message: message.into(),
            found: t.text.clone(),
            expected: expected.into(),
        }
    }
}

/// True when `text` is a Heidenhain conversational program: its first statement is
/// `BEGIN PGM` (after an optional block number), or the first of its first 200 lines written
/// unmistakably for some control other than an RS274/NGC one is Heidenhain (`5 L X+10 R0
/// FMAX`, `TOOL CALL`, `CYCL DEF`: a program fragment without its header).
pub fn is_heidenhain(text: &str) -> bool {
    let begins = crate::gcode::lexer::lines(text)
        .map(|l| l.trim_start_matches('\u{feff}').trim())
        .find(|l| !l.is_empty())
        .is_some_and(|l| {
            let body = l
                .trim_start_matches(|c: char| c.is_ascii_digit())
                .trim_start();
            body.len() >= 9
                && body.is_char_boundary(9)
                && body[..9].eq_ignore_ascii_case("BEGIN PGM")
        });
    use crate::gcode::dialect::Dialect;
    begins || matches!(Dialect::detect(text, 200), Some((Dialect::Heidenhain, _)))
}

/// Reads a Heidenhain conversational program, handing its events to `sink` (see the
/// [module documentation](self)). Of `opts`, the move limit, the loop limit (jumps back), the
/// call depth, the repeat limit, the home and the subroutine path apply.
///
/// # Errors
/// The first statement that cannot be read or is refused: file, line, column, what was found
/// and what was expected.
pub fn read_heidenhain(
    text: &str,
    file: &str,
    opts: &GcodeOptions,
    sink: &mut dyn CanonSink,
) -> Result<(), PathError> {
    let mut r = Reader::new(file, opts, sink);
    let result = match lexer::blocks(text) {
        Ok(blocks) => r.run(blocks),
        Err(f) => Err(f),
    };
    let file_of = |r: &Reader| {
        r.error_file.clone().unwrap_or_else(|| {
            r.sources
                .get(r.cur)
                .map_or(file.to_string(), |s| s.name.clone())
        })
    };
    let out = match result {
        Ok(()) if r.sink.over => Err(reader_core::limit_error(file, r.sink.max())),
        Ok(()) => Ok(()),
        Err(f) => Err(PathError::new(
            SourcePos {
                file: file_of(&r),
                line: f.line,
                column: f.col,
            },
            f.kind,
            f.message,
            f.found,
            f.expected,
        )),
    };
    r.sink.finish();
    out
}

/// One program file: its blocks and labels.
struct Source {
    name: String,
    blocks: Rc<Vec<Block>>,
    /// Label → index of the `LBL` block.
    labels: HashMap<String, usize>,
    /// mm per program unit.
    scale: f64,
}

/// Where a call returns to.
enum Ret {
    /// `CALL LBL`: back to `back`; the subprogram runs `left` more times from `again`.
    Lbl {
        back: (usize, usize),
        again: usize,
        left: u64,
    },
    /// `CALL PGM`: back to `back` at the called program's `END PGM`.
    Pgm { back: (usize, usize) },
}

/// What a block does to the flow.
enum Flow {
    Next,
    Jump(usize, usize),
    End,
}

/// The words of a positioning block.
#[derive(Default)]
struct Words {
    /// X Y Z (mm) A B C (degrees), each with "incremental".
    axes: [Option<(f64, bool)>; 6],
    feed: Option<Feed>,
    /// M functions with their tokens.
    m: Vec<(u32, usize)>,
    /// Named values: `R` (arc radius), `DR` (direction), `PR PA IPR IPA`, `NX…TZ`, `MB`.
    named: Vec<(&'static str, f64)>,
    /// `MB MAX`.
    mb_max: bool,
}

impl Words {
    fn get(&self, name: &str) -> Option<f64> {
        self.named
            .iter()
            .rev()
            .find(|(n, _)| *n == name)
            .map(|(_, v)| *v)
    }
    fn has_m(&self, m: u32) -> bool {
        self.m.iter().any(|(n, _)| *n == m)
    }
}

#[derive(Clone, Copy, Debug)]
enum Feed {
    Rapid,
    /// Per minute (mm/min).
    Value(f64),
    /// Per revolution (mm/rev).
    PerRev(f64),
    Auto,
}

const NAMED: [&str; 17] = [
    "R", "DR", "PR", "PA", "IPR", "IPA", "NX", "NY", "NZ", "TX", "TY", "TZ", "MB", "DL", "DR2",
    "S", "IR",
];

struct Reader<'a> {
    file: &'a str,
    opts: &'a GcodeOptions,
    sink: MoveLimit<'a>,
    sources: Vec<Source>,
    cur: usize,
    stack: Vec<Ret>,
    /// Remaining repeats of each `CALL LBL … REP` block being repeated.
    repeats: HashMap<(usize, usize), u64>,
    jumps: u64,
    q: HashMap<(u8, u32), f64>,
    /// mm per program unit; feed factor to mm/min.
    scale: f64,
    feed_scale: f64,
    /// Position, working plane and the contour's direction.
    c: Contour,
    /// Datum shift, rotation and tilted plane.
    frame: PartFrame,
    pole: Option<[f64; 2]>,
    /// Last arc direction (`DR+`: 1).
    dr: Option<f64>,
    feed: Option<f64>,
    feed_mode: FeedMode,
    tool_feed: Option<f64>,
    rpm: f64,
    dir: SpindleDir,
    /// The defined cycle's number, and the values of an old-style cycle's sub-blocks.
    cycle: Option<u32>,
    old_cycle: HashMap<u32, f64>,
    modal_call: bool,
    m136: bool,
    /// M126: rotary axes take the shortest way to an absolute position.
    shortest: bool,
    /// `FUNCTION TCPM … AXIS SPAT`: the A B C words are spatial angles of the tool (the last
    /// ones given), not the machine's rotary axes; `None` under `AXIS POS`, M128 or no TCPM.
    spat: Option<[f64; 3]>,
    /// The blank's least corner (`BLK FORM 0.1`).
    blank_min: Option<[f64; 3]>,
    tool_names: HashMap<String, u32>,
    warned: Vec<&'static str>,
    ended: bool,
    /// The called file an error was found in while loading it.
    error_file: Option<String>,
}

impl<'a> Reader<'a> {
    fn new(file: &'a str, opts: &'a GcodeOptions, sink: &'a mut dyn CanonSink) -> Self {
        let mut pos = [0.0; 6];
        if let Some(h) = opts.home {
            pos[..3].copy_from_slice(&h);
        }
        Reader {
            file,
            opts,
            sink: MoveLimit::new(sink, opts.max_moves),
            sources: Vec::new(),
            cur: 0,
            stack: Vec::new(),
            repeats: HashMap::new(),
            jumps: 0,
            q: HashMap::new(),
            scale: 1.0,
            feed_scale: 1.0,
            c: Contour::new(pos),
            frame: PartFrame::default(),
            pole: None,
            dr: None,
            feed: None,
            feed_mode: FeedMode::PerMinute,
            tool_feed: None,
            rpm: 0.0,
            dir: SpindleDir::Stopped,
            spat: None,
            cycle: None,
            old_cycle: HashMap::new(),
            modal_call: false,
            m136: false,
            shortest: false,
            blank_min: None,
            tool_names: HashMap::new(),
            warned: Vec::new(),
            ended: false,
            error_file: None,
        }
    }

    fn emit(&mut self, line: u32, e: Canon<'_>) {
        self.sink.emit(line, &e);
    }

    fn warn(&mut self, line: u32, col: u32, message: String) {
        let file = self
            .sources
            .get(self.cur)
            .map_or(self.file.to_string(), |s| s.name.clone());
        self.sink.warn(Warning {
            file,
            line,
            column: col,
            message,
        });
    }

    /// Warns once per program about `what`.
    fn warn_once(&mut self, key: &'static str, line: u32, col: u32, message: String) {
        if !self.warned.contains(&key) {
            self.warned.push(key);
            self.warn(line, col, message);
        }
    }

    fn source(name: String, blocks: Vec<Block>) -> Res<Source> {
        let mut labels = HashMap::new();
        let mut scale = 1.0;
        for (i, b) in blocks.iter().enumerate() {
            let t = &b.toks;
            match t.first().map(|t| t.text.as_str()) {
                Some("LBL") => {
                    let Some(l) = t.get(1) else {
                        return Err(Fault::at(
                            &t[0],
                            PathErrorKind::Syntax,
                            "LBL without a label",
                            "a label number or name",
                        ));
                    };
                    let key = label_key(&l.text);
                    if key != "0" && labels.insert(key, i).is_some() {
                        return Err(Fault::at(
                            l,
                            PathErrorKind::Semantic,
                            format!("label {} is defined twice", l.text),
                            "each label once",
                        ));
                    }
                }
                Some("BEGIN") if t.last().is_some_and(|u| u.text == "INCH") => scale = 25.4,
                _ => {}
            }
        }
        Ok(Source {
            name,
            blocks: Rc::new(blocks),
            labels,
            scale,
        })
    }

    fn run(&mut self, blocks: Vec<Block>) -> Res<()> {
        let main = Self::source(self.file.to_string(), blocks)?;
        self.scale = main.scale;
        self.feed_scale = if main.scale == 1.0 { 1.0 } else { 2.54 };
        self.sources.push(main);
        for e in reader_core::opening(self.scale, &self.frame, self.c.pos) {
            self.emit(0, e);
        }
        let mut pc = 0;
        loop {
            if self.sink.over {
                return Ok(());
            }
            let blocks = Rc::clone(&self.sources[self.cur].blocks);
            let Some(b) = blocks.get(pc) else {
                // The end of a called program's file returns; the main program's ends reading.
                if let Some(Ret::Pgm { back }) = self.stack.last() {
                    let back = *back;
                    self.stack.pop();
                    self.switch_to(back.0);
                    pc = back.1;
                    continue;
                }
                if !self.ended {
                    let line = blocks.last().map_or(0, |b| b.line);
                    self.warn(line, 0, "the program has no END PGM, M2 or M30".into());
                }
                return Ok(());
            };
            pc += 1;
            match self.block(b, pc - 1)? {
                Flow::Next => {}
                Flow::Jump(src, to) => {
                    self.switch_to(src);
                    pc = to;
                }
                Flow::End => {
                    self.ended = true;
                    self.emit(b.line, Canon::ProgramEnd);
                    return Ok(());
                }
            }
        }
    }

    fn switch_to(&mut self, src: usize) {
        if src != self.cur {
            self.cur = src;
            self.scale = self.sources[src].scale;
            self.feed_scale = if self.scale == 1.0 { 1.0 } else { 2.54 };
            let name = self.sources[src].name.clone();
            self.emit(0, Canon::SourceFile(name.into()));
        }
    }

    /// Counts a jump back; the loop limit stops a program that would never end.
    fn jump(&mut self, t: &Tok) -> Res<()> {
        self.jumps += 1;
        if self.jumps > self.opts.max_loop_iterations {
            return Err(Fault::at(
                t,
                PathErrorKind::Limit,
                format!(
                    "more than {} jumps and repeats: the program may never end",
                    self.opts.max_loop_iterations
                ),
                "a program that ends",
            ));
        }
        Ok(())
    }

    fn qv(&self, r: lexer::QRef) -> f64 {
        let v = self.q.get(&(r.kind, r.index)).copied().unwrap_or(0.0);
        if r.negate {
            -v
        } else {
            v
        }
    }

    fn value(&self, v: Val, t: &Tok) -> Res<f64> {
        match v {
            Val::Num(x) => Ok(x),
            Val::Q(q) => Ok(self.qv(q)),
            _ => Err(Fault::at(
                t,
                PathErrorKind::Syntax,
                format!("{} needs a value", t.text),
                "a signed number or a Q parameter",
            )),
        }
    }

    fn block(&mut self, b: &Block, index: usize) -> Res<Flow> {
        let Some(head) = b.toks.first() else {
            if let Some(c) = &b.comment {
                if !c.is_empty() {
                    self.emit(b.line, Canon::Comment(c.as_str().into()));
                }
            }
            return Ok(Flow::Next);
        };
        let second = b.toks.get(1).map(|t| t.text.as_str());
        match head.text.as_str() {
            "BEGIN" => Ok(Flow::Next),
            "END" => {
                if let Some(Ret::Pgm { back }) = self.stack.last() {
                    let back = *back;
                    self.stack.pop();
                    return Ok(Flow::Jump(back.0, back.1));
                }
                Ok(Flow::End)
            }
            "BLK" => self.blank(b).map(|_| Flow::Next),
            "TOOL" if second == Some("CALL") => self.tool_call(b).map(|_| Flow::Next),
            "TOOL" if second == Some("DEF") => Ok(Flow::Next),
            "L" | "LN" | "C" | "CR" | "CT" | "LP" | "CP" => self.motion(b),
            "CC" => self.pole(b).map(|_| Flow::Next),
            "CYCL" if second == Some("DEF") => self.cycle_def(b).map(|_| Flow::Next),
            "CYCL" if second == Some("CALL") => {
                self.cycle_call_block(b)?;
                Ok(Flow::Next)
            }
            "PLANE" => self.plane_function(b).map(|_| Flow::Next),
            "FUNCTION" => {
                match second {
                    Some("TCPM") => {
                        self.tcpm(b.line, true);
                        // `AXIS SPAT`: A B C are spatial angles (`AXIS POS`, the default: the
                        // rotary axes' positions).
                        let spat = b
                            .toks
                            .windows(2)
                            .any(|t| t[0].text == "AXIS" && t[1].text == "SPAT");
                        if spat {
                            self.spat = Some([0.0; 3]);
                        }
                    }
                    Some("RESET") if b.toks.get(2).is_some_and(|t| t.text == "TCPM") => {
                        self.tcpm(b.line, false)
                    }
                    Some("RESET") | Some("MODE") => {}
                    _ => self.warn(
                        b.line,
                        head.col,
                        format!("{} is not read (it changes nothing swarf models)", b.code),
                    ),
                }
                Ok(Flow::Next)
            }
            "STOP" => self.m_only(b, 1),
            t if t.starts_with('M')
                && t[1..].bytes().all(|c| c.is_ascii_digit())
                && t.len() > 1 =>
            {
                self.m_only(b, 0)
            }
            "LBL" => {
                if second.map(label_key).as_deref() == Some("0") {
                    return self.subprogram_end(head);
                }
                Ok(Flow::Next)
            }
            "CALL" => self.call(b, index),
            "FN" => self.function(b),
            t if t.starts_with("QS") => {
                self.warn(
                    b.line,
                    head.col,
                    "string parameters (QS) are not read".into(),
                );
                Ok(Flow::Next)
            }
            t if t.starts_with('Q') => {
                self.assign(&b.code, b.line, b.code_col)?;
                Ok(Flow::Next)
            }
            "TCH" => {
                self.warn(
                    b.line,
                    head.col,
                    "touch-probe cycle skipped: the probing moves are not simulated and what \
                     it measures (a datum, a rotation) is not applied"
                        .into(),
                );
                Ok(Flow::Next)
            }
            "RND" | "CHF" => Err(Fault::at(
                head,
                PathErrorKind::Unsupported,
                format!(
                    "{} (rounding or chamfer between contour elements) is not read: program the \
                     arc or line itself",
                    head.text
                ),
                "L, C, CR, CT, LP or CP",
            )),
            "APPR" | "DEP" => Err(Fault::at(
                head,
                PathErrorKind::Unsupported,
                format!(
                    "{} (approach and departure with radius compensation) is not read: swarf \
                     reads programs of the tool path (R0)",
                    head.text
                ),
                "L, C, CR, CT, LP or CP",
            )),
            "FL" | "FLT" | "FC" | "FCT" | "FPOL" | "FSELECT" | "FLN" | "FCN" => Err(Fault::at(
                head,
                PathErrorKind::Unsupported,
                "FK free contour programming is not read",
                "L, C, CR, CT, LP or CP",
            )),
            "SPL" => Err(Fault::at(
                head,
                PathErrorKind::Unsupported,
                "SPL spline blocks are not read",
                "L, LN, C, CR, CT, LP or CP",
            )),
            // Tables and declarations the program selects: their contents are the control's.
            "PRESET" => {
                self.warn(
                    b.line,
                    head.col,
                    format!(
                        "{} is not read (the preset table is the control's): positions stay in \
                         the current datum",
                        b.code
                    ),
                );
                Ok(Flow::Next)
            }
            "DECLARE" | "SEL"
                if head.text == "DECLARE" || matches!(second, Some("TABLE" | "CORR-TABLE")) =>
            {
                self.warn(b.line, head.col, format!("{} is not read", b.code));
                Ok(Flow::Next)
            }
            "PATTERN" | "SEL" => Err(Fault::at(
                head,
                PathErrorKind::Unsupported,
                format!("{} is not read", b.code),
                "a statement swarf reads (see `swarf path --help`)",
            )),
            _ => Err(Fault::at(
                head,
                PathErrorKind::Syntax,
                "unknown Heidenhain statement",
                "L, LN, C, CC, CR, CT, LP, CP, TOOL CALL, CYCL DEF, CYCL CALL, PLANE, FN, Q…, \
                 LBL, CALL, M…, BEGIN PGM or END PGM",
            )),
        }
    }

    /// Tool centre point management on (M128, FUNCTION TCPM) or off (M129, FUNCTION RESET
    /// TCPM): while on, X Y Z are tool-tip positions in the part frame.
    fn tcpm(&mut self, line: u32, on: bool) {
        self.spat = None;
        let before = self.sink.position();
        self.emit(line, Canon::ToolCentrePoint(on));
        reader_core::follow_sink(&mut self.c.pos, before, self.sink.position());
    }

    /// `BLK FORM 0.1 Z X… Y… Z…` (least corner), `BLK FORM 0.2 X… Y… Z…` (greatest, or
    /// `IX…` from the least): the workpiece blank.
    fn blank(&mut self, b: &Block) -> Res<()> {
        let which = b.toks.get(2).map(|t| t.text.as_str());
        let first = match which {
            Some("0.1") => true,
            Some("0.2") => false,
            _ => {
                self.warn(
                    b.line,
                    b.code_col,
                    "only a box blank (BLK FORM 0.1/0.2) is read: give the stock with --stock"
                        .into(),
                );
                return Ok(());
            }
        };
        // (`0.1` names the tool axis before the corner.)
        let skip = if first && b.toks.get(3).is_some_and(|t| t.text.len() == 1) {
            4
        } else {
            3
        };
        let w = self.words(b.toks.get(skip..).unwrap_or(&[]), b.line)?;
        let mut p = match (first, self.blank_min) {
            (false, Some(m)) => m,
            _ => [0.0; 3],
        };
        for (k, a) in w.axes.iter().take(3).enumerate() {
            if let Some((v, inc)) = *a {
                p[k] = if inc { p[k] + v } else { v };
            }
        }
        if first {
            self.blank_min = Some(p);
        } else if let Some(m) = self.blank_min {
            let (min, max) = (
                std::array::from_fn(|k| m[k].min(p[k])),
                std::array::from_fn(|k| m[k].max(p[k])),
            );
            self.emit(b.line, Canon::Blank { min, max });
        }
        Ok(())
    }

    // ---- tools and M functions ----

    fn tool_call(&mut self, b: &Block) -> Res<()> {
        let t = &b.toks;
        let mut i = 2;
        let mut tool = None;
        if let Some(tok) = t.get(i) {
            let s = tok.text.as_str();
            if s.starts_with('"') {
                let name = s.trim_matches('"').to_string();
                tool = Some(self.named_tool(&name, b.line, tok.col));
                i += 1;
            } else if let Some(v) = lexer::number(s) {
                if v.fract() != 0.0 {
                    self.warn(
                        b.line,
                        tok.col,
                        format!("indexed tool {s} is read as tool {}", v.trunc()),
                    );
                }
                if v < 0.0 || v > f64::from(u32::MAX) {
                    return Err(Fault::at(
                        tok,
                        PathErrorKind::Semantic,
                        "bad tool number",
                        "a tool number from 0",
                    ));
                }
                tool = Some(v as u32);
                i += 1;
            } else if let Some(q) = lexer::qref(s) {
                tool = Some(self.qv(q).max(0.0) as u32);
                i += 1;
            }
        }
        if let Some(axis) = t
            .get(i)
            .filter(|a| matches!(a.text.as_str(), "X" | "Y" | "Z"))
        {
            let plane = match axis.text.as_str() {
                "Z" => Plane::XY,
                "Y" => Plane::XZ,
                _ => Plane::YZ,
            };
            if plane != Plane::XY {
                self.warn(
                    b.line,
                    axis.col,
                    format!(
                        "tool axis {}: its working plane is used for arcs and cycles; the tool's \
                         orientation comes from the machine (--machine)",
                        axis.text
                    ),
                );
            }
            if plane != self.c.plane {
                self.c.plane = plane;
                self.pole = None;
                self.c.tangent = None;
                self.emit(b.line, Canon::Plane(plane));
            }
            i += 1;
        }
        let mut deltas = false;
        for tok in &t[i..] {
            let (name, val) = lexer::word(tok)?;
            match name {
                "S" => {
                    self.rpm = self.value(val, tok)?.abs();
                    self.tell_spindle(b.line);
                }
                "F" => {
                    let f = self.value(val, tok)?.abs() * self.feed_scale;
                    self.tool_feed = Some(f);
                    self.feed = Some(f);
                    self.feed_mode = FeedMode::PerMinute;
                }
                "DL" | "DR" | "DR2" => deltas |= self.value(val, tok)? != 0.0,
                _ => self.warn(
                    b.line,
                    tok.col,
                    format!("{} in TOOL CALL is not read", tok.text),
                ),
            }
        }
        if deltas {
            self.warn(
                b.line,
                b.code_col,
                "tool oversizes (DL, DR, DR2) are not applied: the tool tip path is read as \
                 programmed"
                    .into(),
            );
        }
        if let Some(n) = tool {
            self.emit(b.line, Canon::ToolChange { tool: n });
        }
        Ok(())
    }

    /// The number of the tool called by name: the tool library's, or numbered in order of
    /// first call (with a warning).
    fn named_tool(&mut self, name: &str, line: u32, col: u32) -> u32 {
        let (n, warning) = reader_core::tool_by_name(self.opts, &mut self.tool_names, name);
        if let Some(w) = warning {
            self.warn(line, col, w);
        }
        n
    }

    fn tell_spindle(&mut self, line: u32) {
        self.emit(
            line,
            Canon::Spindle {
                rpm: self.rpm,
                dir: self.dir,
            },
        );
    }

    /// The M functions of a block that act before its motion.
    fn m_before(&mut self, w: &Words, line: u32) {
        for &(m, _) in &w.m {
            match m {
                3 | 13 => self.dir = SpindleDir::Clockwise,
                4 | 14 => self.dir = SpindleDir::CounterClockwise,
                128 => self.tcpm(line, true),
                136 => self.m136 = true,
                137 => self.m136 = false,
                126 => self.shortest = true,
                127 => self.shortest = false,
                89 => self.modal_call = true,
                _ => continue,
            }
            if matches!(m, 3 | 4 | 13 | 14) {
                self.tell_spindle(line);
            }
        }
    }

    /// The M functions of a block that act after its motion; true when the program ends.
    fn m_after(&mut self, w: &Words, toks: &[Tok], line: u32) -> Res<bool> {
        let mut end = false;
        for &(m, ti) in &w.m {
            match m {
                5 => {
                    self.dir = SpindleDir::Stopped;
                    self.tell_spindle(line);
                }
                2 | 30 => end = true,
                // (M129 acts at the block's end.)
                129 => self.tcpm(line, false),
                99 => {
                    self.modal_call = false;
                    self.cycle_call(&toks[ti], None)?;
                }
                3 | 4 | 13 | 14 | 128 | 136 | 137 | 89 | 91 | 92 | 140 => {}
                // Stops, coolant, orientation, look-ahead, feed behaviour on arcs and rotary
                // axes, display: nothing the path or its removal depends on.
                0 | 1 | 6 | 7 | 8 | 9 | 19 | 94 | 97 | 101 | 102 | 103 | 104 | 105 | 107 | 108
                | 109 | 110 | 111 | 112 | 113 | 114 | 115 | 116 | 117 | 118 | 120 | 124 | 126
                | 127 | 130 | 138 | 141 | 142 | 143 | 144 | 145 | 148 | 149 | 150 => {}
                _ => self.warn(
                    line,
                    toks[ti].col,
                    format!("M{m} is not read (a machine function swarf does not model)"),
                ),
            }
        }
        Ok(end)
    }

    /// A block of M functions only (`M30`, `STOP M0`).
    fn m_only(&mut self, b: &Block, skip: usize) -> Res<Flow> {
        let w = self.words(&b.toks[skip..], b.line)?;
        if w.axes.iter().any(Option::is_some) || w.feed.is_some() {
            return Err(Fault::at(
                &b.toks[0],
                PathErrorKind::Syntax,
                "a block of M functions with coordinates",
                "L before the coordinates",
            ));
        }
        self.m_before(&w, b.line);
        self.retract(&w, b)?;
        Ok(if self.m_after(&w, &b.toks[skip..], b.line)? {
            Flow::End
        } else {
            Flow::Next
        })
    }

    // ---- words ----

    fn words(&mut self, toks: &[Tok], line: u32) -> Res<Words> {
        let mut w = Words::default();
        let mut i = 0;
        while i < toks.len() {
            let tok = &toks[i];
            let (name, val) = lexer::word(tok)?;
            let axis = |n: &str| "XYZABC".find(n);
            match name {
                "X" | "Y" | "Z" | "A" | "B" | "C" | "IX" | "IY" | "IZ" | "IA" | "IB" | "IC" => {
                    let inc = name.len() == 2;
                    let k = axis(&name[name.len() - 1..]).unwrap_or(0);
                    // (`L X+10 X+20` took the second: the control refuses it.)
                    if w.axes[k].is_some() {
                        return Err(Fault::at(
                            tok,
                            PathErrorKind::Semantic,
                            format!(
                                "{} is programmed twice in the block",
                                &name[name.len() - 1..]
                            ),
                            "each axis once",
                        ));
                    }
                    let mut v = self.value(val, tok)?;
                    if k < 3 {
                        v *= self.scale;
                    } else if self.spat.is_none() {
                        // A rotary axis turned: a tool axis held from a plane reset with STAY
                        // is the machine's again.
                        self.emit(line, Canon::MachineAxis);
                    }
                    w.axes[k] = Some((v, inc));
                }
                "U" | "V" | "W" | "IU" | "IV" | "IW" => {
                    return Err(Fault::at(
                        tok,
                        PathErrorKind::Unsupported,
                        "parallel axes U V W are not read",
                        "X Y Z A B C",
                    ))
                }
                "R" if tok.text == "R0" => {}
                "RL" | "RR" => {
                    return Err(Fault::at(
                        tok,
                        PathErrorKind::Unsupported,
                        "radius compensation (RL/RR) is not read: swarf reads programs of the \
                         tool path (R0), as CAM systems write them",
                        "R0",
                    ))
                }
                "R" if matches!(val, Val::Sign(_)) => {
                    return Err(Fault::at(
                        tok,
                        PathErrorKind::Unsupported,
                        "paraxial radius compensation (R+/R-) is not read",
                        "R0",
                    ))
                }
                // The F after M128 is the feed of its compensating moves, not the path's.
                "F" if i > 0 && toks[i - 1].text == "M128" => {}
                "F" | "FU" | "FZ" | "FMAX" | "FAUTO" => {
                    let next = toks.get(i + 1).map(|t| t.text.as_str());
                    w.feed = Some(match (name, val) {
                        ("FMAX", Val::None) => Feed::Rapid,
                        ("FAUTO", Val::None) => Feed::Auto,
                        ("F", Val::None) if next == Some("MAX") => {
                            i += 1;
                            Feed::Rapid
                        }
                        ("F", Val::None) if next == Some("AUTO") => {
                            i += 1;
                            Feed::Auto
                        }
                        ("F", v) => Feed::Value(self.value(v, tok)?.abs() * self.feed_scale),
                        ("FU", v) => Feed::PerRev(self.value(v, tok)?.abs() * self.scale),
                        ("FZ", _) => {
                            return Err(Fault::at(
                                tok,
                                PathErrorKind::Unsupported,
                                "feed per tooth (FZ) needs the tool's number of teeth, which \
                                 the program does not give",
                                "F (per minute) or FU (per revolution)",
                            ))
                        }
                        _ => {
                            return Err(Fault::at(
                                tok,
                                PathErrorKind::Syntax,
                                "bad feed word",
                                "F<feed>, FMAX, FAUTO or FU<feed>",
                            ))
                        }
                    });
                }
                "M" => {
                    let m = self.value(val, tok)?;
                    if m < 0.0 || m.fract() != 0.0 || m > 100_000.0 {
                        return Err(Fault::at(
                            tok,
                            PathErrorKind::Syntax,
                            "bad M function number",
                            "M and a whole number",
                        ));
                    }
                    w.m.push((m as u32, i));
                    // The parameters of M functions that take some (M120 LA, M124 T, M118's
                    // handwheel limits, M138's axes …) stand after them: theirs, not the block's.
                    let params: &[&str] = match m as u32 {
                        120 => &["LA"],
                        112 | 124 => &["T", "R", "A"],
                        118 => &["X", "Y", "Z", "A", "B", "C"],
                        94 | 138 => &["A", "B", "C"],
                        _ => &[],
                    };
                    while let Some(t) = toks.get(i + 1) {
                        match lexer::word(t) {
                            Ok((n, _)) if params.contains(&n) => i += 1,
                            _ => break,
                        }
                    }
                }
                "MB" => {
                    let next = toks.get(i + 1).map(|t| t.text.as_str());
                    match (val, next) {
                        (Val::None, Some("MAX")) => {
                            w.mb_max = true;
                            i += 1;
                        }
                        (Val::None, Some(n)) if lexer::number(n).is_some() => {
                            w.named
                                .push(("MB", lexer::number(n).unwrap_or(0.0) * self.scale));
                            i += 1;
                        }
                        (v, _) => {
                            let v = self.value(v, tok)? * self.scale;
                            w.named.push(("MB", v));
                        }
                    }
                }
                _ => match NAMED.iter().find(|n| **n == name) {
                    Some(n) => {
                        let v = match val {
                            Val::Sign(s) => s,
                            v => self.value(v, tok)?,
                        };
                        let v = if matches!(*n, "R" | "PR" | "IPR" | "MB") {
                            v * self.scale
                        } else {
                            v
                        };
                        w.named.push((n, v));
                    }
                    None => {
                        return Err(Fault::at(
                            tok,
                            PathErrorKind::Syntax,
                            format!("unexpected word {}", tok.text),
                            "coordinates, R0, F, M functions",
                        ))
                    }
                },
            }
            i += 1;
        }
        let _ = line;
        Ok(w)
    }

    // ---- frames ----

    fn machine_of(&self, p: [f64; 3]) -> [f64; 3] {
        self.frame.machine_of(p)
    }

    fn program_of(&self, m: [f64; 3]) -> [f64; 3] {
        self.frame.program_of(m)
    }

    /// Changes the frame with `f`, keeping the machine position (and the pole's place on
    /// the part); tells the sink of the offsets when `offsets`.
    fn change_frame(&mut self, line: u32, offsets: bool, f: impl FnOnce(&mut Self)) {
        let m = self.machine_of([self.c.pos[0], self.c.pos[1], self.c.pos[2]]);
        let (i1, i2, _) = self.c.plane.axes();
        let pole = self.pole.map(|p| {
            let mut q = [self.c.pos[0], self.c.pos[1], self.c.pos[2]];
            (q[i1], q[i2]) = (p[0], p[1]);
            self.machine_of(q)
        });
        f(self);
        let p = self.program_of(m);
        self.c.pos[..3].copy_from_slice(&p);
        if let Some(pm) = pole {
            let q = self.program_of(pm);
            self.pole = Some([q[i1], q[i2]]);
        }
        self.c.tangent = None;
        if offsets {
            self.emit_frame(line);
        }
    }

    fn emit_frame(&mut self, line: u32) {
        for e in self.frame.events() {
            self.emit(line, e);
        }
    }

    // ---- motion ----

    fn pole(&mut self, b: &Block) -> Res<()> {
        let w = self.words(&b.toks[1..], b.line)?;
        let (i1, i2, _) = self.c.plane.axes();
        let mut p = [self.c.pos[i1], self.c.pos[i2]];
        for (k, a) in w.axes.iter().enumerate() {
            let Some((v, inc)) = *a else { continue };
            let slot = if k == i1 {
                0
            } else if k == i2 {
                1
            } else {
                return Err(Fault::at(
                    &b.toks[0],
                    PathErrorKind::Semantic,
                    "CC takes the two axes of the working plane",
                    "the plane's axes",
                ));
            };
            p[slot] = if inc {
                [self.c.pos[i1], self.c.pos[i2]][slot] + v
            } else {
                v
            };
        }
        self.pole = Some(p);
        Ok(())
    }

    /// The target of a block's axis words.
    fn target(&self, w: &Words) -> [f64; 6] {
        let mut t = self.c.pos;
        for (k, a) in w.axes.iter().enumerate() {
            if let Some((v, inc)) = *a {
                t[k] = if inc {
                    self.c.pos[k] + v
                } else if k >= 3 && self.shortest {
                    // Under M126 a rotary axis turns at most half a turn, either way.
                    self.c.pos[k] + (v - self.c.pos[k] + 180.0).rem_euclid(360.0) - 180.0
                } else {
                    v
                };
            }
        }
        t
    }

    /// Says the feed to the sink before a feed move; errors when there is none.
    fn feed_for(&mut self, w: &Words, head: &Tok) -> Res<bool> {
        if self.take_feed(w, head)? {
            return Ok(true);
        }
        self.tell_feed(head)?;
        Ok(false)
    }

    /// Takes the block's feed word as the modal feed; true for `FMAX`.
    fn take_feed(&mut self, w: &Words, head: &Tok) -> Res<bool> {
        match w.feed {
            Some(Feed::Rapid) => return Ok(true),
            // Under M136, F is in µm per revolution.
            Some(Feed::Value(f)) if self.m136 => {
                self.feed = Some(f / 1000.0);
                self.feed_mode = FeedMode::PerRevolution;
            }
            Some(Feed::Value(f)) => {
                self.feed = Some(f);
                self.feed_mode = FeedMode::PerMinute;
            }
            Some(Feed::PerRev(f)) => {
                self.feed = Some(f);
                self.feed_mode = FeedMode::PerRevolution;
            }
            Some(Feed::Auto) => match self.tool_feed {
                Some(f) => {
                    self.feed = Some(f);
                    self.feed_mode = FeedMode::PerMinute;
                }
                None => {
                    return Err(Fault::at(
                        head,
                        PathErrorKind::Semantic,
                        "FAUTO without a feed in the TOOL CALL",
                        "F in the TOOL CALL",
                    ))
                }
            },
            None => {}
        }
        Ok(false)
    }

    /// Tells the sink the feed a feed move runs at; an error when there is none yet.
    fn tell_feed(&mut self, head: &Tok) -> Res<()> {
        let Some(f) = self.feed else {
            return Err(Fault::at(
                head,
                PathErrorKind::Semantic,
                "a feed move before any feed rate",
                "F<feed> or FMAX",
            ));
        };
        let events: Vec<Canon<'static>> = self.c.feed(self.feed_mode, f).collect();
        for e in events {
            self.emit(head.line, e);
        }
        Ok(())
    }

    fn motion(&mut self, b: &Block) -> Res<Flow> {
        let head = &b.toks[0];
        let w = self.words(&b.toks[1..], b.line)?;
        self.m_before(&w, b.line);
        if matches!(head.text.as_str(), "L" | "LN") && w.axes.iter().all(Option::is_none) {
            // A block of M functions (and maybe a feed) written as a line: no motion.
            self.take_feed(&w, head)?;
            return self.after_motion(&w, b);
        }
        let rapid = self.feed_for(&w, head)?;
        let (i1, i2, n) = self.c.plane.axes();
        let start = self.c.pos;
        match head.text.as_str() {
            "L" | "LN" => {
                let mut end = self.target(&w);
                if w.has_m(91) || w.has_m(92) {
                    end = self.machine_target(&w, b)?;
                }
                if head.text == "LN" {
                    self.tool_vector(&w, b.line)?;
                }
                self.spatial_axis(&w, &mut end, b.line);
                self.line_to(b.line, end, rapid);
            }
            "LP" => {
                let pole = self.need_pole(head)?;
                let (r0, a0) = polar(pole, [start[i1], start[i2]]);
                let r = match (w.get("PR"), w.get("IPR")) {
                    (Some(r), _) => r,
                    (None, Some(d)) => r0 + d,
                    _ => r0,
                };
                let a = match (w.get("PA"), w.get("IPA")) {
                    (Some(a), _) => a,
                    (None, Some(d)) => a0 + d,
                    _ => a0,
                };
                let mut end = self.target(&w);
                let (s, c) = a.to_radians().sin_cos();
                end[i1] = pole[0] + r * c;
                end[i2] = pole[1] + r * s;
                self.line_to(b.line, end, rapid);
            }
            "C" | "CR" | "CT" | "CP" => {
                if rapid {
                    // (FMAX on an arc moves it at rapid speed; swarf keeps the arc.)
                    self.warn(
                        b.line,
                        head.col,
                        "an arc at FMAX is read at the last feed".into(),
                    );
                    self.feed_for(&Words::default(), head)?;
                }
                let mut end = self.target(&w);
                let dr = w.get("DR").map(f64::signum);
                let (center, ccw, turns) = match head.text.as_str() {
                    "C" => {
                        let c = self.need_pole(head)?;
                        let ccw = self.direction(dr, head)?;
                        let r0 = dist([start[i1], start[i2]], c);
                        let r1 = dist([end[i1], end[i2]], c);
                        self.check_radius(r0, r1, head)?;
                        (c, ccw, 1)
                    }
                    "CR" => {
                        let Some(r) = w.get("R") else {
                            return Err(Fault::at(
                                head,
                                PathErrorKind::Syntax,
                                "CR without a radius",
                                "R+<radius> (≤ 180°) or R-<radius> (> 180°)",
                            ));
                        };
                        let ccw = self.direction(dr, head)?;
                        let tol = self.arc_tolerance(r.abs());
                        let c = cr_centre([start[i1], start[i2]], [end[i1], end[i2]], r, ccw, tol)
                            .ok_or_else(|| {
                                Fault::at(
                                    head,
                                    PathErrorKind::Semantic,
                                    format!(
                                        "the radius {} mm is too small for the arc's chord",
                                        r.abs()
                                    ),
                                    "a radius at least half the chord",
                                )
                            })?;
                        (c, ccw, 1)
                    }
                    "CT" => match self.c.tangent_arc(end) {
                        Some(Some((c, ccw))) => (c, ccw, 1),
                        Some(None) => {
                            self.line_to(b.line, end, false);
                            return self.after_motion(&w, b);
                        }
                        None => {
                            return Err(Fault::at(
                                head,
                                PathErrorKind::Semantic,
                                "CT without a contour element before it to be tangent to",
                                "a line or arc in the working plane before CT",
                            ))
                        }
                    },
                    _ => {
                        // CP: about the pole at the current radius.
                        let pole = self.need_pole(head)?;
                        let (r0, a0) = polar(pole, [start[i1], start[i2]]);
                        let (a1, sweep) = match (w.get("PA"), w.get("IPA")) {
                            (_, Some(d)) => (a0 + d, Some(d)),
                            (Some(a), None) => (a, None),
                            (None, None) => {
                                return Err(Fault::at(
                                    head,
                                    PathErrorKind::Syntax,
                                    "CP without an angle",
                                    "PA<angle> or IPA<angle>",
                                ))
                            }
                        };
                        let ccw = match (dr, sweep) {
                            (Some(d), _) => d > 0.0,
                            (None, Some(s)) => s > 0.0,
                            (None, None) => self.direction(None, head)?,
                        };
                        if dr.is_some() {
                            self.dr = dr;
                        }
                        let (s, c) = a1.to_radians().sin_cos();
                        end[i1] = pole[0] + r0 * c;
                        end[i2] = pole[1] + r0 * s;
                        let turns = match sweep {
                            Some(s) if s.abs() > 360.0 * (1.0 + 1e-12) => {
                                let t = (s.abs() / 360.0 - 1e-9).ceil();
                                if t > self.opts.max_repeat as f64 {
                                    return Err(Fault::at(
                                        head,
                                        PathErrorKind::Limit,
                                        "too many turns",
                                        "fewer turns",
                                    ));
                                }
                                t as i32
                            }
                            _ => 1,
                        };
                        (pole, ccw, turns)
                    }
                };
                self.arc_to(b.line, end, center, ccw, turns);
            }
            _ => unreachable!("motion called for a motion block"),
        }
        let _ = n;
        self.after_motion(&w, b)
    }

    fn after_motion(&mut self, w: &Words, b: &Block) -> Res<Flow> {
        let toks = &b.toks[1..];
        let (i1, i2, _) = self.c.plane.axes();
        let moved_in_plane = w.axes[i1].is_some() || w.axes[i2].is_some();
        if self.modal_call && moved_in_plane && !w.has_m(99) {
            self.cycle_call(&b.toks[0], None)?;
        }
        // M140 acts at the end of its block.
        self.retract(w, b)?;
        Ok(if self.m_after(w, toks, b.line)? {
            Flow::End
        } else {
            Flow::Next
        })
    }

    fn need_pole(&self, head: &Tok) -> Res<[f64; 2]> {
        self.pole.ok_or_else(|| {
            Fault::at(
                head,
                PathErrorKind::Semantic,
                "no circle centre or pole (CC) defined",
                "a CC block before it",
            )
        })
    }

    fn direction(&mut self, dr: Option<f64>, head: &Tok) -> Res<bool> {
        if let Some(d) = dr {
            self.dr = Some(d);
        }
        match self.dr {
            Some(d) => Ok(d > 0.0),
            None => Err(Fault::at(
                head,
                PathErrorKind::Syntax,
                "an arc without a direction",
                "DR+ (counter-clockwise) or DR-",
            )),
        }
    }

    fn arc_tolerance(&self, r: f64) -> f64 {
        reader_core::arc_tolerance(self.opts, self.scale, r)
    }

    fn check_radius(&self, r0: f64, r1: f64, head: &Tok) -> Res<()> {
        if (r0 - r1).abs() > self.arc_tolerance(r0.max(r1)) {
            return Err(Fault::at(
                head,
                PathErrorKind::Semantic,
                format!(
                    "the arc's end is not on its circle: {r0:.4} mm from the centre at the \
                     start, {r1:.4} mm at the end"
                ),
                "an end point on the circle about CC",
            ));
        }
        Ok(())
    }

    fn line_to(&mut self, line: u32, end: [f64; 6], rapid: bool) {
        let e = self.c.line(end, rapid);
        self.emit(line, e);
    }

    fn arc_to(&mut self, line: u32, end: [f64; 6], center: [f64; 2], ccw: bool, turns: i32) {
        let e = self.c.arc(end, center, ccw, turns);
        self.emit(line, e);
    }

    /// `M91`/`M92`: the block's coordinates are machine coordinates (zero at the home).
    fn machine_target(&mut self, w: &Words, b: &Block) -> Res<[f64; 6]> {
        if self.opts.home.is_none() {
            self.warn_once(
                "home",
                b.line,
                b.code_col,
                "M91/M92 machine coordinates are taken from the machine's home, which is not \
                 given (--home X,Y,Z): they are read from the work origin"
                    .into(),
            );
        }
        let home = self.opts.home.unwrap_or([0.0; 3]);
        let mut m = self.machine_of([self.c.pos[0], self.c.pos[1], self.c.pos[2]]);
        let mut out = self.c.pos;
        for (k, a) in w.axes.iter().enumerate() {
            let Some((v, inc)) = *a else { continue };
            if k < 3 {
                m[k] = if inc { m[k] + v } else { home[k] + v };
            } else {
                out[k] = if inc { self.c.pos[k] + v } else { v };
            }
        }
        let p = self.program_of(m);
        out[..3].copy_from_slice(&p);
        Ok(out)
    }

    /// Under `FUNCTION TCPM … AXIS SPAT` a block's A B C are the tool's spatial angles (about
    /// the fixed X, then Y, then Z, as `PLANE SPATIAL`'s): they turn the tool axis, and the
    /// rotary axes, which the control then chooses, are not the words' values.
    fn spatial_axis(&mut self, w: &Words, end: &mut [f64; 6], line: u32) {
        let Some(mut angles) = self.spat else { return };
        if w.axes[3..].iter().all(Option::is_none) {
            return;
        }
        for (a, word) in angles.iter_mut().zip(&w.axes[3..]) {
            if let Some((v, inc)) = *word {
                *a = if inc { *a + v } else { v };
            }
        }
        self.spat = Some(angles);
        end[3..].copy_from_slice(&self.c.pos[3..]);
        let r = crate::part_frame::spatial(angles[0], angles[1], angles[2]);
        let t = self.machine_direction([r[0][2], r[1][2], r[2][2]]);
        self.emit(line, Canon::ToolAxis(t));
    }

    /// `LN … TX TY TZ`: the tool axis, turned as the program frame is.
    fn tool_vector(&mut self, w: &Words, line: u32) -> Res<()> {
        let t = [w.get("TX"), w.get("TY"), w.get("TZ")];
        if t.iter().all(Option::is_none) {
            return Ok(());
        }
        let t = self.machine_direction(t.map(|v| v.unwrap_or(0.0)));
        self.emit(line, Canon::ToolAxis(t));
        Ok(())
    }

    /// `M140 MB …` (and the `MB` of a `PLANE` function): retract along the tool axis.
    fn retract(&mut self, w: &Words, b: &Block) -> Res<()> {
        if !(w.has_m(140) || b.toks[0].text == "PLANE") {
            return Ok(());
        }
        // Along the tool axis: the working plane's normal, turned as the program frame is.
        let (_, _, n) = self.c.plane.axes();
        let dist = if w.mb_max {
            let mut axis = [0.0; 3];
            axis[n] = 1.0;
            let dir = self.machine_direction(axis);
            match self.opts.home {
                Some(h) if dir[n] > 0.05 => {
                    let m = self.machine_of([self.c.pos[0], self.c.pos[1], self.c.pos[2]]);
                    ((h[n] - m[n]) / dir[n]).max(0.0)
                }
                _ => {
                    self.warn_once(
                        "mbmax",
                        b.line,
                        b.code_col,
                        "MB MAX retracts 100 mm along the tool axis: the machine's travel is \
                         not known (give its home with --home for a retract to the home's Z)"
                            .into(),
                    );
                    100.0
                }
            }
        } else {
            match w.get("MB") {
                Some(d) => d,
                None => return Ok(()),
            }
        };
        if dist != 0.0 {
            let mut end = self.c.pos;
            end[n] += dist;
            self.line_to(b.line, end, true);
        }
        Ok(())
    }

    fn machine_direction(&self, d: [f64; 3]) -> [f64; 3] {
        self.frame.direction(d)
    }

    // ---- parameters, labels, calls ----

    /// `Q1 = formula` (also the `Q200=+2` words of a cycle definition).
    fn assign(&mut self, code: &str, line: u32, col: u32) -> Res<()> {
        let Some(eq) = code.find('=') else {
            return Err(Fault {
                line,
                col,
                kind: PathErrorKind::Syntax,
                message: "a Q parameter without an assignment".into(),
                found: code.to_string(),
                expected: "Q<n> = <formula>".into(),
            });
        };
        let lhs = code[..eq].trim();
        let Some(q) = lexer::qref(lhs).filter(|q| !q.negate) else {
            return Err(Fault {
                line,
                col,
                kind: PathErrorKind::Syntax,
                message: "bad parameter name".into(),
                found: lhs.to_string(),
                expected: "Q<n>, QL<n> or QR<n>".into(),
            });
        };
        let rhs = &code[eq + 1..];
        let v = crate::formula::eval(rhs, &|r| self.qv(r)).map_err(|e| Fault {
            line,
            col: col + (eq + 1 + e.at) as u32,
            kind: if e.message.starts_with("unexpected") || e.message.starts_with("expected") {
                PathErrorKind::Syntax
            } else {
                PathErrorKind::Semantic
            },
            message: e.message,
            found: rhs.trim().to_string(),
            expected: e.expected.into(),
        })?;
        self.q.insert((q.kind, q.index), v);
        Ok(())
    }

    fn function(&mut self, b: &Block) -> Res<Flow> {
        // `FN 9: …`: the number, with or without the colon joined to it.
        let head = &b.toks[0];
        let Some(num_tok) = b.toks.get(1) else {
            return Err(Fault::at(
                head,
                PathErrorKind::Syntax,
                "FN without a number",
                "FN <n>:",
            ));
        };
        let num: u32 =
            num_tok.text.trim_end_matches(':').parse().map_err(|_| {
                Fault::at(num_tok, PathErrorKind::Syntax, "bad FN number", "FN <n>:")
            })?;
        let colon = b.code.find(':').map_or(b.code.len(), |c| c + 1);
        let rest = &b.code[colon..];
        let rest_col = b.code_col + colon as u32;
        match num {
            0..=8 | 13 => {
                self.assign(rest, b.line, rest_col)?;
                Ok(Flow::Next)
            }
            9..=12 => self.conditional(b, num, rest, rest_col),
            14 => Err(Fault::at(
                head,
                PathErrorKind::Semantic,
                format!("the program stops with an error ({})", rest.trim()),
                "a program that runs without FN 14",
            )),
            18 => {
                // SYSREAD: what the control would report is not known; the parameter reads 0.
                if let Some(eq) = rest.find('=') {
                    if let Some(q) = lexer::qref(rest[..eq].trim()) {
                        self.q.insert((q.kind, q.index), 0.0);
                    }
                }
                self.warn(
                    b.line,
                    head.col,
                    "FN 18 (reading the control's data) is not modelled: its parameter reads 0"
                        .into(),
                );
                Ok(Flow::Next)
            }
            _ => {
                self.warn(
                    b.line,
                    head.col,
                    format!("FN {num} is not read (it moves nothing)"),
                );
                Ok(Flow::Next)
            }
        }
    }

    /// `FN 9: IF +Q1 EQU +Q2 GOTO LBL 5` (10 `NE`, 11 `GT`, 12 `LT`).
    fn conditional(&mut self, b: &Block, num: u32, rest: &str, col: u32) -> Res<Flow> {
        let bad = |what: &str| Fault {
            line: b.line,
            col,
            kind: PathErrorKind::Syntax,
            message: format!("bad conditional jump: {what}"),
            found: rest.trim().to_string(),
            expected: "IF <value> EQU|NE|GT|LT <value> GOTO LBL <label>".into(),
        };
        let body = rest.trim();
        let body = body.strip_prefix("IF").ok_or_else(|| bad("no IF"))?;
        let goto = body.find("GOTO").ok_or_else(|| bad("no GOTO"))?;
        let cond = &body[..goto];
        let target = body[goto + 4..].trim();
        let target = target
            .strip_prefix("LBL")
            .ok_or_else(|| bad("no LBL"))?
            .trim();
        let op = match num {
            9 => "EQU",
            10 => "NE",
            11 => "GT",
            _ => "LT",
        };
        let at = cond
            .find(op)
            .ok_or_else(|| bad("the comparison does not match the FN"))?;
        let q = |s: &str| crate::formula::eval(s, &|r| self.qv(r)).map_err(|_| bad("bad operand"));
        let (a, c) = (q(&cond[..at])?, q(&cond[at + op.len()..])?);
        let yes = match num {
            9 => a == c,
            10 => a != c,
            11 => a > c,
            _ => a < c,
        };
        if !yes {
            return Ok(Flow::Next);
        }
        let key = label_key(target);
        let Some(&to) = self.sources[self.cur].labels.get(&key) else {
            let at = b.toks.last().unwrap_or(&b.toks[0]);
            return Err(Fault::at(
                at,
                PathErrorKind::Semantic,
                format!("label {target} is not defined"),
                "a label defined with LBL",
            ));
        };
        self.jump(&b.toks[0])?;
        Ok(Flow::Jump(self.cur, to + 1))
    }

    fn call(&mut self, b: &Block, index: usize) -> Res<Flow> {
        let head = &b.toks[0];
        match b.toks.get(1).map(|t| t.text.as_str()) {
            Some("LBL") => {
                let Some(lt) = b.toks.get(2) else {
                    return Err(Fault::at(
                        head,
                        PathErrorKind::Syntax,
                        "CALL LBL without a label",
                        "CALL LBL <label>",
                    ));
                };
                let key = label_key(&lt.text);
                let Some(&to) = self.sources[self.cur].labels.get(&key) else {
                    return Err(Fault::at(
                        lt,
                        PathErrorKind::Semantic,
                        format!("label {} is not defined", lt.text),
                        "a label defined with LBL",
                    ));
                };
                // `REP 2`, `REP2`, or `REP 2/2` as the control shows it while running.
                let (rt, count, next) = match b.toks.get(3) {
                    Some(t) if t.text == "REP" => {
                        let rt = b.toks.get(4).ok_or_else(|| {
                            Fault::at(t, PathErrorKind::Syntax, "REP without a count", "REP <n>")
                        })?;
                        (Some(rt), rt.text.as_str(), 5)
                    }
                    Some(t) if t.text.starts_with("REP") => (Some(t), &t.text[3..], 4),
                    Some(t) => {
                        return Err(Fault::at(
                            t,
                            PathErrorKind::Syntax,
                            "unexpected word after CALL LBL",
                            "REP <n> or the end of the block",
                        ))
                    }
                    None => (None, "", 3),
                };
                if let Some(t) = b.toks.get(next) {
                    return Err(Fault::at(
                        t,
                        PathErrorKind::Syntax,
                        "unexpected word after the repeat count",
                        "the end of the block",
                    ));
                }
                let rep = match rt {
                    Some(rt) => {
                        let n = count.split('/').next().unwrap_or("");
                        let n = lexer::number(n)
                            .or_else(|| lexer::qref(n).map(|q| self.qv(q)))
                            .filter(|n| *n >= 0.0 && n.fract() == 0.0)
                            .ok_or_else(|| {
                                Fault::at(
                                    rt,
                                    PathErrorKind::Syntax,
                                    "bad repeat count",
                                    "a whole number",
                                )
                            })?;
                        if n > self.opts.max_repeat as f64 {
                            return Err(Fault::at(
                                rt,
                                PathErrorKind::Limit,
                                format!("more than {} repeats", self.opts.max_repeat),
                                "fewer repeats",
                            ));
                        }
                        Some(n as u64)
                    }
                    None => None,
                };
                if to < index {
                    // A program section repeat: back to the label `rep` times.
                    let Some(rep) = rep else {
                        // A call of a label above the call: a subprogram call all the same.
                        return self.subprogram_call(head, to, index, 0);
                    };
                    let k = (self.cur, index);
                    let left = *self.repeats.entry(k).or_insert(rep);
                    if left == 0 {
                        self.repeats.remove(&k);
                        return Ok(Flow::Next);
                    }
                    self.repeats.insert(k, left - 1);
                    self.jump(head)?;
                    return Ok(Flow::Jump(self.cur, to + 1));
                }
                self.subprogram_call(head, to, index, rep.unwrap_or(0))
            }
            Some("PGM") => self.program_call(b, index),
            _ => Err(Fault::at(
                head,
                PathErrorKind::Syntax,
                "bad CALL",
                "CALL LBL <label> or CALL PGM <name>",
            )),
        }
    }

    fn subprogram_call(&mut self, head: &Tok, label: usize, index: usize, rep: u64) -> Res<Flow> {
        self.push_call(head)?;
        self.stack.push(Ret::Lbl {
            back: (self.cur, index + 1),
            again: label + 1,
            left: rep,
        });
        self.jump(head)?;
        Ok(Flow::Jump(self.cur, label + 1))
    }

    fn push_call(&self, head: &Tok) -> Res<()> {
        if self.stack.len() >= self.opts.max_call_depth {
            return Err(Fault::at(
                head,
                PathErrorKind::Limit,
                format!("calls nested deeper than {}", self.opts.max_call_depth),
                "shallower calls",
            ));
        }
        Ok(())
    }

    /// `LBL 0`: the end of a subprogram.
    fn subprogram_end(&mut self, head: &Tok) -> Res<Flow> {
        match self.stack.last_mut() {
            Some(Ret::Lbl { again, left, .. }) if *left > 0 => {
                *left -= 1;
                let again = *again;
                self.jump(head)?;
                Ok(Flow::Jump(self.cur, again))
            }
            Some(Ret::Lbl { back, .. }) => {
                let back = *back;
                self.stack.pop();
                Ok(Flow::Jump(back.0, back.1))
            }
            // (A subprogram's end met in the main flow, after M30, or in a called program.)
            _ => Ok(Flow::Next),
        }
    }

    fn program_call(&mut self, b: &Block, index: usize) -> Res<Flow> {
        let head = &b.toks[0];
        let Some(nt) = b.toks.get(2) else {
            return Err(Fault::at(
                head,
                PathErrorKind::Syntax,
                "CALL PGM without a name",
                "CALL PGM <name>",
            ));
        };
        self.push_call(head)?;
        // The name as written (case kept for the file system): from the original line.
        let name = nt.text.trim_matches('"');
        let leaf = name
            .rsplit(['\\', '/', ':'])
            .next()
            .unwrap_or(name)
            .to_string();
        let path = self.find_program(&leaf).ok_or_else(|| {
            Fault::at(
                nt,
                PathErrorKind::Io,
                format!("cannot find the called program {leaf} beside the program or in the subroutine path"),
                "a program file name.h",
            )
        })?;
        let shown = path.display().to_string();
        let src = match self.sources.iter().position(|s| s.name == shown) {
            Some(i) => i,
            None => {
                let text = crate::load::read_text(&path).map_err(|e| {
                    Fault::at(nt, PathErrorKind::Io, e.message, "a readable program file")
                })?;
                // (An error in the called file names that file.)
                let read = lexer::blocks(&text).and_then(|b| Self::source(shown.clone(), b));
                let s = read.inspect_err(|_| self.error_file = Some(shown))?;
                self.sources.push(s);
                self.sources.len() - 1
            }
        };
        self.stack.push(Ret::Pgm {
            back: (self.cur, index + 1),
        });
        self.jump(head)?;
        Ok(Flow::Jump(src, 0))
    }

    /// The called program's file: `leaf` or `leaf.h` beside the program or in the subroutine
    /// path, its case ignored.
    fn find_program(&self, leaf: &str) -> Option<PathBuf> {
        reader_core::find_program(
            self.file,
            self.opts,
            &[leaf.to_string(), format!("{leaf}.h")],
        )
    }
}

/// A label's key: a number without its leading zeros, or a name without its quotes.
fn label_key(s: &str) -> String {
    let s = s.trim_matches('"');
    match s.parse::<u64>() {
        Ok(n) => n.to_string(),
        Err(_) => s.to_string(),
    }
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// Radius and angle (degrees) of `p` about `pole`.
fn polar(pole: [f64; 2], p: [f64; 2]) -> (f64, f64) {
    let d = [p[0] - pole[0], p[1] - pole[1]];
    (d[0].hypot(d[1]), d[1].atan2(d[0]).to_degrees())
}

/// The centre of the arc of radius `|r|` from `a` to `b` (`r > 0`: at most a half circle,
/// `r < 0`: more), counter-clockwise when `ccw`.
/// A chord longer than the diameter by at most `tol` (posted coordinates' rounding) gives the
/// half circle.
pub(crate) fn cr_centre(a: [f64; 2], b: [f64; 2], r: f64, ccw: bool, tol: f64) -> Option<[f64; 2]> {
    let d = [b[0] - a[0], b[1] - a[1]];
    let l = d[0].hypot(d[1]);
    if l == 0.0 || r == 0.0 {
        return None;
    }
    let half = l / 2.0;
    let ra = r.abs();
    if half > ra + tol {
        return None;
    }
    let h = (ra * ra - half * half).max(0.0).sqrt();
    let left = [-d[1] / l, d[0] / l];
    // Counter-clockwise and short: the centre is on the left of the chord.
    let s = if ccw == (r > 0.0) { 1.0 } else { -1.0 };
    let m = [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0];
    Some([m[0] + s * h * left[0], m[1] + s * h * left[1]])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cr_centres_follow_the_sign_rules() {
        // A quarter circle of radius 10 about the origin from (10, 0) to (0, 10).
        let c = cr_centre([10.0, 0.0], [0.0, 10.0], 10.0, true, 0.0).unwrap();
        assert!(c[0].abs() < 1e-12 && c[1].abs() < 1e-12);
        // The same ends clockwise the short way: centre at (10, 10).
        let c = cr_centre([10.0, 0.0], [0.0, 10.0], 10.0, false, 0.0).unwrap();
        assert!((c[0] - 10.0).abs() < 1e-12 && (c[1] - 10.0).abs() < 1e-12);
        // Counter-clockwise the long way: (10, 10).
        let c = cr_centre([10.0, 0.0], [0.0, 10.0], -10.0, true, 0.0).unwrap();
        assert!((c[0] - 10.0).abs() < 1e-12 && (c[1] - 10.0).abs() < 1e-12);
        assert!(cr_centre([0.0, 0.0], [30.0, 0.0], 10.0, true, 0.01).is_none());
        // Within the tolerance: the half circle.
        let c = cr_centre([0.0, 0.0], [10.0004, 0.0], 5.0, true, 0.01).unwrap();
        assert!((c[0] - 5.0002).abs() < 1e-12 && c[1] == 0.0);
    }

    #[test]
    fn detection_needs_begin_pgm_first() {
        assert!(is_heidenhain("0 BEGIN PGM X MM\n1 END PGM X MM\n"));
        assert!(is_heidenhain("\n  begin pgm x mm"));
        assert!(!is_heidenhain("G0 X1\n; BEGIN PGM"));
    }
}
