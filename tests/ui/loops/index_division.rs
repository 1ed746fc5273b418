use varembed::lagrangian;

const N: usize = 8;

#[lagrangian]
fn pairs(x: [f64; N], v: [f64; N]) -> f64 {
    (0..N).map(|i| 0.5 * v[i] * v[i] - x[i / 2] * x[i]).sum()
}

fn main() {}
