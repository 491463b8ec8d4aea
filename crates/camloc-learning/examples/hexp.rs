#[path = "../tests/support/mod.rs"]
mod support;
use camloc_learning::*;
use std::time::Instant;
fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .map(|s| s.parse().unwrap())
        .unwrap_or(43188);
    let (x, y) = support::gaussian_classes(n, 74, 12, 0.3, 3.0, 2024);
    let f = Features::new(&x, 74).unwrap();
    let cfg = LogisticRegression::default();
    let mut bn = f64::INFINITY;
    let mut p = None;
    for _ in 0..3 {
        let t = Instant::now();
        p = Some(NewtonProblem::new(&f, &y, 12, &cfg).unwrap());
        bn = bn.min(t.elapsed().as_secs_f64());
    }
    let mut p = p.unwrap();
    eprintln!("new {bn:.3}");
    let t = Instant::now();
    p.newton_step().unwrap();
    eprintln!("first step {:?}", t.elapsed());
    let th = p.parameters().to_vec();
    let mut bs = f64::INFINITY;
    let mut bst = f64::INFINITY;
    let mut bh = f64::INFINITY;
    for _ in 0..4 {
        let t = Instant::now();
        p.set_parameters(&th).unwrap();
        bs = bs.min(t.elapsed().as_secs_f64());
        let t = Instant::now();
        p.newton_step().unwrap();
        bst = bst.min(t.elapsed().as_secs_f64());
        p.set_parameters(&th).unwrap();
        let t = Instant::now();
        p.assemble_hessian();
        bh = bh.min(t.elapsed().as_secs_f64());
    }
    eprintln!(
        "set_parameters {bs:.3} step {bst:.3} hessian {bh:.3} ({:.1} GF/s)",
        p.hessian_flops() / bh / 1e9
    );
    for _ in 0..2 {
        let t = Instant::now();
        let (_, r) = cfg.fit(&f, &y, 12).unwrap();
        eprintln!("fit {:?} {} its", t.elapsed(), r.iterations.len() - 1);
    }
}
