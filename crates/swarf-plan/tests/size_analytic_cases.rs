//! The allowable size on surfaces whose answer is known in closed form, all written as NURBS,
//! to 1e-6 mm, with the certified solver (and the certificate checked).

mod common;
use common::sphere_step_file;

use std::f64::consts::FRAC_1_SQRT_2;

use swarf_geom::math::Vec3;
use swarf_plan::size::{
    allowable_certified, check_shank, shank_limited, AllowableSize, CertifiedOptions, Contact,
    CutterFamily, Limit, ShankCheck, ShankStatus,
};
use swarf_surface::PreparedSurface;
use swarf_surface::{io, CompoundSurface, NurbsSurface, Patch, Surface, Tolerances};

const EPS: f64 = 1e-6;

/// A NURBS with every control point mapped by `f` (weights kept).
fn mapped(s: &NurbsSurface, f: impl Fn(Vec3) -> Vec3) -> NurbsSurface {
    let (nu, nv) = s.net_size();
    let pts: Vec<Vec<Vec3>> = (0..nu)
        .map(|i| (0..nv).map(|j| f(s.control_point(i, j))).collect())
        .collect();
    let ws: Vec<Vec<f64>> = (0..nu)
        .map(|i| (0..nv).map(|j| s.weight(i, j)).collect())
        .collect();
    NurbsSurface::new(
        s.degree_u(),
        s.degree_v(),
        s.knots_u().to_vec(),
        s.knots_v().to_vec(),
        &pts,
        Some(&ws),
    )
    .unwrap()
}

/// A patch whose normal at its parameter centre points up (flipped if needed).
fn up(s: NurbsSurface) -> Patch {
    let mut p = Patch::new(Surface::Nurbs(s));
    let n = p
        .local(0.5, 0.5, &Tolerances::DEFAULT)
        .normal
        .vector()
        .unwrap();
    p.flipped = n.z < 0.0;
    p
}

fn bilinear(p00: Vec3, p10: Vec3, p01: Vec3, p11: Vec3) -> NurbsSurface {
    NurbsSurface::new(
        1,
        1,
        vec![0.0, 0.0, 1.0, 1.0],
        vec![0.0, 0.0, 1.0, 1.0],
        &[vec![p00, p01], vec![p10, p11]],
        None,
    )
    .unwrap()
}

fn solve(
    part: &CompoundSurface,
    family: CutterFamily,
    patch: usize,
    u: f64,
    v: f64,
) -> AllowableSize {
    let prep = PreparedSurface::new(part);
    let cc = part.points(&[(patch, u, v)]).unwrap()[0];
    let c = Contact::at(part, &cc, &Tolerances::DEFAULT).unwrap();
    let a = allowable_certified(&prep, &family, &c, &CertifiedOptions::DEFAULT);
    assert!(
        a.certified && a.gap <= 1e-6_f64.max(1e-6 * a.size),
        "not certified: {a:?}"
    );
    a
}

/// The lower hemisphere of radius 5 (four octants), concave from above.
fn bowl(r: f64) -> CompoundSurface {
    let oct = common::sphere_octant(r);
    let patches = (0..4)
        .map(|k| {
            let (s, c) = (f64::from(k) * std::f64::consts::FRAC_PI_2).sin_cos();
            up(mapped(&oct, |p| {
                Vec3::new(c * p.x - s * p.y, s * p.x + c * p.y, -p.z)
            }))
        })
        .collect();
    CompoundSurface::new(patches)
}

#[test]
fn inside_a_concave_sphere_the_ball_is_its_radius() {
    let part = bowl(5.0);
    for &(k, u, v) in &[(0, 0.5, 0.5), (1, 0.2, 0.7), (2, 0.9, 0.1), (3, 0.5, 0.95)] {
        let a = solve(&part, CutterFamily::ball(), k, u, v);
        assert!((a.size - 5.0).abs() < EPS, "{a:?}");
        assert_eq!(a.limit, Some(Limit::Gouge), "curvature-governed");
    }
}

#[test]
fn inside_a_concave_cylinder_the_ball_is_its_radius() {
    // A trough along x: the quarter cylinder turned so that its axis is horizontal.
    let q = common::quarter_cylinder(4.0, 10.0);
    let a = up(mapped(&q, |p| Vec3::new(p.z, p.x, -p.y)));
    let b = up(mapped(&q, |p| Vec3::new(p.z, -p.x, -p.y)));
    let part = CompoundSurface::new(vec![a, b]);
    for &(k, u, v) in &[(0, 0.3, 0.5), (1, 0.6, 0.1), (0, 0.95, 0.9)] {
        let r = solve(&part, CutterFamily::ball(), k, u, v);
        assert!((r.size - 4.0).abs() < EPS, "{r:?}");
    }
}

#[test]
fn inside_a_concave_torus_the_ball_is_its_tube_radius() {
    // The lower half of the tube (inner equator → bottom → outer equator), a quarter turn.
    let (big, r, h) = (10.0, 3.0, FRAC_1_SQRT_2);
    let profile = [
        (big - r, 0.0, 1.0),
        (big - r, -r, h),
        (big, -r, 1.0),
        (big + r, -r, h),
        (big + r, 0.0, 1.0),
    ];
    let s = common::revolved(&profile, vec![0.0, 0.0, 0.0, 0.5, 0.5, 1.0, 1.0, 1.0], 2);
    let part = CompoundSurface::new(vec![up(s)]);
    for &(u, v) in &[(0.5, 0.5), (0.2, 0.3), (0.8, 0.7), (0.5, 0.9)] {
        let a = solve(&part, CutterFamily::ball(), 0, u, v);
        assert!((a.size - r).abs() < EPS, "{a:?}");
    }
}

fn floor_and_wall(d: f64, h: f64) -> CompoundSurface {
    let floor = bilinear(
        Vec3::new(-d, -d, 0.0),
        Vec3::new(d, -d, 0.0),
        Vec3::new(-d, d, 0.0),
        Vec3::new(d, d, 0.0),
    );
    let wall = bilinear(
        Vec3::new(d, -d, 0.0),
        Vec3::new(d, d, 0.0),
        Vec3::new(d, -d, h),
        Vec3::new(d, d, h),
    );
    let mut w = Patch::new(Surface::Nurbs(wall));
    let n = w
        .local(0.5, 0.5, &Tolerances::DEFAULT)
        .normal
        .vector()
        .unwrap();
    w.flipped = n.x > 0.0; // the cutter comes from −x
    CompoundSurface::new(vec![up(floor), w])
}

#[test]
fn floor_next_to_a_wall_flat_and_bull_nose_and_tapered() {
    let part = floor_and_wall(10.0, 8.0);
    // CC at the floor's centre (0, 0, 0): the wall is 10 mm away.
    let a = solve(&part, CutterFamily::flat(), 0, 0.5, 0.5);
    assert!((a.size - 10.0).abs() < EPS, "{a:?}");
    assert_eq!(a.limit, Some(Limit::Interference));
    assert!((a.limit_point.unwrap().x - 10.0).abs() < 1e-9);
    // CC at x = 5: 5 mm.
    let a = solve(&part, CutterFamily::flat(), 0, 0.75, 0.3);
    assert!((a.size - 5.0).abs() < EPS, "{a:?}");
    // Bull-nose r = 2: R + r = 10.
    let f = CutterFamily::bull(2.0).unwrap();
    let a = solve(&part, f, 0, 0.5, 0.5);
    assert!((f.nominal_radius(a.size) - 10.0).abs() < EPS, "{a:?}");
    // Tapered flat end mill (3°): the wall's top edge limits, R = 10 − 8·tan 3°.
    let f = CutterFamily::apt(0.0, 3.0, 0.0).unwrap();
    let a = solve(&part, f, 0, 0.5, 0.5);
    let want = 10.0 - 8.0 * 3f64.to_radians().tan();
    assert!((a.size - want).abs() < EPS, "{} vs {want}", a.size);
    assert!((a.limit_point.unwrap().z - 8.0).abs() < 1e-6);
}

#[test]
fn shank_above_the_flutes_is_checked_against_the_wall() {
    // Flat end mill of R = 10 at the floor's centre, the wall 8 mm high at x = 10.
    let part = floor_and_wall(10.0, 8.0);
    let prep = PreparedSurface::new(&part);
    let cc = part.points(&[(0, 0.5, 0.5)]).unwrap()[0];
    let c = Contact::at(&part, &cc, &Tolerances::DEFAULT).unwrap();
    let f = CutterFamily::flat();
    let a = allowable_certified(&prep, &f, &c, &CertifiedOptions::DEFAULT);
    let model = CertifiedOptions::DEFAULT.model;
    // A thinner shank (Ø10) above 5 mm of flutes clears the wall.
    let thin = ShankCheck {
        diameter: Some(10.0),
        ..ShankCheck::new(5.0)
    };
    assert_eq!(
        check_shank(&prep, &f, &c, a.size, &thin, &model),
        ShankStatus::Free
    );
    // A fatter one (Ø24) reaches 2 mm into the wall above z = 5.
    let fat = ShankCheck {
        diameter: Some(24.0),
        ..ShankCheck::new(5.0)
    };
    match check_shank(&prep, &f, &c, a.size, &fat, &model) {
        ShankStatus::Interferes { point, depth } => {
            assert!((point.x - 10.0).abs() < 1e-9 && point.z > 5.0, "{point:?}");
            assert!(depth > 0.0 && depth <= 2.0 + 1e-9, "{depth}");
        }
        other => panic!("expected interference, got {other:?}"),
    }
    // Flutes longer than the wall: free whatever the shank.
    let long = ShankCheck {
        diameter: Some(24.0),
        ..ShankCheck::new(9.0)
    };
    assert_eq!(
        check_shank(&prep, &f, &c, a.size, &long, &model),
        ShankStatus::Free
    );
}

#[test]
fn shank_lowers_the_size_until_it_clears_the_wall() {
    // A bare sphere of radius L tangent to the floor's centre, the wall 8 mm high at x = 10:
    // the sphere meets the wall's top edge first, at L = (8² + 10²)/(2·8) = 10.25. Its shank
    // (radius L above 5 mm of flutes) meets the wall as soon as L > 10, so the size is 10.
    let part = floor_and_wall(10.0, 8.0);
    let prep = PreparedSurface::new(&part);
    let cc = part.points(&[(0, 0.5, 0.5)]).unwrap()[0];
    let c = Contact::at(&part, &cc, &Tolerances::DEFAULT).unwrap();
    let f = CutterFamily::ball();
    let a = allowable_certified(&prep, &f, &c, &CertifiedOptions::DEFAULT);
    assert!((a.size - 10.25).abs() < EPS, "{a:?}");
    let model = CertifiedOptions::DEFAULT.model;
    let (b, st) = shank_limited(&prep, &f, &c, a, &ShankCheck::new(5.0), &model);
    assert!((b.size - 10.0).abs() < 1e-6 + model.contact, "{b:?}");
    assert_eq!(b.limit, Some(Limit::Interference));
    let p = b.limit_point.unwrap();
    assert!(
        (p.x - 10.0).abs() < 1e-9 && p.z >= 5.0 && p.z <= 8.0,
        "{p:?}"
    );
    assert!(matches!(st, ShankStatus::Limits { cutting_size, .. } if cutting_size == a.size));
    // Free at the answer, not just above it.
    assert_eq!(
        check_shank(&prep, &f, &c, b.size, &ShankCheck::new(5.0), &model),
        ShankStatus::Free
    );
    // Flutes longer than the wall: the sphere's own size stands.
    let (b, st) = shank_limited(&prep, &f, &c, a, &ShankCheck::new(9.0), &model);
    assert_eq!(b, a);
    assert_eq!(st, ShankStatus::Free);
}

#[test]
fn v_groove_between_two_patches() {
    // Two 45° flanks meeting at the line x = 0, z = 0: the ball tangent at distance s from
    // the crease along a flank has radius s; at the crease nothing fits.
    let a = bilinear(
        Vec3::new(-5.0, -5.0, 5.0),
        Vec3::new(0.0, -5.0, 0.0),
        Vec3::new(-5.0, 5.0, 5.0),
        Vec3::new(0.0, 5.0, 0.0),
    );
    let b = bilinear(
        Vec3::new(0.0, -5.0, 0.0),
        Vec3::new(5.0, -5.0, 5.0),
        Vec3::new(0.0, 5.0, 0.0),
        Vec3::new(5.0, 5.0, 5.0),
    );
    let part = CompoundSurface::new(vec![up(a), up(b)]);
    for &u in &[0.2, 0.5, 0.9] {
        let s = (1.0 - u) * 5.0 * 2f64.sqrt();
        let r = solve(&part, CutterFamily::ball(), 0, u, 0.4);
        assert!((r.size - s).abs() < EPS, "u = {u}: {} vs {s}", r.size);
        assert_eq!(r.limit, Some(Limit::Interference));
    }
    let r = solve(&part, CutterFamily::ball(), 0, 1.0, 0.4);
    assert!(r.size < 2e-3, "at the crease: {r:?}");
    assert_eq!(r.limit, Some(Limit::Gouge));
}

#[test]
fn fillet_between_floor_and_wall() {
    // Floor x ∈ [−10, 0], a concave fillet of radius 2 (centre (0, ·, 2)), wall x = 2 up to 10.
    let floor = bilinear(
        Vec3::new(-10.0, -5.0, 0.0),
        Vec3::new(0.0, -5.0, 0.0),
        Vec3::new(-10.0, 5.0, 0.0),
        Vec3::new(0.0, 5.0, 0.0),
    );
    let q = common::quarter_cylinder(2.0, 10.0);
    // Quarter arc from +x to +y at height z ↦ (x', y', z') = (y, z − 5, 2 − x):
    // from (0, ·, 0) to (2, ·, 2) around (0, ·, 2).
    let fillet = mapped(&q, |p| Vec3::new(p.y, p.z - 5.0, 2.0 - p.x));
    let wall = bilinear(
        Vec3::new(2.0, -5.0, 2.0),
        Vec3::new(2.0, -5.0, 10.0),
        Vec3::new(2.0, 5.0, 2.0),
        Vec3::new(2.0, 5.0, 10.0),
    );
    let mut w = Patch::new(Surface::Nurbs(wall));
    let n = w
        .local(0.5, 0.5, &Tolerances::DEFAULT)
        .normal
        .vector()
        .unwrap();
    w.flipped = n.x > 0.0;
    let mut fl = Patch::new(Surface::Nurbs(fillet));
    let n = fl
        .local(0.5, 0.5, &Tolerances::DEFAULT)
        .normal
        .vector()
        .unwrap();
    fl.flipped = n.dot(Vec3::new(-1.0, 0.0, 1.0)) < 0.0;
    let part = CompoundSurface::new(vec![up(floor), fl, w]);
    // On the fillet: its radius.
    for &u in &[0.1, 0.5, 0.8] {
        let r = solve(&part, CutterFamily::ball(), 1, u, 0.5);
        assert!((r.size - 2.0).abs() < EPS, "{r:?}");
    }
    // On the floor at x = −a: a + 2 (the ball touches the wall).
    for &u in &[0.3, 0.7] {
        let a = 10.0 * (1.0 - u);
        let r = solve(&part, CutterFamily::ball(), 0, u, 0.5);
        assert!(
            (r.size - (a + 2.0)).abs() < EPS,
            "{} vs {}",
            r.size,
            a + 2.0
        );
        assert_eq!(r.limit, Some(Limit::Interference));
    }
}

#[test]
fn convex_surfaces_are_unbounded() {
    let dome = CompoundSurface::new(vec![up(common::sphere_octant(5.0))]);
    let hump = CompoundSurface::new(vec![up(mapped(
        &common::quarter_cylinder(4.0, 10.0),
        |p| Vec3::new(p.z, p.x, p.y),
    ))]);
    for part in [&dome, &hump] {
        for f in [
            CutterFamily::ball(),
            CutterFamily::ball_with_side(),
            CutterFamily::flat(),
            CutterFamily::bull(1.0).unwrap(),
        ] {
            let a = solve(part, f, 0, 0.3, 0.4);
            assert_eq!(a.size, f64::INFINITY, "{f:?}: {a:?}");
            assert_eq!(a.limit, None);
        }
    }
}

#[test]
fn step_sphere_concave_inside_is_five_convex_outside_unbounded() {
    let mut part = io::read_file(&sphere_step_file()).unwrap();
    let prep = PreparedSurface::new(&part);
    let outside = part.grid(7);
    let tol = Tolerances::DEFAULT;
    let opts = CertifiedOptions::DEFAULT;
    // Outside (as read): convex, unbounded wherever the normal points up.
    for cc in &outside {
        let Some(c) = Contact::at(&part, cc, &tol) else {
            continue;
        };
        if c.normal.z <= 0.0 {
            continue;
        }
        let a = allowable_certified(&prep, &CutterFamily::ball(), &c, &opts);
        assert_eq!(a.size, f64::INFINITY, "{cc:?}: {a:?}");
    }
    // Inside (flipped): 5 wherever the cutter can come from above.
    part.flip_all();
    let prep = PreparedSurface::new(&part);
    let mut checked = 0;
    for cc in &part.grid(7) {
        let Some(c) = Contact::at(&part, cc, &tol) else {
            continue;
        };
        if c.normal.z <= 0.1 {
            continue;
        }
        let a = allowable_certified(&prep, &CutterFamily::ball(), &c, &opts);
        assert!((a.size - 5.0).abs() < EPS && a.certified, "{cc:?}: {a:?}");
        // The sphere is closed: the shank above the ball must hit its upper half.
        let s = check_shank(
            &prep,
            &CutterFamily::ball(),
            &c,
            a.size,
            &ShankCheck::new(5.0),
            &opts.model,
        );
        assert!(matches!(s, ShankStatus::Interferes { .. }), "{s:?}");
        checked += 1;
    }
    assert!(checked >= 10);
}
