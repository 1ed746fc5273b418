use varembed::lagrangian;

const N: usize = 8;

#[lagrangian]
fn chain(x: [f64; N], v: [f64; N], k: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..(k as usize) {
        l += 0.5 * v[i] * v[i] - x[i].exp2();
    }
    l + x.iter().sum::<f64>()
}

fn main() {}
