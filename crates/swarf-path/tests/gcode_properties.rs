//! Property tests of the G-code reader: expressions evaluate like an independent reference
//! evaluator, incremental moves sum, and no input makes the reader panic.

use proptest::prelude::*;
use swarf_path::canon::Recorder;
use swarf_path::gcode::{read_gcode, GcodeOptions};
use swarf_path::{Canon, CanonSink, Warning};

/// An expression tree, printed as G-code and evaluated by a reference written here from the
/// RS274/NGC rules (left-associative binary operators in five precedence levels).
#[derive(Clone, Debug)]
enum E {
    Num(f64),
    Neg(Box<E>),
    Bin(Box<E>, &'static str, Box<E>),
    Fun(&'static str, Box<E>),
}

fn leaf() -> impl Strategy<Value = E> {
    (-1000i32..1000, 0u32..3).prop_map(|(m, k)| E::Num(f64::from(m) / 10f64.powi(k as i32)))
}

fn expr() -> impl Strategy<Value = E> {
    leaf().prop_recursive(5, 40, 3, |inner| {
        prop_oneof![
            (
                inner.clone(),
                prop::sample::select(vec![
                    "+", "-", "*", "/", "MOD", "**", "EQ", "NE", "GT", "GE", "LT", "LE", "AND",
                    "OR", "XOR"
                ]),
                inner.clone()
            )
                .prop_map(|(a, op, b)| E::Bin(Box::new(a), op, Box::new(b))),
            inner.clone().prop_map(|a| E::Neg(Box::new(a))),
            (
                prop::sample::select(vec!["ABS", "FIX", "FUP", "ROUND", "SIN", "COS"]),
                inner
            )
                .prop_map(|(f, a)| E::Fun(f, Box::new(a))),
        ]
    })
}

/// Prints a flat chain where possible so precedence matters: `[a op b]` for binary nodes whose
/// operands are printed with their own brackets only when needed.
fn print(e: &E) -> String {
    match e {
        E::Num(v) => format!("{v}"),
        E::Neg(a) => format!("-[{}]", print(a)),
        E::Bin(a, op, b) => format!("[{} {op} {}]", print(a), print(b)),
        E::Fun(f, a) => format!("{f}[{}]", print(a)),
    }
}

fn reference(e: &E) -> Option<f64> {
    Some(match e {
        E::Num(v) => *v,
        E::Neg(a) => -reference(a)?,
        E::Fun(f, a) => {
            let x = reference(a)?;
            match *f {
                "ABS" => x.abs(),
                "FIX" => x.floor(),
                "FUP" => x.ceil(),
                "ROUND" => x.round(),
                "SIN" => (x * std::f64::consts::PI / 180.0).sin(),
                _ => (x * std::f64::consts::PI / 180.0).cos(),
            }
        }
        E::Bin(a, op, b) => {
            let (x, y) = (reference(a)?, reference(b)?);
            let t = |c: bool| if c { 1.0 } else { 0.0 };
            match *op {
                "+" => x + y,
                "-" => x - y,
                "*" => x * y,
                "/" if y == 0.0 => return None,
                "/" => x / y,
                "MOD" if y == 0.0 => return None,
                "MOD" => {
                    // fmod (exact, as LinuxCNC computes it); `x − y·trunc(x/y)` loses digits
                    // once x/y is large.
                    let r = x % y;
                    if r < 0.0 {
                        r + y.abs()
                    } else {
                        r
                    }
                }
                "**" if x < 0.0 && y.fract() != 0.0 => return None,
                "**" => x.powf(y),
                "EQ" => t((x - y).abs() < 1e-4),
                "NE" => t((x - y).abs() >= 1e-4),
                "GT" => t(x > y),
                "GE" => t(x >= y),
                "LT" => t(x < y),
                "LE" => t(x <= y),
                "AND" => t(x != 0.0 && y != 0.0),
                "OR" => t(x != 0.0 || y != 0.0),
                _ => t((x != 0.0) != (y != 0.0)),
            }
        }
    })
}

/// Evaluates through the reader: `#1 = expr` then a move to X#1 in a mm program.
fn via_reader(src: &str) -> Result<f64, swarf_path::PathError> {
    // A value beyond the machine range (1e6 mm) is no coordinate: it is read divided by 2³²
    // as many times as it takes (exact: a power of two), and multiplied back.
    let mut last = None;
    for k in 0..=32 {
        let scaled = format!("#1{}", " / 4294967296".repeat(k));
        let mut rec = Recorder::default();
        match read_gcode(
            &format!("#1 = {src}\nG0 X[{scaled}]\n"),
            "p.ngc",
            &GcodeOptions::default(),
            &mut rec,
        ) {
            Ok(()) => {
                let x = rec
                    .events
                    .iter()
                    .find_map(|(_, e)| match e {
                        Canon::Traverse { end } => Some(end.x),
                        _ => None,
                    })
                    .unwrap();
                return Ok((0..k).fold(x, |x, _| x * 4294967296.0));
            }
            Err(e) if e.message.contains("machine range") => last = Some(e),
            Err(e) => return Err(e),
        }
    }
    Err(last.unwrap())
}

/// Binary chains without brackets, to test precedence: `a op b op c …`.
fn chain() -> impl Strategy<Value = (Vec<f64>, Vec<&'static str>)> {
    (2usize..7).prop_flat_map(|n| {
        (
            prop::collection::vec((1i32..50).prop_map(f64::from), n),
            prop::collection::vec(
                prop::sample::select(vec!["+", "-", "*", "/", "**", "LT", "EQ", "AND", "OR"]),
                n - 1,
            ),
        )
    })
}

/// Reference for a flat chain: precedence climbing written independently (shunting-yard).
fn chain_reference(nums: &[f64], ops: &[&str]) -> Option<f64> {
    fn prec(op: &str) -> u8 {
        match op {
            "**" => 6,
            "*" | "/" => 5,
            "+" | "-" => 4,
            "LT" | "EQ" => 3,
            _ => 2,
        }
    }
    fn apply(op: &str, x: f64, y: f64) -> Option<f64> {
        reference(&E::Bin(Box::new(E::Num(x)), leak(op), Box::new(E::Num(y))))
    }
    fn leak(op: &str) -> &'static str {
        ["+", "-", "*", "/", "**", "LT", "EQ", "AND", "OR"]
            .into_iter()
            .find(|o| *o == op)
            .unwrap()
    }
    let mut vals = vec![nums[0]];
    let mut stack: Vec<&str> = Vec::new();
    for (i, op) in ops.iter().enumerate() {
        while let Some(top) = stack.last() {
            if prec(top) >= prec(op) {
                let y = vals.pop()?;
                let x = vals.pop()?;
                vals.push(apply(stack.pop()?, x, y)?);
            } else {
                break;
            }
        }
        stack.push(op);
        vals.push(nums[i + 1]);
    }
    while let Some(op) = stack.pop() {
        let y = vals.pop()?;
        let x = vals.pop()?;
        vals.push(apply(op, x, y)?);
    }
    vals.pop()
}

struct Null;
impl CanonSink for Null {
    fn emit(&mut self, _: u32, _: &Canon<'_>) {}
    fn warn(&mut self, _: Warning) {}
}

/// True when the comparison cannot decide: a SIN/COS argument so large that one rounding in the
/// degree-to-radian conversion (about `|x|·π/180·2⁻⁵³`) moves the result by more than [`close`]
/// allows (the reader's `x.to_radians()` and the reference's `x·π/180` may round differently, and
/// neither value means anything), or a computed operand within rounding of a point where the
/// operation jumps (ROUND at halves, FIX/FUP and MOD at whole multiples, comparisons at equality,
/// EQ/NE at their 1e-4 threshold, the logic operators at zero): there the last bit decides, as
/// `ROUND[COS[-780]]`, exactly ½, shows. Literal operands are exact and always compared.
fn ill_conditioned(e: &E) -> bool {
    // Within rounding of the jump at `d`, for a computed value.
    let computed = |a: &E| !matches!(a, E::Num(_));
    let near =
        |computed: bool, x: f64, d: f64| computed && (x - d).abs() <= 1e-9 * x.abs().max(1.0);
    match e {
        E::Num(_) => false,
        E::Neg(a) => ill_conditioned(a),
        E::Fun(f, a) => {
            let x = reference(a);
            ill_conditioned(a)
                || x.is_some_and(|x| match *f {
                    "SIN" | "COS" => x.abs() > 1e6,
                    "ROUND" => near(computed(a), x, x.trunc() + 0.5 * x.signum()),
                    "FIX" | "FUP" => near(computed(a), x, x.round()),
                    _ => false,
                })
        }
        E::Bin(a, op, b) => {
            let (x, y) = (reference(a), reference(b));
            ill_conditioned(a)
                || ill_conditioned(b)
                || x.zip(y).is_some_and(|(x, y)| {
                    let (ca, cb) = (computed(a), computed(b));
                    match *op {
                        "EQ" | "NE" => near(true, (x - y).abs(), 1e-4),
                        "GT" | "GE" | "LT" | "LE" => near(ca || cb, x - y, 0.0),
                        "MOD" if y != 0.0 => near(true, x / y, (x / y).round()),
                        "AND" | "OR" | "XOR" => near(ca, x, 0.0) || near(cb, y, 0.0),
                        _ => false,
                    }
                })
        }
    }
}

fn close(a: f64, b: f64) -> bool {
    a == b || (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1.0) || (a.is_nan() && b.is_nan())
}

proptest! {
    #![proptest_config(swarf_testdata::proptest_config(400))]

    #[test]
    fn expressions_match_the_reference(e in expr()) {
        prop_assume!(!ill_conditioned(&e));
        let src = print(&e);
        match (reference(&e), via_reader(&src)) {
            (Some(want), Ok(got)) if want.is_finite() => prop_assert!(close(got, want), "{src}: got {got}, want {want}"),
            (Some(want), Err(err)) => prop_assert!(!want.is_finite(), "{src}: {err}"),
            (None, r) => prop_assert!(r.is_err(), "{src}: domain error expected, got {r:?}"),
            _ => {}
        }
    }

    #[test]
    fn unbracketed_chains_follow_linuxcnc_precedence((nums, ops) in chain()) {
        let mut src = String::from("[");
        for (i, n) in nums.iter().enumerate() {
            src += &format!("{n}");
            if i < ops.len() {
                src += &format!(" {} ", ops[i]);
            }
        }
        src += "]";
        match (chain_reference(&nums, &ops), via_reader(&src)) {
            (Some(want), Ok(got)) if want.is_finite() => prop_assert!(close(got, want), "{src}: got {got}, want {want}"),
            (Some(want), Err(err)) => prop_assert!(!want.is_finite(), "{src}: {err}"),
            (None, r) => prop_assert!(r.is_err(), "{src}: {r:?}"),
            _ => {}
        }
    }

    #[test]
    fn incremental_moves_sum(steps in prop::collection::vec((-1000i32..1000, -1000i32..1000, -1000i32..1000), 1..60), inch in any::<bool>()) {
        let mut src = String::from(if inch { "G20 G91 F10\n" } else { "G21 G91 F10\n" });
        let mut sum = [0i64; 3];
        for (x, y, z) in &steps {
            src += &format!("G1 X{} Y{} Z{}\n", f64::from(*x) / 100.0, f64::from(*y) / 100.0, f64::from(*z) / 100.0);
            sum[0] += i64::from(*x);
            sum[1] += i64::from(*y);
            sum[2] += i64::from(*z);
        }
        let mut rec = Recorder::default();
        read_gcode(&src, "p.ngc", &GcodeOptions::default(), &mut rec).unwrap();
        let last = rec.events.iter().rev().find_map(|(_, e)| match e { Canon::Feed { end } => Some(*end), _ => None }).unwrap();
        let scale = if inch { 25.4 } else { 1.0 };
        for (got, s) in [last.x, last.y, last.z].into_iter().zip(sum) {
            let want = s as f64 / 100.0 * scale;
            prop_assert!((got - want).abs() < 1e-9, "got {got}, want {want}");
        }
    }

    #[test]
    fn never_panics_on_random_bytes(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        let text = String::from_utf8_lossy(&bytes);
        let opts = GcodeOptions::default().with_max_loop_iterations(10_000);
        let _ = read_gcode(&text, "fuzz", &opts, &mut Null);
    }

    #[test]
    fn never_panics_on_gcode_like_text(words in prop::collection::vec(prop::sample::select(vec![
        "G0", "G1", "G2", "G3", "G17", "G18", "G19", "G20", "G21", "G90", "G91", "G81", "G83", "G73", "G85", "G89", "G98", "G99",
        "G28", "G30", "G53", "G54", "G92", "G92.1", "G10 L2 P1", "G10 L20 P0", "G43", "G49", "G93", "G94", "M3", "M5", "M6", "M98", "M99",
        "M2", "X1", "Y-2.5", "Z-1", "I1", "J-1", "K0.5", "R2", "R-2", "P2", "Q0.3", "L3", "F100", "S1000", "T2", "@1", "^45", "A90",
        "#1=", "#<a>=", "#1", "#<a>", "[", "]", "+", "*", "/", "\n", "\n", "\n", "o1 while [#1 LT 3]", "o1 endwhile", "o2 if [1]",
        "o2 else", "o2 endif", "o3 sub", "o3 endsub", "o3 call [1]", "o4 repeat [2]", "o4 endrepeat", "(c)", ";x", "%", "/", "O5", "N10",
    ]), 0..80)) {
        let text = words.join(" ");
        let opts = GcodeOptions::default().with_max_loop_iterations(10_000);
        let _ = read_gcode(&text, "fuzz", &opts, &mut Null);
    }
}
