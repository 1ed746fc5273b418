use varembed::lagrangian;

#[lagrangian]
fn free(x: f32, v: f32) -> f32 {
    x * v
}

fn main() {}
