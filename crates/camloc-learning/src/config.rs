//! The estimator configuration ([`LogisticRegression`]); fitting is in `fit.rs`.

use serde::{Deserialize, Serialize};

use crate::LearningError;

/// How the classes are modelled.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Mode {
    /// One multinomial (softmax) model, eq. 8: `P(k | x) = softmax(W x + b)_k`. The
    /// parameters are `(d + 1) K` (full parametrisation, every class has weights and a
    /// bias); the Hessian couples all classes.
    #[default]
    Multinomial,
    /// One binary L2 logistic problem per class ("class k against the rest"), eq. 9, each
    /// solved by its own Newton iteration (block-diagonal Hessian, one line search per
    /// class). Probabilities are the per-class sigmoids normalised to sum to 1.
    OneVsRest,
}

/// How each Newton system `H d = -grad f` is solved (multinomial mode; one-vs-rest always
/// uses [`DirectionSolver::Cholesky`], its blocks being small).
///
/// All of them converge to the same optimum (the stopping rule is on the gradient); they
/// differ in how much each Newton system costs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum DirectionSolver {
    /// Assemble the exact Hessian and factorise it with faer's dense Cholesky at every
    /// iteration: the exact Newton direction.
    Cholesky,
    /// Truncated Newton (Newton-CG), the default: each Newton system is solved by conjugate
    /// gradients on exact Hessian-vector products (`4 n (d + 1) K` flops each, against
    /// `O(n d^2 K^2)` for an assembly) only as far as the iteration needs, preconditioned by
    /// the Cholesky factor of a Hessian assembled on an evenly spaced subset of the samples
    /// ([`PRECONDITIONER_ROWS_PER_PARAMETER`] per parameter, at least
    /// [`MIN_PRECONDITIONER_ROWS`]; see [`preconditioner_rows`](Self::preconditioner_rows)),
    /// doubled each time a solve spends its budget of products (the subsample was too small
    /// to precondition this problem well). Otherwise the same solver as
    /// [`TruncatedCg`](Self::TruncatedCg).
    #[default]
    PreconditionedCg,
    /// Truncated Newton (Newton-CG) with a preconditioner assembled on `preconditioner_rows`
    /// samples. Each Newton system is solved by conjugate gradients on Hessian-vector
    /// products (exact, or subsampled: `product_rows` below) only to the relative residual
    /// `eta = min(0.5, sqrt(||g|| / ||g_0||))` (Eisenstat and Walker's forcing term, in the
    /// preconditioner's norm; never below `1e-10`), or until the residual, which is the
    /// gradient the quadratic model predicts after the step, is a quarter of the convergence
    /// threshold, so that early iterations are cheap and the last ones no more exact than the
    /// stopping rule needs; and at most to a trust radius in the preconditioner's norm
    /// (Steihaug), which shrinks to the part of a direction the line search accepted and
    /// doubles after a full step on it. The preconditioner is the Cholesky factor of the
    /// Hessian assembled on `preconditioner_rows` evenly spaced samples (rescaled to all
    /// samples), assembled afresh when a solve spends its budget of products. Every direction
    /// is a descent direction, so the line search and the objective behave as with the exact
    /// solver.
    /// For problems whose Hessian is too costly to assemble from every sample (many samples
    /// and a large `(d + 1) K`, e.g. after a [`QuadraticExpansion`](crate::QuadraticExpansion)).
    ///
    /// With `product_rows` below the number of samples, the conjugate-gradient products use
    /// the Hessian of an evenly spaced subset of the samples (whole blocks of consecutive
    /// rows, rescaled to all samples) instead of the exact one: subsampled Newton-CG (Byrd,
    /// Chin, Neveitt and Nocedal, 2011). The gradient, the objective and the line search stay
    /// exact, and the subsampled Hessian is positive definite, so every direction is still a
    /// descent direction and the fit stops at the same gradient tolerance; each product costs
    /// `product_rows / n` of an exact one, at the price of a less exact Newton direction.
    TruncatedCg {
        /// Samples the preconditioning Hessian is assembled on (all of them when there are
        /// fewer); at least 1.
        preconditioner_rows: usize,
        /// Samples, at least, the Hessian-vector products of conjugate gradients are computed
        /// on (every sample when there are fewer, which makes the products exact); at least 1.
        product_rows: usize,
    },
}

impl DirectionSolver {
    /// Samples the preconditioning Hessian is assembled on, for a problem of `n_samples`
    /// samples and `n_parameters = (d + 1) K` parameters: all of them for
    /// [`Cholesky`](Self::Cholesky); for [`PreconditionedCg`](Self::PreconditionedCg)
    /// [`PRECONDITIONER_ROWS_PER_PARAMETER`] per parameter, at least
    /// [`MIN_PRECONDITIONER_ROWS`]; for [`TruncatedCg`](Self::TruncatedCg) its
    /// `preconditioner_rows`; never more than `n_samples`.
    pub fn preconditioner_rows(&self, n_samples: usize, n_parameters: usize) -> usize {
        let rows = match self {
            DirectionSolver::Cholesky => n_samples,
            DirectionSolver::PreconditionedCg => n_parameters
                .saturating_mul(PRECONDITIONER_ROWS_PER_PARAMETER)
                .max(MIN_PRECONDITIONER_ROWS),
            DirectionSolver::TruncatedCg {
                preconditioner_rows,
                ..
            } => *preconditioner_rows,
        };
        rows.min(n_samples)
    }

    /// Samples the conjugate-gradient Hessian-vector products are computed on, at least,
    /// for a problem of `n_samples` samples: all of them except for
    /// [`TruncatedCg`](Self::TruncatedCg) with a smaller `product_rows`.
    pub fn product_rows(&self, n_samples: usize) -> usize {
        match self {
            DirectionSolver::TruncatedCg { product_rows, .. } => (*product_rows).min(n_samples),
            DirectionSolver::Cholesky | DirectionSolver::PreconditionedCg => n_samples,
        }
    }
}

/// Preconditioner samples per parameter of [`DirectionSolver::PreconditionedCg`]: the
/// subsampled Hessian of `8 (d + 1) K` samples preconditions well enough that a Newton system
/// takes a few products, at a small fraction of a full assembly's cost once there are many
/// samples (measured on the paper's synthetic size and on the default model's training set).
pub const PRECONDITIONER_ROWS_PER_PARAMETER: usize = 8;
/// Fewest preconditioner samples of [`DirectionSolver::PreconditionedCg`] (all of them when
/// there are fewer).
pub const MIN_PRECONDITIONER_ROWS: usize = 4096;

/// The largest ridge weight [`LogisticRegression::validate`] accepts: far beyond any useful
/// one (the default models use 1 and 100 on hundreds of thousands of samples), below the
/// weights whose Newton systems overflow.
pub const MAX_LAMBDA: f64 = 1e12;

/// L2-regularised logistic regression fitted by Newton's method (docs/conventions.md section 5).
///
/// Minimises, over weights `W` (`K x d`) and biases `b` (`K`),
///
/// * [`Mode::Multinomial`]: `f = -sum_i log softmax(W x_i + b)_{y_i} + lambda ||W||_F^2`;
/// * [`Mode::OneVsRest`]: `f = sum_k [ -sum_i log sigmoid(s_ik (w_k . x_i + b_k)) + lambda
///   ||w_k||^2 ]` with `s_ik = +1` if `y_i = k` and `-1` otherwise.
///
/// The loss is a *sum* over samples (not a mean) and the bias is not penalised; `x_i` are
/// the standardised features when [`standardise`](Self::standardise) is set. In
/// scikit-learn's terms `lambda = 1 / (2 C)`.
///
/// Each iteration computes the exact gradient, solves the Newton system of the exact
/// Hessian (with faer's dense Cholesky, or as far as the iteration needs by conjugate
/// gradients on exact Hessian-vector products, preconditioned by the Cholesky factor of a
/// subsampled Hessian: see [`DirectionSolver`]), and takes the Newton step with a
/// backtracking (Armijo) line search. It stops when the infinity norm of the gradient of
/// `f` is at most `gradient_tolerance * n_samples` (the tolerance is on the gradient of the *mean*
/// loss, so it does not depend on the number of samples).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LogisticRegression {
    /// Ridge weight `lambda >= 0` on the squared weights (biases excluded). Default 0.5,
    /// scikit-learn's default `C = 1`.
    pub lambda: f64,
    /// Maximum number of Newton iterations. Default 100.
    pub max_iter: usize,
    /// Stop when `||grad f||_inf <= gradient_tolerance * n_samples`. Default 1e-8.
    pub gradient_tolerance: f64,
    /// Multinomial (default) or one-vs-rest.
    pub mode: Mode,
    /// Standardise features (zero mean, unit variance per column, fitted on the training
    /// data and stored in the model). Default true.
    pub standardise: bool,
    /// How the Newton systems are solved. Default [`DirectionSolver::PreconditionedCg`].
    #[serde(default)]
    pub direction_solver: DirectionSolver,
}

impl Default for LogisticRegression {
    fn default() -> Self {
        Self {
            lambda: 0.5,
            max_iter: 100,
            gradient_tolerance: 1e-8,
            mode: Mode::Multinomial,
            standardise: true,
            direction_solver: DirectionSolver::PreconditionedCg,
        }
    }
}

impl LogisticRegression {
    /// Returns `self` with the ridge weight `lambda` set.
    pub fn with_lambda(mut self, lambda: f64) -> Self {
        self.lambda = lambda;
        self
    }

    /// Returns `self` with the maximum number of Newton iterations set.
    pub fn with_max_iter(mut self, max_iter: usize) -> Self {
        self.max_iter = max_iter;
        self
    }

    /// Returns `self` with the (per-sample) gradient tolerance set.
    pub fn with_gradient_tolerance(mut self, gradient_tolerance: f64) -> Self {
        self.gradient_tolerance = gradient_tolerance;
        self
    }

    /// Returns `self` with the mode set.
    pub fn with_mode(mut self, mode: Mode) -> Self {
        self.mode = mode;
        self
    }

    /// Returns `self` with standardisation switched on or off.
    pub fn with_standardise(mut self, standardise: bool) -> Self {
        self.standardise = standardise;
        self
    }

    /// Returns `self` with the Newton system solver set.
    pub fn with_direction_solver(mut self, direction_solver: DirectionSolver) -> Self {
        self.direction_solver = direction_solver;
        self
    }

    /// Checks the hyper-parameters.
    ///
    /// # Errors
    /// [`LearningError::InvalidParameter`] if `lambda` is negative, not finite or above
    /// [`MAX_LAMBDA`], or `gradient_tolerance` negative or not finite.
    pub fn validate(&self) -> Result<(), LearningError> {
        if !(self.lambda.is_finite() && (0.0..=MAX_LAMBDA).contains(&self.lambda)) {
            return Err(LearningError::InvalidParameter {
                name: "lambda",
                value: format!("{:?}", self.lambda),
                reason: "must be from 0 to 1e12 (a larger weight leaves only the biases, and \
                         1e308 overflowed the Newton system)",
            });
        }
        if let DirectionSolver::TruncatedCg {
            preconditioner_rows,
            product_rows,
        } = self.direction_solver
        {
            for (name, rows) in [
                ("preconditioner_rows", preconditioner_rows),
                ("product_rows", product_rows),
            ] {
                if rows == 0 {
                    return Err(LearningError::InvalidParameter {
                        name,
                        value: "0".into(),
                        reason: "must be at least 1",
                    });
                }
            }
        }
        if !(self.gradient_tolerance.is_finite() && self.gradient_tolerance >= 0.0) {
            return Err(LearningError::InvalidParameter {
                name: "gradient_tolerance",
                value: format!("{:?}", self.gradient_tolerance),
                reason: "must be finite and >= 0",
            });
        }
        Ok(())
    }
}
