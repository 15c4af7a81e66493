//! One block (line) of G-code as words in fixed slots: letters with their values, the G codes of
//! each modal group, the M codes, and the parameter assignments — no allocation per line.

use super::expr::{assign_index, is_vacant, read_infix, read_name, read_real, Cur, ParamRead};
use super::lexer::LineBuf;
use super::params::{Target, MAX_ASSIGNS};
use super::{Fault, Res, Span};
use crate::PathErrorKind;

/// Slot of a letter word: `a`..`z` are 0..25, `@` (polar radius) 26, `^` (polar angle) 27.
pub(crate) const fn slot(c: u8) -> usize {
    match c {
        b'@' => 26,
        b'^' => 27,
        _ => (c - b'a') as usize,
    }
}

/// Modal groups (LinuxCNC's numbering).
pub(crate) mod group {
    /// G4 G10 G28 G30 G53 G92…
    pub(crate) const NON_MODAL: usize = 0;
    /// G0 G1 G2 G3 G80–G89 G73 G74.
    pub(crate) const MOTION: usize = 1;
    /// G17 G18 G19.
    pub(crate) const PLANE: usize = 2;
    /// G90 G91.
    pub(crate) const DISTANCE: usize = 3;
    /// G90.1 G91.1.
    pub(crate) const ARC_DISTANCE: usize = 4;
    /// G93 G94 G95.
    pub(crate) const FEED_MODE: usize = 5;
    /// G20 G21.
    pub(crate) const UNITS: usize = 6;
    /// G40 G41 G42 G41.1 G42.1.
    pub(crate) const CUTTER_COMP: usize = 7;
    /// G43 G43.1 G49.
    pub(crate) const TOOL_LENGTH: usize = 8;
    /// G98 G99.
    pub(crate) const RETRACT: usize = 10;
    /// G54–G59.3 (and Fanuc's G54.1, Haas's G154).
    pub(crate) const COORD: usize = 12;
    /// G61 G61.1 G64.
    pub(crate) const PATH: usize = 13;
    /// G96 G97.
    pub(crate) const SPINDLE_MODE: usize = 14;
    /// G50 G51 (Fanuc scaling).
    pub(crate) const SCALING: usize = 15;
    /// G68 G69 (Fanuc coordinate rotation).
    pub(crate) const ROTATION: usize = 16;
    /// Number of groups.
    pub(crate) const N: usize = 17;
}

/// The modal group of G code `code` (the G number × 10), or why it is not accepted.
fn g_group(code: u16) -> Result<usize, (PathErrorKind, &'static str)> {
    use group::*;
    let unsupported = |m| Err((PathErrorKind::Unsupported, m));
    match code {
        40 | 100 | 280 | 281 | 300 | 301 | 520 | 530 | 920 | 921 | 922 | 923 => Ok(NON_MODAL),
        0 | 10 | 20 | 30 | 50 | 51 | 52 | 53 | 730 | 740 | 800 | 810 | 820 | 830 | 840 | 850
        | 860 | 870 | 880 | 890 => Ok(MOTION),
        170 | 180 | 190 => Ok(PLANE),
        900 | 910 => Ok(DISTANCE),
        901 | 911 => Ok(ARC_DISTANCE),
        930 | 940 | 950 => Ok(FEED_MODE),
        200 | 210 => Ok(UNITS),
        400 | 410 | 420 | 411 | 421 => Ok(CUTTER_COMP),
        430 | 431 | 490 | 2340 => Ok(TOOL_LENGTH),
        980 | 990 => Ok(RETRACT),
        // (G54.1 and G154, Fanuc's and Haas's additional work offsets: Fanuc dialect only.)
        540 | 550 | 560 | 570 | 580 | 590 | 591 | 592 | 593 | 541 | 1540 => Ok(COORD),
        610 | 611 | 640 => Ok(PATH),
        960 | 970 => Ok(SPINDLE_MODE),
        330 | 331 | 382..=385 => Ok(MOTION),
        760 => unsupported(
            "G76 (LinuxCNC's lathe threading cycle) is not read: swarf simulates milling (a Fanuc \
             program's G76 fine boring is read with --dialect fanuc)",
        ),
        120 | 130 => unsupported(
            "Mach3's circular pocket G12/G13 is not read (its path is the control's): write the \
             pocket's moves (the CAM system's, or G2/G3 full circles such as `G2 I-5`)",
        ),
        70 | 80 => unsupported("lathe diameter/radius modes (G7/G8) are not supported"),
        700 | 710 => unsupported(
            "G70/G71 with words are finishing and roughing cycles (Fanuc lathes, LinuxCNC 2.9), \
             which are not read; alone in a block (with other G codes), as Mach3 and Vectric's \
             posts write them, they are read as G20 (inch) and G21 (mm)",
        ),
        650 | 660 | 670 => unsupported(
            "custom macro calls (G65/G66/G67, such as a probing cycle G65 P9810) are not read, so \
             the motion of the macro would be missing",
        ),
        150 | 160 => {
            unsupported("Fanuc polar coordinate mode (G15/G16) is not supported; use `@` and `^`")
        }
        171 | 181 | 191 => unsupported("UVW planes (G17.1, G18.1, G19.1) are not supported"),
        433 => unsupported("G43.3 is not a tool length offset swarf reads (G43, G43.1, G43.2)"),
        432 | 434 | 435 => Ok(TOOL_LENGTH),
        531 => Ok(NON_MODAL),
        683 | 684 | 691 => unsupported(
            "G68.3/G68.4 (a working plane from the tool axis, incremental) and G69.1 are not \
             read; G68.2 (Euler angles) with G53.1 is",
        ),
        500 | 510 => Ok(SCALING),
        511 => unsupported("mirroring (G51.1) is not supported"),
        680 | 682 | 690 => Ok(ROTATION),
        _ => Err((PathErrorKind::Syntax, "unknown G code")),
    }
}

/// The words of one block.
#[derive(Debug)]
pub(crate) struct Block {
    /// Value of each letter word (see [`slot`]).
    pub(crate) val: [f64; 28],
    /// Code index of each letter word, for error positions.
    pub(crate) at: [u32; 28],
    /// Which letter words are present.
    pub(crate) mask: u32,
    /// Which letter words are literal numbers written without a decimal point (`P500`, not
    /// `P0.5`, `P#1` or `P[500]`): Fanuc reads such a dwell time in milliseconds.
    pub(crate) no_point: u32,
    /// G code (× 10) of each modal group.
    pub(crate) g: [u16; group::N],
    /// Code index of each G word.
    pub(crate) g_at: [u32; group::N],
    /// Which groups have a G code.
    pub(crate) g_mask: u32,
    /// M0 M1 M2 M30 M60.
    pub(crate) m_stop: Option<u16>,
    /// Code index of the stop M code.
    pub(crate) m_stop_at: u32,
    /// M3 M4 M5.
    pub(crate) m_spindle: Option<u16>,
    /// M6.
    pub(crate) m6: bool,
    /// M98 (Fanuc subprogram call).
    pub(crate) m98: bool,
    /// M97 (Haas local subprogram call, Fanuc dialect).
    pub(crate) m97: bool,
    /// M99 (Fanuc subprogram return).
    pub(crate) m99: bool,
    /// Other M codes and their code index: reported as warnings.
    pub(crate) m_other: [(u16, u32); 8],
    /// How many of `m_other` are in use.
    pub(crate) n_other: usize,
    /// Fanuc: G80 shared the block with another motion code (the cycle is cancelled first).
    pub(crate) g80_too: bool,
    /// Fanuc: controller-mode G codes read and left out (see [`fanuc_mode`]), with their code
    /// index: reported as warnings.
    pub(crate) modes: [(u16, u32); 4],
    /// How many of `modes` are in use.
    pub(crate) n_modes: usize,
    /// Fanuc: the block's G76 (fine boring) is read as G86.
    pub(crate) fine_boring: bool,
    /// Fanuc: the block has G50.1 (programmable mirror image cancel), whose axis words name
    /// the axes it cancels and move nothing.
    pub(crate) mirror_cancel: bool,
    /// G70/G71 read as G20/G21 (Mach3's and old controls' inch/mm codes), with its code index.
    pub(crate) units_synonym: Option<(u16, u32, u32)>,
    /// The spindle a `$` word selects (LinuxCNC 2.8's several spindles: `M3 $0 S1000`; −1 all
    /// of them) and where the word starts.
    pub(crate) spindle: Option<(i32, u32)>,
    /// Parameter assignments, applied after the line is read.
    pub(crate) assigns: [(Target, f64); MAX_ASSIGNS],
    /// How many of `assigns` are in use.
    pub(crate) n_assigns: usize,
}

impl Default for Block {
    fn default() -> Self {
        Self {
            val: [0.0; 28],
            at: [0; 28],
            mask: 0,
            g: [0; group::N],
            g_at: [0; group::N],
            g_mask: 0,
            no_point: 0,
            m_stop: None,
            m_stop_at: 0,
            m_spindle: None,
            m6: false,
            m98: false,
            m97: false,
            m99: false,
            m_other: [(0, 0); 8],
            n_other: 0,
            g80_too: false,
            modes: [(0, 0); 4],
            n_modes: 0,
            fine_boring: false,
            mirror_cancel: false,
            units_synonym: None,
            spindle: None,
            assigns: [(Target::Num(0), 0.0); MAX_ASSIGNS],
            n_assigns: 0,
        }
    }
}

impl Block {
    fn clear(&mut self) {
        self.mask = 0;
        self.no_point = 0;
        self.g_mask = 0;
        self.m_stop = None;
        self.m_spindle = None;
        self.m6 = false;
        self.m98 = false;
        self.m97 = false;
        self.m99 = false;
        self.n_other = 0;
        self.n_assigns = 0;
        self.g80_too = false;
        self.n_modes = 0;
        self.fine_boring = false;
        self.mirror_cancel = false;
        self.units_synonym = None;
        self.spindle = None;
    }
    /// Whether letter `c` is present.
    #[inline]
    pub(crate) fn has(&self, c: u8) -> bool {
        self.mask & (1 << slot(c)) != 0
    }
    /// Whether letter `c` is present as a literal number without a decimal point.
    #[inline]
    pub(crate) fn without_point(&self, c: u8) -> bool {
        self.no_point & (1 << slot(c)) != 0
    }
    /// The value of letter `c`, if present.
    #[inline]
    pub(crate) fn get(&self, c: u8) -> Option<f64> {
        self.has(c).then(|| self.val[slot(c)])
    }
    /// The code span of letter `c` (its letter only).
    pub(crate) fn span(&self, c: u8) -> Span {
        let a = self.at[slot(c)] as usize;
        Span::Code(a, a + 1)
    }
    /// The G code of group `grp`, if present.
    #[inline]
    pub(crate) fn g(&self, grp: usize) -> Option<u16> {
        (self.g_mask & (1 << grp) != 0).then(|| self.g[grp])
    }
    /// The code span of the G word of group `grp`.
    pub(crate) fn g_span(&self, grp: usize) -> Span {
        let a = self.g_at[grp] as usize;
        Span::Code(a, a + 1)
    }
}

/// Reads the words of a normalised line into `b` (cleared first). Parameter references are
/// evaluated with `params`' values from before the line.
///
/// With `fanuc`, G80 may share the block with another motion code (`b.g80_too`).
/// What LinuxCNC's read-only numbered parameter `n` holds (`_readonly_parameters` in its
/// interpreter: the tool in the spindle, its offsets, diameter, angles and orientation, and the
/// current position); `None` for a parameter a program may set.
pub(crate) fn read_only_number(n: usize) -> Option<&'static str> {
    match n {
        5400 => Some("the tool in the spindle"),
        5401..=5409 => Some("an offset of the tool in the spindle"),
        5410 => Some("the diameter of the tool in the spindle"),
        5411..=5413 => Some("an angle or the orientation of the tool in the spindle"),
        5420..=5428 => Some("the current position"),
        _ => None,
    }
}

/// `X1e3`: an `e` written straight after a number's digits (no blank between) and followed by
/// a digit, a sign or a point is scientific notation, which G-code does not have: LinuxCNC
/// reads `X1` and an E word, which would move the tool to 1 where 1000 was meant. An error at
/// the number (code index `e_at` is the `e`).
fn scientific_notation(lb: &LineBuf, e_at: usize) -> Res<()> {
    let code = &lb.code;
    let numeric = |i: usize| matches!(code.get(i), Some(b'0'..=b'9' | b'.'));
    let adjacent = |i: usize| {
        i > 0 && i < lb.offs.len() && lb.offs[i] == lb.offs[i - 1] + 1 // no blank between
    };
    if e_at == 0 || !numeric(e_at - 1) || !adjacent(e_at) {
        return Ok(());
    }
    let mut end = e_at + 1;
    if matches!(code.get(end), Some(b'+' | b'-')) {
        end += 1;
    }
    if !numeric(end) || !adjacent(e_at + 1) {
        return Ok(());
    }
    while numeric(end) {
        end += 1;
    }
    let mut start = e_at;
    while start > 0 && (numeric(start - 1) || matches!(code[start - 1], b'+' | b'-')) {
        start -= 1;
    }
    let text = String::from_utf8_lossy(&code[start..end]).into_owned();
    Err(Fault::new(
        PathErrorKind::Syntax,
        Span::Code(start, end),
        format!(
            "`{text}` is scientific notation, which G-code does not have (LinuxCNC reads the \
             number before the `e` and an E word after it)"
        ),
        "a plain decimal number (1000, not 1e3)",
    ))
}

/// The parameters as a line's words read them: rs274 defines a named parameter when it reads
/// `#<name> =` (read_named_parameter_setting adds it, 0, before its value is read), so the
/// rest of the line, that value included, reads a name it did not know as 0.
struct LineParams<'a> {
    p: &'a dyn ParamRead,
    code: &'a [u8],
    defined: std::cell::RefCell<Vec<(usize, usize)>>,
}

impl ParamRead for LineParams<'_> {
    fn numbered(&self, n: usize) -> f64 {
        self.p.numbered(n)
    }
    fn named(&self, name: &str) -> Option<f64> {
        self.p.named(name).or_else(|| {
            self.defined
                .borrow()
                .iter()
                .any(|&(x, y)| &self.code[x..y] == name.as_bytes())
                .then_some(0.0)
        })
    }
    fn read_only_named(&self, name: &str) -> bool {
        self.p.read_only_named(name)
    }
    fn fanuc(&self) -> bool {
        self.p.fanuc()
    }
    fn ini_file(&self) -> Option<(&std::path::Path, bool)> {
        self.p.ini_file()
    }
}

pub(crate) fn parse(lb: &LineBuf, b: &mut Block, params: &dyn ParamRead, fanuc: bool) -> Res<()> {
    b.clear();
    let line_params = LineParams {
        p: params,
        code: &lb.code,
        defined: std::cell::RefCell::new(Vec::new()),
    };
    let params: &dyn ParamRead = if fanuc { params } else { &line_params };
    let mut c = Cur::new(&lb.code);
    let mut first = true;
    let mut units_clash = None;
    while let Some(ch) = c.peek() {
        let at = c.i;
        c.word_start = at;
        match ch {
            b'n' if first => {
                // Line number: digits (and a point, as LinuxCNC tolerates), value unused.
                c.i += 1;
                let s = c.i;
                while matches!(c.peek(), Some(b'0'..=b'9' | b'.')) {
                    c.i += 1;
                }
                if c.i == s {
                    return Err(Fault::syntax(
                        Span::Code(at, c.token_end(at)),
                        "bad line number",
                        "N followed by digits",
                    ));
                }
            }
            b'g' => {
                c.i += 1;
                let v = read_real(&mut c, params)?;
                if is_vacant(v) {
                    // Fanuc: a word whose value is a vacant variable is not written.
                    first = false;
                    continue;
                }
                let code10 = (v * 10.0).round();
                let span = Span::Code(at, c.i);
                if (v * 10.0 - code10).abs() > 1e-6 || !(0.0..=9999.0).contains(&code10) {
                    return Err(Fault::syntax(
                        span,
                        format!("unknown G code G{v}"),
                        "a G code",
                    ));
                }
                let mut code = code10 as u16;
                if fanuc && matches!(code, 150 | 501 | 670) {
                    // The cancels of a Fanuc safe-start line: polar coordinates (G15), the
                    // programmable mirror image (G50.1), a modal macro call (G67). The modes
                    // they cancel are refused (G16, G51.1, G66), so they are never on: read
                    // past, as G69 and G50 are.
                    b.mirror_cancel |= code == 501;
                    first = false;
                    continue;
                }
                if fanuc && fanuc_mode(code).is_some() {
                    if b.n_modes == b.modes.len() {
                        return Err(Fault::semantic(span, "too many controller-mode G codes"));
                    }
                    b.modes[b.n_modes] = (code, at as u32);
                    b.n_modes += 1;
                    first = false;
                    continue;
                }
                if !fanuc && matches!(code, 434 | 435 | 2340 | 541 | 1540) {
                    // (Tool centre point control is Fanuc's (G43.4, G43.5) and Haas's (G234),
                    // and so are the additional work offsets (G54.1, G154); LinuxCNC has
                    // none.)
                    return Err(Fault::syntax(
                        span,
                        format!(
                            "unknown G code {} (a Fanuc/Haas code: --dialect fanuc reads it)",
                            g_name(code)
                        ),
                        "a G code",
                    ));
                }
                if fanuc && code == 760 {
                    // Fanuc milling's G76 is fine boring (not LinuxCNC's threading): read as
                    // G86, whose path it follows but for the shift away from the wall (Q)
                    // before the retract.
                    code = 860;
                    b.fine_boring = true;
                }
                if matches!(code, 700 | 710) && b.units_synonym.is_none() {
                    // Mach3 (and Fanuc lathes in G-code system B/C) read G70/G71 as inch/mm;
                    // a block with other words is a lathe cycle (checked once the block is read).
                    b.units_synonym = Some((code, at as u32, c.i as u32));
                    code -= 500;
                }
                let grp = g_group(code).map_err(|(kind, m)| {
                    let name = g_name(code);
                    Fault::new(kind, span, format!("{name}: {m}"), "")
                })?;
                let other = b.g[grp];
                if fanuc
                    && grp == group::MOTION
                    && b.g_mask & (1 << grp) != 0
                    && (code == 800) != (other == 800)
                    && !b.g80_too
                {
                    // Fanuc: G80 (group 09) and G0–G3 (group 01) in one block.
                    b.g80_too = true;
                    if code == 800 {
                        first = false;
                        continue;
                    }
                } else if !fanuc
                    && grp == group::MOTION
                    && b.g_mask & (1 << grp) != 0
                    && (code == 800 || other == 800)
                {
                    // LinuxCNC (read_g): G80 beside another motion code yields to it, in
                    // either order (`G80 G0`, `G81 G80 X…`).
                    if code == 800 {
                        first = false;
                        continue;
                    }
                } else if b.g_mask & (1 << grp) != 0 {
                    // (G70/G71 by their own names: `G21 G71 U1.` is a lathe cycle, said below.)
                    let name = |code: u16, at: usize| match b.units_synonym {
                        Some((g, a, _)) if grp == group::UNITS && a as usize == at => g_name(g),
                        _ => g_name(code),
                    };
                    let clash = Fault::semantic(
                        span,
                        format!(
                            "{} and {} are in the same modal group",
                            name(b.g[grp], b.g_at[grp] as usize),
                            name(code, at)
                        ),
                    );
                    if grp != group::UNITS || b.units_synonym.is_none() {
                        return Err(clash);
                    }
                    units_clash.get_or_insert(clash);
                }
                b.g[grp] = code;
                b.g_at[grp] = at as u32;
                b.g_mask |= 1 << grp;
            }
            b'm' => {
                c.i += 1;
                let v = read_real(&mut c, params)?;
                if is_vacant(v) {
                    first = false;
                    continue;
                }
                let span = Span::Code(at, c.i);
                if v.fract() != 0.0 || !(0.0..=9999.0).contains(&v) {
                    return Err(Fault::syntax(
                        span,
                        format!("bad M code M{v}"),
                        "an integer M code",
                    ));
                }
                let m = v as u16;
                let dup =
                    |what: &str| Fault::semantic(span, format!("two {what} M codes on one line"));
                match m {
                    0 | 1 | 2 | 30 | 60 => {
                        if b.m_stop.replace(m).is_some() {
                            return Err(dup("program stop"));
                        }
                        b.m_stop_at = at as u32;
                    }
                    3..=5 => {
                        if b.m_spindle.replace(m).is_some() {
                            return Err(dup("spindle"));
                        }
                    }
                    6 => b.m6 = true,
                    98 => b.m98 = true,
                    97 if fanuc => b.m97 = true,
                    99 => b.m99 = true,
                    _ => {
                        if b.n_other == b.m_other.len() {
                            return Err(Fault::semantic(span, "too many M codes on one line"));
                        }
                        b.m_other[b.n_other] = (m, at as u32);
                        b.n_other += 1;
                    }
                }
            }
            b'#' => {
                c.i += 1;
                let target = if c.peek() == Some(b'<') {
                    let (x, y) = read_name(&mut c)?;
                    let name = std::str::from_utf8(&lb.code[x..y]).unwrap_or("");
                    if !fanuc && name.starts_with("_ini[") && params.read_only_named(name) {
                        // rs274's message for a value the INI gives.
                        return Err(Fault::semantic(
                            Span::Code(at, c.i),
                            format!("Cannot assign to read-only parameter #<{name}>"),
                        ));
                    }
                    if !fanuc && params.read_only_named(name) {
                        return Err(Fault::new(
                            PathErrorKind::Semantic,
                            Span::Code(at, c.i),
                            format!(
                                "#<{name}> is one of LinuxCNC's predefined (system) parameters, \
                                 which are read-only"
                            ),
                            "a parameter name of the program's own (a global: `_` and a name \
                             LinuxCNC does not predefine)",
                        ));
                    }
                    if !fanuc {
                        line_params.defined.borrow_mut().push((x, y));
                    }
                    Target::Named(x as u32, y as u32)
                } else {
                    let n = read_real(&mut c, params)?;
                    let n = assign_index(n, Span::Code(at, c.i), fanuc)?;
                    if let Some(what) = read_only_number(n).filter(|_| !fanuc) {
                        return Err(Fault::new(
                            PathErrorKind::Semantic,
                            Span::Code(at, c.i),
                            format!("parameter #{n} ({what}) is read-only"),
                            "a parameter other than #5400–#5413 and #5420–#5428",
                        ));
                    }
                    Target::Num(n)
                };
                if c.peek() != Some(b'=') {
                    return Err(c.unexpected("`=` in a parameter assignment"));
                }
                c.i += 1;
                c.word_start = c.i;
                // Fanuc Macro B writes the value without brackets: `#500=#500+1`. A value
                // that is a vacant variable alone (`#2=#1`) leaves the target vacant.
                let v = if fanuc {
                    read_infix(&mut c, params)?
                } else {
                    read_real(&mut c, params)?
                };
                if b.n_assigns == MAX_ASSIGNS {
                    return Err(Fault::new(
                        PathErrorKind::Limit,
                        Span::Code(at, c.i),
                        format!("more than {MAX_ASSIGNS} parameter assignments on one line"),
                        "",
                    ));
                }
                b.assigns[b.n_assigns] = (target, v);
                b.n_assigns += 1;
            }
            b'$' => {
                c.i += 1;
                let v = read_real(&mut c, params)?;
                if is_vacant(v) {
                    first = false;
                    continue;
                }
                if b.spindle.is_some() {
                    return Err(Fault::semantic(
                        Span::Code(at, c.i),
                        "two $ words on one line",
                    ));
                }
                if !(v.fract() == 0.0 && (-1.0..=99.0).contains(&v)) {
                    return Err(Fault::syntax(
                        Span::Code(at, c.i),
                        format!("spindle ${v}"),
                        "a spindle number: $0, $1 … ($-1: every spindle)",
                    ));
                }
                b.spindle = Some((v as i32, at as u32));
            }
            b'a'..=b'z' | b'@' | b'^' if !matches!(ch, b'n' | b'o') => {
                if ch == b'e' {
                    scientific_notation(lb, at)?;
                }
                c.i += 1;
                let v = read_real(&mut c, params)?;
                if is_vacant(v) {
                    // Fanuc: `G1 X#110 Y20.` with #110 vacant is `G1 Y20.` (not X0): as if
                    // the word were not written, so it is no second X word either.
                    first = false;
                    continue;
                }
                let s = slot(ch);
                if b.mask & (1 << s) != 0 {
                    return Err(Fault::semantic(
                        Span::Code(at, c.i),
                        format!(
                            "two {} words on one line",
                            (ch as char).to_ascii_uppercase()
                        ),
                    ));
                }
                if !v.is_finite() {
                    return Err(Fault::semantic(
                        Span::Code(at, c.i),
                        "value is not a finite number",
                    ));
                }
                b.val[s] = v;
                b.at[s] = at as u32;
                b.mask |= 1 << s;
                if literal_has_point(&lb.code, at) == Some(false) {
                    b.no_point |= 1 << s;
                }
            }
            _ => {
                let end = c.token_end(at);
                let what = if ch == b'o' {
                    "an O word must start the line"
                } else {
                    "unexpected text"
                };
                return Err(Fault::syntax(
                    Span::Code(at, end),
                    what,
                    "a letter starting a word (G1, X2.5…)",
                ));
            }
        }
        first = false;
    }
    if let Some((code, at, end)) = b.units_synonym {
        if b.mask != 0 {
            let (kind, m) = g_group(code)
                .err()
                .unwrap_or((PathErrorKind::Unsupported, ""));
            return Err(Fault::new(
                kind,
                Span::Code(at as usize, end as usize),
                format!("{}: {m}", g_name(code)),
                "",
            ));
        }
    }
    units_clash.map_or(Ok(()), Err)
}

/// `G59.1` from 591.
/// What a Fanuc/Haas controller-mode G code does, for the codes that change how the control
/// follows the programmed path (look-ahead, smoothing, high-speed modes), not the path itself:
/// read in the Fanuc dialect, reported and left out, with their P, Q and E words. (In
/// LinuxCNC, G5 and G5.1 are splines.)
pub(crate) fn fanuc_mode(code: u16) -> Option<(&'static str, &'static str)> {
    const FOLLOWS: &str = "it changes how the control follows the path, not the path";
    Some(match code {
        50 => ("high-precision contour control", FOLLOWS),
        51 => ("AI contour control", FOLLOWS),
        80 => ("AI look-ahead control", FOLLOWS),
        1030 => ("block look-ahead limit", FOLLOWS),
        1870 => ("smoothness and corner tolerance", FOLLOWS),
        2540 => (
            "Haas dynamic work offset",
            "its offset is not applied: X Y Z are read as the machine (--machine) reads them, \
             tool-tip positions in the part frame only on a `-tcp` machine",
        ),
        2550 => (
            "Haas dynamic work offset cancel",
            "X Y Z are read as the machine (--machine) reads them throughout",
        ),
        _ => return None,
    })
}

pub(crate) fn g_name(code: u16) -> String {
    if code % 10 == 0 {
        format!("G{}", code / 10)
    } else {
        format!("G{}.{}", code / 10, code % 10)
    }
}

/// Whether the value of the word whose letter stands at code index `at` is a literal number
/// written with a decimal point; `None` when it is not a literal (a parameter, an expression).
fn literal_has_point(code: &[u8], at: usize) -> Option<bool> {
    let rest = code.get(at + 1..)?;
    let rest = rest
        .strip_prefix(b"-")
        .or(rest.strip_prefix(b"+"))
        .unwrap_or(rest);
    let n = rest
        .iter()
        .take_while(|c| c.is_ascii_digit() || **c == b'.')
        .count();
    (n > 0).then(|| rest[..n].contains(&b'.'))
}

#[cfg(test)]
mod tests {
    use super::super::lexer::normalize;
    use super::*;

    struct Zero;
    impl ParamRead for Zero {
        fn numbered(&self, n: usize) -> f64 {
            n as f64
        }
        fn named(&self, _: &str) -> Option<f64> {
            None
        }
    }

    fn parsed(s: &str) -> Res<Block> {
        let mut lb = LineBuf::default();
        normalize(s, &mut lb)?;
        let mut b = Block::default();
        parse(&lb, &mut b, &Zero, false)?;
        Ok(b)
    }

    #[test]
    fn words_and_groups() {
        let b = parsed("N10 G1 g90 X1.5 y#2 Z[1+1] F100 M3 S1000 #3=4").unwrap();
        assert_eq!(b.g(group::MOTION), Some(10));
        assert_eq!(b.g(group::DISTANCE), Some(900));
        assert_eq!(b.get(b'x'), Some(1.5));
        assert_eq!(b.get(b'y'), Some(2.0));
        assert_eq!(b.get(b'z'), Some(2.0));
        assert_eq!(b.m_spindle, Some(3));
        assert_eq!(b.n_assigns, 1);
        let b = parsed("G59.1 G92.3 @1 ^45").unwrap();
        assert_eq!(b.g(group::COORD), Some(591));
        assert_eq!(b.g(group::NON_MODAL), Some(923));
        assert_eq!(b.get(b'^'), Some(45.0));
    }

    #[test]
    fn errors() {
        let e = parsed("G1 X1 X2").unwrap_err();
        assert_eq!(e.span, Span::Code(4, 6));
        let e = parsed("G0 G1").unwrap_err();
        assert_eq!(e.kind, PathErrorKind::Semantic);
        // (Probing is a motion code: not with another one.)
        let e = parsed("G38.2 G1 X1").unwrap_err();
        assert_eq!(e.kind, PathErrorKind::Semantic);
        assert_eq!(parsed("G1.5").unwrap_err().kind, PathErrorKind::Syntax);
        assert_eq!(parsed("G1 X1.2.3").unwrap_err().span, Span::Code(2, 8));
        assert!(parsed("G1 X").is_err());
        assert!(parsed("G1 %").is_err());
        assert!(parsed("#1 2").is_err());
    }
}
