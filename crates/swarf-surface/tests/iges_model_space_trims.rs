//! IGES trims from model-space curves: a 142 without a parameter-space curve (BPTR = 0, or one
//! of a kind not evaluated) is trimmed through its model-space curve (CPTR), mapped onto the
//! 128. Checked on plates built in code and against the parameter-space curve of a real file.

mod common;
use common::data;

use common::iges::{circle126, plate_with, polygon, Iges, PLATE};
use swarf_surface::io::iges;
use swarf_surface::{CompoundSurface, ParametricSurface, ReadNote, Trim};

/// The notes as text.
fn notes(s: &CompoundSurface) -> Vec<String> {
    s.notes.iter().map(ToString::to_string).collect()
}

/// The `by` of the only `Trimmed` note.
fn trimmed_by(s: &CompoundSurface) -> String {
    let by: Vec<&String> = s
        .notes
        .iter()
        .filter_map(|n| match n {
            ReadNote::Trimmed { by, .. } => Some(by),
            _ => None,
        })
        .collect();
    assert_eq!(by.len(), 1, "{:?}", notes(s));
    by[0].clone()
}

/// Share of the centres of an `n × n` grid of cells over the patch's box on the part.
fn on_part_fraction(t: &Trim, s: &impl ParametricSurface, n: usize) -> f64 {
    let d = s.domain();
    let mut on = 0;
    for i in 0..n {
        for j in 0..n {
            let u = d.u_at((i as f64 + 0.5) / n as f64);
            let v = d.v_at((j as f64 + 0.5) / n as f64);
            on += usize::from(t.contains(u, v));
        }
    }
    on as f64 / (n * n) as f64
}

/// Shoelace area of a closed polygon, its coordinates taken from `origin`.
fn area(l: &[[f64; 2]], origin: [f64; 2]) -> f64 {
    let p = |k: usize| {
        let q = l[k % l.len()];
        [q[0] - origin[0], q[1] - origin[1]]
    };
    0.5 * (0..l.len())
        .map(|k| {
            let (a, b) = (p(k), p(k + 1));
            a[0] * b[1] - a[1] * b[0]
        })
        .sum::<f64>()
        .abs()
}

/// Distance from `q` to the closed polygon `l`.
fn polygon_distance(q: [f64; 2], l: &[[f64; 2]]) -> f64 {
    (0..l.len())
        .map(|k| {
            let (a, b) = (l[k], l[(k + 1) % l.len()]);
            let d = [b[0] - a[0], b[1] - a[1]];
            let len2 = d[0] * d[0] + d[1] * d[1];
            let s = if len2 > 0.0 {
                (((q[0] - a[0]) * d[0] + (q[1] - a[1]) * d[1]) / len2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            (q[0] - a[0] - s * d[0]).hypot(q[1] - a[1] - s * d[1])
        })
        .fold(f64::INFINITY, f64::min)
}

/// The 10 mm plate (in the file's units) with a hole of radius 2 around (5, 5) whose 142 has
/// only a model-space curve, built by `curve` (returns its DE); and its BPTR (0, or a curve
/// the reader does not evaluate, built by `bptr`).
fn plate_with_model_hole(
    units: &str,
    curve: impl FnOnce(&mut Iges) -> usize,
    unsupported_bptr: bool,
) -> String {
    let mut f = Iges::default();
    let plate = f.add(128, PLATE);
    let c = curve(&mut f);
    let b = if unsupported_bptr {
        f.add(104, "1.,0.,1.,0.,0.,-0.04,0.,0.5,0.7,0.5,0.7")
    } else {
        0
    };
    let c142 = f.add(142, &format!("0,{plate},{b},{c},2"));
    f.add(144, &format!("{plate},0,1,0,{c142}"));
    f.text(units)
}

#[test]
fn a_circular_hole_given_only_in_model_space() {
    let (r, centre) = (2.0, [5.0, 5.0]);
    let arc = |f: &mut Iges| {
        // A full circle about the origin, moved to the centre by a 124.
        let shift = f.add(124, "1.,0.,0.,5.,0.,1.,0.,5.,0.,0.,1.,0.");
        f.add_moved(100, "0.,0.,0.,2.,0.,2.,0.", shift)
    };
    let spline = move |f: &mut Iges| circle126(f, centre, r);
    type Build = Box<dyn Fn(&mut Iges) -> usize>;
    let kinds: [(&str, Build); 2] = [("100 arc", Box::new(arc)), ("126 circle", Box::new(spline))];
    for (kind, build) in &kinds {
        for (units, scale) in [("2,2HMM", 1.0), ("1,2HIN", 25.4)] {
            for unsupported_bptr in [false, true] {
                let what = format!("{kind}, {units}, unsupported BPTR {unsupported_bptr}");
                let text = plate_with_model_hole(units, build, unsupported_bptr);
                let s = iges::parse(&text).unwrap_or_else(|e| panic!("{what}: {e}\n{text}"));
                let p = &s.patches[0];
                let t = p
                    .trim
                    .as_ref()
                    .unwrap_or_else(|| panic!("{what}: {:?}", notes(&s)));
                let by = trimmed_by(&s);
                assert!(
                    by.starts_with("IGES 144 at D")
                        && by.ends_with("mapped from its model-space curve"),
                    "{by}"
                );
                // The hole's centre is cut away, the corners kept.
                assert!(!t.contains(0.5, 0.5), "{what}");
                assert!(t.contains(0.05, 0.05) && t.contains(0.95, 0.5), "{what}");
                assert!(!t.contains(0.5, 0.69) && t.contains(0.5, 0.71), "{what}");
                // The loop's points, mapped back through the surface, lie on the circle; the
                // middles of its chords within the chord tolerance (1e-3 mm) of it.
                let l = &t.holes()[0];
                let (c, rr) = (
                    swarf_geom::math::Vec3::new(centre[0], centre[1], 0.0) * scale,
                    r * scale,
                );
                let mut worst_point = 0.0f64;
                let mut worst_chord = 0.0f64;
                for k in 0..l.len() {
                    let (a, b) = (l[k], l[(k + 1) % l.len()]);
                    let x = p.surface.point(a[0], a[1]);
                    worst_point = worst_point.max(((x - c).length() - rr).abs());
                    let m = p.surface.point(0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]));
                    worst_chord = worst_chord.max(((m - c).length() - rr).abs());
                }
                println!(
                    "{what}: {} points, off the circle {worst_point:e} mm, chords {worst_chord:e} mm",
                    l.len()
                );
                assert!(worst_point < 1e-9 * scale, "{what}: {worst_point}");
                assert!(worst_chord < 1e-3, "{what}: {worst_chord}");
                // The on-part share of a grid of cells: 1 − πr²/area, within the cells the
                // circle crosses (its length over the cell size, times √2, of n² cells).
                let n = 200;
                let frac = on_part_fraction(t, &p.surface, n);
                let want = 1.0 - std::f64::consts::PI * r * r / 100.0;
                let cells = std::f64::consts::TAU * (r / 10.0) * n as f64 * 2f64.sqrt();
                println!("{what}: on-part share {frac}, expected {want}");
                assert!(
                    (frac - want).abs() <= cells / (n * n) as f64,
                    "{what}: {frac} {want}"
                );
            }
        }
    }
}

#[test]
fn a_square_hole_of_model_space_lines() {
    // A 102 of 110 lines in model space (mm on the 10 mm plate): the square [3, 7]².
    let text = plate_with_model_hole(
        "2,2HMM",
        |f| polygon(f, &[[3.0, 3.0], [7.0, 3.0], [7.0, 7.0], [3.0, 7.0]]),
        false,
    );
    let s = iges::parse(&text).unwrap();
    let t = s.patches[0].trim.as_ref().unwrap();
    let frac = on_part_fraction(t, &s.patches[0].surface, 100);
    assert!((frac - 0.84).abs() < 1e-12, "{frac}");
    for q in &t.holes()[0] {
        let (du, dv) = ((q[0] - 0.5).abs(), (q[1] - 0.5).abs());
        assert!((du.max(dv) - 0.2).abs() < 1e-9, "{q:?}");
    }
}

#[test]
fn a_model_space_curve_off_the_surface_is_refused_with_the_distance() {
    // The circle 1 mm above the plate (ZT = 1).
    let text = plate_with(|f, plate| {
        let arc = f.add(100, "1.,5.,5.,7.,5.,7.,5.");
        f.add(142, &format!("0,{plate},0,{arc},2"))
    });
    let s = iges::parse(&text).unwrap();
    assert!(s.patches[0].trim.is_none());
    let n = notes(&s);
    println!("{n:?}");
    assert_eq!(n.len(), 1);
    assert!(
        n[0].starts_with("patch 0 is trimmed by IGES 144 at D7 (model-space curve of 142 at D5 lies 1.000e0 mm off the surface"),
        "{n:?}"
    );
    assert!(n[0].ends_with("the trim is not honoured (the whole patch is used)"));
    // Within the tolerance (1e-4 of the patch's size + 0.01 mm) it is taken.
    let text = plate_with(|f, plate| {
        let arc = f.add(100, "0.005,5.,5.,7.,5.,7.,5.");
        f.add(142, &format!("0,{plate},0,{arc},2"))
    });
    let s = iges::parse(&text).unwrap();
    assert!(s.patches[0].trim.is_some(), "{:?}", notes(&s));
    // 0.03 mm off: refused, unless the G section's minimum resolution (field 19) is coarser
    // (0.05; the writer's 1e-6 replaced, same width).
    let text = plate_with(|f, plate| {
        let arc = f.add(100, "0.03,5.,5.,7.,5.,7.,5.");
        f.add(142, &format!("0,{plate},0,{arc},2"))
    });
    let s = iges::parse(&text).unwrap();
    assert!(s.patches[0].trim.is_none(), "{:?}", notes(&s));
    assert_eq!(text.matches(",1e-6,").count(), 1);
    let s = iges::parse(&text.replace(",1e-6,", ",0.05,")).unwrap();
    assert!(s.patches[0].trim.is_some(), "{:?}", notes(&s));
}

/// The real file, as written and with the BPTR of its 142 at D5 set to 0 (only the model-space
/// curve left).
fn occt_both() -> Option<(CompoundSurface, CompoundSurface)> {
    let text = std::fs::read_to_string(data("iges/occt_bug29356.igs")?).unwrap();
    let from = "142,0,3,7,25,3;";
    assert_eq!(text.matches(from).count(), 1);
    let line = text.lines().find(|l| l.starts_with(from)).unwrap();
    let edited = line.replacen(from, "142,0,3,0,25,3;", 1);
    assert_eq!(edited.len(), line.len());
    let model_only = text.replacen(line, &edited, 1);
    Some((
        iges::parse(&text).unwrap(),
        iges::parse(&model_only).unwrap(),
    ))
}

#[test]
fn occt_model_space_trim_agrees_with_the_parameter_space_one() {
    let Some((param, model)) = occt_both() else {
        return;
    };
    assert_eq!(param.patches.len(), 1);
    assert_eq!(model.patches.len(), 1);
    let by = trimmed_by(&model);
    println!("{:?}", notes(&model));
    assert_eq!(
        by,
        "IGES 144 at D1, the loop of the 142 at D5 mapped from its model-space curve"
    );
    let p = &param.patches[0];
    let (tp, tm) = (
        p.trim.as_ref().unwrap(),
        model.patches[0].trim.as_ref().unwrap(),
    );
    let (lp, lm) = (tp.outer().unwrap(), tm.outer().unwrap());
    println!(
        "loop points: parameter-space {}, model-space {}",
        lp.len(),
        lm.len()
    );
    let d = p.surface.domain();
    let (su, sv) = d.span();
    // `contains` on a 101 × 101 grid over the box.
    let n = 101;
    let (mut agree, mut worst) = (0, 0.0f64);
    let norm = |q: [f64; 2]| [(q[0] - d.u[0]) / su, (q[1] - d.v[0]) / sv];
    let lp_norm: Vec<[f64; 2]> = lp.iter().map(|&q| norm(q)).collect();
    for i in 0..n {
        for j in 0..n {
            let (u, v) = (
                d.u_at(i as f64 / (n - 1) as f64),
                d.v_at(j as f64 / (n - 1) as f64),
            );
            if tp.contains(u, v) == tm.contains(u, v) {
                agree += 1;
            } else {
                // Disagreements only near the boundary (in shares of the box's sides).
                worst = worst.max(polygon_distance(norm([u, v]), &lp_norm));
            }
        }
    }
    let share = agree as f64 / (n * n) as f64;
    println!(
        "grid agreement {share} ({} of {} differ), farthest disagreement from the boundary {worst:e} of the box",
        n * n - agree,
        n * n
    );
    assert!(share >= 0.995, "{share}");
    assert!(worst <= 1.0 / (n - 1) as f64, "{worst}");
    // The loops' areas (in parameters, from the box's corner).
    let (ap, am) = (area(lp, [d.u[0], d.v[0]]), area(lm, [d.u[0], d.v[0]]));
    let rel = (am - ap).abs() / ap;
    println!("loop areas: parameter-space {ap}, model-space {am}, relative difference {rel:e}");
    assert!(rel <= 5e-3, "{rel}");
    // The model-space loop on the surface follows the parameter-space one (both the CAD
    // system's fits of one curve, within its 1e-3 mm): S along each edge of the
    // parameter-space loop (cut in 16), against S at the model-space loop's points.
    let image: Vec<swarf_geom::math::Vec3> = (0..lp.len())
        .flat_map(|k| {
            let (a, b) = (lp[k], lp[(k + 1) % lp.len()]);
            (0..16).map(move |i| {
                let s = i as f64 / 16.0;
                [a[0] + (b[0] - a[0]) * s, a[1] + (b[1] - a[1]) * s]
            })
        })
        .map(|q| p.surface.point(q[0], q[1]))
        .collect();
    let mut far = 0.0f64;
    for q in lm {
        let x = p.surface.point(q[0], q[1]);
        let dist = (0..image.len())
            .map(|k| {
                let (a, b) = (image[k], image[(k + 1) % image.len()]);
                let e = b - a;
                let s = if e.length_squared() > 0.0 {
                    ((x - a).dot(e) / e.length_squared()).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                (x - a - e * s).length()
            })
            .fold(f64::INFINITY, f64::min);
        far = far.max(dist);
    }
    println!("model-space loop to the parameter-space loop on the surface: {far:e} mm");
    assert!(far < 1e-3, "{far}");
}
