use varembed::lagrangian;

#[lagrangian]
fn many(x: f64, v: f64, k: f64) -> f64 {
    let a = x % k;
    let b = match v > 0.0 { true => v, false => -v };
    a + b + x.exp2() + k.log(2.0)
}

fn main() {}
