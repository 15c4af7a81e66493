//! Invariants of material removal, on random moves of random cutters with random fixed axes:
//! volume never increases; cutting a move twice removes nothing more; splitting a move in two
//! gives the same stock; moves commute; nothing outside the sweep is removed; and whatever the
//! stock's state, a batch leaves every ray exactly as an exact subtraction would (no bound ever
//! skips a ray the sweep changes), moves in one plane cut together included.

use proptest::prelude::*;
use swarf_geom::math::Vec3;
use swarf_stock::TriDexel;
use swarf_sweep::ToolShape;
use swarf_tool::Cutter;

fn stock() -> TriDexel {
    TriDexel::from_box(Vec3::ZERO, Vec3::new(16.0, 12.0, 8.0), 0.25).unwrap()
}

fn cutter(kind: u8, d: f64) -> Cutter {
    match kind % 5 {
        0 => Cutter::flat(d),
        1 => Cutter::ball(d),
        2 => Cutter::bull(d, d / 4.0),
        3 => Cutter::drill(d, 118.0),
        _ => Cutter::taper_ball(d, 6.0),
    }
    .unwrap()
}

/// Per-family lengths: the whole stock at a glance.
fn lengths(s: &TriDexel) -> [f64; 3] {
    s.volumes()
}

fn arb_point() -> impl Strategy<Value = Vec3> {
    (-2.0f64..18.0, -2.0f64..14.0, 2.0f64..10.0).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

fn arb_axis() -> impl Strategy<Value = Vec3> {
    prop_oneof![
        Just(Vec3::Z),
        (-0.6f64..0.6, -0.6f64..0.6).prop_map(|(x, y)| Vec3::new(x, y, 1.0).normalize()),
    ]
}

proptest! {
    #![proptest_config(swarf_testdata::proptest_config(24))]

    #[test]
    fn removal_invariants(kind in 0u8..5, d in 2.0f64..8.0, a in arb_point(), b in arb_point(),
                          c in arb_point(), axis in arb_axis(), split in 0.1f64..0.9) {
        let tool = ToolShape::new(&cutter(kind, d));
        let base = stock();
        let v0 = base.volume();

        // Volume never increases; cutting again removes nothing more.
        let mut s1 = base.clone();
        s1.cut_linear(&tool, a, b, axis);
        let v1 = s1.volume();
        prop_assert!(v1 <= v0 + 1e-9);
        let again = s1.cut_linear(&tool, a, b, axis);
        let rem: f64 = again.cutting.removed_length.iter().chain(&again.non_cutting.removed_length).sum();
        prop_assert!(rem <= 1e-9, "second cut removed {} mm of ray length", rem);

        // Splitting the move gives the same stock.
        let m = a.lerp(b, split);
        let mut s2 = base.clone();
        s2.cut_linear(&tool, a, m, axis);
        s2.cut_linear(&tool, m, b, axis);
        let (l1, l2) = (lengths(&s1), lengths(&s2));
        for k in 0..3 {
            prop_assert!((l1[k] - l2[k]).abs() <= 1e-6 * v0, "family {}: {} vs {}", k, l1[k], l2[k]);
        }

        // Moves commute.
        let mut s3 = base.clone();
        s3.cut_linear(&tool, a, b, axis);
        s3.cut_linear(&tool, b, c, axis);
        let mut s4 = base.clone();
        s4.cut_linear(&tool, b, c, axis);
        s4.cut_linear(&tool, a, b, axis);
        let (l3, l4) = (lengths(&s3), lengths(&s4));
        for k in 0..3 {
            prop_assert!((l3[k] - l4[k]).abs() <= 1e-9 * v0);
        }
    }

    #[test]
    fn removal_stays_inside_the_sweep(kind in 0u8..5, d in 2.0f64..8.0, a in arb_point(), b in arb_point(),
                                      axis in arb_axis()) {
        // The removed length on every Z ray is at most the ray's length inside the swept
        // volume (computed by the public single-ray query), and the material left on the ray
        // never overlaps the swept interval.
        let c = cutter(kind, d);
        let tool = ToolShape::new(&c);
        let mut s = stock();
        let before = s.clone();
        s.cut_linear(&tool, a, b, axis);
        let shapes = [tool.cutting(), tool.non_cutting()];
        let g = *s.grid();
        let fam = s.family(2);
        let (nu, nv) = fam.dims();
        let mut swept_total = 0.0;
        for j in 0..nv {
            for i in 0..nu {
                let o = Vec3::new(g.center(0, i), g.center(1, j), 0.0);
                let mut sw: Vec<(f64, f64)> = Vec::new();
                for sh in shapes {
                    for p in sh.parts() {
                        let sc = swarf_sweep::SweptConvex::new(p, a, axis, b - a);
                        if let Some(iv) = sc.ray_interval(o, Vec3::Z) {
                            sw.push(iv);
                        }
                    }
                }
                let removed = swarf_stock::dexel::dexel_length(before.family(2).ray(i, j))
                    - swarf_stock::dexel::dexel_length(fam.ray(i, j));
                let inside: f64 = sw.iter().map(|&(lo, hi)| {
                    // material that was there, inside this interval
                    before.family(2).ray(i, j).iter().map(|m| (m.exit.min(hi) - m.enter.max(lo)).max(0.0)).sum::<f64>()
                }).sum();
                prop_assert!(removed <= inside + 1e-9, "ray ({}, {}): removed {} > {}", i, j, removed, inside);
                for m in fam.ray(i, j) {
                    for &(lo, hi) in &sw {
                        prop_assert!(m.exit.min(hi) - m.enter.max(lo) <= 1e-9, "material left inside the sweep");
                    }
                }
                swept_total += inside;
            }
        }
        let removed_v = before.volume() - s.volume();
        prop_assert!(removed_v <= swept_total * s.ray_area(2) + 1e-9);
    }
}

/// `ray` minus the intervals `cut`, slivers under the stock's minimum dropped: what an exact
/// subtraction leaves.
fn subtract_all(ray: &[swarf_stock::Interval], cut: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut left: Vec<(f64, f64)> = ray.iter().map(|m| (m.enter, m.exit)).collect();
    for &(lo, hi) in cut {
        left = left
            .into_iter()
            .flat_map(|(a, b)| [(a, b.min(lo)), (a.max(hi), b)])
            .filter(|(a, b)| b - a > swarf_stock::dexel::MIN_INTERVAL_MM)
            .collect();
    }
    left
}

fn arb_move() -> impl Strategy<Value = (Vec3, Vec3, Vec3)> {
    (arb_point(), arb_point(), arb_axis())
}

/// A step of a chained path: anywhere, level (no change along Z), straight up or down, or
/// along one world axis — the cases the trailing-start skip tells apart.
fn arb_step() -> impl Strategy<Value = Vec3> {
    prop_oneof![
        (-3.0f64..3.0, -3.0f64..3.0, -2.0f64..2.0).prop_map(|(x, y, z)| Vec3::new(x, y, z)),
        (-3.0f64..3.0, -3.0f64..3.0).prop_map(|(x, y)| Vec3::new(x, y, 0.0)),
        (-2.0f64..2.0).prop_map(|z| Vec3::new(0.0, 0.0, z)),
        (-3.0f64..3.0, 0usize..3).prop_map(|(t, k)| {
            let mut v = Vec3::ZERO;
            v[k] = t;
            v
        }),
        Just(Vec3::ZERO),
    ]
}

/// The moves `(tip0, tip1, axis)` as the stock takes them.
fn linear(moves: &[(Vec3, Vec3, Vec3)]) -> Vec<swarf_stock::LinearMove> {
    moves
        .iter()
        .map(|&(tip0, tip1, axis)| swarf_stock::LinearMove { tip0, tip1, axis })
        .collect()
}

/// Every ray of `s` is `state` less the exact swept intervals of `moves` (both groups).
fn check_exact(
    s: &TriDexel,
    state: &TriDexel,
    tool: &ToolShape,
    moves: &[swarf_stock::LinearMove],
) -> Result<(), TestCaseError> {
    let g = *s.grid();
    let shapes = [tool.cutting(), tool.non_cutting()];
    for k in 0..3 {
        let (u, v) = ((k + 1) % 3, (k + 2) % 3);
        let mut dir = Vec3::ZERO;
        dir[k] = 1.0;
        let (nu, nv) = s.family(k).dims();
        for j in 0..nv {
            for i in 0..nu {
                let mut o = Vec3::ZERO;
                o[u] = g.center(u, i);
                o[v] = g.center(v, j);
                let mut sw = Vec::new();
                for m in moves {
                    for sh in shapes {
                        for p in sh.parts() {
                            let sc =
                                swarf_sweep::SweptConvex::new(p, m.tip0, m.axis, m.tip1 - m.tip0);
                            sw.extend(sc.ray_interval(o, dir));
                        }
                    }
                }
                let want = subtract_all(state.family(k).ray(i, j), &sw);
                let got = s.family(k).ray(i, j);
                prop_assert_eq!(
                    got.len(),
                    want.len(),
                    "family {} ray ({}, {}): {:?} vs {:?}",
                    k,
                    i,
                    j,
                    got,
                    want
                );
                for (a, b) in got.iter().zip(&want) {
                    prop_assert!(
                        (a.enter - b.0).abs() <= 1e-9 && (a.exit - b.1).abs() <= 1e-9,
                        "family {} ray ({}, {}): {:?} vs {:?}",
                        k,
                        i,
                        j,
                        got,
                        want
                    );
                }
            }
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(swarf_testdata::proptest_config(16))]

    /// Issue 14's guard on the skipping: whatever the stock's state (random cuts before, in
    /// batches, with the tile bounds they leave behind), a batch of moves leaves on every ray
    /// of every family exactly the material minus the exact swept intervals of its moves —
    /// so no tile or ray bound ever skipped a ray the sweep changes (nor did it cut one it
    /// does not).
    #[test]
    fn bounds_never_skip_a_ray_the_sweep_changes(
        kind in 0u8..5,
        d in 2.0f64..8.0,
        before in prop::collection::vec(arb_move(), 1..5),
        batch in prop::collection::vec(arb_move(), 1..4),
        batch_kind in 0u8..5,
    ) {
        let mut s = stock();
        // A random state: earlier batches of another cutter.
        let earlier = ToolShape::new(&cutter(kind, d));
        for chunk in before.chunks(2) {
            s.cut_linear_batch(&earlier, &linear(chunk));
        }
        let state = s.clone();
        let c = cutter(batch_kind, d.min(6.0));
        let tool = ToolShape::new(&c);
        let moves = linear(&batch);
        s.cut_linear_batch(&tool, &moves);
        check_exact(&s, &state, &tool, &moves)?;
    }

    /// Along a chained path (each move starting where the last ended, in one call or across
    /// two; level, vertical and axis-aligned steps included; tools short enough that the tops
    /// of both parts are inside the stock), every ray ends exactly as the material less the
    /// moves' exact swept intervals — the guard any skipping of rays a move's start instance
    /// already cut must pass.
    #[test]
    fn chained_moves_are_cut_exactly(
        kind in 0u8..5,
        d in 2.0f64..8.0,
        before in prop::collection::vec(arb_move(), 0..3),
        start in arb_point(),
        steps in prop::collection::vec(arb_step(), 1..6),
        axis in prop_oneof![Just(Vec3::Z), Just(Vec3::X), Just(Vec3::Y), arb_axis()],
        batch_kind in 0u8..5,
        split in 0usize..6,
        short in any::<bool>(),
    ) {
        let mut s = stock();
        let earlier = ToolShape::new(&cutter(kind, d));
        s.cut_linear_batch(&earlier, &linear(&before));
        let state = s.clone();
        // A short tool (flutes one diameter long, the shank half that) puts the tops of both
        // parts inside the stock, where a rising tool's tops lead.
        let c = cutter(batch_kind, d.min(6.0));
        let c = if short {
            let (d, h) = (c.max_diameter(), c.apt_params().h.min(c.max_diameter()));
            let opts = swarf_tool::CutterOptions {
                flute_length: Some(h),
                overall_length: Some(1.5 * h),
                ..swarf_tool::CutterOptions::default()
            };
            let nums: Vec<f64> = match batch_kind % 5 {
                2 => vec![d, d / 4.0],
                3 => vec![d, 118.0],
                4 => vec![d, 6.0],
                _ => vec![d],
            };
            Cutter::named(c.kind(), &nums, &opts).unwrap_or(c)
        } else {
            c
        };
        let tool = ToolShape::new(&c);
        let mut tip = start;
        let chain: Vec<_> = steps
            .iter()
            .map(|&v| {
                let m = swarf_stock::LinearMove { tip0: tip, tip1: tip + v, axis };
                tip += v;
                m
            })
            .collect();
        let cut = split.min(chain.len());
        s.cut_linear_batch(&tool, &chain[..cut]);
        s.cut_linear_batch(&tool, &chain[cut..]);
        check_exact(&s, &state, &tool, &chain)?;
    }

    /// The same guard on the runs of ball-end moves in one plane normal to a ray family, cut
    /// together on that family's rows (`swarf_sweep::PlanarMember`): a chained path in the
    /// plane (any tool axis along a world axis, plunges and lifts included), after a random
    /// state; flutes long enough for the chords to be exact over the whole stock, or short
    /// (the runs refused where the tool's top could cut a chord short).
    #[test]
    fn planar_runs_are_cut_exactly(
        before in prop::collection::vec(arb_move(), 0..3),
        start in arb_point(),
        steps in prop::collection::vec((-3.0f64..3.0, -2.0f64..2.0, 0u8..4), 2..12),
        kt in 0usize..3,
        side in 1usize..3,
        d in 2.0f64..6.0,
        long in any::<bool>(),
    ) {
        let k = (kt + side) % 3;
        let a = 3 - k - kt;
        let mut s = stock();
        s.cut_linear_batch(&ToolShape::new(&cutter(0, 4.0)), &linear(&before));
        let state = s.clone();
        let opts = swarf_tool::CutterOptions {
            flute_length: Some(if long { 40.0 } else { d }),
            ..swarf_tool::CutterOptions::default()
        };
        let c = Cutter::named(swarf_tool::CutterKind::Ball, &[d], &opts).unwrap();
        let tool = ToolShape::new(&c);
        let mut axis = Vec3::ZERO;
        axis[kt] = 1.0;
        let mut p = start;
        let mut moves = Vec::new();
        for (da, dz, kind) in steps {
            let mut q = p;
            // Across the axis, along it, both, or not at all.
            match kind {
                0 => q[a] += da,
                1 => q[kt] += dz,
                2 => {
                    q[a] += da;
                    q[kt] += dz;
                }
                _ => {}
            }
            moves.push((p, q, axis));
            p = q;
        }
        let moves = linear(&moves);
        s.cut_linear_batch(&tool, &moves);
        check_exact(&s, &state, &tool, &moves)?;
    }
}
