use varembed::lagrangian;

const N: usize = 8;

/// The right neighbour behind a condition that every iteration passes.
#[lagrangian]
fn fixed(x: [f64; N], v: [f64; N]) -> f64 {
    (0..N)
        .map(|j| {
            let right = if j < N { x[j + 1] } else { 0.0 };
            0.5 * v[j] * v[j] - 0.5 * (right - x[j]).powi(2)
        })
        .sum::<f64>()
        - 0.5 * x[0].powi(2)
}

fn main() {}
