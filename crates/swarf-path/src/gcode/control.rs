//! O-word control flow (`sub`/`endsub`/`call`/`return`, `while`/`endwhile`, `do`/`while`,
//! `repeat`/`endrepeat`, `if`/`elseif`/`else`/`endif`, `break`, `continue`) and Fanuc
//! subprograms (`M98 P<n> L<count>` calling `O<n>` … `M99` in the same file).
//!
//! Like LinuxCNC, control lines are matched by their O name, not by nesting: `o100 if` ends at
//! `o100 endif`. Jumps move the reading cursor; a forward jump scans lines until the matching
//! O-word, a backward jump returns to a remembered cursor. Every backward jump counts against
//! [`GcodeOptions::max_loop_iterations`](super::GcodeOptions) and calls against
//! `max_call_depth`, so no program can run forever or exhaust memory.

use std::collections::HashMap;
use std::rc::Rc;

use super::block::Block;
use super::expr::{number, read_real, Cur, ParamRead};
use super::interp::Interp;
use super::lexer::{normalize, skip_line_number, LineBuf};
use super::params::N_ARGS;
use super::stack::{Ctl, Cursor, Frame, Kw, LoopKind};
use super::{Fault, Res, Span};
use crate::PathErrorKind;

const KEYWORDS: [(&[u8], Kw); 15] = [
    (b"endsub", Kw::Endsub),
    (b"endwhile", Kw::Endwhile),
    (b"endif", Kw::Endif),
    (b"endrepeat", Kw::Endrepeat),
    (b"elseif", Kw::Elseif),
    (b"else", Kw::Else),
    (b"sub", Kw::Sub),
    (b"call", Kw::Call),
    (b"do", Kw::Do),
    (b"while", Kw::While),
    (b"if", Kw::If),
    (b"break", Kw::Break),
    (b"continue", Kw::Continue),
    (b"repeat", Kw::Repeat),
    (b"return", Kw::Return),
];

/// The parameters as rs274 reads them while it skips a subroutine's definition: a named
/// parameter that is not defined reads 0.
struct Defining<'a>(&'a dyn ParamRead);

impl ParamRead for Defining<'_> {
    fn numbered(&self, n: usize) -> f64 {
        self.0.numbered(n)
    }
    fn named(&self, name: &str) -> Option<f64> {
        Some(self.0.named(name).unwrap_or(0.0))
    }
    fn read_only_named(&self, name: &str) -> bool {
        self.0.read_only_named(name)
    }
    fn fanuc(&self) -> bool {
        self.0.fanuc()
    }
    fn ini_file(&self) -> Option<(&std::path::Path, bool)> {
        self.0.ini_file()
    }
}

/// Parses `o<name> keyword …` at code index `at`: the name's code range, the keyword and the
/// index after the keyword.
pub(crate) fn parse_oword(code: &[u8], at: usize) -> Res<(usize, usize, Kw, usize)> {
    let mut i = at + 1;
    let (a, b) = if code.get(i) == Some(&b'<') {
        let a = i + 1;
        while i < code.len() && code[i] != b'>' {
            i += 1;
        }
        if i >= code.len() || i == a {
            return Err(Fault::syntax(
                Span::Code(at, i),
                "bad O-word name",
                "o<name> or o123",
            ));
        }
        i += 1;
        (a, i - 1)
    } else {
        let a = i;
        while matches!(code.get(i), Some(b'0'..=b'9')) {
            i += 1;
        }
        if i == a {
            return Err(Fault::syntax(
                Span::Code(at, (at + 2).min(code.len())),
                "bad O-word name",
                "o<name> or o123",
            ));
        }
        (a, i)
    };
    let rest = &code[i..];
    if rest.is_empty() {
        return Ok((a, b, Kw::Label, i));
    }
    match KEYWORDS.iter().find(|(w, _)| rest.starts_with(w)) {
        Some(&(w, kw)) => Ok((a, b, kw, i + w.len())),
        None => Err(Fault::syntax(
            Span::Code(i, code.len()),
            "unknown O-word keyword",
            "sub, endsub, call, return, do, while, endwhile, if, elseif, else, endif, repeat, endrepeat, break or continue",
        )),
    }
}

/// The name as compared: numeric names without leading zeros (`o0100` is `o100`).
pub(crate) fn key(name: &[u8]) -> &[u8] {
    if name.iter().all(u8::is_ascii_digit) {
        let z = name
            .iter()
            .take_while(|&&c| c == b'0')
            .count()
            .min(name.len().saturating_sub(1));
        &name[z..]
    } else {
        name
    }
}

impl Interp<'_, '_> {
    /// Executes an O-word line; `at` is the index of the `o` in the normalised code.
    pub(crate) fn exec_oword(&mut self, lb: &LineBuf, at: usize) -> Res<()> {
        let code = &lb.code[..];
        if matches!(code.get(at + 1), Some(b'[' | b'#')) {
            return self.exec_computed_call(code, at);
        }
        let (a, b, kw, i) = parse_oword(code, at)?;
        let name = key(&code[a..b]);
        let span = Span::Code(at, i);
        let here = Cursor {
            pos: self.cur_start,
            line: self.cur_line - 1,
            file: self.cur_file,
        };
        let after = self.at;
        let cond = |me: &Self| -> Res<f64> {
            let mut c = Cur::new(code);
            c.i = i;
            if c.at_end() {
                return Err(c.unexpected("a condition in brackets"));
            }
            // (A Fanuc vacant variable is 0 here.)
            let v = number(read_real(&mut c, me)?);
            if !c.at_end() {
                return Err(c.unexpected("end of line"));
            }
            Ok(v)
        };
        match kw {
            Kw::Label => self.check_fanuc_subs("a bare O-word"),
            Kw::Sub => {
                self.subs.insert(name.to_vec(), after);
                self.skip_to(name, &[Kw::Endsub], span)?;
                if !self.fanuc {
                    self.read_skipped_returns(after, name)?;
                }
                Ok(())
            }
            Kw::Endsub | Kw::Return => {
                let value = if i < code.len() {
                    Some(cond(self)?)
                } else {
                    None
                };
                self.sub_return(value, span)
            }
            Kw::Call => {
                let mut args = [0.0; N_ARGS];
                let mut n = 0;
                let mut c = Cur::new(code);
                c.i = i;
                while !c.at_end() {
                    if n == N_ARGS {
                        return Err(Fault::semantic(
                            Span::Code(c.i, code.len()),
                            "more than 30 subroutine arguments",
                        ));
                    }
                    c.word_start = c.i;
                    args[n] = read_real(&mut c, self)?;
                    n += 1;
                }
                self.call_sub(name, args, span)
            }
            Kw::Do => {
                self.check_label(name, kw, here, span)?;
                self.ctl.push(Ctl {
                    kind: LoopKind::Do,
                    name: name.to_vec(),
                    head: here,
                    body: after,
                    remaining: 0,
                });
                Ok(())
            }
            Kw::While => {
                let v = cond(self)?;
                let top = self.top_loop();
                if let Some(t) = top
                    .clone()
                    .filter(|t| t.kind == LoopKind::Do && t.name == name)
                {
                    // The tail of a do-while loop. (rs274 does not loop back while its
                    // `doing_break` is set, and clears it here, looping or not.)
                    let broken = std::mem::take(&mut self.doing_break);
                    if v != 0.0 && !broken {
                        self.count_iteration(span)?;
                        self.at = t.body;
                    } else {
                        self.ctl.pop();
                    }
                    return Ok(());
                }
                self.check_label(name, kw, here, span)?;
                let reentry = top.is_some_and(|t| t.kind == LoopKind::While && t.head == here);
                if v != 0.0 {
                    if !reentry {
                        self.ctl.push(Ctl {
                            kind: LoopKind::While,
                            name: name.to_vec(),
                            head: here,
                            body: after,
                            remaining: 0,
                        });
                    }
                    Ok(())
                } else {
                    if reentry {
                        self.ctl.pop();
                    }
                    self.skip_loop_body(name, Kw::Endwhile, span).map(|_| ())
                }
            }
            Kw::Endwhile => {
                let t = self.expect_loop(name, LoopKind::While, span, "endwhile")?;
                self.count_iteration(span)?;
                self.at = t.head;
                Ok(())
            }
            Kw::Repeat => {
                let v = cond(self)?.round();
                self.check_label(name, kw, here, span)?;
                if v > self.opts.max_repeat as f64 {
                    return Err(Fault::new(
                        PathErrorKind::Limit,
                        span,
                        format!(
                            "repeat [{v}] asks for more than {} repeats (the reader's limit on repeats)",
                            self.opts.max_repeat
                        ),
                        "",
                    ));
                }
                if v >= 1.0 {
                    self.ctl.push(Ctl {
                        kind: LoopKind::Repeat,
                        name: name.to_vec(),
                        head: here,
                        body: after,
                        remaining: v as u64,
                    });
                    Ok(())
                } else {
                    self.skip_loop_body(name, Kw::Endrepeat, span).map(|_| ())
                }
            }
            Kw::Endrepeat => {
                let t = self.expect_loop(name, LoopKind::Repeat, span, "endrepeat")?;
                let last = self.ctl.last_mut().expect("checked by expect_loop");
                last.remaining -= 1;
                if last.remaining > 0 {
                    self.count_iteration(span)?;
                    self.at = t.body;
                } else {
                    self.ctl.pop();
                }
                Ok(())
            }
            Kw::If => {
                let v = cond(self)?;
                self.check_label(name, kw, here, span)?;
                if v == 0.0 {
                    self.skip_if(name, span)?;
                }
                Ok(())
            }
            Kw::Elseif => {
                if std::mem::take(&mut self.if_probe) {
                    if cond(self)? == 0.0 {
                        self.skip_if(name, span)?;
                    }
                    Ok(())
                } else if self.fanuc {
                    // A branch was taken: the rest of the if is skipped.
                    self.skip_to(name, &[Kw::Endif], span).map(|_| ())
                } else {
                    // A branch was taken: the rest of the if is skipped, but rs274 reads every
                    // `elseif` of it on the way (read_o evaluates the condition of an elseif
                    // whose name it skips to), so a condition that cannot be evaluated (a
                    // division by zero) is an error. The next elseif runs this again.
                    cond(self)?;
                    let (kw, before) =
                        self.skip_to(name, &[Kw::Elseif, Kw::Else, Kw::Endif], span)?;
                    match kw {
                        Kw::Elseif => self.at = before,
                        Kw::Else => {
                            self.skip_to(name, &[Kw::Endif], span)?;
                        }
                        _ => {}
                    }
                    Ok(())
                }
            }
            Kw::Else => self.skip_to(name, &[Kw::Endif], span).map(|_| ()),
            Kw::Endif => Ok(()),
            Kw::Break | Kw::Continue => {
                let floor = self.frames.last().map_or(0, |f| f.ctl_len);
                let Some(k) = (floor..self.ctl.len())
                    .rev()
                    .find(|&k| self.ctl[k].name == name)
                else {
                    let level = self.frames.len();
                    let repeat = matches!(
                        self.o_labels.get(&(level, name.to_vec())),
                        Some((Kw::Repeat, _))
                    );
                    if repeat && !self.fanuc {
                        return Err(Self::not_a_while_or_do(kw, name, span));
                    }
                    return Err(Fault::semantic(
                        span,
                        format!(
                            "{} outside a loop named o{}",
                            if kw == Kw::Break { "break" } else { "continue" },
                            String::from_utf8_lossy(name)
                        ),
                    ));
                };
                let kind = self.ctl[k].kind;
                if kind == LoopKind::Repeat && !self.fanuc {
                    return Err(Self::not_a_while_or_do(kw, name, span));
                }
                if kw == Kw::Break && (self.fanuc || kind != LoopKind::Do) {
                    // (Out of a `while` nothing clears rs274's flag.)
                    self.doing_break |= !self.fanuc;
                    self.ctl.truncate(k);
                    self.skip_loop_body(name, kind.end(), span).map(|_| ())
                } else {
                    // Continue, or under LinuxCNC's rules a break out of a `do`: run the
                    // loop's closing line, which loops or ends it — rs274 evaluates a do's
                    // closing condition after a break too, its `doing_break` keeping it from
                    // looping back — reading the breaks of the loop's name on the way.
                    self.doing_break |= kw == Kw::Break;
                    self.ctl.truncate(k + 1);
                    if let Some(end_line) = self.skip_loop_body(name, kind.end(), span)? {
                        self.at = end_line;
                    }
                    Ok(())
                }
            }
        }
    }

    /// Skips a `while` or `repeat` whose condition or count ends it, to the line after its
    /// closing `end`. rs274 skips by reading every line of the loop's name on the way, and a
    /// `break` of that name (in an `if` that never ran) sets its `doing_break` flag, which only
    /// the end of a `do` loop clears: the next do-while loop then runs once (LinuxCNC 2.9,
    /// interp_o_word.cc; seen in rs274's output for `o1 while [0]` … `o1 break` … `o1
    /// endwhile` then `o2 do` … `o2 while [#1 LT 3]`).
    /// A `break` or `continue` naming a `repeat` is an error there as anywhere: the reading
    /// stops at it (`None`), to refuse it at its line. Otherwise the cursor is after the `end`
    /// line, and the one before it is returned.
    fn skip_loop_body(&mut self, name: &[u8], end: Kw, span: Span) -> Res<Option<Cursor>> {
        if !self.fanuc {
            while let Some((kw @ (Kw::Break | Kw::Continue), at, after)) =
                self.scan(self.at, name, &[Kw::Break, Kw::Continue, end])
            {
                if end == Kw::Endrepeat {
                    // Read from its own line, where it is refused.
                    self.at = at;
                    return Ok(None);
                }
                self.doing_break |= kw == Kw::Break;
                self.at = after;
            }
        }
        self.skip_to(name, &[end], span)
            .map(|(_, before)| Some(before))
    }

    /// rs274's refusal of a `break` or `continue` whose name is a `repeat`'s.
    fn not_a_while_or_do(kw: Kw, name: &[u8], span: Span) -> Fault {
        Fault::semantic(
            span,
            format!(
                "no matching while/do label: o{} {} names a repeat loop (LinuxCNC breaks out of, \
                 or continues, while and do loops only)",
                String::from_utf8_lossy(name),
                if kw == Kw::Break { "break" } else { "continue" }
            ),
        )
    }

    /// rs274's O-word offset table: in one call level an O name starts one `if`, `while` or
    /// `repeat` (a `while` may close the `do` of its name), at one line; another line starting
    /// one with that name is "duplicate O-word label". (The table outlives the loop: two
    /// separate `o100 if` blocks are refused.)
    fn check_label(&mut self, name: &[u8], kw: Kw, here: Cursor, span: Span) -> Res<()> {
        if self.fanuc {
            return Ok(());
        }
        let level = self.frames.len();
        match self.o_labels.get(&(level, name.to_vec())) {
            None => {
                self.o_labels.insert((level, name.to_vec()), (kw, here));
                Ok(())
            }
            Some(&(first, at)) => {
                if at == here || kw == Kw::Do || (kw == Kw::While && first == Kw::Do) {
                    return Ok(());
                }
                Err(Fault::semantic(
                    span,
                    format!(
                        "duplicate O-word label o{}: already used at line {} (LinuxCNC gives each \
                         if, while, do and repeat of a call level its own name)",
                        String::from_utf8_lossy(name),
                        at.line + 1
                    ),
                ))
            }
        }
    }

    /// `o[expression] call …` or `o#<name> call …`: calls the subroutine whose number the
    /// expression or parameter gives (rs274 reads an O number as any integer value).
    fn exec_computed_call(&mut self, code: &[u8], at: usize) -> Res<()> {
        let mut c = Cur::new(code);
        c.i = at + 1;
        c.word_start = at;
        let v = number(read_real(&mut c, self)?);
        let span = Span::Code(at, c.i);
        if !(0.0..1e15).contains(&v) || (v - v.round()).abs() > 1e-6 {
            return Err(Fault::semantic(
                span,
                format!("o[…] gives {v}, not a subroutine number"),
            ));
        }
        if !code[c.i..].starts_with(b"call") {
            return Err(Fault::syntax(
                Span::Code(c.i, code.len()),
                "a computed O-word can only be called",
                "call",
            ));
        }
        let name = format!("{}", v.round() as u64).into_bytes();
        let mut line = b"o".to_vec();
        line.extend_from_slice(&name);
        line.extend_from_slice(&code[c.i..]);
        let (_, _, _, i) = parse_oword(&line, 0)?;
        let mut args = [0.0; N_ARGS];
        let mut n = 0;
        let mut ac = Cur::new(&line);
        ac.i = i;
        while !ac.at_end() {
            if n == N_ARGS {
                return Err(Fault::semantic(span, "more than 30 subroutine arguments"));
            }
            ac.word_start = ac.i;
            args[n] = read_real(&mut ac, self)
                .map_err(|_| Fault::syntax(span, "bad subroutine argument", "[expression]"))?;
            n += 1;
        }
        self.call_sub(&name, args, span)
    }

    /// The start of file `file`.
    pub(crate) fn file_start(&self, file: u32) -> Cursor {
        Cursor {
            pos: 0,
            line: 0,
            file,
        }
    }

    /// Finds `name.ngc` in the program's folder and the subroutine path (LinuxCNC's
    /// `SUBROUTINE_PATH`), reads it and returns its index in `files`.
    fn load_sub_file(&mut self, name: &[u8]) -> Option<u32> {
        let name = std::str::from_utf8(name).ok()?;
        if name.is_empty() || name.contains(['/', '\\']) || name.starts_with('.') {
            return None;
        }
        self.load_named_file(&[format!("{name}.ngc")])
    }

    /// Finds the first of the file names `names` (tried in order in each folder) in the
    /// program's folder, then in the subroutine path, reads it and returns its index in
    /// `files` (a file already read keeps its index).
    fn load_named_file(&mut self, names: &[String]) -> Option<u32> {
        let program = std::path::Path::new(&*self.files[0].0);
        let dirs = program
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .into_iter()
            .chain(
                self.opts
                    .subroutine_path
                    .iter()
                    .map(std::path::PathBuf::as_path),
            );
        for dir in dirs {
            for name in names {
                let path = dir.join(name);
                let shown: Rc<str> = Rc::from(path.display().to_string());
                if let Some(i) = self.files.iter().position(|(n, _)| *n == shown) {
                    return Some(i as u32);
                }
                if !path.is_file() {
                    continue;
                }
                if let Ok(bytes) = std::fs::read(&path) {
                    let text: Rc<str> =
                        Rc::from(super::without_bom(&crate::load::decode_text(bytes)));
                    self.files.push((shown, text));
                    return Some(self.files.len() as u32 - 1);
                }
            }
        }
        None
    }

    fn top_loop(&self) -> Option<Ctl> {
        let floor = self.frames.last().map_or(0, |f| f.ctl_len);
        if self.ctl.len() > floor {
            self.ctl.last().cloned()
        } else {
            None
        }
    }

    fn expect_loop(&self, name: &[u8], kind: LoopKind, span: Span, what: &str) -> Res<Ctl> {
        match self.top_loop() {
            Some(t) if t.kind == kind && t.name == name => Ok(t),
            _ => Err(Fault::semantic(
                span,
                format!(
                    "{what} without a matching open loop o{}",
                    String::from_utf8_lossy(name)
                ),
            )),
        }
    }

    /// After a false `if`/`elseif`: on to the next `elseif` (to be tested), `else` or `endif`.
    fn skip_if(&mut self, name: &[u8], span: Span) -> Res<()> {
        let (kw, at) = self.skip_to(name, &[Kw::Elseif, Kw::Else, Kw::Endif], span)?;
        if kw == Kw::Elseif {
            self.if_probe = true;
            self.at = at;
        }
        Ok(())
    }

    /// Moves the cursor past the next line `o<name> kw` with `kw` in `kws`. Returns the keyword
    /// found and the cursor *before* that line.
    fn skip_to(&mut self, name: &[u8], kws: &[Kw], span: Span) -> Res<(Kw, Cursor)> {
        match self.scan(self.at, name, kws) {
            Some((kw, before, after)) => {
                self.at = after;
                Ok((kw, before))
            }
            None => Err(Fault::new(
                PathErrorKind::Semantic,
                span,
                format!(
                    "o{} has no matching {:?}",
                    String::from_utf8_lossy(name),
                    kws[kws.len() - 1]
                )
                .to_lowercase(),
                "",
            )),
        }
    }

    /// Finds the next line `o<name> kw` (kw in `kws`) from `from`: the keyword, the cursor
    /// before that line and the cursor after it. Lines that do not normalise are not O-words.
    fn scan(&mut self, from: Cursor, name: &[u8], kws: &[Kw]) -> Option<(Kw, Cursor, Cursor)> {
        // The text never changes, so a scan from the same place for the same O-word always
        // ends at the same line: remember it, or a loop around a long false `if` would rescan
        // the same lines on every iteration.
        let mask = kws.iter().fold(0u32, |m, &k| m | 1 << k as u32);
        if let Some((n, hit)) = self.scan_cache.get(&(from.file, from.pos, mask)) {
            if n == name {
                return *hit;
            }
        }
        let found = self.scan_uncached(from, name, kws);
        self.scan_cache
            .insert((from.file, from.pos, mask), (name.to_vec(), found));
        found
    }

    fn scan_uncached(
        &mut self,
        from: Cursor,
        name: &[u8],
        kws: &[Kw],
    ) -> Option<(Kw, Cursor, Cursor)> {
        let mut buf = std::mem::take(&mut self.skip_buf);
        let mut found = None;
        let text = self.files[from.file as usize].1.clone();
        for (raw, at, after) in from.lines(&text) {
            if raw.bytes().any(|c| c | 0x20 == b'o')
                && normalize(raw, &mut buf).is_ok()
                && !(buf.deleted && self.opts.block_delete)
            {
                let o = skip_line_number(&buf.code);
                if buf.code.get(o) == Some(&b'o') {
                    if let Ok((a, b, kw, _)) = parse_oword(&buf.code, o) {
                        if key(&buf.code[a..b]) == name && kws.contains(&kw) {
                            found = Some((kw, at, after));
                            break;
                        }
                    }
                }
            }
        }
        self.skip_buf = buf;
        found
    }

    /// rs274 reads every `o<name> return` and `o<name> endsub` line of a subroutine it skips
    /// past at its definition (read_o: the skip looks for that name), and reading one sets
    /// `#<_value>` and `#<_value_returned>` from its value, or clears them: after a definition
    /// they are those of its `endsub`, and an expression there that cannot be evaluated (a
    /// division by zero) is an error even though the subroutine never runs. `from` is the
    /// line after `o<name> sub`.
    fn read_skipped_returns(&mut self, from: Cursor, name: &[u8]) -> Res<()> {
        let mut buf = std::mem::take(&mut self.skip_buf);
        let text = self.files[from.file as usize].1.clone();
        let mut result = Ok(());
        for (raw, _, _) in from.lines(&text) {
            if !raw.bytes().any(|c| c | 0x20 == b'o')
                || normalize(raw, &mut buf).is_err()
                || (buf.deleted && self.opts.block_delete)
            {
                continue;
            }
            let o = skip_line_number(&buf.code);
            if buf.code.get(o) != Some(&b'o') {
                continue;
            }
            let Ok((a, b, kw, i)) = parse_oword(&buf.code, o) else {
                continue;
            };
            if key(&buf.code[a..b]) != name || !matches!(kw, Kw::Return | Kw::Endsub) {
                continue;
            }
            let value = if i < buf.code.len() && buf.code[i] == b'[' {
                let mut c = Cur::new(&buf.code);
                c.i = i;
                // During a definition an undefined named parameter reads 0 (read_named_parameter
                // does not require them while defining_sub).
                match read_real(&mut c, &Defining(self)) {
                    Ok(v) => Some(number(v)),
                    Err(mut e) => {
                        // Reported at the `sub` line, whose columns these are not.
                        e.span = Span::Line;
                        e.message = format!(
                            "{} (in o{} {}, read where the subroutine is defined)",
                            e.message,
                            String::from_utf8_lossy(name),
                            if kw == Kw::Endsub { "endsub" } else { "return" }
                        );
                        result = Err(e);
                        break;
                    }
                }
            } else {
                None
            };
            self.params
                .set_named("_value_returned", f64::from(u8::from(value.is_some())));
            self.params.set_named("_value", value.unwrap_or(0.0));
            if kw == Kw::Endsub {
                break;
            }
        }
        self.skip_buf = buf;
        result
    }

    fn call_sub(&mut self, name: &[u8], args: [f64; N_ARGS], span: Span) -> Res<()> {
        self.enter_call(span)?;
        let body = match self.subs.get(name) {
            Some(&c) => c,
            None => {
                // Not yet defined: LinuxCNC looks for it in the rest of the file, then from the top.
                let hit = self
                    .scan(self.at, name, &[Kw::Sub])
                    .or_else(|| self.scan(self.file_start(self.cur_file), name, &[Kw::Sub]))
                    .or_else(|| {
                        let file = self.load_sub_file(name)?;
                        self.scan(self.file_start(file), name, &[Kw::Sub])
                    });
                let Some((_, _, after)) = hit else {
                    return Err(Fault::semantic(
                        span,
                        format!(
                            "subroutine o{} is not defined",
                            String::from_utf8_lossy(name)
                        ),
                    ));
                };
                self.subs.insert(name.to_vec(), after);
                after
            }
        };
        let mut saved = [0.0; N_ARGS];
        saved.copy_from_slice(&self.params.num[1..=N_ARGS]);
        self.params.num[1..=N_ARGS].copy_from_slice(&args);
        self.params.locals.push(HashMap::new());
        self.frames.push(Frame {
            ret: self.at,
            saved,
            ctl_len: self.ctl.len(),
            fanuc: None,
        });
        self.at = body;
        Ok(())
    }

    fn enter_call(&mut self, span: Span) -> Res<()> {
        if self.frames.len() >= self.opts.max_call_depth {
            return Err(Fault::new(
                PathErrorKind::Limit,
                span,
                format!(
                    "subroutine calls nested more than {} deep (the reader's limit on nesting)",
                    self.opts.max_call_depth
                ),
                "",
            ));
        }
        self.count_iteration(span)
    }

    fn sub_return(&mut self, value: Option<f64>, span: Span) -> Res<()> {
        if self.frames.last().is_some_and(|f| f.fanuc.is_none()) {
            self.modal_on_return(span)?;
        }
        let Some(f) = self.frames.pop() else {
            return Err(Fault::semantic(
                span,
                "endsub or return outside a subroutine call",
            ));
        };
        // Macro B loops the subroutine left open end with it.
        let level = self.frames.len();
        self.macro_loops.retain(|l| l.2 <= level);
        if f.fanuc.is_some() {
            self.frames.push(f);
            return Err(Fault::semantic(
                span,
                "endsub or return inside an M98 subprogram (end it with M99)",
            ));
        }
        self.params.num[1..=N_ARGS].copy_from_slice(&f.saved);
        self.params.locals.pop();
        // The call's O-word offset table goes with it.
        let level = self.frames.len() + 1;
        self.o_labels.retain(|(l, _), _| *l < level);
        self.ctl.truncate(f.ctl_len);
        self.params
            .set_named("_value_returned", f64::from(u8::from(value.is_some())));
        // A call that returns nothing clears the value of the one before (LinuxCNC).
        self.params.set_named("_value", value.unwrap_or(0.0));
        self.at = f.ret;
        Ok(())
    }

    /// rs274's refusal of Fanuc-style subprograms under the INI's `DISABLE_FANUC_STYLE_SUB`.
    fn check_fanuc_subs(&self, what: &str) -> Res<()> {
        match &self.opts.ini {
            Some(ini) if !self.fanuc && self.fanuc_subs_off => Err(Fault::new(
                PathErrorKind::Semantic,
                Span::Line,
                format!(
                    "DISABLE_FANUC_STYLE_SUB set in INI file {}, but found {what}",
                    ini.path.display()
                ),
                "O-word subroutines (o<name> sub … endsub, o<name> call)",
            )),
            _ => Ok(()),
        }
    }

    /// `M98 P<n> L<count>`: calls the subprogram labelled `O<n>`; Haas `M97 P<n> L<count>`
    /// (`b.m97`) the local subprogram starting at the line numbered `N<n>`. Both end with M99.
    pub(crate) fn m98(&mut self, b: &Block) -> Res<()> {
        let m = if b.m97 { "M97" } else { "M98" };
        self.check_fanuc_subs(m)?;
        let p = b.get(b'p').ok_or_else(|| {
            Fault::new(
                PathErrorKind::Semantic,
                Span::Line,
                format!("{m} needs a P word"),
                if b.m97 {
                    "P<line number>"
                } else {
                    "P<program number>"
                },
            )
        })?;
        if p < 0.0 || p.fract() != 0.0 || p > 1e15 {
            return Err(Fault::new(
                PathErrorKind::Semantic,
                b.span(b'p'),
                "bad subprogram number",
                "a non-negative integer",
            ));
        }
        // Fanuc `M98 Pxxxxyyyy`: xxxx repeats of program yyyy — unless program O<P> itself
        // exists (in this file or a file of its own): Haas numbers its programs O00000–O99999
        // and repeats them with L, so `M98 P10005` there calls O10005.
        let whole_exists = self.fanuc
            && !b.m97
            && !b.has(b'l')
            && p >= 10_000.0
            && self.m98_target(p as u64).is_some();
        let (p, packed) = if self.fanuc && !b.m97 && !b.has(b'l') && p >= 10_000.0 && !whole_exists
        {
            ((p % 10_000.0).round(), Some((p / 10_000.0).floor() as u64))
        } else {
            (p, None)
        };
        let count = match b.get(b'l') {
            None => packed.unwrap_or(1).min(self.opts.max_repeat),
            Some(l) if l.fract() == 0.0 && l >= 0.0 && l <= self.opts.max_repeat as f64 => l as u64,
            Some(l) => {
                return Err(Fault::new(
                    if l > self.opts.max_repeat as f64 {
                        PathErrorKind::Limit
                    } else {
                        PathErrorKind::Semantic
                    },
                    b.span(b'l'),
                    format!("bad {m} repeat count L{l}"),
                    format!("an integer from 0 to {}", self.opts.max_repeat),
                ))
            }
        };
        if count == 0 {
            return Ok(());
        }
        // Where the call goes: the line numbered N<p> (M97), or the one after O<p> (M98).
        let start = if b.m97 {
            let map = self
                .line_numbers
                .take()
                .unwrap_or_else(|| self.index_targets(true, false));
            let start = map.get(&(p as u64)).copied();
            self.line_numbers = Some(map);
            start
        } else {
            self.m98_target(p as u64)
        };
        let start = start.ok_or_else(|| {
            let what = if b.m97 {
                format!("no line numbered N{p} in this file")
            } else if self.fanuc {
                format!(
                    "subprogram O{p} is not in this file, nor in a file O{p} or {p} (.nc, \
                     .ngc, .tap, .txt or no extension) in the program's folder or the \
                     subroutine path"
                )
            } else {
                format!("subprogram O{p} is not in this file")
            };
            Fault::semantic(b.span(b'p'), what)
        })?;
        self.enter_call(b.span(b'p'))?;
        self.frames.push(Frame {
            ret: self.at,
            saved: [0.0; N_ARGS],
            ctl_len: self.ctl.len(),
            fanuc: Some((start, count)),
        });
        self.at = start;
        Ok(())
    }

    /// Where `M98 P<p>` goes: the line after the label `O<p>` of the program's file, else
    /// (Fanuc) the subprogram's own file, found as `o<name> call` finds one (the program's
    /// folder, then the subroutine path): `O<p>` or `<p>` (also with the number written with
    /// four or five digits, `O0012`, `O00012`), with the extension .nc, .ngc, .tap, .txt or
    /// none; in it, the line after its `O<p>` label, else its start. Found files' targets are
    /// kept with the program's.
    fn m98_target(&mut self, p: u64) -> Option<Cursor> {
        let map = self
            .labels
            .take()
            .unwrap_or_else(|| self.index_targets(false, false));
        let start = map.get(&p).copied();
        self.labels = Some(map);
        if start.is_some() || !self.fanuc {
            return start;
        }
        let mut stems = vec![format!("O{p}"), format!("{p}")];
        for padded in [format!("{p:04}"), format!("{p:05}")] {
            for stem in [format!("O{padded}"), padded] {
                if !stems.contains(&stem) {
                    stems.push(stem);
                }
            }
        }
        let names: Vec<String> = stems
            .iter()
            .flat_map(|s| {
                ["nc", "ngc", "tap", "txt", "NC", "NGC", "TAP", "TXT", ""]
                    .iter()
                    .map(move |e| {
                        if e.is_empty() {
                            s.clone()
                        } else {
                            format!("{s}.{e}")
                        }
                    })
            })
            .collect();
        let file = self.load_named_file(&names)?;
        // The file's own `O<p>` label, else its first line.
        let (saved_file, saved_text) = (self.cur_file, self.text.clone());
        self.cur_file = file;
        self.text = self.files[file as usize].1.clone();
        let in_file = self.index_targets(false, false);
        self.cur_file = saved_file;
        self.text = saved_text;
        let start = in_file
            .get(&p)
            .copied()
            .unwrap_or_else(|| self.file_start(file));
        if let Some(map) = self.labels.as_mut() {
            map.insert(p, start);
        }
        Some(start)
    }

    /// `M99`: the end of an `M98` subprogram (repeat it or return), or in the main program a
    /// restart.
    pub(crate) fn m99(&mut self, b: &Block) -> Res<()> {
        if !self.frames.is_empty() {
            // (rs274 checks the setting in a call only: a main program's M99 is its loop.)
            self.check_fanuc_subs("M99")?;
        }
        if b.has(b'p') && !self.frames.is_empty() {
            return Err(Fault::new(
                PathErrorKind::Unsupported,
                b.span(b'p'),
                "M99 P in a subprogram (a return to the caller's block N<P>) is not read",
                "M99 without P",
            ));
        }
        match self.frames.last_mut() {
            Some(Frame {
                fanuc: Some((start, left)),
                ..
            }) => {
                *left -= 1;
                if *left > 0 {
                    let s = *start;
                    self.count_iteration(Span::Line)?;
                    self.at = s;
                } else {
                    self.modal_on_return(Span::Line)?;
                    let f = self.frames.pop().expect("just matched");
                    let level = self.frames.len();
                    self.macro_loops.retain(|l| l.2 <= level);
                    self.ctl.truncate(f.ctl_len);
                    self.at = f.ret;
                }
                Ok(())
            }
            Some(_) => Err(Fault::semantic(
                Span::Line,
                "M99 inside an O-word subroutine (end it with endsub)",
            )),
            None => self.restart_main(b),
        }
    }

    /// `M99` in the main program: LinuxCNC and Fanuc controls run the program again from its
    /// top (Fanuc's `M99 P<n>`: from the block numbered N<n>), parameters and modes kept,
    /// until an M2/M30 ends it. A pass that changed neither a parameter nor the position or
    /// an offset starts the next in the state it started from, and no file read has an M2/M30
    /// at all in a bar feeder's loop: either would repeat for ever, so reading ends here with
    /// a warning.
    fn restart_main(&mut self, b: &Block) -> Res<()> {
        let target = match b.get(b'p') {
            None => None,
            Some(p) if p >= 0.0 && p.fract() == 0.0 && p <= u64::MAX as f64 => {
                let map = match self.main_line_numbers.take() {
                    Some(m) => m,
                    None => self.index_targets(true, true),
                };
                let at = map.get(&(p as u64)).copied();
                self.main_line_numbers = Some(map);
                Some(at.ok_or_else(|| {
                    Fault::semantic(
                        b.span(b'p'),
                        format!("no line numbered N{p} in the main program"),
                    )
                })?)
            }
            Some(p) => {
                return Err(Fault::new(
                    PathErrorKind::Semantic,
                    b.span(b'p'),
                    format!("M99 P{p}"),
                    "P<a line number>",
                ))
            }
        };
        let files = self.files.len();
        let has_end = match self.files_have_end {
            Some((n, e)) if n == files => e,
            _ => {
                let e = (0..files as u32).any(|f| self.file_has_program_end(f));
                self.files_have_end = Some((files, e));
                e
            }
        };
        let control = PassControl::of(self);
        let unchanged = self.pass_control.as_ref() == Some(&control);
        let endless = if !has_end {
            Some("no file it reads has an M2/M30 to end it")
        } else if !self.params.pass.changed(&self.params) && unchanged {
            Some("this pass changed no parameter, position, offset, tool or mode")
        } else {
            None
        };
        if let Some(why) = endless {
            self.warn_at(
                0,
                format!(
                    "M99 in the main program restarts it (LinuxCNC, Fanuc), but {why}, so it \
                     would repeat without end: reading ends here"
                ),
            );
            self.ended = true;
            return Ok(());
        }
        self.count_iteration(Span::Line)?;
        self.main_passes += 1;
        if self.main_passes == 1 {
            let from = match b.get(b'p') {
                Some(p) => format!("from N{p}"),
                None => "from the top".into(),
            };
            self.warn_at(
                0,
                format!(
                    "M99 in the main program: run again {from}, as LinuxCNC and Fanuc controls do \
                     (parameters and modes kept; later restarts are not reported)"
                ),
            );
        }
        self.params.pass.clear();
        self.pass_control = Some(control);
        self.ctl.clear();
        self.macro_loops.clear();
        match target {
            Some(at) => self.at = at,
            None => {
                self.tape = false;
                self.seen_code = false;
                self.at = self.file_start(self.cur_file);
            }
        }
        Ok(())
    }

    /// Whether file `file` of those read has an M2 or M30 word anywhere (comments aside).
    fn file_has_program_end(&mut self, file: u32) -> bool {
        let mut buf = std::mem::take(&mut self.skip_buf);
        let text = self.files[file as usize].1.clone();
        let found = self.file_start(file).lines(&text).any(|(raw, _, _)| {
            raw.bytes().any(|c| c | 0x20 == b'm')
                && normalize(raw, &mut buf).is_ok()
                && has_program_end_word(&buf.code)
        });
        self.skip_buf = buf;
        found
    }

    /// The call targets of the current file: with `numbers`, where the first line numbered
    /// `N<n>` starts (an `N` with a fraction or none is no target), for Haas `M97` — with
    /// `main_only`, in the main program only, up to the first subprogram (an `O<n>` label after
    /// the program's first block; the main program's own number may head it), for Fanuc's
    /// `M99 P<n>`; else where the line after the first `O<n>` label starts, for `M98`.
    pub(crate) fn index_targets(&mut self, numbers: bool, main_only: bool) -> HashMap<u64, Cursor> {
        let mut map = HashMap::new();
        let mut buf = std::mem::take(&mut self.skip_buf);
        let text = self.text.clone();
        let number = |digits: &[u8]| std::str::from_utf8(digits).ok()?.parse::<u64>().ok();
        let is_label = |code: &[u8]| {
            let o = skip_line_number(code);
            code.get(o) == Some(&b'o') && matches!(parse_oword(code, o), Ok((_, _, Kw::Label, _)))
        };
        let mut code_seen = false;
        for (raw, line, at) in self.file_start(self.cur_file).lines(&text) {
            let found = if numbers {
                if normalize(raw, &mut buf).is_err()
                    || matches!(buf.code.first(), None | Some(b'%'))
                {
                    continue;
                }
                if main_only {
                    let label = is_label(&buf.code);
                    if label && code_seen {
                        break;
                    }
                    code_seen |= !label;
                }
                (buf.code[0] == b'n')
                    .then(|| number(&buf.code[1..skip_line_number(&buf.code)]))
                    .flatten()
                    .map(|n| (n, line))
            } else if raw.bytes().any(|c| c | 0x20 == b'o') && normalize(raw, &mut buf).is_ok() {
                let o = skip_line_number(&buf.code);
                match (buf.code.get(o) == Some(&b'o')).then(|| parse_oword(&buf.code, o)) {
                    Some(Ok((a, b, Kw::Label, _))) => number(&buf.code[a..b]).map(|n| (n, at)),
                    _ => None,
                }
            } else {
                None
            };
            if let Some((n, c)) = found {
                map.entry(n).or_insert(c);
            }
        }
        self.skip_buf = buf;
        map
    }
}

/// Whether normalised code holds an `M2` or `M30` word: an `m` that starts a word (not inside
/// a `#<name>`, an `o<name>` or a bracketed expression, nor after another letter).
fn has_program_end_word(code: &[u8]) -> bool {
    let (mut i, mut depth) = (0, 0usize);
    while i < code.len() {
        match code[i] {
            b'<' => {
                i += code[i..]
                    .iter()
                    .position(|&c| c == b'>')
                    .unwrap_or(code.len() - i)
            }
            b'[' => depth += 1,
            b']' => depth = depth.saturating_sub(1),
            b'm' if depth == 0 && (i == 0 || !code[i - 1].is_ascii_alphabetic()) => {
                let rest = &code[i + 1..];
                let digits = rest.iter().take_while(|d| d.is_ascii_digit()).count();
                let n = std::str::from_utf8(&rest[..digits])
                    .ok()
                    .and_then(|d| d.parse::<u32>().ok());
                if matches!(n, Some(2 | 30)) {
                    return true;
                }
            }
            _ => {}
        }
        i += 1;
    }
    false
}

/// What besides the parameters it wrote a pass of the main program may change that the next
/// pass can read (#5000 on, the predefined named parameters): the position, the offsets and
/// their tables, the G28/G30 homes, the tools (loaded, selected, their offsets and radii) and
/// the modal state (units, plane, distance modes, feed mode and feed, spindle, coordinate
/// system, retract mode, tool length offset, compensation, coolant, overrides: what M70
/// keeps), and the motion mode.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct PassControl {
    p: [f64; 6],
    g5x: [[f64; 6]; 9],
    rot: [f64; 9],
    ext: (Option<u16>, std::collections::BTreeMap<u16, [f64; 6]>),
    g92: [f64; 6],
    g92_saved: [f64; 6],
    g92_flag: f64,
    homes: [[f64; 6]; 2],
    tool: u32,
    tool_table: std::collections::BTreeMap<u32, [f64; 6]>,
    tool_radii: std::collections::BTreeMap<u32, f64>,
    modal: super::modal::ModalState,
    motion: Option<u16>,
}

impl PassControl {
    pub(crate) fn of(i: &Interp<'_, '_>) -> Self {
        PassControl {
            p: i.p,
            g5x: i.g5x_table,
            rot: i.rot_table,
            ext: (i.ext_coord, i.ext_table.clone()),
            g92: i.g92,
            g92_saved: i.g92_saved,
            g92_flag: i.g92_flag,
            homes: i.homes,
            tool: i.tool,
            tool_table: i.tool_table.clone(),
            tool_radii: i.tool_radii.clone(),
            modal: i.modal_state(),
            motion: i.motion,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_owords() {
        let (a, b, kw, i) = parse_oword(b"o100while[#1lt3]", 0).unwrap();
        assert_eq!((a, b, kw, i), (1, 4, Kw::While, 9));
        let (a, b, kw, _) = parse_oword(b"o<my_sub>call[1]", 0).unwrap();
        assert_eq!((a, b, kw), (2, 8, Kw::Call));
        assert_eq!(parse_oword(b"o100elseif[1]", 0).unwrap().2, Kw::Elseif);
        assert_eq!(parse_oword(b"o100else", 0).unwrap().2, Kw::Else);
        assert_eq!(parse_oword(b"o0001", 0).unwrap().2, Kw::Label);
        assert!(parse_oword(b"o100foo", 0).is_err());
        assert!(parse_oword(b"o<>sub", 0).is_err());
        assert!(parse_oword(b"osub", 0).is_err());
        assert_eq!(key(b"0100"), b"100");
        assert_eq!(key(b"000"), b"0");
    }
}
