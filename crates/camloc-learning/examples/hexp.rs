#[path = "../tests/support/mod.rs"]
mod support;
use camloc_learning::*;
use std::time::Instant;
fn main() {
    let n = 43188;
    let (x, y) = support::gaussian_classes(n, 74, 12, 0.3, 3.0, 2024);
    let f = Features::new(&x, 74).unwrap();
    let mut p = NewtonProblem::new(&f, &y, 12, &LogisticRegression::default()).unwrap();
    p.newton_step().unwrap();
    let mut best = f64::INFINITY;
    for _ in 0..6 { let t = Instant::now(); p.assemble_hessian(); best = best.min(t.elapsed().as_secs_f64()); }
    eprintln!("hessian {:.3}s {:.1} GF/s", best, p.hessian_flops() / best / 1e9);
    let t = Instant::now();
    let (_, r) = LogisticRegression::default().fit(&f, &y, 12).unwrap();
    eprintln!("fit {:?} {} its", t.elapsed(), r.iterations.len() - 1);
}
