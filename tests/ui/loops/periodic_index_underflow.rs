use varembed::lagrangian;

const N: usize = 8;

#[lagrangian]
fn ring(x: [f64; N], v: [f64; N]) -> f64 {
    (0..N)
        .map(|i| 0.5 * v[i] * v[i] - 0.5 * (x[i] - x[(i - 1) % N]).powi(2))
        .sum()
}

fn main() {}
