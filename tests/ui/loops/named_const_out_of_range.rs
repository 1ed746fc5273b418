use varembed::lagrangian;

const N: usize = 8;
const M: usize = 5;

/// `M` dimers need `2 M` components: the compiler checks the last index against `N`.
#[lagrangian]
fn dimers(x: [f64; N], v: [f64; N]) -> f64 {
    let mut l = 0.0;
    for i in 0..M {
        l += 0.5 * v[2 * i] * v[2 * i] - (x[2 * i + 1] - x[2 * i]).powi(2);
    }
    l
}

fn main() {}
