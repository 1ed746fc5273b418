//! The exports of a run-time-dimension solution's node values: CSV whose numbers read back bit
//! for bit, in the columns of [`NodeValues::to_csv`](crate::NodeValues::to_csv), and
//! `serde::Serialize` behind the `serde` feature.

use super::DynNodeValues;
use crate::solve::nodes::export::{csv_header, to_csv};

impl DynNodeValues {
    /// The CSV header: `t,q0,…,q{d−1},v0,…,v{d−1},p0,…,p{d−1}`, then `E` when the energy is
    /// known — the columns of [`NodeValues::csv_header`](crate::NodeValues::csv_header).
    pub fn csv_header(&self) -> String {
        csv_header(self.dimension, self.energy.is_some())
    }

    /// The nodes as CSV: [`csv_header`](Self::csv_header), then one line per node, every number
    /// in Rust's shortest round-trip form (`{:e}`, e.g. `1.25e-1`), so that parsing it back
    /// with `str::parse::<f64>` gives the same bits (as
    /// [`NodeValues::to_csv`](crate::NodeValues::to_csv)).
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{DynProblem, Grid, Scheme, lagrangian};
    ///
    /// #[lagrangian]
    /// fn oscillators(x: &[f64], v: &[f64], n: usize) -> f64 {
    ///     let mut l = 0.0;
    ///     for i in 0..n {
    ///         l += 0.5 * (v[i] * v[i] - x[i] * x[i]);
    ///     }
    ///     l
    /// }
    ///
    /// let model = Oscillators { n: 2 };
    /// let problem = DynProblem::recommended(&model, Grid::new(0.0, 1.0, 10)?);
    /// let nodes = problem.solve_ivp(Scheme::Variational, &[1.0, 0.5], &[0.0; 2])?.node_values(&model)?;
    /// let csv = nodes.to_csv();
    /// assert_eq!(csv.lines().next(), Some("t,q0,q1,v0,v1,p0,p1,E"));
    /// let line: Vec<f64> = csv.lines().nth(4).unwrap().split(',').map(|x| x.parse().unwrap()).collect();
    /// let node = nodes.get(3).unwrap();
    /// assert_eq!(line[0].to_bits(), node.t.to_bits());
    /// assert_eq!(&line[3..5], node.v);
    /// assert_eq!(line[7], node.energy.unwrap());
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn to_csv(&self) -> String {
        let nodes = self
            .iter()
            .map(|node| (node.t, [node.q, node.v, node.p], node.energy));
        to_csv(self.dimension, self.energy.is_some(), nodes)
    }
}

#[cfg(feature = "serde")]
mod serde_impls {
    use super::super::{DynNodeState, DynNodeValues};
    use crate::solve::nodes::export::serde_impls::serialize_node;
    use serde::ser::{Serialize, SerializeSeq, Serializer};

    /// `{"t": …, "q": [..], "v": [..], "p": [..], "energy": … or null}`, as
    /// [`NodeState`](crate::NodeState).
    impl Serialize for DynNodeState<'_> {
        fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
            serialize_node(serializer, self.t, [self.q, self.v, self.p], self.energy)
        }
    }

    /// The sequence of the nodes' [`DynNodeState`]s, as [`NodeValues`](crate::NodeValues).
    impl Serialize for DynNodeValues {
        fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
            let mut seq = serializer.serialize_seq(Some(self.len()))?;
            for node in self.iter() {
                seq.serialize_element(&node)?;
            }
            seq.end()
        }
    }
}
