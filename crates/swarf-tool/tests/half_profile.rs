//! `Cutter::half_profile`: the drawn outline of a tool, tip to shank end, on the axis at both
//! ends, the cutting part's radius up to the flutes and the shank's above.

use swarf_tool::Cutter;

#[test]
fn ball_end_mill_outline() {
    let c = Cutter::from_spec("ball:d=10,flute-length=20,shank=8,length=50").unwrap();
    let p = c.half_profile(100);
    assert_eq!(p.len(), 103);
    assert_eq!(p[0], (0.0, 0.0));
    assert_eq!(*p.last().unwrap(), (0.0, 50.0));
    // z = 2.5 (sample 5): on the ball, r = √(5² − 2.5²).
    let (r, z) = p[1 + 5];
    assert!((z - 2.5).abs() < 1e-12);
    assert!((r - (25.0f64 - 6.25).sqrt()).abs() < 1e-9, "{r}");
    // z = 10 (sample 20): the flutes, r = 5; z = 40 (sample 80): the shank, r = 4.
    assert!((p[1 + 20].0 - 5.0).abs() < 1e-9);
    assert!((p[1 + 80].0 - 4.0).abs() < 1e-9, "{:?}", p[1 + 80]);
}
