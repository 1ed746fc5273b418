use varembed::lagrangian;

#[lagrangian]
fn frame(x: [f64; 2], v: [f64; 2], b: f64) -> f64 {
    let a = [-b * x[1], b * x[0]];
    let mut l = 0.0;
    for k in 0..3 {
        l += 0.5 * (v[0] + a[k]).powi(2);
    }
    l + a[2]
}

fn main() {}
