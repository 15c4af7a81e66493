//! Tool spec strings: `flat:d=12`, `bull:d=16,r=2,flutes=4`, `apt:10,2,3,2,0,0,30`.
//!
//! Grammar: `KIND ":" ITEM ("," ITEM)*`. For `apt` the first seven items are the APT numbers
//! `d, r, e, f, α, β, h` (degrees); every other item is `KEY=NUMBER`. Keys by kind:
//!
//! | kind         | required      | optional (default)                      |
//! |--------------|---------------|-----------------------------------------|
//! | `flat`       | `d`           |                                         |
//! | `ball`       | `d`           |                                         |
//! | `bull`       | `d`, `r`      |                                         |
//! | `taper-flat` | `d`, `taper`  |                                         |
//! | `taper-ball` | `d`, `taper`  |                                         |
//! | `chamfer`    | `d`           | `angle` (90, included tip angle)        |
//! | `drill`      | `d`           | `angle` (118, point angle)              |
//!
//! and for all kinds `flutes`, `helix` (deg), `rake` (normal rake, deg), `flute-length`, `shank` (diameter), `length`
//! (overall), all in mm. For the named kinds `flute-length` is also the height h of the modelled
//! cutting part (default 3·d); for `apt` h is the seventh number and `flute-length` defaults to
//! it. Errors carry the 1-based column of the offending text.

use crate::cutter::{Cutter, CutterKind, CutterOptions};
use crate::error::{SpecError, ToolError};

const COMMON_KEYS: [&str; 6] = ["flutes", "helix", "rake", "flute-length", "shank", "length"];

struct Item<'a> {
    text: &'a str,
    column: usize,
}

fn syntax(column: usize, found: impl Into<String>, expected: impl Into<String>) -> SpecError {
    SpecError::Syntax {
        column,
        found: found.into(),
        expected: expected.into(),
    }
}

fn describe_found(s: &str) -> String {
    if s.is_empty() {
        "nothing".to_string()
    } else {
        format!("{s:?}")
    }
}

fn parse_number(text: &str, column: usize, what: &str) -> Result<f64, SpecError> {
    match text.trim().parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(syntax(
            column,
            describe_found(text.trim()),
            format!("a finite number for {what}"),
        )),
    }
}

/// Required and optional (with default) numeric keys of each kind, besides the common ones.
fn kind_keys(kind: CutterKind) -> (&'static [&'static str], &'static [(&'static str, f64)]) {
    match kind {
        CutterKind::Flat | CutterKind::Ball => (&["d"], &[]),
        CutterKind::Bull => (&["d", "r"], &[]),
        CutterKind::TaperFlat | CutterKind::TaperBall => (&["d", "taper"], &[]),
        CutterKind::Chamfer => (&["d"], &[("angle", 90.0)]),
        CutterKind::Drill => (&["d"], &[("angle", 118.0)]),
        CutterKind::Apt => (&[], &[]),
    }
}

const KINDS: [CutterKind; 8] = [
    CutterKind::Flat,
    CutterKind::Ball,
    CutterKind::Bull,
    CutterKind::TaperFlat,
    CutterKind::TaperBall,
    CutterKind::Chamfer,
    CutterKind::Drill,
    CutterKind::Apt,
];

/// Parses a tool spec string into a validated cutter.
pub fn parse(spec: &str) -> Result<Cutter, SpecError> {
    parse_given(spec).map(|(c, _)| c)
}

/// [`parse`], and the options the string gives itself (`flutes=`, `helix=`, …; `None` where it
/// leaves the default), so that a library row's own keys can be checked against them.
pub fn parse_given(spec: &str) -> Result<(Cutter, CutterOptions), SpecError> {
    let col_of = |byte: usize| spec[..byte].chars().count() + 1;
    let Some(colon) = spec.find(':') else {
        return Err(syntax(
            col_of(spec.len()),
            format!("{} without ':'", describe_found(spec.trim())),
            "KIND:PARAMS, e.g. flat:d=12",
        ));
    };
    let kind_text = spec[..colon].trim();
    let kind = KINDS
        .iter()
        .copied()
        .find(|k| k.spec_name().eq_ignore_ascii_case(kind_text))
        .ok_or_else(|| {
            syntax(
                col_of(spec[..colon].len() - spec[..colon].trim_start().len()),
                describe_found(kind_text),
                "a tool kind: flat, ball, bull, taper-flat, taper-ball, chamfer, drill or apt",
            )
        })?;
    // Split the rest on commas, remembering where each item starts.
    let mut items = Vec::new();
    let mut start = colon + 1;
    for part in spec[colon + 1..].split(',') {
        let lead = part.len() - part.trim_start().len();
        items.push(Item {
            text: part.trim(),
            column: col_of(start + lead),
        });
        start += part.len() + 1;
    }
    let (required, optional) = kind_keys(kind);
    let mut nums: Vec<f64> = Vec::new();
    let mut idx = 0;
    if kind == CutterKind::Apt {
        const NAMES: [&str; 7] = ["d", "r", "e", "f", "alpha (deg)", "beta (deg)", "h"];
        for (i, name) in NAMES.iter().enumerate() {
            let Some(item) = items.get(i) else {
                return Err(syntax(
                    col_of(spec.len()),
                    "end of spec",
                    format!("APT number {} ({name})", i + 1),
                ));
            };
            if item.text.contains('=') {
                return Err(syntax(
                    item.column,
                    describe_found(item.text),
                    format!("APT number {} ({name}) before any key=value", i + 1),
                ));
            }
            nums.push(parse_number(
                item.text,
                item.column,
                &format!("APT number {} ({name})", i + 1),
            )?);
        }
        idx = 7;
    }
    let mut given: Vec<(&str, f64, usize)> = Vec::new();
    for item in &items[idx..] {
        let Some(eq) = item.text.find('=') else {
            return Err(syntax(item.column, describe_found(item.text), "KEY=VALUE"));
        };
        let key = item.text[..eq].trim();
        let allowed = required.contains(&key)
            || optional.iter().any(|(k, _)| *k == key)
            || COMMON_KEYS.contains(&key);
        if !allowed {
            let mut keys: Vec<&str> = required.to_vec();
            keys.extend(optional.iter().map(|(k, _)| *k));
            keys.extend(COMMON_KEYS);
            return Err(syntax(
                item.column,
                format!("unknown key {key:?}"),
                format!("one of {} for {}", keys.join(", "), kind.spec_name()),
            ));
        }
        if given.iter().any(|(k, _, _)| *k == key) {
            return Err(syntax(
                item.column,
                format!("{key:?} a second time"),
                "each key at most once",
            ));
        }
        let vcol = item.column + item.text[..=eq].chars().count();
        let v = parse_number(&item.text[eq + 1..], vcol, key)?;
        given.push((key, v, vcol));
    }
    let get = |k: &str| given.iter().find(|(g, _, _)| *g == k).map(|(_, v, _)| *v);
    for k in required {
        match get(k) {
            Some(v) => nums.push(v),
            None => {
                return Err(syntax(
                    col_of(spec.len()),
                    format!("no {k}="),
                    format!("{k}=NUMBER for {}", kind.spec_name()),
                ))
            }
        }
    }
    for (k, default) in optional {
        nums.push(get(k).unwrap_or(*default));
    }
    let flutes = match given.iter().find(|(k, _, _)| *k == "flutes") {
        Some(&(_, v, col)) => {
            if v.fract() != 0.0 || !(1.0..=1000.0).contains(&v) {
                return Err(syntax(
                    col,
                    format!("{v}"),
                    "a whole number of flutes from 1 to 1000",
                ));
            }
            Some(v as u32)
        }
        None => None,
    };
    let opts = CutterOptions {
        flutes,
        helix_deg: get("helix"),
        rake_deg: get("rake"),
        flute_length: get("flute-length"),
        shank_diameter: get("shank"),
        overall_length: get("length"),
        holder: None,
    };
    // A value out of range is told at its column, as a syntax error is.
    let cutter = Cutter::named(kind, &nums, &opts).map_err(|e| {
        let at = |param: &str| {
            let key = param.split_whitespace().next().unwrap_or("");
            given
                .iter()
                .find(|(k, _, _)| *k == key)
                .map(|&(_, v, col)| (v, col))
        };
        match &e {
            ToolError::OutOfRange {
                param, requirement, ..
            } => match at(param) {
                Some((v, col)) => syntax(col, format!("{v}"), format!("{param} {requirement}")),
                None => e.into(),
            },
            _ => e.into(),
        }
    })?;
    Ok((cutter, opts))
}

/// The spec string of a cutter; [`parse`] of it rebuilds the same cutter (holder excepted).
pub(crate) fn to_spec(c: &Cutter) -> String {
    let a = c.apt_params();
    let mut s = match c.kind() {
        CutterKind::Flat | CutterKind::Ball => format!("{}:d={}", c.kind().spec_name(), a.d),
        CutterKind::Bull => format!("bull:d={},r={}", a.d, a.r),
        CutterKind::TaperFlat => format!("taper-flat:d={},taper={}", a.d, a.beta_deg),
        CutterKind::TaperBall => format!("taper-ball:d={},taper={}", 2.0 * a.r, a.beta_deg),
        CutterKind::Chamfer | CutterKind::Drill => {
            format!(
                "{}:d={},angle={}",
                c.kind().spec_name(),
                a.d,
                180.0 - 2.0 * a.alpha_deg
            )
        }
        CutterKind::Apt => format!(
            "apt:{},{},{},{},{},{},{}",
            a.d, a.r, a.e, a.f, a.alpha_deg, a.beta_deg, a.h
        ),
    };
    if c.kind() != CutterKind::Apt {
        s.push_str(&format!(",flute-length={}", a.h));
    }
    s.push_str(&format!(
        ",flutes={},helix={},shank={},length={}",
        c.flutes(),
        c.helix_deg(),
        c.shank_diameter(),
        c.overall_length()
    ));
    if let Some(r) = c.rake_deg() {
        s.push_str(&format!(",rake={r}"));
    }
    if c.kind() == CutterKind::Apt && c.flute_length() != a.h {
        s.push_str(&format!(",flute-length={}", c.flute_length()));
    }
    s
}
