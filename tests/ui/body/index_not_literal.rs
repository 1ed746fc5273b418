use varembed::lagrangian;

#[lagrangian]
fn planar(x: [f64; 2], v: [f64; 2]) -> f64 {
    let i = 1;
    0.5 * v[0] * v[0] - x[i]
}

fn main() {}
