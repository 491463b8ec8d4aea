//! `cargo xtask compare-sklearn`: camloc's Newton solver side by side with scikit-learn's
//! `newton-cholesky` and `lbfgs` solvers on the same design matrix.
//!
//! The command builds a problem (overlapping Gaussian classes of the paper's size by default,
//! or the landmark descriptors of a camloc dataset file), standardises it once (column mean 0,
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
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Instant;

use camloc::Descriptor;
use camloc::dataset::{Dataset, Sample};
use camloc::learning::{
    DirectionSolver, Features, FitReport, LogisticModel, LogisticRegression, Mode,
    QuadraticExpansion, Standardiser,
};
use camloc::store::Persist;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use serde::Deserialize;

/// The scikit-learn solvers compared with camloc, in table order.
const SKLEARN_SOLVERS: [&str; 2] = ["newton-cholesky", "lbfgs"];
/// Standard deviation of each coordinate of a synthetic class mean, in units of the
/// within-class standard deviation: small enough that the classes overlap (about 80%
/// training accuracy), so that Newton's method needs several iterations.
const CLASS_SEPARATION: f64 = 0.3;
/// Environment variables that set the thread count of the BLAS and OpenMP runtimes
/// numpy and scikit-learn may use.
const THREAD_VARIABLES: [&str; 3] = ["OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"];

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

/// A classification problem with standardised features.
struct Problem {
    /// Row-major `n x n_features` features, every column standardised.
    x: Vec<f64>,
    /// Labels in `0..n_classes`.
    y: Vec<usize>,
    n_features: usize,
    n_classes: usize,
    /// Where the data come from, for the output.
    description: String,
}

/// What the Python script prints (see its docstring).
#[derive(Deserialize)]
struct SklearnReport {
    python: String,
    numpy: String,
    sklearn: String,
    blas: Vec<BlasPool>,
    /// Objective of camloc's coefficients, evaluated by numpy.
    camloc_objective: f64,
    solvers: Vec<SklearnFit>,
}

/// One thread pool found by threadpoolctl.
#[derive(Deserialize)]
struct BlasPool {
    internal_api: Option<String>,
    version: Option<String>,
    num_threads: Option<usize>,
}

/// One scikit-learn solver's fits.
#[derive(Deserialize)]
struct SklearnFit {
    solver: String,
    /// Wall time of every repeat of `.fit`, seconds.
    wall_s: Vec<f64>,
    n_iter: usize,
    /// Objective evaluated by numpy (not done for the direct-solver row).
    objective: f64,
    /// `K x d`, class-major.
    coef: Vec<Vec<f64>>,
    intercept: Vec<f64>,
    warnings: Vec<String>,
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
    /// `"6 (2 Hessians assembled)"`.
    fn iterations_cell(&self) -> String {
        format!(
            "{} ({} Hessians assembled)",
            self.report.newton_iterations(),
            self.report.hessian_assemblies()
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

/// Deletes a folder (and its content) when dropped.
struct TempDir(PathBuf);

impl Drop for TempDir {
    fn drop(&mut self) {
        // Best effort: a leftover folder in the system temp dir is harmless.
        let _ = std::fs::remove_dir_all(&self.0);
    }
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
    let python = sklearn_python(&root)?;

    let mut problem = match &args.dataset {
        Some(path) => from_dataset(path)?,
        None => synthetic(args.n, args.d, args.k, args.seed)?,
    };
    standardise(&mut problem.x, problem.n_features)?;
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
    write_inputs(&folder.0, &problem, model)?;
    eprintln!(
        "fitting scikit-learn {} ({} times each, {threads} BLAS/OpenMP threads)",
        SKLEARN_SOLVERS.join(", "),
        args.repeats
    );
    let sklearn = run_sklearn(&python, &script, &folder.0, args, threads)?;

    let mut rows = vec![
        Row {
            solver: "camloc (Newton; CG on the last Cholesky factor, default)".into(),
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

/// `n` samples of `d` features in `k` overlapping Gaussian classes, deterministic for a
/// seed: class means drawn from `N(0, CLASS_SEPARATION^2 I)`, samples `mean + N(0, I)`,
/// balanced labels `i mod k`.
fn synthetic(n: usize, d: usize, k: usize, seed: u64) -> Result<Problem, String> {
    if d == 0 || k < 2 || n < k {
        return Err(format!(
            "synthetic problem needs d >= 1, k >= 2 and n >= k (every class present), got \
             n = {n}, d = {d}, k = {k}"
        ));
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut gaussian = move || -> f64 { StandardNormal.sample(&mut rng) };
    let means: Vec<f64> = (0..k * d).map(|_| CLASS_SEPARATION * gaussian()).collect();
    let y: Vec<usize> = (0..n).map(|i| i % k).collect();
    let x = y
        .iter()
        .flat_map(|&label| &means[label * d..(label + 1) * d])
        .map(|mean| mean + gaussian())
        .collect();
    Ok(Problem {
        x,
        y,
        n_features: d,
        n_classes: k,
        description: format!(
            "synthetic Gaussian classes, n = {n}, d = {d}, K = {k}, class-mean spread \
             {CLASS_SEPARATION}, seed {seed}"
        ),
    })
}

/// The landmark descriptors and 0-based camera labels of the complete poses (no dropped
/// landmark) of the dataset file at `path`.
fn from_dataset(path: &Path) -> Result<Problem, String> {
    // Store errors (validation included) name the file.
    let dataset = Dataset::load(path).map_err(|e| e.to_string())?;
    let complete: Vec<(usize, &Sample)> = dataset
        .samples
        .iter()
        .enumerate()
        .filter(|(_, s)| s.missing_mask == 0)
        .collect();
    let y = complete
        .iter()
        .map(|(i, s)| {
            usize::from(s.label)
                .checked_sub(1)
                .ok_or_else(|| format!("{}: sample {i} has label 0", path.display()))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let poses: Vec<_> = complete.iter().map(|(_, s)| s.landmarks).collect();
    let descriptor = Descriptor::Landmarks;
    let x = descriptor.extract_batch(&poses).map_err(|(i, e)| {
        let sample = complete.get(i).map_or(i, |(original, _)| *original);
        format!("{}: sample {sample}: {e}", path.display())
    })?;
    let n_classes = dataset.header.cameras.len();
    Ok(Problem {
        description: format!(
            "{}: '{}' descriptors of {} complete poses ({} with dropped landmarks left \
             out), d = {}, K = {n_classes}",
            path.display(),
            descriptor.name(),
            y.len(),
            dataset.samples.len() - y.len(),
            descriptor.len()
        ),
        x,
        y,
        n_features: descriptor.len(),
        n_classes,
    })
}

/// Standardises every column of the row-major `x` (`d` columns) in place with camloc's own
/// [`Standardiser`] (column mean 0, population standard deviation 1; a constant column is
/// only centred).
fn standardise(x: &mut [f64], d: usize) -> Result<(), String> {
    let standardiser = Standardiser::fit(&Features::new(x, d).map_err(|e| e.to_string())?);
    for row in x.chunks_exact_mut(d) {
        for ((v, m), s) in row
            .iter_mut()
            .zip(standardiser.means())
            .zip(standardiser.scales())
        {
            *v = (*v - m) / s;
        }
    }
    Ok(())
}

/// The Python of the virtual environment `target/sklearn-venv`, created with
/// `python3 -m venv` and filled by `pip install numpy scikit-learn` when needed.
fn sklearn_python(root: &Path) -> Result<PathBuf, String> {
    let venv = root.join("target").join("sklearn-venv");
    let python = venv.join("bin").join("python");
    if !python.exists() {
        eprintln!(
            "creating a Python virtual environment: python3 -m venv {}",
            venv.display()
        );
        run_logged(
            Command::new("python3").args(["-m", "venv"]).arg(&venv),
            "python3 -m venv",
        )
        .map_err(|e| format!("{e} (is python3 with its venv module installed?)"))?;
    }
    let ready = Command::new(&python)
        .args(["-c", "import numpy, sklearn, threadpoolctl"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if !ready {
        eprintln!(
            "installing numpy and scikit-learn from PyPI: {} -m pip install numpy scikit-learn",
            python.display()
        );
        run_logged(
            Command::new(&python).args(["-m", "pip", "install", "numpy", "scikit-learn"]),
            "pip install numpy scikit-learn",
        )
        .map_err(|e| {
            format!(
                "{e}: could not install numpy and scikit-learn (is https://pypi.org reachable \
                 from this machine?); delete {} to start over",
                venv.display()
            )
        })?;
    }
    Ok(python)
}

/// Runs `command`, its output going to stderr (stdout is kept for the table).
fn run_logged(command: &mut Command, what: &str) -> Result<(), String> {
    let status = command
        .stdout(Stdio::from(std::io::stderr()))
        .status()
        .map_err(|e| format!("{what}: cannot start: {e}"))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!("{what}: failed ({status})"))
    }
}

/// Writes `x.npy` (`n x d`, f64), `y.npy` (`n`, i64) and camloc's coefficients
/// `camloc_w.npy` (`d x K`, feature-major) and `camloc_b.npy` (`K`) into `folder`.
fn write_inputs(folder: &Path, problem: &Problem, model: &LogisticModel) -> Result<(), String> {
    let n = problem.y.len();
    let labels = problem
        .y
        .iter()
        .map(|&label| i64::try_from(label).map(i64::to_le_bytes))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| format!("label does not fit in i64: {e}"))?
        .concat();
    write_npy(
        &folder.join("x.npy"),
        "<f8",
        &[n, problem.n_features],
        &f64_bytes(&problem.x),
    )?;
    write_npy(&folder.join("y.npy"), "<i8", &[n], &labels)?;
    write_npy(
        &folder.join("camloc_w.npy"),
        "<f8",
        &[problem.n_features, problem.n_classes],
        &f64_bytes(model.weights()),
    )?;
    write_npy(
        &folder.join("camloc_b.npy"),
        "<f8",
        &[problem.n_classes],
        &f64_bytes(model.biases()),
    )
}

/// Little-endian bytes of `values`.
fn f64_bytes(values: &[f64]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

/// Writes a C-order array in NPY format version 1.0: magic, version, header length, a
/// Python-dict header padded with spaces to a multiple of 64 bytes and ended by a newline,
/// then the raw elements. `descr` is the NumPy type string (`<f8`, `<i8`), `payload` the
/// little-endian elements.
fn write_npy(path: &Path, descr: &str, shape: &[usize], payload: &[u8]) -> Result<(), String> {
    let dims: Vec<String> = shape.iter().map(usize::to_string).collect();
    let shape = match dims.as_slice() {
        [single] => format!("({single},)"),
        _ => format!("({})", dims.join(", ")),
    };
    let mut header = format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': {shape}, }}");
    let unpadded = 10 + header.len() + 1;
    header.push_str(&" ".repeat(unpadded.next_multiple_of(64) - unpadded));
    header.push('\n');
    let header_len = u16::try_from(header.len())
        .map_err(|_| format!("{}: NPY header too long", path.display()))?;
    let mut bytes = Vec::with_capacity(10 + header.len() + payload.len());
    bytes.extend_from_slice(b"\x93NUMPY\x01\x00");
    bytes.extend_from_slice(&header_len.to_le_bytes());
    bytes.extend_from_slice(header.as_bytes());
    bytes.extend_from_slice(payload);
    std::fs::write(path, bytes).map_err(|e| format!("{}: {e}", path.display()))
}

/// Runs the Python script on the files in `folder` with `threads` BLAS/OpenMP threads.
fn run_sklearn(
    python: &Path,
    script: &Path,
    folder: &Path,
    args: &Args,
    threads: usize,
) -> Result<SklearnReport, String> {
    let output = Command::new(python)
        .arg(script)
        .arg("--dir")
        .arg(folder)
        .args(["--lambda", &args.lambda.to_string()])
        .args(["--tol", &args.tol.to_string()])
        .args(["--max-iter", &args.max_iter.to_string()])
        .args(["--repeats", &args.repeats.to_string()])
        .args(["--solvers", &SKLEARN_SOLVERS.join(",")])
        .envs(THREAD_VARIABLES.map(|v| (v, threads.to_string())))
        .stderr(Stdio::inherit())
        .output()
        .map_err(|e| format!("{}: cannot start: {e}", python.display()))?;
    if !output.status.success() {
        return Err(format!("{}: failed ({})", script.display(), output.status));
    }
    serde_json::from_slice(&output.stdout)
        .map_err(|e| format!("{}: cannot parse its JSON output: {e}", script.display()))
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
