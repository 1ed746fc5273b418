use varembed::lagrangian;

#[lagrangian]
fn kink(x: f64, v: f64) -> f64 {
    if x > 0.0 { 0.5 * v * v } else { v * v }
}

fn main() {}
