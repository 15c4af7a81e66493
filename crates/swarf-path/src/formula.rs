//! Parameter arithmetic: the formulas of Heidenhain `Q1 = …` blocks and the operands of `FN`
//! functions, and the expressions of Sinumerik programs (`R1=R2*SIN(30)`, `IF R1>=5 …`),
//! evaluated as they are read (angles in degrees, as the controls take them).
//!
//! Grammar: `sum := product (('+' | '-') product)*`, `product := power (('*' | '/' | DIV |
//! LEN | ANG) power)*`, `power := unary ('^' unary)?`, `unary := ('+' | '-')* primary`,
//! `primary := number | Q-parameter | PI | '(' sum ')' | function primary`. `LEN` (FN 8) is
//! `√(a² + b²)`, `ANG` (FN 13) the angle of `(a, b)` in degrees; a function's argument may be
//! written without parentheses, as `FN 5: Q1 = SQRT +Q2` writes it.

use crate::heidenhain::lexer::{qref, QRef};

/// Evaluation failure: the byte offset in the text and what is wrong.
#[derive(Debug, PartialEq)]
pub(crate) struct ExprError {
    pub(crate) at: usize,
    pub(crate) message: String,
    pub(crate) expected: &'static str,
}

type R = Result<f64, ExprError>;

/// Deepest nesting of parentheses and unary signs (bounds the recursion on hostile input).
const MAX_DEPTH: usize = 200;

struct Parser<'a, 'q> {
    s: &'a [u8],
    pos: usize,
    depth: usize,
    /// The value of a name (a parameter or variable), `None` for an unknown one.
    var: &'q dyn Fn(&str) -> Option<f64>,
    /// Sinumerik rules: comparisons and `AND OR XOR NOT` (true is 1), `DIV` and `MOD` of
    /// integers, `MIN MAX ATAN2 POT TRUNC ROUND`, names with `_` and `$`.
    siemens: bool,
}

/// Evaluates the whole of `text` (upper case, Heidenhain) with parameters read through `q`.
pub(crate) fn eval(text: &str, q: &dyn Fn(QRef) -> f64) -> R {
    eval_with(text, &|name| qref(name).map(q), false)
}

/// Evaluates the whole of a Sinumerik expression (upper case) with names read through `var`.
pub(crate) fn eval_siemens(text: &str, var: &dyn Fn(&str) -> Option<f64>) -> R {
    eval_with(text, var, true)
}

fn eval_with(text: &str, var: &dyn Fn(&str) -> Option<f64>, siemens: bool) -> R {
    let mut p = Parser {
        s: text.as_bytes(),
        pos: 0,
        depth: 0,
        var,
        siemens,
    };
    let v = if siemens { p.logic()? } else { p.sum()? };
    p.skip_ws();
    if p.pos < p.s.len() {
        return Err(p.err(
            "unexpected text after the formula",
            "an operator or the end",
        ));
    }
    finite(v, 0)
}

fn finite(v: f64, at: usize) -> R {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(ExprError {
            at,
            message: "the formula's value is not a finite number".into(),
            expected: "a finite value",
        })
    }
}

impl Parser<'_, '_> {
    fn err(&self, message: &str, expected: &'static str) -> ExprError {
        ExprError {
            at: self.pos,
            message: message.into(),
            expected,
        }
    }

    fn skip_ws(&mut self) {
        while self.s.get(self.pos).is_some_and(u8::is_ascii_whitespace) {
            self.pos += 1;
        }
    }

    /// Consumes `kw` (a keyword or an operator) when it comes next.
    fn eat(&mut self, kw: &str) -> bool {
        self.skip_ws();
        let k = kw.as_bytes();
        if self.s[self.pos..].starts_with(k) {
            // A keyword must not run into a longer name (`SIN` in `SINX`).
            let after = self.s.get(self.pos + k.len());
            let continues = |c: &u8| c.is_ascii_alphabetic() || (self.siemens && *c == b'_');
            if k[0].is_ascii_alphabetic() && after.is_some_and(continues) {
                return false;
            }
            self.pos += k.len();
            true
        } else {
            false
        }
    }

    fn enter(&mut self) -> Result<(), ExprError> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(self.err("the formula nests too deeply", "a simpler formula"));
        }
        Ok(())
    }

    /// `OR`, `XOR`, `AND`, `NOT` over comparisons (Sinumerik).
    fn logic(&mut self) -> R {
        let mut v = self.conjunction()?;
        loop {
            if self.eat("OR") {
                let b = self.conjunction()?;
                v = f64::from(v != 0.0 || b != 0.0);
            } else if self.eat("XOR") {
                let b = self.conjunction()?;
                v = f64::from((v != 0.0) != (b != 0.0));
            } else {
                return Ok(v);
            }
        }
    }

    fn conjunction(&mut self) -> R {
        let mut v = self.negation()?;
        while self.eat("AND") {
            let b = self.negation()?;
            v = f64::from(v != 0.0 && b != 0.0);
        }
        Ok(v)
    }

    fn negation(&mut self) -> R {
        if self.eat("NOT") {
            self.enter()?;
            let v = self.negation()?;
            self.depth -= 1;
            return Ok(f64::from(v == 0.0));
        }
        self.comparison()
    }

    fn comparison(&mut self) -> R {
        let a = self.sum()?;
        for (op, f) in [
            ("==", (|a, b| a == b) as fn(f64, f64) -> bool),
            ("<>", |a, b| a != b),
            ("<=", |a, b| a <= b),
            (">=", |a, b| a >= b),
            ("<", |a, b| a < b),
            (">", |a, b| a > b),
        ] {
            if self.eat(op) {
                let b = self.sum()?;
                return Ok(f64::from(f(a, b)));
            }
        }
        Ok(a)
    }

    fn sum(&mut self) -> R {
        let mut v = self.product()?;
        loop {
            if self.eat("+") {
                v += self.product()?;
            } else if self.eat("-") {
                v -= self.product()?;
            } else {
                return Ok(v);
            }
        }
    }

    fn product(&mut self) -> R {
        let mut v = self.power()?;
        loop {
            self.skip_ws();
            let at = self.pos;
            if self.eat("*") {
                v *= self.power()?;
            } else if self.eat("/") || self.eat("DIV") || (self.siemens && self.eat("MOD")) {
                let op = self.s[at];
                let d = self.power()?;
                if d == 0.0 {
                    return Err(ExprError {
                        at,
                        message: "division by zero".into(),
                        expected: "a non-zero divisor",
                    });
                }
                v = match op {
                    b'D' if self.siemens => (v / d).trunc(),
                    b'M' => v % d,
                    _ => v / d,
                };
            } else if self.eat("LEN") {
                v = v.hypot(self.power()?);
            } else if self.eat("ANG") {
                v = self.power()?.atan2(v).to_degrees();
            } else {
                return Ok(v);
            }
        }
    }

    fn power(&mut self) -> R {
        let b = self.unary()?;
        if self.eat("^") {
            let e = self.unary()?;
            return finite(b.powf(e), self.pos);
        }
        Ok(b)
    }

    fn unary(&mut self) -> R {
        self.enter()?;
        let v = if self.eat("-") {
            -self.unary()?
        } else if self.eat("+") {
            self.unary()?
        } else {
            self.primary()?
        };
        self.depth -= 1;
        Ok(v)
    }

    fn primary(&mut self) -> R {
        self.skip_ws();
        let start = self.pos;
        if self.eat("(") {
            self.enter()?;
            let v = if self.siemens {
                self.logic()?
            } else {
                self.sum()?
            };
            self.depth -= 1;
            if !self.eat(")") {
                return Err(self.err("missing closing parenthesis", "')'"));
            }
            return Ok(v);
        }
        // A name the program defined comes before a function of the same letters (a
        // Sinumerik `DEF REAL SQ1`, `MAX_Z`).
        let name_len = self.s[start..]
            .iter()
            .take_while(|c| c.is_ascii_alphanumeric() || (self.siemens && b"_$".contains(c)))
            .count();
        if name_len > 0 && self.s[start].is_ascii_alphabetic() {
            let name = std::str::from_utf8(&self.s[start..start + name_len]).unwrap_or("");
            if let Some(v) = (self.var)(name) {
                self.pos = start + name_len;
                return Ok(v);
            }
        }
        if self.eat("PI") {
            return Ok(std::f64::consts::PI);
        }
        type F = fn(f64) -> Option<f64>;
        const FUNCTIONS: [(&str, F); 15] = [
            ("SQRT", |x| (x >= 0.0).then(|| x.sqrt())),
            ("SQ", |x| Some(x * x)),
            ("SIN", |x| Some(x.to_radians().sin())),
            ("COS", |x| Some(x.to_radians().cos())),
            ("TAN", |x| Some(x.to_radians().tan())),
            ("ASIN", |x| {
                (-1.0..=1.0).contains(&x).then(|| x.asin().to_degrees())
            }),
            ("ACOS", |x| {
                (-1.0..=1.0).contains(&x).then(|| x.acos().to_degrees())
            }),
            ("ATAN", |x| Some(x.atan().to_degrees())),
            ("LN", |x| (x > 0.0).then(|| x.ln())),
            ("LOG", |x| (x > 0.0).then(|| x.log10())),
            ("EXP", |x| Some(x.exp())),
            ("ABS", |x| Some(x.abs())),
            ("INT", |x| Some(x.trunc())),
            ("FRAC", |x| Some(x.fract())),
            ("SGN", |x| {
                Some(if x > 0.0 {
                    1.0
                } else if x < 0.0 {
                    -1.0
                } else {
                    0.0
                })
            }),
        ];
        // (Before the one-argument functions: `ATAN` would take `ATAN2`'s name.)
        if self.siemens {
            type F2 = fn(f64, f64) -> f64;
            const TWO: [(&str, F2); 3] = [
                ("ATAN2", |y, x| y.atan2(x).to_degrees()),
                ("MIN", f64::min),
                ("MAX", f64::max),
            ];
            for (name, f) in TWO {
                if self.eat(name) {
                    if !self.eat("(") {
                        return Err(self.err("expected '(' after the function", "'('"));
                    }
                    self.enter()?;
                    let a = self.logic()?;
                    if !self.eat(",") {
                        return Err(self.err("expected ',' between the arguments", "','"));
                    }
                    let b = self.logic()?;
                    self.depth -= 1;
                    if !self.eat(")") {
                        return Err(self.err("missing closing parenthesis", "')'"));
                    }
                    return finite(f(a, b), start);
                }
            }
        }
        for (name, f) in FUNCTIONS {
            if self.eat(name) {
                let arg = self.unary()?;
                return match f(arg) {
                    Some(v) => finite(v, start),
                    None => Err(ExprError {
                        at: start,
                        message: format!("{name} of {arg} is not defined"),
                        expected: "an argument in the function's domain",
                    }),
                };
            }
        }
        if self.eat("NEG") {
            return Ok(-self.unary()?);
        }
        if self.siemens {
            type F1 = fn(f64) -> f64;
            const ONE: [(&str, F1); 3] = [
                ("POT", |x| x * x),
                ("TRUNC", f64::trunc),
                ("ROUND", f64::round),
            ];
            for (name, f) in ONE {
                if self.eat(name) {
                    let arg = self.unary()?;
                    return finite(f(arg), start);
                }
            }
        }
        // A number or a parameter.
        let len = self.s[start..]
            .iter()
            .take_while(|c| {
                c.is_ascii_alphanumeric() || **c == b'.' || (self.siemens && b"_$".contains(c))
            })
            .count();
        let tok = std::str::from_utf8(&self.s[start..start + len]).unwrap_or("");
        if let Some(v) = (self.var)(tok) {
            self.pos += len;
            return Ok(v);
        }
        if let Some(v) = crate::heidenhain::lexer::number(tok) {
            self.pos += len;
            return Ok(v);
        }
        Err(self.err(
            "expected a number, a parameter, a function or '('",
            "a value",
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ev(s: &str) -> R {
        eval(s, &|q: QRef| {
            f64::from(q.index) * if q.negate { -1.0 } else { 1.0 }
        })
    }

    #[test]
    fn formulas_follow_precedence_and_degrees() {
        assert_eq!(ev("1 + 2 * 3").unwrap(), 7.0);
        assert_eq!(ev("(1 + 2) * 3").unwrap(), 9.0);
        assert_eq!(ev("+Q2 + +Q3").unwrap(), 5.0);
        assert_eq!(ev("-Q2 - -3").unwrap(), 1.0);
        assert_eq!(ev("Q8 DIV Q2").unwrap(), 4.0);
        assert_eq!(ev("2 ^ 3").unwrap(), 8.0);
        assert!((ev("SIN 30").unwrap() - 0.5).abs() < 1e-15);
        assert!((ev("COS(60) * 2").unwrap() - 1.0).abs() < 1e-15);
        assert_eq!(ev("SQRT +Q16").unwrap(), 4.0);
        assert_eq!(ev("Q3 LEN Q4").unwrap(), 5.0);
        assert!((ev("+1 ANG +1").unwrap() - 45.0).abs() < 1e-12);
        assert_eq!(ev("ABS -2.5").unwrap(), 2.5);
        assert!((ev("PI").unwrap() - std::f64::consts::PI).abs() < 1e-15);
    }

    #[test]
    fn siemens_two_argument_functions_are_not_taken_for_one_argument_ones() {
        let sv = |s: &str| eval_siemens(s, &|n| n.starts_with('R').then_some(1.0)).unwrap();
        assert!((sv("ATAN2(1,1)") - 45.0).abs() < 1e-12);
        assert!((sv("5*ATAN2(R2,-1)") - 675.0).abs() < 1e-12);
        assert!((sv("ATAN(1)") - 45.0).abs() < 1e-12);
        assert_eq!(sv("MIN(3,R1)"), 1.0);
    }

    #[test]
    fn bad_formulas_are_errors_with_a_place() {
        assert_eq!(ev("1 / 0").unwrap_err().message, "division by zero");
        assert!(ev("SQRT -1").is_err());
        assert!(ev("(1 + 2").is_err());
        assert_eq!(ev("1 + ").unwrap_err().at, 4);
        assert!(ev("1 2").is_err());
        assert!(ev("10 ^ 400").is_err());
        assert!(ev(&"(".repeat(10_000)).is_err());
        assert!(ev(&"-".repeat(10_000)).is_err());
    }
}
