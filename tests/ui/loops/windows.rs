use varembed::lagrangian;

const N: usize = 8;

#[lagrangian]
fn chain(x: [f64; N], v: [f64; N]) -> f64 {
    let kinetic: f64 = (0..N).map(|i| 0.5 * v[i] * v[i]).sum();
    kinetic - x.windows(2).map(|w| (w[1] - w[0]).powi(2)).sum::<f64>()
}

fn main() {}
