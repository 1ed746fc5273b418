use varembed::lagrangian;

const N: usize = 8;

#[lagrangian]
fn free(x: [f64; N], v: [f64; N]) -> f64 {
    x.iter().zip(v.iter()).map(|(a, b)| 0.5 * b * b - a).sum::<f64>()
}

fn main() {}
