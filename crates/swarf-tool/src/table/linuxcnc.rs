//! LinuxCNC tool tables (`.tbl`): one tool per line, `T1 P1 D0.125 Z+1.0 ;comment`.
//!
//! Words are a letter and a number: `T` tool number, `P` pocket, `X Y Z A B C U V W` offsets,
//! `D` diameter, `I` front angle, `J` back angle, `Q` orientation; `;` starts the comment,
//! which becomes the description. The offsets `X Y Z A B C` and the pocket are kept
//! ([`ToolEntry::offsets`], [`ToolEntry::pocket`]: G43 applies them; U V W are not). Lengths are in the machine's units, given by the caller.
//! The table carries no shape, so every tool is taken as a **flat end mill** of diameter D
//! (noted in the warnings); a positive Z offset (the tool length) becomes the overall length.
//! A tool with no diameter, or a diameter that is not positive (probes, placeholders), is an
//! error at its line, as in swarf's TOML library: a table the simulation cannot use whole is
//! not used in part (remove the line, or give the tool its diameter).

use super::{LengthUnit, ToolEntry, ToolTable};
use crate::cutter::{Cutter, CutterKind, CutterOptions};
use crate::error::TableError;

/// Parses a LinuxCNC tool table whose lengths are in `unit`; `file` names the source in errors.
pub fn parse_linuxcnc(text: &str, file: &str, unit: LengthUnit) -> Result<ToolTable, TableError> {
    let mut table = ToolTable::default();
    let scale = unit.to_mm();
    for (li, raw) in text.lines().enumerate() {
        let line = li + 1;
        let err = |column: usize, found: String, expected: &str| TableError::Parse {
            file: file.to_string(),
            line,
            column,
            found,
            expected: expected.to_string(),
        };
        let (body, comment) = match raw.find(';') {
            Some(i) => (&raw[..i], raw[i + 1..].trim()),
            None => (raw, ""),
        };
        if body.trim().is_empty() {
            continue;
        }
        let mut number = None;
        let mut diameter = None;
        let mut z = None;
        let mut pocket = None;
        let mut offsets = [0.0; 6];
        let mut has_offsets = false;
        let mut offset = 0;
        for word in body.split_whitespace() {
            let start = offset + body[offset..].find(word).unwrap_or(0);
            offset = start + word.len();
            let column = body[..start].chars().count() + 1;
            let mut chars = word.chars();
            let letter = chars.next().unwrap_or(' ').to_ascii_uppercase();
            let num_text = chars.as_str();
            if !"TPXYZABCUVWDIJQ".contains(letter) || !letter.is_ascii_alphabetic() {
                return Err(err(
                    column,
                    format!("{word:?}"),
                    "a word starting with one of T P X Y Z A B C U V W D I J Q",
                ));
            }
            let value: f64 = match num_text.parse() {
                Ok(v) if f64::is_finite(v) => v,
                _ => {
                    return Err(err(
                        column + 1,
                        format!("{num_text:?} after {letter}"),
                        "a number",
                    ))
                }
            };
            match letter {
                'T' => {
                    if value.fract() != 0.0 || !(0.0..=u32::MAX as f64).contains(&value) {
                        return Err(err(
                            column + 1,
                            format!("T{num_text}"),
                            "a whole tool number",
                        ));
                    }
                    if number.is_some() {
                        return Err(err(column, "a second T word".into(), "one T word per line"));
                    }
                    number = Some((value as u32, column));
                }
                'D' => diameter = Some((value * scale, column, start)),
                'P' if value.fract() == 0.0 && (0.0..=u32::MAX as f64).contains(&value) => {
                    pocket = Some(value as u32)
                }
                'X' | 'Y' | 'Z' | 'A' | 'B' | 'C' => {
                    let i = "XYZABC".find(letter).unwrap_or(0);
                    // Lengths in the table's unit, angles in degrees.
                    offsets[i] = if i < 3 { value * scale } else { value };
                    has_offsets = true;
                    if letter == 'Z' {
                        z = Some(value * scale);
                    }
                }
                _ => {}
            }
        }
        let Some((number, tcol)) = number else {
            return Err(err(
                1,
                format!("{:?}", body.trim()),
                "a tool line with a T word",
            ));
        };
        if table.tools.contains_key(&number) {
            return Err(err(
                tcol,
                format!("tool T{number} a second time"),
                "unique tool numbers",
            ));
        }
        let d = match diameter {
            Some((d, _, _)) if d > 0.0 => d,
            // No diameter, or D0: LinuxCNC's own tables have such lines (`T99999 … Z+0.1`, a
            // probe); the table serves the other tools, and a program cutting with this one
            // is refused then (its offsets still apply).
            None | Some((0.0, _, _)) => {
                table.left_out.insert(
                    number,
                    format!(
                        "{file}:{line}: T{number} has no diameter (D) in a LinuxCNC table, so no \
                         cutter; LinuxCNC reads it as 0"
                    ),
                );
                table
                    .left_out_offsets
                    .insert(number, (has_offsets.then_some(offsets), pocket));
                continue;
            }
            Some((_, column, start)) => {
                // (`start` is the word's byte offset: `column` counts characters.)
                let word = body[start..].split_whitespace().next().unwrap_or("D");
                return Err(err(
                    column + 1,
                    format!("T{number} with diameter {word}"),
                    "a diameter (D) of 0 or more: a negative one makes no cutter",
                ));
            }
        };
        let overall = z.filter(|&z| z > 0.0);
        let opts = CutterOptions {
            overall_length: overall,
            // A flute length of 3·d may exceed a short tool length: cap it.
            flute_length: overall.map(|l| l.min(3.0 * d)),
            ..CutterOptions::default()
        };
        let cutter = Cutter::named(CutterKind::Flat, &[d], &opts)
            .map_err(|e| err(tcol, e.to_string(), "a valid tool"))?;
        table.warnings.push(format!(
            "{file}:{line}: T{number}: a LinuxCNC table has no shape information; assumed a flat end mill of diameter {d} mm"
        ));
        table.tools.insert(
            number,
            ToolEntry {
                cutter,
                description: comment.to_string(),
                name: None,
                offsets: has_offsets.then_some(offsets),
                pocket,
            },
        );
    }
    Ok(table)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The offsets (`X Y Z A B C`, lengths in the table's unit) and the pocket are kept.
    #[test]
    fn keeps_offsets_and_pocket() {
        let text = "T1 P7 D0.125 Z+1.0 X-0.5 C90 U3\nT2 P2 D0.25\n";
        let t = parse_linuxcnc(text, "tool.tbl", LengthUnit::Inch).unwrap();
        assert_eq!(
            t.tools[&1].offsets,
            Some([-12.7, 0.0, 25.4, 0.0, 0.0, 90.0])
        );
        assert_eq!(t.tools[&1].pocket, Some(7));
        assert_eq!(t.tools[&2].offsets, None);
        assert_eq!(t.tools[&2].pocket, Some(2));
    }

    #[test]
    fn reads_inch_table() {
        let text = "T1 P1 D0.125 Z+1.0 ;1/8 end mill\n\n; only a comment\nt3 p3 d0.5\n";
        let t = parse_linuxcnc(text, "tool.tbl", LengthUnit::Inch).unwrap();
        assert_eq!(t.tools.len(), 2);
        let c = &t.tools[&1].cutter;
        assert!((c.apt_params().d - 3.175).abs() < 1e-12);
        assert!((c.overall_length() - 25.4).abs() < 1e-12);
        assert_eq!(t.tools[&1].description, "1/8 end mill");
        assert!(t
            .warnings
            .iter()
            .any(|w| w.contains("T1") && w.contains("flat end mill")));
    }

    #[test]
    fn a_negative_diameter_is_an_error_at_its_line() {
        let (at, found, s) =
            parse_error("T1 P1 D0.125\nT2 P2 D-1 Z0\n", "tool.tbl", LengthUnit::Inch);
        assert_eq!(at, (2, 8), "{s}");
        assert_eq!(found, "T2 with diameter D-1");
        assert!(
            s.starts_with("tool.tbl:2:8") && s.contains("a diameter (D) of 0 or more"),
            "{s}"
        );
        let e = parse_linuxcnc("T1 D1\nT4 D-3\n", "t.tbl", LengthUnit::Mm).unwrap_err();
        assert!(e.to_string().starts_with("t.tbl:2:5"), "{e}");
    }

    /// LinuxCNC's own `tool.tbl` and `sim.tbl` end with `T99999 P99999 Z+0.1 ;big tool
    /// number` (no diameter), and probes are often `D0`: the table serves its other tools, the
    /// tool is left out with why (a program cutting with it is refused then), and its offsets
    /// and pocket still count. (The whole table was refused: "T99999 without a diameter".)
    #[test]
    fn a_tool_without_a_diameter_is_left_out_with_its_offsets() {
        let text = "T1 P1 D0.125 Z+0.511 ;1/8 end mill\nT2 P2 D0 Z+0.1 ;probe\n\
            T99999 P99999 Z+0.1 ;big tool number\n";
        let t = parse_linuxcnc(text, "tool.tbl", LengthUnit::Inch).unwrap();
        assert_eq!(t.tools.keys().collect::<Vec<_>>(), [&1]);
        assert_eq!(t.left_out.keys().collect::<Vec<_>>(), [&2, &99999]);
        assert!(
            t.left_out[&99999].starts_with("tool.tbl:3: T99999 has no diameter"),
            "{}",
            t.left_out[&99999]
        );
        let z = 0.1 * 25.4;
        assert_eq!(
            t.left_out_offsets[&2],
            (Some([0.0, 0.0, z, 0.0, 0.0, 0.0]), Some(2))
        );
        assert_eq!(
            t.left_out_offsets[&99999],
            (Some([0.0, 0.0, z, 0.0, 0.0, 0.0]), Some(99999))
        );
    }

    #[test]
    fn a_bad_diameter_after_a_wide_space_is_reported_not_a_panic() {
        // Found by the `tbl` fuzz target: the word was cut at its character column as if it
        // were a byte offset, inside a multi-byte space (U+2000).
        let (at, found, s) = parse_error("T6\u{2000}D-1\n", "w.tbl", LengthUnit::Mm);
        assert_eq!(at, (1, 5), "{s}");
        assert_eq!(found, "T6 with diameter D-1");
    }

    /// The position `(line, column)`, the `found` text and the message of the parse error
    /// `text` must give.
    fn parse_error(text: &str, file: &str, unit: LengthUnit) -> ((usize, usize), String, String) {
        let e = parse_linuxcnc(text, file, unit).unwrap_err();
        let TableError::Parse {
            line,
            column,
            ref found,
            ..
        } = e
        else {
            panic!("{e:?}")
        };
        ((line, column), found.clone(), e.to_string())
    }

    #[test]
    fn errors_name_line_and_column() {
        let e = parse_linuxcnc("T1 D1\nT2 D1x\n", "a.tbl", LengthUnit::Mm).unwrap_err();
        assert_eq!(
            e,
            TableError::Parse {
                file: "a.tbl".into(),
                line: 2,
                column: 5,
                found: "\"1x\" after D".into(),
                expected: "a number".into()
            }
        );
        let e = parse_linuxcnc("T1 D1\n  T1 D2\n", "a.tbl", LengthUnit::Mm).unwrap_err();
        assert!(
            matches!(
                e,
                TableError::Parse {
                    line: 2,
                    column: 3,
                    ..
                }
            ),
            "{e}"
        );
        let e = parse_linuxcnc("T1 D1 K3\n", "a.tbl", LengthUnit::Mm).unwrap_err();
        assert!(
            matches!(
                e,
                TableError::Parse {
                    line: 1,
                    column: 7,
                    ..
                }
            ),
            "{e}"
        );
        assert!(parse_linuxcnc("D1\n", "a.tbl", LengthUnit::Mm).is_err());
        // Non-ASCII junk must not panic.
        assert!(parse_linuxcnc("T1 Dé\né\n", "a.tbl", LengthUnit::Mm).is_err());
    }
}
