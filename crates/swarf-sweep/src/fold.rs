//! Self-intersecting sweeps: where the envelope folds into the swept volume.
//!
//! A grazing point `x` of the tool at instant `s₀` lies on the tool's surface with `N·V = 0`,
//! so the signed distance `d(s)` from the fixed point `x` to the tool at instant `s` has
//! `d(s₀) = 0` and `d'(s₀) = −N·V = 0`. If `d''(s₀) > 0` the tool stays locally on one side of
//! `x` and `x` is on the boundary of the swept volume; if `d''(s₀) < 0` the tool contains `x`
//! just before and after `s₀`: the envelope sheet has passed through the edge of regression
//! (where `d'' = 0`, the Jacobian of the envelope map `(s, q) ↦ x` changes sign) and folded into
//! the sweep — the swallowtail of a tight 5-axis turn, or the inner side of an arc tighter than
//! the tool. For a translating convex tool `d'' = II(V, V) ≥ 0` (the second fundamental form),
//! so fixed-axis lines never fold and are not tested.
//!
//! Only curved pieces are tested. A flat face has no normal curvature, so `d''` there is the
//! motion term alone: its grazing chord sheet lies inside the sweep whenever the face leans into
//! its own path (the top of a tool that tilts forward while feeding forward), which every such
//! 5-axis move does without any fold; the boundary there is swept by the face's rim and the
//! curved pieces next to it, which are tested.
//!
//! The test samples [`FOLD_SAMPLES`] instants per move and [`FOLD_PARALLELS`] parallels per
//! piece, and takes `d''` by a central second difference of the exact distance to the piece's
//! surface with step [`FOLD_FD_STEP`], against the scale `|V|²/L` of the curvature term
//! ([`FOLD_REL_TOL`]). The envelope mesh itself is the union of exact fixed-axis sweeps and is
//! right either way; the report says where the analytic envelope surface is not the boundary.

use serde::Serialize;
use swarf_geom::math::Vec3;
use swarf_path::{Move, MoveKind, Program};
use swarf_tool::{AnyPiece, Cutter};

use crate::grazing::grazing_points;
use crate::kinematics::MotionState;
use crate::tolerance::{FOLD_FD_STEP, FOLD_PARALLELS, FOLD_REL_TOL, FOLD_SAMPLES};

/// Relative step (of the tool's reach) outward along the normal with which a grazing point is
/// probed for lying on an internal face of the tool.
const INTERNAL_PROBE: f64 = 1e-7;

/// One move whose envelope folds into its own sweep.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SelfIntersection {
    /// Index of the move.
    pub move_index: usize,
    /// Its source file.
    pub file: String,
    /// Its source line.
    pub line: u32,
    /// Parameter of the worst sample.
    pub s: f64,
    /// Shape of the piece where it is worst.
    pub piece: &'static str,
    /// `d''·L/|V|²` at the worst grazing point (negative: folded).
    pub fold_ratio: f64,
    /// What it means.
    pub message: String,
}

/// Every piece of the whole tool: cutting part, shank, holder.
pub fn whole_tool_pieces(cutter: &Cutter) -> Vec<AnyPiece> {
    let mut v = cutter.pieces().to_vec();
    v.extend_from_slice(cutter.shank_solid().pieces());
    if let Some(h) = cutter.holder_solid() {
        v.extend_from_slice(h.pieces());
    }
    v
}

/// Signed distance from the world point `x` to the (extended) surface of `piece` placed at
/// `tip` with axis `axis`: positive outside.
pub fn piece_distance(piece: &AnyPiece, tip: Vec3, axis: Vec3, x: Vec3) -> f64 {
    let y = x - tip;
    let z = y.dot(axis);
    let rho = (y - axis * z).length();
    match piece {
        AnyPiece::Disc(d) => {
            if d.facing_up {
                z - d.z
            } else {
                d.z - z
            }
        }
        AnyPiece::Cone(c) => {
            let t = (c.top - c.bottom).normalize();
            let n = swarf_geom::math::Vec2::new(t.y, -t.x);
            (swarf_geom::math::Vec2::new(rho, z) - c.bottom).dot(n)
        }
        AnyPiece::Cylinder(c) => rho - c.radius,
        AnyPiece::Torus(t) => (rho - t.major).hypot(z - t.center_z) - t.minor,
        AnyPiece::Sphere(s) => rho.hypot(z - s.center_z) - s.radius,
    }
}

/// `d''·L/|V|²` at the grazing points of move `m` at `s`: `(ratio, piece index)` per smooth
/// grazing point of `pieces` (the whole tool of `cutter`) that is not on an internal face.
pub fn fold_ratios(
    program: &Program,
    m: &Move,
    s: f64,
    cutter: &Cutter,
    pieces: &[AnyPiece],
    reach: f64,
) -> Vec<(f64, usize)> {
    let state = MotionState::of_move(program, m, s);
    let h = FOLD_FD_STEP;
    let (pa, pb) = (program.pose_at(m, s - h), program.pose_at(m, s + h));
    let set = grazing_points(pieces, &state, FOLD_PARALLELS);
    let speed = state.v_tip.length() + state.omega.length() * reach;
    let frame = state.tool_frame();
    // Faces shared by two solids of the tool (the cutting part's top cap under the shank) are
    // inside the tool: a point just outside them along their normal is still in the tool.
    let internal = |p: Vec3, n: Vec3| {
        let y = frame.to_local(p + n * (INTERNAL_PROBE * reach));
        cutter.contains(y)
            || cutter.shank_solid().contains(y)
            || cutter.holder_solid().is_some_and(|h| h.contains(y))
    };
    set.points
        .iter()
        .filter(|g| {
            !g.edge && !matches!(pieces[g.piece], AnyPiece::Disc(_)) && !internal(g.point, g.normal)
        })
        .filter_map(|g| {
            let v2 = state.velocity_at(g.point).length_squared();
            if v2 <= (1e-6 * speed).powi(2) {
                return None; // a point at rest (on the instantaneous axis): nothing sweeps
            }
            let p = &pieces[g.piece];
            let d0 = piece_distance(p, state.tip, state.axis, g.point);
            let da = piece_distance(p, pa.tip, pa.axis.normalize(), g.point);
            let db = piece_distance(p, pb.tip, pb.axis.normalize(), g.point);
            let d2 = (da + db - 2.0 * d0) / (h * h);
            Some((d2 * reach / v2, g.piece))
        })
        .collect()
}

/// The fold test of move `index` (arcs and moves whose axis turns; `None` for the others and
/// for moves whose envelope does not fold).
pub fn fold_check(program: &Program, index: usize, cutter: &Cutter) -> Option<SelfIntersection> {
    let m = &program.moves[index];
    if !(matches!(m.kind, MoveKind::Arc(_)) || program.is_five_axis(m)) {
        return None;
    }
    let pieces = whole_tool_pieces(cutter);
    let reach = cutter
        .overall_length()
        .hypot(0.5 * cutter.max_diameter())
        .max(1e-9);
    let mut worst: Option<(f64, f64, usize)> = None;
    for i in 0..FOLD_SAMPLES {
        let s = (i as f64 + 0.5) / FOLD_SAMPLES as f64;
        for (r, piece) in fold_ratios(program, m, s, cutter, &pieces, reach) {
            if worst.map_or(true, |(w, _, _)| r < w) {
                worst = Some((r, s, piece));
            }
        }
    }
    let (ratio, s, piece) = worst?;
    if ratio >= -FOLD_REL_TOL {
        return None;
    }
    let file = program
        .files
        .get(m.file as usize)
        .cloned()
        .unwrap_or_default();
    let shape = pieces[piece].shape_name();
    Some(SelfIntersection {
        move_index: index,
        file: file.clone(),
        line: m.line,
        s,
        piece: shape,
        fold_ratio: ratio,
        message: format!(
            "{file}:{}: move {index}: the envelope folds into its own sweep (s = {s:.3}, {shape} piece): \
             grazing points lie inside the swept volume, the turn is tighter than the tool; \
             the mesh is the exact union of fixed-axis pieces, but the analytic envelope surface self-intersects here",
            m.line
        ),
    })
}
