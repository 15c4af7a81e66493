//! Heidenhain blocks and words: a program's lines cut into blocks (the block number, the
//! statement, its `;` comment; TNC 640 continuation lines ending in `~` joined), each statement
//! cut into whitespace-separated tokens that keep their line and column, and a token read as a
//! word (`X+10.5`, `IX-Q3`, `DR+`, `FMAX`, `RL`).

use super::{Fault, Res};

/// One token of a statement: its text in upper case (ASCII; other characters as written) and
/// where it starts.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Tok {
    pub(crate) text: String,
    pub(crate) line: u32,
    pub(crate) col: u32,
}

/// A parameter reference: `Q5`, `QL5` (local), `QR5` (non-volatile), negated by a leading `-`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct QRef {
    pub(crate) kind: u8,
    pub(crate) index: u32,
    pub(crate) negate: bool,
}

/// The value part of a word.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Val {
    /// Nothing after the letters (`FMAX`, `RL`, `R0` reads as a number).
    None,
    /// A bare sign (`DR+`, `R-`).
    Sign(f64),
    /// A number.
    Num(f64),
    /// A parameter.
    Q(QRef),
}

/// One block: the line it starts on, its statement's tokens (continuation lines included) and
/// the raw statement text of its first line (for formulas), with the column where it starts.
#[derive(Clone, Debug, Default)]
pub(crate) struct Block {
    pub(crate) line: u32,
    pub(crate) toks: Vec<Tok>,
    /// The statement on the first line, upper case, without block number and comment.
    pub(crate) code: String,
    /// 1-based column of `code`'s first character.
    pub(crate) code_col: u32,
    /// The block's comment (after `;`, or a `*` structure block's text).
    pub(crate) comment: Option<String>,
}

/// The program's blocks, in order. A line whose statement ends in `~` continues on the next
/// line (TNC 640 cycle definitions: `CYCL DEF 200 DRILLING ~`, then one `Q200=+2 ;SET-UP
/// CLEARANCE ~` per line).
pub(crate) fn blocks(text: &str) -> Res<Vec<Block>> {
    let mut out: Vec<Block> = Vec::new();
    let mut continuing = false;
    for (i, raw) in crate::gcode::lexer::lines(text).enumerate() {
        let line = u32::try_from(i + 1).unwrap_or(u32::MAX);
        let raw = if i == 0 {
            raw.strip_prefix('\u{feff}').unwrap_or(raw)
        } else {
            raw
        };
        // A `~` ends a continued line, after its comment if it has one.
        let trimmed = raw.trim_end();
        let continues = trimmed.ends_with('~');
        let raw = if continues {
            &trimmed[..trimmed.len() - 1]
        } else {
            raw
        };
        let (code, comment) = split_comment(raw);
        let upper = code.to_ascii_uppercase();
        // Where the statement starts: after the block number (not on a continuation line).
        let lead = upper.len() - upper.trim_start().len();
        let mut start = lead;
        if !continuing {
            let digits = upper[lead..].bytes().take_while(u8::is_ascii_digit).count();
            start += digits;
        }
        let rest = &upper[start..];
        let body_start = start + (rest.len() - rest.trim_start().len());
        let body = upper[body_start..].trim_end();
        // Columns count characters, as the G-code reader's do.
        let body_col = upper[..body_start].chars().count() as u32 + 1;
        let toks = tokens(body, line, body_col)?;
        if continuing {
            if let Some(b) = out.last_mut() {
                b.toks.extend(toks);
            }
        } else {
            let star = body.starts_with('*');
            out.push(Block {
                line,
                toks: if star { Vec::new() } else { toks },
                code: if star {
                    String::new()
                } else {
                    body.to_string()
                },
                code_col: body_col,
                comment: if star {
                    Some(code[body_start + 1..].trim().to_string())
                } else {
                    comment.map(|c| c.trim().to_string())
                },
            });
        }
        continuing = continues;
    }
    Ok(out)
}

/// The code of a line and its `;` comment (a `;` inside quotes is text).
fn split_comment(raw: &str) -> (&str, Option<&str>) {
    let mut quoted = false;
    for (i, c) in raw.char_indices() {
        match c {
            '"' => quoted = !quoted,
            ';' if !quoted => return (&raw[..i], Some(&raw[i + 1..])),
            _ => {}
        }
    }
    (raw, None)
}

/// The whitespace-separated tokens of `body` (upper case), which starts at column `col0` of
/// `line`; a quoted name (`"MILL D10"`) is one token with its quotes.
fn tokens(body: &str, line: u32, col0: u32) -> Res<Vec<Tok>> {
    let mut out = Vec::new();
    let b = body.as_bytes();
    let mut i = 0;
    while i < b.len() {
        if b[i].is_ascii_whitespace() {
            i += 1;
            continue;
        }
        let start = i;
        if b[i] == b'"' {
            match body[i + 1..].find('"') {
                Some(j) => i += j + 2,
                None => {
                    return Err(Fault {
                        line,
                        col: col0 + body[..start].chars().count() as u32,
                        kind: crate::PathErrorKind::Syntax,
                        message: "unclosed quoted name".into(),
                        found: body[start..].to_string(),
                        expected: "a name in double quotes".into(),
                    })
                }
            }
        } else {
            while i < b.len() && !b[i].is_ascii_whitespace() {
                i += 1;
            }
        }
        out.push(Tok {
            text: body[start..i].to_string(),
            line,
            col: col0 + body[..start].chars().count() as u32,
        });
    }
    Ok(out)
}

/// Reads a signed decimal number (`+10.5`, `-.5`, `10`, `+0.`) filling all of `s`.
pub(crate) fn number(s: &str) -> Option<f64> {
    let digits = s.strip_prefix(['+', '-']).unwrap_or(s);
    let ok = !digits.is_empty()
        && digits.bytes().any(|c| c.is_ascii_digit())
        && digits.bytes().all(|c| c.is_ascii_digit() || c == b'.')
        && digits.bytes().filter(|&c| c == b'.').count() <= 1;
    let v: f64 = if ok { s.parse().ok()? } else { return None };
    v.is_finite().then_some(v)
}

/// Reads a parameter reference (`Q5`, `-QL2`, `+QR10`) filling all of `s`.
pub(crate) fn qref(s: &str) -> Option<QRef> {
    let (negate, rest) = match s.as_bytes().first()? {
        b'-' => (true, &s[1..]),
        b'+' => (false, &s[1..]),
        _ => (false, s),
    };
    let rest = rest.strip_prefix('Q')?;
    let (kind, digits) = match rest.as_bytes().first()? {
        b'L' => (b'L', &rest[1..]),
        b'R' => (b'R', &rest[1..]),
        _ => (b'Q', rest),
    };
    if digits.is_empty() || !digits.bytes().all(|c| c.is_ascii_digit()) {
        return None;
    }
    Some(QRef {
        kind,
        index: digits.parse().ok()?,
        negate,
    })
}

/// A token as a word: its letters and what follows them.
pub(crate) fn word(t: &Tok) -> Res<(&str, Val)> {
    let s = t.text.as_str();
    let n = s.bytes().take_while(u8::is_ascii_alphabetic).count();
    let (name, rest) = s.split_at(n);
    // `QL`/`QR` parameters after a letter: `X+QL3` splits as `X` and `+QL3`; a word whose
    // letters run into the parameter (`XQ3`) is split at the `Q`.
    let (name, rest) = match name.find('Q') {
        Some(q) if q > 0 && qref(&s[q..]).is_some() => (&s[..q], &s[q..]),
        _ => (name, rest),
    };
    let val = match rest {
        "" => Val::None,
        "+" => Val::Sign(1.0),
        "-" => Val::Sign(-1.0),
        _ => match (number(rest), qref(rest)) {
            (Some(v), _) => Val::Num(v),
            (None, Some(q)) => Val::Q(q),
            _ => {
                return Err(Fault {
                    line: t.line,
                    col: t.col + n as u32,
                    kind: crate::PathErrorKind::Syntax,
                    message: format!("bad value in the word {s}"),
                    found: rest.to_string(),
                    expected: "a signed number (+10.5) or a Q parameter".into(),
                })
            }
        },
    };
    Ok((name, val))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blocks_lose_numbers_and_comments_and_join_continuations() {
        let text = "0 BEGIN PGM A MM\n5 * - ROUGH\n6 L X+10 Y-5 FMAX ; go\n\
                    7 CYCL DEF 200 DRILLING ~\n  Q200=+2 ;SET-UP CLEARANCE ~\n  Q201=-5 ;DEPTH\n8 M30";
        let b = blocks(text).unwrap();
        assert_eq!(b.len(), 5);
        assert_eq!(b[1].comment.as_deref(), Some("- ROUGH"));
        assert!(b[1].toks.is_empty());
        let t: Vec<&str> = b[2].toks.iter().map(|t| t.text.as_str()).collect();
        assert_eq!(t, ["L", "X+10", "Y-5", "FMAX"]);
        assert_eq!((b[2].toks[1].line, b[2].toks[1].col), (3, 5));
        assert_eq!(b[2].comment.as_deref(), Some("go"));
        let t: Vec<&str> = b[3].toks.iter().map(|t| t.text.as_str()).collect();
        assert_eq!(t, ["CYCL", "DEF", "200", "DRILLING", "Q200=+2", "Q201=-5"]);
        assert_eq!((b[3].toks[5].line, b[3].toks[5].col), (6, 3));
        assert_eq!(b[4].line, 7);
    }

    #[test]
    fn words_read_signs_numbers_and_parameters() {
        let tok = |s: &str| Tok {
            text: s.into(),
            line: 1,
            col: 1,
        };
        assert_eq!(word(&tok("X+10.5")).unwrap(), ("X", Val::Num(10.5)));
        assert_eq!(word(&tok("IY-.5")).unwrap(), ("IY", Val::Num(-0.5)));
        assert_eq!(word(&tok("FMAX")).unwrap(), ("FMAX", Val::None));
        assert_eq!(word(&tok("DR+")).unwrap(), ("DR", Val::Sign(1.0)));
        assert_eq!(word(&tok("R0")).unwrap(), ("R", Val::Num(0.0)));
        let q = |kind, index, negate| {
            Val::Q(QRef {
                kind,
                index,
                negate,
            })
        };
        assert_eq!(word(&tok("Z-Q3")).unwrap(), ("Z", q(b'Q', 3, true)));
        assert_eq!(word(&tok("X+QL12")).unwrap(), ("X", q(b'L', 12, false)));
        assert_eq!(word(&tok("XQR2")).unwrap(), ("X", q(b'R', 2, false)));
        assert!(word(&tok("X+1.2.3")).is_err());
        assert!(word(&tok("X+")).is_ok());
        assert_eq!(number("1e5"), None);
        assert_eq!(number("."), None);
    }
}
