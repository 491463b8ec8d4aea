//! Newton solver benchmarks on synthetic data of the paper's size (n = 43188 samples,
//! d = 74 features, K = 12 classes) and ten times larger, plus the machine's GEMM peak.
//!
//! Besides criterion's times, GFLOP/s figures are printed to stderr (best of a few runs):
//! the GEMM peak (`2 m^3` flops) and the Hessian assembly, both as actually computed
//! (`2 n T Q`, `T = D(D+1)/2`, `Q = K(K-1)/2`, see `NewtonProblem::hessian_flops`) and as
//! the equivalent textbook count (`2 n D^2 K(K+1)/2`).
//!
//! Run: `cargo bench -p camloc-learning` (filter with e.g. `-- paper`).

#[path = "../tests/support/mod.rs"]
mod support;

use std::hint::black_box;
use std::time::{Duration, Instant};

use camloc_learning::{Features, LogisticRegression, NewtonProblem};
use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, Par};

const D_FEATURES: usize = 74;
const K_CLASSES: usize = 12;
const PAPER_N: usize = 43_188;
/// Class-mean spread: overlapping classes (about 80% training accuracy), so that Newton
/// needs several iterations.
const SEPARATION: f64 = 0.3;

/// Best wall time of `runs` calls of `f`.
fn best_of(runs: usize, mut f: impl FnMut()) -> Duration {
    (0..runs)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed()
        })
        .min()
        .unwrap_or_default()
}

fn data(n: usize) -> (Vec<f64>, Vec<usize>) {
    support::gaussian_classes(n, D_FEATURES, K_CLASSES, SEPARATION, 3.0, 2024)
}

/// Parameters after one Newton iteration from zero: a typical mid-fit state.
fn mid_fit_problem(x: &[f64], y: &[usize]) -> (NewtonProblem, Vec<f64>) {
    let features = Features::new(x, D_FEATURES).expect("valid features");
    let mut problem = NewtonProblem::new(&features, y, K_CLASSES, &LogisticRegression::default())
        .expect("valid problem");
    problem.newton_step().expect("first step");
    let theta = problem.parameters().to_vec();
    (problem, theta)
}

fn gemm_peak(c: &mut Criterion) {
    let m = 2048;
    let a = Mat::<f64>::from_fn(m, m, |i, j| ((i * 7 + j * 13) % 17) as f64 * 0.1);
    let b = Mat::<f64>::from_fn(m, m, |i, j| ((i * 5 + j * 3) % 11) as f64 * 0.1);
    let mut out = Mat::<f64>::zeros(m, m);
    let flops = 2.0 * (m as f64).powi(3);
    let mut group = c.benchmark_group("gemm_peak");
    group.sample_size(10);
    for (name, par) in [("seq", Par::Seq), ("rayon", Par::rayon(0))] {
        let best = best_of(5, || {
            matmul(out.as_mut(), Accum::Replace, a.as_ref(), b.as_ref(), 1.0, par)
        });
        eprintln!(
            "GEMM {m}x{m}x{m} {name}: {:.1} GFLOP/s (best of 5)",
            flops / best.as_secs_f64() / 1e9
        );
        group.bench_function(BenchmarkId::new("2048", name), |bench| {
            bench.iter(|| matmul(out.as_mut(), Accum::Replace, a.as_ref(), b.as_ref(), 1.0, par))
        });
    }
    group.finish();
}

fn newton_benches(c: &mut Criterion, label: &str, n: usize, with_fit: bool) {
    let (x, y) = data(n);
    let (mut problem, theta) = mid_fit_problem(&x, &y);
    let mut group = c.benchmark_group(label);
    group.sample_size(10);
    group.warm_up_time(Duration::from_secs(1));

    problem.set_parameters(&theta).expect("valid parameters");
    let best = best_of(5, || problem.assemble_hessian());
    eprintln!(
        "{label}: Hessian assembly {:.1} ms: {:.1} GFLOP/s as computed ({:.2e} flops), \
         {:.1} GFLOP/s textbook-equivalent ({:.2e} flops)",
        best.as_secs_f64() * 1e3,
        problem.hessian_flops() / best.as_secs_f64() / 1e9,
        problem.hessian_flops(),
        problem.hessian_flops_textbook() / best.as_secs_f64() / 1e9,
        problem.hessian_flops_textbook(),
    );
    group.bench_function("hessian", |bench| bench.iter(|| problem.assemble_hessian()));

    group.bench_function("newton_iteration", |bench| {
        bench.iter_custom(|iters| {
            let mut total = Duration::ZERO;
            for _ in 0..iters {
                problem.set_parameters(&theta).expect("valid parameters");
                let t = Instant::now();
                black_box(problem.newton_step().expect("step"));
                total += t.elapsed();
            }
            total
        })
    });

    if with_fit {
        let features = Features::new(&x, D_FEATURES).expect("valid features");
        let config = LogisticRegression::default();
        let (_, report) = config.fit(&features, &y, K_CLASSES).expect("fit");
        eprintln!(
            "{label}: whole fit takes {} Newton iterations ({:?})",
            report.iterations.len() - 1,
            report.termination
        );
        group.bench_function("fit", |bench| {
            bench.iter(|| black_box(config.fit(&features, &y, K_CLASSES).expect("fit")))
        });
    }
    group.finish();
}

fn paper_size(c: &mut Criterion) {
    newton_benches(c, "paper", PAPER_N, true);
}

fn ten_times(c: &mut Criterion) {
    newton_benches(c, "large", 10 * PAPER_N, true);
}

fn predict(c: &mut Criterion) {
    let (x, y) = support::gaussian_classes(4000, D_FEATURES, K_CLASSES, SEPARATION, 3.0, 5);
    let features = Features::new(&x, D_FEATURES).expect("valid features");
    let (model, _) = LogisticRegression::default()
        .fit(&features, &y, K_CLASSES)
        .expect("fit");
    let sample = &x[..D_FEATURES];
    let mut out = vec![0.0; K_CLASSES];
    c.bench_function("predict_proba_into", |bench| {
        bench.iter(|| {
            model
                .predict_proba_into(black_box(sample), &mut out)
                .expect("valid sample");
            black_box(&out);
        })
    });
}

criterion_group!(benches, predict, gemm_peak, paper_size, ten_times);
criterion_main!(benches);
