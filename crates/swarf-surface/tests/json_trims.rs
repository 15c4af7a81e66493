//! swarf JSON trims: `"trim": {"outer": ..., "holes": ...}` read into `Patch::trim`, written
//! back (flipped patches included), and refused with the patch named when malformed.

mod common;

use common::*;
use swarf_geom::math::Vec3;
use swarf_surface::io::json;
use swarf_surface::{CompoundSurface, Coverage, ParametricSurface, Patch, Surface, Trim};

/// The 10 mm floor of the format's example with `trim` (JSON text) added.
fn floor(trim: &str) -> String {
    format!(
        r#"{{"units": "mm", "patches": [{{"name": "floor", "degree_u": 1, "degree_v": 1,
  "knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1],
  "control_points": [[[0, 0, 0, 1], [0, 10, 0, 1]], [[10, 0, 0, 1], [10, 10, 0, 1]]],
  "trim": {trim}}}]}}"#
    )
}

/// `contains` on a 41 × 41 grid over `[−0.1, 1.1]²` that keeps off the loops' edges.
fn answers(t: &Trim) -> Vec<bool> {
    let mut out = Vec::new();
    for i in 0..41 {
        for j in 0..41 {
            let (u, v) = (
                -0.1 + 1.2 * (i as f64 + 0.37) / 41.0,
                -0.1 + 1.2 * (j as f64 + 0.61) / 41.0,
            );
            out.push(t.contains(u, v));
        }
    }
    out
}

#[test]
fn trims_read_as_documented() {
    // A triangle with a square hole; the closing repeat is optional.
    let s = json::parse(&floor(
        r#"{"outer": [[0, 0], [1, 0], [0, 1], [0, 0]], "holes": [[[0.1, 0.1], [0.3, 0.1], [0.3, 0.3], [0.1, 0.3]]]}"#,
    ))
    .unwrap();
    let t = s.patches[0].trim.as_ref().unwrap();
    assert_eq!(t.loops().len(), 2);
    assert!(t.contains(0.05, 0.5) && !t.contains(0.6, 0.6) && !t.contains(0.2, 0.2));
    assert_eq!(t.coverage([0.5, 0.55, 0.1, 0.15]), Coverage::Inside);
    // Holes only: the outer boundary is the parameter box.
    let s = json::parse(&floor(
        r#"{"holes": [[[0.4, 0.4], [0.6, 0.4], [0.5, 0.6]]]}"#,
    ))
    .unwrap();
    let t = s.patches[0].trim.as_ref().unwrap();
    assert!(t.outer().is_none() && t.holes().len() == 1);
    assert!(t.contains(0.99, 0.99) && !t.contains(0.5, 0.45) && !t.contains(1.01, 0.5));
    // Parameters are not lengths: an inch file scales the points, not the trim.
    let inch =
        floor(r#"{"outer": [[0, 0], [0.5, 0], [0.5, 1], [0, 1]]}"#).replace("\"mm\"", "\"in\"");
    let s = json::parse(&inch).unwrap();
    let t = s.patches[0].trim.as_ref().unwrap();
    assert!(t.contains(0.25, 0.5) && !t.contains(0.75, 0.5));
    // (The parameter box is cut down to the outer boundary's: `[0, 0.5] × [0, 1]`.)
    assert_eq!(s.patches[0].surface.point(0.5, 1.0).x, 127.0);
    // No trim: none.
    let s = json::parse(&floor("null")).unwrap();
    assert!(s.patches[0].trim.is_none());
}

#[test]
fn a_trimmed_patch_is_gridded_over_its_outer_boundary_only() {
    // A quarter disc in a corner of the 10 mm floor: its box is [0, 0.3]², 9 % of the patch's.
    let quarter: Vec<String> = (0..=16)
        .map(|k| {
            let a = std::f64::consts::FRAC_PI_2 * k as f64 / 16.0;
            format!("[{}, {}]", 0.3 * a.cos(), 0.3 * a.sin())
        })
        .chain(std::iter::once("[0, 0]".to_string()))
        .collect();
    let s = json::parse(&floor(&format!(r#"{{"outer": [{}]}}"#, quarter.join(", ")))).unwrap();
    let d = s.patches[0].surface.domain();
    assert_eq!((d.u, d.v), ([0.0, 0.3], [0.0, 0.3]));
    // The geometry is the floor's: the point at (u, v) is (10u, 10v, 0).
    for (u, v) in [(0.0, 0.0), (0.3, 0.1), (0.17, 0.29)] {
        let p = s.patches[0].surface.point(u, v);
        assert!(
            (p - Vec3::new(10.0 * u, 10.0 * v, 0.0)).length() < 1e-12,
            "{p}"
        );
    }
    // A 21 × 21 grid over the box: the points (0.015 i, 0.015 j) inside the quarter circle,
    // i² + j² < 20², and the polygon's two vertices on it, (20, 0) and (0, 20) — the other two
    // on the circle, (12, 16) and (16, 12), lie outside the chords: 333, where the whole
    // patch's grid had 35.
    let n = 21;
    let on = s.grid(n).len();
    let count = (0..n * n)
        .filter(|k| (k / n).pow(2) + (k % n).pow(2) < 400)
        .count()
        + 2;
    assert_eq!((on, count), (333, 333));
    // Every grid point is on the part's box, and the trim still says which are on it.
    let t = s.patches[0].trim.as_ref().unwrap();
    assert_eq!(t.region_box(), [0.0, 0.3, 0.0, 0.3]);
    assert!(t.contains(0.1, 0.1) && !t.contains(0.29, 0.29));
    // Written and read again, flipped or not, the cut patch is the same part: the same box
    // (a flipped one's u mirrored within it, u → 0.3 − u), the same points, the same trim.
    for flipped in [false, true] {
        let mut cut = s.clone();
        cut.patches[0].flipped = flipped;
        let back = json::parse(&json::to_string(&cut).unwrap()).unwrap();
        let (p, q) = (&cut.patches[0], &back.patches[0]);
        assert_eq!(q.surface.domain(), p.surface.domain(), "flipped {flipped}");
        let (tp, tq) = (p.trim.as_ref().unwrap(), q.trim.as_ref().unwrap());
        for i in 0..=30 {
            for j in 0..=30 {
                let (u, v) = (
                    0.3 * (i as f64 + 0.37) / 31.0,
                    0.3 * (j as f64 + 0.61) / 31.0,
                );
                let ub = if flipped { 0.3 - u } else { u };
                assert_eq!(
                    tp.contains(u, v),
                    tq.contains(ub, v),
                    "({u}, {v}) {flipped}"
                );
                let (a, b) = (p.surface.point(u, v), q.surface.point(ub, v));
                assert!((a - b).length() < 1e-12, "({u}, {v}) {flipped}: {a} {b}");
            }
        }
    }
    // A trim without an outer boundary keeps the whole box.
    let s = json::parse(&floor(
        r#"{"holes": [[[0.4, 0.4], [0.6, 0.4], [0.5, 0.6]]]}"#,
    ))
    .unwrap();
    let d = s.patches[0].surface.domain();
    assert_eq!((d.u, d.v), ([0.0, 1.0], [0.0, 1.0]));
}

#[test]
fn trims_round_trip_through_the_writer_flipped_or_not() {
    let outer = vec![[0.05, 0.0], [1.0, 0.1], [0.9, 1.0], [0.0, 0.8]];
    let hole = swarf_surface::trim::sample_curve(
        |a| [0.5 + 0.2 * a.cos(), 0.5 + 0.15 * a.sin()],
        0.0,
        std::f64::consts::TAU,
        16,
        1e-6,
    );
    let mut patches = Vec::new();
    for (k, flipped) in [false, true].into_iter().enumerate() {
        let surface = if k == 0 {
            bilinear_plane()
        } else {
            quarter_cylinder(3.0, 5.0)
        };
        let domain = surface.domain();
        let trim = Trim::new(&domain, Some(outer.clone()), vec![hole.clone()]).unwrap();
        patches.push(Patch {
            name: Some(format!("p{k}")),
            flipped,
            trim: Some(trim),
            ..Patch::new(Surface::Nurbs(surface))
        });
    }
    // A trim of holes only (the outer boundary is the box).
    let box_only = Trim::new(&bilinear_plane().domain(), None, vec![hole.clone()]).unwrap();
    patches.push(Patch {
        trim: Some(box_only),
        ..Patch::new(Surface::Nurbs(bilinear_plane()))
    });
    patches.push(Patch::new(Surface::Nurbs(bilinear_plane())));
    let s = CompoundSurface::new(patches);
    let text = json::to_string(&s).unwrap();
    let back = json::parse(&text).unwrap();
    assert_eq!(back.patches.len(), 4);
    assert!(back.patches[3].trim.is_none());
    for k in [0, 2] {
        let (a, b) = (
            s.patches[k].trim.as_ref().unwrap(),
            back.patches[k].trim.as_ref().unwrap(),
        );
        assert_eq!(answers(a), answers(b), "patch {k}");
        // The same loops (to the last bit or so: serde_json's default float parsing may be off
        // by an ulp).
        assert_eq!(a.outer().is_some(), b.outer().is_some());
        let pairs = a.loops().iter().zip(b.loops()).flat_map(|(x, y)| {
            assert_eq!(x.len(), y.len());
            x.iter().zip(y)
        });
        for (p, q) in pairs {
            assert!(
                (p[0] - q[0]).abs() <= 1e-15 && (p[1] - q[1]).abs() <= 1e-15,
                "{p:?} {q:?}"
            );
        }
    }
    // The flipped patch comes back with u reversed (u → 1 − u on [0, 1]): the same points of
    // the part are on it.
    let (a, b) = (
        s.patches[1].trim.as_ref().unwrap(),
        back.patches[1].trim.as_ref().unwrap(),
    );
    assert_eq!(s.patches[1].surface.domain().u, [0.0, 1.0]);
    let mut both = 0;
    for i in 0..41 {
        for j in 0..41 {
            let (u, v) = ((i as f64 + 0.37) / 41.0, (j as f64 + 0.61) / 41.0);
            assert_eq!(a.contains(u, v), b.contains(1.0 - u, v), "({u}, {v})");
            let (p, q) = (
                s.patches[1].surface.point(u, v),
                back.patches[1].surface.point(1.0 - u, v),
            );
            assert!((p - q).length() < 1e-12);
            both += usize::from(a.contains(u, v));
        }
    }
    assert!(both > 100 && both < 41 * 41 - 100, "{both}");
}

#[test]
fn bad_trims_are_refused_naming_the_patch() {
    // A loop of two points.
    let (l, c, m) = json_error(&floor(r#"{"outer": [[0, 0], [1, 1]]}"#));
    assert_eq!(
        m,
        "patch 0 \"floor\": trim.outer has 2 distinct point(s); a loop needs at least 3"
    );
    assert_eq!((l, c), (4, 39), "just past the patch's closing brace");
    let (_, _, m) = json_error(&floor(
        r#"{"holes": [[[0, 0], [1, 0], [1, 1]], [[0.5, 0.5], [0.5, 0.5], [0.5, 0.5], [0.5, 0.5]]]}"#,
    ));
    assert_eq!(
        m,
        "patch 0 \"floor\": trim.holes[1] has 1 distinct point(s); a loop needs at least 3"
    );
    // Not a loop at all.
    let (l, _, m) = json_error(&floor(r#"{"outer": 5}"#));
    assert_eq!(l, 4);
    assert!(
        m.starts_with("patch 0: invalid type: integer `5`, expected a sequence"),
        "{m}"
    );
    // A point of one number, of three; an unknown key; trim not an object.
    let (_, _, m) = json_error(&floor(r#"{"outer": [[0], [1, 0], [0, 1]]}"#));
    assert!(
        m.starts_with("patch 0: invalid length 1, expected an array of length 2"),
        "{m}"
    );
    let (_, _, m) = json_error(&floor(r#"{"outer": [[0, 0, 0], [1, 0], [0, 1]]}"#));
    assert_eq!(m, "patch 0: trailing characters");
    let (_, _, m) = json_error(&floor(r#"{"outre": []}"#));
    assert!(
        m.starts_with("patch 0: unknown field `outre`, expected `outer` or `holes`"),
        "{m}"
    );
    let (_, _, m) = json_error(&floor("7"));
    assert!(
        m.starts_with("patch 0: invalid type: integer `7`, expected struct JsonTrim"),
        "{m}"
    );
    // The second patch named by its index, without a name.
    let two = floor("{}").replace(
        "{}}]}",
        r#"{}}, {"degree_u": 1, "degree_v": 1, "knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1],
  "control_points": [[[0, 0, 0, 1], [0, 10, 0, 1]], [[10, 0, 0, 1], [10, 10, 0, 1]]],
  "trim": {"holes": [[[0.2, 0.2]]]}}]}"#,
    );
    let (_, _, m) = json_error(&two);
    assert_eq!(
        m,
        "patch 1: trim.holes[0] has 1 distinct point(s); a loop needs at least 3"
    );
    // Whatever the trim, a number too large for f64 is refused by the JSON reader.
    let (_, _, m) = json_error(&floor(r#"{"outer": [[0, 0], [1e999, 0], [0, 1]]}"#));
    assert!(m.starts_with("patch 0: number out of range"), "{m}");
}
