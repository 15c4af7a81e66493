//! The workpiece a CAMotics project with `"automatic": true` stands for, made as CAMotics makes
//! it (`Project::updateAutomaticWorkpiece`): the box of every cutting move's tool — the tip's
//! path grown by the tool's radius sideways and by its length upwards — with its top put at
//! Z = 0, 2 mm deeper than its lowest cut where it is less than 2 mm thick, then grown by the margin (per cent of its size) on every
//! side but the top.

use std::collections::BTreeMap;

use swarf_geom::math::Vec3;
use swarf_geom::Aabb;
use swarf_path::summary::move_tip_bounds;
use swarf_path::{MoveKind, Program};
use swarf_tool::ToolSet;

/// CAMotics' least workpiece thickness, mm.
const MIN_THICKNESS_MM: f64 = 2.0;

/// The automatic workpiece of `program` cut with `tools`, grown by `margin_percent`; `None`
/// when no feed move has a defined tool, or the lowest cut lies 2 mm or more above Z = 0 (no
/// box is left under Z = 0).
pub fn automatic_workpiece(
    program: &Program,
    tools: &ToolSet,
    margin_percent: f64,
) -> Option<Aabb> {
    let mut by_tool: BTreeMap<u32, (Vec3, Vec3)> = BTreeMap::new();
    for m in &program.moves {
        if matches!(m.kind, MoveKind::Rapid) {
            continue;
        }
        let (lo, hi) = move_tip_bounds(program, m);
        let b = by_tool.entry(m.tool).or_insert((lo, hi));
        *b = (b.0.min(lo), b.1.max(hi));
    }
    automatic_workpiece_of(&by_tool, tools, margin_percent)
}

/// [`automatic_workpiece`] from the box of the tool tip's path over each tool's feed moves,
/// (min, max) by tool number (what `swarf_path::summary::SummarySink` gathers as a program
/// streams by).
pub fn automatic_workpiece_of(
    tip_bounds_by_tool: &BTreeMap<u32, (Vec3, Vec3)>,
    tools: &ToolSet,
    margin_percent: f64,
) -> Option<Aabb> {
    let (mut min, mut max) = (Vec3::splat(f64::INFINITY), Vec3::splat(f64::NEG_INFINITY));
    for (&tool, &(lo, hi)) in tip_bounds_by_tool {
        let Some(cutter) = tools.get(tool) else {
            continue;
        };
        let r = 0.5 * cutter.max_diameter();
        min = min.min(lo - Vec3::new(r, r, 0.0));
        max = max.max(hi + Vec3::new(r, r, cutter.flute_length()));
    }
    if min.x > max.x {
        // (No feed move with a tool: the box is still empty.)
        return None;
    }
    max.z = 0.0;
    if max.z - min.z < MIN_THICKNESS_MM {
        // (CAMotics adds a point 2 mm under the lowest cut: a 1 mm deep path gets 3 mm.)
        min.z -= MIN_THICKNESS_MM;
    }
    if min.z >= max.z {
        return None;
    }
    let margin = (max - min) * (margin_percent / 100.0);
    Some(Aabb {
        min: min - margin,
        max: max + Vec3::new(margin.x, margin.y, 0.0),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{JobOptions, JobSetup};

    fn job(src: &str) -> crate::Job {
        let setup = JobSetup::load(&JobOptions {
            tool: Some("flat:d=6".into()),
            ..JobOptions::default()
        })
        .unwrap();
        setup.read_str(src, "a.ngc").unwrap()
    }

    /// A 1 mm deep cut along X, then a clockwise half circle over (15, 5): tip box X 0–20,
    /// Y 0–5, Z −1 (the plunge's top is cut off at Z0); the 3 mm radius around it; 2 mm more
    /// under the cut (less than 2 mm thick); then 10 % of (26, 11, 3) on every side but the top.
    #[test]
    fn the_box_is_camotics_rule_worked_by_hand() {
        let j =
            job("G21 G90\nT1 M6\nG0 X0 Y0 Z5\nG1 Z-1 F100\nG1 X10\nG2 X20 Y0 I5 J0\nG0 Z50 X90\n");
        let b = automatic_workpiece(&j.program, &j.tools, 10.0).unwrap();
        let want_min = Vec3::new(-3.0 - 2.6, -3.0 - 1.1, -3.0 - 0.3);
        let want_max = Vec3::new(23.0 + 2.6, 8.0 + 1.1, 0.0);
        assert!((b.min - want_min).abs().max_element() < 1e-9, "{b:?}");
        assert!((b.max - want_max).abs().max_element() < 1e-9, "{b:?}");
        // Deeper than 2 mm: no extra depth; no margin.
        let j = job("G21 G90\nT1 M6\nG0 X0 Y0 Z5\nG1 Z-4 F100\nG1 X10\n");
        let b = automatic_workpiece(&j.program, &j.tools, 0.0).unwrap();
        assert!(
            (b.min - Vec3::new(-3.0, -3.0, -4.0)).abs().max_element() < 1e-9,
            "{b:?}"
        );
        assert!(
            (b.max - Vec3::new(13.0, 3.0, 0.0)).abs().max_element() < 1e-9,
            "{b:?}"
        );
        // Rapids alone, or cuts 2 mm above the top: nothing to make it from.
        let j = job("G21 G90\nT1 M6\nG0 X0 Y0 Z-5\nG0 X10\n");
        assert!(automatic_workpiece(&j.program, &j.tools, 5.0).is_none());
        let j = job("G21 G90\nT1 M6\nG0 X0 Y0 Z5\nG1 X10 F100\n");
        assert!(automatic_workpiece(&j.program, &j.tools, 5.0).is_none());
    }
}
