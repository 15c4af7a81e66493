//! Writing a program back with new feeds and every other byte as it was.
//!
//! A feed schedule gives each source line with feed moves a factor `r` (new feed / old feed).
//! The rewrite walks the text in order, tracking the feed word in effect in the original
//! (`F` in G-code, the first number of `FEDRAT/` in APT) and in the rewritten program: a line
//! with moves gets the original value times `r` — in its own F word, replaced in place, or in
//! one added after its last word (before a comment that follows it, `(…)` or `;`) when the
//! value in effect differs; an
//! APT move gets a `FEDRAT/` record inserted before it, in the form of the last one (a hole of
//! an APT drilling cycle with a feed of its own gets the `CYCLE/` record restated before it
//! with the new feed instead, as the cycle's feed is what its holes are fed at). Because the
//! F word is scaled, units (G20/G21, `IPM`/`MMPM`) and feed modes (G93 inverse time, G95 per
//! revolution) need no special case: each is proportional to the feed rate.
//!
//! The text is rewritten in source order, so the moves must come from the lines in the order
//! they are executed (no loops or subroutine calls over feed moves): the caller checks that.

use std::collections::BTreeMap;

use crate::gcode::lexer::{normalize, LineBuf};
use crate::load::ProgramFormat;
use crate::{PathError, PathErrorKind, SourcePos};

/// The rewritten text and what changed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Rewritten {
    /// The new program.
    pub text: String,
    /// Lines whose feed word was changed or added (1-based, of the original text).
    pub lines_changed: Vec<u32>,
}

/// A feed word's number: where it is in its line and its value.
#[derive(Clone, Copy, Debug)]
struct FeedWord {
    /// Byte range of the number.
    start: usize,
    end: usize,
    value: f64,
}

/// What a G-code line holds: its F word (`Err` with a column when it is not a plain number)
/// and where its code ends: after its last word, before any comment that follows it (`(…)`
/// or `;`), so that an added F word goes with the code, not after the comment.
fn scan_gcode(line: &str) -> (Option<Result<FeedWord, usize>>, usize) {
    let b = line.as_bytes();
    let (mut i, mut depth) = (0usize, 0usize);
    // End of the last byte of code seen (comments and blanks are not code).
    let mut code_end = 0usize;
    let mut feed = None;
    while i < b.len() {
        match b[i] {
            b'(' if depth == 0 => match line[i..].find(')') {
                Some(k) => i += k + 1,
                None => break,
            },
            b';' if depth == 0 => break,
            b'[' => {
                depth += 1;
                i += 1;
                code_end = i;
            }
            b']' => {
                depth = depth.saturating_sub(1);
                i += 1;
                code_end = i;
            }
            // A named parameter `#<…>` or subroutine `o<…>`: its name holds no word.
            b'#' | b'o' | b'O' if b.get(i + 1) == Some(&b'<') => {
                i += line[i..].find('>').map_or(b.len() - i, |k| k + 1);
                code_end = i;
            }
            // Letters of a keyword (`o1 if`, `endif`, Macro B's `IF`, `FIX[…]`) are no F word.
            b'f' | b'F'
                if depth == 0
                    && (i > 0 && b[i - 1].is_ascii_alphabetic()
                        || b.get(i + 1).is_some_and(u8::is_ascii_alphabetic)) =>
            {
                i += 1;
                code_end = i;
            }
            b'f' | b'F' if depth == 0 => {
                let mut j = i + 1;
                while j < b.len() && b[j] == b' ' {
                    j += 1;
                }
                let start = j;
                while j < b.len() && (b[j].is_ascii_digit() || matches!(b[j], b'.' | b'+' | b'-')) {
                    j += 1;
                }
                feed = Some(match line[start..j].parse::<f64>() {
                    Ok(v) if v.is_finite() => Ok(FeedWord {
                        start,
                        end: j,
                        value: v,
                    }),
                    _ => Err(i + 1),
                });
                i = j.max(i + 1);
                code_end = i;
            }
            c => {
                i += 1;
                if !c.is_ascii_whitespace() {
                    code_end = i;
                }
            }
        }
    }
    (feed, code_end)
}

/// An APT record's `FEDRAT/` number.
fn scan_apt(line: &str) -> Option<Result<FeedWord, usize>> {
    let t = line.trim_start();
    let lead = line.len() - t.len();
    if !t.to_ascii_uppercase().starts_with("FEDRAT") {
        return None;
    }
    let slash = t.find('/')?;
    // The first numeric field after the slash.
    let mut pos = lead + slash + 1;
    for field in line[pos..].split(',') {
        let trimmed = field.trim();
        if let Ok(v) = trimmed.parse::<f64>() {
            let start = pos + field.find(trimmed).unwrap_or(0);
            return Some(Ok(FeedWord {
                start,
                end: start + trimmed.len(),
                value: v,
            }));
        }
        pos += field.len() + 1;
    }
    Some(Err(lead + slash + 2))
}

/// What a Heidenhain line holds: its feed word (`F1000`, `FU0.2`; `Err` with a column for a
/// parameter or `FAUTO`; `FMAX` is no feed) and where a feed word goes in it (before its M
/// functions and its `;` comment: a TNC block runs coordinates, R, F, then M). A cycle
/// definition's `F` (old cycles) is the cycle's, and the `F` after `M128` that of M128's
/// compensating moves: neither is the program's feed.
fn scan_heidenhain(line: &str) -> (Option<Result<FeedWord, usize>>, usize) {
    let code = line.split(';').next().unwrap_or("");
    let mut code_end = code.trim_end().len();
    let upper = code.to_ascii_uppercase();
    let body = upper.trim_start_matches(|c: char| c.is_ascii_digit() || c.is_whitespace());
    if body.starts_with("CYCL") || body.starts_with('*') {
        return (None, code_end);
    }
    let mut found = None;
    let mut pos = 0;
    let mut prev = "";
    for tok in upper.split(|c: char| c.is_ascii_whitespace()) {
        let start = pos;
        pos += tok.len() + 1;
        let after_m128 = std::mem::replace(&mut prev, tok) == "M128";
        let is_m =
            tok.len() > 1 && tok.starts_with('M') && tok[1..].bytes().all(|c| c.is_ascii_digit());
        if is_m && code_end > start {
            code_end = upper[..start].trim_end().len();
        }
        let Some(rest) = tok.strip_prefix('F') else {
            continue;
        };
        if after_m128 {
            continue;
        }
        let rest = rest.strip_prefix('U').unwrap_or(rest);
        let skip = tok.len() - rest.len();
        if rest.is_empty() || rest == "MAX" || rest.starts_with("N") {
            continue;
        }
        found = Some(match rest.parse::<f64>() {
            Ok(v)
                if rest
                    .bytes()
                    .all(|c| c.is_ascii_digit() || b"+-.".contains(&c)) =>
            {
                Ok(FeedWord {
                    start: start + skip,
                    end: start + tok.len(),
                    value: v,
                })
            }
            _ => Err(start + 1),
        });
    }
    (found, code_end)
}

/// What a Sinumerik line holds: as [`scan_gcode`] (a `F=…` is an expression, refused on a
/// line to rescale), but the `F` of a `G4` block is its dwell in seconds, no feed.
fn scan_sinumerik(line: &str) -> (Option<Result<FeedWord, usize>>, usize) {
    let (word, end) = scan_gcode(line);
    let code = line.split(';').next().unwrap_or("").to_ascii_uppercase();
    let b = code.as_bytes();
    let dwell = ["G4", "G04"].iter().any(|g| {
        code.match_indices(g).any(|(i, m)| {
            let before = i.checked_sub(1).map(|j| b[j]);
            let after = b.get(i + m.len()).copied();
            !before.is_some_and(|c| c.is_ascii_alphanumeric() || c == b'_')
                && !after.is_some_and(|c| c.is_ascii_digit() || c == b'.')
        })
    });
    if dwell {
        (None, end)
    } else {
        (word, end)
    }
}

/// What a `CYCLE/` record does to the feed of the holes after it.
enum CycleLine {
    Off,
    On,
    /// A new cycle, with its own feed number (after `MMPM`, `IPM`, `MMPR` or `IPR`) or none
    /// (its holes are fed at the `FEDRAT/` in effect).
    Define(Option<FeedWord>),
}

/// An APT `CYCLE/` record.
fn scan_apt_cycle(line: &str) -> Option<CycleLine> {
    let t = line.trim_start();
    let upper = t.to_ascii_uppercase();
    let rest = upper
        .strip_prefix("CYCLE")?
        .trim_start()
        .strip_prefix('/')?;
    let first = rest.split(',').next().unwrap_or("").trim();
    match first {
        "OFF" => return Some(CycleLine::Off),
        "ON" => return Some(CycleLine::On),
        _ => {}
    }
    let mut pos = line.len() - rest.len();
    let mut after_unit = false;
    for field in line[pos..].split(',') {
        let trimmed = field.trim();
        if after_unit {
            let start = pos + field.find(trimmed).unwrap_or(0);
            return Some(CycleLine::Define(trimmed.parse::<f64>().ok().map(
                |value| FeedWord {
                    start,
                    end: start + trimmed.len(),
                    value,
                },
            )));
        }
        after_unit =
            ["MMPM", "IPM", "MMPR", "IPR"].contains(&trimmed.to_ascii_uppercase().as_str());
        pos += field.len() + 1;
    }
    Some(CycleLine::Define(None))
}

/// A feed word's number with about six significant digits, no trailing zeros.
pub fn format_feed(v: f64) -> String {
    let s = format!("{v:.*}", feed_decimals(v));
    let s = s.trim_end_matches('0');
    s.strip_suffix('.').unwrap_or(s).to_string()
}

/// Decimals of [`format_feed`]'s number: six significant digits (at least one decimal), below
/// 1 too — a feed per revolution (G95, F0.1) or an inverse time (G93) is a small number, and
/// six decimals left it four or five digits, 1e-4 off the scheduled feed.
fn feed_decimals(v: f64) -> usize {
    // Digits before the decimal point (0 or less below 1). (Saturating: an infinite or huge
    // value is refused before it is written; a zero takes the most decimals, and prints 0.)
    let digits = (v.abs().log10().floor() as i32).saturating_add(1);
    6i32.saturating_sub(digits).clamp(1, 15) as usize
}

/// [`format_feed`] of a positive feed, rounded down at its last digit: a feed scheduled to a
/// limit must not be written a hair above it (rounded to nearest, a feed capped for 300 N
/// gave 300.0003 N).
pub fn format_feed_down(v: f64) -> String {
    format_feed(round_down(v, 10f64.powi(feed_decimals(v) as i32)))
}

/// `v` rounded down to a multiple of `1/scale` — but a value on a digit but for the rounding
/// of the product that made it (a feed of 1 scheduled as 1.7 × (1/1.7) = 0.9999999999999999)
/// keeps that digit: within [`ON_A_DIGIT`] of it, relative. (Floored, `--min-feed 1` wrote
/// F0.999999, under the minimum asked for.)
fn round_down(v: f64, scale: f64) -> f64 {
    let nearest = (v * scale).round() / scale;
    if nearest <= v * (1.0 + ON_A_DIGIT) {
        nearest
    } else {
        (v * scale).floor() / scale
    }
}

/// How far above a feed (relative) its written digits may lie when they are the value it was
/// meant to be: a few roundings of a product (a feed nearer its cap than that is on it).
const ON_A_DIGIT: f64 = 4.0 * f64::EPSILON;

/// A positive feed rounded down to at most `places` decimals (a Heidenhain control takes
/// three), as [`format_feed_down`] rounds.
fn format_feed_down_places(v: f64, places: i32) -> String {
    let x = round_down(v, 10f64.powi(places));
    let s = format!("{x:.*}", places as usize);
    let s = s.trim_end_matches('0');
    s.strip_suffix('.').unwrap_or(s).to_string()
}

/// A piece of a G-code feed line moved out in front of it by a split: the displacement of the
/// tip over the piece in program units (X, Y, Z) and the factor of its feed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SplitPiece {
    /// Displacement, program units.
    pub delta: [f64; 3],
    /// New feed / old feed over the piece.
    pub factor: f64,
}

/// The modes a G-code line runs in, as far as splitting it needs them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LineModes {
    /// Absolute distances (G90) after the line's own words.
    pub absolute: bool,
    /// Inch units (G20) after the line's own words.
    pub inch: bool,
    /// A rotation or scaling of the program frame (G68, G68.2, G51, G10 L2/L20 with R) was
    /// seen on this line or before it.
    pub transformed: bool,
    /// The line's code is only a straight feed: `G1`, `X`, `Y`, `Z`, `F` and `N` words with
    /// plain numbers (and comments). Pieces put in front of it run as the line's own motion
    /// would; in front of a line with other words (`S`, `M3`, `M8`, `T`, a `G21`, a parameter)
    /// they would run before those took effect.
    pub plain: bool,
}

/// Whether a G-code line's code holds only `G1` (`G01`), `X`, `Y`, `Z`, `F` and `N` words whose
/// numbers are plain (comments aside), and no block delete (`/`): see [`LineModes::plain`].
/// `w` is the line's [`words`]; `lb` a buffer for the reader's own lexer, which strips the
/// comments.
fn plain_feed_line(line: &str, w: &[(char, f64)], lb: &mut LineBuf) -> bool {
    if normalize(line, lb).is_err() || lb.deleted {
        return false;
    }
    let letters = lb.code.iter().filter(|c| c.is_ascii_alphabetic()).count();
    // Every letter a word with a plain number (`X#1`, `F[…]`, `O100` fail it), nothing else.
    letters == w.len()
        && !lb.code.iter().any(|c| b"#[<=".contains(c))
        && w.iter().all(|&(c, v)| match c {
            'G' => v == 1.0,
            'X' | 'Y' | 'Z' | 'F' | 'N' => true,
            _ => false,
        })
}

/// The letter–number words of a G-code line's code (comments and bracketed expressions
/// skipped), upper case.
fn words(line: &str) -> Vec<(char, f64)> {
    let b = line.as_bytes();
    let (mut i, mut depth) = (0usize, 0usize);
    let mut out = Vec::new();
    while i < b.len() {
        match b[i] {
            b'(' if depth == 0 => i += line[i..].find(')').map_or(b.len() - i, |k| k + 1),
            b';' if depth == 0 => break,
            b'[' => {
                depth += 1;
                i += 1;
            }
            b']' => {
                depth = depth.saturating_sub(1);
                i += 1;
            }
            c if depth == 0 && c.is_ascii_alphabetic() => {
                let mut j = i + 1;
                while j < b.len() && b[j] == b' ' {
                    j += 1;
                }
                let start = j;
                while j < b.len() && (b[j].is_ascii_digit() || matches!(b[j], b'.' | b'+' | b'-')) {
                    j += 1;
                }
                if let Ok(v) = line[start..j].parse::<f64>() {
                    out.push((char::from(c).to_ascii_uppercase(), v));
                }
                i = j.max(i + 1);
            }
            _ => i += 1,
        }
    }
    out
}

/// The [`LineModes`] after each line of a straight-line G-code program (1-based: index 0 is
/// line 1), starting from G90 and `initial_inch`.
pub fn gcode_line_modes(text: &str, initial_inch: bool) -> Vec<LineModes> {
    let mut m = LineModes {
        absolute: true,
        inch: initial_inch,
        transformed: false,
        plain: false,
    };
    let mut lb = LineBuf::default();
    crate::load::program_lines(text, ProgramFormat::Gcode)
        .map(|line| {
            let w = words(line);
            m.plain = plain_feed_line(line, &w, &mut lb);
            let g = |x: f64| w.iter().any(|&(c, v)| c == 'G' && (v - x).abs() < 1e-9);
            m.absolute = if g(91.0) {
                false
            } else {
                m.absolute || g(90.0)
            };
            m.inch = if g(20.0) { true } else { m.inch && !g(21.0) };
            let l = |x: f64| w.iter().any(|&(c, v)| c == 'L' && (v - x).abs() < 1e-9);
            m.transformed |= g(68.0)
                || g(68.2)
                || g(51.0)
                || (g(10.0) && (l(2.0) || l(20.0)) && w.iter().any(|&(c, _)| c == 'R'));
            m
        })
        .collect()
}

/// A coordinate with six decimals, no trailing zeros, no negative zero.
fn format_coordinate(v: f64) -> String {
    let s = format!("{v:.6}");
    let s = s.trim_end_matches('0');
    let s = s.strip_suffix('.').unwrap_or(s);
    if s == "-0" {
        "0".to_string()
    } else {
        s.to_string()
    }
}

/// Rewrites the feed words of `text` (`file` names it in errors) so that the moves of each line
/// in `factors` run at their original feed times its factor. Every line with feed moves should
/// be in `factors` (factor 1 to keep its feed), so that a changed feed does not carry over.
///
/// A G-code line in `splits` (a straight 3-axis feed in absolute mode, without rotation or
/// scaling in effect: the caller checks) is preceded by its pieces as incremental moves — `G91
/// G1 X… Y… Z… F…` — then `G90`; the line itself, unchanged but for its feed, ends the move
/// exactly where it did.
///
/// # Errors
/// A line with moves and a feed word that is not a plain number (an expression or parameter),
/// or moves before any feed word.
pub fn rewrite_feeds(
    text: &str,
    file: &str,
    format: ProgramFormat,
    factors: &BTreeMap<u32, f64>,
    splits: &BTreeMap<u32, Vec<SplitPiece>>,
) -> Result<Rewritten, PathError> {
    let mut out = String::with_capacity(text.len() + 16 * factors.len());
    let mut changed = Vec::new();
    let (mut original, mut current): (Option<f64>, Option<f64>) = (None, None);
    // The last FEDRAT record, as a template for inserted ones.
    let mut template: Option<(String, FeedWord)> = None;
    // APT drilling cycles with a feed of their own: the record and its feed number as first
    // written (the template for copies with new feeds inserted before holes), whether a cycle
    // is on, and the cycle feed in effect in the rewritten program.
    let mut cycle: Option<(String, FeedWord)> = None;
    let mut cycle_on = false;
    let mut cycle_current: Option<f64> = None;
    let err = |line: u32, column: usize, message: &str, found: &str| {
        PathError::new(
            SourcePos {
                file: file.to_string(),
                line,
                column: column as u32,
            },
            PathErrorKind::Unsupported,
            message,
            found,
            "a plain number, which swarf schedule can rescale",
        )
    };
    for (k, raw) in crate::load::program_lines_with_ends(text, format).enumerate() {
        let n = k as u32 + 1;
        let body_len = raw.trim_end_matches(['\n', '\r']).len();
        let (body, eol) = raw.split_at(body_len);
        if format == ProgramFormat::Apt {
            if let Some(c) = scan_apt_cycle(body) {
                // A record continued over lines would need its copies to keep the continuation.
                if body
                    .split("$$")
                    .next()
                    .unwrap_or("")
                    .trim_end()
                    .ends_with('$')
                {
                    return Err(err(
                        n,
                        1,
                        "a CYCLE/ record continued over lines ($) is not rewritten",
                        body.trim(),
                    ));
                }
                match c {
                    CycleLine::Off => cycle_on = false,
                    CycleLine::On => cycle_on = true,
                    CycleLine::Define(Some(w)) if !w.value.is_finite() => {
                        return Err(err(
                            n,
                            w.start + 1,
                            "the cycle's feed is not a finite number",
                            body.get(w.start..w.end).unwrap_or("").trim(),
                        ));
                    }
                    CycleLine::Define(w) => {
                        cycle_on = true;
                        cycle = w.map(|w| (body.to_string(), w));
                        cycle_current = w.map(|w| w.value);
                    }
                }
                out.push_str(raw);
                continue;
            }
        }
        let (word, code_end) = match format {
            ProgramFormat::Gcode => scan_gcode(body),
            ProgramFormat::Sinumerik => scan_sinumerik(body),
            ProgramFormat::Apt => (scan_apt(body), body.len()),
            ProgramFormat::Heidenhain => scan_heidenhain(body),
        };
        if format == ProgramFormat::Heidenhain && factors.get(&n).is_some_and(|f| *f != 1.0) {
            let upper = body.split(';').next().unwrap_or("").to_ascii_uppercase();
            if upper.contains("M99") || upper.contains("CYCL CALL") || upper.contains("M89") {
                return Err(err(
                    n,
                    1,
                    "a cycle's feed is its Q206 (or its own F), which swarf schedule does not                      rewrite",
                    body.trim(),
                ));
            }
        }
        let word = match word {
            Some(Ok(w)) => Some(w),
            Some(Err(col)) if factors.contains_key(&n) || format == ProgramFormat::Apt => {
                return Err(err(
                    n,
                    col,
                    "the feed word is not a plain number",
                    body.get(col.saturating_sub(1)..).unwrap_or("").trim(),
                ));
            }
            // An expression F on a line without feed moves: its value is unknown from here on.
            Some(Err(_)) => {
                original = None;
                current = None;
                out.push_str(raw);
                continue;
            }
            None => None,
        };
        if let Some(w) = word {
            if !w.value.is_finite() {
                return Err(err(
                    n,
                    w.start + 1,
                    "the feed is not a finite number",
                    body.get(w.start..w.end).unwrap_or("").trim(),
                ));
            }
            original = Some(w.value);
            if format == ProgramFormat::Apt {
                template = Some((body.to_string(), w));
            }
        }
        let Some(&factor) = factors.get(&n) else {
            if let Some(w) = word {
                current = Some(w.value);
            }
            out.push_str(raw);
            continue;
        };
        let hole = format == ProgramFormat::Apt
            && cycle_on
            && body.trim_start().to_ascii_uppercase().starts_with("GOTO");
        if let (true, Some((t, w))) = (hole, &cycle) {
            // A hole of a cycle with its own feed: the cycle is restated before it with the
            // new feed (the holes' feeds are the cycle's, not FEDRAT's).
            let target = w.value * factor;
            let value = if (target - w.value).abs() <= 1e-9 * w.value.abs() {
                w.value
            } else {
                format_feed_down(target).parse().unwrap_or(target)
            };
            if cycle_current != Some(value) {
                changed.push(n);
                let text = if value == w.value {
                    t[w.start..w.end].to_string()
                } else {
                    format_feed_down(target)
                };
                out.push_str(&t[..w.start]);
                out.push_str(&text);
                out.push_str(&t[w.end..]);
                out.push_str(if eol.is_empty() { "\n" } else { eol });
                cycle_current = Some(value);
            }
            out.push_str(raw);
            continue;
        }
        let Some(base) = original else {
            return Err(err(n, 1, "feed moves before any feed word", body.trim()));
        };
        if let (Some(pieces), ProgramFormat::Gcode) = (splits.get(&n), format) {
            let nl = if eol.is_empty() { "\n" } else { eol };
            for (k, p) in pieces.iter().enumerate() {
                let f = format_feed_down(base * p.factor);
                out.push_str(if k == 0 { "G91 G1" } else { "G1" });
                for (axis, d) in ["X", "Y", "Z"].iter().zip(p.delta) {
                    out.push(' ');
                    out.push_str(axis);
                    out.push_str(&format_coordinate(d));
                }
                out.push_str(" F");
                out.push_str(&f);
                out.push_str(nl);
                current = f.parse().ok();
            }
            if !pieces.is_empty() {
                out.push_str("G90");
                out.push_str(nl);
                changed.push(n);
            }
        }
        let target = base * factor;
        // A feed that does not change keeps its own digits (and its exact value).
        let unchanged = |v: f64| (v - target).abs() <= 1e-9 * target.abs();
        let (new_text, value) = match word {
            Some(w) if unchanged(w.value) => (body[w.start..w.end].to_string(), w.value),
            _ if unchanged(base) && current == Some(base) => (format_feed(base), base),
            _ => {
                let t = if format == ProgramFormat::Heidenhain {
                    format_feed_down_places(target, 3)
                } else {
                    format_feed_down(target)
                };
                let v = t.parse::<f64>().unwrap_or(target);
                (t, v)
            }
        };
        match (word, format) {
            (Some(w), _) => {
                if (w.value - value).abs() > 0.0 {
                    changed.push(n);
                }
                out.push_str(&body[..w.start]);
                out.push_str(if (w.value - value).abs() > 0.0 {
                    &new_text
                } else {
                    &body[w.start..w.end]
                });
                out.push_str(&body[w.end..]);
                out.push_str(eol);
            }
            (None, ProgramFormat::Gcode | ProgramFormat::Heidenhain | ProgramFormat::Sinumerik) => {
                if current != Some(value) {
                    changed.push(n);
                    out.push_str(&body[..code_end]);
                    out.push_str(" F");
                    out.push_str(&new_text);
                    out.push_str(&body[code_end..]);
                    out.push_str(eol);
                } else {
                    out.push_str(raw);
                }
            }
            (None, ProgramFormat::Apt) => {
                if current != Some(value) {
                    changed.push(n);
                    let record = match &template {
                        Some((t, w)) => format!("{}{}{}", &t[..w.start], new_text, &t[w.end..]),
                        None => format!("FEDRAT/{new_text}"),
                    };
                    out.push_str(&record);
                    out.push_str(if eol.is_empty() { "\n" } else { eol });
                }
                out.push_str(raw);
            }
        }
        current = Some(value);
    }
    Ok(Rewritten {
        text: out,
        lines_changed: changed,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn factors(v: &[(u32, f64)]) -> BTreeMap<u32, f64> {
        v.iter().copied().collect()
    }

    /// An APT text rewritten with these line factors and no splits.
    fn apt(text: &str, f: &[(u32, f64)]) -> Result<Rewritten, PathError> {
        rewrite_feeds(
            text,
            "t.apt",
            ProgramFormat::Apt,
            &factors(f),
            &BTreeMap::new(),
        )
    }

    #[test]
    fn gcode_feeds_replaced_added_and_restored() {
        let text = "G21 G90\r\nG1 X10 F600 (first)\r\nG1 X20\r\nG1 X30 ; last\r\nG0 Z5\r\n";
        let r = rewrite_feeds(
            text,
            "t.ngc",
            ProgramFormat::Gcode,
            &factors(&[(2, 0.5), (3, 1.0), (4, 1.0)]),
            &BTreeMap::new(),
        )
        .unwrap();
        assert_eq!(
            r.text,
            "G21 G90\r\nG1 X10 F300 (first)\r\nG1 X20 F600\r\nG1 X30 ; last\r\nG0 Z5\r\n"
        );
        assert_eq!(r.lines_changed, vec![2, 3]);
        // An added F goes after the line's last word, before the comments that follow it
        // (a parenthesised one too: it was appended after it, `X20 (comment) F300`), and after
        // a comment that comes before the words.
        let text =
            "G1 X10 F600\nG1 X20 (comment)\nG1 X30 (a) ; b\n(lead) G1 X40 (trail)  \nG1 X50\t(x)\n";
        let r = rewrite_feeds(
            text,
            "t.ngc",
            ProgramFormat::Gcode,
            &factors(&[(1, 1.0), (2, 0.5), (3, 1.0), (4, 0.5), (5, 1.0)]),
            &BTreeMap::new(),
        )
        .unwrap();
        assert_eq!(
            r.text,
            "G1 X10 F600\nG1 X20 F300 (comment)\nG1 X30 F600 (a) ; b\n(lead) G1 X40 F300 (trail)  \nG1 X50 F600\t(x)\n"
        );
        // Unchanged factors change nothing.
        let same = rewrite_feeds(
            text,
            "t.ngc",
            ProgramFormat::Gcode,
            &factors(&[(2, 1.0), (3, 1.0), (4, 1.0)]),
            &BTreeMap::new(),
        )
        .unwrap();
        assert_eq!(same.text, text);
        assert!(same.lines_changed.is_empty());
    }

    /// The letters of keywords are no F words: LinuxCNC's `o1 if`/`endif`/`elseif`, Fanuc's
    /// `IF`, `FIX[…]`, `FUP[…]` (each used to read as an expression F, after which the feed
    /// was unknown and the next feed move refused).
    #[test]
    fn keywords_hold_no_feed_word() {
        for line in [
            "o1 if [#1 GT 0]",
            "O100 ENDIF",
            "o2 elseif [#2 EQ 1]",
            "IF [#1 GT 3] GOTO 10",
            "#1=FIX[#2]+FUP[#3]",
            "o<f1> call",
            "O<cut_f> sub",
            "#<feed>=3",
        ] {
            assert!(scan_gcode(line).0.is_none(), "{line}");
        }
        for (line, v) in [
            ("G1X10F100", 100.0),
            ("g1 x1 f 25.5", 25.5),
            ("F2.(x)", 2.0),
        ] {
            assert_eq!(scan_gcode(line).0.unwrap().unwrap().value, v, "{line}");
        }
        assert!(scan_gcode("G1 X1 F#1").0.unwrap().is_err());
    }

    /// The holes of an APT drilling cycle with its own feed are fed at the cycle's feed, not
    /// FEDRAT's: the cycle is restated before a hole with a new feed, and read back each hole
    /// is fed at its scheduled feed while the program's feed is untouched.
    #[test]
    fn apt_cycle_feeds_are_restated_before_their_holes() {
        let text = "FEDRAT/MMPM,500\nGOTO/0,0,50\nCYCLE/DRILL,FEDTO,-12,RAPTO,3,MMPM,100\n\
                    GOTO/10,20,0\nGOTO/30,20,0\nGOTO/40,20,0\nCYCLE/OFF\nGOTO/0,0,50\n";
        let r = apt(text, &[(4, 0.5), (5, 0.5), (6, 1.0), (8, 1.0)]).unwrap();
        assert_eq!(
            r.text,
            "FEDRAT/MMPM,500\nGOTO/0,0,50\nCYCLE/DRILL,FEDTO,-12,RAPTO,3,MMPM,100\n\
             CYCLE/DRILL,FEDTO,-12,RAPTO,3,MMPM,50\nGOTO/10,20,0\nGOTO/30,20,0\n\
             CYCLE/DRILL,FEDTO,-12,RAPTO,3,MMPM,100\nGOTO/40,20,0\nCYCLE/OFF\nGOTO/0,0,50\n"
        );
        assert_eq!(r.lines_changed, [4, 6]);
        // Read back: the feed in effect at each feed move.
        let mut rec = crate::canon::Recorder::default();
        crate::apt::read_apt(&r.text, "t.apt", &Default::default(), &mut rec).unwrap();
        let mut feed = 0.0;
        let mut fed = Vec::new();
        for (_, e) in &rec.events {
            match e {
                crate::Canon::FeedRate(f) => feed = *f,
                crate::Canon::Feed { .. } => fed.push(feed),
                _ => {}
            }
        }
        assert_eq!(fed, [50.0, 50.0, 100.0, 500.0]);
        // GODLTA inside a cycle is a move fed at FEDRAT; a continued CYCLE record is refused.
        let text = "FEDRAT/MMPM,500\nGOTO/0,0,50\nCYCLE/DRILL,FEDTO,-12,MMPM,100\nGODLTA/1,0,0\n";
        let r = apt(text, &[(4, 0.5)]).unwrap();
        assert!(
            r.text.contains("FEDRAT/MMPM,250\nGODLTA/1,0,0\n"),
            "{}",
            r.text
        );
        let text = "FEDRAT/MMPM,500\nCYCLE/DRILL,FEDTO,-12, $\nMMPM,100\nGOTO/1,2,3\n";
        let e = apt(text, &[(4, 0.5)]).unwrap_err();
        assert_eq!(e.pos.line, 2);
        let bad = "CYCLE/DRILL,FEDTO,-12,MMPM,inf\nGOTO/1,2,3\n";
        let e = apt(bad, &[(2, 1.0)]).unwrap_err();
        assert_eq!((e.pos.line, e.pos.column), (1, 28));
        // A cycle without a feed of its own is fed at FEDRAT, which is rescaled as usual.
        let text = "FEDRAT/MMPM,500\nGOTO/0,0,50\nCYCLE/DRILL,FEDTO,-12\nGOTO/10,20,0\n";
        let r = apt(text, &[(4, 0.5)]).unwrap();
        assert_eq!(
            r.text,
            "FEDRAT/MMPM,500\nGOTO/0,0,50\nCYCLE/DRILL,FEDTO,-12\nFEDRAT/MMPM,250\nGOTO/10,20,0\n"
        );
    }

    #[test]
    fn gcode_f_in_comments_and_expressions() {
        let text = "G1 X1 F100 (F999)\nG1 X2 [#<f>*2]\n#1 = [FIX[2.5]]\nG1 X3\n";
        let r = rewrite_feeds(
            text,
            "t.ngc",
            ProgramFormat::Gcode,
            &factors(&[(1, 2.0), (2, 2.0), (4, 1.0)]),
            &BTreeMap::new(),
        )
        .unwrap();
        assert_eq!(
            r.text,
            "G1 X1 F200 (F999)\nG1 X2 [#<f>*2]\n#1 = [FIX[2.5]]\nG1 X3 F100\n"
        );
        let e = rewrite_feeds(
            "G1 X1 F[#1]\n",
            "t.ngc",
            ProgramFormat::Gcode,
            &factors(&[(1, 2.0)]),
            &BTreeMap::new(),
        )
        .unwrap_err();
        assert_eq!((e.pos.line, e.pos.column), (1, 7));
        let e = rewrite_feeds(
            "G1 X1\n",
            "t.ngc",
            ProgramFormat::Gcode,
            &factors(&[(1, 2.0)]),
            &BTreeMap::new(),
        )
        .unwrap_err();
        assert!(e.message.contains("before any feed word"));
    }

    #[test]
    fn apt_fedrat_records_rescaled_and_inserted() {
        let text = "FEDRAT/ 500.0000,MMPM\nGOTO/1,0,0\nGOTO/2,0,0\nRAPID\nGOTO/2,0,9\n";
        let r = rewrite_feeds(
            text,
            "t.apt",
            ProgramFormat::Apt,
            &factors(&[(2, 0.5), (3, 1.0)]),
            &BTreeMap::new(),
        )
        .unwrap();
        assert_eq!(
            r.text,
            "FEDRAT/ 500.0000,MMPM\nFEDRAT/ 250,MMPM\nGOTO/1,0,0\nFEDRAT/ 500,MMPM\nGOTO/2,0,0\nRAPID\nGOTO/2,0,9\n"
        );
    }

    #[test]
    fn a_split_line_gets_incremental_pieces_in_front() {
        let text = "G21 G90\nG1 X0 Y0 F600\nG1 X30 Y0\nG0 Z5\n";
        let splits: BTreeMap<u32, Vec<SplitPiece>> = [(
            3,
            vec![
                SplitPiece {
                    delta: [10.0, 0.0, 0.0],
                    factor: 0.5,
                },
                SplitPiece {
                    delta: [10.0, -0.0, 0.0],
                    factor: 0.25,
                },
            ],
        )]
        .into_iter()
        .collect();
        let r = rewrite_feeds(
            text,
            "t.ngc",
            ProgramFormat::Gcode,
            &factors(&[(2, 1.0), (3, 1.0)]),
            &splits,
        )
        .unwrap();
        assert_eq!(
            r.text,
            "G21 G90\nG1 X0 Y0 F600\nG91 G1 X10 Y0 Z0 F300\nG1 X10 Y0 Z0 F150\nG90\nG1 X30 Y0 F600\nG0 Z5\n"
        );
    }

    #[test]
    fn only_a_line_of_motion_and_feed_is_plain() {
        let plain = |line: &str| gcode_line_modes(line, false)[0].plain;
        for yes in [
            "G1 X30 Y0",
            "N20 G01 X30.5 Y-2 Z-3 F600 (comment: S1 M3)",
            "x1 y2 ; M8 in a comment",
            "G1X1Y2F3",
        ] {
            assert!(plain(yes), "{yes}");
        }
        for no in [
            "G1 X50 F1000 M3 S10000",
            "G21 G1 X10",
            "G1 X10 M8",
            "G1 X#1",
            "G1 X[1+2]",
            "G1 X#<x>",
            "/G1 X10",
            "T2 G1 X10",
            "G1 X10 E3",
            "G2 X10 I5",
            "G91 G1 X10",
            "O100 sub",
        ] {
            assert!(!plain(no), "{no}");
        }
    }

    #[test]
    fn an_unchanged_feed_keeps_its_digits() {
        // Found by the fuzzer: F317.2802 at factor 1 was rounded to six digits.
        let text = "G1 X1 F317.2802\nG1 X2\nFEDRAT/ 123.456789\n";
        let ones = factors(&[(1, 1.0), (2, 1.0)]);
        let r =
            rewrite_feeds(text, "t.ngc", ProgramFormat::Gcode, &ones, &BTreeMap::new()).unwrap();
        assert_eq!(r.text, text);
        assert!(r.lines_changed.is_empty());
    }

    #[test]
    fn an_infinite_feed_is_refused_not_written() {
        // Found by the fuzzer: FEDRAT/ 3.3E3333333 overflowed the digit count (a panic in a
        // debug build; "inf" written in a release one).
        let huge = format!("G1 X1 F{}\nG1 X2\n", "9".repeat(400));
        for (text, format) in [
            ("FEDRAT/ 3.3E3333333\nGOTO/1,2,3\n", ProgramFormat::Apt),
            (huge.as_str(), ProgramFormat::Gcode),
        ] {
            let f = factors(&[(1, 0.5), (2, 0.5)]);
            let e = rewrite_feeds(text, "t", format, &f, &BTreeMap::new()).unwrap_err();
            // (G-code's number reader refuses the 400 digits itself: not a plain number.)
            assert!(e.to_string().contains("not a"), "{e}");
        }
        // Out of range, the digit count saturates instead of overflowing.
        assert_eq!(feed_decimals(f64::INFINITY), 1);
        assert_eq!(feed_decimals(f64::MAX), 1);
    }

    #[test]
    fn feed_numbers_keep_six_digits() {
        assert_eq!(format_feed(1234.5678), "1234.57");
        assert_eq!(format_feed(600.0), "600");
        // Rounded down, except where only a product's rounding put the value under a digit.
        assert_eq!(format_feed_down(300.00049), "300");
        assert_eq!(format_feed_down(299.99999), "299.999");
        assert_eq!(format_feed_down(1.0 - 1e-16), "1");
        assert_eq!(format_feed_down(1.7 * (1.0 / 1.7)), "1");
        assert_eq!(format_feed_down(1.0 - 1e-9), "0.999999");
        assert_eq!(format_feed_down_places(2.0 - 1e-15, 3), "2");
        assert_eq!(format_feed_down_places(1.9999, 3), "1.999");
        assert_eq!(format_feed(0.0123456), "0.0123456");
        assert_eq!(format_feed(0.10282176), "0.102822");
        assert_eq!(format_feed(0.0), "0");
        assert_eq!(format_feed(25.0), "25");
        // Down at the last digit, never over the value asked for.
        assert_eq!(format_feed_down(1234.5678), "1234.56");
        assert_eq!(format_feed_down(600.0), "600");
        assert_eq!(format_feed_down(0.0123456), "0.0123456");
        assert_eq!(format_feed_down(0.10282176), "0.102821");
        for v in [
            299.99999,
            299.9999999999,
            999.9999999999,
            123.456789,
            1e-3 / 3.0,
            5e4 / 7.0,
        ] {
            assert!(format_feed_down(v).parse::<f64>().unwrap() <= v, "{v}");
        }
        // Within 1e-5 of the value at every magnitude a feed word takes: mm/min, inch/min, a
        // feed per revolution (G95) and an inverse time (G93) — `swarf schedule` reads its
        // program back and checks each feed to that.
        let mut v = 1.234_567_891e-4;
        while v < 1e6 {
            for x in [v, v * 1.000_009_9, v * 9.999_99] {
                let w: f64 = format_feed_down(x).parse().unwrap();
                assert!(w <= x && x - w < 1e-5 * x, "{x} written {w}");
            }
            v *= 1.37;
        }
    }
}
