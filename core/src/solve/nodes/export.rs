//! The exports of a solution's node values: CSV whose numbers read back bit for bit, and
//! `serde::Serialize` behind the `serde` feature.

use super::NodeValues;
use std::fmt::Write as _;

impl<const D: usize> NodeValues<D> {
    /// The CSV header: `t,q0,…,q{D−1},v0,…,v{D−1},p0,…,p{D−1}`, then `E` when the energy is
    /// known.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{Embedding, Grid, Problem, Scheme, Side, lagrangian};
    ///
    /// #[lagrangian]
    /// fn oscillator(x: f64, v: f64) -> f64 {
    ///     0.5 * v * v - 0.5 * x * x
    /// }
    ///
    /// let grid = Grid::new(0.0, 1.0, 10)?;
    /// let problem = Problem::new(&Oscillator, grid, Embedding::finite_difference(Side::Backward));
    /// let nodes = problem.solve_ivp(Scheme::Variational, 1.0, 0.0)?.node_values(&Oscillator)?;
    /// assert_eq!(nodes.csv_header(), "t,q0,v0,p0,E");
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn csv_header(&self) -> String {
        csv_header(D, self.energy.is_some())
    }

    /// The nodes as CSV: [`csv_header`](Self::csv_header), then one line per node. Every number
    /// is written in Rust's shortest round-trip form (`{:e}`, e.g. `1.25e-1`), so that parsing
    /// it back with `str::parse::<f64>` gives the same bits.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{Embedding, Grid, Problem, Scheme, Side, lagrangian};
    ///
    /// #[lagrangian]
    /// fn oscillator(x: f64, v: f64) -> f64 {
    ///     0.5 * v * v - 0.5 * x * x
    /// }
    ///
    /// let grid = Grid::new(0.0, 1.0, 10)?;
    /// let problem = Problem::new(&Oscillator, grid, Embedding::finite_difference(Side::Backward));
    /// let nodes = problem.solve_ivp(Scheme::Variational, 1.0, 0.0)?.node_values(&Oscillator)?;
    /// let csv = nodes.to_csv();
    /// let line = csv.lines().nth(4).expect("node 3");
    /// let t: f64 = line.split(',').next().unwrap().parse().unwrap();
    /// assert_eq!(t.to_bits(), nodes.t[3].to_bits());
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn to_csv(&self) -> String {
        let nodes = (0..self.len()).map(|k| {
            let values = [
                self.q[k].as_slice(),
                self.v[k].as_slice(),
                self.p[k].as_slice(),
            ];
            (self.t[k], values, self.energy.as_ref().map(|e| e[k]))
        });
        to_csv(D, self.energy.is_some(), nodes)
    }
}

/// The CSV header of nodes of dimension `d`: `t,q0,…,q{d−1},v0,…,v{d−1},p0,…,p{d−1}`, then `E`
/// when the energy is known. Both paths' node values write it.
pub(crate) fn csv_header(d: usize, energy: bool) -> String {
    let mut header = String::from("t");
    for name in ["q", "v", "p"] {
        for i in 0..d {
            let _ = write!(header, ",{name}{i}");
        }
    }
    if energy {
        header.push_str(",E");
    }
    header
}

/// The header, then one line per node `(t, [q, v, p], E)`, every number in Rust's shortest
/// round-trip form (`{:e}`). Both paths' node values write it.
pub(crate) fn to_csv<X: AsRef<[f64]>>(
    d: usize,
    energy: bool,
    nodes: impl Iterator<Item = (f64, [X; 3], Option<f64>)>,
) -> String {
    let mut csv = csv_header(d, energy);
    csv.push('\n');
    for (t, values, energy) in nodes {
        let _ = write!(csv, "{t:e}");
        for x in values.iter().flat_map(|x| x.as_ref()) {
            let _ = write!(csv, ",{x:e}");
        }
        if let Some(e) = energy {
            let _ = write!(csv, ",{e:e}");
        }
        csv.push('\n');
    }
    csv
}

#[cfg(feature = "serde")]
pub(crate) mod serde_impls {
    use super::super::{NodeState, NodeValues};
    use serde::ser::{Serialize, SerializeSeq, SerializeStruct, Serializer};

    /// `{"t": …, "q": [..], "v": [..], "p": [..], "energy": … or null}`.
    impl<const D: usize> Serialize for NodeState<D> {
        fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
            let values = [self.q.as_slice(), self.v.as_slice(), self.p.as_slice()];
            serialize_node(serializer, self.t, values, self.energy)
        }
    }

    /// A node as `{"t": …, "q": [..], "v": [..], "p": [..], "energy": … or null}`: both paths'
    /// node states.
    pub(crate) fn serialize_node<S: Serializer>(
        serializer: S,
        t: f64,
        [q, v, p]: [&[f64]; 3],
        energy: Option<f64>,
    ) -> Result<S::Ok, S::Error> {
        let mut s = serializer.serialize_struct("NodeState", 5)?;
        s.serialize_field("t", &t)?;
        s.serialize_field("q", q)?;
        s.serialize_field("v", v)?;
        s.serialize_field("p", p)?;
        s.serialize_field("energy", &energy)?;
        s.end()
    }

    /// The sequence of the nodes' [`NodeState`]s.
    impl<const D: usize> Serialize for NodeValues<D> {
        fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
            let mut seq = serializer.serialize_seq(Some(self.len()))?;
            for node in self.iter() {
                seq.serialize_element(&node)?;
            }
            seq.end()
        }
    }
}
