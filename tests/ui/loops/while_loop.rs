use varembed::lagrangian;

#[lagrangian]
fn damped(x: f64, v: f64) -> f64 {
    let mut k = 0.0;
    while k < 3.0 {
        k += 1.0;
    }
    0.5 * v * v - k * x * x
}

fn main() {}
