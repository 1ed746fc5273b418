use varembed::lagrangian;

#[lagrangian]
fn free(_x: f64, _v: f64) {}

fn main() {}
