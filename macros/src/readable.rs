//! The formulas of `DERIVATIVES` in a normal form for reading: every product of sums
//! multiplied out (as long as it stays short), numeric factors collected into one coefficient,
//! like factors into one power, like terms into one, quotients by a product written once
//! (`2.0 * (0.5 * v[i])` reads `v[i]`, `1.0 / a * (1.0 / a)` reads `1.0 / a.powi(2)`). The
//! generated code keeps its own operations (whose rounding the tests pin); this form is only
//! printed, its coefficients rounded to 12 significant digits.

use crate::ir::Prec;

/// How many terms a product may multiply out to before its factors are kept whole.
const MAX_EXPANDED_TERMS: usize = 12;

/// A printed factor that the normal form does not look into (a leaf, a call, a branch, a
/// sum), with the strength of its syntax.
#[derive(Clone, Debug, PartialEq)]
pub struct Atom {
    pub text: String,
    pub prec: Prec,
}

/// `coefficient · Π atom^power`, atoms in first-seen order.
#[derive(Clone, Debug, PartialEq)]
struct Monomial {
    coefficient: f64,
    factors: Vec<(Atom, i32)>,
}

/// A sum of monomials, like terms combined.
#[derive(Clone, Debug, PartialEq)]
pub struct Poly(Vec<Monomial>);

impl Poly {
    pub fn number(c: f64) -> Self {
        Poly(vec![Monomial {
            coefficient: c,
            factors: Vec::new(),
        }])
        .tidy()
    }

    pub fn atom(text: String, prec: Prec) -> Self {
        Poly(vec![Monomial {
            coefficient: 1.0,
            factors: vec![(Atom { text, prec }, 1)],
        }])
    }

    /// Like terms combined, zero terms dropped.
    fn tidy(self) -> Self {
        let mut out: Vec<Monomial> = Vec::new();
        for m in self.0 {
            let mut factors: Vec<(Atom, i32)> = Vec::new();
            for (a, p) in m.factors {
                match factors.iter_mut().find(|(b, _)| *b == a) {
                    Some((_, q)) => *q += p,
                    None => factors.push((a, p)),
                }
            }
            factors.retain(|f| f.1 != 0);
            let same = |o: &Monomial| {
                o.factors.len() == factors.len() && o.factors.iter().all(|f| factors.contains(f))
            };
            match out.iter_mut().find(|o| same(o)) {
                Some(o) => o.coefficient += m.coefficient,
                None => out.push(Monomial {
                    coefficient: m.coefficient,
                    factors,
                }),
            }
        }
        out.retain(|m| m.coefficient != 0.0);
        Poly(out)
    }

    pub fn add(self, other: Poly) -> Self {
        Poly(self.0.into_iter().chain(other.0).collect()).tidy()
    }

    pub fn scale(self, c: f64) -> Self {
        Poly(
            self.0
                .into_iter()
                .map(|m| Monomial {
                    coefficient: m.coefficient * c,
                    ..m
                })
                .collect(),
        )
        .tidy()
    }

    /// The product, multiplied out while it stays short; otherwise a factor of several terms
    /// is kept whole, in parentheses.
    pub fn mul(self, other: Poly) -> Self {
        let (a, b) = if self.0.len() * other.0.len() > MAX_EXPANDED_TERMS {
            (self.whole(), other.whole())
        } else {
            (self, other)
        };
        let mut out = Vec::new();
        for x in &a.0 {
            for y in &b.0 {
                out.push(Monomial {
                    coefficient: x.coefficient * y.coefficient,
                    factors: x.factors.iter().chain(&y.factors).cloned().collect(),
                });
            }
        }
        Poly(out).tidy()
    }

    /// `self^n`: a monomial's powers multiplied, anything else kept whole.
    pub fn powi(self, n: i32) -> Self {
        match self.0.as_slice() {
            [m] if n >= 0 || m.coefficient != 0.0 => Poly(vec![Monomial {
                coefficient: m.coefficient.powi(n),
                factors: m.factors.iter().map(|(a, p)| (a.clone(), p * n)).collect(),
            }])
            .tidy(),
            [] if n > 0 => Poly::number(0.0),
            _ => {
                let (text, prec) = self.print();
                Poly(vec![Monomial {
                    coefficient: 1.0,
                    factors: vec![(Atom { text, prec }, n)],
                }])
            }
        }
    }

    /// `self / other`.
    pub fn div(self, other: Poly) -> Self {
        self.mul(other.powi(-1))
    }

    /// One term: a sum of several kept as one parenthesised factor.
    fn whole(self) -> Self {
        if self.0.len() <= 1 {
            return self;
        }
        let (text, prec) = self.print();
        Poly::atom(text, prec)
    }

    /// The text, and the strength of its syntax.
    pub fn print(&self) -> (String, Prec) {
        if self.0.is_empty() {
            return ("0.0".into(), Prec::Atom);
        }
        let mut out = String::new();
        let mut prec = Prec::Mul;
        for (k, m) in self.0.iter().enumerate() {
            let (text, negative, p) = monomial(m);
            if k == 0 {
                if negative {
                    out.push('-');
                    prec = Prec::Neg;
                } else {
                    prec = p;
                }
            } else {
                out.push_str(if negative { " - " } else { " + " });
                prec = Prec::Add;
            }
            out.push_str(&text);
        }
        if self.0.len() > 1 {
            prec = Prec::Add;
        }
        (out, prec)
    }
}

/// A factor at the strength `need`, parenthesised if it is weaker.
fn wrap(a: &Atom, need: Prec) -> String {
    if a.prec < need {
        format!("({})", a.text)
    } else {
        a.text.clone()
    }
}

/// A monomial's magnitude as text, whether it is negative, and its strength.
fn monomial(m: &Monomial) -> (String, bool, Prec) {
    let power = |a: &Atom, p: i32| {
        if p == 1 {
            wrap(a, Prec::Mul.right_operand())
        } else {
            format!("{}.powi({p})", wrap(a, Prec::Atom))
        }
    };
    let num: Vec<String> = m
        .factors
        .iter()
        .filter(|f| f.1 > 0)
        .map(|(a, p)| power(a, *p))
        .collect();
    let den: Vec<String> = m
        .factors
        .iter()
        .filter(|f| f.1 < 0)
        .map(|(a, p)| power(a, -p))
        .collect();
    let c = m.coefficient.abs();
    let mut parts = Vec::new();
    if c != 1.0 || num.is_empty() {
        parts.push(number(c));
    }
    parts.extend(num);
    let mut text = parts.join(" * ");
    let simple = m.factors.len() == 1 && m.factors[0].1 == 1 && c == 1.0;
    if !den.is_empty() {
        let d = if den.len() == 1 {
            den[0].clone()
        } else {
            format!("({})", den.join(" * "))
        };
        text = format!("{text} / {d}");
    }
    let prec = if simple {
        m.factors[0].0.prec.max(Prec::Mul)
    } else if parts_len(&text) {
        Prec::Mul
    } else {
        Prec::Atom
    };
    (text, m.coefficient < 0.0, prec)
}

/// Whether a monomial's text is a product or quotient (not a single factor).
fn parts_len(text: &str) -> bool {
    text.contains(" * ") || text.contains(" / ")
}

/// A coefficient, rounded to 12 significant digits for reading; a `std::f64::consts` value
/// by its name.
pub fn number(c: f64) -> String {
    if let Some(name) = crate::ir::constant_name(c) {
        return name.into();
    }
    let rounded: f64 = format!("{c:.11e}").parse().unwrap_or(c);
    format!("{rounded:?}")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn var(name: &str) -> Poly {
        Poly::atom(name.into(), Prec::Atom)
    }

    #[test]
    fn coefficients_powers_and_terms_are_collected() {
        let v = var("v[i]");
        let two_half = Poly::number(2.0).mul(Poly::number(0.5).mul(v.clone()));
        assert_eq!(two_half.print().0, "v[i]");
        let a = var("a");
        let inv = Poly::number(1.0).div(a.clone());
        assert_eq!(inv.clone().mul(inv).print().0, "1.0 / a.powi(2)");
        let s = a.clone().add(v.clone()).add(a.clone().scale(-1.0));
        assert_eq!(s.print().0, "v[i]");
        let square = a.clone().add(v.clone()).powi(2);
        assert_eq!(square.print().0, "(a + v[i]).powi(2)");
        let product = a.clone().add(Poly::number(1.0)).mul(v.clone().scale(-3.0));
        assert_eq!(product.print().0, "-3.0 * a * v[i] - 3.0 * v[i]");
        assert_eq!(Poly::number(0.1).mul(Poly::number(0.5)).print().0, "0.05");
        assert_eq!(a.div(v.scale(2.0)).print().0, "0.5 * a / v[i]");
    }
}
