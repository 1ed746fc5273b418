//! The side σ of an embedding, of its operators and of its quadrature.

/// The side σ of an embedding.
///
/// # Example
///
/// ```
/// use varembed::Side;
/// assert_eq!(Side::Backward.sign(), -1.0);
/// assert_eq!(Side::Backward.opposite(), Side::Forward);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Side {
    /// σ = −: backward differences, Gauss quadrature on `I_− = {1..N}`.
    Backward,
    /// σ = +: forward differences, Gauss quadrature on `I_+ = {0..N−1}`.
    Forward,
}

impl Side {
    /// σ as a number: −1 for [`Side::Backward`], +1 for [`Side::Forward`].
    ///
    /// ```
    /// assert_eq!(varembed::Side::Forward.sign(), 1.0);
    /// ```
    pub fn sign(self) -> f64 {
        match self {
            Side::Backward => -1.0,
            Side::Forward => 1.0,
        }
    }
    /// The other side, −σ.
    ///
    /// ```
    /// use varembed::Side;
    /// assert_eq!(Side::Forward.opposite(), Side::Backward);
    /// ```
    pub fn opposite(self) -> Side {
        match self {
            Side::Backward => Side::Forward,
            Side::Forward => Side::Backward,
        }
    }
    /// `−` or `+`, as in the embeddings' names.
    pub(crate) fn symbol(self) -> char {
        match self {
            Side::Backward => '−',
            Side::Forward => '+',
        }
    }
}
