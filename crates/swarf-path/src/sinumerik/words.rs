//! Sinumerik blocks cut into words: `N10 G1 X10.5 Y=IC(2) CR=5 F=R1*2 M3 ; comment`.
//!
//! A word is an address with a number written after it (`X10.5`, `G642`, `M30`, `L100`), an
//! address and `=` with an expression (`X=R1+2`, `A3=0.7071`, `T="MILL D10"`, `X=IC(5)`), a
//! call with its arguments (`CYCLE81(10,0,2,-5)`, `MSG("…")`), or a keyword (`TRAORI`,
//! `SUPA`, a subprogram's name). Words may be written without spaces (`G1X10Y20`).

/// One word of a block, upper case, with its byte offset in the block's code.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Word {
    /// The address or name (`X`, `G`, `A3`, `CR`, `CYCLE81`, `TRAORI`).
    pub(crate) name: String,
    pub(crate) value: Value,
    /// Byte offset of the word in the block's code.
    pub(crate) at: usize,
}

#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Value {
    /// A keyword or name alone.
    None,
    /// A number written after the address.
    Number(f64),
    /// `=` and an expression (as written, upper case).
    Expr(String),
    /// `(`…`)`: a call's arguments, as written.
    Args(String),
}

/// Why a block could not be cut into words: the offset and what is wrong.
#[derive(Debug, PartialEq)]
pub(crate) struct WordError {
    pub(crate) at: usize,
    pub(crate) message: &'static str,
}

/// The words of `code` (upper case, without block number, label and comment).
pub(crate) fn words(code: &str) -> Result<Vec<Word>, WordError> {
    let b = code.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        if c.is_ascii_whitespace() || c == b',' {
            i += 1;
            continue;
        }
        let start = i;
        if !(c.is_ascii_alphabetic() || c == b'_' || c == b'$') {
            return Err(WordError {
                at: i,
                message: "expected an address or a name",
            });
        }
        // The name: letters (and `_`/`$`), then — for an extended address (`A3=`, `I1=`,
        // `R10=`) or a call (`CYCLE81(`) — digits.
        while i < b.len() && (b[i].is_ascii_alphabetic() || b[i] == b'_' || b[i] == b'$') {
            i += 1;
        }
        let letters = i;
        let mut j = i;
        while j < b.len() && (b[j].is_ascii_alphanumeric() || b[j] == b'_') {
            j += 1;
        }
        let next = b.get(j).copied();
        if NAMES_WITH_DIGITS
            .iter()
            .any(|n| n.eq_ignore_ascii_case(&code[start..j]))
        {
            // `CUT3DC`, `CDOF2`: one name, not an address and a number.
            i = j;
        }
        // `R1 = 5`, `X = 20`: spaces before the `=` of an assignment.
        let eq = skip_ws(b, j);
        let assigns = b.get(eq) == Some(&b'=') && b.get(eq + 1) != Some(&b'=');
        if assigns || (j > letters && matches!(next, Some(b'('))) {
            i = j;
        } else if j > letters
            && code[letters..j].bytes().all(|c| c.is_ascii_digit())
            && !matches!(next, Some(b'.'))
        {
            // `G642`, `M30`, `L100`: the digits are the value.
        } else if j > letters {
            // Letters and digits run together (`CYCLE832` alone, `R1` as a name) only when no
            // number follows them; `X10.5` goes to the number below.
            let rest = &code[letters..j];
            if !rest.bytes().next().is_some_and(|c| c.is_ascii_digit()) {
                i = j;
            }
        }
        let name = code[start..i].to_string();
        let eq = skip_ws(b, i);
        let value = match b.get(eq) {
            Some(b'=') if b.get(eq + 1) != Some(&b'=') => {
                let v = skip_ws(b, eq + 1);
                i = expr_end(b, v)?;
                Value::Expr(code[v..i].trim().to_string())
            }
            Some(b'(') => {
                let v = i + 1;
                i = close(b, i)?;
                Value::Args(code[v..i - 1].to_string())
            }
            Some(c) if c.is_ascii_digit() || matches!(c, b'.' | b'+' | b'-') => {
                let v = i;
                if matches!(b[i], b'+' | b'-') {
                    i += 1;
                }
                while i < b.len() && (b[i].is_ascii_digit() || b[i] == b'.') {
                    i += 1;
                }
                let text = &code[v..i];
                let n = crate::heidenhain::lexer::number(text).ok_or(WordError {
                    at: v,
                    message: "bad number",
                })?;
                Value::Number(n)
            }
            _ => Value::None,
        };
        out.push(Word {
            name,
            value,
            at: start,
        });
    }
    Ok(out)
}

/// Sinumerik keywords whose names end in digits or mix them with letters: read whole, not as
/// an address with a number.
const NAMES_WITH_DIGITS: [&str; 12] = [
    "CUT2D", "CUT2DF", "CUT3DC", "CUT3DCC", "CUT3DCCD", "CUT3DF", "CUT3DFS", "CUT3DFF", "CDOF2",
    "ORIVIRT1", "ORIVIRT2", "DIAM90",
];

fn skip_ws(b: &[u8], mut i: usize) -> usize {
    while b.get(i).is_some_and(u8::is_ascii_whitespace) {
        i += 1;
    }
    i
}

/// Characters that join the terms of an expression across spaces (`R1 + 2`).
const OPERATORS: &[u8] = b"+-*/<>=^";

/// Words that do (`R3 = 10 MOD 3`).
const WORD_OPERATORS: [&str; 6] = ["DIV", "MOD", "AND", "OR", "XOR", "NOT"];

/// The end of an expression from `i`: the next space outside parentheses and quotes that
/// neither follows nor precedes an operator.
fn expr_end(b: &[u8], mut i: usize) -> Result<usize, WordError> {
    let start = i;
    let mut depth = 0usize;
    let mut quoted = false;
    while i < b.len() {
        match b[i] {
            b'"' => quoted = !quoted,
            _ if quoted => {}
            b'(' | b'[' => depth += 1,
            b')' | b']' if depth == 0 => break,
            b')' | b']' => depth -= 1,
            c if depth == 0 && c.is_ascii_whitespace() => {
                let after = skip_ws(b, i);
                let before = b[..i].iter().rev().find(|c| !c.is_ascii_whitespace());
                // The word operators too: `10 MOD 3`, `R1==0 AND R2==0`.
                let word_at = |j: usize, back: bool| -> bool {
                    let w: Vec<u8> = if back {
                        let e = b[..j]
                            .iter()
                            .rposition(|c| !c.is_ascii_whitespace())
                            .map_or(0, |k| k + 1);
                        let s0 = b[..e]
                            .iter()
                            .rposition(|c| !c.is_ascii_alphabetic())
                            .map_or(0, |k| k + 1);
                        b[s0..e].to_vec()
                    } else {
                        b[j..]
                            .iter()
                            .take_while(|c| c.is_ascii_alphabetic())
                            .copied()
                            .collect()
                    };
                    WORD_OPERATORS.iter().any(|o| o.as_bytes() == w.as_slice())
                };
                let joined = before.is_some_and(|c| OPERATORS.contains(c))
                    || b.get(after).is_some_and(|c| OPERATORS.contains(c))
                    || word_at(i, true)
                    || word_at(after, false);
                if !joined || after >= b.len() {
                    break;
                }
                i = after;
                continue;
            }
            _ => {}
        }
        i += 1;
    }
    if quoted || depth > 0 {
        return Err(WordError {
            at: start,
            message: "unclosed parenthesis or quote",
        });
    }
    if i == start {
        return Err(WordError {
            at: start,
            message: "nothing after '='",
        });
    }
    Ok(i)
}

/// The position after the `)` closing the `(` at `i`.
fn close(b: &[u8], mut i: usize) -> Result<usize, WordError> {
    let start = i;
    let mut depth = 0usize;
    let mut quoted = false;
    while i < b.len() {
        match b[i] {
            b'"' => quoted = !quoted,
            _ if quoted => {}
            b'(' => depth += 1,
            b')' => {
                depth -= 1;
                if depth == 0 {
                    return Ok(i + 1);
                }
            }
            _ => {}
        }
        i += 1;
    }
    Err(WordError {
        at: start,
        message: "unclosed parenthesis",
    })
}

/// Splits a call's arguments at the commas outside parentheses and quotes.
pub(crate) fn args(s: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let (mut depth, mut quoted, mut from) = (0usize, false, 0);
    for (i, c) in s.bytes().enumerate() {
        match c {
            b'"' => quoted = !quoted,
            _ if quoted => {}
            b'(' => depth += 1,
            b')' => depth = depth.saturating_sub(1),
            b',' if depth == 0 => {
                out.push(s[from..i].trim());
                from = i + 1;
            }
            _ => {}
        }
    }
    out.push(s[from..].trim());
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(code: &str) -> Vec<(String, Value)> {
        words(code)
            .unwrap()
            .into_iter()
            .map(|w| (w.name, w.value))
            .collect()
    }

    #[test]
    fn words_of_every_form() {
        use Value::*;
        assert_eq!(
            names("G1X10.5Y-.5 F=R1*2 CR=5"),
            [
                ("G".into(), Number(1.0)),
                ("X".into(), Number(10.5)),
                ("Y".into(), Number(-0.5)),
                ("F".into(), Expr("R1*2".into())),
                ("CR".into(), Expr("5".into()))
            ]
        );
        assert_eq!(
            names("G642 A3=0.5 X=IC(2) CYCLE81(10,0,2,-5) TRAORI M30"),
            [
                ("G".into(), Number(642.0)),
                ("A3".into(), Expr("0.5".into())),
                ("X".into(), Expr("IC(2)".into())),
                ("CYCLE81".into(), Args("10,0,2,-5".into())),
                ("TRAORI".into(), None),
                ("M".into(), Number(30.0))
            ]
        );
        assert_eq!(
            names("T=\"END MILL\""),
            [("T".into(), Expr("\"END MILL\"".into()))]
        );
        assert_eq!(
            names("L100 P3"),
            [("L".into(), Number(100.0)), ("P".into(), Number(3.0))]
        );
        assert_eq!(names("R10=R1+1"), [("R10".into(), Expr("R1+1".into()))]);
        assert_eq!(
            names("R3=10 MOD 3 R5=R1==0 AND R2==0 X1"),
            [
                ("R3".into(), Expr("10 MOD 3".into())),
                ("R5".into(), Expr("R1==0 AND R2==0".into())),
                ("X".into(), Number(1.0))
            ]
        );
        assert_eq!(
            names("R1 = 5 X = R2 + 2 Y=3"),
            [
                ("R1".into(), Expr("5".into())),
                ("X".into(), Expr("R2 + 2".into())),
                ("Y".into(), Expr("3".into()))
            ]
        );
        assert!(words("X=").is_err());
        assert!(words("MSG(\"a").is_err());
        assert!(words("X1.2.3").is_err());
        assert_eq!(
            args("1,(2,3),\"a,b\",,5"),
            ["1", "(2,3)", "\"a,b\"", "", "5"]
        );
    }
}
