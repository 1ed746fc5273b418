use varembed::lagrangian;

#[lagrangian]
fn noisy(x: f64, v: f64) -> f64 {
    println!("{x}");
    0.5 * v * v
}

fn main() {}
