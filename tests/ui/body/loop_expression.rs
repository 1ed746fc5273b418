use varembed::lagrangian;

#[lagrangian]
fn looped(x: f64, v: f64) -> f64 {
    let s = loop {
        break x;
    };
    s * v
}

fn main() {}
