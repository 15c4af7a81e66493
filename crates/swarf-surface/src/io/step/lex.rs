//! Part 21 (ISO 10303-21) lexing: the exchange structure's `DATA` section as instances of
//! (possibly complex) entities with their parameter values, by instance id.

use std::collections::HashMap;

use super::super::{line_col, Format, ReadError};

/// Deepest nesting of parameter lists accepted (real files use 3).
pub(super) const MAX_DEPTH: usize = 32;

/// A parameter value.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Param {
    Ref(u64),
    Num(f64),
    Str(String),
    Enum(String),
    List(Vec<Param>),
    Typed(String, Vec<Param>),
    Null,
    Derived,
}

#[derive(Debug)]
pub(super) struct Instance {
    pub(super) offset: usize,
    pub(super) parts: Vec<(String, Vec<Param>)>,
}

impl Instance {
    pub(super) fn part(&self, name: &str) -> Option<&[Param]> {
        self.parts
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, p)| p.as_slice())
    }
    pub(super) fn first_name(&self) -> &str {
        self.parts.first().map_or("", |(n, _)| n.as_str())
    }
}

pub(super) struct Lexer<'a> {
    text: &'a str,
    b: &'a [u8],
    pos: usize,
}

impl<'a> Lexer<'a> {
    pub(super) fn new(text: &'a str) -> Self {
        Self {
            text,
            b: text.as_bytes(),
            pos: 0,
        }
    }

    pub(super) fn err(&self, at: usize, message: String) -> ReadError {
        let (line, column) = line_col(self.text, at);
        ReadError::Syntax {
            format: Format::Step,
            line,
            column,
            message,
        }
    }

    pub(super) fn found(&self) -> String {
        match self.b.get(self.pos) {
            None => "end of file".into(),
            Some(_) => {
                let s: String = self
                    .text
                    .get(self.pos..)
                    .unwrap_or("")
                    .chars()
                    .take(12)
                    .collect();
                format!("`{}`", s.split_whitespace().next().unwrap_or(""))
            }
        }
    }

    pub(super) fn skip_ws(&mut self) -> Result<(), ReadError> {
        loop {
            while self.pos < self.b.len() && self.b[self.pos].is_ascii_whitespace() {
                self.pos += 1;
            }
            if self.b[self.pos..].starts_with(b"/*") {
                let start = self.pos;
                match self.text[self.pos + 2..].find("*/") {
                    Some(i) => self.pos += 2 + i + 2,
                    None => return Err(self.err(start, "unterminated comment `/*`".into())),
                }
            } else {
                return Ok(());
            }
        }
    }

    pub(super) fn peek(&mut self) -> Result<Option<u8>, ReadError> {
        self.skip_ws()?;
        Ok(self.b.get(self.pos).copied())
    }

    pub(super) fn expect(&mut self, c: u8, what: &str) -> Result<(), ReadError> {
        if self.peek()? == Some(c) {
            self.pos += 1;
            Ok(())
        } else {
            Err(self.err(self.pos, format!("found {}, expected {what}", self.found())))
        }
    }

    pub(super) fn keyword(&mut self) -> Option<String> {
        let start = self.pos;
        if !self
            .b
            .get(self.pos)
            .is_some_and(|c| c.is_ascii_alphabetic() || *c == b'_' || *c == b'!')
        {
            return None;
        }
        self.pos += 1;
        while self
            .b
            .get(self.pos)
            .is_some_and(|c| c.is_ascii_alphanumeric() || *c == b'_' || *c == b'-')
        {
            self.pos += 1;
        }
        Some(self.text[start..self.pos].to_ascii_uppercase())
    }

    pub(super) fn integer(&mut self) -> Option<u64> {
        let start = self.pos;
        while self.b.get(self.pos).is_some_and(u8::is_ascii_digit) {
            self.pos += 1;
        }
        self.text[start..self.pos].parse().ok()
    }

    /// Every instance of every DATA section.
    pub(super) fn instances(mut self) -> Result<HashMap<u64, Instance>, ReadError> {
        let mut map = HashMap::new();
        let mut saw_data = false;
        loop {
            // Skip to the next `DATA ;` (headers and other sections hold no geometry).
            match self.next_data()? {
                false => break,
                true => saw_data = true,
            }
            loop {
                self.skip_ws()?;
                let at = self.pos;
                match self.b.get(at).copied() {
                    Some(b'#') => {
                        self.pos += 1;
                        let id = self.integer().ok_or_else(|| {
                            self.err(
                                at,
                                format!(
                                    "found {}, expected an instance name like #12",
                                    self.found()
                                ),
                            )
                        })?;
                        self.expect(b'=', "`=` after the instance name")?;
                        let parts = self.record()?;
                        self.expect(b';', "`;` at the end of the instance")?;
                        if map.insert(id, Instance { offset: at, parts }).is_some() {
                            return Err(self.err(at, format!("instance #{id} is defined twice")));
                        }
                    }
                    Some(_) => {
                        let kw = self.keyword();
                        if kw.as_deref() == Some("ENDSEC") {
                            self.expect(b';', "`;` after ENDSEC")?;
                            break;
                        }
                        self.pos = at;
                        return Err(self.err(
                            at,
                            format!(
                                "found {}, expected an instance `#n = …;` or ENDSEC",
                                self.found()
                            ),
                        ));
                    }
                    None => {
                        return Err(self.err(at, "found end of file, expected ENDSEC".into()));
                    }
                }
            }
        }
        if !saw_data {
            let (line, column) = line_col(self.text, self.pos);
            return Err(ReadError::Syntax {
                format: Format::Step,
                line,
                column,
                message: "found end of file, expected a DATA section (is this a STEP file?)".into(),
            });
        }
        Ok(map)
    }

    /// Advance past the next `DATA;` (or `DATA(…);`); false at end of file.
    pub(super) fn next_data(&mut self) -> Result<bool, ReadError> {
        loop {
            match self.peek()? {
                None => return Ok(false),
                Some(b'\'') => {
                    self.string()?;
                }
                Some(c) if c.is_ascii_alphabetic() => {
                    let kw = self.keyword();
                    if kw.as_deref() == Some("DATA") {
                        if self.peek()? == Some(b'(') {
                            self.param(0)?;
                        }
                        self.expect(b';', "`;` after DATA")?;
                        return Ok(true);
                    }
                }
                Some(_) => self.pos += 1,
            }
        }
    }

    /// `KEYWORD(params)` or `(KEYWORD(params) KEYWORD(params) …)`.
    pub(super) fn record(&mut self) -> Result<Vec<(String, Vec<Param>)>, ReadError> {
        if self.peek()? == Some(b'(') {
            self.pos += 1;
            let mut parts = Vec::new();
            while self.peek()? != Some(b')') {
                parts.push(self.simple()?);
            }
            self.pos += 1;
            if parts.is_empty() {
                return Err(self.err(self.pos - 1, "empty complex instance `()`".into()));
            }
            Ok(parts)
        } else {
            Ok(vec![self.simple()?])
        }
    }

    pub(super) fn simple(&mut self) -> Result<(String, Vec<Param>), ReadError> {
        self.skip_ws()?;
        let at = self.pos;
        let kw = self.keyword().ok_or_else(|| {
            self.err(
                at,
                format!("found {}, expected an entity name", self.found()),
            )
        })?;
        let params = self.list(0)?;
        Ok((kw, params))
    }

    pub(super) fn list(&mut self, depth: usize) -> Result<Vec<Param>, ReadError> {
        if depth > MAX_DEPTH {
            return Err(self.err(self.pos, format!("lists nested deeper than {MAX_DEPTH}")));
        }
        self.expect(b'(', "`(`")?;
        let mut out = Vec::new();
        if self.peek()? == Some(b')') {
            self.pos += 1;
            return Ok(out);
        }
        loop {
            out.push(self.param(depth + 1)?);
            match self.peek()? {
                Some(b',') => self.pos += 1,
                Some(b')') => {
                    self.pos += 1;
                    return Ok(out);
                }
                _ => {
                    return Err(self.err(
                        self.pos,
                        format!(
                            "found {}, expected `,` or `)` in a parameter list",
                            self.found()
                        ),
                    ))
                }
            }
        }
    }

    pub(super) fn string(&mut self) -> Result<String, ReadError> {
        let start = self.pos;
        self.pos += 1;
        let mut s = String::new();
        loop {
            let rest = &self.text[self.pos..];
            match rest.find('\'') {
                None => return Err(self.err(start, "unterminated string".into())),
                Some(i) => {
                    s.push_str(&rest[..i]);
                    self.pos += i + 1;
                    if self.b.get(self.pos) == Some(&b'\'') {
                        s.push('\'');
                        self.pos += 1;
                    } else {
                        return Ok(decode(&s));
                    }
                }
            }
        }
    }

    pub(super) fn param(&mut self, depth: usize) -> Result<Param, ReadError> {
        let at = self.pos;
        match self.peek()? {
            Some(b'#') => {
                self.pos += 1;
                self.integer().map(Param::Ref).ok_or_else(|| {
                    self.err(at, "found `#`, expected an instance name like #12".into())
                })
            }
            Some(b'$') => {
                self.pos += 1;
                Ok(Param::Null)
            }
            Some(b'*') => {
                self.pos += 1;
                Ok(Param::Derived)
            }
            Some(b'\'') => self.string().map(Param::Str),
            Some(b'"') => {
                let rest = &self.text[self.pos + 1..];
                let i = rest
                    .find('"')
                    .ok_or_else(|| self.err(at, "unterminated binary `\"`".into()))?;
                self.pos += i + 2;
                Ok(Param::Str(rest[..i].to_string()))
            }
            Some(b'.') => {
                let start = self.pos;
                self.pos += 1;
                let kw = self.keyword().unwrap_or_default();
                if self.b.get(self.pos) != Some(&b'.') {
                    return Err(self.err(
                        start,
                        format!("found {}, expected an enumeration like .T.", self.found()),
                    ));
                }
                self.pos += 1;
                Ok(Param::Enum(kw))
            }
            Some(b'(') => self.list(depth).map(Param::List),
            Some(c) if c == b'+' || c == b'-' || c.is_ascii_digit() => {
                let start = self.pos;
                self.pos += 1;
                while self.b.get(self.pos).is_some_and(|c| {
                    c.is_ascii_digit() || matches!(c, b'.' | b'E' | b'e' | b'+' | b'-')
                }) {
                    self.pos += 1;
                }
                let s = &self.text[start..self.pos];
                let v = s
                    .parse::<f64>()
                    .ok()
                    .or_else(|| s.strip_suffix('.').and_then(|t| t.parse().ok()))
                    .or_else(|| s.replace(".E", "E").replace(".e", "e").parse().ok())
                    .filter(|v: &f64| v.is_finite())
                    .ok_or_else(|| self.err(start, format!("found `{s}`, expected a number")))?;
                Ok(Param::Num(v))
            }
            Some(c) if c.is_ascii_alphabetic() || c == b'_' => {
                let kw = self.keyword().unwrap_or_default();
                let inner = self.list(depth)?;
                Ok(Param::Typed(kw, inner))
            }
            _ => Err(self.err(at, format!("found {}, expected a parameter", self.found()))),
        }
    }
}

/// A string's characters from its ISO 10303-21 encoding (section 6.4.3; the doubled quotes
/// already undoubled): `\\` a backslash; `\S\c` the character `c` + 128 of the code page in
/// force (ISO 8859-1 unless a `\P?\` directive names another page); `\X\hh` the ISO 8859-1
/// character hh; `\X2\` … `\X0\` UCS-2 (UTF-16) code units, four hex digits each; `\X4\` …
/// `\X0\` UCS-4 code points, eight each. `\S\` under a page other than ISO 8859-1 (`\PA\`),
/// and any sequence that is not well formed, stay as written.
pub(super) fn decode(raw: &str) -> String {
    if !raw.contains('\\') {
        return raw.to_string();
    }
    let mut out = String::with_capacity(raw.len());
    let mut latin1 = true;
    let mut rest = raw;
    while let Some(c) = rest.chars().next() {
        if c != '\\' {
            out.push(c);
            rest = &rest[c.len_utf8()..];
            continue;
        }
        match escape(rest, &mut latin1) {
            Some((text, used)) => {
                out.push_str(&text);
                rest = &rest[used..];
            }
            None => {
                out.push('\\');
                rest = &rest[1..];
            }
        }
    }
    out
}

/// The escape at the start of `s` (which starts with a backslash): what it stands for and
/// the bytes it takes; `None` when it is not one. A code page directive sets `latin1`.
fn escape(s: &str, latin1: &mut bool) -> Option<(String, usize)> {
    let hex = |h: &str| -> Option<u32> {
        h.bytes()
            .all(|c| c.is_ascii_hexdigit())
            .then(|| u32::from_str_radix(h, 16).ok())?
    };
    if s.starts_with("\\\\") {
        return Some(("\\".into(), 2));
    }
    if let Some(r) = s.strip_prefix("\\S\\") {
        let c = r.chars().next().filter(char::is_ascii)?;
        return latin1.then(|| (char::from(c as u8 + 128).to_string(), 4));
    }
    if let Some(r) = s.strip_prefix("\\P") {
        let b = r.as_bytes();
        if b.len() >= 2 && b[0].is_ascii_uppercase() && b[1] == b'\\' {
            *latin1 = b[0] == b'A';
            return Some((String::new(), 4));
        }
        return None;
    }
    for (tag, width) in [("\\X2\\", 4), ("\\X4\\", 8)] {
        let Some(r) = s.strip_prefix(tag) else {
            continue;
        };
        let end = r.find("\\X0\\")?;
        let body = &r[..end];
        if body.len() % width != 0 || !body.is_ascii() {
            return None;
        }
        let units = (0..body.len() / width)
            .map(|k| hex(&body[k * width..(k + 1) * width]))
            .collect::<Option<Vec<u32>>>()?;
        let text = if width == 4 {
            String::from_utf16(&units.iter().map(|&u| u as u16).collect::<Vec<_>>()).ok()?
        } else {
            units
                .into_iter()
                .map(char::from_u32)
                .collect::<Option<String>>()?
        };
        return Some((text, tag.len() + end + 4));
    }
    if let Some(r) = s.strip_prefix("\\X\\") {
        let c = char::from_u32(hex(r.get(..2)?)?)?;
        return Some((c.to_string(), 5));
    }
    None
}

pub(super) fn refs(p: &Param, out: &mut Vec<u64>) {
    match p {
        Param::Ref(r) => out.push(*r),
        Param::List(l) | Param::Typed(_, l) => l.iter().for_each(|q| refs(q, out)),
        _ => {}
    }
}

pub(super) fn show(p: Option<&Param>) -> String {
    match p {
        None => "nothing (too few attributes)".into(),
        Some(Param::Ref(r)) => format!("#{r}"),
        Some(Param::Num(v)) => format!("{v}"),
        Some(Param::Str(s)) => format!("'{s}'"),
        Some(Param::Enum(e)) => format!(".{e}."),
        Some(Param::List(_)) => "a list".into(),
        Some(Param::Typed(t, _)) => format!("{t}(…)"),
        Some(Param::Null) => "$".into(),
        Some(Param::Derived) => "*".into(),
    }
}
