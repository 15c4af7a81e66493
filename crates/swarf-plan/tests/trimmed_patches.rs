//! Trimmed patches through the whole planner, on a case known in closed form: a 20 × 20 mm
//! floor and a 10 mm high wall at x = 20 facing it, with a slot 10 mm wide (y ∈ [5, 15]) cut out
//! of the wall by its trim. At the floor's centre the wall no longer limits a flat end mill at
//! 10 mm but at the slot's edge, √(10² + 5²); the program check sees the edges, not the wall
//! that is gone; grid points, meshes, maps and areas leave the slot out. Then random trims
//! against brute force.

mod common;

use common::{sampled_min, Rng};
use swarf_geom::math::Vec3;
use swarf_path::load::{read_program_str, ReadOptions};
use swarf_path::Machine;
use swarf_plan::gouge::{check_program, GougeOptions, GougeSurface, SurfaceRef};
use swarf_plan::plot::{write_patch_maps, PlotOptions, OFF_PART_RGB};
use swarf_plan::size::{
    allowable_certified, allowable_map, allowable_pso, grid_cell_areas, AreaRule, CertifiedOptions,
    Contact, CutterFamily, Limit, MapOptions, PsoOptions,
};
use swarf_surface::PreparedSurface;
use swarf_surface::{
    tessellate, CcPointError, CompoundSurface, NurbsSurface, ParametricSurface, Patch, Surface,
    Tolerances, Trim,
};

const TOL: Tolerances = Tolerances::DEFAULT;

/// A planar bilinear patch with corners `o`, `o + du`, `o + dv`, `o + du + dv`; its normal is
/// `du × dv`.
fn plane(o: Vec3, du: Vec3, dv: Vec3) -> Patch {
    let pts = vec![vec![o, o + dv], vec![o + du, o + du + dv]];
    let k = vec![0.0, 0.0, 1.0, 1.0];
    Patch::new(Surface::Nurbs(
        NurbsSurface::new(1, 1, k.clone(), k, &pts, None).unwrap(),
    ))
}

/// The floor (patch 0) and the wall (patch 1: u along z, v along y, normal −x), the wall
/// trimmed by the slot when `slot`.
fn part(slot: bool) -> CompoundSurface {
    let floor = plane(Vec3::ZERO, Vec3::X * 20.0, Vec3::Y * 20.0);
    let mut wall = plane(Vec3::new(20.0, 0.0, 0.0), Vec3::Z * 10.0, Vec3::Y * 20.0);
    if slot {
        // The hole overhangs the wall's parameter box in u: the slot runs its full height.
        let hole = vec![[-0.1, 0.25], [1.1, 0.25], [1.1, 0.75], [-0.1, 0.75]];
        wall.trim = Some(Trim::new(&wall.surface.domain(), None, vec![hole]).unwrap());
    }
    CompoundSurface::new(vec![floor, wall])
}

fn centre_contact(part: &CompoundSurface) -> Contact {
    let cc = part.points(&[(0, 0.5, 0.5)]).unwrap()[0];
    Contact::at(part, &cc, &TOL).unwrap()
}

#[test]
fn the_slot_raises_the_allowable_cutter_to_its_edges() {
    let opts = CertifiedOptions::DEFAULT;
    let (whole, slotted) = (part(false), part(true));
    let edge = 125f64.sqrt();
    // Flat end mill: the wall at 10 mm, the slot's edges at √125.
    let a = allowable_certified(
        &PreparedSurface::new(&whole),
        &CutterFamily::flat(),
        &centre_contact(&whole),
        &opts,
    );
    assert!((a.size - 10.0).abs() < 1e-6 && a.certified, "{a:?}");
    let prep = PreparedSurface::new(&slotted);
    let c = centre_contact(&slotted);
    let a = allowable_certified(&prep, &CutterFamily::flat(), &c, &opts);
    // The trim is honoured to its resolution, on the conservative side.
    let res = 20.0 * Trim::RELATIVE_RESOLUTION * 2f64.sqrt();
    assert!(
        a.size <= edge + 1e-6 && a.size >= edge - res - 1e-6,
        "{a:?}"
    );
    assert!(a.certified, "{a:?}");
    assert_eq!(a.limit, Some(Limit::Interference));
    let p = a.limit_point.unwrap();
    assert!((p.x - 20.0).abs() < 1e-9 && ((p.y - 5.0).abs() < 1e-5 || (p.y - 15.0).abs() < 1e-5));
    // A ball: the sphere reaches the top of the slot's edge, (20, 5, 10): R = 225/20.
    let a = allowable_certified(&prep, &CutterFamily::ball(), &c, &opts);
    assert!((a.size - 11.25).abs() < 1e-5, "{a:?}");
    // The swarm only ever evaluates points on the part, so it cannot go below the edge.
    let s = allowable_pso(&slotted, &CutterFamily::flat(), &c, &PsoOptions::default());
    assert!(s.size >= edge - 1e-9 && s.size < edge + 0.05, "{s:?}");
}

#[test]
fn grid_mesh_areas_and_maps_leave_the_slot_out() {
    let slotted = part(true);
    let n = 21;
    let grid = slotted.grid(n);
    let lattice = slotted.lattice(n);
    assert_eq!(lattice.len(), 2 * n * n);
    // Wall grid points with v strictly inside (0.25, 0.75) are off: 9 columns of 21.
    let off = lattice.iter().filter(|(_, on)| !on).count();
    assert!((9 * n..=11 * n).contains(&off), "{off}");
    assert_eq!(grid.len(), 2 * n * n - off);
    assert!(grid
        .iter()
        .all(|c| slotted.patches[c.patch].on_part(c.u, c.v)));
    // An explicit point in the slot is refused.
    assert!(matches!(
        slotted.points(&[(1, 0.5, 0.5)]),
        Err(CcPointError::OffPart { patch: 1, .. })
    ));
    // Areas: the floor 400 mm², the wall what is left of it (100 mm²) less the slivers of the
    // slot-side cells whose grid points are off (at most a cell column each side).
    let areas = grid_cell_areas(&slotted, n, AreaRule::DEFAULT);
    assert_eq!(areas.len(), grid.len());
    let floor: f64 = areas[..n * n].iter().sum();
    let wall: f64 = areas[n * n..].iter().sum();
    assert!((floor - 400.0).abs() < 1e-9, "{floor}");
    let column = 10.0 * 20.0 / (n - 1) as f64;
    assert!(
        wall <= 100.0 + 1e-9 && wall >= 100.0 - 2.0 * column,
        "{wall}"
    );
    // The mesh keeps no triangle over the slot.
    let m = tessellate(&slotted, n, &TOL);
    for (t, &k) in m.mesh.triangles.iter().zip(&m.triangle_patch) {
        if k == 1 {
            let y = t.map(|i| m.mesh.vertices[i as usize].y);
            assert!(y.iter().all(|&y| y <= 5.0 + 1e-9) || y.iter().all(|&y| y >= 15.0 - 1e-9));
        }
    }
    let wall_tris = m.triangle_patch.iter().filter(|&&k| k == 1).count();
    assert!(wall_tris < 2 * (n - 1) * (n - 1) * 6 / 10, "{wall_tris}");
    // The maps draw the slot in the off-part colour.
    let map = allowable_map(
        &slotted,
        &CutterFamily::flat(),
        &grid,
        &MapOptions::default(),
    );
    assert_eq!(map.points.len(), grid.len());
    let dir = swarf_testdata::scratch_dir("trim-maps");
    let paths = write_patch_maps(&slotted, &map, n, &dir, &PlotOptions::default()).unwrap();
    let decoder = png::Decoder::new(std::io::BufReader::new(
        std::fs::File::open(&paths[1]).unwrap(),
    ));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    let off_pixels = buf[..info.buffer_size()]
        .chunks(3)
        .filter(|p| *p == OFF_PART_RGB)
        .count();
    assert!(off_pixels > 100, "{off_pixels}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn the_program_check_sees_the_slot_edges_not_the_wall() {
    // A flat end mill of radius 10.5 along the floor's centre line, y from 8 to 12: the whole
    // wall would be 0.5 mm inside it; the slot leaves its edges, inside only while
    // √(10² + (y − 5)²) < 10.5, i.e. for y < 8.2016 (and y > 11.7984 at the other edge).
    let cutter = swarf_tool::spec::parse("flat:d=21").unwrap();
    let program = read_program_str(
        "G0 X10 Y8 Z20\nG1 Z0 F100\nG1 Y12\n",
        "t.ngc",
        Machine::three_axis(),
        &ReadOptions::default(),
    )
    .unwrap();
    let check = |slot: bool| {
        let s = GougeSurface::new(&PreparedSurface::new(&part(slot)));
        check_program(
            &s,
            &program,
            &swarf_tool::ToolSet::single(cutter.clone()),
            &GougeOptions::DEFAULT,
        )
        .unwrap()
    };
    let whole = check(false);
    let along: Vec<_> = whole
        .violations
        .iter()
        .filter(|v| v.move_index == 2)
        .collect();
    assert_eq!(along.len(), 1, "{:#?}", whole.violations);
    assert!((along[0].depth - 0.5).abs() <= GougeOptions::DEFAULT.gap(0.5));
    let slotted = check(true);
    let along: Vec<_> = slotted
        .violations
        .iter()
        .filter(|v| v.move_index == 2)
        .collect();
    assert_eq!(along.len(), 2, "{:#?}", slotted.violations);
    let depth = 10.5 - 109f64.sqrt();
    let s_edge = (5.0 + 10.25f64.sqrt() - 8.0) / 4.0;
    let res = GougeOptions::DEFAULT.resolution / 4.0;
    for (v, (s0, s1)) in along.iter().zip([(0.0, s_edge), (1.0 - s_edge, 1.0)]) {
        assert_eq!(v.surface, SurfaceRef::Patch(1));
        assert!(
            (v.depth - depth).abs() <= GougeOptions::DEFAULT.gap(depth),
            "{v:?}"
        );
        assert!((v.s_start - s0).abs() <= res + 1e-9, "{v:?}");
        assert!((v.s_end - s1).abs() <= res + 1e-9, "{v:?}");
        assert!(
            (v.point.y - 5.0).abs() < 1e-6 || (v.point.y - 15.0).abs() < 1e-6,
            "{v:?}"
        );
    }
}

/// A bicubic height field over `[ox, ox + 10] × [oy, oy + 10]` with random heights, trimmed by
/// a random star-shaped outer loop and a round hole.
fn random_trimmed_patch(rng: &mut Rng, ox: f64, oy: f64) -> Patch {
    let knots = vec![0.0, 0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0, 1.0];
    let pts: Vec<Vec<Vec3>> = (0..5)
        .map(|i| {
            (0..5)
                .map(|j| Vec3::new(ox + 2.5 * i as f64, oy + 2.5 * j as f64, 6.0 * rng.f()))
                .collect()
        })
        .collect();
    let mut p = Patch::new(Surface::Nurbs(
        NurbsSurface::new(3, 3, knots.clone(), knots, &pts, None).unwrap(),
    ));
    let outer: Vec<[f64; 2]> = (0..24)
        .map(|k| {
            let a = k as f64 / 24.0 * std::f64::consts::TAU;
            let r = 0.35 + 0.15 * rng.f();
            [0.5 + r * a.cos(), 0.5 + r * a.sin()]
        })
        .collect();
    let (hx, hy, hr) = (
        0.4 + 0.2 * rng.f(),
        0.4 + 0.2 * rng.f(),
        0.05 + 0.1 * rng.f(),
    );
    let hole: Vec<[f64; 2]> = (0..32)
        .map(|k| {
            let a = k as f64 / 32.0 * std::f64::consts::TAU;
            [hx + hr * a.cos(), hy + hr * a.sin()]
        })
        .collect();
    p.trim = Some(Trim::new(&p.surface.domain(), Some(outer), vec![hole]).unwrap());
    p
}

/// Distance in parameters from `(u, v)` to the nearest trim loop.
fn distance_to_loops(trim: &Trim, u: f64, v: f64) -> f64 {
    let mut best = f64::INFINITY;
    for l in trim.loops() {
        for e in 0..l.len() {
            let (a, b) = (l[e], l[(e + 1) % l.len()]);
            let d = [b[0] - a[0], b[1] - a[1]];
            let t = (((u - a[0]) * d[0] + (v - a[1]) * d[1]) / (d[0] * d[0] + d[1] * d[1]))
                .clamp(0.0, 1.0);
            best = best.min((u - a[0] - t * d[0]).hypot(v - a[1] - t * d[1]));
        }
    }
    best
}

/// The patch and parameters of the surface point nearest `p` (dense samples, then Gauss–Newton),
/// and the distance left.
fn project(part: &CompoundSurface, p: Vec3) -> (usize, f64, f64, f64) {
    let mut best = (0, 0.0, 0.0, f64::INFINITY);
    for (k, patch) in part.patches.iter().enumerate() {
        let d = patch.surface.domain();
        for i in 0..=100 {
            for j in 0..=100 {
                let (u, v) = (d.u_at(i as f64 / 100.0), d.v_at(j as f64 / 100.0));
                let dist = (patch.surface.point(u, v) - p).length();
                if dist < best.3 {
                    best = (k, u, v, dist);
                }
            }
        }
    }
    let (k, mut u, mut v, _) = best;
    let s = &part.patches[k].surface;
    let d = s.domain();
    for _ in 0..30 {
        let g = s.derivs(u, v);
        let r = p - g.point;
        let (a, b, c) = (g.su.dot(g.su), g.su.dot(g.sv), g.sv.dot(g.sv));
        let (x, y) = (g.su.dot(r), g.sv.dot(r));
        let det = a * c - b * b;
        u = (u + (c * x - b * y) / det).clamp(d.u[0], d.u[1]);
        v = (v + (a * y - b * x) / det).clamp(d.v[0], d.v[1]);
    }
    (k, u, v, (s.point(u, v) - p).length())
}

#[test]
fn certified_matches_dense_sampling_on_random_trimmed_surfaces() {
    let mut rng = Rng(20_261_121);
    let families = [
        CutterFamily::ball(),
        CutterFamily::flat(),
        CutterFamily::bull(1.0).unwrap(),
    ];
    let opts = CertifiedOptions::DEFAULT;
    let (mut compared, mut changed, mut certified, mut missed) = (0, 0, 0, 0);
    for _ in 0..3 {
        let patches: Vec<Patch> = [(0.0, 0.0), (10.0, 0.0), (0.0, 10.0), (10.0, 10.0)]
            .into_iter()
            .map(|(ox, oy)| random_trimmed_patch(&mut rng, ox, oy))
            .collect();
        let part = CompoundSurface::new(patches.clone());
        let untrimmed = CompoundSurface::new(
            patches
                .into_iter()
                .map(|mut p| {
                    p.trim = None;
                    p
                })
                .collect(),
        );
        let (prep, prep_whole) = (
            PreparedSurface::new(&part),
            PreparedSurface::new(&untrimmed),
        );
        let grid = part.grid(9);
        for _ in 0..5 {
            let cc = grid[(rng.f() * grid.len() as f64) as usize];
            let mut c = Contact::at(&part, &cc, &TOL).unwrap();
            if c.normal.z < 0.0 {
                c.normal = -c.normal;
                c.curvature = None;
            }
            for f in &families {
                let a = allowable_certified(&prep, f, &c, &opts);
                let (b, spread) = sampled_min(&part, f, &c, &opts, 200);
                if b.is_infinite() {
                    assert!(a.size >= 1e5, "{f:?}: brute ∞, certified {a:?}");
                    continue;
                }
                let t = opts.tol_abs.max(opts.tol_rel * b);
                assert!(a.size <= b + t, "{f:?}: certified {} > sampled {b}", a.size);
                if a.size < b - spread - t {
                    // Below every sample: then its witness must be a point of the part that
                    // sampling missed (a flat bottom's plane cuts the surface along a curve
                    // where the imaginary size jumps), with that very size.
                    let lp = a.limit_point.unwrap();
                    let (k, u, v, miss) = project(&part, lp);
                    let trim = part.patches[k].trim.as_ref().unwrap();
                    // The trim is honoured to its resolution: a piece that small still crossing
                    // the boundary counts as on the part, so its corners may lie that far out.
                    let out = if part.patches[k].on_part(u, v) {
                        0.0
                    } else {
                        distance_to_loops(trim, u, v)
                    };
                    assert!(
                        miss < 1e-9 && out <= 2f64.sqrt() * trim.resolution(),
                        "{f:?}: certified {} < sampled {b} − {spread}, witness {lp:?} \
                         is {miss} mm off patch {k} at ({u}, {v}), {out} outside its trim",
                        a.size
                    );
                    let reg = f.regime(&c, &opts.model);
                    let r = f.imaginary(&c, &reg, lp, &opts.model);
                    assert!(
                        (r - a.size).abs() <= t,
                        "{f:?}: witness size {r} vs {}",
                        a.size
                    );
                    missed += 1;
                }
                let w = allowable_certified(&prep_whole, f, &c, &opts);
                assert!(w.size <= a.size + t, "trimming can only raise the size");
                changed += usize::from(w.size < a.size - 1e-6);
                compared += 1;
                certified += usize::from(a.certified);
            }
        }
    }
    eprintln!(
        "{compared} comparisons, {changed} raised by the trim, {certified} certified, \
         {missed} below the samples with a witness on the part"
    );
    assert!(compared >= 30 && changed >= 5, "{compared} / {changed}");
    assert!(certified * 10 >= compared * 9, "{certified}/{compared}");
}

#[test]
fn an_elementary_surface_is_trimmed_in_its_own_parameters() {
    // The same slot in a wall that is a STEP-style plane (parameters in mm: u along z, v along
    // y), and a quarter cylinder (parameters: angle, height) with a window in its angle range.
    use swarf_geom::Frame;
    use swarf_surface::{CylindricalSurface, ParamBox, PlaneSurface};
    let frame = Frame::from_axis_and_x(Vec3::new(20.0, 0.0, 0.0), -Vec3::X, Vec3::Z);
    let dom = ParamBox {
        u: [0.0, 10.0],
        v: [0.0, 20.0],
    };
    let mut wall = Patch::new(Surface::Plane(PlaneSurface::new(frame, dom)));
    assert!((wall.surface.point(10.0, 20.0) - Vec3::new(20.0, 20.0, 10.0)).length() < 1e-12);
    let hole = vec![[-1.0, 5.0], [11.0, 5.0], [11.0, 15.0], [-1.0, 15.0]];
    wall.trim = Some(Trim::new(&dom, None, vec![hole]).unwrap());
    let floor = plane(Vec3::ZERO, Vec3::X * 20.0, Vec3::Y * 20.0);
    let part = CompoundSurface::new(vec![floor, wall]);
    let c = centre_contact(&part);
    let prep = PreparedSurface::new(&part);
    let opts = CertifiedOptions::DEFAULT;
    let a = allowable_certified(&prep, &CutterFamily::flat(), &c, &opts);
    assert!(
        (a.size - 125f64.sqrt()).abs() < 1e-5 && a.certified,
        "{a:?}"
    );

    // A concave half cylinder of radius 10 around the line y = 0, z = 10 (its inside faces
    // the cutter), its bottom (angles within 45° of straight down) cut away, over a floor at
    // z = −2: whole, its bottom line 2 mm over the floor stops a ball at radius 1; cut, the
    // ball reaches the cut edges (y, z) = (±10 sin 45°, 10 − 10 cos 45°).
    let cyl = CylindricalSurface::new(
        Frame::from_axis_and_x(Vec3::new(0.0, 0.0, 10.0), Vec3::X, -Vec3::Z),
        10.0,
        ParamBox {
            u: [-std::f64::consts::FRAC_PI_2, std::f64::consts::FRAC_PI_2],
            v: [0.0, 40.0],
        },
    )
    .unwrap();
    let mut trough = Patch::new(Surface::Cylinder(cyl));
    let q = std::f64::consts::FRAC_PI_4;
    let window = vec![[-q, -1.0], [q, -1.0], [q, 41.0], [-q, 41.0]];
    trough.trim = Some(Trim::new(&trough.surface.domain(), None, vec![window]).unwrap());
    let floor = plane(Vec3::new(0.0, -10.0, -2.0), Vec3::X * 40.0, Vec3::Y * 20.0);
    let part = CompoundSurface::new(vec![floor, trough.clone()]);
    let cc = part.points(&[(0, 0.5, 0.5)]).unwrap()[0];
    let c = Contact::at(&part, &cc, &TOL).unwrap();
    assert!((c.point - Vec3::new(20.0, 0.0, -2.0)).length() < 1e-12);
    // Ball centre (20, 0, R − 2) through the edge (y, z) = (10 sin q, 10 − 10 cos q):
    // y² + (z + 2 − R)² = R².
    let (ey, ez) = (10.0 * q.sin(), 12.0 - 10.0 * q.cos());
    let want = (ey * ey + ez * ez) / (2.0 * ez);
    let a = allowable_certified(
        &PreparedSurface::new(&part),
        &CutterFamily::ball(),
        &c,
        &opts,
    );
    assert!(
        (a.size - want).abs() < 1e-5 && a.certified,
        "{a:?} vs {want}"
    );
    trough.trim = None;
    let whole = CompoundSurface::new(vec![part.patches[0].clone(), trough]);
    let a = allowable_certified(
        &PreparedSurface::new(&whole),
        &CutterFamily::ball(),
        &c,
        &opts,
    );
    assert!((a.size - 1.0).abs() < 1e-5, "{a:?}");
}
