//! The check's outputs with stable field names: `violations.csv`, `points.csv` and the JSON
//! summary of `swarf gouge`.

use std::io::{self, Write};

use serde::Serialize;

use super::{GougeOptions, GougeReport, SurfaceRef, ViolationKind};
use swarf_surface::{Caveats, CompoundSurface};

/// The JSON summary (field names are a contract).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct GougeSummary {
    /// Program points checked (the start and every move's end).
    pub points: usize,
    /// Moves checked.
    pub moves: usize,
    /// Fixed-axis sub-moves they were checked as (all tool parts).
    pub sub_moves: usize,
    /// Violations (stretches of moves).
    pub violations: usize,
    /// Moves with a gouge.
    pub gouging_moves: usize,
    /// Moves with an interference.
    pub interfering_moves: usize,
    /// Points that gouge.
    pub gouging_points: usize,
    /// Points that interfere.
    pub interfering_points: usize,
    /// Deepest gouge, mm (0 when none).
    pub max_gouge_mm: f64,
    /// Deepest interference, mm (0 when none).
    pub max_interference_mm: f64,
    /// Every search finished within its budget, every face of the surface file was read
    /// (`skipped_faces` is 0) within its trim (`untrimmed_faces` is 0) and every assembly
    /// placement in it applied (`unapplied_placements` is 0): the clear stretches are proven
    /// clear and every violation is on the part.
    pub certified: bool,
    /// Searches whose budget ran out.
    pub unresolved_searches: usize,
    /// What the surface's reader could not carry over (`skipped_faces`, `untrimmed_faces`,
    /// `unapplied_placements`, each with its notes: [`Caveats`]); any makes `certified` false
    /// (a face not read is not checked; one read without its trim may give violations outside
    /// the face; a part not placed may be misplaced).
    #[serde(flatten)]
    pub caveats: Caveats,
    /// Search nodes expanded in all.
    pub nodes: u64,
    /// The reporting tolerance, mm.
    pub tolerance_mm: f64,
    /// The certificate gap on depths, mm (or [`GougeSummary::accuracy_relative`] times the
    /// depth, if larger).
    pub accuracy_mm: f64,
    /// The certificate gap on depths relative to the depth (0.001: 0.1 %).
    pub accuracy_relative: f64,
    /// Bound on the distance between true and checked motion, mm.
    pub motion_tolerance_mm: f64,
    /// Wall-clock time, s.
    pub elapsed_s: f64,
}

impl GougeReport {
    /// The summary of this report on `surface` (whose reader's notes list the faces it
    /// skipped and the placements it could not apply; `elapsed_s` as given).
    pub fn summary(
        &self,
        surface: &CompoundSurface,
        opts: &GougeOptions,
        moves: usize,
        elapsed_s: f64,
    ) -> GougeSummary {
        let caveats = surface.caveats();
        GougeSummary {
            points: self.points.len(),
            moves,
            sub_moves: self.sub_moves,
            violations: self.violations.len(),
            gouging_moves: self.moves_with(ViolationKind::Gouge),
            interfering_moves: self.moves_with(ViolationKind::Interference),
            gouging_points: self.points_with(ViolationKind::Gouge),
            interfering_points: self.points_with(ViolationKind::Interference),
            max_gouge_mm: self.max_depth(ViolationKind::Gouge),
            max_interference_mm: self.max_depth(ViolationKind::Interference),
            certified: self.unresolved == 0 && caveats.is_empty(),
            caveats,
            unresolved_searches: self.unresolved,
            nodes: self.nodes,
            tolerance_mm: opts.tolerance,
            accuracy_mm: opts.accuracy,
            accuracy_relative: opts.relative_accuracy,
            motion_tolerance_mm: opts.motion_tolerance,
            elapsed_s,
        }
    }

    /// `violations.csv`: one row per violation, header
    /// `move,file,line,kind,part,rapid,s_start,s_end,depth_mm,depth_upper_mm,s_deepest,tip_x,tip_y,tip_z,axis_i,axis_j,axis_k,point_x,point_y,point_z,surface`.
    /// `surface` is the patch's name (its index when unnamed) or `check:<triangle>`; `files`
    /// names the program's source files by index.
    ///
    /// # Errors
    /// When `out` fails.
    pub fn write_violations_csv(
        &self,
        surface: &CompoundSurface,
        files: &[String],
        out: &mut impl Write,
    ) -> io::Result<()> {
        writeln!(
            out,
            "move,file,line,kind,part,rapid,s_start,s_end,depth_mm,depth_upper_mm,s_deepest,\
             tip_x,tip_y,tip_z,axis_i,axis_j,axis_k,point_x,point_y,point_z,surface"
        )?;
        for v in &self.violations {
            writeln!(
                out,
                "{},{},{},{},{},{},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.9},{:.9},{:.9},{:.6},{:.6},{:.6},{}",
                v.move_index,
                csv_field(file_name(files, v.file)),
                v.line,
                v.kind.as_str(),
                v.part.as_str(),
                v.rapid,
                v.s_start,
                v.s_end,
                v.depth,
                v.depth_upper,
                v.s_deepest,
                v.tip.x,
                v.tip.y,
                v.tip.z,
                v.axis.x,
                v.axis.y,
                v.axis.z,
                v.point.x,
                v.point.y,
                v.point.z,
                csv_field(&surface_label(surface, v.surface)),
            )?;
        }
        Ok(())
    }

    /// `points.csv`: one row per program point, header
    /// `point,move,file,line,x,y,z,i,j,k,depth_mm,depth_upper_mm,status,part,surface`.
    /// `move` is empty for the program's start; `depth_mm` is the deepest point found (empty
    /// when nothing was near; at a clear point the search stops once it proves the depth under
    /// the tolerance, so this is a surface point met on the way, not the clearance);
    /// `depth_upper_mm` bounds the depth of any point (at most the tolerance when clear);
    /// `status` is `clear`, `gouge` or `interference`.
    ///
    /// # Errors
    /// When `out` fails.
    pub fn write_points_csv(
        &self,
        surface: &CompoundSurface,
        files: &[String],
        out: &mut impl Write,
    ) -> io::Result<()> {
        writeln!(
            out,
            "point,move,file,line,x,y,z,i,j,k,depth_mm,depth_upper_mm,status,part,surface"
        )?;
        for (k, p) in self.points.iter().enumerate() {
            let depth = if p.depth.is_finite() {
                format!("{:.6}", p.depth)
            } else {
                String::new()
            };
            writeln!(
                out,
                "{},{},{},{},{:.6},{:.6},{:.6},{:.9},{:.9},{:.9},{},{:.6},{},{},{}",
                k,
                p.move_index.map_or(String::new(), |m| m.to_string()),
                csv_field(file_name(files, p.file)),
                p.line,
                p.tip.x,
                p.tip.y,
                p.tip.z,
                p.axis.x,
                p.axis.y,
                p.axis.z,
                depth,
                p.depth_upper,
                p.status.map_or("clear", ViolationKind::as_str),
                p.part.as_str(),
                p.surface
                    .map_or(String::new(), |s| csv_field(&surface_label(surface, s))),
            )?;
        }
        Ok(())
    }
}

fn file_name(files: &[String], index: u16) -> &str {
    files.get(usize::from(index)).map_or("", String::as_str)
}

/// The patch's label or `check:<triangle>`.
pub fn surface_label(surface: &CompoundSurface, s: SurfaceRef) -> String {
    match s {
        SurfaceRef::Patch(i) => surface.patch_label(i),
        SurfaceRef::Check(t) => format!("check:{t}"),
    }
}

/// A CSV field, quoted when it holds a comma, quote or line break.
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}
