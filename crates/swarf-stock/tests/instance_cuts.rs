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

#[test]
fn an_instance_removes_the_tilted_cutters_chord_on_every_ray() {
    let mut rng = Lcg(0x1957_2026_1126);
    let (lo, hi) = (Vec3::new(-9.0, -9.0, -4.0), Vec3::new(9.0, 9.0, 14.0));
    let mut rays = 0usize;
    for round in 0..3 {
        for cutter in every_cutter_kind(&mut rng, 4.0, 10.0, general_apt(8.0, 1.5, 14.0)) {
            let tilt = rng.range(0.0, 1.2);
            let turn = rng.range(0.0, std::f64::consts::TAU);
            // Round 0 also tries an axis along Z, where rays run along faces.
            let axis = if round == 0 {
                Vec3::Z
            } else {
                Vec3::new(tilt.sin() * turn.cos(), tilt.sin() * turn.sin(), tilt.cos())
            };
            let tip = Vec3::new(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-2.0, 0.0),
            );
            let shape = SweepShape::from_solid(cutter.cutting_solid());
            let instance = SubMove {
                s0: 0.0,
                s1: 0.0,
                tip0: tip,
                tip1: tip,
                axis,
                error_bound: 0.0,
            };
            let mut block = TriDexel::from_box(lo, hi, 0.37).unwrap();
            block.cut_shape_pieces(&shape, &[instance], 1e-3);
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
