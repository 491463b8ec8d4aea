"""scikit-learn side of `cargo xtask compare-sklearn`.

Loads the design matrix written by the xtask (x.npy: n x d float64, already standardised;
y.npy: n int64 labels in 0..K), fits scikit-learn's multinomial LogisticRegression with each
requested solver, and prints one JSON document on stdout:

    {"python": ..., "numpy": ..., "sklearn": ..., "blas": [...],
     "camloc_objective": f,            # objective of camloc's coefficients, evaluated here
     "solvers": [{"solver", "wall_s" (one per repeat), "n_iter", "objective",
                  "coef" (K x d), "intercept" (K), "warnings"}]}

Objective (camloc's definition, crates/camloc-learning/src/config.rs):
    f(W, b) = -sum_i log softmax(W x_i + b)_{y_i} + lambda * ||W||_F^2,
a sum over samples with the intercept unpenalised; scikit-learn minimises
C * sum_i loss_i + ||W||_F^2 / 2, the same minimiser for C = 1 / (2 lambda).

Thread counts are taken from the environment (OMP_NUM_THREADS, OPENBLAS_NUM_THREADS, ...),
which the xtask sets before starting this script.
"""

import argparse
import json
import platform
import sys
import time
import warnings


def parse_args():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dir", required=True, help="folder holding x.npy, y.npy, camloc_w.npy, camloc_b.npy")
    parser.add_argument("--lambda", dest="lam", type=float, required=True, help="ridge weight lambda > 0")
    parser.add_argument("--tol", type=float, required=True, help="scikit-learn tol (gradient of the mean loss)")
    parser.add_argument("--max-iter", type=int, required=True)
    parser.add_argument("--repeats", type=int, required=True, help="fits per solver (wall time of each)")
    parser.add_argument("--solvers", required=True, help="comma-separated scikit-learn solvers")
    return parser.parse_args()


def objective(np, x, y, coef, intercept, lam):
    """camloc's objective: summed negative log-likelihood plus lambda * ||coef||_F^2."""
    z = x @ coef.T + intercept
    top = z.max(axis=1)
    log_norm = top + np.log(np.exp(z - top[:, None]).sum(axis=1))
    nll = float((log_norm - z[np.arange(z.shape[0]), y]).sum())
    return nll + lam * float((coef * coef).sum())


def version_tuple(text):
    parts = []
    for piece in text.split(".")[:2]:
        digits = "".join(ch for ch in piece if ch.isdigit())
        parts.append(int(digits) if digits else 0)
    return tuple(parts)


def main():
    args = parse_args()
    import numpy as np
    import sklearn
    from sklearn.linear_model import LogisticRegression
    from threadpoolctl import threadpool_info

    if version_tuple(sklearn.__version__) < (1, 6):
        sys.exit(
            f"scikit-learn {sklearn.__version__} is too old: multinomial 'newton-cholesky' "
            "needs scikit-learn >= 1.6"
        )
    if args.lam <= 0:
        sys.exit(f"lambda must be > 0 for scikit-learn (C = 1 / (2 lambda)), got {args.lam}")

    x = np.load(f"{args.dir}/x.npy")
    y = np.load(f"{args.dir}/y.npy")
    camloc_w = np.load(f"{args.dir}/camloc_w.npy")  # d x K, feature-major like camloc
    camloc_b = np.load(f"{args.dir}/camloc_b.npy")
    if x.ndim != 2 or y.shape != (x.shape[0],):
        sys.exit(f"bad shapes: x {x.shape}, y {y.shape}")
    n_classes = int(y.max()) + 1
    if np.unique(y).size != n_classes:
        sys.exit("every class 0..K-1 must occur in y (scikit-learn drops absent classes)")
    x = np.ascontiguousarray(x, dtype=np.float64)

    c = 1.0 / (2.0 * args.lam)
    results = []
    for solver in args.solvers.split(","):
        times = []
        model = None
        caught = []
        for _ in range(args.repeats):
            model = LogisticRegression(solver=solver, C=c, tol=args.tol, max_iter=args.max_iter)
            with warnings.catch_warnings(record=True) as recorded:
                warnings.simplefilter("always")
                start = time.perf_counter()
                model.fit(x, y)
                times.append(time.perf_counter() - start)
            caught = sorted({f"{w.category.__name__}: {w.message}" for w in recorded})
        if model.coef_.shape != (n_classes, x.shape[1]):
            sys.exit(f"{solver}: coef_ has shape {model.coef_.shape}, expected a multinomial fit")
        results.append(
            {
                "solver": solver,
                "wall_s": times,
                "n_iter": int(np.max(model.n_iter_)),
                "objective": objective(np, x, y, model.coef_, model.intercept_, args.lam),
                "coef": model.coef_.tolist(),
                "intercept": model.intercept_.tolist(),
                "warnings": caught,
            }
        )

    report = {
        "python": platform.python_version(),
        "numpy": np.__version__,
        "sklearn": sklearn.__version__,
        "blas": [
            {k: info.get(k) for k in ("internal_api", "version", "num_threads")}
            for info in threadpool_info()
        ],
        "camloc_objective": objective(np, x, y, camloc_w.T, camloc_b, args.lam),
        "solvers": results,
    }
    json.dump(report, sys.stdout)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main()
