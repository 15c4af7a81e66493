//! Recognising programs written for controllers whose language is not RS274/NGC, so they are
//! rejected with a clear [`PathErrorKind::Unsupported`](crate::PathErrorKind) naming the dialect
//! instead of a confusing syntax error somewhere in the middle.

use std::fmt;

/// A controller language swarf recognises but does not read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dialect {
    /// Siemens Sinumerik 840D (`CR=`, `CYCLE81(…)`, `TRAORI`, `MSG("…")`, `DEF REAL …`).
    Siemens840D,
    /// Heidenhain conversational (`BEGIN PGM`, `L X+10 FMAX`, `TOOL CALL`, `CYCL DEF`).
    Heidenhain,
}

impl fmt::Display for Dialect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Dialect::Siemens840D => "Siemens 840D",
            Dialect::Heidenhain => "Heidenhain conversational",
        })
    }
}

impl Dialect {
    /// The dialect one program line is unmistakably written in, if any. RS274/NGC comments in
    /// parentheses are ignored, so a comment mentioning `TOOL CALL` is not a false alarm.
    pub fn of_line(line: &str) -> Option<Dialect> {
        // Code before any `;` comment, upper case, parenthesised comments kept only when the
        // parenthesis follows a word directly (Siemens `MSG(`, `CYCLE81(`).
        let code = line.split(';').next().unwrap_or("");
        let trimmed = code.trim_start();
        // Heidenhain lines start with a block number.
        let body = trimmed
            .trim_start_matches(|c: char| c.is_ascii_digit())
            .trim_start();
        let upper = |s: &str| s.to_ascii_uppercase();
        let b = upper(body);
        if body.len() != trimmed.len() || b.starts_with("BEGIN PGM") {
            const HEID: [&str; 8] = [
                "BEGIN PGM",
                "END PGM",
                "TOOL CALL",
                "CYCL DEF",
                "BLK FORM",
                "CALL LBL",
                "LBL ",
                "FN ",
            ];
            if HEID.iter().any(|k| b.starts_with(k)) {
                return Some(Dialect::Heidenhain);
            }
            if (b.starts_with("L ") || b.starts_with("CC ") || b.starts_with("C "))
                && (b.contains("X+")
                    || b.contains("X-")
                    || b.contains("Y+")
                    || b.contains("Y-")
                    || b.contains("Z+")
                    || b.contains("Z-")
                    || b.contains("FMAX"))
            {
                return Some(Dialect::Heidenhain);
            }
        }
        if b.starts_with("TOOL CALL") || b.starts_with("CYCL DEF") {
            return Some(Dialect::Heidenhain);
        }
        // Siemens calls stand at the start of a block (after an optional N number); anything
        // else in parentheses is an RS274/NGC comment.
        let after_n = {
            let t = b.trim_start();
            let t = t
                .strip_prefix('N')
                .map_or(t, |r| r.trim_start_matches(|c: char| c.is_ascii_digit()));
            t.trim_start().to_string()
        };
        const CALLS: [&str; 7] = [
            "MSG(",
            "MSG (",
            "CYCLE",
            "POCKET",
            "SLOT1(",
            "SLOT2(",
            "WORKPIECE(",
        ];
        if CALLS.iter().any(|k| after_n.starts_with(k)) && after_n.contains('(') {
            return Some(Dialect::Siemens840D);
        }
        let mut no_comments = String::with_capacity(b.len());
        let mut depth = 0;
        for ch in b.chars() {
            match ch {
                '(' => depth += 1,
                ')' if depth > 0 => depth -= 1,
                _ if depth == 0 => no_comments.push(ch),
                _ => {}
            }
        }
        const SIEMENS: [&str; 9] = [
            "CR=", "TRAORI", "DEF REAL", "DEF INT", "MCALL", "SUPA", "AROT", "TURN=", "=AC(",
        ];
        let tight: String = no_comments.chars().filter(|c| !c.is_whitespace()).collect();
        let tight_n = tight.strip_prefix('N').map_or(tight.as_str(), |r| {
            r.trim_start_matches(|c: char| c.is_ascii_digit())
        });
        if SIEMENS.iter().any(|k| tight.contains(&k.replace(' ', "")))
            || tight.contains("=IC(")
            || tight_n.starts_with("G500")
        {
            return Some(Dialect::Siemens840D);
        }
        // Words of the 840D's own that posts write at a program's head (look-ahead, units,
        // acceleration, tools by name, system variables, jumps): whole words, or the text
        // they start.
        const WORDS: [&str; 16] = [
            "G642", "G641", "G645", "G710", "G700", "SOFT", "BRISK", "FFWON", "FFWOF", "STOPRE",
            "TRAFOOF", "ORIWKS", "ORIAXES", "COMPCAD", "COMPCURV", "COMPOF",
        ];
        const STARTS: [&str; 3] = ["T=\"", "GOTOF", "GOTOB"];
        const SYSTEM: [&str; 5] = ["$P_", "$A_", "$AA_", "$MC_", "$TC_"];
        if no_comments.split_whitespace().any(|w| {
            let w = w
                .strip_prefix('N')
                .filter(|r| r.starts_with(|c: char| c.is_ascii_digit()))
                .map_or(w, |r| r.trim_start_matches(|c: char| c.is_ascii_digit()));
            WORDS.contains(&w)
                || STARTS.iter().any(|k| w.starts_with(k))
                || SYSTEM.iter().any(|k| w.contains(k))
        }) {
            return Some(Dialect::Siemens840D);
        }
        None
    }

    /// The first dialect found in the first `lines` lines of `text`, with its 1-based line.
    pub fn detect(text: &str, lines: usize) -> Option<(Dialect, u32)> {
        super::lexer::lines(text)
            .take(lines)
            .enumerate()
            .find_map(|(i, l)| Self::of_line(l).map(|d| (d, i as u32 + 1)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recognises_dialects() {
        assert_eq!(
            Dialect::of_line("0 BEGIN PGM TEST MM"),
            Some(Dialect::Heidenhain)
        );
        assert_eq!(
            Dialect::of_line("5 L X+10 Y-5 R0 FMAX"),
            Some(Dialect::Heidenhain)
        );
        assert_eq!(
            Dialect::of_line("3 TOOL CALL 1 Z S2000"),
            Some(Dialect::Heidenhain)
        );
        assert_eq!(
            Dialect::of_line("N20 G2 X10 Y10 CR=5"),
            Some(Dialect::Siemens840D)
        );
        assert_eq!(
            Dialect::of_line("CYCLE81(10,0,2,-5)"),
            Some(Dialect::Siemens840D)
        );
        assert_eq!(
            Dialect::of_line("MSG(\"hello\")"),
            Some(Dialect::Siemens840D)
        );
        assert_eq!(Dialect::of_line("TRAORI"), Some(Dialect::Siemens840D));
        assert_eq!(Dialect::of_line("G500"), Some(Dialect::Siemens840D));
        for line in [
            "N10 G17 G90 G710",
            "G642 SOFT FFWON",
            "T=\"EM10\" D1",
            "N30 GOTOF END1",
            "R1=$P_TOOLNO",
            "WORKPIECE(,\"\",,\"BOX\",112,0,-50,-80,-50,-50,50,50)",
        ] {
            assert_eq!(Dialect::of_line(line), Some(Dialect::Siemens840D), "{line}");
        }
        // Not these: a Fanuc lathe G70, a comment.
        assert_eq!(Dialect::of_line("G70 P100 Q200"), None);
        assert_eq!(Dialect::of_line("G0 X1 (SOFT JAWS, G642)"), None);
        // RS274/NGC lines, including comments that mention the keywords.
        assert_eq!(Dialect::of_line("G1 X10 Y-5 F100"), None);
        assert_eq!(Dialect::of_line("(TOOL CALL 1, CR=5, MSG(x))"), None);
        assert_eq!(Dialect::of_line("G0 X1 (MSG, hello)"), None);
        assert_eq!(Dialect::of_line("o100 call [1]"), None);
        assert_eq!(Dialect::of_line("N10 G1 X1 ; CYCLE81 in a comment"), None);
        assert_eq!(Dialect::of_line("%"), None);
        assert_eq!(Dialect::of_line("G1X1(CR=5)"), None);
    }
}
