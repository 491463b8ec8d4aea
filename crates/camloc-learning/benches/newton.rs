//! Newton solver benchmarks on synthetic data of the paper's size (n = 43188 samples,
//! d = 74 features, K = 12 classes) and ten times larger, a Hessian-vector product on the
//! default model's quadratic shape (group `quadratic`), plus the machine's GEMM peak and
//! single-sample prediction.
//!
//! Besides criterion's times, GFLOP/s figures are printed to stderr, from the fastest
//! iteration criterion measured:
//! * GEMM peak: `2 m^3` flops for an `m x m` product;
//! * Hessian-vector product: `4 n D K` (`NewtonProblem::hessian_vector_product_flops`: the
//!   two products with the `n x D` design matrix), also as a share of the 2-core GEMM peak
//!   when the `gemm_peak` group ran in the same invocation;
//! * Hessian assembly, as actually computed: `2 n T Q` with `T = D(D+1)/2`, `Q = K(K-1)/2`,
//!   `D = d + 1` (`NewtonProblem::hessian_flops`), and the textbook-equivalent count
//!   `2 n D^2 K(K+1)/2` of assembling every upper block as a full GEMM
//!   (`NewtonProblem::hessian_flops_textbook`), which is what an implementation without
//!   the symmetry savings would have to compute.
//!
//! Data are generated lazily, so a filter (`cargo bench -p camloc-learning -- paper`) skips
//! the cost of the groups it excludes.

#[path = "../tests/support/mod.rs"]
mod support;

use std::hint::black_box;
use std::sync::Mutex;
use std::time::{Duration, Instant};

use camloc_learning::{
    DesignRows, DirectionSolver, Features, LogisticRegression, NewtonProblem, QuadraticExpansion,
};
use criterion::{Bencher, BenchmarkId, Criterion, criterion_group, criterion_main};
use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, Par};

const D_FEATURES: usize = 74;
const K_CLASSES: usize = 12;
const PAPER_N: usize = 43_188;
/// Class-mean spread: overlapping classes (about 80% training accuracy), so that Newton
/// needs several iterations.
const SEPARATION: f64 = 0.3;
/// Fixed seed of the synthetic data.
const SEED: u64 = 2024;

/// The 2-core GEMM rate measured by the `gemm_peak` group of this run, GFLOP/s.
static GEMM_PEAK_GFLOPS: Mutex<Option<f64>> = Mutex::new(None);

/// Data and a Newton problem in a typical mid-fit state (after one iteration from zero),
/// with the direct solver, so that every timed iteration assembles and factorises the
/// Hessian (with conjugate gradients, repeating an iteration from the same point would
/// reuse the factor of that very point).
struct Setup {
    x: Vec<f64>,
    y: Vec<usize>,
    problem: NewtonProblem,
    theta: Vec<f64>,
}

impl Setup {
    fn new(n: usize) -> Self {
        let (x, y) = support::gaussian_classes(n, D_FEATURES, K_CLASSES, SEPARATION, 3.0, SEED);
        let features = Features::new(&x, D_FEATURES).expect("valid features");
        let mut problem = NewtonProblem::new(
            &features,
            &y,
            K_CLASSES,
            &LogisticRegression::default().with_direction_solver(DirectionSolver::Cholesky),
        )
        .expect("valid problem");
        problem.newton_step().expect("first step");
        let theta = problem.parameters().to_vec();
        Self {
            x,
            y,
            problem,
            theta,
        }
    }
}

/// Times `routine` per iteration with criterion's `iter_custom`, keeping the fastest
/// per-iteration time seen in `best`. `prepare` runs untimed before each iteration.
fn timed<S>(
    bench: &mut Bencher<'_>,
    state: &mut S,
    best: &mut Duration,
    mut prepare: impl FnMut(&mut S),
    mut routine: impl FnMut(&mut S),
) {
    bench.iter_custom(|iters| {
        let mut total = Duration::ZERO;
        for _ in 0..iters {
            prepare(state);
            let t = Instant::now();
            routine(state);
            let elapsed = t.elapsed();
            *best = (*best).min(elapsed);
            total += elapsed;
        }
        total
    });
}

fn gflops(flops: f64, time: Duration) -> f64 {
    flops / time.as_secs_f64() / 1e9
}

fn gemm_peak(c: &mut Criterion) {
    let m = 2048;
    let flops = 2.0 * (m as f64).powi(3);
    let mut operands: Option<(Mat<f64>, Mat<f64>, Mat<f64>)> = None;
    let mut group = c.benchmark_group("gemm_peak");
    group.sample_size(10);
    for (name, par) in [("seq", Par::Seq), ("rayon", Par::rayon(0))] {
        let mut best = Duration::MAX;
        group.bench_function(BenchmarkId::new("2048", name), |bench| {
            let ops = operands.get_or_insert_with(|| {
                (
                    Mat::from_fn(m, m, |i, j| ((i * 7 + j * 13) % 17) as f64 * 0.1),
                    Mat::from_fn(m, m, |i, j| ((i * 5 + j * 3) % 11) as f64 * 0.1),
                    Mat::zeros(m, m),
                )
            });
            timed(
                bench,
                ops,
                &mut best,
                |_| {},
                |(a, b, out)| {
                    matmul(
                        out.as_mut(),
                        Accum::Replace,
                        a.as_ref(),
                        b.as_ref(),
                        1.0,
                        par,
                    )
                },
            );
        });
        if best < Duration::MAX {
            let rate = gflops(flops, best);
            eprintln!("GEMM {m}x{m}x{m} {name}: {rate:.1} GFLOP/s (fastest iteration)");
            if name == "rayon" {
                *GEMM_PEAK_GFLOPS
                    .lock()
                    .unwrap_or_else(std::sync::PoisonError::into_inner) = Some(rate);
            }
        }
    }
    group.finish();
}

fn newton_benches(c: &mut Criterion, label: &str, n: usize) {
    let mut setup: Option<Setup> = None;
    let mut group = c.benchmark_group(label);
    group.sample_size(10);
    group.warm_up_time(Duration::from_secs(1));

    let mut best = Duration::MAX;
    group.bench_function("hessian", |bench| {
        let s = setup.get_or_insert_with(|| Setup::new(n));
        s.problem
            .set_parameters(&s.theta)
            .expect("valid parameters");
        timed(
            bench,
            &mut s.problem,
            &mut best,
            |_| {},
            |p| p.assemble_hessian(),
        );
    });
    if let Some(s) = setup.as_ref().filter(|_| best < Duration::MAX) {
        eprintln!(
            "{label}: Hessian assembly {:.1} ms (fastest): {:.1} GFLOP/s as computed \
             ({:.3e} flops), {:.1} GFLOP/s textbook-equivalent ({:.3e} flops)",
            best.as_secs_f64() * 1e3,
            gflops(s.problem.hessian_flops(), best),
            s.problem.hessian_flops(),
            gflops(s.problem.hessian_flops_textbook(), best),
            s.problem.hessian_flops_textbook(),
        );
    }

    let mut best = Duration::MAX;
    let mut product_input = Vec::new();
    group.bench_function("hessian_vector_product", |bench| {
        let s = setup.get_or_insert_with(|| Setup::new(n));
        s.problem
            .set_parameters(&s.theta)
            .expect("valid parameters");
        // Any vector of the right size: the product's cost does not depend on its values.
        product_input = s.theta.iter().map(|t| 1.0 - t).collect();
        let mut out = vec![0.0; product_input.len()];
        timed(
            bench,
            &mut s.problem,
            &mut best,
            |_| {},
            |p| {
                p.hessian_vector_product(&product_input, &mut out)
                    .expect("sizes match");
                black_box(&out);
            },
        );
    });
    if let Some(s) = setup.as_ref().filter(|_| best < Duration::MAX) {
        let rate = gflops(s.problem.hessian_vector_product_flops(), best);
        let peak = *GEMM_PEAK_GFLOPS
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let share = peak.map_or_else(String::new, |peak| {
            format!(
                ", {:.0}% of the 2-core GEMM peak {peak:.1} GFLOP/s",
                100.0 * rate / peak
            )
        });
        eprintln!(
            "{label}: Hessian-vector product {:.3} ms (fastest): {rate:.1} GFLOP/s ({:.3e} \
             flops){share}",
            best.as_secs_f64() * 1e3,
            s.problem.hessian_vector_product_flops(),
        );
    }

    let mut best = Duration::MAX;
    group.bench_function("newton_iteration", |bench| {
        let s = setup.get_or_insert_with(|| Setup::new(n));
        let theta = s.theta.clone();
        timed(
            bench,
            &mut s.problem,
            &mut best,
            |p| p.set_parameters(&theta).expect("valid parameters"),
            |p| {
                black_box(p.newton_step().expect("step"));
            },
        );
    });
    if best < Duration::MAX {
        eprintln!(
            "{label}: Newton iteration {:.1} ms (fastest)",
            best.as_secs_f64() * 1e3
        );
    }

    for (name, solver) in [
        ("fit", DirectionSolver::PreconditionedCg),
        ("fit_cholesky_every_iteration", DirectionSolver::Cholesky),
    ] {
        let mut best = Duration::MAX;
        let mut summary = String::new();
        group.bench_function(name, |bench| {
            let s = setup.get_or_insert_with(|| Setup::new(n));
            let features = Features::new(&s.x, D_FEATURES).expect("valid features");
            let config = LogisticRegression::default().with_direction_solver(solver);
            timed(
                bench,
                &mut (),
                &mut best,
                |_| {},
                |()| {
                    let (_, report) = config.fit(&features, &s.y, K_CLASSES).expect("fit");
                    summary = format!(
                        "{} Newton iterations, {} Hessian assemblies, {} CG products",
                        report.newton_iterations(),
                        report.hessian_assemblies(),
                        report.cg_products()
                    );
                    black_box(report);
                },
            );
        });
        if best < Duration::MAX {
            eprintln!(
                "{label}: {name} {:.1} ms (fastest), {summary}",
                best.as_secs_f64() * 1e3
            );
        }
    }
    group.finish();
}

fn paper_size(c: &mut Criterion) {
    newton_benches(c, "paper", PAPER_N);
}

fn ten_times(c: &mut Criterion) {
    newton_benches(c, "large", 10 * PAPER_N);
}

/// Samples of the quadratic group: a quarter of the default model's training rows.
const QUADRATIC_N: usize = 300_000;
/// Components of the quadratic group's expansion (the default model's).
const QUADRATIC_COMPONENTS: usize = 30;

/// One Hessian-vector product on the default model's problem shape (74 features expanded
/// by 30 components to 519, 12 classes), with the expanded design matrix stored whole and
/// generated chunk by chunk from the features and components.
fn quadratic(c: &mut Criterion) {
    let mut group = c.benchmark_group("quadratic");
    group.sample_size(10);
    group.warm_up_time(Duration::from_secs(1));
    let mut data = None;
    for generated in [false, true] {
        let name = if generated {
            "hessian_vector_product_generated"
        } else {
            "hessian_vector_product_stored"
        };
        let mut best = Duration::MAX;
        let mut problem = None;
        group.bench_function(name, |bench| {
            let (x, y, expansion) = data.get_or_insert_with(|| {
                let (x, y) = support::gaussian_classes(
                    QUADRATIC_N,
                    D_FEATURES,
                    K_CLASSES,
                    SEPARATION,
                    3.0,
                    SEED,
                );
                let features = Features::new(&x, D_FEATURES).expect("valid features");
                let expansion =
                    QuadraticExpansion::fit(&features, QUADRATIC_COMPONENTS).expect("expansion");
                (x, y, expansion)
            });
            let problem: &mut NewtonProblem = problem.get_or_insert_with(|| {
                let features = Features::new(x, D_FEATURES).expect("valid features");
                let config = LogisticRegression::default();
                let mut problem = if generated {
                    let rows = DesignRows::expanded(features, expansion).expect("rows");
                    NewtonProblem::from_rows(&rows, y, K_CLASSES, &config)
                } else {
                    let stored = expansion.expand_rows(&features).expect("expanded");
                    let stored = Features::new(&stored, expansion.n_outputs()).expect("rows");
                    NewtonProblem::new(&stored, y, K_CLASSES, &config)
                }
                .expect("valid problem");
                problem.newton_step().expect("first step");
                problem
            });
            let input: Vec<f64> = problem.parameters().iter().map(|t| 1.0 - t).collect();
            let mut out = vec![0.0; input.len()];
            timed(
                bench,
                problem,
                &mut best,
                |_| {},
                |p| {
                    p.hessian_vector_product(&input, &mut out)
                        .expect("sizes match");
                    black_box(&out);
                },
            );
        });
        if let Some(p) = problem.as_ref().filter(|_| best < Duration::MAX) {
            eprintln!(
                "quadratic: {name} {:.1} ms (fastest): {:.1} GFLOP/s ({:.3e} flops)",
                best.as_secs_f64() * 1e3,
                gflops(p.hessian_vector_product_flops(), best),
                p.hessian_vector_product_flops(),
            );
        }
    }
    group.finish();
}

fn predict(c: &mut Criterion) {
    let mut model = None;
    let mut out = vec![0.0; K_CLASSES];
    c.bench_function("predict_proba_into", |bench| {
        let (model, sample) = model.get_or_insert_with(|| {
            let (x, y) =
                support::gaussian_classes(4000, D_FEATURES, K_CLASSES, SEPARATION, 3.0, SEED);
            let features = Features::new(&x, D_FEATURES).expect("valid features");
            let (model, _) = LogisticRegression::default()
                .fit(&features, &y, K_CLASSES)
                .expect("fit");
            (model, x[..D_FEATURES].to_vec())
        });
        bench.iter(|| {
            model
                .predict_proba_into(black_box(sample), &mut out)
                .expect("valid sample");
            black_box(&out);
        })
    });
}

criterion_group!(
    benches, predict, gemm_peak, paper_size, ten_times, quadratic
);
criterion_main!(benches);
