//! swarf's own tool library, TOML, lengths in mm.
//!
//! ```toml
//! [[tool]]
//! number = 3
//! spec = "bull:d=16,r=2"          # any spec string (see `swarf_tool::spec`)
//! description = "16 mm bull nose"
//!
//! [[tool]]
//! number = 4
//! apt = [10, 2, 3, 2, 0, 0, 30]   # or the seven APT numbers (d, r, e, f, α°, β°, h)
//! flutes = 4                      # optional, beside what the spec leaves out
//! helix_deg = 35
//! rake_deg = 12                   # optional, normal rake (force coefficient prediction)
//! flute_length_mm = 25
//! shank_diameter_mm = 10
//! overall_length_mm = 75
//! holder = { base_z_mm = 50, segments = [
//!     { length_mm = 20, bottom_diameter_mm = 25, top_diameter_mm = 40 } ] }
//! ```
//!
//! Exactly one of `spec` and `apt` per tool; numbers are unique; unknown keys are errors; a key
//! that the spec string gives too must agree with it (`spec = "flat:d=10,flutes=4"` with
//! `flutes = 2` is an error: one of the two is a mistake, and forces and feeds depend on it).

use super::{line_col, ToolEntry, ToolTable};
use crate::cutter::{Cutter, CutterKind, CutterOptions};
use crate::error::TableError;
use crate::holder::Holder;
use toml::Spanned;

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct LibraryFile {
    #[serde(default)]
    tool: Vec<Spanned<ToolRow>>,
}

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct ToolRow {
    number: Spanned<i64>,
    spec: Option<Spanned<String>>,
    apt: Option<Spanned<Vec<f64>>>,
    #[serde(default)]
    description: String,
    flutes: Option<u32>,
    helix_deg: Option<f64>,
    rake_deg: Option<f64>,
    flute_length_mm: Option<f64>,
    shank_diameter_mm: Option<f64>,
    overall_length_mm: Option<f64>,
    holder: Option<Holder>,
}

/// Parses swarf's TOML tool library; `file` names the source in errors.
pub fn parse_toml_library(text: &str, file: &str) -> Result<ToolTable, TableError> {
    let err_at = |byte: usize, found: String, expected: String| {
        let (line, column) = line_col(text, byte);
        TableError::Parse {
            file: file.to_string(),
            line,
            column,
            found,
            expected,
        }
    };
    let lib: LibraryFile = toml::from_str(text).map_err(|e| {
        let at = e.span().map_or(0, |s| s.start);
        err_at(
            at,
            e.message().trim().to_string(),
            "a swarf tool library ([[tool]] tables with number and spec or apt)".into(),
        )
    })?;
    let mut table = ToolTable::default();
    for row in lib.tool {
        let row_start = row.span().start;
        let row = row.into_inner();
        let n = *row.number.get_ref();
        if !(0..=u32::MAX as i64).contains(&n) {
            return Err(err_at(
                row.number.span().start,
                format!("tool number {n}"),
                "a tool number from 0 to 4294967295".into(),
            ));
        }
        let number = n as u32;
        if table.tools.contains_key(&number) {
            return Err(err_at(
                row.number.span().start,
                format!("tool number {number} a second time"),
                "unique tool numbers".into(),
            ));
        }
        let mut in_spec = CutterOptions::default();
        let (cutter, at) = match (&row.spec, &row.apt) {
            (Some(spec), None) => {
                let (c, given) = crate::spec::parse_given(spec.get_ref()).map_err(|e| {
                    // Point at the column inside the quoted spec when the error has one.
                    let col = match &e {
                        crate::error::SpecError::Syntax { column, .. } => *column,
                        _ => 0,
                    };
                    err_at(
                        spec.span().start + 1 + col.saturating_sub(1),
                        e.to_string(),
                        "a valid tool spec".into(),
                    )
                })?;
                in_spec = given;
                (c, spec.span().start)
            }
            (None, Some(apt)) => {
                let c = Cutter::named(CutterKind::Apt, apt.get_ref(), &CutterOptions::default())
                    .map_err(|e| {
                        err_at(
                            apt.span().start,
                            e.to_string(),
                            "seven consistent APT numbers [d, r, e, f, α, β, h]".into(),
                        )
                    })?;
                (c, apt.span().start)
            }
            (Some(_), Some(_)) => {
                return Err(err_at(
                    row_start,
                    "both spec and apt".into(),
                    "exactly one of spec and apt".into(),
                ))
            }
            (None, None) => {
                return Err(err_at(
                    row_start,
                    "neither spec nor apt".into(),
                    "exactly one of spec and apt".into(),
                ))
            }
        };
        // A key given twice, in the spec and beside it, must agree.
        let twice = [
            (
                "flutes",
                "flutes",
                row.flutes.map(f64::from),
                in_spec.flutes.map(f64::from),
            ),
            ("helix_deg", "helix", row.helix_deg, in_spec.helix_deg),
            ("rake_deg", "rake", row.rake_deg, in_spec.rake_deg),
            (
                "flute_length_mm",
                "flute-length",
                row.flute_length_mm,
                in_spec.flute_length,
            ),
            (
                "shank_diameter_mm",
                "shank",
                row.shank_diameter_mm,
                in_spec.shank_diameter,
            ),
            (
                "overall_length_mm",
                "length",
                row.overall_length_mm,
                in_spec.overall_length,
            ),
        ];
        for (key, spec_key, beside, inside) in twice {
            if let (Some(a), Some(b)) = (beside, inside) {
                if (a - b).abs() > 1e-9 * a.abs().max(b.abs()) {
                    return Err(err_at(
                        at,
                        format!("{key} = {a} beside the spec's {spec_key}={b}"),
                        format!("one value: give {key} in the spec or beside it, not both"),
                    ));
                }
            }
        }
        let opts = CutterOptions {
            flutes: row.flutes.or(cutter.flutes_given()),
            helix_deg: Some(row.helix_deg.unwrap_or(cutter.helix_deg())),
            rake_deg: row.rake_deg.or(cutter.rake_deg()),
            flute_length: Some(row.flute_length_mm.unwrap_or(cutter.flute_length())),
            shank_diameter: Some(row.shank_diameter_mm.unwrap_or(cutter.shank_diameter())),
            overall_length: Some(row.overall_length_mm.unwrap_or(cutter.overall_length())),
            holder: row.holder,
        };
        let cutter = cutter
            .with_options(&opts)
            .map_err(|e| err_at(at, e.to_string(), "tool options that fit the cutter".into()))?;
        table.tools.insert(
            number,
            ToolEntry {
                cutter,
                description: row.description,
                name: None,
                offsets: None,
                pocket: None,
            },
        );
    }
    Ok(table)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn library_with_spec_apt_and_holder() {
        let text = r#"
[[tool]]
number = 3
spec = "bull:d=16,r=2"
description = "16 mm bull"

[[tool]]
number = 4
apt = [10, 2, 3, 2, 0, 0, 30]
flutes = 4
holder = { base_z_mm = 50, segments = [ { length_mm = 20, bottom_diameter_mm = 25, top_diameter_mm = 40 } ] }
"#;
        let t = parse_toml_library(text, "lib.toml").unwrap();
        assert_eq!(t.tools.len(), 2);
        assert_eq!(t.tools[&3].description, "16 mm bull");
        assert!((t.tools[&3].cutter.profile_radius(2.0).unwrap() - 8.0).abs() < 1e-12);
        assert_eq!(t.tools[&4].cutter.flutes(), 4);
        assert!(t.tools[&4]
            .cutter
            .holder_solid()
            .unwrap()
            .contains(swarf_geom::math::Vec3::new(0.0, 15.0, 69.0)));
    }

    #[test]
    fn errors_carry_line_and_column() {
        let e = parse_toml_library("[[tool]]\nnumber = 1\nspec = \"bull:d=16,q=2\"\n", "x.toml")
            .unwrap_err();
        match e {
            TableError::Parse {
                file,
                line,
                column,
                found,
                ..
            } => {
                assert_eq!((file.as_str(), line), ("x.toml", 3));
                // The spec starts at column 8 (the quote); "q=2" is at column 11 of the spec.
                assert_eq!(column, 8 + 11, "{found}");
                assert!(found.contains("unknown key \"q\""), "{found}");
            }
            other => panic!("{other:?}"),
        }
        let e = parse_toml_library("[[tool]]\nnumber = 1\nspek = \"flat:d=1\"\n", "x.toml")
            .unwrap_err();
        assert!(matches!(e, TableError::Parse { line: 3, .. }), "{e}");
        let e = parse_toml_library("[[tool]]\nnumber = 1\nspec = \"flat:d=1\"\n[[tool]]\nnumber = 1\nspec = \"flat:d=2\"\n", "x.toml").unwrap_err();
        assert!(
            matches!(
                e,
                TableError::Parse {
                    line: 5,
                    column: 10,
                    ..
                }
            ),
            "{e}"
        );
        let e = parse_toml_library(
            "[[tool]]\nnumber = 1\napt = [10, 2, 3, 2, 0, 0]\n",
            "x.toml",
        )
        .unwrap_err();
        assert!(e.to_string().contains("exactly 7"), "{e}");
    }

    /// A key the spec gives and the row gives again must agree (the row's silently won: a
    /// 4-flute spec with `flutes = 2` took the forces of 2 flutes); the same value twice, or a
    /// key the spec leaves out, is fine.
    #[test]
    fn a_key_in_the_spec_and_beside_it_must_agree() {
        let lib = |spec: &str, extra: &str| {
            parse_toml_library(
                &format!("[[tool]]\nnumber = 1\nspec = \"{spec}\"\n{extra}\n"),
                "lib.toml",
            )
        };
        for (spec, extra, key) in [
            ("flat:d=10,flutes=4,helix=0", "flutes = 2", "flutes = 2"),
            ("flat:d=10,helix=30", "helix_deg = 0", "helix_deg = 0"),
            ("flat:d=10,rake=12", "rake_deg = 5", "rake_deg = 5"),
            (
                "flat:d=10,length=60",
                "overall_length_mm = 70",
                "overall_length_mm = 70",
            ),
        ] {
            let e = lib(spec, extra).unwrap_err();
            assert!(matches!(e, TableError::Parse { line: 3, .. }), "{e}");
            assert!(
                e.to_string().contains(key) && e.to_string().contains("spec's"),
                "{e}"
            );
        }
        let t = lib("flat:d=10,flutes=4", "flutes = 4\nhelix_deg = 45").unwrap();
        assert_eq!(t.tools[&1].cutter.flutes(), 4);
        assert_eq!(t.tools[&1].cutter.helix_deg(), 45.0);
    }
}
