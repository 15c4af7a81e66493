//! Cutter families: a cutter shape with its one free size left open, as the allowable-size
//! planner searches it (`swarf toolsize --cutter`).
//!
//! Grammar: `NAME[:KEY=NUMBER(,KEY=NUMBER)*]` with
//!
//! | spec | family | free size |
//! |---|---|---|
//! | `ball` | ball end mill (the sphere only) | ball radius |
//! | `ball-side` | ball end mill with its flutes on the cylinder above the equator | ball radius |
//! | `flat` | flat end mill | radius |
//! | `bull:r=R` | bull-nose with corner radius R mm | distance of the corner centre from the axis |
//! | `taper-ball:taper=T` | tapered ball, side half-angle T° | ball radius |
//! | `apt:r=R,taper=T,cone=C` | the APT shape (corner radius, side taper, bottom cone angle) | distance of the corner centre from the axis |
//!
//! Errors name the 1-based column of the offending text ([`SpecError::Syntax`]); the ranges of
//! the numbers are the planner's to check.

use crate::error::SpecError;

/// A parsed cutter-family spec.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FamilySpec {
    /// `ball`.
    Ball,
    /// `ball-side`.
    BallWithSide,
    /// `flat`.
    Flat,
    /// `bull:r=R`.
    Bull {
        /// Corner radius, mm.
        corner_radius: f64,
    },
    /// `taper-ball:taper=T`.
    TaperBall {
        /// Side half-angle, degrees.
        taper_deg: f64,
    },
    /// `apt:r=R,taper=T,cone=C` (each defaults to 0).
    Apt {
        /// Corner radius, mm.
        corner_radius: f64,
        /// Side half-angle, degrees.
        taper_deg: f64,
        /// Bottom cone angle, degrees.
        cone_deg: f64,
    },
}

const EXPECTED: &str =
    "ball, ball-side, flat, bull:r=R, taper-ball:taper=T or apt:r=R,taper=T,cone=C";

fn syntax(column: usize, found: impl Into<String>, expected: impl Into<String>) -> SpecError {
    SpecError::Syntax {
        column,
        found: found.into(),
        expected: expected.into(),
    }
}

impl FamilySpec {
    /// Parses a family spec.
    ///
    /// ```
    /// use swarf_tool::FamilySpec;
    /// assert_eq!(FamilySpec::parse("bull:r=2").unwrap(), FamilySpec::Bull { corner_radius: 2.0 });
    /// assert!(FamilySpec::parse("bull").unwrap_err().to_string().contains("r="));
    /// ```
    ///
    /// # Errors
    /// Unknown names or keys, keys the family does not take, missing keys, bad numbers — with
    /// their column.
    pub fn parse(spec: &str) -> Result<Self, SpecError> {
        let (name, params) = spec.split_once(':').unwrap_or((spec, ""));
        let allowed: &[&str] = match name {
            "ball" | "ball-side" | "flat" => &[],
            "bull" => &["r"],
            "taper-ball" => &["taper"],
            "apt" => &["r", "taper", "cone"],
            _ => return Err(syntax(1, format!("`{name}`"), EXPECTED)),
        };
        let mut given: Vec<(&str, f64)> = Vec::new();
        let mut column = name.chars().count() + 2;
        for item in params.split(',') {
            let here = column;
            column += item.chars().count() + 1;
            if item.trim().is_empty() {
                if params.is_empty() {
                    continue;
                }
                return Err(syntax(here, "an empty item", "KEY=NUMBER"));
            }
            let Some((k, v)) = item.split_once('=') else {
                return Err(syntax(here, format!("`{item}`"), "KEY=NUMBER"));
            };
            let k = k.trim();
            if !allowed.contains(&k) {
                let want = if allowed.is_empty() {
                    format!("no parameters for {name}")
                } else {
                    format!("one of {} for {name}", allowed.join(", "))
                };
                return Err(syntax(here, format!("`{k}`"), want));
            }
            if given.iter().any(|(g, _)| *g == k) {
                return Err(syntax(
                    here,
                    format!("`{k}` a second time"),
                    "each key once",
                ));
            }
            let vcol = here + k.len() + 1;
            let v: f64 = v
                .trim()
                .parse()
                .ok()
                .filter(|x: &f64| x.is_finite())
                .ok_or_else(|| syntax(vcol, format!("`{}`", v.trim()), "a finite number"))?;
            given.push((k, v));
        }
        let get = |k: &str| given.iter().find(|(g, _)| *g == k).map(|(_, v)| *v);
        let need = |k: &str, what: &str| {
            get(k).ok_or_else(|| {
                syntax(
                    spec.chars().count() + 1,
                    "the end of the spec",
                    format!("{k}={what} for {name}"),
                )
            })
        };
        Ok(match name {
            "ball" => FamilySpec::Ball,
            "ball-side" => FamilySpec::BallWithSide,
            "flat" => FamilySpec::Flat,
            "bull" => FamilySpec::Bull {
                corner_radius: need("r", "R (corner radius, mm)")?,
            },
            "taper-ball" => FamilySpec::TaperBall {
                taper_deg: need("taper", "T (side half-angle, degrees)")?,
            },
            _ => FamilySpec::Apt {
                corner_radius: get("r").unwrap_or(0.0),
                taper_deg: get("taper").unwrap_or(0.0),
                cone_deg: get("cone").unwrap_or(0.0),
            },
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn families_and_their_errors() {
        assert_eq!(FamilySpec::parse("ball").unwrap(), FamilySpec::Ball);
        assert_eq!(
            FamilySpec::parse("ball-side").unwrap(),
            FamilySpec::BallWithSide
        );
        assert_eq!(
            FamilySpec::parse("taper-ball:taper=3").unwrap(),
            FamilySpec::TaperBall { taper_deg: 3.0 }
        );
        assert_eq!(
            FamilySpec::parse("apt:cone=10").unwrap(),
            FamilySpec::Apt {
                corner_radius: 0.0,
                taper_deg: 0.0,
                cone_deg: 10.0
            }
        );
        let col = |s: &str| match FamilySpec::parse(s).unwrap_err() {
            SpecError::Syntax { column, .. } => column,
            e => panic!("{e}"),
        };
        assert_eq!(col("drill"), 1);
        assert_eq!(col("ball:r=1"), 6);
        assert_eq!(col("bull:r=x"), 8);
        assert_eq!(col("bull"), 5);
        assert_eq!(col("apt:r=1,r=2"), 9);
        assert_eq!(col("bull:r"), 6);
    }
}
