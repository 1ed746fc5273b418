use varembed::lagrangian;

#[lagrangian(fast)]
fn free(x: f64, v: f64) -> f64 {
    0.5 * v * v + 0.0 * x
}

fn main() {}
