use varembed::force;

#[force]
fn drag(x: [f64; 2], v: [f64; 2], c: f64) -> f64 {
    -c * v[0] * x[1]
}

fn main() {}
