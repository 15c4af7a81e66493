//! Numbers, parameter references and bracketed expressions, read from normalised code.
//!
//! The grammar and the arithmetic are LinuxCNC's: binary operators are left-associative with
//! the precedence `**` > `* / MOD` > `+ -` > `EQ NE GT GE LT LE` > `AND OR XOR`; `EQ`/`NE`
//! compare with LinuxCNC's tolerance of 0.0001; trigonometric functions work in degrees;
//! `ATAN[y]/[x]` is the two-argument arc tangent (Fanuc: 0° to 360°, also written `ATAN[y,x]`);
//! `ROUND` rounds half away from zero; `MOD` gives a result with the divisor's magnitude and a
//! non-negative sign, like LinuxCNC.
//!
//! Fanuc Custom Macro B has *vacant* (null) variables: `#0`, and the local and common
//! variables never assigned (see [`vacant`]). Where a value is a variable and nothing else it
//! stays vacant (`#2=#1` copies the vacancy, `X#1` is a word not written); where it enters
//! an operator, a function, a sign or brackets it is 0, except that `EQ` and `NE` tell it
//! from 0 (`#1 EQ #0` holds only when #1 is vacant, `#1 EQ 0` does not then).

use super::{Fault, Res, Span};
use crate::PathErrorKind;

/// Deepest nesting of brackets and unary operators: a line of ten thousand `[` must not
/// overflow the stack.
const MAX_DEPTH: u32 = 64;

/// LinuxCNC's `TOLERANCE_EQUAL`: two numbers compare `EQ` when closer than this.
const TOLERANCE_EQUAL: f64 = 0.0001;

/// Read access to parameters, so expressions can be evaluated without knowing the interpreter.
pub(crate) trait ParamRead {
    /// The value of numbered parameter `n` (already checked to be in range).
    fn numbered(&self, n: usize) -> f64;
    /// The value of a named parameter (name in lower case, without `#<` `>`), if it exists.
    fn named(&self, name: &str) -> Option<f64>;
    /// True for a named parameter the interpreter predefines (`_x`, `_motion_mode` …): a
    /// program cannot assign it.
    fn read_only_named(&self, _name: &str) -> bool {
        false
    }
    /// Read by Fanuc's rules: `FIX` truncates towards zero and `FUP` away from it (LinuxCNC
    /// floors and ceils), `ATAN` gives 0° to 360° and takes `ATAN[y,x]`.
    fn fanuc(&self) -> bool {
        false
    }
    /// The LinuxCNC INI file given, and whether `#<_ini[…]>` reads it (its `INI_VARS`).
    fn ini_file(&self) -> Option<(&std::path::Path, bool)> {
        None
    }
}

/// The highest parameter number (LinuxCNC's `RS274NGC_MAX_PARAMETERS` − 1).
pub(crate) const MAX_PARAM: usize = 5601;

/// The bits of [`vacant`]: a quiet NaN whose payload spells `VACANT` in ASCII.
const VACANT_BITS: u64 = 0x7ff8_5641_4341_4e54;

/// A Fanuc vacant variable's value, as the `f64` every value is.
///
/// Why a NaN payload rather than a separate bitset of vacant parameters or a tagged value:
/// vacancy must travel with values in flight, not only sit in the table (`#2=#1` copies it
/// into #2, `X#1` drops the word, `#1 EQ #0` compares it), so a bitset would still need the
/// evaluator, the block's word slots and its assignments to carry a tag beside each number.
/// As a NaN payload it rides in the same `f64` slots, and the LinuxCNC path keeps its types,
/// storage and arithmetic unchanged: nothing there makes this payload (its parameters start
/// at 0; `#0` is refused; a NaN from arithmetic on numbers carries the hardware's default
/// payload), so the cost there is one compare of bits where a value enters an operator, a
/// function or a word, never taken. It must never reach arithmetic (a NaN would propagate):
/// every operator, function, sign and bracket reads it through [`number`] first.
#[inline]
pub(crate) fn vacant() -> f64 {
    f64::from_bits(VACANT_BITS)
}

/// Whether `v` is a Fanuc vacant variable's value ([`vacant`]).
#[inline]
pub(crate) fn is_vacant(v: f64) -> bool {
    v.to_bits() == VACANT_BITS
}

/// `v` as a number: a vacant variable is 0 in an expression (Fanuc).
#[inline]
pub(crate) fn number(v: f64) -> f64 {
    if is_vacant(v) {
        0.0
    } else {
        v
    }
}

/// A cursor over normalised code.
pub(crate) struct Cur<'a> {
    pub(crate) code: &'a [u8],
    pub(crate) i: usize,
    /// Where the word being read starts: errors in its value quote the word from there.
    pub(crate) word_start: usize,
}

impl<'a> Cur<'a> {
    pub(crate) fn new(code: &'a [u8]) -> Self {
        Self {
            code,
            i: 0,
            word_start: 0,
        }
    }
    pub(crate) fn peek(&self) -> Option<u8> {
        self.code.get(self.i).copied()
    }
    pub(crate) fn at_end(&self) -> bool {
        self.i >= self.code.len()
    }
    pub(crate) fn starts_with(&self, s: &[u8]) -> bool {
        self.code[self.i.min(self.code.len())..].starts_with(s)
    }
    /// The end of the token starting at `from`: the next letter that starts a word.
    pub(crate) fn token_end(&self, from: usize) -> usize {
        let mut j = from + 1;
        let mut depth = 0i32;
        while j < self.code.len() {
            match self.code[j] {
                b'[' => depth += 1,
                b']' => depth -= 1,
                c if depth <= 0 && c.is_ascii_lowercase() => break,
                _ => {}
            }
            j += 1;
        }
        j.min(self.code.len())
    }
    fn expect(&mut self, c: u8, what: &str) -> Res<()> {
        if self.peek() == Some(c) {
            self.i += 1;
            Ok(())
        } else {
            Err(self.unexpected(what))
        }
    }
    /// An error about what stands at the cursor.
    pub(crate) fn unexpected(&self, expected: &str) -> Fault {
        let end = if self.at_end() { self.i } else { self.i + 1 };
        Fault::syntax(Span::Code(self.i, end), "unexpected text", expected)
    }
}

/// Reads a real value: a number, a parameter reference, a bracketed expression, a function call,
/// or one of those preceded by `+` or `-`.
pub(crate) fn read_real(c: &mut Cur<'_>, p: &dyn ParamRead) -> Res<f64> {
    real(c, p, 0)
}

/// Reads an infix expression without enclosing brackets, as a Fanuc control reads the value
/// of an assignment (`#500=#500+1`): values and operators for as long as an operator follows.
pub(crate) fn read_infix(c: &mut Cur<'_>, p: &dyn ParamRead) -> Res<f64> {
    binary(c, p, 1, 1)
}

fn real(c: &mut Cur<'_>, p: &dyn ParamRead, depth: u32) -> Res<f64> {
    let start = c.i;
    let v = real_value(c, p, depth)?;
    // LinuxCNC's read_real_value refuses a value that is not a number or infinite (`0**-1`,
    // `EXP[1000]`); a Fanuc vacant variable is a NaN and passes.
    if !p.fanuc() && !v.is_finite() {
        return Err(Fault::semantic(
            Span::Code(start, c.i),
            if v.is_nan() {
                "calculation resulted in 'not a number'"
            } else {
                "calculation resulted in 'infinity'"
            },
        ));
    }
    Ok(v)
}

fn real_value(c: &mut Cur<'_>, p: &dyn ParamRead, depth: u32) -> Res<f64> {
    if depth > MAX_DEPTH {
        return Err(Fault::new(
            PathErrorKind::Limit,
            Span::Code(c.i, c.i + 1),
            format!("expression nested more than {MAX_DEPTH} deep"),
            "",
        ));
    }
    match c.peek() {
        Some(b'0'..=b'9' | b'.') => read_number(c),
        Some(b'-' | b'+') => {
            // A signed literal is one number (so `-2**2` is 4, as in LinuxCNC).
            if matches!(c.code.get(c.i + 1), Some(b'0'..=b'9' | b'.')) {
                return read_number(c);
            }
            let neg = c.peek() == Some(b'-');
            c.i += 1;
            let v = number(real(c, p, depth + 1)?);
            Ok(if neg { -v } else { v })
        }
        Some(b'[') => {
            // A bracketed expression is a number: `[#1]` of a vacant #1 is 0.
            c.i += 1;
            let v = number(binary(c, p, depth + 1, 1)?);
            c.expect(b']', "an operator or `]`")?;
            Ok(v)
        }
        Some(b'#') => {
            c.i += 1;
            read_param(c, p, depth + 1)
        }
        Some(b'a'..=b'z') => function(c, p, depth + 1),
        _ => Err(c.unexpected("a number, `#`, `[` or a function")),
    }
}

/// Reads a literal number: optional sign, digits, optional point and digits.
pub(crate) fn read_number(c: &mut Cur<'_>) -> Res<f64> {
    let code = c.code;
    let start = c.i;
    let mut i = start;
    let neg = match code.get(i) {
        Some(b'-') => {
            i += 1;
            true
        }
        Some(b'+') => {
            i += 1;
            false
        }
        _ => false,
    };
    let mut mant: u64 = 0;
    let mut digits = 0u32;
    let mut frac = 0u32;
    let mut seen_dot = false;
    let mut exact = true;
    while let Some(&ch) = code.get(i) {
        match ch {
            b'0'..=b'9' => {
                if mant < 100_000_000_000_000_000 {
                    mant = mant * 10 + u64::from(ch - b'0');
                    if seen_dot {
                        frac += 1;
                    }
                } else {
                    exact = false;
                }
                digits += 1;
            }
            b'.' if !seen_dot => seen_dot = true,
            _ => break,
        }
        i += 1;
    }
    if digits == 0 {
        let ws = c.word_start.min(start);
        let end = c.token_end(ws);
        return Err(Fault::syntax(
            Span::Code(ws, end),
            "malformed number",
            "a number",
        ));
    }
    if matches!(code.get(i), Some(b'.')) {
        // `X1.2.3`: quote the whole word.
        let ws = c.word_start.min(start);
        let end = c.token_end(ws);
        return Err(Fault::syntax(
            Span::Code(ws, end),
            "malformed number",
            "a number",
        ));
    }
    c.i = i;
    // Clinger's fast path: both operands exact, one correctly rounded division.
    let v = if exact && mant < (1u64 << 53) && frac <= 22 {
        mant as f64 / POW10[frac as usize]
    } else {
        // Rare: more than 17 significant digits. The slice is ASCII digits, sign and point.
        let s = std::str::from_utf8(&code[start..i]).unwrap_or("0");
        let s = s.trim_start_matches(['+', '-']);
        s.parse::<f64>().unwrap_or(f64::NAN).abs()
    };
    Ok(if neg { -v } else { v })
}

const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// After `#`: `<name>` or a real value giving the parameter number. Fanuc: `#0` is vacant.
fn read_param(c: &mut Cur<'_>, p: &dyn ParamRead, depth: u32) -> Res<f64> {
    let start = c.i.saturating_sub(1);
    if c.peek() == Some(b'<') {
        let (a, b) = read_name(c)?;
        let name = std::str::from_utf8(&c.code[a..b]).unwrap_or("");
        return p.named(name).ok_or_else(|| {
            let lower = name.to_ascii_lowercase();
            if let (true, Some((ini, vars))) = (lower.starts_with("_ini["), p.ini_file()) {
                return Fault::semantic(
                    Span::Code(start, c.i),
                    if vars {
                        format!(
                            "#<{name}> is not a number of the INI file {} (named parameter \
                             #<{name}> not defined)",
                            ini.display()
                        )
                    } else {
                        format!(
                            "#<{name}> is not read: the INI file {} sets [RS274NGC] INI_VARS = 0",
                            ini.display()
                        )
                    },
                );
            }
            let source = if lower.starts_with("_ini[") {
                Some("a value of LinuxCNC's INI file")
            } else if lower.starts_with("_hal[") {
                Some("a LinuxCNC HAL pin or parameter")
            } else {
                None
            };
            match source {
                Some(what) => Fault::new(
                    crate::PathErrorKind::Unsupported,
                    Span::Code(start, c.i),
                    format!(
                        "#<{name}> reads {what}, which swarf does not have (it simulates the \
                         program alone, with no INI file or HAL)"
                    ),
                    "a number in its place: replace the parameter with the value it has on \
                     the machine",
                ),
                None => Fault::semantic(
                    Span::Code(start, c.i),
                    format!("named parameter #<{name}> is not defined"),
                ),
            }
        });
    }
    let n = number(real(c, p, depth)?);
    if p.fanuc() && is_zero_index(n) {
        return Ok(vacant());
    }
    let idx = param_index(n, Span::Code(start, c.i))?;
    Ok(p.numbered(idx))
}

/// Whether `n` names parameter 0 (rounded as [`param_index`] rounds).
fn is_zero_index(n: f64) -> bool {
    n.round() == 0.0 && n.abs() <= 1e-6
}

/// Reads `<name>` at the cursor; returns the code range of the name.
pub(crate) fn read_name(c: &mut Cur<'_>) -> Res<(usize, usize)> {
    c.expect(b'<', "`<`")?;
    let a = c.i;
    while let Some(ch) = c.peek() {
        if ch == b'>' {
            break;
        }
        c.i += 1;
    }
    let b = c.i;
    if c.at_end() {
        return Err(Fault::syntax(
            Span::Code(a.saturating_sub(1), b),
            "parameter name is not closed",
            "`>`",
        ));
    }
    c.i += 1;
    if a == b {
        return Err(Fault::syntax(
            Span::Code(a - 1, c.i),
            "empty parameter name",
            "a name between `<` and `>`",
        ));
    }
    Ok((a, b))
}

/// Checks that `n` names a numbered parameter.
pub(crate) fn param_index(n: f64, span: Span) -> Res<usize> {
    let r = n.round();
    if !(n - r).abs().le(&1e-6) || !(1.0..=MAX_PARAM as f64).contains(&r) {
        return Err(Fault::new(
            PathErrorKind::Semantic,
            span,
            format!("parameter number {n} is out of range"),
            format!("an integer from 1 to {MAX_PARAM}"),
        ));
    }
    Ok(r as usize)
}

/// The parameter an assignment writes, `n` read after its `#` (`span`: from the `#`): as
/// [`param_index`], and under Fanuc's rules `#0`, always vacant, cannot be assigned (an
/// alarm on the control). `n` may be a vacant variable's value (`#[#1]=…`), which is 0.
pub(crate) fn assign_index(n: f64, span: Span, fanuc: bool) -> Res<usize> {
    let n = number(n);
    if fanuc && is_zero_index(n) {
        return Err(Fault::new(
            PathErrorKind::Semantic,
            span,
            "#0 is always vacant: it cannot be assigned",
            format!("a variable from #1 to #{MAX_PARAM}"),
        ));
    }
    param_index(n, span)
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Op {
    Pow,
    Mul,
    Div,
    Mod,
    Add,
    Sub,
    Eq,
    Ne,
    Gt,
    Ge,
    Lt,
    Le,
    And,
    Or,
    Xor,
}

impl Op {
    fn precedence(self) -> u8 {
        match self {
            Op::Pow => 6,
            Op::Mul | Op::Div | Op::Mod => 5,
            Op::Add | Op::Sub => 4,
            Op::Eq | Op::Ne | Op::Gt | Op::Ge | Op::Lt | Op::Le => 3,
            Op::And | Op::Or | Op::Xor => 2,
        }
    }
}

fn peek_op(c: &Cur<'_>) -> Option<(Op, usize)> {
    let rest = &c.code[c.i.min(c.code.len())..];
    const WORDS: [(&[u8], Op); 15] = [
        (b"**", Op::Pow),
        (b"*", Op::Mul),
        (b"/", Op::Div),
        (b"mod", Op::Mod),
        (b"+", Op::Add),
        (b"-", Op::Sub),
        (b"eq", Op::Eq),
        (b"ne", Op::Ne),
        (b"gt", Op::Gt),
        (b"ge", Op::Ge),
        (b"lt", Op::Lt),
        (b"le", Op::Le),
        (b"and", Op::And),
        (b"or", Op::Or),
        (b"xor", Op::Xor),
    ];
    WORDS
        .iter()
        .find(|(w, _)| rest.starts_with(w))
        .map(|&(w, op)| (op, w.len()))
}

/// Precedence climbing; every operator is left-associative, as in LinuxCNC.
fn binary(c: &mut Cur<'_>, p: &dyn ParamRead, depth: u32, min: u8) -> Res<f64> {
    let mut lhs = real(c, p, depth)?;
    while let Some((op, len)) = peek_op(c) {
        let prec = op.precedence();
        if prec < min {
            break;
        }
        let op_at = c.i;
        c.i += len;
        let rhs = binary(c, p, depth + 1, prec + 1)?;
        lhs =
            apply(op, lhs, rhs).map_err(|m| Fault::semantic(Span::Code(op_at, op_at + len), m))?;
    }
    Ok(lhs)
}

fn truth(b: bool) -> f64 {
    if b {
        1.0
    } else {
        0.0
    }
}

/// One binary operation, with LinuxCNC's domain errors. A vacant operand (Fanuc) is 0, but
/// for `EQ` and `NE`, by which it equals only another vacant one.
fn apply(op: Op, a: f64, b: f64) -> Result<f64, String> {
    let (va, vb) = (is_vacant(a), is_vacant(b));
    let (a, b) = (number(a), number(b));
    Ok(match op {
        Op::Pow => {
            if a < 0.0 && b.fract() != 0.0 {
                return Err("attempt to raise a negative number to a non-integer power".into());
            }
            a.powf(b)
        }
        Op::Mul => a * b,
        Op::Div => {
            if b == 0.0 {
                return Err("division by zero".into());
            }
            a / b
        }
        Op::Mod => {
            if b == 0.0 {
                return Err("MOD by zero".into());
            }
            let r = a % b;
            if r < 0.0 {
                r + b.abs()
            } else {
                r
            }
        }
        Op::Add => a + b,
        Op::Sub => a - b,
        Op::Eq | Op::Ne if va || vb => truth((va == vb) == (op == Op::Eq)),
        Op::Eq => truth((a - b).abs() < TOLERANCE_EQUAL),
        Op::Ne => truth((a - b).abs() >= TOLERANCE_EQUAL),
        Op::Gt => truth(a > b),
        Op::Ge => truth(a >= b),
        Op::Lt => truth(a < b),
        Op::Le => truth(a <= b),
        Op::And => truth(a != 0.0 && b != 0.0),
        Op::Or => truth(a != 0.0 || b != 0.0),
        Op::Xor => truth((a != 0.0) != (b != 0.0)),
    })
}

fn function(c: &mut Cur<'_>, p: &dyn ParamRead, depth: u32) -> Res<f64> {
    const NAMES: [&[u8]; 14] = [
        b"acos", b"asin", b"atan", b"abs", b"cos", b"exists", b"exp", b"fix", b"fup", b"ln",
        b"round", b"sin", b"sqrt", b"tan",
    ];
    let start = c.i;
    let Some(name) = NAMES.iter().copied().find(|n| c.starts_with(n)) else {
        if c.word_start < start {
            // `Q X1`: the Q word has no value.
            return Err(Fault::syntax(
                Span::Code(c.word_start, start),
                "word without a value",
                "a number",
            ));
        }
        let end = c.token_end(start);
        return Err(Fault::syntax(
            Span::Code(start, end),
            "unknown word or function",
            "a number, a parameter, `[` or one of ABS ACOS ASIN ATAN COS EXISTS EXP FIX FUP LN ROUND SIN SQRT TAN",
        ));
    };
    c.i += name.len();
    if c.peek() != Some(b'[') {
        return Err(c.unexpected("`[` after the function name"));
    }
    if name == b"exists" {
        c.i += 1;
        c.expect(b'#', "`#<name>` or `#number`")?;
        if c.peek() != Some(b'<') {
            // rs274 (read_parameter with check_exists): a numbered parameter exists when its
            // number, read as any value (`EXISTS[##1]`), is in range; out of range is 0, not
            // an error.
            let at = c.i;
            let n = number(real(c, p, depth)?);
            c.expect(b']', "`]`")?;
            let r = n.round();
            if (n - r).abs() > 1e-4 {
                return Err(Fault::semantic(
                    Span::Code(at, c.i - 1),
                    format!("parameter number {n} is not an integer"),
                ));
            }
            return Ok(truth((1.0..=MAX_PARAM as f64).contains(&r)));
        }
        let (a, b) = read_name(c)?;
        c.expect(b']', "`]`")?;
        let nm = std::str::from_utf8(&c.code[a..b]).unwrap_or("");
        return Ok(truth(p.named(nm).is_some()));
    }
    if name == b"atan" {
        return atan(c, p, depth);
    }
    let arg = number(real(c, p, depth)?);
    let span = Span::Code(start, c.i);
    let dom = |ok: bool, what: &str| -> Res<()> {
        if ok {
            Ok(())
        } else {
            Err(Fault::semantic(
                span,
                format!("argument {arg} out of range for {what}"),
            ))
        }
    };
    Ok(match name {
        b"acos" => {
            dom((-1.0..=1.0).contains(&arg), "ACOS")?;
            arg.acos().to_degrees()
        }
        b"asin" => {
            dom((-1.0..=1.0).contains(&arg), "ASIN")?;
            arg.asin().to_degrees()
        }
        b"abs" => arg.abs(),
        b"cos" => arg.to_radians().cos(),
        b"exp" => arg.exp(),
        b"fix" if p.fanuc() => arg.trunc(),
        b"fup" if p.fanuc() => arg.signum() * arg.abs().ceil(),
        b"fix" => arg.floor(),
        b"fup" => arg.ceil(),
        b"ln" => {
            dom(arg > 0.0, "LN")?;
            arg.ln()
        }
        b"round" => arg.round(),
        b"sin" => arg.to_radians().sin(),
        b"sqrt" => {
            dom(arg >= 0.0, "SQRT")?;
            arg.sqrt()
        }
        _ => arg.to_radians().tan(),
    })
}

/// The two-argument arc tangent after `ATAN` (at its `[`), in degrees: `ATAN[y]/[x]`, and a
/// Fanuc 30i's `ATAN[y,x]`, which means the same. LinuxCNC's result is −180° to 180°, a Fanuc
/// control's 0° to 360° (parameter NAT = 0, its default): `ATAN[-1]/[-1]` is −135 and 225.
fn atan(c: &mut Cur<'_>, p: &dyn ParamRead, depth: u32) -> Res<f64> {
    c.expect(b'[', "`[` after the function name")?;
    let y = number(binary(c, p, depth + 1, 1)?);
    let x = if p.fanuc() && c.peek() == Some(b',') {
        c.i += 1;
        let x = number(binary(c, p, depth + 1, 1)?);
        c.expect(b']', "an operator or `]`")?;
        x
    } else {
        c.expect(
            b']',
            if p.fanuc() {
                "an operator, `,` or `]`"
            } else {
                "an operator or `]`"
            },
        )?;
        if c.peek() != Some(b'/') || c.code.get(c.i + 1) != Some(&b'[') {
            return Err(c.unexpected("`/[x]` after ATAN[y]"));
        }
        c.i += 1;
        number(real(c, p, depth)?)
    };
    let deg = y.atan2(x).to_degrees();
    Ok(if p.fanuc() && deg < 0.0 {
        deg + 360.0
    } else {
        deg
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    struct P(HashMap<String, f64>);
    impl ParamRead for P {
        fn numbered(&self, n: usize) -> f64 {
            n as f64 * 10.0
        }
        fn named(&self, name: &str) -> Option<f64> {
            self.0.get(name).copied()
        }
    }

    fn ev(s: &str) -> Res<f64> {
        let p = P([("a".to_string(), 2.5)].into_iter().collect());
        let mut c = Cur::new(s.as_bytes());
        let v = read_real(&mut c, &p)?;
        assert!(c.at_end(), "left over in {s}");
        Ok(v)
    }

    #[test]
    fn numbers() {
        assert_eq!(ev("1.5").unwrap(), 1.5);
        assert_eq!(ev("-.5").unwrap(), -0.5);
        assert_eq!(ev("+3.").unwrap(), 3.0);
        assert_eq!(ev("0.1").unwrap(), 0.1);
        assert_eq!(
            ev("123456789012345678901234.5").unwrap(),
            123456789012345678901234.5
        );
        assert_eq!(ev("0.000000000000000000000000001").unwrap(), 1e-27);
        assert!(ev("1.2.3").is_err());
        assert!(ev(".").is_err());
    }

    #[test]
    fn precedence_and_associativity() {
        assert_eq!(ev("[1+2*3]").unwrap(), 7.0);
        assert_eq!(ev("[2**3**2]").unwrap(), 64.0);
        assert_eq!(ev("[10-4-3]").unwrap(), 3.0);
        assert_eq!(ev("[12/2/3]").unwrap(), 2.0);
        assert_eq!(ev("[-2**2]").unwrap(), 4.0);
        // Unary minus binds to its operand, like the sign of a literal.
        assert_eq!(ev("[-[2]**2]").unwrap(), 4.0);
        assert_eq!(ev("[0-[2]**2]").unwrap(), -4.0);
        assert_eq!(ev("[1+1eq2]").unwrap(), 1.0);
        assert_eq!(ev("[1lt2and3gt4]").unwrap(), 0.0);
        assert_eq!(ev("[1or0xor1]").unwrap(), 0.0);
        assert_eq!(ev("[-7mod3]").unwrap(), 2.0);
        assert_eq!(ev("[7mod-3]").unwrap(), 1.0);
        assert_eq!(ev("[1eq1.00001]").unwrap(), 1.0);
        assert_eq!(ev("[1ne1.001]").unwrap(), 1.0);
    }

    #[test]
    fn functions_and_params() {
        assert!((ev("atan[1]/[-1]").unwrap() - 135.0).abs() < 1e-12);
        assert!((ev("sin[30]").unwrap() - 0.5).abs() < 1e-15);
        assert!((ev("acos[0]").unwrap() - 90.0).abs() < 1e-12);
        assert_eq!(ev("round[-2.5]").unwrap(), -3.0);
        assert_eq!(ev("fix[-2.5]").unwrap(), -3.0);
        assert_eq!(ev("fup[2.1]").unwrap(), 3.0);
        assert_eq!(ev("sqrt[16]").unwrap(), 4.0);
        assert!((ev("ln[exp[2]]").unwrap() - 2.0).abs() < 1e-15);
        assert_eq!(ev("abs[-3]").unwrap(), 3.0);
        assert_eq!(ev("exists[#<a>]").unwrap(), 1.0);
        assert_eq!(ev("exists[#<b>]").unwrap(), 0.0);
        // Numbered parameters as rs274 2.9 (tests/interp/exists): in range exists, out of
        // range reads 0; the number may itself be read from a parameter.
        assert_eq!(ev("exists[#1]").unwrap(), 1.0);
        assert_eq!(ev("exists[#5601]").unwrap(), 1.0);
        assert_eq!(ev("exists[#99999]").unwrap(), 0.0);
        assert_eq!(ev("exists[#0]").unwrap(), 0.0);
        assert_eq!(ev("exists[#[2+3]]").unwrap(), 1.0);
        assert!(ev("exists[#1.5]").is_err());
        assert_eq!(ev("#<a>").unwrap(), 2.5);
        assert_eq!(ev("#3").unwrap(), 30.0);
        assert_eq!(ev("-#[1+1]").unwrap(), -20.0);
        assert!(ev("#<b>").is_err());
        assert!(ev("#0").is_err());
        assert!(ev("#1.5").is_err());
        assert!(ev("sqrt[-1]").is_err());
        assert!(ev("[1/0]").is_err());
        assert!(ev("[[-8]**0.5]").is_err());
        assert!(ev("acos[2]").is_err());
        assert!(ev("foo[1]").is_err());
        assert!(ev("[1+2").is_err());
    }

    /// Fanuc's rules, with #1 vacant and #2 = 0.
    struct Fanuc;
    impl ParamRead for Fanuc {
        fn numbered(&self, n: usize) -> f64 {
            if n == 1 {
                vacant()
            } else {
                0.0
            }
        }
        fn named(&self, _: &str) -> Option<f64> {
            None
        }
        fn fanuc(&self) -> bool {
            true
        }
    }

    #[test]
    fn vacant_variables() {
        let ev = |s: &str| -> f64 {
            let mut c = Cur::new(s.as_bytes());
            let v = read_infix(&mut c, &Fanuc).unwrap();
            assert!(c.at_end(), "left over in {s}");
            v
        };
        // Alone, a variable keeps its vacancy; in arithmetic, signs, brackets and functions
        // it is 0.
        assert!(is_vacant(ev("#1")) && is_vacant(ev("#0")) && is_vacant(ev("#[#1]")));
        assert!(!is_vacant(ev("#2")));
        for s in [
            "#1*5",
            "#1+#1",
            "-#1",
            "[#1]",
            "abs[#1]",
            "atan[#1,1]",
            "#0+0",
        ] {
            assert_eq!(number(ev(s)), 0.0, "{s}");
            assert!(!ev(s).is_nan(), "{s}");
        }
        assert_eq!(ev("#1+2"), 2.0);
        // EQ and NE tell vacant from 0; the other comparisons take it as 0.
        let truth = |s: &str| ev(&format!("[{s}]"));
        assert_eq!(truth("#1eq#0"), 1.0);
        assert_eq!(truth("#2eq#0"), 0.0);
        assert_eq!(truth("#1eq0"), 0.0);
        assert_eq!(truth("#1ne0"), 1.0);
        assert_eq!(truth("#1ne#0"), 0.0);
        assert_eq!(truth("#2ne#0"), 1.0);
        assert_eq!(truth("#1ge#0"), 1.0);
        assert_eq!(truth("#1gt0"), 0.0);
        assert_eq!(truth("#1lt1"), 1.0);
        assert_eq!(truth("#1le-1"), 0.0);
        assert_eq!(truth("[#1]eq0"), 1.0);
        // The target of an assignment: #0 is refused by Fanuc's rules, by LinuxCNC's as out
        // of range.
        let e = assign_index(0.0, Span::Line, true).unwrap_err();
        assert!(e.message.contains("vacant"), "{e:?}");
        assert!(assign_index(vacant(), Span::Line, true).is_err());
        let e = assign_index(0.0, Span::Line, false).unwrap_err();
        assert!(e.message.contains("out of range"), "{e:?}");
        assert_eq!(assign_index(7.0, Span::Line, true).unwrap(), 7);
    }

    #[test]
    fn deep_nesting_is_a_limit_not_a_crash() {
        let s = "[".repeat(10_000) + "1" + &"]".repeat(10_000);
        let e = ev(&s).unwrap_err();
        assert_eq!(e.kind, PathErrorKind::Limit);
        let s = "-".repeat(10_000) + "#1";
        assert_eq!(ev(&s).unwrap_err().kind, PathErrorKind::Limit);
    }
}
