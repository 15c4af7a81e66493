//! Siemens Sinumerik 840D programs (`.mpf` main programs, `.spf` subprograms), read into the
//! same [`Canon`] events as G-code — the other language of European 5-axis machines and the
//! CAM posts written for them.
//!
//! # What is read
//! * Blocks: `N` numbers, labels (`START:`), `;` comments, `MSG("…")` (a message), `/` block
//!   delete (as the G-code reader's option says), words with or without spaces (`G1X10`),
//!   `=` values with expressions (`X=R1+2`), `IC()`/`AC()` per coordinate, `DC()`/`ACP()`/
//!   `ACN()` for rotary axes.
//! * Motion: `G0 G1 G2 G3` (centre `I J K`, incremental unless `=AC()`; radius `CR=`, negative
//!   for more than a half circle; `TURN=` extra turns; helices), `CIP` (arc through `I1= J1=
//!   K1=`), `CT` (tangent arc); `G17 G18 G19`, `G90 G91`, `G70 G71 G700 G710` (inch lengths
//!   × 25.4), `G93 G94 G95`, `G4 F…` (seconds) / `G4 S…` (revolutions), `G53 G153 SUPA`
//!   (machine coordinates in the block, zero at `--home`), `G500 G54–G57 G505–G599` (settable
//!   offsets, which the program does not give: zero), `G40`.
//! * Tools: `T1`, `T="name"` (numbered in order of first use, a warning says which number),
//!   `M6` (without any `M6` in the program, `T` changes the tool), `D`, `S`, `M3 M4 M5`.
//! * Frames: `TRANS`/`ATRANS X… Y… Z…`, `ROT`/`AROT RPL=…` or `Z…` (rotation in the XY
//!   plane), `CYCLE800` in its axis-by-axis modes (a tilted plane, the tool turned normal to
//!   it; `CYCLE800()` resets).
//! * 5-axis: `TRAORI`/`TRAFOOF` (tool-tip positions, as a `-tcp` machine reads them), the tool
//!   vector `A3= B3= C3=`.
//! * Cycles: `CYCLE81`–`CYCLE85` drilling, counter-boring, deep-hole drilling, rigid tapping
//!   and boring, at the tool's position or under `MCALL` at every position after it;
//!   `CYCLE832` (path smoothing) noted.
//! * Parameters and flow: `R` parameters, `DEF` variables, expressions (see
//!   [`crate::formula`]), `GOTOF`/`GOTOB`/`GOTO` to labels or block numbers, `IF … GOTOF`,
//!   `IF`/`ELSE`/`ENDIF`, `WHILE`/`ENDWHILE`, `FOR`/`ENDFOR`, `LOOP`/`ENDLOOP`,
//!   `REPEAT`/`UNTIL`, subprograms called by name or `L` number (`P` repeats) from files beside
//!   the program or on the subroutine path (`M17`/`RET` return), `M2 M30`.
//!
//! Refused with an error naming the word: cutter compensation (`G41`/`G42`), mirror images and
//! scaling, rotations out of the XY plane, polar coordinates, splines, thread cutting
//! (`G33 G331 G332`), pocket and contour cycles, `CYCLE800` by solid or projection angles or
//! rotary positions. Other keywords (path control, feed-forward, orientation interpolation
//! modes) change nothing swarf models and are noted once.

mod cycles;
pub(crate) mod words;

use std::collections::HashMap;
use std::path::PathBuf;
use std::rc::Rc;

use crate::gcode::GcodeOptions;
use crate::limit::MoveLimit;
use crate::part_frame::PartFrame;
use crate::reader_core::{self, Contour};
use crate::{
    Axes, Canon, CanonSink, FeedMode, MessageKind, PathError, PathErrorKind, Plane, SourcePos,
    SpindleDir, Warning,
};
use words::{Value, Word};

/// A reader error before it is given its file.
#[derive(Debug)]
struct Fault {
    line: u32,
    col: u32,
    kind: PathErrorKind,
    message: String,
    found: String,
    expected: String,
}

type Res<T> = Result<T, Fault>;

/// True when `text` is written for a Sinumerik control (the G-code reader's dialect test:
/// `CR=`, `TRAORI`, `DEF REAL`, `MCALL`, `SUPA`, `=AC(`, `CYCLE…(`, `MSG(`, `G500`… within
/// its first 200 lines).
pub fn is_sinumerik(text: &str) -> bool {
    use crate::gcode::dialect::Dialect;
    // The archive header the control writes: `%_N_NAME_MPF`.
    let header = crate::gcode::lexer::lines(text)
        .map(|l| l.trim_start_matches('\u{feff}').trim())
        .find(|l| !l.is_empty())
        .is_some_and(|l| l.starts_with("%_N_"));
    header || matches!(Dialect::detect(text, 200), Some((Dialect::Siemens840D, _)))
}

/// One block: its line, the byte offset of its code in the line, the code (upper case, no
/// block number, label or comment) and its label.
#[derive(Clone, Debug, Default)]
struct Block {
    line: u32,
    col0: u32,
    code: String,
    label: Option<String>,
    number: Option<u64>,
    /// Skipped by block delete.
    deleted: bool,
}

/// The 1-based column (in characters, as the G-code reader counts) of byte `at` of `b`'s code.
fn col(b: &Block, at: usize) -> u32 {
    let at = at.min(b.code.len());
    let chars = b.code.get(..at).map_or(at, |c| c.chars().count());
    b.col0 + chars as u32 + 1
}

fn blocks(text: &str) -> Vec<Block> {
    let mut out = Vec::new();
    for (i, raw) in crate::gcode::lexer::lines(text).enumerate() {
        let raw = if i == 0 {
            raw.strip_prefix('\u{feff}').unwrap_or(raw)
        } else {
            raw
        };
        // The comment: after a `;` outside quotes.
        let mut quoted = false;
        let mut end = raw.len();
        for (k, c) in raw.char_indices() {
            match c {
                '"' => quoted = !quoted,
                ';' if !quoted => {
                    end = k;
                    break;
                }
                _ => {}
            }
        }
        // The control's archive lines (`%_N_NAME_MPF`, `%MPF10`) are no blocks.
        let upper = if raw.trim_start().starts_with('%') {
            String::new()
        } else {
            raw[..end].to_ascii_uppercase()
        };
        let mut at = upper.len() - upper.trim_start().len();
        let mut deleted = false;
        if upper[at..].starts_with('/') {
            deleted = true;
            at += 1;
        }
        // `N10` or `:10`.
        let mut number = None;
        let rest = &upper[at..];
        if let Some(r) = rest.strip_prefix('N').or_else(|| rest.strip_prefix(':')) {
            let d = r.bytes().take_while(u8::is_ascii_digit).count();
            if d > 0 {
                number = r[..d].parse().ok();
                at += 1 + d;
            }
        }
        at += upper[at..].len() - upper[at..].trim_start().len();
        // A label: a name and a colon.
        let mut label = None;
        let rest = &upper[at..];
        let n = rest
            .bytes()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == b'_')
            .count();
        if n >= 2
            && rest.as_bytes()[0].is_ascii_alphabetic()
            && rest.as_bytes().get(n) == Some(&b':')
        {
            label = Some(rest[..n].to_string());
            at += n + 1;
            at += upper[at..].len() - upper[at..].trim_start().len();
        }
        out.push(Block {
            line: u32::try_from(i + 1).unwrap_or(u32::MAX),
            col0: upper[..at].chars().count() as u32,
            code: upper[at..].trim_end().to_string(),
            label,
            number,
            deleted,
        });
    }
    out
}

/// Reads a Sinumerik program, handing its events to `sink` (see the [module
/// documentation](self)). Of `opts`, the move limit, the loop limit, the call depth, the repeat
/// limit, block delete, the home and the subroutine path apply.
///
/// # Errors
/// The first block that cannot be read or is refused: file, line, column, what was found and
/// what was expected.
pub fn read_sinumerik(
    text: &str,
    file: &str,
    opts: &GcodeOptions,
    sink: &mut dyn CanonSink,
) -> Result<(), PathError> {
    let mut r = Reader::new(file, opts, sink);
    let result = r.run(blocks(text));
    let name = r.error_file.clone().unwrap_or_else(|| {
        r.sources
            .get(r.cur)
            .map_or(file.to_string(), |s| s.name.clone())
    });
    let out = match result {
        Ok(()) if r.sink.over => Err(reader_core::limit_error(file, r.sink.max())),
        Ok(()) => Ok(()),
        Err(f) => Err(PathError::new(
            SourcePos {
                file: name,
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

/// One program file with its jump tables.
struct Source {
    name: String,
    blocks: Rc<Vec<Block>>,
    /// Labels and block numbers → the blocks that carry them (block numbers may repeat).
    labels: HashMap<String, Vec<usize>>,
    /// Structured control: the block each `IF`/`ELSE`/`WHILE`/`FOR`/`LOOP`/`REPEAT` and
    /// their ends jump to.
    pair: HashMap<usize, usize>,
}

/// Where a call returns to.
struct Ret {
    back: (usize, usize),
    /// Runs left, and where the subprogram starts.
    left: u64,
    start: (usize, usize),
    /// `DEF` variables of the caller.
    locals: HashMap<String, f64>,
}

/// What a block does to the flow.
enum Flow {
    Next,
    Jump(usize, usize),
    End,
}

struct Reader<'a> {
    file: &'a str,
    opts: &'a GcodeOptions,
    sink: MoveLimit<'a>,
    sources: Vec<Source>,
    cur: usize,
    stack: Vec<Ret>,
    jumps: u64,
    r: HashMap<u32, f64>,
    locals: HashMap<String, f64>,
    /// mm per program unit of lengths, and of feeds (`G70` changes lengths only, `G700`
    /// both).
    scale: f64,
    feed_scale: f64,
    /// Position, working plane and the contour's direction.
    c: Contour,
    frame: PartFrame,
    /// The frame chain: the swivel (`CYCLE800`: pivot, turn, offset along the turned axes),
    /// then the programmable frame (`TRANS`/`ATRANS` translation and `ROT`/`AROT` rotation)
    /// within it. Machine = pivot + R·(offset + t + Rz(rot)·p); the part frame is made from
    /// them.
    swivel: Option<([f64; 3], crate::part_frame::Mat, [f64; 3])>,
    trans: [f64; 3],
    rot: f64,
    /// The block's rotary directions (`DC` 0, `ACP` 1, `ACN` −1).
    turning: [Option<i8>; 6],
    absolute: bool,
    motion: u32,
    feed: Option<f64>,
    feed_mode: FeedMode,
    rpm: f64,
    dir: SpindleDir,
    tool_names: HashMap<String, u32>,
    selected: Option<u32>,
    has_m6: bool,
    /// The modal cycle call (`MCALL CYCLE81(…)`): the call's name, arguments and line.
    mcall: Option<(String, String)>,
    /// Counts of `REPEAT label P=n` sections running, by block.
    repeats: HashMap<(usize, usize), u64>,
    warned: Vec<String>,
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
            jumps: 0,
            r: HashMap::new(),
            locals: HashMap::new(),
            scale: opts.initial_units.mm_per_unit(),
            feed_scale: opts.initial_units.mm_per_unit(),
            c: Contour::new(pos),
            frame: PartFrame::default(),
            trans: [0.0; 3],
            swivel: None,
            rot: 0.0,
            turning: [None; 6],
            absolute: true,
            motion: 0,
            feed: None,
            feed_mode: FeedMode::PerMinute,
            rpm: 0.0,
            dir: SpindleDir::Stopped,
            tool_names: HashMap::new(),
            selected: None,
            has_m6: false,
            mcall: None,
            repeats: HashMap::new(),
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

    fn warn_once(&mut self, key: &str, line: u32, col: u32, message: String) {
        if !self.warned.iter().any(|k| k == key) {
            self.warned.push(key.to_string());
            self.warn(line, col, message);
        }
    }

    fn fault(
        b: &Block,
        at: usize,
        kind: PathErrorKind,
        message: impl Into<String>,
        expected: &str,
    ) -> Fault {
        let found: String = b.code[at.min(b.code.len())..]
            .split_whitespace()
            .next()
            .unwrap_or("")
            .to_string();
        Fault {
            line: b.line,
            col: col(b, at),
            kind,
            message: message.into(),
            found,
            expected: expected.into(),
        }
    }

    fn source(name: String, blocks: Vec<Block>) -> Res<Source> {
        let mut labels = HashMap::new();
        let mut pair = HashMap::new();
        let mut open: Vec<(usize, &str)> = Vec::new();
        for (i, b) in blocks.iter().enumerate() {
            if let Some(l) = &b.label {
                labels.entry(l.clone()).or_insert_with(Vec::new).push(i);
            }
            if let Some(n) = b.number {
                labels
                    .entry(format!("N{n}"))
                    .or_insert_with(Vec::new)
                    .push(i);
            }
            let head = b
                .code
                .split(|c: char| c.is_whitespace() || c == '(' || c == '=')
                .next()
                .unwrap_or("");
            let goto_if = head == "IF" && b.code.contains("GOTO");
            let opener = match head {
                "IF" if !goto_if => Some("IF"),
                "WHILE" => Some("WHILE"),
                "FOR" => Some("FOR"),
                "LOOP" => Some("LOOP"),
                "REPEAT" if b.code.split_whitespace().nth(1).is_none() => Some("REPEAT"),
                _ => None,
            };
            if let Some(o) = opener {
                open.push((i, o));
                continue;
            }
            let closes = match head {
                "ELSE" => Some("IF"),
                "ENDIF" => Some("IF"),
                "ENDWHILE" => Some("WHILE"),
                "ENDFOR" => Some("FOR"),
                "ENDLOOP" => Some("LOOP"),
                "UNTIL" => Some("REPEAT"),
                _ => None,
            };
            if let Some(c) = closes {
                let bad = |m: &str| Fault {
                    line: b.line,
                    col: b.col0 + 1,
                    kind: PathErrorKind::Syntax,
                    message: m.to_string(),
                    found: head.to_string(),
                    expected: format!("a {c} before it"),
                };
                let Some(&(o, kind)) = open.last() else {
                    return Err(bad("an end of a block structure without its start"));
                };
                if kind != c {
                    return Err(bad("block structures cross"));
                }
                if head == "ELSE" {
                    // IF → ELSE; ELSE is the opener of the ENDIF now.
                    pair.insert(o, i);
                    open.pop();
                    open.push((i, "IF"));
                } else {
                    pair.insert(o, i);
                    pair.insert(i, o);
                    open.pop();
                }
            }
        }
        if let Some(&(o, kind)) = open.last() {
            let b = &blocks[o];
            return Err(Fault {
                line: b.line,
                col: b.col0 + 1,
                kind: PathErrorKind::Syntax,
                message: format!("{kind} without its end"),
                found: kind.to_string(),
                expected: "the structure closed".into(),
            });
        }
        Ok(Source {
            name,
            blocks: Rc::new(blocks),
            labels,
            pair,
        })
    }

    fn run(&mut self, blocks: Vec<Block>) -> Res<()> {
        self.has_m6 = blocks.iter().any(|b| {
            b.code
                .split(|c: char| !c.is_ascii_alphanumeric())
                .any(|w| w == "M6" || w == "M06")
        });
        let main = Self::source(self.file.to_string(), blocks)?;
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
                if !self.stack.is_empty() {
                    let last = blocks.last().cloned().unwrap_or_default();
                    let flow = self.ret(&last)?;
                    if let Flow::Jump(s, p) = flow {
                        self.switch_to(s);
                        pc = p;
                    }
                    continue;
                }
                if !self.ended {
                    let line = blocks.last().map_or(0, |b| b.line);
                    self.warn(line, 0, "the program has no M2, M30 or M17".into());
                }
                return Ok(());
            };
            pc += 1;
            if b.deleted {
                let (line, skip) = (b.line, self.opts.block_delete);
                self.warn_once(
                    "blockdelete",
                    line,
                    1,
                    if skip {
                        "block skipped: block delete (`/`) is on (--block-delete; first such \
                         block)"
                    } else {
                        "block read: it starts with `/` (skip), and the switch is off, as the \
                         control starts (first such block; --block-delete skips them)"
                    }
                    .into(),
                );
                if skip {
                    continue;
                }
            }
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
            let name = self.sources[src].name.clone();
            self.emit(0, Canon::SourceFile(name.into()));
        }
    }

    fn jump(&mut self, b: &Block) -> Res<()> {
        self.jumps += 1;
        if self.jumps > self.opts.max_loop_iterations {
            return Err(Self::fault(
                b,
                0,
                PathErrorKind::Limit,
                format!(
                    "more than {} jumps and loop turns: the program may never end",
                    self.opts.max_loop_iterations
                ),
                "a program that ends",
            ));
        }
        Ok(())
    }

    /// The value of a name in an expression.
    fn var(&self, name: &str) -> Option<f64> {
        if let Some(n) = name.strip_prefix('R') {
            if !n.is_empty() && n.bytes().all(|c| c.is_ascii_digit()) {
                return Some(
                    n.parse()
                        .ok()
                        .and_then(|n| self.r.get(&n))
                        .copied()
                        .unwrap_or(0.0),
                );
            }
        }
        if let Some(v) = self.locals.get(name) {
            return Some(*v);
        }
        // System variables read 0 (what the control would report is not known).
        name.starts_with('$').then_some(0.0)
    }

    fn eval(&self, b: &Block, at: usize, text: &str) -> Res<f64> {
        crate::formula::eval_siemens(text, &|n| self.var(n)).map_err(|e| Fault {
            line: b.line,
            col: col(b, at + e.at),
            kind: if e.message.contains("expected") {
                PathErrorKind::Syntax
            } else {
                PathErrorKind::Semantic
            },
            message: e.message,
            found: text.to_string(),
            expected: e.expected.into(),
        })
    }

    /// The number a word gives (a number, or an expression).
    fn number(&self, b: &Block, w: &Word) -> Res<f64> {
        match &w.value {
            Value::Number(v) => Ok(*v),
            Value::Expr(e) => {
                let at = w.at + w.name.len() + 1;
                self.eval(b, at, e)
            }
            _ => Err(Self::fault(
                b,
                w.at,
                PathErrorKind::Syntax,
                format!("{} needs a value", w.name),
                "a number or `=` and an expression",
            )),
        }
    }

    fn assign(&mut self, name: &str, v: f64) {
        if let Some(n) = name.strip_prefix('R').and_then(|n| n.parse::<u32>().ok()) {
            self.r.insert(n, v);
        } else {
            self.locals.insert(name.to_string(), v);
        }
    }

    fn emit_frame(&mut self, line: u32) {
        for e in self.frame.events() {
            self.emit(line, e);
        }
    }

    /// Changes the frame with `f`, keeping the machine position.
    fn change_frame(&mut self, line: u32, f: impl FnOnce(&mut Self)) {
        let m = self
            .frame
            .machine_of([self.c.pos[0], self.c.pos[1], self.c.pos[2]]);
        let untilting = self.frame.tilt.is_some();
        f(self);
        if untilting && self.frame.tilt.is_none() {
            // (Whether the rotary axes turn back is the caller's: `CYCLE800`'s reset.)
            self.emit(line, Canon::WorkPlane(None));
        }
        let p = self.frame.program_of(m);
        self.c.pos[..3].copy_from_slice(&p);
        self.c.tangent = None;
        self.emit_frame(line);
    }

    // ---- blocks ----

    fn block(&mut self, b: &Block, index: usize) -> Res<Flow> {
        let code = b.code.as_str();
        let head = code
            .split(|c: char| c.is_whitespace() || c == '(' || c == '=')
            .next()
            .unwrap_or("");
        let rest = code[head.len()..].trim();
        let rest_at = code.len() - code[head.len()..].trim_start().len();
        match head {
            "" => Ok(Flow::Next),
            "PROC" => Ok(Flow::Next),
            "DEF" => self.define(b).map(|_| Flow::Next),
            "GOTOF" | "GOTOB" | "GOTO" | "GOTOC" => self.goto(b, index, head, rest),
            "IF" => self.if_block(b, index, rest, rest_at),
            "ELSE" => Ok(Flow::Jump(self.cur, self.pair(index) + 1)),
            "ENDIF" => Ok(Flow::Next),
            "WHILE" => {
                if self.eval(b, rest_at, rest)? != 0.0 {
                    Ok(Flow::Next)
                } else {
                    Ok(Flow::Jump(self.cur, self.pair(index) + 1))
                }
            }
            "ENDWHILE" | "ENDLOOP" => {
                self.jump(b)?;
                Ok(Flow::Jump(self.cur, self.pair(index)))
            }
            "LOOP" | "REPEAT" if rest.is_empty() => Ok(Flow::Next),
            "UNTIL" => {
                if self.eval(b, rest_at, rest)? != 0.0 {
                    Ok(Flow::Next)
                } else {
                    self.jump(b)?;
                    Ok(Flow::Jump(self.cur, self.pair(index) + 1))
                }
            }
            "FOR" => self.for_block(b, index, rest, rest_at),
            "ENDFOR" => self.end_for(b, index),
            "REPEAT" => self.repeat(b, index, rest),
            "REPEATB" => Err(Self::fault(
                b,
                0,
                PathErrorKind::Unsupported,
                "REPEATB (one block repeated) is not read",
                "REPEAT <label> P=<n>",
            )),
            "MSG" => {
                let text = rest
                    .trim_start_matches('(')
                    .trim_end_matches(')')
                    .trim()
                    .trim_matches('"')
                    .to_string();
                if !text.is_empty() {
                    self.emit(
                        b.line,
                        Canon::Message {
                            kind: MessageKind::Msg,
                            text: text.into(),
                        },
                    );
                }
                Ok(Flow::Next)
            }
            "RET" | "M17" => self.ret(b),
            "TRANS" | "ATRANS" | "ROT" | "AROT" | "SCALE" | "ASCALE" | "MIRROR" | "AMIRROR"
            | "CTRANS" | "CROT" => self.frame_block(b, head, rest_at).map(|_| Flow::Next),
            "MCALL" => {
                self.mcall = None;
                if !rest.is_empty() {
                    let ws = self.words_at(b, rest_at)?;
                    match ws.first() {
                        Some(w) if w.name.starts_with("CYCLE") => {
                            let Value::Args(a) = &w.value else {
                                return Err(Self::fault(
                                    b,
                                    w.at,
                                    PathErrorKind::Syntax,
                                    "MCALL of a cycle without its arguments",
                                    "MCALL CYCLE81(…)",
                                ));
                            };
                            self.mcall = Some((w.name.clone(), a.clone()));
                        }
                        _ => {
                            return Err(Self::fault(
                                b,
                                rest_at,
                                PathErrorKind::Unsupported,
                                "MCALL of a subprogram is not read",
                                "MCALL CYCLE8x(…) or MCALL alone",
                            ))
                        }
                    }
                }
                Ok(Flow::Next)
            }
            _ => self.word_block(b, index),
        }
    }

    fn words_at(&self, b: &Block, at: usize) -> Res<Vec<Word>> {
        let mut ws = words::words(&b.code[at..]).map_err(|e| {
            Self::fault(
                b,
                at + e.at,
                PathErrorKind::Syntax,
                e.message,
                "a Sinumerik word",
            )
        })?;
        for w in &mut ws {
            w.at += at;
        }
        Ok(ws)
    }

    fn pair(&self, index: usize) -> usize {
        self.sources[self.cur]
            .pair
            .get(&index)
            .copied()
            .unwrap_or(index)
    }

    /// `DEF REAL A, B=5` (the type is not checked).
    fn define(&mut self, b: &Block) -> Res<()> {
        let rest = b.code[3..].trim_start();
        let Some(sp) = rest.find(char::is_whitespace) else {
            return Err(Self::fault(
                b,
                0,
                PathErrorKind::Syntax,
                "DEF without a name",
                "DEF REAL <name>",
            ));
        };
        let names = &rest[sp..];
        let base = b.code.len() - names.len();
        let mut off = 0;
        for part in words::args(names) {
            let at = base + names[off..].find(part).map_or(0, |p| p + off);
            off = (at - base) + part.len();
            let (name, value) = match part.split_once('=') {
                Some((n, v)) => {
                    let v = self.eval(b, at + n.len() + 1, v.trim())?;
                    (n.trim(), v)
                }
                None => (part, 0.0),
            };
            // (`DEF REAL A[3]`: arrays are not read; the name alone is declared.)
            let name = name.split('[').next().unwrap_or(name).trim();
            if !name.is_empty() {
                self.locals.insert(name.to_string(), value);
            }
        }
        Ok(())
    }

    /// The block a jump from block `here` to `name` goes to: searching forward for `GOTOF`,
    /// back for `GOTOB` (and `REPEAT`), forward then from the start for `GOTO`/`GOTOC`.
    fn target_of(&self, b: &Block, here: usize, how: &str, name: &str) -> Res<usize> {
        let key = if name.starts_with('N') && name[1..].bytes().all(|c| c.is_ascii_digit()) {
            format!("N{}", name[1..].parse::<u64>().unwrap_or(0))
        } else {
            name.to_string()
        };
        let at = b.code.rfind(name).unwrap_or(0);
        let Some(all) = self.sources[self.cur].labels.get(&key) else {
            return Err(Self::fault(
                b,
                at,
                PathErrorKind::Semantic,
                format!("jump target {name} is not defined"),
                "a label (NAME:) or block number of this program",
            ));
        };
        let forward = all.iter().copied().find(|&i| i > here);
        let back = all.iter().copied().rev().find(|&i| i <= here);
        let to = match how {
            "GOTOF" => forward,
            "GOTOB" | "REPEAT" => back,
            _ => forward.or_else(|| all.first().copied()),
        };
        to.ok_or_else(|| {
            Self::fault(
                b,
                at,
                PathErrorKind::Semantic,
                format!("{how} to {name}, which is not in that direction"),
                "GOTOF to a later block, GOTOB to an earlier one",
            )
        })
    }

    fn goto(&mut self, b: &Block, here: usize, how: &str, target: &str) -> Res<Flow> {
        let name = target.split_whitespace().next().unwrap_or("");
        let to = self.target_of(b, here, how, name)?;
        if to <= here {
            self.jump(b)?;
        }
        Ok(Flow::Jump(self.cur, to))
    }

    fn if_block(&mut self, b: &Block, index: usize, rest: &str, rest_at: usize) -> Res<Flow> {
        if let Some(g) = rest.find("GOTO") {
            let cond = &rest[..g];
            let yes = self.eval(b, rest_at, cond.trim())? != 0.0;
            if !yes {
                return Ok(Flow::Next);
            }
            let how = rest[g..].split_whitespace().next().unwrap_or("GOTO");
            let target = rest[g + how.len()..].trim();
            return self.goto(b, index, how, target);
        }
        if self.eval(b, rest_at, rest)? != 0.0 {
            Ok(Flow::Next)
        } else {
            // To the block after the ELSE (or the ENDIF).
            Ok(Flow::Jump(self.cur, self.pair(index) + 1))
        }
    }

    /// `FOR R1 = 1 TO 10` (or a `DEF` variable).
    fn for_block(&mut self, b: &Block, index: usize, rest: &str, rest_at: usize) -> Res<Flow> {
        let bad = || {
            Self::fault(
                b,
                rest_at,
                PathErrorKind::Syntax,
                "bad FOR",
                "FOR <variable> = <start> TO <end>",
            )
        };
        let (var, range) = rest.split_once('=').ok_or_else(bad)?;
        let to = range.find("TO").ok_or_else(bad)?;
        let var = var.trim().to_string();
        let start = self.eval(b, rest_at + var.len() + 1, range[..to].trim())?;
        let end = self.eval(b, rest_at, range[to + 2..].trim())?;
        self.assign(&var, start);
        self.locals.insert(format!("\u{0}FOR{index}"), end);
        if start > end {
            return Ok(Flow::Jump(self.cur, self.pair(index) + 1));
        }
        Ok(Flow::Next)
    }

    fn end_for(&mut self, b: &Block, index: usize) -> Res<Flow> {
        let open = self.pair(index);
        let blocks = Rc::clone(&self.sources[self.cur].blocks);
        let head = &blocks[open];
        let var = head.code[3..]
            .split('=')
            .next()
            .unwrap_or("")
            .trim()
            .to_string();
        let end = self
            .locals
            .get(&format!("\u{0}FOR{open}"))
            .copied()
            .unwrap_or(0.0);
        let v = self.var(&var).unwrap_or(0.0) + 1.0;
        self.assign(&var, v);
        if v <= end {
            self.jump(b)?;
            return Ok(Flow::Jump(self.cur, open + 1));
        }
        Ok(Flow::Next)
    }

    /// `REPEAT START P=3` (the section from label START to here, P times; `REPEAT START END`
    /// from START to END): the section is run again from its label.
    fn repeat(&mut self, b: &Block, index: usize, rest: &str) -> Res<Flow> {
        let mut parts = rest.split_whitespace();
        let from = parts.next().unwrap_or("");
        let mut count = 1.0;
        let mut until = None;
        for p in parts {
            if let Some(v) = p.strip_prefix("P=") {
                count = self.eval(b, 0, v)?;
            } else {
                until = Some(p);
            }
        }
        if until.is_some() {
            return Err(Self::fault(
                b,
                0,
                PathErrorKind::Unsupported,
                "REPEAT of a section between two labels elsewhere is not read",
                "REPEAT <label> P=<n> after the section",
            ));
        }
        let start = self.target_of(b, index, "REPEAT", from)?;
        let k = (self.cur, index);
        let left = match self.repeats.get(&k) {
            Some(&l) => l,
            None => {
                if !(count >= 0.0 && count <= self.opts.max_repeat as f64) {
                    return Err(Self::fault(
                        b,
                        0,
                        PathErrorKind::Limit,
                        "bad repeat count",
                        "P=<n>, 0 to the repeat limit",
                    ));
                }
                count as u64
            }
        };
        if left == 0 {
            self.repeats.remove(&k);
            return Ok(Flow::Next);
        }
        self.repeats.insert(k, left - 1);
        self.jump(b)?;
        Ok(Flow::Jump(self.cur, start))
    }

    /// `M17`/`RET`, and the end of a subprogram's file.
    fn ret(&mut self, b: &Block) -> Res<Flow> {
        let Some(top) = self.stack.last_mut() else {
            return Ok(Flow::End);
        };
        if top.left > 0 {
            top.left -= 1;
            let start = top.start;
            // (A repeat counts as a jump: nested repeats could otherwise run for ever.)
            self.jump(b)?;
            return Ok(Flow::Jump(start.0, start.1));
        }
        let Some(top) = self.stack.pop() else {
            return Ok(Flow::End);
        };
        self.locals = top.locals;
        Ok(Flow::Jump(top.back.0, top.back.1))
    }

    /// A subprogram call: `L100`, `NAME`, with `P` repeats.
    fn call(&mut self, b: &Block, index: usize, name: &str, at: usize, runs: u64) -> Res<Flow> {
        if self.stack.len() >= self.opts.max_call_depth {
            return Err(Self::fault(
                b,
                at,
                PathErrorKind::Limit,
                format!("calls nested deeper than {}", self.opts.max_call_depth),
                "shallower calls",
            ));
        }
        let path = self.find_program(name).ok_or_else(|| {
            Self::fault(
                b,
                at,
                PathErrorKind::Syntax,
                format!("unknown word or subprogram {name} (no {name}.SPF beside the program or on the subroutine path)"),
                "a Sinumerik word, or a subprogram's name",
            )
        })?;
        let shown = path.display().to_string();
        let src = match self.sources.iter().position(|s| s.name == shown) {
            Some(i) => i,
            None => {
                let text = crate::load::read_text(&path).map_err(|e| {
                    Self::fault(
                        b,
                        at,
                        PathErrorKind::Io,
                        e.message,
                        "a readable program file",
                    )
                })?;
                // (An error in the called file names that file.)
                let s = Self::source(shown.clone(), blocks(&text))
                    .inspect_err(|_| self.error_file = Some(shown))?;
                self.sources.push(s);
                self.sources.len() - 1
            }
        };
        if runs == 0 {
            return Ok(Flow::Next);
        }
        self.stack.push(Ret {
            back: (self.cur, index + 1),
            left: runs - 1,
            start: (src, 0),
            locals: std::mem::take(&mut self.locals),
        });
        self.jump(b)?;
        Ok(Flow::Jump(src, 0))
    }

    /// `name.SPF`, `name.MPF` or `name` beside the program or on the subroutine path, its
    /// case ignored.
    fn find_program(&self, name: &str) -> Option<PathBuf> {
        let wanted = [
            format!("{name}.SPF"),
            format!("{name}.MPF"),
            name.to_string(),
        ];
        reader_core::find_program(self.file, self.opts, &wanted)
    }

    /// `TRANS`, `ATRANS`, `ROT`, `AROT` (and the refused mirror and scale).
    fn frame_block(&mut self, b: &Block, head: &str, at: usize) -> Res<()> {
        let ws = self.words_at(b, at)?;
        let mut v = [None; 3];
        let mut angle = None;
        for w in &ws {
            match w.name.as_str() {
                "X" | "Y" | "Z" if head.ends_with("TRANS") => {
                    let k = usize::from(w.name.as_bytes()[0] - b'X');
                    v[k] = Some(self.number(b, w)? * self.scale);
                }
                "RPL" | "Z" if head.ends_with("ROT") => {
                    if self.c.plane != Plane::XY && w.name == "RPL" {
                        return Err(Self::fault(
                            b,
                            w.at,
                            PathErrorKind::Unsupported,
                            "a rotation in the G18 or G19 plane is not read",
                            "ROT RPL=… in G17",
                        ));
                    }
                    angle = Some(self.number(b, w)?)
                }
                "X" | "Y" if head.ends_with("ROT") => {
                    return Err(Self::fault(
                        b,
                        w.at,
                        PathErrorKind::Unsupported,
                        "a frame rotation about X or Y is not read: tilt the plane with CYCLE800",
                        "ROT Z… or ROT RPL=…",
                    ))
                }
                _ => {
                    return Err(Self::fault(
                        b,
                        w.at,
                        PathErrorKind::Unsupported,
                        format!("{head} {} is not read", w.name),
                        "TRANS/ATRANS X Y Z, ROT/AROT RPL= or Z",
                    ))
                }
            }
        }
        match head {
            "SCALE" | "ASCALE" | "MIRROR" | "AMIRROR" if !ws.is_empty() => {
                return Err(Self::fault(
                    b,
                    0,
                    PathErrorKind::Unsupported,
                    "mirror images and scaling are not read",
                    "TRANS, ATRANS, ROT or AROT",
                ))
            }
            "SCALE" | "MIRROR" => {}
            "TRANS" | "CTRANS" => {
                // A new programmable frame: this translation alone.
                let t = v.map(|x| x.unwrap_or(0.0));
                self.set_chain(b.line, t, 0.0);
            }
            "ATRANS" => {
                // Along the programmable frame's (rotated) axes.
                let d = crate::part_frame::mul(
                    &crate::part_frame::rz(self.rot),
                    v.map(|x| x.unwrap_or(0.0)),
                );
                let t = std::array::from_fn(|k| self.trans[k] + d[k]);
                self.set_chain(b.line, t, self.rot);
            }
            "ROT" | "CROT" => self.set_chain(b.line, [0.0; 3], angle.unwrap_or(0.0)),
            _ => {
                // AROT
                let r = self.rot + angle.unwrap_or(0.0);
                self.set_chain(b.line, self.trans, r);
            }
        }
        Ok(())
    }

    /// Sets the programmable frame to translation `t` and rotation `rot` and makes the part
    /// frame from the chain.
    pub(super) fn set_chain(&mut self, line: u32, t: [f64; 3], rot: f64) {
        (self.trans, self.rot) = (t, rot);
        let (shift, tilt) = match self.swivel {
            Some((pivot, r, offset)) => {
                let d = crate::part_frame::mul(&r, std::array::from_fn(|k| offset[k] + t[k]));
                (std::array::from_fn(|k| pivot[k] + d[k]), Some(r))
            }
            None => (t, None),
        };
        self.change_frame(line, |s| {
            s.frame.shift = shift;
            s.frame.tilt = tilt;
            s.frame.rot = rot;
        });
    }

    // ---- the word block ----

    fn word_block(&mut self, b: &Block, index: usize) -> Res<Flow> {
        let ws = self.words_at(b, 0)?;
        let mut axes: [Option<(f64, Option<bool>, usize)>; 6] = [None; 6];
        let mut centre: [Option<(f64, bool)>; 3] = [None; 3];
        let mut inter: [Option<(f64, bool)>; 3] = [None; 3];
        let mut vector: [Option<f64>; 3] = [None; 3];
        let mut cr = None;
        let mut turn = 0.0;
        let mut gs: Vec<(u32, usize)> = Vec::new();
        let mut ms: Vec<(u32, usize)> = Vec::new();
        let mut feed = None;
        let mut dwell_f = None;
        let mut dwell_s = None;
        let mut machine = false;
        let mut call: Option<(String, usize, Option<String>)> = None;
        let mut repeat = 1.0;
        let mut tool: Option<(u32, usize)> = None;
        let mut reference: Vec<(usize, usize)> = Vec::new();
        let mut turning: [Option<i8>; 6] = [None; 6];
        // The block's units apply to its own coordinates.
        for w in &ws {
            match (w.name.as_str(), &w.value) {
                // G70/G71: lengths only, feeds in the basic system (`--initial-units`).
                ("G", Value::Number(g)) if *g == 70.0 || *g == 71.0 => {
                    self.scale = if *g == 70.0 { 25.4 } else { 1.0 };
                    self.feed_scale = self.opts.initial_units.mm_per_unit();
                }
                ("G", Value::Number(g)) if *g == 700.0 => {
                    (self.scale, self.feed_scale) = (25.4, 25.4)
                }
                ("G", Value::Number(g)) if *g == 710.0 => {
                    (self.scale, self.feed_scale) = (1.0, 1.0)
                }
                _ => {}
            }
        }
        for w in &ws {
            let name = w.name.as_str();
            match name {
                "G" => {
                    let g = self.number(b, w)?;
                    let g10 = (g * 10.0).round();
                    if !(0.0..=99990.0).contains(&g10) || (g10 / 10.0 - g).abs() > 1e-9 {
                        return Err(Self::fault(b, w.at, PathErrorKind::Syntax, "bad G code", "G and a code number"));
                    }
                    gs.push((g10 as u32, w.at));
                }
                "M" => {
                    let m = self.number(b, w)?;
                    if !(0.0..=100_000.0).contains(&m) || m.fract() != 0.0 {
                        return Err(Self::fault(b, w.at, PathErrorKind::Syntax, "bad M function", "M and a whole number"));
                    }
                    ms.push((m as u32, w.at));
                }
                // `M1=3`: spindle 1's M function.
                n if n.len() > 1 && n.starts_with('M') && n[1..].bytes().all(|c| c.is_ascii_digit()) => {
                    let m = self.number(b, w)?;
                    ms.push((m.max(0.0) as u32, w.at));
                }
                "X" | "Y" | "Z" | "A" | "B" | "C" => {
                    let k = "XYZABC".find(name).unwrap_or(0);
                    if axes[k].is_some() {
                        return Err(Self::fault(
                            b,
                            w.at,
                            PathErrorKind::Semantic,
                            format!("{name} is programmed twice in the block"),
                            "each axis once",
                        ));
                    }
                    let (v, inc) = self.coordinate(b, w)?;
                    let v = if k < 3 { v * self.scale } else { v };
                    axes[k] = Some((v, inc, w.at));
                    // `DC()`, `ACP()`, `ACN()`: which way a rotary axis turns.
                    if let Value::Expr(e) = &w.value {
                        turning[k] = [("DC(", 0), ("ACP(", 1), ("ACN(", -1)]
                            .into_iter()
                            .find(|(p, _)| e.starts_with(p))
                            .map(|(_, d)| d);
                    }
                }
                "I" | "J" | "K" => {
                    let k = "IJK".find(name).unwrap_or(0);
                    let (v, abs) = self.coordinate(b, w)?;
                    centre[k] = Some((v * self.scale, abs == Some(false)));
                }
                "I1" | "J1" | "K1" => {
                    let k = "IJK".find(&name[..1]).unwrap_or(0);
                    let (v, inc) = self.coordinate(b, w)?;
                    inter[k] = Some((v * self.scale, inc.unwrap_or(!self.absolute)));
                }
                "A3" | "B3" | "C3" => {
                    let k = "ABC".find(&name[..1]).unwrap_or(0);
                    vector[k] = Some(self.number(b, w)?);
                }
                "CR" => cr = Some(self.number(b, w)? * self.scale),
                "TURN" => turn = self.number(b, w)?,
                "F" => feed = Some((self.number(b, w)?, w.at)),
                "S" | "S1" => dwell_s = Some(self.number(b, w)?),
                // G74/G75 reference and fixed-point approach: to the home on those axes.
                "X1" | "Y1" | "Z1" => reference.push(("XYZ".find(&name[..1]).unwrap_or(0), w.at)),
                "T" => {
                    let n = match &w.value {
                        Value::Expr(e) if e.starts_with('"') => {
                            let name = e.trim_matches('"').to_string();
                            let (n, warning) =
                                reader_core::tool_by_name(self.opts, &mut self.tool_names, &name);
                            if let Some(m) = warning {
                                self.warn(b.line, col(b, w.at), m);
                            }
                            n
                        }
                        _ => {
                            let n = self.number(b, w)?;
                            if !(0.0..=f64::from(u32::MAX)).contains(&n) || n.fract() != 0.0 {
                                return Err(Self::fault(b, w.at, PathErrorKind::Syntax, "bad tool number", "T and a whole number from 0, or T=\"name\""));
                            }
                            n as u32
                        }
                    };
                    tool = Some((n, w.at));
                }
                "D" | "H" | "DL" => {}
                "L" => {
                    let n = self.number(b, w)?;
                    if !(0.0..=f64::from(u32::MAX)).contains(&n) || n.fract() != 0.0 {
                        return Err(Self::fault(b, w.at, PathErrorKind::Syntax, "bad subprogram number", "L and a whole number"));
                    }
                    call = Some((format!("L{}", n as u64), w.at, None));
                }
                "P" => repeat = self.number(b, w)?,
                "SUPA" => machine = true,
                // The 5-axis transformation: while on, X Y Z are tool-tip positions in the
                // part frame.
                "TRAORI" | "TRAFOOF" => {
                    let before = self.sink.position();
                    self.emit(b.line, Canon::ToolCentrePoint(name == "TRAORI"));
                    reader_core::follow_sink(&mut self.c.pos, before, self.sink.position());
                }
                "CFC" | "CFTCP" | "CFIN" | "SOFT" | "BRISK" | "DRIVE" | "FFWON" | "FFWOF"
                | "COMPON" | "COMPCURV" | "COMPCAD" | "COMPOF" | "UPATH" | "SPATH" | "FNORM"
                | "FLIN" | "FCUB" | "ORIWKS" | "ORIMKS" | "ORIAXES" | "ORIVECT" | "ORIEULER"
                | "ORIRPY" | "OST" | "STOPRE" | "WAITM" | "WAITS" | "SPOS" | "SPOSA" | "FGROUP"
                | "FGREF" | "ADIS" | "ADISPOS" | "CTOL" | "OTOL" | "CTOLG0" | "OTOLG0" | "STOLF"
                | "ORISON" | "ORISOF" | "ORIC" | "ORID" | "TCOABS" | "TCOFR" | "TCARR" | "PAROT"
                | "PAROTOF" | "TOROT" | "TOROTOF" | "LIMS" | "FP" | "WORKPIECE" | "SETMS"
                | "SOFTA" | "BRISKA" | "FIFOCTRL" | "ORIPLANE" | "ORIVIRT1" | "ORIVIRT2"
                | "COMPSURF" | "WALIMON" | "WALIMOF" | "DIAMOF" | "FTOCON" | "FTOCOF" => {}
                // The kind of tool radius compensation and how it approaches and leaves the
                // contour: nothing without G41/G42, which are refused.
                "CUT2D" | "CUT2DF" | "CUT3DC" | "CUT3DCC" | "CUT3DCCD" | "CUT3DF" | "CUT3DFS" | "CUT3DFF" | "CDON"
                | "CDOF" | "CDOF2" | "NORM" | "KONT" | "KONTC" | "KONTT" => {}
                "ORIPATH" | "ORIPATHS" | "ORICONCW" | "ORICONCCW" | "ORICONIO" | "ORICONTO"
                | "ORICURVE" => self.warn_once(
                    "oriinterp",
                    b.line,
                    col(b, w.at),
                    format!(
                        "{name}: the tool axis is interpolated on the great circle between the \
                         blocks' orientations (ORIVECT), not as {name} says"
                    ),
                ),
                "DIAMON" | "DIAM90" | "DIAMCYCOF" | "TRACYL" | "TRANSMIT" | "TRACON" | "TRAANG"
                | "CTAB" | "CTABDEF" | "CTABEND" => {
                    return Err(Self::fault(
                        b,
                        w.at,
                        PathErrorKind::Unsupported,
                        format!(
                            "{name} is not read (diameter programming, the cylinder and face \
                             transformations and curve tables change what the axes' words mean)"
                        ),
                        "X Y Z as Cartesian positions",
                    ))
                }
                "TOFRAME" | "TOFRAMEX" | "TOFRAMEY" | "TOFRAMEZ" => self.warn_once(
                    "toframe",
                    b.line,
                    col(b, w.at),
                    format!("{name} (frame turned to the tool) is not read"),
                ),
                "CYCLE832" | "CYCLE800" | "CYCLE81" | "CYCLE82" | "CYCLE83" | "CYCLE84" | "CYCLE840"
                | "CYCLE85" | "CYCLE86" | "CYCLE87" | "CYCLE88" | "CYCLE89" => {
                    let args = match &w.value {
                        Value::Args(a) => a.clone(),
                        _ => String::new(),
                    };
                    call = Some((name.to_string(), w.at, Some(args)));
                }
                n if n.starts_with("CYCLE") || n.starts_with("POCKET") || n.starts_with("SLOT") || n.starts_with("LONGHOLE") || n.starts_with("HOLES") => {
                    return Err(Self::fault(
                        b,
                        w.at,
                        PathErrorKind::Unsupported,
                        format!("{n} is not read: its path is the control's (swarf runs CYCLE81–CYCLE86, CYCLE89 and CYCLE800)"),
                        "a drilling cycle or the path itself",
                    ))
                }
                "CIP" => gs.push((9001, w.at)),
                "CT" => gs.push((9002, w.at)),
                "AP" | "RP" | "ASPLINE" | "BSPLINE" | "CSPLINE" | "POLY" | "RND" | "RNDM" | "CHF" | "CHR" | "AR" => {
                    return Err(Self::fault(
                        b,
                        w.at,
                        PathErrorKind::Unsupported,
                        format!("{name} is not read (polar coordinates, splines, corner rounding and arcs by opening angle)"),
                        "X Y Z, I J K or CR",
                    ))
                }
                n if n.starts_with('R') && n[1..].bytes().all(|c| c.is_ascii_digit()) && n.len() > 1 => {
                    let v = self.number(b, w)?;
                    self.assign(n, v);
                }
                n if self.locals.contains_key(n) => {
                    let v = self.number(b, w)?;
                    self.assign(n, v);
                }
                n if matches!(w.value, Value::Args(ref a) if !a.trim().is_empty()) => {
                    return Err(Self::fault(
                        b,
                        w.at,
                        PathErrorKind::Unsupported,
                        format!("a call of {n} with arguments is not read (PROC parameters)"),
                        "a subprogram call without arguments",
                    ))
                }
                n if matches!(w.value, Value::None | Value::Args(_)) && n.len() > 1 => {
                    call = Some((n.to_string(), w.at, None));
                }
                // The tool's orientation as Euler or RPY angles (A2= B2= C2=, ORIEULER /
                // ORIRPY), lead and tilt angles (LEAD= TILT=), or a second vector (XH= …):
                // only the direction vector A3= B3= C3= and rotary axis words are read.
                "A2" | "B2" | "C2" | "LEAD" | "TILT" | "THETA" | "XH" | "YH" | "ZH" | "A4" | "B4"
                | "C4" | "A5" | "B5" | "C5" => {
                    return Err(Self::fault(
                        b,
                        w.at,
                        PathErrorKind::Unsupported,
                        format!(
                            "{name}= states the tool orientation in a form swarf does not read \
                             (Euler or RPY angles, lead and tilt, a second point or the path's \
                             normal)"
                        ),
                        "the orientation as a direction vector A3= B3= C3=, or rotary axis words",
                    ))
                }
                _ => {
                    return Err(Self::fault(
                        b,
                        w.at,
                        PathErrorKind::Syntax,
                        format!("unexpected word {name}"),
                        "G M X Y Z A B C I J K CR F S T D, a cycle, an assignment or a subprogram",
                    ))
                }
            }
        }
        // Modal and non-modal G codes, in their order of effect; one motion code a block.
        let motions: Vec<&(u32, usize)> = gs
            .iter()
            .filter(|g| matches!(g.0, 0 | 10 | 20 | 30 | 9001 | 9002))
            .collect();
        if let Some(&&(_, at)) = motions.get(1) {
            return Err(Self::fault(
                b,
                at,
                PathErrorKind::Semantic,
                "two motion codes in one block",
                "one of G0 G1 G2 G3 CIP CT",
            ));
        }
        let mut dwell = false;
        for &(g, at) in &gs {
            match g {
                0 | 10 | 20 | 30 | 9001 | 9002 => self.motion = g,
                170 => self.set_plane(b, Plane::XY),
                180 => self.set_plane(b, Plane::XZ),
                190 => self.set_plane(b, Plane::YZ),
                900 => self.absolute = true,
                910 => self.absolute = false,
                700 | 710 | 7000 | 7100 => {}
                930 => self.feed_mode = FeedMode::InverseTime,
                940 => self.feed_mode = FeedMode::PerMinute,
                950 => self.feed_mode = FeedMode::PerRevolution,
                40 => dwell = true,
                740 | 750 => {}
                530 | 1530 => machine = true,
                5000 | 540..=570 | 5050..=5990 => {}
                400 => {}
                410 | 420 => {
                    return Err(Self::fault(
                        b,
                        at,
                        PathErrorKind::Unsupported,
                        "cutter radius compensation (G41/G42) is not read: swarf reads programs of the tool centre path",
                        "G40",
                    ))
                }
                330 | 3310 | 3320 | 340 | 350 => {
                    return Err(Self::fault(b, at, PathErrorKind::Unsupported, "thread cutting is not read", "G0–G3"))
                }
                // Path control, exact stop, acceleration, working area: nothing swarf models.
                600 | 640 | 6410 | 6420 | 6430 | 6440 | 6450 | 6010 | 6020 | 6030 | 90 | 620 | 6210 | 250 | 260 | 4500 | 4510 | 960 | 970 | 1100 | 1110 | 1120 => {
                    if matches!(g, 1100 | 1110 | 1120) {
                        return Err(Self::fault(b, at, PathErrorKind::Unsupported, "polar coordinates (G110–G112) are not read", "X Y Z"));
                    }
                }
                _ => {
                    return Err(Self::fault(
                        b,
                        at,
                        PathErrorKind::Syntax,
                        format!("G{} is not read", f64::from(g) / 10.0),
                        "a G code swarf reads",
                    ))
                }
            }
        }
        // G74/G75: at rapid to the home on the axes named (X1=0 …), in machine coordinates.
        let to_home = gs.iter().any(|g| g.0 == 740 || g.0 == 750);
        match (to_home, reference.first()) {
            (true, _) => {
                for &(k, at) in &reference {
                    axes[k] = Some((0.0, Some(false), at));
                }
                machine = true;
            }
            (false, Some(&(_, at))) => {
                return Err(Self::fault(
                    b,
                    at,
                    PathErrorKind::Syntax,
                    "a machine axis word (X1= Y1= Z1=) without G74 or G75",
                    "G74 or G75 in the block",
                ))
            }
            (false, None) => {}
        }
        if let Some((f, _)) = feed {
            if !dwell {
                self.feed = Some(if self.feed_mode == FeedMode::InverseTime {
                    f
                } else {
                    f * self.feed_scale
                });
            } else {
                dwell_f = Some(f);
            }
        }
        // Spindle and tool before the motion.
        for &(m, _) in &ms {
            match m {
                3 => self.dir = SpindleDir::Clockwise,
                4 => self.dir = SpindleDir::CounterClockwise,
                _ => continue,
            }
            self.tell_spindle(b.line);
        }
        if let (Some(s), false) = (dwell_s, dwell) {
            self.rpm = s.abs();
            self.tell_spindle(b.line);
        }
        if let Some((n, _)) = tool {
            self.selected = Some(n);
            if !self.has_m6 {
                self.emit(b.line, Canon::ToolChange { tool: n });
            }
        }
        if ms.iter().any(|m| m.0 == 6) {
            if let Some(n) = self.selected {
                self.emit(b.line, Canon::ToolChange { tool: n });
            }
        }
        if dwell {
            let secs = match (dwell_f, dwell_s) {
                (Some(f), _) => f,
                (None, Some(s)) if self.rpm > 0.0 => s / self.rpm * 60.0,
                _ => 0.0,
            };
            if secs > 0.0 {
                self.emit(b.line, Canon::Dwell(secs));
            }
        }
        if vector.iter().any(Option::is_some) {
            let t = self.frame.direction(vector.map(|v| v.unwrap_or(0.0)));
            self.emit(b.line, Canon::ToolAxis(t));
        }
        if axes[3..].iter().any(Option::is_some) {
            // A rotary axis turned: a tool axis held after a swivel's deselection is the
            // machine's again.
            self.emit(b.line, Canon::MachineAxis);
        }
        let moved = axes.iter().any(Option::is_some)
            || (self.motion >= 20 && (cr.is_some() || centre.iter().any(Option::is_some)));
        if moved && !dwell {
            let modal = self.motion;
            if to_home {
                self.motion = 0;
            }
            self.turning = turning;
            self.motion_block(b, &axes, centre, inter, cr, turn, machine)?;
            self.motion = modal;
        }
        // Cycles: at the block's end, the modal one after a positioning block.
        if let Some((name, at, args)) = call {
            match args {
                Some(a) => self.cycle(b, &name, at, &a)?,
                None => {
                    if !(repeat >= 0.0 && repeat <= self.opts.max_repeat as f64)
                        || repeat.fract() != 0.0
                    {
                        return Err(Self::fault(
                            b,
                            at,
                            PathErrorKind::Syntax,
                            "bad repeat count P",
                            "P and a whole number",
                        ));
                    }
                    return self.call(b, index, &name, at, repeat as u64);
                }
            }
        } else if moved {
            if let Some((name, args)) = self.mcall.clone() {
                self.cycle(b, &name, 0, &args)?;
            }
        }
        let mut end = false;
        for &(m, at) in &ms {
            match m {
                5 => {
                    self.dir = SpindleDir::Stopped;
                    self.tell_spindle(b.line);
                }
                2 | 30 => end = true,
                17 => return self.ret(b),
                0 | 1 | 3 | 4 | 6 | 7 | 8 | 9 | 19 | 40 | 41 | 42 | 70 => {}
                _ => self.warn(
                    b.line,
                    col(b, at),
                    format!("M{m} is not read (a machine function swarf does not model)"),
                ),
            }
        }
        if end {
            if !self.stack.is_empty() {
                return self.ret(b);
            }
            return Ok(Flow::End);
        }
        Ok(Flow::Next)
    }

    fn set_plane(&mut self, b: &Block, p: Plane) {
        if p != self.c.plane {
            self.c.plane = p;
            self.c.tangent = None;
            self.emit(b.line, Canon::Plane(p));
        }
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

    /// A coordinate word's value and whether it is incremental (`Some(true)` for `IC()`,
    /// `Some(false)` for `AC()`, `None`: the modal G90/G91).
    fn coordinate(&self, b: &Block, w: &Word) -> Res<(f64, Option<bool>)> {
        if let Value::Expr(e) = &w.value {
            let at = w.at + w.name.len() + 1;
            for (prefix, inc) in [
                ("IC(", Some(true)),
                ("AC(", Some(false)),
                ("DC(", Some(false)),
                ("ACP(", Some(false)),
                ("ACN(", Some(false)),
            ] {
                if let Some(inner) = e.strip_prefix(prefix).and_then(|r| r.strip_suffix(')')) {
                    let v = self.eval(b, at + prefix.len(), inner)?;
                    return Ok((v, inc));
                }
            }
        }
        Ok((self.number(b, w)?, None))
    }

    fn tell_feed(&mut self, b: &Block) -> Res<()> {
        let Some(f) = self.feed else {
            return Err(Self::fault(
                b,
                0,
                PathErrorKind::Semantic,
                "a feed move before any feed rate",
                "F<feed>",
            ));
        };
        let events: Vec<Canon<'static>> = self.c.feed(self.feed_mode, f).collect();
        for e in events {
            self.emit(b.line, e);
        }
        Ok(())
    }

    #[allow(clippy::too_many_arguments)]
    fn motion_block(
        &mut self,
        b: &Block,
        axes: &[Option<(f64, Option<bool>, usize)>; 6],
        centre: [Option<(f64, bool)>; 3],
        inter: [Option<(f64, bool)>; 3],
        cr: Option<f64>,
        turn: f64,
        machine: bool,
    ) -> Res<()> {
        let mut end = self.c.pos;
        for (k, a) in axes.iter().enumerate() {
            if let Some((v, inc, _)) = *a {
                let inc = inc.unwrap_or(!self.absolute);
                let from = self.c.pos[k];
                end[k] = match (inc, self.turning[k]) {
                    (true, _) => from + v,
                    (false, None) => v,
                    // Shortest way, or the positive or negative way, to the angle.
                    (false, Some(0)) => from + (v - from + 180.0).rem_euclid(360.0) - 180.0,
                    (false, Some(1)) => from + (v - from).rem_euclid(360.0),
                    (false, Some(_)) => from - (from - v).rem_euclid(360.0),
                };
            }
        }
        if machine {
            if self.opts.home.is_none() {
                self.warn_once("home", b.line, b.col0 + 1, "SUPA/G53 machine coordinates are taken from the machine's home, which is not given (--home X,Y,Z): they are read from the work origin".into());
            }
            let home = self.opts.home.unwrap_or([0.0; 3]);
            let mut m = self
                .frame
                .machine_of([self.c.pos[0], self.c.pos[1], self.c.pos[2]]);
            for k in 0..3 {
                if let Some((v, inc, _)) = axes[k] {
                    m[k] = if inc == Some(true) {
                        m[k] + v
                    } else {
                        home[k] + v
                    };
                }
            }
            let p = self.frame.program_of(m);
            end[..3].copy_from_slice(&p);
        }
        let (i1, i2, n) = self.c.plane.axes();
        match self.motion {
            0 => self.line_to(b.line, end, true),
            10 => {
                self.tell_feed(b)?;
                self.line_to(b.line, end, false);
            }
            20 | 30 => {
                self.tell_feed(b)?;
                let ccw = self.motion == 30;
                let s = [self.c.pos[i1], self.c.pos[i2]];
                let e = [end[i1], end[i2]];
                let c = match cr {
                    Some(r) => {
                        let tol = self.arc_tolerance(r.abs());
                        crate::heidenhain::cr_centre(s, e, r, ccw, tol).ok_or_else(|| {
                            Self::fault(
                                b,
                                0,
                                PathErrorKind::Semantic,
                                format!(
                                    "the radius {} mm is too small for the arc's chord",
                                    r.abs()
                                ),
                                "CR at least half the chord",
                            )
                        })?
                    }
                    None => {
                        // (I J K are along X Y Z: the plane's axes pick two of them.)
                        let pick = |axis: usize| centre[axis];
                        let c1 = match pick(i1) {
                            Some((v, true)) => v,
                            Some((v, false)) => s[0] + v,
                            None => s[0],
                        };
                        let c2 = match pick(i2) {
                            Some((v, true)) => v,
                            Some((v, false)) => s[1] + v,
                            None => s[1],
                        };
                        let c = [c1, c2];
                        let r0 = (s[0] - c[0]).hypot(s[1] - c[1]);
                        let r1 = (e[0] - c[0]).hypot(e[1] - c[1]);
                        if (r0 - r1).abs() > self.arc_tolerance(r0.max(r1)) {
                            return Err(Self::fault(b, 0, PathErrorKind::Semantic, format!("the arc's end is not on its circle: {r0:.4} mm from the centre at the start, {r1:.4} mm at the end"), "I J K (or CR) of a circle through both ends"));
                        }
                        c
                    }
                };
                if !(turn >= 0.0 && turn <= self.opts.max_repeat as f64) || turn.fract() != 0.0 {
                    return Err(Self::fault(
                        b,
                        0,
                        PathErrorKind::Syntax,
                        "bad TURN",
                        "TURN= a whole number of extra turns",
                    ));
                }
                let turns = 1 + turn as i32;
                self.arc_to(b.line, end, c, ccw, turns);
            }
            9001 => {
                // CIP: through the intermediate point.
                self.tell_feed(b)?;
                let mut mid = [self.c.pos[0], self.c.pos[1], self.c.pos[2]];
                for k in 0..3 {
                    if let Some((v, inc)) = inter[k] {
                        mid[k] = if inc { self.c.pos[k] + v } else { v };
                    }
                }
                let p0 = [self.c.pos[0], self.c.pos[1], self.c.pos[2]];
                let p2 = [end[0], end[1], end[2]];
                let Some((c, normal)) = circle3(p0, mid, p2) else {
                    return Err(Self::fault(
                        b,
                        0,
                        PathErrorKind::Semantic,
                        "CIP's three points lie on a line",
                        "an intermediate point off the line",
                    ));
                };
                // In a plane of the program frame: an ordinary arc; else about its own axis
                // (the frame must then be a plain shift).
                let on = |k: usize| normal[k].abs() > 1.0 - 1e-12;
                if on(n) {
                    let ccw = normal[n] > 0.0;
                    self.arc_to(b.line, end, [c[i1], c[i2]], ccw, 1);
                } else if self.frame.rot == 0.0 && self.frame.tilt.is_none() {
                    self.c.pos = end;
                    self.c.tangent = None;
                    self.emit(
                        b.line,
                        Canon::ArcAxis {
                            end: Axes::from_array(end),
                            center: c,
                            normal,
                            turns: 1,
                        },
                    );
                } else {
                    return Err(Self::fault(b, 0, PathErrorKind::Unsupported, "a CIP arc out of the working plane under a rotated or tilted frame is not read", "CIP in the working plane"));
                }
            }
            _ => {
                // CT: tangent to the contour before.
                self.tell_feed(b)?;
                match self.c.tangent_arc(end) {
                    Some(Some((c, ccw))) => self.arc_to(b.line, end, c, ccw, 1),
                    Some(None) => self.line_to(b.line, end, false),
                    None => {
                        return Err(Self::fault(
                            b,
                            0,
                            PathErrorKind::Semantic,
                            "CT without a contour element before it to be tangent to",
                            "a line or arc in the working plane before CT",
                        ))
                    }
                }
            }
        }
        Ok(())
    }

    fn arc_tolerance(&self, r: f64) -> f64 {
        reader_core::arc_tolerance(self.opts, self.scale, r)
    }

    fn line_to(&mut self, line: u32, end: [f64; 6], rapid: bool) {
        let e = self.c.line(end, rapid);
        self.emit(line, e);
    }

    fn arc_to(&mut self, line: u32, end: [f64; 6], center: [f64; 2], ccw: bool, turns: i32) {
        let e = self.c.arc(end, center, ccw, turns);
        self.emit(line, e);
    }
}

/// The circle through `a`, `b`, `c` (in that order): its centre and the unit normal about which
/// the motion from `a` through `b` to `c` is counter-clockwise.
fn circle3(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> Option<([f64; 3], [f64; 3])> {
    use crate::part_frame::{cross, unit};
    let u: [f64; 3] = std::array::from_fn(|k| b[k] - a[k]);
    let v: [f64; 3] = std::array::from_fn(|k| c[k] - a[k]);
    let w = cross(u, v);
    let ww: f64 = w.iter().map(|x| x * x).sum();
    let (uu, vv): (f64, f64) = (u.iter().map(|x| x * x).sum(), v.iter().map(|x| x * x).sum());
    if ww <= 1e-18 * uu.max(vv) * uu.max(vv) || ww == 0.0 {
        return None;
    }
    // Centre = a + (|u|² (v × w) + |v|² (w × u)) / (2 |w|²).
    let vw = cross(v, w);
    let wu = cross(w, u);
    let c0: [f64; 3] = std::array::from_fn(|k| a[k] + (uu * vw[k] + vv * wu[k]) / (2.0 * ww));
    Some((c0, unit(w)?))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn circles_through_three_points() {
        let (c, n) = circle3([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]).unwrap();
        assert!(c.iter().all(|v| v.abs() < 1e-12));
        assert_eq!(n, [0.0, 0.0, 1.0]);
        let (_, n) = circle3([1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [-1.0, 0.0, 0.0]).unwrap();
        assert_eq!(n, [0.0, 0.0, -1.0]);
        assert!(circle3([0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]).is_none());
    }

    #[test]
    fn blocks_keep_numbers_labels_and_lose_comments() {
        let b = blocks("N10 G1 X1 ; go\nSTART: G0 X0\n/N20 M30\n");
        assert_eq!((b[0].number, b[0].code.as_str()), (Some(10), "G1 X1"));
        assert_eq!(
            (b[1].label.as_deref(), b[1].code.as_str()),
            (Some("START"), "G0 X0")
        );
        assert!(b[2].deleted && b[2].code == "M30");
        assert_eq!(b[0].col0, 4);
    }
}
