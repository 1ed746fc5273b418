//! The corrected Gauss-GLEσ on the fast path: its starting columns beside the FFT products.
//!
//! The corrected velocity operator is `D = −σ(Δ + C)`: the paper's `Δ^α_σ` (applied by FFT as
//! for Gauss-GLEσ) and `C`, two columns at the nodes next to where its sums start. The momenta
//! enter the rows through `B = −σ(Δᵀ + E)`: for the direct scheme `E` is the two columns of the
//! momentum operator (at the nodes next to the other end, read by every interior row), for the
//! variational scheme `E = Cᵀ` (two rows). Both are `O(N)` entries, added here to what the FFT
//! products give: `O(N d)` per product, beside their `O(N log N)`.
//!
//! The direct scheme's `B` is then not `Dᵀ`: its Jacobian
//! `L_xx + L_xv D + B L_vx + B L_vv D` is not symmetric, which the solver's choice of Krylov
//! method reads from [`EndColumns::symmetric`].

use crate::embedding::Scheme;
use crate::lagrangian::Vector;
use crate::operator::Operator;

/// `C` and `E` of the module docs, as columns by node.
pub(super) struct EndColumns {
    sigma: f64,
    /// `(node, c)` with `c[k] = C[k, node]`, `k = 0..=N`.
    velocity: Vec<(usize, Vec<f64>)>,
    /// The direct scheme's `E` as `(node m, e)` with `e[j] = E[j, m]`; `None` for the
    /// variational scheme (`E = Cᵀ`).
    momentum: Option<Vec<(usize, Vec<f64>)>>,
}

impl EndColumns {
    /// The columns of `velocity` and, for the direct scheme, of `adjoint` (the momentum
    /// operator); `None` for the paper's operators, which have none.
    pub(super) fn new(scheme: Scheme, velocity: &Operator, adjoint: &Operator) -> Option<Self> {
        velocity.has_end_columns().then(|| EndColumns {
            sigma: velocity.side().sign(),
            velocity: velocity.end_columns(),
            momentum: (scheme == Scheme::Direct).then(|| adjoint.end_columns()),
        })
    }

    /// Whether `B = Dᵀ`, so that the Jacobian is symmetric.
    pub(super) fn symmetric(&self) -> bool {
        self.momentum.is_none()
    }

    /// The largest row sum of `|C|` and of `|E|`: what the columns add to the bounds
    /// `‖Δ‖∞ ≤ 2h^{−α}` and `‖Δᵀ‖∞` of the plain operator.
    pub(super) fn row_sums(&self) -> (f64, f64) {
        let largest = |columns: &[(usize, Vec<f64>)], len: usize| {
            (0..len)
                .map(|k| columns.iter().map(|(_, c)| c[k].abs()).sum::<f64>())
                .fold(0.0, f64::max)
        };
        let len = self.velocity.first().map_or(0, |(_, c)| c.len());
        let momentum = match &self.momentum {
            Some(e) => largest(e, len),
            // Cᵀ: a row of it is a whole column of C.
            None => self
                .velocity
                .iter()
                .map(|(_, c)| c.iter().map(|x| x.abs()).sum::<f64>())
                .fold(0.0, f64::max),
        };
        (largest(&self.velocity, len), momentum)
    }

    /// Hands `(i, −σ (C x)_k)` to `add` for the `N` rows `k = i + first_row`, with `node(j)`
    /// the value of `x` at node `j`.
    pub(super) fn add_velocity<const D: usize>(
        &self,
        node: impl Fn(usize) -> Vector<D>,
        first_row: usize,
        mut add: impl FnMut(usize, Vector<D>),
    ) {
        for (j, c) in &self.velocity {
            let x = node(*j) * -self.sigma;
            for i in 0..c.len() - 1 {
                add(i, x * c[i + first_row]);
            }
        }
    }

    /// Hands `(j, −σ (E b)_j)` to `out` for the interior nodes `j = 1..N−1` it reaches, with
    /// `b(i)` the value on row `i + first_row` (`N` rows).
    pub(super) fn add_momentum<const D: usize>(
        &self,
        b: impl Fn(usize) -> Vector<D>,
        first_row: usize,
        mut out: impl FnMut(usize, Vector<D>),
    ) {
        let n = self.velocity.first().map_or(0, |(_, c)| c.len() - 1);
        match &self.momentum {
            Some(columns) => {
                for (m, e) in columns {
                    let bm = b(m - first_row) * -self.sigma;
                    for j in 1..n {
                        out(j, bm * e[j]);
                    }
                }
            }
            None => {
                for (j, c) in &self.velocity {
                    if (1..n).contains(j) {
                        let sum = (0..n)
                            .fold(Vector::<D>::zeros(), |acc, i| acc + b(i) * c[i + first_row]);
                        out(*j, sum * -self.sigma);
                    }
                }
            }
        }
    }
}
