use varembed::lagrangian;

#[lagrangian]
fn spring(x: f64, v: f64, _k: f32) -> f64 {
    0.5 * v * v - 0.5 * x * x
}

fn main() {}
