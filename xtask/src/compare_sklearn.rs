//! `cargo xtask compare-sklearn`: camloc's Newton solver side by side with scikit-learn's
//! `newton-cholesky` and `lbfgs` solvers on the same design matrix.
//!
//! The command builds a problem (overlapping Gaussian classes of the paper's size by default,
//! the landmark descriptors of a camloc dataset file, or the default model's real training
//! problem), standardises it once (column mean 0,
//! population standard deviation 1; constant columns are only centred) and fits camloc on
//! it with camloc's own standardisation switched off, so that both libraries solve exactly
//! the same problem. It then writes the matrix, the labels and camloc's coefficients as
//! `.npy` files to a temporary folder and runs `xtask/python/compare_sklearn.py` with the
//! Python of a virtual environment in `target/sklearn-venv` (created on first use, with
//! `numpy` and `scikit-learn` installed by pip from PyPI).
//!
//! Every final objective is evaluated twice, by camloc's [`LogisticModel::objective`] (the
//! table) and by numpy (a cross-check of the definition, printed below the table).

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

use camloc::Descriptor;
use camloc::learning::{
    DirectionSolver, Features, FitReport, LogisticModel, LogisticRegression, Mode,
    QuadraticExpansion, Standardiser,
};

mod problem;
mod python;

use problem::Problem;
use python::{SklearnFit, SklearnReport, THREAD_VARIABLES, TempDir};

/// The scikit-learn solvers compared with camloc, in table order.
pub const SKLEARN_SOLVERS: [&str; 2] = ["newton-cholesky", "lbfgs"];
/// Arguments of `compare-sklearn`.
#[derive(clap::Args)]
pub struct Args {
    /// Number of synthetic samples (the paper's training set size).
    #[arg(long, default_value_t = 43_188)]
    pub n: usize,
    /// Number of synthetic features.
    #[arg(long, default_value_t = 74)]
    pub d: usize,
    /// Number of synthetic classes.
    #[arg(long, default_value_t = 12)]
    pub k: usize,
    /// Seed of the synthetic data.
    #[arg(long, default_value_t = 2024)]
    pub seed: u64,
    /// Use the landmark descriptors of the complete poses of this camloc dataset file
    /// (labels = camera label - 1) instead of synthetic data.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["n", "d", "k", "seed"])]
    pub dataset: Option<PathBuf>,
    /// Use the default model's real training problem instead of synthetic data: the
    /// descriptors (joints) and camera labels of the complete poses of the dataset
    /// `cargo xtask train-default` generates, built by the same code from the motion
    /// capture (see --mocap).
    #[arg(long, conflicts_with_all = ["n", "d", "k", "seed", "dataset"])]
    pub default_training_set: bool,
    /// Motion capture folders of --default-training-set [default: $CAMLOC_DATA/cmu, else
    /// ../shared/data/cmu].
    #[arg(long = "mocap", value_name = "DIR", requires = "default_training_set")]
    pub mocap: Vec<PathBuf>,
    /// Ridge weight lambda on the squared weights (scikit-learn's C = 1 / (2 lambda)).
    #[arg(long, default_value_t = 1.0)]
    pub lambda: f64,
    /// Every solver stops when the infinity norm of the gradient of the mean objective
    /// (objective / n) is at most this: camloc's `gradient_tolerance`, scikit-learn's `tol`.
    /// Newton's method converges quadratically, so at 1e-8 the objective is already at its
    /// optimum to rounding precision; much tighter values fall below what the objective's
    /// rounding lets a line search resolve.
    #[arg(long, default_value_t = 1e-8)]
    pub tol: f64,
    /// Iteration cap of every solver.
    #[arg(long, default_value_t = 1000)]
    pub max_iter: usize,
    /// Fits per solver; the table reports the fastest.
    #[arg(long, default_value_t = 3)]
    pub repeats: usize,
    /// Threads of camloc's rayon pool and of scikit-learn's BLAS/OpenMP [default: the
    /// number of cores].
    #[arg(long)]
    pub threads: Option<usize>,
    /// Print the table as Markdown, with a line describing the machine.
    #[arg(long)]
    pub markdown: bool,
}

/// camloc's fits of the problem with one solver configuration.
struct CamlocFits {
    /// Wall time of every fit, seconds.
    times: Vec<f64>,
    /// The first fit's model and report (all fits are identical).
    model: LogisticModel,
    report: FitReport,
}

impl CamlocFits {
    /// `"7 (2 Hessians assembled, 31 CG products)"`.
    fn iterations_cell(&self) -> String {
        format!(
            "{} ({} Hessians assembled, {} CG products)",
            self.report.newton_iterations(),
            self.report.hessian_assemblies(),
            self.report.cg_products()
        )
    }
}

/// Fits `repeats` times with `estimator`, logging the first fit's iterations to stderr.
fn fit_camloc(
    estimator: &LogisticRegression,
    features: &Features<'_>,
    problem: &Problem,
    repeats: usize,
) -> Result<CamlocFits, String> {
    eprintln!(
        "fitting camloc, {:?} direction solver ({repeats} times)",
        estimator.direction_solver
    );
    let timed_fit = |log: bool| {
        let start = Instant::now();
        let fit = estimator
            .fit_with_progress(features, &problem.y, problem.n_classes, |it| {
                if log {
                    eprintln!(
                        "  camloc newton {:>3}: objective {:.15e}  |grad|_inf {:.3e}  step {}  {}",
                        it.iteration,
                        it.objective,
                        it.gradient_norm,
                        it.step,
                        it.direction_summary()
                    );
                }
            })
            .map_err(|e| format!("camloc fit: {e}"))?;
        Ok::<_, String>((start.elapsed().as_secs_f64(), fit))
    };
    let (first_time, (model, report)) = timed_fit(true)?;
    let mut times = vec![first_time];
    for _ in 1..repeats {
        times.push(timed_fit(false)?.0);
    }
    Ok(CamlocFits {
        times,
        model,
        report,
    })
}

/// One line of the table.
struct Row {
    solver: String,
    /// Fastest wall time over the repeats, seconds.
    wall_s: f64,
    /// Iterations (for camloc, with how many Hessians were assembled).
    iterations: String,
    /// Objective evaluated by camloc.
    objective: f64,
    /// Objective evaluated by numpy (not done for the direct-solver row).
    objective_numpy: Option<f64>,
}

/// Runs `compare-sklearn`.
pub fn run(args: &Args) -> Result<(), String> {
    if args.repeats == 0 {
        return Err("--repeats must be at least 1".into());
    }
    if !(args.lambda.is_finite() && args.lambda > 0.0) {
        return Err(format!(
            "--lambda must be finite and > 0 (scikit-learn's C = 1 / (2 lambda)), got {}",
            args.lambda
        ));
    }
    let threads = match args.threads {
        Some(0) => return Err("--threads must be at least 1".into()),
        Some(t) => t,
        None => std::thread::available_parallelism().map_or(1, usize::from),
    };
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build_global()
        .map_err(|e| format!("cannot set up {threads} rayon threads: {e}"))?;

    let root = crate::workspace_root();
    let script = root.join("xtask").join("python").join("compare_sklearn.py");
    if !script.is_file() {
        return Err(format!("{}: script not found", script.display()));
    }
    let python = python::sklearn_python(&root)?;

    let mut problem = match &args.dataset {
        _ if args.default_training_set => problem::default_training_set(&args.mocap)?,
        Some(path) => problem::from_dataset(path)?,
        None => problem::synthetic(args.n, args.d, args.k, args.seed)?,
    };
    problem::standardise(&mut problem.x, problem.n_features)?;
    eprintln!("problem: {}", problem.description);
    let components = camloc::DEFAULT_QUADRATIC_COMPONENTS;
    println!(
        "camloc descriptor sizes (features per pose, and weights d x K of a 12-camera model): {}",
        ["joints", "landmarks", "paper"]
            .iter()
            .filter_map(|name| Descriptor::from_name(name).ok())
            .flat_map(|d| {
                let expanded = QuadraticExpansion::output_len(d.len(), components);
                [
                    format!("{} {} ({})", d.name(), d.len(), 12 * d.len()),
                    format!(
                        "{} + quadratic-{components} {expanded} ({})",
                        d.name(),
                        12 * expanded
                    ),
                ]
            })
            .collect::<Vec<_>>()
            .join(", ")
    );

    let features = Features::new(&problem.x, problem.n_features).map_err(|e| e.to_string())?;
    let estimator = LogisticRegression::default()
        .with_lambda(args.lambda)
        .with_gradient_tolerance(args.tol)
        .with_max_iter(args.max_iter)
        .with_standardise(false);
    let camloc = fit_camloc(&estimator, &features, &problem, args.repeats)?;
    let direct = fit_camloc(
        &estimator
            .clone()
            .with_direction_solver(DirectionSolver::Cholesky),
        &features,
        &problem,
        args.repeats,
    )?;
    let (model, report) = (&camloc.model, &camloc.report);
    let camloc_objective = model
        .objective(&features, &problem.y)
        .map_err(|e| format!("camloc objective: {e}"))?;

    let folder = TempDir(
        std::env::temp_dir().join(format!("camloc-compare-sklearn-{}", std::process::id())),
    );
    std::fs::create_dir_all(&folder.0).map_err(|e| format!("{}: {e}", folder.0.display()))?;
    python::write_inputs(&folder.0, &problem, model)?;
    eprintln!(
        "fitting scikit-learn {} ({} times each, {threads} BLAS/OpenMP threads)",
        SKLEARN_SOLVERS.join(", "),
        args.repeats
    );
    let sklearn = python::run_sklearn(&python, &script, &folder.0, args, threads)?;

    let mut rows = vec![
        Row {
            solver: "camloc (truncated Newton-CG, subsampled preconditioner, default)".into(),
            wall_s: fastest(&camloc.times),
            iterations: camloc.iterations_cell(),
            objective: camloc_objective,
            objective_numpy: Some(sklearn.camloc_objective),
        },
        Row {
            solver: "camloc (Newton; Hessian + Cholesky every iteration)".into(),
            wall_s: fastest(&direct.times),
            iterations: direct.iterations_cell(),
            objective: direct
                .model
                .objective(&features, &problem.y)
                .map_err(|e| format!("camloc objective: {e}"))?,
            objective_numpy: None,
        },
    ];
    for fit in &sklearn.solvers {
        rows.push(Row {
            solver: format!("scikit-learn {}", fit.solver),
            wall_s: fastest(&fit.wall_s),
            iterations: fit.n_iter.to_string(),
            objective: camloc_objective_of(fit, &problem, &features, args.lambda)?,
            objective_numpy: Some(fit.objective),
        });
    }

    let mut notes = Vec::new();
    if !report.converged {
        notes.push(format!(
            "camloc did not converge: {:?} after {} iterations",
            report.termination,
            report.newton_iterations()
        ));
    }
    for fit in &sklearn.solvers {
        notes.extend(fit.warnings.iter().map(|w| format!("{}: {w}", fit.solver)));
    }
    print!(
        "{}",
        render(&rows, &problem, args, threads, &sklearn, &notes)
    );
    Ok(())
}

/// Objective of a scikit-learn fit's coefficients, evaluated by camloc.
fn camloc_objective_of(
    fit: &SklearnFit,
    problem: &Problem,
    features: &Features<'_>,
    lambda: f64,
) -> Result<f64, String> {
    let d = problem.n_features;
    if fit.coef.len() != problem.n_classes || fit.coef.iter().any(|row| row.len() != d) {
        return Err(format!(
            "scikit-learn {}: coef_ is not {} x {d}",
            fit.solver, problem.n_classes
        ));
    }
    // scikit-learn's coef_ is class-major (K x d); camloc's weights are feature-major.
    let weights = (0..d)
        .flat_map(|j| fit.coef.iter().map(move |row| row[j]))
        .collect();
    let model = LogisticModel::new(
        Mode::Multinomial,
        lambda,
        Standardiser::identity(d),
        weights,
        fit.intercept.clone(),
    )
    .map_err(|e| format!("scikit-learn {}: coefficients: {e}", fit.solver))?;
    model
        .objective(features, &problem.y)
        .map_err(|e| format!("scikit-learn {}: objective: {e}", fit.solver))
}

/// Smallest of `times` (infinity for none).
fn fastest(times: &[f64]) -> f64 {
    times.iter().copied().fold(f64::INFINITY, f64::min)
}

/// The table (plain or Markdown) and the notes that make it reproducible.
fn render(
    rows: &[Row],
    problem: &Problem,
    args: &Args,
    threads: usize,
    sklearn: &SklearnReport,
    notes: &[String],
) -> String {
    let best = rows
        .iter()
        .map(|r| r.objective)
        .fold(f64::INFINITY, f64::min);
    let camloc_time = rows.first().map_or(f64::NAN, |r| r.wall_s);
    let header = [
        "solver",
        "wall time (s)",
        "iterations",
        "final objective",
        "rel. diff vs best",
        "time / camloc default time",
    ];
    let cells: Vec<[String; 6]> = rows
        .iter()
        .enumerate()
        .map(|(i, r)| {
            [
                r.solver.clone(),
                format!("{:.3}", r.wall_s),
                r.iterations.clone(),
                format!("{:.12e}", r.objective),
                format!("{:.1e}", (r.objective - best) / best.abs()),
                if i == 0 {
                    "1 (reference)".into()
                } else {
                    format!("{:.1}", r.wall_s / camloc_time)
                },
            ]
        })
        .collect();

    let mut out = String::new();
    if args.markdown {
        let _ = writeln!(out, "| {} |", header.join(" | "));
        let _ = writeln!(out, "|{}", "---|".repeat(header.len()));
        for row in &cells {
            let _ = writeln!(out, "| {} |", row.join(" | "));
        }
    } else {
        let widths: Vec<usize> = (0..header.len())
            .map(|c| {
                cells
                    .iter()
                    .map(|row| row[c].len())
                    .chain([header[c].len()])
                    .max()
                    .unwrap_or(0)
            })
            .collect();
        let line = |values: &[&str]| {
            let padded: Vec<String> = values
                .iter()
                .zip(&widths)
                .map(|(v, w)| format!("{v:<w$}"))
                .collect();
            format!("{}\n", padded.join(" | ").trim_end())
        };
        out.push_str(&line(&header));
        let rule: Vec<String> = widths.iter().map(|w| "-".repeat(*w)).collect();
        out.push_str(&line(&rule.iter().map(String::as_str).collect::<Vec<_>>()));
        for row in &cells {
            out.push_str(&line(&row.iter().map(String::as_str).collect::<Vec<_>>()));
        }
    }

    out.push('\n');
    let bullet = if args.markdown { "- " } else { "  " };
    let mut note = |text: String| {
        let _ = writeln!(out, "{bullet}{text}");
    };
    note(format!(
        "Problem: {}; lambda = {} (scikit-learn C = 1 / (2 lambda) = {}).",
        problem.description,
        args.lambda,
        1.0 / (2.0 * args.lambda)
    ));
    note(
        "Both sides fit the same matrix, standardised once by this command (column mean 0, \
         standard deviation 1); camloc runs with `standardise: false`, so both solve the \
         identical multinomial problem, intercepts unpenalised. Objective: \
         -sum_i log softmax(W x_i + b)_{y_i} + lambda ||W||_F^2, evaluated by camloc."
            .into(),
    );
    note(format!(
        "Stopping: infinity norm of the gradient of the mean objective <= {:e} for every \
         solver (camloc's gradient_tolerance, scikit-learn's tol); at most {} iterations. \
         Wall time: fastest of {} fits, fit only (camloc: LogisticRegression::fit, \
         scikit-learn: .fit, each including its input copies and checks).",
        args.tol, args.max_iter, args.repeats
    ));
    let pools: Vec<String> = sklearn
        .blas
        .iter()
        .map(|p| {
            format!(
                "{} {} with {} threads",
                p.internal_api.as_deref().unwrap_or("?"),
                p.version.as_deref().unwrap_or("?"),
                p.num_threads.map_or_else(|| "?".into(), |t| t.to_string())
            )
        })
        .collect();
    note(format!(
        "Threads: camloc {threads} (rayon pool; faer and the Hessian assembly run on it); \
         scikit-learn {} = {threads} ({}). Python {}, numpy {}, scikit-learn {}.",
        THREAD_VARIABLES.join(" = "),
        if pools.is_empty() {
            "threadpoolctl found no BLAS/OpenMP pool".to_string()
        } else {
            format!("threadpoolctl: {}", pools.join("; "))
        },
        sklearn.python,
        sklearn.numpy,
        sklearn.sklearn
    ));
    let evaluator_gap = rows
        .iter()
        .filter_map(|r| {
            r.objective_numpy
                .map(|o| ((r.objective - o) / r.objective.abs()).abs())
        })
        .fold(0.0, f64::max);
    note(format!(
        "Cross-check: camloc's and numpy's evaluations of each objective (camloc's default \
         fit and every scikit-learn fit) differ by at most {evaluator_gap:.1e} relative."
    ));
    for text in notes {
        note(format!("Warning: {text}"));
    }
    if args.markdown {
        note(format!("Machine: {}.", crate::report::machine()));
    }
    let command: Vec<String> = std::env::args().skip(1).collect();
    note(format!("Command: `cargo xtask {}`.", command.join(" ")));
    out
}
