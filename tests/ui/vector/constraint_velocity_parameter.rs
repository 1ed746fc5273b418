use varembed::constraint;

#[constraint]
fn rod(x: [f64; 2], v: [f64; 2], l: f64) -> [f64; 1] {
    [x[0] * x[0] + x[1] * x[1] - l * l]
}

fn main() {}
