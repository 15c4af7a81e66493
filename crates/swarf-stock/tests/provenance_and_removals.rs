//! Provenance of interval ends ("which move cut this") and the removal visitor: each end of a
//! simulated stock names the move that cut it last; tracking changes nothing else; the pieces
//! the visitor hears of add up to what each move removed; an arc's chords, cut as one batch,
//! leave what they leave cut one by one, their ends all naming the arc's move.

mod common;

use std::sync::Mutex;
use swarf_geom::math::Vec3;
use swarf_stock::{simulate, LinearMove, Removal, SimOptions, TriDexel, UNCUT};
use swarf_sweep::ToolShape;
use swarf_tool::{Cutter, ToolSet};

/// Two slots (y = 10 at depth 2, y = 30 at depth 4, moves 3 and 7) and a 270° arc (move 11)
/// in a 40 × 40 × 10 block with a 6 mm flat end mill.
const PROGRAM: &str = "G21 G90 G0 Z5
G0 X-10 Y10
G1 Z-2 F100
G1 X50
G0 Z5
G0 X-10 Y30
G1 Z-4
G1 X50
G0 Z5
G0 X20 Y20
G1 Z-1
G2 X30 Y30 I0 J10
G0 Z5
";

fn block() -> TriDexel {
    TriDexel::from_box(Vec3::new(0.0, 0.0, -10.0), Vec3::new(40.0, 40.0, 0.0), 0.25).unwrap()
}

/// The tags of the Z ray through `(x, y)`: `(enter, exit)` of its intervals.
fn z_tags(s: &TriDexel, x: f64, y: f64) -> Vec<(u32, u32)> {
    let g = s.grid();
    let i = ((x - g.min.x) / g.h[0]) as usize;
    let j = ((y - g.min.y) / g.h[1]) as usize;
    let fam = s.family(2);
    fam.ray_tags(i, j)
        .unwrap()
        .iter()
        .map(|t| (t.enter, t.exit))
        .collect()
}

#[test]
fn every_end_names_the_move_that_cut_it() {
    let program = common::gcode(PROGRAM);
    assert_eq!(program.moves.len(), 13, "{:#?}", program.moves.len());
    let tools = ToolSet::single(Cutter::flat(6.0).unwrap());
    let mut s = block();
    s.track_provenance();
    simulate(&program, &tools, &mut s, &SimOptions::default()).unwrap();
    assert_eq!(z_tags(&s, 20.1, 10.1), vec![(UNCUT, 3)]);
    assert_eq!(z_tags(&s, 5.1, 30.1), vec![(UNCUT, 7)]);
    assert_eq!(z_tags(&s, 35.1, 20.1), vec![(UNCUT, UNCUT)]);
    // The arc (cut as chords, one move) about (20, 30), radius 10, clockwise from the bottom
    // through the left and the top to the right: at 135°.
    let (x, y) = (20.0 - 10.0 * 0.5f64.sqrt(), 30.0 + 10.0 * 0.5f64.sqrt());
    assert_eq!(z_tags(&s, x, y), vec![(UNCUT, 11)]);
    // An X ray through the first slot's floor height, inside the slot's width, crosses it
    // whole: no interval left (the slot goes from x = −10 to 50).
    let g = s.grid();
    let (j, kk) = (
        ((10.0 - g.min.y) / g.h[1]) as usize,
        ((-1.1 - g.min.z) / g.h[2]) as usize,
    );
    assert!(s.family(0).ray(j, kk).is_empty());
    // A Y ray at x = 20, z = −1.1 crosses the first slot's walls (y = 7 and 13): made by
    // move 3.
    let i = ((20.1 - g.min.x) / g.h[0]) as usize;
    let tags = s.family(1).ray_tags(kk, i).unwrap();
    let ray = s.family(1).ray(kk, i);
    assert_eq!(ray.len(), tags.len());
    assert!(
        (ray[0].exit - 7.0).abs() < 1e-9 && tags[0].exit == 3,
        "{ray:?} {tags:?}"
    );
    assert!(
        (ray[1].enter - 13.0).abs() < 1e-9 && tags[1].enter == 3,
        "{ray:?} {tags:?}"
    );
}

#[test]
fn tracking_changes_nothing_else() {
    let program = common::gcode(PROGRAM);
    let tools = ToolSet::single(Cutter::ball(5.0).unwrap());
    let mut plain = block();
    let mut tracked = block();
    tracked.track_provenance();
    assert!(tracked.tracks_provenance() && !plain.tracks_provenance());
    let a = simulate(&program, &tools, &mut plain, &SimOptions::default()).unwrap();
    let b = simulate(&program, &tools, &mut tracked, &SimOptions::default()).unwrap();
    assert_eq!(a.removed_per_move_mm3, b.removed_per_move_mm3);
    for k in 0..3 {
        let (nu, nv) = plain.family(k).dims();
        for j in 0..nv {
            for i in 0..nu {
                let (p, t) = (plain.family(k).ray(i, j), tracked.family(k).ray(i, j));
                assert_eq!(p, t);
                let tags = tracked.family(k).ray_tags(i, j).unwrap();
                assert_eq!(tags.len(), t.len());
                // Every tag is a move of the program or the stock itself.
                for e in tags {
                    for m in [e.enter, e.exit] {
                        assert!(m == UNCUT || (m as usize) < program.moves.len());
                    }
                }
                assert!(plain.family(k).ray_tags(i, j).is_none());
            }
        }
    }
    assert!(tracked.stats().bytes > plain.stats().bytes);
}

#[test]
fn removals_add_up_to_what_each_move_removed() {
    let tool = ToolShape::new(&Cutter::bull(8.0, 2.0).unwrap());
    let moves: Vec<LinearMove> = [
        (Vec3::new(-5.0, 8.0, -3.0), Vec3::new(45.0, 12.0, -1.0)),
        (Vec3::new(20.0, -5.0, -2.0), Vec3::new(20.0, 45.0, -2.0)),
        (Vec3::new(20.0, 20.0, -6.0), Vec3::new(20.0, 20.0, -6.0)),
    ]
    .into_iter()
    .map(|(tip0, tip1)| LinearMove {
        tip0,
        tip1,
        axis: Vec3::Z,
    })
    .collect();
    let mut plain = block();
    let want = plain.cut_linear_batch(&tool, &moves);
    let mut s = block();
    s.set_move_tag(100);
    let heard: Mutex<Vec<Removal>> = Mutex::new(Vec::new());
    let got =
        s.cut_linear_batch_visited(&tool, &moves, &|r: &Removal| heard.lock().unwrap().push(*r));
    assert_eq!(got, want);
    let heard = heard.into_inner().unwrap();
    for (m, cut) in want.iter().enumerate() {
        for k in 0..3 {
            let sum: f64 = heard
                .iter()
                .filter(|r| r.move_index == m && r.family == k && r.group == 0)
                .map(|r| r.removed.len())
                .sum();
            let expect = cut.cutting.removed_length[k];
            assert!(expect > 1.0, "move {m} family {k} removed nothing");
            assert!(
                (sum - expect).abs() < 1e-9 * expect,
                "{m} {k}: {sum} vs {expect}"
            );
        }
    }
    assert!(heard.iter().all(|r| r.tag == 100 + r.move_index as u32));
    // Removed pieces lie where the stock had material before the move.
    let before = block();
    for r in heard.iter().filter(|r| r.move_index == 0) {
        let (i, j) = r.ray;
        let ray = before.family(r.family).ray(i, j);
        assert!(ray
            .iter()
            .any(|iv| iv.enter <= r.removed.enter && r.removed.exit <= iv.exit));
    }
}

#[test]
fn an_arcs_chords_cut_together_leave_what_they_leave_cut_one_by_one() {
    // `cut_move` cuts an arc's chords as one batch; here each chord of the same points is cut
    // by its own `cut_linear` call. The arc of PROGRAM (move 11) and a helix (one and a half
    // turns down 2 mm), with a ball end mill whose shank reaches the block.
    let helix = "G21 G90 G0 X20 Y10 Z5\nG1 Z-1 F100\nG3 X20 Y30 Z-3 I0 J10 P2\nG0 Z5\n";
    for (text, arc) in [(PROGRAM, 11), (helix, 2)] {
        let program = common::gcode(text);
        let swarf_path::MoveKind::Arc(g) = program.moves[arc].kind else {
            panic!("move {arc} is no arc");
        };
        let tool = ToolShape::new(&Cutter::ball(6.0).unwrap());
        let tol = swarf_stock::DEFAULT_CHORDAL_TOLERANCE_MM;
        let (mut together, mut apart) = (block(), block());
        for s in [&mut together, &mut apart] {
            for i in 0..arc {
                s.cut_move(&program, i, &tool, tol).unwrap();
            }
        }
        let whole = together.cut_move(&program, arc, &tool, tol).unwrap();
        let m = &program.moves[arc];
        let n = swarf_sweep::arc_chords(g.start_radius.max(g.end_radius), g.sweep, tol);
        assert!(n > 100, "{n} chords");
        let axis = m.start.axis.normalize();
        let mut removed = 0.0;
        for i in 0..n {
            let tip = |k: usize| program.pose_at(m, k as f64 / n as f64).tip;
            let (a, b) = (tip(i), if i + 1 == n { m.end.tip } else { tip(i + 1) });
            let a = if i == 0 { m.start.tip } else { a };
            removed += apart.cut_linear(&tool, a, b, axis).cutting.removed_length[2];
        }
        assert_eq!(whole.cutting.removed_length[2], removed);
        for k in 0..3 {
            let (nu, nv) = together.family(k).dims();
            for j in 0..nv {
                for i in 0..nu {
                    assert_eq!(
                        together.family(k).ray(i, j),
                        apart.family(k).ray(i, j),
                        "family {k} ray ({i}, {j})"
                    );
                }
            }
        }
    }
}
