use varembed::lagrangian;

#[lagrangian]
fn planar(x: [f64; 2], v: [f64; 2]) -> f64 {
    0.5 * (v[0] * v[0] + v[1] * v[1]) - x[2]
}

fn main() {}
