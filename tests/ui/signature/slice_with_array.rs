use varembed::lagrangian;

#[lagrangian]
fn chain(x: &[f64], v: [f64; 4], n: usize) -> f64 {
    (0..n).map(|i| 0.5 * v[i] * v[i] - x[i] * x[i]).sum()
}

fn main() {}
