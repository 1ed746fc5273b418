use varembed::lagrangian;

#[lagrangian]
fn pointer(x: f64, v: f64) -> f64 {
    0.5 * v * v - *&x
}

fn main() {}
