use varembed::lagrangian;

const N: usize = 8;
const PAIRS: usize = 4;

#[lagrangian]
fn dimers(x: [f64; N], v: [f64; N]) -> f64 {
    let mut l = 0.0;
    for i in 0..PAIR {
        l += 0.5 * v[2 * i] * v[2 * i] - (x[2 * i + 1] - x[2 * i]).powi(2);
    }
    l
}

fn main() {}
