use varembed::lagrangian;

const N: usize = 8;
const M: usize = 2;

#[lagrangian]
fn blocks(x: [f64; N], v: [f64; N]) -> f64 {
    (0..N / M).map(|i| 0.5 * v[i] * v[i] - x[i] * x[i]).sum()
}

fn main() {}
