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

/// `C` and `E` of the module docs, read from the operators' starting columns.
pub(super) struct EndColumns<'a> {
    sigma: f64,
    /// The velocity operator, whose starting columns are `C`.
    velocity: &'a Operator,
    /// The direct scheme's momentum operator, whose starting columns are `E`; `None` for the
    /// variational scheme (`E = Cᵀ`).
    momentum: Option<&'a Operator>,
}

impl<'a> EndColumns<'a> {
    /// The columns of `velocity` and, for the direct scheme, of `adjoint` (the momentum
    /// operator); `None` for the paper's operators, which have none.
    pub(super) fn new(
        scheme: Scheme,
        velocity: &'a Operator,
        adjoint: &'a Operator,
    ) -> Option<Self> {
        velocity.has_end_columns().then(|| EndColumns {
            sigma: velocity.side().sign(),
            velocity,
            momentum: (scheme == Scheme::Direct).then_some(adjoint),
        })
    }

    /// Whether `B = Dᵀ`, so that the Jacobian is symmetric.
    pub(super) fn symmetric(&self) -> bool {
        self.momentum.is_none()
    }

    /// The largest row sum of `|C|` and of `|E|`: what the columns add to the bounds
    /// `‖Δ‖∞ ≤ 2h^{−α}` and `‖Δᵀ‖∞` of the plain operator.
    pub(super) fn row_sums(&self) -> (f64, f64) {
        let largest = |op: &Operator| {
            op.rows()
                .map(|k| {
                    op.column_entries_in_row(k)
                        .map(|(_, c)| c.abs())
                        .sum::<f64>()
                })
                .fold(0.0, f64::max)
        };
        let momentum = match self.momentum {
            Some(op) => largest(op),
            // Cᵀ: a row of it is a whole column of C.
            None => self
                .column_sums(0.0, |_| 1.0, |c| c.abs())
                .into_iter()
                .fold(0.0, f64::max),
        };
        (largest(self.velocity), momentum)
    }

    /// For each starting column of `C`, in order, `Σ_k f(C[k, node]) · b(i)` over the rows
    /// `k = i + first_row`.
    fn column_sums<T>(&self, zero: T, b: impl Fn(usize) -> T, f: impl Fn(f64) -> f64) -> Vec<T>
    where
        T: std::ops::Mul<f64, Output = T> + std::ops::Add<Output = T> + Copy,
    {
        let mut sums = vec![zero; self.velocity.end_column_nodes().count()];
        for (i, k) in self.velocity.rows().enumerate() {
            let bi = b(i);
            for (sum, (_, c)) in sums.iter_mut().zip(self.velocity.column_entries_in_row(k)) {
                *sum = *sum + bi * f(c);
            }
        }
        sums
    }

    /// Hands `(i, −σ (C x)_k)` to `add` for the `N` rows `k = i + first_row`, with `node(j)`
    /// the value of `x` at node `j`.
    pub(super) fn add_velocity<const D: usize>(
        &self,
        node: impl Fn(usize) -> Vector<D>,
        first_row: usize,
        mut add: impl FnMut(usize, Vector<D>),
    ) {
        let x: Vec<Vector<D>> = self
            .velocity
            .end_column_nodes()
            .map(|j| node(j) * -self.sigma)
            .collect();
        for (i, k) in self.velocity.rows().enumerate() {
            debug_assert_eq!(k, i + first_row);
            for (x, (_, c)) in x.iter().zip(self.velocity.column_entries_in_row(k)) {
                add(i, x * c);
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
        let n = self.velocity.rows().count();
        match self.momentum {
            Some(op) => {
                let bm: Vec<Vector<D>> = op
                    .end_column_nodes()
                    .map(|m| b(m - first_row) * -self.sigma)
                    .collect();
                for j in 1..n {
                    for (bm, (_, e)) in bm.iter().zip(op.column_entries_in_row(j)) {
                        out(j, bm * e);
                    }
                }
            }
            None => {
                let sums = self.column_sums(Vector::<D>::zeros(), &b, |c| c);
                for (j, sum) in self.velocity.end_column_nodes().zip(sums) {
                    if (1..n).contains(&j) {
                        out(j, sum * -self.sigma);
                    }
                }
            }
        }
    }
}
