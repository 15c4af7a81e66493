//! Stock sizes are checked before anything is allocated: a huge, non-finite or too finely
//! resolved stock is an error that says what was asked and what the limit is, never a panic
//! ("capacity overflow" from a ray count that wrapped) or an allocation failure.

use swarf_geom::math::{Vec3, MACHINE_RANGE_MM};
use swarf_stock::{StockError, TriDexel, MAX_RAYS};

#[test]
fn a_stock_beyond_the_machine_range_is_refused_by_name() {
    // `--stock box:0,0,-1e30,1,1,0`: rays along Z counted 4e30 and wrapped.
    let e =
        TriDexel::from_box(Vec3::new(0.0, 0.0, -1e30), Vec3::new(1.0, 1.0, 0.0), 0.25).unwrap_err();
    let msg = e.to_string();
    assert!(matches!(e, StockError::BadDimensions(_)), "{e:?}");
    assert!(
        msg.contains("1e30") && msg.contains("machine range"),
        "{msg}"
    );
    // Just inside the range it is the ray count that refuses it.
    let r = 0.5 * MACHINE_RANGE_MM;
    let e = TriDexel::from_box(Vec3::splat(-r), Vec3::splat(r), 0.25).unwrap_err();
    let StockError::TooManyRays { rays, limit, .. } = &e else {
        panic!("{e:?}")
    };
    assert_eq!(*limit, MAX_RAYS);
    assert!((rays / (3.0 * 4e6 * 4e6) - 1.0).abs() < 1e-9, "{rays}");
    let msg = e.to_string();
    assert!(
        msg.contains("4.800e13 rays") && msg.contains("coarser"),
        "{msg}"
    );
}

#[test]
fn counts_that_overflow_every_integer_are_errors_with_readable_numbers() {
    // 1e6 mm at 1e-12 mm: 1e18 cells a side, 3e36 rays — more than u64 holds.
    let e = TriDexel::from_box(Vec3::ZERO, Vec3::splat(1e6), 1e-12).unwrap_err();
    let msg = e.to_string();
    assert!(matches!(e, StockError::TooManyRays { .. }), "{e:?}");
    assert!(!msg.contains("18446744073709551615"), "{msg}");
    assert!(msg.contains("3.000e36 rays"), "{msg}");
}

#[test]
fn non_finite_stocks_and_resolutions_are_errors() {
    for (lo, hi) in [
        (Vec3::new(0.0, 0.0, f64::NEG_INFINITY), Vec3::ONE),
        (Vec3::new(0.0, f64::NAN, 0.0), Vec3::ONE),
        (Vec3::ZERO, Vec3::new(1.0, 1.0, f64::INFINITY)),
        (Vec3::new(f64::NAN, 0.0, 0.0), Vec3::new(f64::NAN, 1.0, 1.0)),
        (Vec3::ZERO, Vec3::new(1.0, 0.0, 1.0)),
    ] {
        let e = TriDexel::from_box(lo, hi, 0.25).unwrap_err();
        assert!(
            matches!(e, StockError::BadDimensions(_)),
            "{lo} {hi}: {e:?}"
        );
    }
    for h in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let e = TriDexel::from_box(Vec3::ZERO, Vec3::ONE, h).unwrap_err();
        assert!(matches!(e, StockError::BadResolution(_)), "{h}: {e:?}");
    }
}
