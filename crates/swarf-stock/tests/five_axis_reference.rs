//! 5-axis simultaneous moves against an independent brute-force reference: the stock's own rays
//! against densely sampled tool instances along the true motion (`Program::pose_at`, the
//! cutting part and the shank posed in their frames), for every cutter type, on a table-table
//! machine without TCP (the tip curves), a head-head machine with TCP, and CL moves (straight
//! and helical tip) with a slerped axis.
//!
//! The sub-moves' sweep `S̃` is within `ε` (the reported error bound) of the true sweep `S`
//! in Hausdorff distance, and more precisely a point deeper than `ε` inside a true instance is
//! inside `S̃` (five_axis module documentation). The samples are true instances, and the true
//! sweep is within `δ` of their union `U` (half the largest motion of any tool point between
//! two samples, with a margin). So on every ray:
//! 1. material left by the simulation is nowhere deeper than `ε` inside any sampled instance;
//! 2. every point the simulation removed is within `ε + δ` of some sampled instance.

mod common;

use common::{boundary_distance, every_cutter_kind, general_apt, Lcg};
use swarf_geom::math::Vec3;
use swarf_geom::{Frame, Ray};
use swarf_path::{Axes, AxisSource, FeedMode, Machine, Move, MoveKind, Pose, Program};
use swarf_stock::TriDexel;
use swarf_sweep::{ConvexProfile, ToolShape};
use swarf_tool::{Cutter, RevolvedSolid};

/// A convex solid of the tool with its profile, for distances.
struct Solid<'a> {
    solid: &'a RevolvedSolid,
    prof: ConvexProfile,
}

impl Solid<'_> {
    /// Signed distance of a tool-frame point: negative inside (minus the depth).
    fn signed(&self, q: Vec3) -> f64 {
        let (rho, z) = (q.x.hypot(q.y), q.z);
        let d = boundary_distance(self.prof.elements(), rho, z);
        if self.solid.contains(q) {
            -d
        } else {
            d
        }
    }
}

/// A sampled tool instance.
struct Instance {
    frame: Frame,
    tip: Vec3,
}

impl Instance {
    fn local(&self, p: Vec3) -> Vec3 {
        self.frame.vector_to_local(p - self.tip)
    }
}

struct Figures {
    sub_moves: u64,
    bound: f64,
    delta: f64,
    removed_sim: f64,
    removed_ref: f64,
    worst_depth: f64,
    worst_distance: f64,
}

/// Cuts move 0 of `p` with `cutter` on a fresh box and checks it against `samples` instances.
fn check(p: &Program, cutter: &Cutter, tol: f64, samples: usize) -> Figures {
    let (lo, hi) = (Vec3::new(-10.0, -10.0, -8.0), Vec3::new(10.0, 10.0, 2.0));
    let h = 0.5;
    let mut stock = TriDexel::from_box(lo, hi, h).unwrap();
    let v0 = stock.volume();
    let tool = ToolShape::new(cutter);
    let cut = stock.cut_move(p, 0, &tool, tol).unwrap();
    assert!(cut.error_bound_mm <= tol && cut.sub_moves >= 1);
    let eps = cut.error_bound_mm;

    let mut solids = vec![Solid {
        solid: cutter.cutting_solid(),
        prof: ConvexProfile::from_solid(cutter.cutting_solid()).unwrap(),
    }];
    if !cutter.shank_solid().pieces().is_empty() {
        solids.push(Solid {
            solid: cutter.shank_solid(),
            prof: ConvexProfile::from_solid(cutter.shank_solid()).unwrap(),
        });
    }
    let reach = solids
        .iter()
        .map(|s| {
            let (z0, z1) = s.solid.z_range();
            s.solid.max_radius().hypot(z0.abs().max(z1.abs()))
        })
        .fold(0.0, f64::max);
    let m = &p.moves[0];
    let poses: Vec<Pose> = (0..=samples)
        .map(|i| p.pose_at(m, i as f64 / samples as f64))
        .collect();
    // Largest motion of a tool point between neighbouring samples; the true instance at any
    // s is within half of it of a sample (×1.25 for the curvature of the motion between them).
    let step = poses
        .windows(2)
        .map(|w| {
            let th = w[0].axis.angle_between(w[1].axis);
            (w[1].tip - w[0].tip).length() + 2.0 * (th / 2.0).sin() * reach
        })
        .fold(0.0, f64::max);
    let delta = 0.625 * step;
    let inst: Vec<Instance> = poses
        .iter()
        .map(|q| Instance {
            frame: Frame::from_axis(Vec3::ZERO, q.axis),
            tip: q.tip,
        })
        .collect();

    let g = *stock.grid();
    let mut hits = Vec::new();
    let (mut worst_depth, mut worst_distance) = (f64::NEG_INFINITY, 0.0f64);
    let mut removed_ref = 0.0;
    for k in 0..3 {
        let (u, v) = ((k + 1) % 3, (k + 2) % 3);
        let fam = stock.family(k);
        let (nu, nv) = fam.dims();
        let dir = Vec3::AXES[k];
        for j in 0..nv {
            for i in 0..nu {
                let mut origin = Vec3::ZERO;
                origin[u] = g.center(u, i);
                origin[v] = g.center(v, j);
                let left = fam.ray(i, j);
                let at = |t: f64| origin + dir * t;
                // Sampled intervals of the ray (clipped to the block).
                let mut ivs: Vec<(f64, f64, usize, usize)> = Vec::new();
                for (n, ins) in inst.iter().enumerate() {
                    let ray = Ray::new(ins.local(origin), ins.frame.vector_to_local(dir));
                    for (si, s) in solids.iter().enumerate() {
                        // Skip instances whose bounding ball the ray misses.
                        let (z0, z1) = s.solid.z_range();
                        let c = ins.tip + ins.frame.z * (0.5 * (z0 + z1)) - origin;
                        let r = s.solid.max_radius().hypot(0.5 * (z1 - z0));
                        if c[u].hypot(c[v]) > r {
                            continue;
                        }
                        hits.clear();
                        s.solid.ray_intersections(&ray, &mut hits);
                        if hits.len() >= 2 {
                            let (a, b) = (hits[0].max(lo[k]), hits[hits.len() - 1].min(hi[k]));
                            if a < b {
                                ivs.push((a, b, n, si));
                            }
                        }
                    }
                }
                // 1. Material left is nowhere deeper than ε inside a sampled instance (depth
                //    is concave along a chord of a convex solid: ternary search for its top).
                for &(a, b, n, si) in &ivs {
                    for iv in left.iter() {
                        let (c, d) = (a.max(iv.enter), b.min(iv.exit));
                        if c >= d {
                            continue;
                        }
                        let depth = |t: f64| -solids[si].signed(inst[n].local(at(t)));
                        let (mut x0, mut x1) = (c, d);
                        for _ in 0..60 {
                            let (m1, m2) = (x0 + (x1 - x0) / 3.0, x1 - (x1 - x0) / 3.0);
                            if depth(m1) < depth(m2) {
                                x0 = m1;
                            } else {
                                x1 = m2;
                            }
                        }
                        let top = depth(0.5 * (x0 + x1)).max(depth(c)).max(depth(d));
                        worst_depth = worst_depth.max(top);
                        assert!(
                            top <= eps + 1e-7,
                            "material left {top} mm deep (bound {eps}) in instance {n} on ray {k} ({i}, {j}), cutter {}",
                            cutter.spec()
                        );
                    }
                }
                // 2. Removed points lie within ε + δ of a sampled instance.
                let mut removed: Vec<(f64, f64)> = Vec::new();
                let mut t = lo[k];
                for iv in left.iter().chain(std::iter::once(&swarf_stock::Interval {
                    enter: hi[k],
                    exit: hi[k],
                })) {
                    if iv.enter > t + 1e-12 {
                        removed.push((t, iv.enter));
                    }
                    t = iv.exit;
                }
                for &(c, d) in &removed {
                    for f in [0.0, 0.25, 0.5, 0.75, 1.0] {
                        let x = at(c + f * (d - c));
                        let mut best = f64::INFINITY;
                        'search: for ins in &inst {
                            let q = ins.local(x);
                            if q.length() > reach + best {
                                continue;
                            }
                            for s in &solids {
                                best = best.min(s.signed(q).max(0.0));
                                if best == 0.0 {
                                    break 'search;
                                }
                            }
                        }
                        worst_distance = worst_distance.max(best);
                        assert!(
                            best <= eps + delta + 1e-7,
                            "removed point {x} is {best} mm from every sample (ε {eps}, δ {delta}), ray {k} ({i}, {j}), cutter {}",
                            cutter.spec()
                        );
                    }
                }
                if k == 2 {
                    // Reference removal on the Z rays: the union of the sampled intervals.
                    ivs.sort_by(|x, y| x.0.total_cmp(&y.0));
                    let (mut len, mut end) = (0.0, f64::NEG_INFINITY);
                    for &(a, b, ..) in &ivs {
                        if b > end {
                            len += b - a.max(end);
                            end = b;
                        }
                    }
                    removed_ref += len * stock.ray_area(2);
                }
            }
        }
    }
    Figures {
        sub_moves: cut.sub_moves,
        bound: eps,
        delta,
        removed_sim: v0 - stock.volume(),
        removed_ref,
        worst_depth,
        worst_distance,
    }
}

fn cutters(rng: &mut Lcg) -> Vec<Cutter> {
    every_cutter_kind(rng, 3.0, 8.0, general_apt(8.0, 1.5, 14.0))
}

fn program(machine: Machine, source: AxisSource, mv: Move) -> Program {
    Program {
        moves: vec![Move {
            axis_source: source,
            tcp: machine.tcp,
            ..mv
        }],
        files: vec!["test".into()],
        machine,
        axis_source: source,
        ..Program::default()
    }
}

fn blank_move(kind: MoveKind, start: Pose, end: Pose, j0: Axes, j1: Axes) -> Move {
    Move {
        kind,
        start,
        end,
        start_joints: j0,
        end_joints: j1,
        feed: 500.0,
        feed_mode: FeedMode::PerMinute,
        spindle_rpm: 10000.0,
        spindle_dir: swarf_path::SpindleDir::Clockwise,
        tool: 1,
        file: 0,
        line: 1,
        axis_source: AxisSource::Machine,
        tcp: false,
        rotary_feed_combined: None,
    }
}

/// A random point where the tip cuts into the block's top.
fn tip_point(rng: &mut Lcg) -> Vec3 {
    Vec3::new(
        rng.range(-6.0, 6.0),
        rng.range(-6.0, 6.0),
        rng.range(-3.0, 0.5),
    )
}

/// A joint move of `machine` between random workpiece tips at random rotary positions.
fn machine_move(rng: &mut Lcg, name: &str) -> Program {
    let mach = Machine::from_name(name).unwrap();
    let rot = |rng: &mut Lcg| {
        let mut j = Axes::default();
        if name.contains("ac") {
            j.a = rng.range(-35.0, 35.0);
        } else {
            j.b = rng.range(-35.0, 35.0);
        }
        j.c = rng.range(-60.0, 60.0);
        j
    };
    let (r0, r1) = (rot(rng), rot(rng));
    let j0 = mach.joints_for_tip(tip_point(rng), &r0);
    let j1 = mach.joints_for_tip(tip_point(rng), &r1);
    let mv = blank_move(MoveKind::Linear, mach.pose(&j0), mach.pose(&j1), j0, j1);
    program(mach, AxisSource::Machine, mv)
}

/// A CL move: straight tip, or a helix about a random centre, axis slerped.
fn cl_move(rng: &mut Lcg, helix: bool) -> Program {
    let (a0, a1) = (rng.axis(40.0), rng.axis(40.0));
    let p0 = tip_point(rng);
    let (kind, p1) = if helix {
        let r = rng.range(2.0, 5.0);
        let sweep = rng.range(1.0, 4.0);
        let centre = Vec3::new(p0.x - r, p0.y, p0.z);
        let g = swarf_path::ArcGeom {
            center: centre,
            normal: Vec3::Z,
            sweep,
            start_radius: r,
            end_radius: r,
            helix: rng.range(-2.0, 1.0),
        };
        (MoveKind::Arc(g), g.point_at(p0, 1.0))
    } else {
        (MoveKind::Linear, tip_point(rng))
    };
    let mv = blank_move(
        kind,
        Pose { tip: p0, axis: a0 },
        Pose { tip: p1, axis: a1 },
        Axes::default(),
        Axes::default(),
    );
    program(Machine::three_axis(), AxisSource::Program, mv)
}

#[test]
fn five_axis_moves_match_sampled_instances() {
    let mut rng = Lcg(0x5a_2026_0005);
    let tol = 0.02;
    println!(
        "{:<28} {:<16} {:>6} {:>8} {:>8} {:>10} {:>10} {:>9} {:>9}",
        "cutter", "motion", "subs", "eps", "delta", "V sim", "V ref", "depth", "dist"
    );
    let mut cases = 0;
    for round in 0..4 {
        for cutter in cutters(&mut rng) {
            let (label, p) = match round {
                0 => ("table-ac (no TCP)", machine_move(&mut rng, "table-ac")),
                1 => ("head-bc-tcp", machine_move(&mut rng, "head-bc-tcp")),
                2 => ("CL straight", cl_move(&mut rng, false)),
                _ => ("CL helix", cl_move(&mut rng, true)),
            };
            assert!(p.is_five_axis(&p.moves[0]));
            let f = check(&p, &cutter, tol, 400);
            println!(
                "{:<28} {:<16} {:>6} {:>8.4} {:>8.4} {:>10.2} {:>10.2} {:>9.2e} {:>9.2e}",
                cutter.spec().chars().take(28).collect::<String>(),
                label,
                f.sub_moves,
                f.bound,
                f.delta,
                f.removed_sim,
                f.removed_ref,
                f.worst_depth,
                f.worst_distance
            );
            assert!(f.sub_moves > 1);
            cases += 1;
        }
    }
    assert_eq!(cases, 32);
}
