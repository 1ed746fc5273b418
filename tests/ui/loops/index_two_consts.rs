use varembed::lagrangian;

const N: usize = 8;
const M: usize = 3;
const K: usize = 2;

#[lagrangian]
fn shifted(x: [f64; N], v: [f64; N]) -> f64 {
    let mut l = 0.5 * v[0] * v[0];
    for i in 0..M {
        l -= x[i + K].powi(2);
    }
    l
}

fn main() {}
