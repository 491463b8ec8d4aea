//! The scikit-learn side of `compare-sklearn`: the virtual environment, the `.npy` inputs
//! and the run of `xtask/python/compare_sklearn.py`.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use camloc::learning::LogisticModel;
use serde::Deserialize;

use super::problem::Problem;
use super::{Args, SKLEARN_SOLVERS};

/// Environment variables that set the thread count of the BLAS and OpenMP runtimes
/// numpy and scikit-learn may use.
pub const THREAD_VARIABLES: [&str; 3] =
    ["OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"];

/// What the Python script prints (see its docstring).
#[derive(Deserialize)]
pub struct SklearnReport {
    pub python: String,
    pub numpy: String,
    pub sklearn: String,
    pub blas: Vec<BlasPool>,
    /// Objective of camloc's coefficients, evaluated by numpy.
    pub camloc_objective: f64,
    pub solvers: Vec<SklearnFit>,
}

/// One thread pool found by threadpoolctl.
#[derive(Deserialize)]
pub struct BlasPool {
    pub internal_api: Option<String>,
    pub version: Option<String>,
    pub num_threads: Option<usize>,
}

/// One scikit-learn solver's fits.
#[derive(Deserialize)]
pub struct SklearnFit {
    pub solver: String,
    /// Wall time of every repeat of `.fit`, seconds.
    pub wall_s: Vec<f64>,
    pub n_iter: usize,
    /// Objective evaluated by numpy (not done for the direct-solver row).
    pub objective: f64,
    /// `K x d`, class-major.
    pub coef: Vec<Vec<f64>>,
    pub intercept: Vec<f64>,
    pub warnings: Vec<String>,
}

/// Deletes a folder (and its content) when dropped.
pub struct TempDir(pub PathBuf);

impl Drop for TempDir {
    fn drop(&mut self) {
        // Best effort: a leftover folder in the system temp dir is harmless.
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// The Python of the virtual environment `target/sklearn-venv`, created with
/// `python3 -m venv` and filled by `pip install numpy scikit-learn` when needed.
pub fn sklearn_python(root: &Path) -> Result<PathBuf, String> {
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
pub fn write_inputs(folder: &Path, problem: &Problem, model: &LogisticModel) -> Result<(), String> {
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
pub fn run_sklearn(
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
