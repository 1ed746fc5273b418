use varembed::lagrangian;

#[lagrangian]
fn nothing() -> f64 {
    1.0
}

fn main() {}
