//! The integer side of the IR: loop variables, their ranges, index expressions and the
//! comparisons of conditions. Small `Copy + Hash` values, so that nodes holding them are
//! hash-consed like the others.

/// A loop variable: each loop or summing closure binds a new one.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct IndexVar(pub u32);

/// A constant whose value the macro does not know: a `usize` const item other than the
/// dimension (`M`), or an integer division of constants (`N / 2`). The generated code names it,
/// and the checks that need its value become `const` assertions.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct SymId(pub u32);

/// What a [`SymId`] stands for.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Sym {
    /// A `usize` const item in scope where the fn is, named as written.
    Named(proc_macro2::Ident),
    /// `⌊a / d⌋` with `a` free of loop variables and `d ≥ 1` a literal.
    Div(Affine, i64),
}

/// An integer index `scale·i + n·N + k·s + c` (`i` a loop variable, `N` the dimension, `s` a
/// [`Sym`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Affine {
    pub var: Option<IndexVar>,
    pub scale: i64,
    pub n: i64,
    pub sym: Option<SymId>,
    pub k: i64,
    pub c: i64,
}

impl Affine {
    /// The constant `c`.
    pub fn constant(c: i64) -> Self {
        Self {
            var: None,
            scale: 0,
            n: 0,
            sym: None,
            k: 0,
            c,
        }
    }

    /// The loop variable `i`.
    pub fn var(i: IndexVar) -> Self {
        Self {
            var: Some(i),
            scale: 1,
            n: 0,
            sym: None,
            k: 0,
            c: 0,
        }
    }

    /// The dimension `N`.
    pub fn dim() -> Self {
        Self {
            var: None,
            scale: 0,
            n: 1,
            sym: None,
            k: 0,
            c: 0,
        }
    }

    /// The constant `s`.
    pub fn sym(s: SymId) -> Self {
        Self {
            sym: Some(s),
            k: 1,
            ..Self::constant(0)
        }
    }

    /// `self + k·other`, or `None` when that mixes two loop variables or two [`Sym`]s.
    pub fn add_scaled(self, other: Affine, k: i64) -> Option<Self> {
        let var = match (self.var, other.var) {
            (Some(a), Some(b)) if a != b && self.scale != 0 && other.scale != 0 => return None,
            (Some(a), _) if self.scale != 0 => Some(a),
            (_, Some(b)) if other.scale != 0 => Some(b),
            _ => None,
        };
        let sym = match (self.sym, other.sym) {
            (Some(a), Some(b)) if a != b && self.k != 0 && other.k != 0 => return None,
            (Some(a), _) if self.k != 0 => Some(a),
            (_, Some(b)) if other.k != 0 => Some(b),
            _ => None,
        };
        let out = Self {
            var,
            scale: self.scale + k * other.scale,
            n: self.n + k * other.n,
            sym,
            k: self.k + k * other.k,
            c: self.c + k * other.c,
        };
        Some(out.normal())
    }

    /// `k·self`.
    pub fn scaled(self, k: i64) -> Self {
        Self {
            var: self.var,
            scale: k * self.scale,
            n: k * self.n,
            sym: self.sym,
            k: k * self.k,
            c: k * self.c,
        }
        .normal()
    }

    fn normal(mut self) -> Self {
        if self.scale == 0 {
            self.var = None;
        }
        if self.k == 0 {
            self.sym = None;
        }
        self
    }

    /// The constant value, when the index names neither a loop variable, nor `N`, nor a
    /// [`Sym`].
    pub fn as_constant(self) -> Option<i64> {
        (self.var.is_none() && self.n == 0 && self.sym.is_none()).then_some(self.c)
    }

    /// Substitutes the value `n` for `N`.
    pub fn at_dim(self, n: Option<usize>) -> Self {
        match n {
            Some(d) => Self {
                n: 0,
                c: self.c + self.n * d as i64,
                ..self
            },
            None => self,
        }
    }
}

/// The component a state array is read at: `at`, or `at mod N` for a periodic index, in the
/// iterations of its loop that `guard` lets through.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Component {
    pub at: Affine,
    pub wrap: bool,
    pub guard: Guard,
}

/// The iterations at which a component is read, `low ≤ i < high` for the loop variable `i` of
/// its index, on the sides that the condition of an `if` around the read decides and that its
/// index needs (`x[i - 1]` in `if i > 0 { … }`: `low = 1`). Each side is free of loop
/// variables. A component with a side is read, and its derivatives added, only where the
/// side holds: elsewhere its index may not exist.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Guard {
    pub low: Option<Affine>,
    pub high: Option<Affine>,
}

impl Guard {
    /// Every iteration.
    pub const NONE: Guard = Guard {
        low: None,
        high: None,
    };

    /// Whether the guard lets every iteration through.
    pub fn is_none(self) -> bool {
        self == Guard::NONE
    }
}

/// A check of an index that needs the value of a [`Sym`]: `lhs < rhs` wherever the loop
/// range `guard` is not empty, asserted at compile time by the generated code.
#[derive(Clone, Debug)]
pub struct Bound {
    pub guard: Option<(Affine, Affine)>,
    pub lhs: Affine,
    pub rhs: Affine,
    /// What fails, for the assertion's message.
    pub what: String,
    pub span: proc_macro2::Span,
}

/// The range `start..end` of a loop variable, and the name it was written with.
#[derive(Clone, Debug)]
pub struct Range {
    pub name: String,
    pub start: Affine,
    pub end: Affine,
}

/// A comparison in a condition.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Cmp {
    Lt,
    Le,
    Gt,
    Ge,
    Eq,
    Ne,
}

impl Cmp {
    /// The operator as written in Rust.
    pub fn symbol(self) -> &'static str {
        match self {
            Cmp::Lt => "<",
            Cmp::Le => "<=",
            Cmp::Gt => ">",
            Cmp::Ge => ">=",
            Cmp::Eq => "==",
            Cmp::Ne => "!=",
        }
    }

    /// Evaluates `a op b`.
    pub fn eval(self, a: f64, b: f64) -> bool {
        match self {
            Cmp::Lt => a < b,
            Cmp::Le => a <= b,
            Cmp::Gt => a > b,
            Cmp::Ge => a >= b,
            Cmp::Eq => a == b,
            Cmp::Ne => a != b,
        }
    }
}
