use varembed::lagrangian;

#[lagrangian]
fn free(x: f64, v: [f64; 2]) -> f64 {
    x * v[0]
}

fn main() {}
