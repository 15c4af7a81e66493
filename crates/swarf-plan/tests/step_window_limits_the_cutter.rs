//! A window in a STEP face sets a certified allowable size: a floor z = 0 over [0, 20]² and,
//! 5 mm above it, a ceiling facing down with a window x ∈ [6, 14], y ∈ [7, 13] (the files are
//! written by swarf-surface's STEP trim tests). A flat end mill standing at the floor's centre
//! (10, 10) meets the ceiling at the window's nearer edges: R = 3; without the window, right
//! above it.

use swarf_plan::size::{allowable_certified, CertifiedOptions, Contact, CutterFamily, Limit};
use swarf_surface::io::step;
use swarf_surface::{PreparedSurface, Tolerances, Trim};

#[test]
fn a_trimmed_step_face_raises_the_allowable_cutter() {
    for (window, text) in [
        (true, include_str!("fixtures/ceiling_with_window.step")),
        (false, include_str!("fixtures/ceiling.step")),
    ] {
        let part = step::parse(text).unwrap();
        assert_eq!(part.patches.len(), 2);
        let cc = part.points(&[(0, 10.0, 10.0)]).unwrap()[0];
        let c = Contact::at(&part, &cc, &Tolerances::DEFAULT).unwrap();
        let prep = PreparedSurface::new(&part);
        let got = allowable_certified(&prep, &CutterFamily::flat(), &c, &CertifiedOptions::DEFAULT);
        println!("ceiling with window {window}: {got:?}");
        assert!(got.certified, "{got:?}");
        if window {
            let res = 20.0 * Trim::RELATIVE_RESOLUTION * 2f64.sqrt();
            assert!(
                got.size <= 3.0 + 1e-6 && got.size >= 3.0 - res - 1e-6,
                "{got:?}"
            );
            assert_eq!(got.limit, Some(Limit::Interference));
            let q = got.limit_point.unwrap();
            assert!(
                (q.z - 5.0).abs() < 1e-9 && ((q.y - 7.0).abs() < 1e-5 || (q.y - 13.0).abs() < 1e-5),
                "{q:?}"
            );
        } else {
            assert!(got.size < 1e-3, "{got:?}");
        }
    }
}
