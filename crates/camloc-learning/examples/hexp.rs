#[path = "../tests/support/mod.rs"]
mod support;
use camloc_learning::*;
use std::time::Instant;
fn main() {
    let n: usize = std::env::args().nth(1).map(|s| s.parse().unwrap()).unwrap_or(43188);
    let (x, y) = support::gaussian_classes(n, 74, 12, 0.3, 3.0, 7);
    let f = Features::new(&x, 74).unwrap();
    for mode in [Mode::Multinomial, Mode::OneVsRest] {
        let cfg = LogisticRegression::default().with_mode(mode);
        let t = Instant::now();
        let mut p = NewtonProblem::new(&f, &y, 12, &cfg).unwrap();
        eprintln!("new {:?}", t.elapsed());
        for _ in 0..3 {
            let t = Instant::now();
            p.assemble_hessian();
            let h = t.elapsed().as_secs_f64();
            eprintln!("hessian {:.3}s {:.1} GF/s actual", h, p.hessian_flops() / h / 1e9);
        }
        let t = Instant::now();
        p.newton_step().unwrap();
        eprintln!("step {:?}", t.elapsed());
    }
}
