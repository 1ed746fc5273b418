use varembed::lagrangian;

const N: usize = 1;

#[lagrangian]
fn pair(x: [f64; N], v: [f64; N]) -> f64 {
    let kinetic: f64 = (0..N).map(|i| 0.5 * v[i] * v[i]).sum();
    kinetic - (x[1] - x[0]).powi(2)
}

fn main() {}
