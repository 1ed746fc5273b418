use varembed::lagrangian;

#[lagrangian]
fn many(x: f64, v: f64, k: f64) -> f64 {
    let a = x % k;
    let b = if v > 0.0 { v } else { -v };
    a + b + x.exp2() + helper(v)
}

fn helper(v: f64) -> f64 {
    v
}

fn main() {}
