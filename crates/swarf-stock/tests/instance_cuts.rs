//! A tool instance cut into a block (a zero-length piece, as 5-axis moves of round tools are
//! cut: `swarf_sweep::five_axis`, "Instances") removes from every ray of all three families
//! exactly the chord of the tilted cutter: checked against the cutter's own ray intersections
//! (an independent kernel) for every cutter kind at random tilts. The instance kernel stops at
//! the first two crossings it finds, cheap elements first; this is its proof.

mod common;

use common::{every_cutter_kind, general_apt, Lcg};
use swarf_geom::math::Vec3;
use swarf_geom::{Frame, Ray};
use swarf_stock::TriDexel;
use swarf_sweep::five_axis::SubMove;
use swarf_sweep::SweepShape;
use swarf_tool::CutterKind;

/// The block both tests cut: 18 × 18 × 18 mm, the tip near its middle.
const BLOCK: (Vec3, Vec3) = (Vec3::new(-9.0, -9.0, -4.0), Vec3::new(9.0, 9.0, 14.0));

/// The unit axis tilted `tilt` from +Z towards the direction `turn` about it (radians).
fn axis_at(tilt: f64, turn: f64) -> Vec3 {
    Vec3::new(tilt.sin() * turn.cos(), tilt.sin() * turn.sin(), tilt.cos())
}

/// The tool standing at `tip` along `axis`: a zero-length piece.
fn instance(tip: Vec3, axis: Vec3) -> SubMove {
    SubMove {
        s0: 0.0,
        s1: 0.0,
        tip0: tip,
        tip1: tip,
        axis,
        error_bound: 0.0,
    }
}

#[test]
fn an_instance_removes_the_tilted_cutters_chord_on_every_ray() {
    let mut rng = Lcg(0x1957_2026_1126);
    let (lo, hi) = BLOCK;
    let mut rays = 0usize;
    for round in 0..3 {
        for cutter in every_cutter_kind(&mut rng, 4.0, 10.0, general_apt(8.0, 1.5, 14.0)) {
            let tilt = rng.range(0.0, 1.2);
            let turn = rng.range(0.0, std::f64::consts::TAU);
            // Round 0 also tries an axis along Z, where rays run along faces.
            let axis = if round == 0 {
                Vec3::Z
            } else {
                axis_at(tilt, turn)
            };
            let tip = Vec3::new(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-2.0, 0.0),
            );
            let shape = SweepShape::from_solid(cutter.cutting_solid());
            let mut block = TriDexel::from_box(lo, hi, 0.37).unwrap();
            block.cut_shape_pieces(&shape, &[instance(tip, axis)], 1e-3);
            let frame = Frame::from_axis(tip, axis);
            let g = *block.grid();
            let mut hits = Vec::new();
            for k in 0..3 {
                let (u, v) = ((k + 1) % 3, (k + 2) % 3);
                let fam = block.family(k);
                let (nu, nv) = fam.dims();
                for j in 0..nv {
                    for i in 0..nu {
                        let mut origin = Vec3::ZERO;
                        origin[u] = g.center(u, i);
                        origin[v] = g.center(v, j);
                        let mut dir = Vec3::ZERO;
                        dir[k] = 1.0;
                        // The cutter's chord on this ray, in the tool frame.
                        let local = Ray::new(frame.to_local(origin), frame.vector_to_local(dir));
                        hits.clear();
                        cutter.cutting_solid().ray_intersections(&local, &mut hits);
                        hits.sort_by(f64::total_cmp);
                        let chord = match (hits.first(), hits.last()) {
                            (Some(&a), Some(&b)) if b - a > 1e-9 => Some((a, b)),
                            _ => None,
                        };
                        // What the block keeps: [lo, hi] less the chord.
                        let mut expect = Vec::new();
                        let (a0, b0) = (lo[k], hi[k]);
                        match chord {
                            Some((a, b)) if a < b0 && b > a0 => {
                                if a > a0 {
                                    expect.push((a0, a));
                                }
                                if b < b0 {
                                    expect.push((b, b0));
                                }
                            }
                            _ => expect.push((a0, b0)),
                        }
                        let got: Vec<(f64, f64)> =
                            fam.ray(i, j).iter().map(|iv| (iv.enter, iv.exit)).collect();
                        let same = got.len() == expect.len()
                            && got
                                .iter()
                                .zip(&expect)
                                .all(|(p, q)| (p.0 - q.0).abs() < 1e-7 && (p.1 - q.1).abs() < 1e-7);
                        // A chord shorter than a few nm may or may not be cut.
                        let tiny = chord.is_some_and(|(a, b)| b - a < 1e-6);
                        assert!(
                            same || tiny,
                            "{:?} axis {axis:?} tip {tip:?}, family {k} ray ({i}, {j}): kept {got:?}, expected {expect:?}",
                            cutter.kind()
                        );
                        rays += 1;
                    }
                }
            }
        }
    }
    assert!(rays > 100_000);
}

#[test]
fn instances_cut_together_leave_what_they_leave_cut_one_by_one() {
    // The instances of a 5-axis move (the tip and axis turning a little from one to the next)
    // cut as one set (each ray's chords joined, the ray changed once) against the same
    // instances cut one after the other, on a block whose rays a first cut split: every ray
    // keeps the same intervals (to rounding; a sliver of a few nm may go either way).
    let mut rng = Lcg(0x2026_1128_0111);
    let (lo, hi) = BLOCK;
    let mut compared = 0usize;
    for _ in 0..2 {
        for cutter in every_cutter_kind(&mut rng, 4.0, 10.0, general_apt(8.0, 1.5, 14.0)) {
            let shape = SweepShape::from_solid(cutter.cutting_solid());
            let (tilt, turn) = (rng.range(0.0, 0.9), rng.range(0.0, std::f64::consts::TAU));
            let (dt, dn) = (rng.range(0.02, 0.3), rng.range(-0.05, 0.05));
            let start = Vec3::new(
                rng.range(-2.0, 0.0),
                rng.range(-1.0, 1.0),
                rng.range(-2.0, 0.5),
            );
            // Eleven instances (two groups), the fourth set a diameter and 1 mm aside along X,
            // so that rays along X meet it and its neighbours in disjoint chords.
            let aside = Vec3::new(cutter.max_diameter() + 1.0, 0.0, 0.0);
            let instances: Vec<SubMove> = (0..11)
                .map(|n| {
                    let tip = start
                        + Vec3::new(dt, 0.3 * dt, -0.1 * dt) * n as f64
                        + if n == 3 { aside } else { Vec3::ZERO };
                    instance(tip, axis_at(tilt + dn * n as f64, turn))
                })
                .collect();
            // A slot across the block first, so that rays hold two intervals.
            let mut first = TriDexel::from_box(lo, hi, 0.29).unwrap();
            let slot = SubMove {
                s0: 0.0,
                s1: 1.0,
                tip0: Vec3::new(-12.0, 1.5, 3.0),
                tip1: Vec3::new(12.0, 1.5, 3.0),
                axis: Vec3::Z,
                error_bound: 0.0,
            };
            first.cut_shape_pieces(&shape, &[slot], 1e-3);
            let mut together = first.clone();
            let mut apart = first;
            let (joined, _) = together.cut_instance_set(&shape, &instances);
            let mut updates = 0;
            for i in &instances {
                updates += apart
                    .cut_shape_pieces(&shape, std::slice::from_ref(i), 1e-3)
                    .0
                    .updates;
            }
            // Grouped: each ray changed once a group, far fewer times than one instance after
            // another. (The round kinds' groups take the joined path, held to each instance's
            // own query in `swarf-sweep`'s `an_instance_set_joins_its_instances_chords`.)
            if matches!(
                cutter.kind(),
                CutterKind::Flat | CutterKind::Ball | CutterKind::Bull
            ) {
                assert!(
                    joined.updates * 2 < updates,
                    "{:?}: {} updates together, {updates} apart",
                    cutter.kind(),
                    joined.updates
                );
            }
            for k in 0..3 {
                let (a, b) = (together.family(k), apart.family(k));
                let (nu, nv) = a.dims();
                for j in 0..nv {
                    for i in 0..nu {
                        let (p, q) = (a.ray(i, j), b.ray(i, j));
                        let long = |r: &[swarf_stock::Interval]| -> Vec<(f64, f64)> {
                            r.iter()
                                .filter(|iv| iv.len() > 1e-8)
                                .map(|iv| (iv.enter, iv.exit))
                                .collect()
                        };
                        let (p, q) = (long(p), long(q));
                        let same = p.len() == q.len()
                            && p.iter()
                                .zip(&q)
                                .all(|(x, y)| (x.0 - y.0).abs() < 1e-9 && (x.1 - y.1).abs() < 1e-9);
                        assert!(
                            same,
                            "{:?}, family {k} ray ({i}, {j}): together {p:?}, apart {q:?}",
                            cutter.kind()
                        );
                        compared += 1;
                    }
                }
            }
            let (vt, va) = (together.volume(), apart.volume());
            assert!(
                (vt - va).abs() <= 1e-9 * va,
                "{:?}: {vt} against {va}",
                cutter.kind()
            );
        }
    }
    assert!(compared > 100_000);
}
