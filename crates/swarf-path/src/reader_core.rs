//! What the Heidenhain and Sinumerik readers share besides the part frame
//! ([`crate::part_frame`]) and the formulas ([`crate::formula`]): the tool's place on its
//! contour (position, working plane, the direction the last element ended in) and the events
//! of a line, an arc, a tangent arc and a feed change; the arc end tolerance; the search for a
//! called program file.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use crate::gcode::GcodeOptions;
use crate::part_frame::PartFrame;
use crate::{Axes, Canon, FeedMode, PathError, PathErrorKind, Plane, SourcePos, Units};

/// Moves a reader's own position `pos` by what the sink's position changed from `before` to
/// `after` around an event that re-expresses where the tool stands (tool centre point control
/// on or off, [`crate::CanonSink::position`]): the axes a later block leaves out then start
/// where the machine is, and the reader's own offsets (a tool length) stay in its position.
pub(crate) fn follow_sink(pos: &mut [f64; 6], before: Option<Axes>, after: Option<Axes>) {
    if let (Some(a), Some(b)) = (before, after) {
        for ((p, a), b) in pos.iter_mut().zip(a.to_array()).zip(b.to_array()) {
            *p += b - a;
        }
    }
}

/// The tool's place on the contour it follows.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Contour {
    /// Position in the program frame: X Y Z mm, A B C degrees.
    pub(crate) pos: [f64; 6],
    pub(crate) plane: Plane,
    /// The direction the last element in the working plane ended in (plane axes), for
    /// tangent arcs.
    pub(crate) tangent: Option<[f64; 2]>,
    /// The feed last told to the sink.
    told_feed: Option<(FeedMode, f64)>,
}

impl Contour {
    pub(crate) fn new(pos: [f64; 6]) -> Self {
        Contour {
            pos,
            plane: Plane::XY,
            tangent: None,
            told_feed: None,
        }
    }

    /// A straight move to `end` (rapid or fed).
    pub(crate) fn line(&mut self, end: [f64; 6], rapid: bool) -> Canon<'static> {
        let (i1, i2, _) = self.plane.axes();
        let d = [end[i1] - self.pos[i1], end[i2] - self.pos[i2]];
        let len = d[0].hypot(d[1]);
        if len > 0.0 {
            self.tangent = Some([d[0] / len, d[1] / len]);
        }
        self.pos = end;
        let end = Axes::from_array(end);
        if rapid {
            Canon::Traverse { end }
        } else {
            Canon::Feed { end }
        }
    }

    /// An arc in the working plane about `center` (plane axes) to `end`, `turns` ≥ 1.
    pub(crate) fn arc(
        &mut self,
        end: [f64; 6],
        center: [f64; 2],
        ccw: bool,
        turns: i32,
    ) -> Canon<'static> {
        let (i1, i2, _) = self.plane.axes();
        let r = [end[i1] - center[0], end[i2] - center[1]];
        let len = r[0].hypot(r[1]);
        if len > 0.0 {
            let s = if ccw { 1.0 } else { -1.0 };
            self.tangent = Some([-s * r[1] / len, s * r[0] / len]);
        }
        self.pos = end;
        Canon::Arc {
            end: Axes::from_array(end),
            center,
            rotation: if ccw { turns } else { -turns },
            plane: self.plane,
        }
    }

    /// The arc from here to `end` tangent to the contour: its centre and direction, `Some(None)`
    /// when `end` lies straight ahead (a line), `None` when no element gives a tangent. The
    /// centre lies on the normal to the tangent, as far from both ends.
    pub(crate) fn tangent_arc(&self, end: [f64; 6]) -> Option<Option<([f64; 2], bool)>> {
        let t = self.tangent?;
        let (i1, i2, _) = self.plane.axes();
        let d = [end[i1] - self.pos[i1], end[i2] - self.pos[i2]];
        let nrm = [-t[1], t[0]];
        let dn = d[0] * nrm[0] + d[1] * nrm[1];
        if dn.abs() < 1e-9 * (d[0].hypot(d[1]) + 1.0) {
            return Some(None);
        }
        let rho = (d[0] * d[0] + d[1] * d[1]) / (2.0 * dn);
        Some(Some((
            [self.pos[i1] + rho * nrm[0], self.pos[i2] + rho * nrm[1]],
            rho > 0.0,
        )))
    }

    /// The events that tell the sink a feed of `f` in `mode` before a feed move: none when it
    /// has them already.
    pub(crate) fn feed(&mut self, mode: FeedMode, f: f64) -> impl Iterator<Item = Canon<'static>> {
        let told = self.told_feed;
        self.told_feed = Some((mode, f));
        let changed = told != Some((mode, f));
        let new_mode = changed && told.map(|t| t.0) != Some(mode);
        new_mode
            .then_some(Canon::FeedMode(mode))
            .into_iter()
            .chain(changed.then_some(Canon::FeedRate(f)))
    }
}

/// The events a reader starts with: the units, the frame, where the tool stands (when not at
/// the origin) and the XY plane.
pub(crate) fn opening(scale: f64, frame: &PartFrame, pos: [f64; 6]) -> Vec<Canon<'static>> {
    let units = if scale == 1.0 { Units::Mm } else { Units::Inch };
    let mut out = vec![Canon::Units(units)];
    out.extend(frame.events());
    if pos != [0.0; 6] {
        out.push(Canon::SetPosition(Axes::from_array(pos)));
    }
    out.push(Canon::Plane(Plane::XY));
    out
}

/// The move limit's error for a program read from `file`.
pub(crate) fn limit_error(file: &str, max: u64) -> PathError {
    let (message, expected) = crate::limit::move_limit_message(max);
    PathError::new(
        SourcePos {
            file: file.to_string(),
            line: 0,
            column: 0,
        },
        PathErrorKind::Limit,
        message,
        "",
        expected,
    )
}

/// The number of the tool a program calls by `name`: the tool library's (its case ignored),
/// else the number `given` it at its first call — above every number the library uses, so
/// that it stays undefined rather than taking a listed tool's cutter — and, on that first
/// call, the warning to give.
pub(crate) fn tool_by_name(
    opts: &GcodeOptions,
    given: &mut HashMap<String, u32>,
    name: &str,
) -> (u32, Option<String>) {
    if let Some(&n) = opts.tool_names.get(&name.to_ascii_uppercase()) {
        return (n, None);
    }
    if let Some(&n) = given.get(name) {
        return (n, None);
    }
    let top = opts
        .tool_names
        .values()
        .copied()
        .chain(opts.tool_diameters.keys().copied())
        .max()
        .unwrap_or(0);
    let n = top.saturating_add(1).saturating_add(given.len() as u32);
    given.insert(name.to_string(), n);
    let warning = format!(
        "tool \"{name}\" is tool {n} for the tool library (--tools; a Heidenhain TOOL.T finds \
         it by name)"
    );
    (n, Some(warning))
}

/// How far an arc's end may be off its circle of radius `r` in a program of `scale` mm per
/// unit: the G-code reader's tolerance.
pub(crate) fn arc_tolerance(opts: &GcodeOptions, scale: f64, r: f64) -> f64 {
    let tol = opts.arc_radius_tolerance;
    let abs = if scale == 1.0 {
        tol.abs_mm
    } else {
        tol.abs_inch * 25.4
    };
    abs.max(tol.relative * r)
}

/// The first of the file names `wanted` beside the program `file` or on the subroutine path,
/// their case ignored (the controls' file names are).
pub(crate) fn find_program(file: &str, opts: &GcodeOptions, wanted: &[String]) -> Option<PathBuf> {
    let base = Path::new(file)
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_default();
    let mut dirs = vec![if base.as_os_str().is_empty() {
        PathBuf::from(".")
    } else {
        base
    }];
    dirs.extend(opts.subroutine_path.iter().cloned());
    dirs.iter().find_map(|d| {
        let entries: Vec<PathBuf> = std::fs::read_dir(d)
            .ok()?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .collect();
        wanted.iter().find_map(|w| {
            entries
                .iter()
                .find(|p| {
                    p.is_file()
                        && p.file_name()
                            .and_then(|n| n.to_str())
                            .is_some_and(|n| n.eq_ignore_ascii_case(w))
                })
                .cloned()
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tangent_arcs_continue_the_contour() {
        let mut c = Contour::new([0.0; 6]);
        let _ = c.line([10.0, 0.0, 0.0, 0.0, 0.0, 0.0], false);
        // Along +X to (10, 0); a tangent arc to (20, 10) turns left about (10, 10).
        let (centre, ccw) = c
            .tangent_arc([20.0, 10.0, 0.0, 0.0, 0.0, 0.0])
            .unwrap()
            .unwrap();
        assert!((centre[0] - 10.0).abs() < 1e-12 && (centre[1] - 10.0).abs() < 1e-12 && ccw);
        assert_eq!(c.tangent_arc([30.0, 0.0, 0.0, 0.0, 0.0, 0.0]), Some(None));
        let _ = c.arc([20.0, 10.0, 0.0, 0.0, 0.0, 0.0], [10.0, 10.0], true, 1);
        assert_eq!(c.tangent, Some([0.0, 1.0]));
        assert_eq!(c.feed(FeedMode::PerMinute, 100.0).count(), 2);
        assert_eq!(c.feed(FeedMode::PerMinute, 100.0).count(), 0);
        assert_eq!(c.feed(FeedMode::PerMinute, 50.0).count(), 1);
    }
}
