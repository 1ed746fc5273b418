use varembed::force;

#[force]
fn field(x: &[f64], v: &[f64], n: usize, c: f64) -> Vec<f64> {
    let s = (0..n).map(|j| x[j] * x[j]).sum::<f64>();
    let mut f = vec![0.0; n];
    for i in 0..n {
        f[i] -= c * s.sqrt() * v[i];
    }
    f
}

fn main() {}
