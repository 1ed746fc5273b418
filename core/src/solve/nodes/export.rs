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
        let mut header = String::from("t");
        for name in ["q", "v", "p"] {
            for i in 0..D {
                let _ = write!(header, ",{name}{i}");
            }
        }
        if self.energy.is_some() {
            header.push_str(",E");
        }
        header
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
        let mut csv = self.csv_header();
        csv.push('\n');
        for node in self.iter() {
            let _ = write!(csv, "{:e}", node.t);
            for x in node.q.iter().chain(node.v.iter()).chain(node.p.iter()) {
                let _ = write!(csv, ",{x:e}");
            }
            if let Some(e) = node.energy {
                let _ = write!(csv, ",{e:e}");
            }
            csv.push('\n');
        }
        csv
    }
}

#[cfg(feature = "serde")]
mod serde_impls {
    use super::super::{NodeState, NodeValues};
    use serde::ser::{Serialize, SerializeSeq, SerializeStruct, Serializer};

    /// `{"t": …, "q": [..], "v": [..], "p": [..], "energy": … or null}`.
    impl<const D: usize> Serialize for NodeState<D> {
        fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
            let mut s = serializer.serialize_struct("NodeState", 5)?;
            s.serialize_field("t", &self.t)?;
            s.serialize_field("q", self.q.as_slice())?;
            s.serialize_field("v", self.v.as_slice())?;
            s.serialize_field("p", self.p.as_slice())?;
            s.serialize_field("energy", &self.energy)?;
            s.end()
        }
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
