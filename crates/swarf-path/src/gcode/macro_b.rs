//! Fanuc Custom Macro B control flow (Fanuc dialect only): `GOTO n`, `IF [cond] GOTO n`,
//! `IF [cond] THEN #i = expr`, `WHILE [cond] DO m` … `END m`; assignments without brackets
//! (`#500 = #500 + 1`) are read by `block`.
//!
//! As a Fanuc control runs them: a `GOTO` goes to the first block numbered `N n` in the file
//! (its number an expression); a `WHILE` whose condition is false goes on after its `END m`; an
//! `END m` goes back to its `WHILE`, which tests the condition again; a `GOTO` may leave a loop.
//! A `WHILE` with no `END m` after it, and a loop numbered other than 1–3, are errors (alarms
//! on the control). Each loop pass and each `GOTO` counts against the reader's loop limit, so a
//! program that never ends stops with an error instead of hanging.

use super::expr::{assign_index, number, read_infix, read_real, Cur};
use super::interp::Interp;
use super::lexer::{normalize, skip_line_number, LineBuf};
use super::stack::{Cursor, Frame};
use super::{Fault, Res, Span};
use std::collections::HashMap;

/// An open `WHILE … DO m` loop: its number, where its line starts, and the call level (M98
/// subprograms) it is open at.
pub(crate) type MacroLoop = (u64, Cursor, usize);

impl Interp<'_, '_> {
    /// Executes a Macro B line; `at` is where its code starts (after any `N` number).
    pub(crate) fn exec_macro_b(&mut self, lb: &LineBuf, at: usize) -> Res<()> {
        let code = &lb.code[..];
        let here = Cursor {
            pos: self.cur_start,
            line: self.cur_line - 1,
            file: self.cur_file,
        };
        let span = Span::Code(at, code.len());
        let mut c = Cur::new(code);
        let rest = &code[at..];
        if rest.starts_with(b"goto") {
            c.i = at + 4;
            let n = number(read_real(&mut c, self)?);
            end_of_line(&c)?;
            return self.macro_goto(n, span);
        }
        if rest.starts_with(b"if") {
            c.i = at + 2;
            // (A vacant variable is 0 as a condition or a block number.)
            let cond = number(read_real(&mut c, self)?);
            let then = &code[c.i..];
            if then.starts_with(b"goto") {
                c.i += 4;
                let n = number(read_real(&mut c, self)?);
                end_of_line(&c)?;
                return if cond != 0.0 {
                    self.macro_goto(n, span)
                } else {
                    Ok(())
                };
            }
            if then.starts_with(b"then#") {
                c.i += 5;
                let hash = c.i - 1;
                let n = read_real(&mut c, self)?;
                let target = assign_index(n, Span::Code(hash, c.i), true)?;
                if c.peek() != Some(b'=') {
                    return Err(c.unexpected("`=` in the assignment after THEN"));
                }
                c.i += 1;
                let v = read_infix(&mut c, self)?;
                end_of_line(&c)?;
                if cond != 0.0 {
                    self.set_numbered(target, v);
                }
                return Ok(());
            }
            return Err(c.unexpected("GOTO n or THEN #i = value after the condition"));
        }
        if rest.starts_with(b"while") {
            c.i = at + 5;
            let cond = number(read_real(&mut c, self)?);
            if !code[c.i..].starts_with(b"do") {
                return Err(c.unexpected("DO m after the condition"));
            }
            c.i += 2;
            let m = loop_number(&mut c, "DO")?;
            end_of_line(&c)?;
            let level = self.frames.len();
            let open = self.macro_loops.iter().position(|&l| l == (m, here, level));
            if cond != 0.0 {
                match open {
                    // Back from its END: the next pass.
                    Some(k) => {
                        self.macro_loops.truncate(k + 1);
                        self.count_iteration(span)?;
                    }
                    None => {
                        // A loop whose END never comes is an alarm at its WHILE on a control,
                        // not a program that runs once through.
                        self.end_of_loop(m, span)?;
                        self.macro_loops.push((m, here, level));
                    }
                }
                return Ok(());
            }
            if let Some(k) = open {
                self.macro_loops.truncate(k);
            }
            self.at = self.end_of_loop(m, span)?;
            return Ok(());
        }
        if rest.starts_with(b"end") {
            c.i = at + 3;
            let m = loop_number(&mut c, "END")?;
            end_of_line(&c)?;
            let level = self.frames.len();
            let open = self.macro_loops.iter().rev();
            let Some(&(_, head, _)) = open.filter(|l| l.2 == level).find(|l| l.0 == m) else {
                return Err(Fault::semantic(
                    span,
                    format!("END{m} without a WHILE … DO{m} open before it"),
                ));
            };
            self.at = head;
            return Ok(());
        }
        Err(c.unexpected("GOTO, IF, WHILE or END"))
    }

    /// `GOTO n`: on from the block numbered `N n` of the current program (the main program or
    /// the M98 subprogram running): the first after the current block, else the first from
    /// the program's start, as a Fanuc control searches.
    fn macro_goto(&mut self, n: f64, span: Span) -> Res<()> {
        self.count_iteration(span)?;
        let start = match self.frames.last() {
            Some(Frame {
                fanuc: Some((start, _)),
                ..
            }) => *start,
            _ => self.file_start(self.cur_file),
        };
        let key = (start.file, start.pos);
        if !self.goto_index.contains_key(&key) {
            let index = self.index_program(start);
            self.goto_index.insert(key, index);
        }
        let here = self.cur_start;
        let target = (n >= 0.0 && n.fract() == 0.0)
            .then(|| self.goto_index[&key].get(&(n as u64)))
            .flatten()
            .and_then(|at| at.iter().find(|c| c.pos > here).or(at.first()).copied());
        let Some(target) = target else {
            return Err(Fault::semantic(
                span,
                format!("GOTO {n}: no block numbered N{n} in this program"),
            ));
        };
        self.at = target;
        Ok(())
    }

    /// Where each `N n` of the program starting at `start` is (in order): from there to the
    /// next `O` label or `%` (leading ones skipped), as a Fanuc program ends.
    fn index_program(&mut self, start: Cursor) -> HashMap<u64, Vec<Cursor>> {
        let text = self.text.clone();
        let mut buf = LineBuf::default();
        let mut map: HashMap<u64, Vec<Cursor>> = HashMap::new();
        let mut body = false;
        for (raw, line, _) in start.lines(&text) {
            if normalize(raw, &mut buf).is_err() || buf.code.is_empty() {
                continue;
            }
            let o = skip_line_number(&buf.code);
            let label = buf.code.first() == Some(&b'%')
                || (buf.code.get(o) == Some(&b'o')
                    && buf.code.len() > o + 1
                    && buf.code[o + 1..].iter().all(u8::is_ascii_digit));
            if label {
                if body {
                    break;
                }
                continue;
            }
            body = true;
            if buf.code.first() == Some(&b'n') {
                let digits = &buf.code[1..o];
                if let Some(n) = std::str::from_utf8(digits)
                    .ok()
                    .and_then(|d| d.parse().ok())
                {
                    map.entry(n).or_default().push(line);
                }
            }
        }
        map
    }

    /// Where reading goes on after the `END m` that closes the loop of the `WHILE … DO m` just
    /// read (the line after it): the first `END m` after the WHILE in its file, found once per
    /// WHILE.
    fn end_of_loop(&mut self, m: u64, span: Span) -> Res<Cursor> {
        let key = (self.cur_file, self.cur_start);
        if let Some(&at) = self.loop_ends.get(&key) {
            return Ok(at);
        }
        let text = self.text.clone();
        let mut buf = LineBuf::default();
        for (raw, _, at) in self.at.lines(&text) {
            if !raw.bytes().any(|b| b | 0x20 == b'e') || normalize(raw, &mut buf).is_err() {
                continue;
            }
            let code = &buf.code[skip_line_number(&buf.code)..];
            if let Some(digits) = code.strip_prefix(b"end") {
                let mut c = Cur::new(digits);
                if loop_number(&mut c, "END").ok() == Some(m) && c.at_end() {
                    self.loop_ends.insert(key, at);
                    return Ok(at);
                }
            }
        }
        Err(Fault::semantic(
            span,
            format!("WHILE … DO{m} without its END{m} after it in this file"),
        ))
    }
}

/// A loop number `m` of `DO m` / `END m` (`word`): 1, 2 or 3, as a Fanuc control numbers
/// them (others are an alarm).
fn loop_number(c: &mut Cur<'_>, word: &str) -> Res<u64> {
    let start = c.i;
    while matches!(c.peek(), Some(b'0'..=b'9')) {
        c.i += 1;
    }
    let m: u64 = std::str::from_utf8(&c.code[start..c.i])
        .ok()
        .and_then(|s| s.parse().ok())
        .ok_or_else(|| c.unexpected("a loop number (DO1, END1)"))?;
    if !(1..=3).contains(&m) {
        return Err(Fault::new(
            crate::PathErrorKind::Semantic,
            Span::Code(start, c.i),
            format!("{word}{m}: Fanuc's loops are {word}1, {word}2 and {word}3"),
            format!("{word}1, {word}2 or {word}3"),
        ));
    }
    Ok(m)
}

fn end_of_line(c: &Cur<'_>) -> Res<()> {
    if c.at_end() {
        Ok(())
    } else {
        Err(c.unexpected("the end of the line"))
    }
}
