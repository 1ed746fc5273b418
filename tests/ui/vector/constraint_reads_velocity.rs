use varembed::constraint;

#[constraint]
fn rolling(x: [f64; 2], r: f64) -> [f64; 1] {
    [x[0] - r * v[1]]
}

fn main() {}
