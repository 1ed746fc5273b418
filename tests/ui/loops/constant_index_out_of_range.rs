use varembed::lagrangian;

const N: usize = 8;

#[lagrangian]
fn pinned(x: [f64; N], v: [f64; N]) -> f64 {
    let kinetic: f64 = (0..N).map(|i| 0.5 * v[i] * v[i]).sum();
    kinetic - 0.5 * x[N] * x[N]
}

fn main() {}
