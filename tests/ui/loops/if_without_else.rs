use varembed::lagrangian;

#[lagrangian]
fn wall(x: f64, v: f64) -> f64 {
    let wall = if x < 0.0 { x * x };
    0.5 * v * v - wall
}

fn main() {}
