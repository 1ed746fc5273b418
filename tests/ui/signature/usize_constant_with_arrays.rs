use varembed::lagrangian;

const N: usize = 4;

#[lagrangian]
fn chain(x: [f64; N], v: [f64; N], _n: usize) -> f64 {
    (0..N).map(|i| 0.5 * v[i] * v[i] - x[i] * x[i]).sum()
}

fn main() {}
