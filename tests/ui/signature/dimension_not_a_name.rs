use varembed::lagrangian;

const N: usize = 2;

#[lagrangian]
fn free(x: [f64; 2 * N], v: [f64; 2 * N]) -> f64 {
    0.5 * v[0] * v[0] + x[1]
}

fn main() {}
