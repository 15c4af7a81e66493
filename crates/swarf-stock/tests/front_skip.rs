//! The front test of chained moves (`swarf_sweep::Front`: a move starting where the tool last
//! stood queries only the rays its start instance's front can reach) leaves the stock exactly
//! as querying every ray does, on a finishing raster over a wavy surface (round, flat and
//! tapered cutters, one with its shank and holder in the block, one on a tilted axis), in one
//! call and move by move — and it does skip rays.

use swarf_geom::math::Vec3;
use swarf_stock::{CutStats, LinearMove, TriDexel};
use swarf_sweep::ToolShape;
use swarf_tool::{Cutter, CutterKind, CutterOptions, Holder, HolderSegment};

/// A zig-zag raster over `z = 6 + sin(x/3)·cos(y/4)`: passes along X, 0.4 mm moves.
fn raster() -> Vec<LinearMove> {
    let surface = |x: f64, y: f64| 6.0 + (x / 3.0).sin() * (y / 4.0).cos();
    let mut pts = Vec::new();
    for pass in 0..6 {
        let y = 2.0 + 0.8 * pass as f64;
        for i in 0..=30 {
            let t = 2.0 + 0.4 * i as f64;
            let x = if pass % 2 == 0 { t } else { 16.0 - t };
            pts.push(Vec3::new(x, y, surface(x, y)));
        }
    }
    LinearMove::chain(&pts, Vec3::Z)
}

fn visited(cuts: &[swarf_stock::SegmentCut]) -> u64 {
    cuts.iter()
        .fold(CutStats::default(), |s, c| s.merged(c.cutting))
        .visited_per_family
        .iter()
        .sum()
}

#[test]
fn the_front_test_changes_no_ray() {
    // A short ball whose narrow shank and stepped holder reach into the block: the shank and
    // holder group has several convex parts, each with its own front.
    let held = CutterOptions {
        flute_length: Some(2.5),
        overall_length: Some(3.5),
        shank_diameter: Some(3.0),
        holder: Some(Holder {
            base_z_mm: 3.5,
            segments: vec![HolderSegment {
                length_mm: 6.0,
                bottom_diameter_mm: 5.0,
                top_diameter_mm: 9.0,
            }],
        }),
        ..CutterOptions::default()
    };
    let tilted = Vec3::new(0.25, -0.15, 1.0).normalize();
    let mut several = 0;
    for (cutter, axis) in [
        (Cutter::ball(4.0).unwrap(), Vec3::Z),
        (Cutter::bull(4.0, 1.0).unwrap(), Vec3::Z),
        (Cutter::flat(3.0).unwrap(), Vec3::Z),
        (Cutter::taper_ball(4.0, 6.0).unwrap(), Vec3::Z),
        (
            Cutter::named(CutterKind::Ball, &[4.0], &held).unwrap(),
            Vec3::Z,
        ),
        (Cutter::bull(4.0, 1.0).unwrap(), tilted),
    ] {
        let moves: Vec<LinearMove> = raster()
            .into_iter()
            .map(|m| LinearMove { axis, ..m })
            .collect();
        let tool = ToolShape::new(&cutter);
        let block = TriDexel::from_box(Vec3::ZERO, Vec3::new(18.0, 10.0, 9.0), 0.13).unwrap();
        let mut every = block.clone();
        every.set_exhaustive(true);
        let all = every.cut_linear_batch(&tool, &moves);
        let mut batch = block.clone();
        let fronted = batch.cut_linear_batch(&tool, &moves);
        if tool.non_cutting().parts().len() > 1 {
            several += 1;
            // The several parts of the shank and holder do cut here.
            let held: f64 = fronted
                .iter()
                .flat_map(|c| c.non_cutting.removed_length)
                .sum();
            assert!(held > 1.0, "{held} mm removed by the shank and holder");
        }
        // Move by move (each call chained to the last through the stock's memory).
        let mut single = block.clone();
        for m in &moves {
            single.cut_linear(&tool, m.tip0, m.tip1, m.axis);
        }
        assert!(
            (visited(&fronted) as f64) < 0.9 * visited(&all) as f64,
            "{:?}: {} rays visited with the front test, {} without",
            cutter.kind(),
            visited(&fronted),
            visited(&all)
        );
        for s in [&batch, &single] {
            for k in 0..3 {
                let (nu, nv) = s.family(k).dims();
                for j in 0..nv {
                    for i in 0..nu {
                        let (a, b) = (s.family(k).ray(i, j), every.family(k).ray(i, j));
                        assert_eq!(
                            a.len(),
                            b.len(),
                            "{:?}: family {k} ray ({i}, {j})",
                            cutter.kind()
                        );
                        for (p, q) in a.iter().zip(b) {
                            assert!(
                                (p.enter - q.enter).abs() <= 1e-9
                                    && (p.exit - q.exit).abs() <= 1e-9,
                                "{:?}: family {k} ray ({i}, {j}): {a:?} vs {b:?}",
                                cutter.kind()
                            );
                        }
                    }
                }
            }
        }
    }
    assert_eq!(
        several, 1,
        "the held cutter's shank and holder are several parts"
    );
}
