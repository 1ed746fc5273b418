use varembed::constraint;

#[constraint]
fn moving_wall(x: [f64; 2]) -> [f64; 1] {
    [x[0] - t]
}

fn main() {}
