use varembed::lagrangian;

#[lagrangian]
fn free(q: f64, v: f64) -> f64 {
    q * v
}

fn main() {}
