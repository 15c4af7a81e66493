//! CAMotics project files (`.camotics`, JSON): tools and workpiece bounds.
//!
//! Each tool has `units` (`imperial` = inches, `metric` = mm), `shape`, `length` (cutting
//! length), `diameter` and, for `snubnose`, `snub_diameter`. Shapes, in any letter case
//! (`"Ballnose"`, `"CYLINDRICAL"`), map to APT cutters:
//!
//! * `cylindrical` → flat end mill of `diameter`, h = `length`;
//! * `ballnose` → ball end mill of `diameter`, h = `length`;
//! * `snubnose` → tapered flat: flat bottom of `snub_diameter`, widening linearly to
//!   `diameter` at `length` (β = atan((diameter − snub_diameter) / (2·length)));
//! * `conical` → V-bit whose cone reaches `diameter` at `length` (tip angle
//!   2·atan(diameter / (2·length)));
//! * `spheroid` (an ellipsoid `diameter` wide and `length` long) is no APT cutter: the tool is
//!   in [`ToolTable::left_out`], and only a program that uses it is refused.
//!
//! The workpiece `bounds`, always mm (CAMotics keeps them in mm whatever the project's display
//! `units`), become [`ToolTable::workpiece`] unless
//! `"automatic": true`, which means CAMotics computes them from the tool path: its `margin`
//! (per cent, default 5) becomes [`ToolTable::automatic_workpiece`], and the job makes the box
//! as CAMotics does (`swarf_job::automatic_workpiece`).
//!
//! The project's `files` (the programs CAMotics runs one after the other) are not run: swarf
//! simulates the one program given to it, and says so in [`ToolTable::warnings`].

use super::{line_col, ToolEntry, ToolTable};
use crate::cutter::{Cutter, CutterKind, CutterOptions};
use crate::error::TableError;
use std::collections::BTreeMap;
use swarf_geom::math::Vec3;
use swarf_geom::Aabb;

/// CAMotics' workpiece margin when a project states none, per cent.
const DEFAULT_MARGIN_PERCENT: f64 = 5.0;
/// The largest margin read: ten times the tool path's size on each side is already far more
/// stock than any set-up holds (a margin of 1e308 % made a box beyond the machine's range).
const MAX_MARGIN_PERCENT: f64 = 1000.0;

#[derive(serde::Deserialize)]
struct Project {
    #[serde(default)]
    units: Option<Units>,
    #[serde(default)]
    tools: BTreeMap<String, Tool>,
    #[serde(default)]
    workpiece: Option<Workpiece>,
    #[serde(default)]
    files: Vec<String>,
}

#[derive(serde::Deserialize, Clone, Copy, PartialEq)]
#[serde(rename_all = "lowercase")]
enum Units {
    Imperial,
    Metric,
}

impl Units {
    fn to_mm(self) -> f64 {
        match self {
            Units::Imperial => 25.4,
            Units::Metric => 1.0,
        }
    }
}

#[derive(Clone, Copy)]
enum Shape {
    Cylindrical,
    Ballnose,
    Snubnose,
    Conical,
    Spheroid,
}

// CAMotics reads its shapes in any letter case (its own files have held `"BALLNOSE"` and
// `"ballnose"`); so does swarf.
impl<'de> serde::Deserialize<'de> for Shape {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        const SHAPES: &[&str] = &["cylindrical", "ballnose", "snubnose", "conical", "spheroid"];
        let name = <std::borrow::Cow<'de, str>>::deserialize(d)?;
        match name.to_ascii_lowercase().as_str() {
            "cylindrical" => Ok(Shape::Cylindrical),
            "ballnose" => Ok(Shape::Ballnose),
            "snubnose" => Ok(Shape::Snubnose),
            "conical" => Ok(Shape::Conical),
            "spheroid" => Ok(Shape::Spheroid),
            _ => Err(serde::de::Error::unknown_variant(&name, SHAPES)),
        }
    }
}

#[derive(serde::Deserialize)]
struct Tool {
    #[serde(default)]
    units: Option<Units>,
    shape: Shape,
    length: f64,
    diameter: f64,
    #[serde(default)]
    snub_diameter: Option<f64>,
    #[serde(default)]
    description: String,
}

#[derive(serde::Deserialize)]
struct Workpiece {
    #[serde(default)]
    automatic: bool,
    #[serde(default)]
    margin: Option<f64>,
    #[serde(default)]
    bounds: Option<Bounds>,
}

#[derive(serde::Deserialize)]
struct Bounds {
    min: [f64; 3],
    max: [f64; 3],
}

/// Parses a CAMotics project; `file` names the source in errors.
pub fn parse_camotics(text: &str, file: &str) -> Result<ToolTable, TableError> {
    let project: Project = serde_json::from_str(text).map_err(|e| TableError::Parse {
        file: file.to_string(),
        line: e.line(),
        column: e.column(),
        found: e.to_string(),
        expected: "a CAMotics project (JSON with tools and workpiece)".into(),
    })?;
    // serde_json::Value keeps no positions; point semantic errors at the tool's key instead.
    let locate = |key: &str| -> (usize, usize) {
        let tools_at = text.find("\"tools\"").unwrap_or(0);
        let needle = format!("\"{key}\"");
        match text[tools_at..].find(&needle) {
            Some(i) => line_col(text, tools_at + i),
            None => (0, 0),
        }
    };
    let project_unit = project.units.unwrap_or(Units::Metric);
    let mut table = ToolTable::default();
    for (key, tool) in &project.tools {
        let (line, column) = locate(key);
        let err = |found: String, expected: &str| TableError::Parse {
            file: file.to_string(),
            line,
            column,
            found,
            expected: expected.to_string(),
        };
        let number: u32 = key
            .parse()
            .map_err(|_| err(format!("tool key {key:?}"), "a whole tool number"))?;
        let unit = tool.units.unwrap_or(project_unit).to_mm();
        let (d, len) = (tool.diameter * unit, tool.length * unit);
        let opts = CutterOptions {
            flute_length: Some(len),
            ..CutterOptions::default()
        };
        let built = match tool.shape {
            Shape::Spheroid => {
                // A tool the project defines but swarf cannot model: left out, with why, so
                // the rest of the project loads and only a program that calls it is refused.
                table.left_out.insert(
                    number,
                    format!(
                        "{file}:{line}:{column}: tool {key} is a spheroid (an ellipsoid {d} mm \
                         wide, {len} mm long), a shape swarf cannot model"
                    ),
                );
                continue;
            }
            Shape::Cylindrical => Cutter::named(CutterKind::Flat, &[d], &opts),
            Shape::Ballnose => Cutter::named(CutterKind::Ball, &[d], &opts),
            Shape::Snubnose => {
                let Some(snub) = tool.snub_diameter else {
                    return Err(err(
                        format!("snubnose tool {key} without snub_diameter"),
                        "a snub_diameter for a snubnose tool",
                    ));
                };
                let snub = snub * unit;
                let taper = ((d - snub) / (2.0 * len)).atan().to_degrees();
                Cutter::named(CutterKind::TaperFlat, &[snub, taper], &opts)
            }
            Shape::Conical => {
                let tip = 2.0 * (d / (2.0 * len)).atan().to_degrees();
                Cutter::named(CutterKind::Chamfer, &[d, tip], &opts)
            }
        };
        let cutter = built.map_err(|e| err(format!("tool {key}: {e}"), "a valid tool"))?;
        table.tools.insert(
            number,
            ToolEntry {
                cutter,
                description: tool.description.clone(),
                name: None,
                offsets: None,
                pocket: None,
            },
        );
    }
    // An error at the first `"key"` of the file.
    let at_key = |key: &str, found: String, expected: &str| {
        let (line, column) = text
            .find(&format!("\"{key}\""))
            .map_or((0, 0), |i| line_col(text, i));
        TableError::Parse {
            file: file.to_string(),
            line,
            column,
            found,
            expected: expected.into(),
        }
    };
    if let Some(w) = &project.workpiece {
        if w.automatic {
            let margin = w.margin.unwrap_or(DEFAULT_MARGIN_PERCENT);
            if !(0.0..=MAX_MARGIN_PERCENT).contains(&margin) {
                return Err(at_key(
                    "margin",
                    format!("margin {margin}"),
                    "a workpiece margin from 0 to 1000 (per cent of its size)",
                ));
            }
            table.automatic_workpiece = Some(margin);
        } else {
            match &w.bounds {
                Some(b) => {
                    // mm whatever the project's `units`: those are CAMotics' display units,
                    // and it stores the workpiece in mm (an imperial project's half-inch-deep
                    // block is `-12.7`).
                    let min = Vec3::from_array(b.min);
                    let max = Vec3::from_array(b.max);
                    if !(min.is_finite() && max.is_finite() && min.cmple(max).all()) {
                        return Err(at_key(
                            "bounds",
                            format!("bounds min {min} max {max}"),
                            "finite workpiece bounds with min ≤ max",
                        ));
                    }
                    table.workpiece = Some(Aabb { min, max });
                }
                None => table.warnings.push(format!(
                    "{file}: workpiece is not automatic but has no bounds; none used"
                )),
            }
        }
    }
    if !project.files.is_empty() {
        table.warnings.push(format!(
            "{file}: the project runs {} in turn; swarf simulates only the program given to it \
             (--program)",
            project.files.join(", ")
        ));
    }
    Ok(table)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shapes_and_units() {
        let text = r#"{"units":"metric","tools":{
            "1":{"units":"metric","shape":"snubnose","length":10,"diameter":6,"snub_diameter":2},
            "2":{"units":"imperial","shape":"conical","length":0.5,"diameter":1}},
            "workpiece":{"automatic":true}}"#;
        let t = parse_camotics(text, "p.camotics").unwrap();
        let snub = &t.tools[&1].cutter;
        assert!((snub.profile_radius(0.0).unwrap() - 1.0).abs() < 1e-12);
        assert!((snub.profile_radius(10.0).unwrap() - 3.0).abs() < 1e-12);
        let v = &t.tools[&2].cutter;
        // Cone reaching Ø25.4 at 12.7 mm: a 90° V.
        assert!((v.profile_radius(6.35).unwrap() - 6.35).abs() < 1e-9);
        assert!(t.workpiece.is_none());
        // Automatic: CAMotics' default margin, or the project's; a negative one refused.
        assert_eq!(t.automatic_workpiece, Some(5.0));
        let with = |w: &str| parse_camotics(&format!("{{\"workpiece\":{w}}}"), "p.camotics");
        let t = with(r#"{"automatic":true,"margin":12.5}"#).unwrap();
        assert_eq!(t.automatic_workpiece, Some(12.5));
        let t =
            with(r#"{"automatic":false,"margin":12.5,"bounds":{"min":[0,0,-1],"max":[1,1,0]}}"#)
                .unwrap();
        assert_eq!((t.automatic_workpiece, t.workpiece.is_some()), (None, true));
        assert!(with(r#"{"automatic":true,"margin":-1}"#).is_err());
        assert!(with(r#"{"automatic":true,"margin":1e308}"#).is_err());
    }

    #[test]
    fn errors_have_positions() {
        let e = parse_camotics(
            "{\"tools\":{\"1\":{\"shape\":\"square\",\"length\":1,\"diameter\":1}}}",
            "p.camotics",
        )
        .unwrap_err();
        assert!(
            matches!(e, TableError::Parse { line: 1, column, .. } if column > 20),
            "{e}"
        );
        let e = parse_camotics(
            "{\"tools\":{\n\"7\":{\"shape\":\"ballnose\",\"length\":1,\"diameter\":-1}}}",
            "p.camotics",
        )
        .unwrap_err();
        assert!(
            matches!(
                e,
                TableError::Parse {
                    line: 2,
                    column: 1,
                    ..
                }
            ),
            "{e}"
        );
        assert!(e.to_string().contains("d (diameter)"), "{e}");
        assert!(parse_camotics("", "p").is_err());
        assert!(parse_camotics("[1,2]", "p").is_err());
    }
}
