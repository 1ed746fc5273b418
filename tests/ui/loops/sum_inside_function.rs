use varembed::lagrangian;

const N: usize = 8;

#[lagrangian]
fn radial(x: [f64; N], v: [f64; N]) -> f64 {
    let kinetic: f64 = (0..N).map(|i| 0.5 * v[i] * v[i]).sum();
    kinetic + (0..N).map(|i| x[i] * x[i]).sum::<f64>().sqrt()
}

fn main() {}
