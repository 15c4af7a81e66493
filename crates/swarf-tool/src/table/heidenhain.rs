//! Heidenhain tool tables (`TOOL.T`, iTNC 530 and TNC 640): `BEGIN TOOL .T MM|INCH`, a header
//! line naming the columns, one tool per line in those columns, `[END]`.
//!
//! The columns are fixed-width, and a row's field is what stands between its column's start
//! in the header and the next column's (so a `DOC` with spaces is one field); tabs count to
//! stops of 8, and a table with one tab between its fields on every line is read by tabs. Read: `T` (the
//! number), `NAME`, `L` (length: the overall length), `R` (radius), `R2` (corner radius),
//! `LCUTS` (cutting length: the flute length), `CUT` (teeth), `TYP` (TNC 640: `DRILL`,
//! `CENTER`, `CSINK` … are drills or countersinks), `T-ANGLE` (point angle), `DOC` (the
//! description). The shape follows from the radii: `R2 = R` a ball-nose, `0 < R2 < R` a
//! bull-nose, `R2 = 0` a flat end mill; a drilling type with a point angle is a drill. Rows
//! whose radius is not positive (the null tool 0, empty places) carry no cutter and are left
//! out, which the warnings count.

use super::{LengthUnit, ToolEntry, ToolTable};
use crate::cutter::{Cutter, CutterKind, CutterOptions};
use crate::error::TableError;

/// Parses a Heidenhain `TOOL.T` table; `file` names the source in errors.
pub fn parse_heidenhain(text: &str, file: &str) -> Result<ToolTable, TableError> {
    let err = |line: usize, column: usize, found: String, expected: &str| TableError::Parse {
        file: file.to_string(),
        line,
        column,
        found,
        expected: expected.to_string(),
    };
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let Some((_, begin)) = lines.next() else {
        return Err(err(1, 1, "an empty file".into(), "BEGIN TOOL .T MM|INCH"));
    };
    let begin = begin.trim_start_matches('\u{feff}');
    let words: Vec<String> = begin
        .split_whitespace()
        .map(str::to_ascii_uppercase)
        .collect();
    if words.first().map(String::as_str) != Some("BEGIN")
        || !begin.to_ascii_uppercase().contains(".T")
    {
        return Err(err(
            1,
            1,
            format!("{:?}", begin.trim()),
            "BEGIN TOOL .T MM|INCH",
        ));
    }
    let unit = if words.iter().any(|w| w == "INCH") {
        LengthUnit::Inch
    } else {
        LengthUnit::Mm
    };
    let scale = unit.to_mm();
    let Some((hi, header)) = lines.next() else {
        return Err(err(
            2,
            1,
            "no header line".into(),
            "the column names (T NAME L R R2 …)",
        ));
    };
    // The data rows (up to `[END]`), for the layout.
    let rows: Vec<(usize, &str)> = lines
        .take_while(|(_, l)| !l.trim_start().starts_with("[END]"))
        .collect();
    let layout = Layout::of(header);
    let columns: Vec<String> = layout
        .cells(header, usize::MAX)
        .into_iter()
        .map(|(name, _)| name.to_ascii_uppercase())
        .collect();
    let find = |name: &str| columns.iter().position(|n| n == name);
    let (Some(t_col), Some(r_col)) = (find("T"), find("R")) else {
        return Err(err(
            hi + 1,
            1,
            format!("{:?}", header.trim()),
            "a header with the columns T and R",
        ));
    };
    let mut table = ToolTable::default();
    let mut empty = 0;
    for (li, raw) in rows {
        let line = li + 1;
        let cells = layout.cells(raw, columns.len());
        let field = |c: usize| -> (String, usize) {
            cells
                .get(c)
                .cloned()
                .unwrap_or((String::new(), raw.chars().count() + 1))
        };
        let number = |c: Option<usize>| -> Result<Option<f64>, TableError> {
            let Some(c) = c else { return Ok(None) };
            let (text, column) = field(c);
            if text.is_empty() {
                return Ok(None);
            }
            match text.parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(Some(v)),
                _ => Err(err(
                    line,
                    column,
                    format!("{text:?} in column {}", columns[c]),
                    "a number",
                )),
            }
        };
        let (t_text, t_column) = field(t_col);
        let t = match t_text.parse::<f64>() {
            Ok(v) if v >= 0.0 && v.fract() == 0.0 && v <= f64::from(u32::MAX) => v as u32,
            // An indexed tool (`1.1`): a variant of tool 1, which the programs call by its
            // number; left out.
            Ok(v) if v >= 0.0 && v <= f64::from(u32::MAX) => {
                table
                    .warnings
                    .push(format!("{file}:{line}: indexed tool {t_text} left out"));
                continue;
            }
            _ => {
                return Err(err(
                    line,
                    t_column,
                    format!("{t_text:?} as the tool number"),
                    "a whole tool number",
                ))
            }
        };
        // The wear offsets DR, DR2 (the control adds them to R, R2): applied, as the control
        // cuts with them.
        let dr = number(find("DR"))?.unwrap_or(0.0) * scale;
        let dr2 = number(find("DR2"))?.unwrap_or(0.0) * scale;
        let r = (number(Some(r_col))?.unwrap_or(0.0) * scale + dr).max(0.0);
        if r <= 0.0 {
            empty += 1;
            continue;
        }
        if table.tools.contains_key(&t) {
            return Err(err(
                line,
                t_column,
                format!("tool {t} a second time"),
                "unique tool numbers",
            ));
        }
        let r2_col = find("R2");
        let r2 = (number(r2_col)?.unwrap_or(0.0) * scale + dr2).max(0.0);
        if dr != 0.0 || dr2 != 0.0 {
            table.warnings.push(format!(
                "{file}:{line}: tool {t}: its wear offsets DR {dr} mm, DR2 {dr2} mm are applied, \
                 as the control applies them: R {r} mm, R2 {r2} mm"
            ));
        }
        if r2 > r + 1e-9 {
            let column = r2_col.map_or(1, |c| field(c).1);
            return Err(err(
                line,
                column,
                format!("tool {t}: R2 {r2} mm, larger than its radius R {r} mm"),
                "a corner radius R2 no larger than R (R2 = R: a ball-nose cutter)",
            ));
        }
        let length = number(find("L"))?.map(|l| l * scale).filter(|l| *l > 0.0);
        let cuts = number(find("LCUTS"))?
            .map(|l| l * scale)
            .filter(|l| *l > 0.0);
        let teeth = number(find("CUT"))?
            .filter(|n| *n >= 1.0 && *n <= 100.0)
            .map(|n| n as u32);
        let point =
            number(find("T-ANGLE").or(find("T_ANGLE")))?.filter(|a| *a > 0.0 && *a <= 180.0);
        let typ = find("TYP")
            .map(|c| field(c).0.to_ascii_uppercase())
            .unwrap_or_default();
        let name = find("NAME").map(|c| field(c).0).unwrap_or_default();
        let doc = find("DOC").map(|c| field(c).0).unwrap_or_default();
        let d = 2.0 * r;
        let drilling = ["DRILL", "NC_DRILL", "CENTER", "CSINK", "REAM", "TAP"]
            .iter()
            .any(|k| typ.starts_with(k));
        let (kind, nums): (CutterKind, Vec<f64>) = match (drilling, point) {
            (true, Some(a)) => (CutterKind::Drill, vec![d, a]),
            (true, None) if typ.starts_with("CSINK") || typ.starts_with("CENTER") => {
                (CutterKind::Drill, vec![d, 90.0])
            }
            (true, None) if typ.starts_with("DRILL") || typ.starts_with("NC_DRILL") => {
                (CutterKind::Drill, vec![d, 118.0])
            }
            _ if r2 >= r - 1e-9 => (CutterKind::Ball, vec![d]),
            _ if r2 > 0.0 => (CutterKind::Bull, vec![d, r2]),
            _ => (CutterKind::Flat, vec![d]),
        };
        let opts = CutterOptions {
            overall_length: length,
            flute_length: cuts.or(length.map(|l| l.min(3.0 * d))),
            flutes: teeth,
            ..CutterOptions::default()
        };
        // Lengths that do not fit the cutter (L stored relative to a master tool, LCUTS longer
        // than L): the cutter without them, and a warning.
        let cutter = match Cutter::named(kind, &nums, &opts) {
            Ok(c) => c,
            Err(first) => {
                let plain = CutterOptions {
                    flutes: teeth,
                    ..CutterOptions::default()
                };
                let c = Cutter::named(kind, &nums, &plain)
                    .map_err(|e| err(line, t_column, e.to_string(), "a valid tool"))?;
                table.warnings.push(format!(
                    "{file}:{line}: tool {t}: its lengths are left out ({first})"
                ));
                c
            }
        };
        let description = match (name.is_empty(), doc.is_empty()) {
            (false, false) => format!("{name} {doc}"),
            (false, true) => name.clone(),
            _ => doc,
        };
        table.tools.insert(
            t,
            ToolEntry {
                cutter,
                description,
                name: (!name.is_empty()).then_some(name),
                offsets: None,
                pocket: None,
            },
        );
    }
    if empty > 0 {
        table.warnings.push(format!(
            "{file}: {empty} row(s) with no radius (the null tool, empty places) define no cutter"
        ));
    }
    Ok(table)
}

/// How a table's lines split into columns.
#[derive(Debug)]
enum Layout {
    /// Fixed-width columns starting at these characters of the line — with its tabs expanded
    /// to stops every 8 characters when the header has tabs (a table saved by an editor that
    /// turned runs of spaces into tabs keeps its columns). A row's field is what stands between
    /// its column's start and the next column's, so a `DOC` with spaces is one field.
    Fixed {
        /// Where each column starts.
        starts: Vec<usize>,
        /// Whether tabs expand (the header has some).
        expand: bool,
    },
    /// One tab between fields (a table exported tab-separated: the header's names each between
    /// single tabs). A row with fewer fields has the others empty; with more, the extra ones
    /// belong to its last field (a tab in a description).
    Tabs,
}

impl Layout {
    fn of(header: &str) -> Layout {
        // Decided by the header alone: a row's tab (in a description) must not change how
        // the others are read.
        if header.contains('\t') && header.split('\t').all(|f| !f.trim().is_empty()) {
            return Layout::Tabs;
        }
        // Each column starts where a name starts; the first at the line's start, however the
        // header is indented.
        let (chars, _) = expand_tabs(header);
        let mut starts: Vec<usize> = (0..chars.len())
            .filter(|&i| !chars[i].is_whitespace() && (i == 0 || chars[i - 1].is_whitespace()))
            .collect();
        if let Some(first) = starts.first_mut() {
            *first = 0;
        }
        Layout::Fixed {
            starts,
            expand: header.contains('\t'),
        }
    }

    /// The line's fields, trimmed, each with the (1-based) character column of the line where
    /// its column starts.
    fn cells(&self, line: &str, columns: usize) -> Vec<(String, usize)> {
        match self {
            Layout::Tabs => {
                let mut at = 1;
                let mut cells: Vec<(String, usize)> = Vec::new();
                for (i, f) in line.split('\t').enumerate() {
                    if i < columns.max(1) {
                        cells.push((f.trim().to_string(), at));
                    } else if let Some(last) = cells.last_mut() {
                        // More fields than columns: a tab inside the last one (a description).
                        last.0 = format!("{}\t{}", last.0, f.trim()).trim().to_string();
                    }
                    at += f.chars().count() + 1;
                }
                cells
            }
            Layout::Fixed { starts, expand } => {
                // A tab counts to the next stop of 8 where the header was written with tabs;
                // in a table aligned with spaces, a tab (in a description) is one character.
                let (chars, origin) = if *expand {
                    expand_tabs(line)
                } else {
                    let chars: Vec<char> = line.chars().collect();
                    let origin = (0..chars.len()).collect();
                    (chars, origin)
                };
                let column = |i: usize| origin.get(i).map_or(chars.len() + 1, |o| o + 1);
                starts
                    .iter()
                    .enumerate()
                    .map(|(c, &start)| {
                        let end = starts
                            .get(c + 1)
                            .map_or(chars.len(), |&n| n.min(chars.len()));
                        let text: String = chars
                            .get(start.min(chars.len())..end)
                            .map_or(String::new(), |s| s.iter().collect());
                        (text.trim().to_string(), column(start))
                    })
                    .collect()
            }
        }
    }
}

/// The line's characters with each tab expanded to the next stop of 8, and for each of them the
/// index of the character of the line it comes from.
fn expand_tabs(line: &str) -> (Vec<char>, Vec<usize>) {
    let (mut chars, mut origin) = (Vec::new(), Vec::new());
    for (i, c) in line.chars().enumerate() {
        if c == '\t' {
            loop {
                chars.push(' ');
                origin.push(i);
                if chars.len() % 8 == 0 {
                    break;
                }
            }
        } else {
            chars.push(c);
            origin.push(i);
        }
    }
    (chars, origin)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cutter::CutterKind;

    const TABLE: &str = "BEGIN TOOL    .T     MM\n\
T    NAME                L           R           R2          DL      DR      LCUTS   CUT  TYP       T-ANGLE  DOC\n\
0    NULLWERKZEUG        +0          +0          +0          +0      +0      +0      0    MILL      +0\n\
1    MILL_D10            +75         +5          +0          +0      +0      +22     4    MILL      +0       end mill d10\n\
2    BALL_D6             +60         +3          +3          +0      +0      +12     2    BALL      +0\n\
3    TORUS_D12           +80         +6          +1          +0      +0      +30     3    TORUS     +0       bull nose, r1\n\
4    DRILL_D8            +90         +4          +0          +0      +0      +40     2    DRILL     +118\n\
[END]\n";

    #[test]
    fn reads_shapes_lengths_and_names_from_the_columns() {
        let t = parse_heidenhain(TABLE, "TOOL.T").unwrap();
        assert_eq!(t.tools.len(), 4);
        let kind = |n: u32| t.tools[&n].cutter.kind();
        assert_eq!(
            [kind(1), kind(2), kind(3), kind(4)],
            [
                CutterKind::Flat,
                CutterKind::Ball,
                CutterKind::Bull,
                CutterKind::Drill
            ]
        );
        let p = t.tools[&3].cutter.apt_params();
        assert!((p.d - 12.0).abs() < 1e-12 && (p.r - 1.0).abs() < 1e-12);
        assert_eq!(t.tools[&1].description, "MILL_D10 end mill d10");
        assert_eq!(t.tools[&3].description, "TORUS_D12 bull nose, r1");
        assert_eq!(t.tools[&2].name.as_deref(), Some("BALL_D6"));
        assert_eq!(t.warnings.len(), 1);
        // Inch: lengths × 25.4.
        let inch = TABLE.replace("MM\n", "INCH\n");
        let t = parse_heidenhain(&inch, "TOOL.T").unwrap();
        assert!((t.tools[&1].cutter.apt_params().d - 254.0).abs() < 1e-9);
    }

    #[test]
    fn wear_offsets_are_applied_and_a_corner_larger_than_the_radius_is_refused() {
        // DR −0.5 on a 6 mm flat end mill: the control cuts with R 2.5; DR2 on a bull-nose
        // corner likewise. (They were ignored, silently.)
        let worn = "BEGIN TOOL .T MM\n\
T    NAME   L      R      R2     DL     DR     DR2    TYP\n\
1    WORN   +60    +3     +0     +0     -0.5   +0     MILL\n\
2    TORUS  +60    +6     +1     +0     +0     +0.25  MILL\n\
[END]\n";
        let t = parse_heidenhain(worn, "TOOL.T").unwrap();
        assert!((t.tools[&1].cutter.apt_params().d - 5.0).abs() < 1e-12);
        let p = t.tools[&2].cutter.apt_params();
        assert!(
            (p.d - 12.0).abs() < 1e-12 && (p.r - 1.25).abs() < 1e-12,
            "{p:?}"
        );
        assert_eq!(t.warnings.len(), 2, "{:?}", t.warnings);
        assert!(t.warnings[0].contains("DR -0.5 mm"), "{:?}", t.warnings);
        // R2 > R is no cutter (it was read as a ball end mill, the README saying flat).
        let bad = "BEGIN TOOL .T MM\n\
T    NAME   L      R      R2     TYP\n\
2    WEIRD  +60    +3     +5     MILL\n\
[END]\n";
        let e = parse_heidenhain(bad, "TOOL.T").unwrap_err().to_string();
        assert!(e.starts_with("TOOL.T:3:") && e.contains("R2 5 mm"), "{e}");
    }

    #[test]
    fn review_cases() {
        // INCH with a version after it; an indented header; an indexed tool; T_ANGLE; L
        // shorter than the cutter (relative to a master tool) left out with a warning.
        let t = parse_heidenhain(
            "BEGIN TOOL .T INCH V2\n   T NAME   L      R      R2     TYP    T_ANGLE\n\
             1000 BIG    +3     +0.2   +0     MILL   +0\n\
             1.1  IDX    +3     +0.2   +0     MILL   +0\n\
             4    DRILL  +0.01  +0.2   +0     DRILL  +140\n[END]\n",
            "TOOL.T",
        )
        .unwrap();
        assert_eq!(t.tools.keys().copied().collect::<Vec<_>>(), [4, 1000]);
        assert!((t.tools[&1000].cutter.apt_params().d - 0.4 * 25.4).abs() < 1e-9);
        assert_eq!(t.tools[&4].cutter.kind(), CutterKind::Drill);
        assert!((t.tools[&4].cutter.apt_params().alpha_deg - 20.0).abs() < 1e-9);
        assert_eq!(t.warnings.len(), 2, "{:?}", t.warnings);
    }

    #[test]
    fn tables_with_tabs_keep_their_columns() {
        // An editor's tabs for runs of spaces (stops of 8): the table reads as with spaces.
        let tabbed = "BEGIN TOOL .T MM\nT\tNAME\t\tL\tR\tR2\tDOC\n\
                      2\tBALL_D6\t\t+60\t+3\t+3\tball six\n\
                      3\tTORUS\t\t+80\t+6\t+1\n[END]\n";
        let t = parse_heidenhain(tabbed, "TOOL.T").unwrap();
        assert_eq!(t.tools[&2].cutter.kind(), CutterKind::Ball);
        assert_eq!(t.tools[&2].description, "BALL_D6 ball six");
        let p = t.tools[&3].cutter.apt_params();
        assert!(
            (p.d - 12.0).abs() < 1e-12 && (p.r - 1.0).abs() < 1e-12,
            "{p:?}"
        );
        // One tab between fields, a name longer than a tab stop: read by tabs.
        let delimited = "BEGIN TOOL .T MM\nT\tNAME\tL\tR\tR2\n\
                         7\tBALL_D10_EXTRA_LONG\t+150\t+5\t+5\n\
                         8\tX\t+50\t+2\t+0.5\n[END]\n";
        let t = parse_heidenhain(delimited, "TOOL.T").unwrap();
        assert_eq!(t.tools[&7].cutter.kind(), CutterKind::Ball);
        assert!((t.tools[&7].cutter.apt_params().d - 10.0).abs() < 1e-12);
        assert_eq!(t.tools[&7].name.as_deref(), Some("BALL_D10_EXTRA_LONG"));
        assert_eq!(t.tools[&8].cutter.kind(), CutterKind::Bull);
        // A row without its last (empty) field, a description with a tab in it: the others as
        // the header says.
        let ragged = "BEGIN TOOL .T MM\nT\tNAME\tL\tR\tDOC\n\
                      7\tB\t+150\t+5\n8\tX\t+50\t+2\ttwo\tparts\n[END]\n";
        let t = parse_heidenhain(ragged, "TOOL.T").unwrap();
        assert_eq!(t.tools[&7].description, "B");
        assert_eq!(t.tools[&8].description, "X two\tparts");
        // A table aligned with spaces whose description holds a tab: the tab is one character,
        // the columns after it stay where the header puts them (a TNC writes DOC before TYP).
        let spaced = "BEGIN TOOL .T MM\n\
                      T    NAME      L      R      DOC          TYP       T-ANGLE\n\
                      3    DR6       +60    +3     twist\tdril   DRILL     +118\n[END]\n";
        let t = parse_heidenhain(spaced, "TOOL.T").unwrap();
        assert_eq!(t.tools[&3].cutter.kind(), CutterKind::Drill);
        // Errors name the field's column in the line as written (after the tabs).
        let e = parse_heidenhain(&delimited.replace("+2\t", "+Q\t"), "t.T")
            .unwrap_err()
            .to_string();
        assert!(e.contains("t.T:4:9") && e.contains("column R"), "{e}");
        let e = parse_heidenhain(&tabbed.replace("+6\t", "+Q\t"), "t.T")
            .unwrap_err()
            .to_string();
        assert!(e.contains("t.T:4:14") && e.contains("column R"), "{e}");
    }

    #[test]
    fn bad_tables_are_errors_at_their_place() {
        let e = parse_heidenhain("G0 X1\n", "t.T").unwrap_err().to_string();
        assert!(e.contains("t.T:1:"), "{e}");
        let bad = TABLE.replace("+75         +5 ", "+75         +X ");
        let e = parse_heidenhain(&bad, "t.T").unwrap_err().to_string();
        assert!(e.contains("t.T:4:38") && e.contains("column R"), "{e}");
        let twice = TABLE.replace("2    BALL", "1    BALL");
        assert!(parse_heidenhain(&twice, "t.T").is_err());
        assert!(parse_heidenhain("", "t.T").is_err());
    }
}
