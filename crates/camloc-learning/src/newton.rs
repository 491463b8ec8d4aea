//! Newton's method on the L2 logistic objective: state, exact gradient and Hessian, Cholesky
//! solve and backtracking line search.
//!
//! # Layout
//!
//! * Design matrix `X`: `n x D` column-major, `D = d + 1`, the standardised features
//!   followed by a column of ones (the bias); for quadratic features its product columns are
//!   formed per chunk of rows rather than stored (module `design_matrix`).
//! * Parameters `theta`: `D x K` column-major, i.e. class-major: `theta[k * D + a]` is the
//!   weight of feature `a` for class `k`, `a = d` being the bias. Gradient and Newton
//!   direction use the same layout; the Hessian is the `P x P` matrix (`P = D K`) on it.
//! * Logits and probabilities: `K x n` column-major (each sample's `K` values contiguous);
//!   the residuals `p - onehot(y)` are made from them as the gradient reads each row.
//!
//! # Hessian
//!
//! Multinomial: block `(j, k)` of the Hessian of the loss is `X^T diag(w_jk) X` with
//! `w_jk = p_j (delta_jk - p_k)`. Since `sum_k w_jk = 0`, every diagonal block is minus the
//! sum of the off-diagonal blocks of its block row, so only the `K (K - 1) / 2` blocks
//! `G_jk = X^T diag(p_j p_k) X`, `j < k`, are computed: `H_jk = -G_jk`,
//! `H_jj = sum_{k != j} G_jk` (a sum of positive semi-definite terms, without the
//! cancellation of `1 - p_j`). Each block is symmetric, so only its upper triangle is
//! needed: with `U` the `n x D(D+1)/2` matrix of products `x_ia x_ib` (`a <= b`) and `W`
//! the `n x K(K-1)/2` matrix of weights `p_ij p_ik`, all packed blocks are the single
//! product `W^T U`. It is accumulated over chunks of rows (`U` is never stored whole)
//! with faer's GEMM on every core, with buffers allocated once per fit and a schedule that
//! keeps the result bit-for-bit reproducible. One-vs-rest uses the `K` weights
//! `sigma(z_k)(1 - sigma(z_k))` instead and a block-diagonal Hessian.
//!
//! When every feature weight is zero (the starting point) all samples share the same
//! weights and the blocks are multiples of one Gram matrix `X^T X`, computed instead.
//!
//! Actual multiply-adds per Hessian: `n * D(D+1)/2 * Q` with `Q = K(K-1)/2` (multinomial)
//! or `K` (one-vs-rest); see [`NewtonProblem::hessian_flops`].
//!
//! # Truncated Newton
//!
//! With [`DirectionSolver::PreconditionedCg`] (the default) and
//! [`DirectionSolver::TruncatedCg`] (multinomial mode) every Newton system is solved by
//! conjugate gradients on exact Hessian-vector products (`4 n D K` flops each, module
//! `product`), only to the forcing term `min(0.5, sqrt(||g|| / ||g_0||))` or until the
//! residual is well inside the convergence threshold, preconditioned by the Cholesky factor
//! of the Hessian assembled on a fixed, evenly spaced subset of the samples (rescaled to all
//! of them), so that an assembly costs `m / n` of a full one. The factor is refreshed when a
//! solve spends its budget (module `cg`); with the default solver the subsample then also
//! doubles.
//!
//! # Where the code is
//!
//! This module holds the solver state, the fit loop and the reports; the direction solvers
//! are in `direct` (Hessian assembly and Cholesky solve) and `cg` (conjugate gradients
//! preconditioned by the last factor, on the Hessian-vector products of `product`), the
//! Armijo backtracking in `line_search`, the products of the design matrix with thin
//! matrices (logits, gradients, Hessian-vector products) in `blocked`, the design matrix
//! itself (stored, or generated chunk by chunk for quadratic features) in `design_matrix`,
//! and the per-sample kernels and reductions in `kernels`.
//!
//! # Evaluations
//!
//! A line-search trial evaluates every sample at the trial logits `z + t dz` (`dz = X d`,
//! computed once per direction) in one pass: loss and probabilities share one exponential
//! per class, and the probabilities are kept. When the trial is accepted (in practice
//! nearly always the unit step) it becomes the new state as it is (its logits made again,
//! the same numbers, in place of the old ones: no second `K x n` array of logits), and only
//! the gradient is left to compute: an iteration evaluates the objective once, not once for
//! the line search and again for the update.
//!
//! # Singular directions
//!
//! In the multinomial model adding the same constant to every class's bias leaves the
//! probabilities unchanged and the bias is not penalised, so the Hessian is singular along
//! `u = (1/sqrt K) sum_k e_(k, bias)`; the gradient is always orthogonal to `u`. The Newton
//! system is solved with `H + c u u^T` (`c` = mean bias curvature), which is positive
//! definite and gives exactly the minimum-norm Newton step. With `lambda = 0` the same is
//! done for every feature (each weight vector shift `w_k -> w_k + v` is then a null
//! direction too). If the Cholesky factorisation still fails, increasing multiples of the
//! identity are added (damping) until it succeeds.

use faer::Par;
use faer::dyn_stack::MemBuffer;
use faer::linalg::cholesky::llt::factor::cholesky_in_place_scratch;

use crate::data::check_labels;
use crate::hessian::PackedHessian;
use crate::standardise::Standardiser;
use crate::{
    DesignRows, DirectionSolver, Features, LearningError, LogisticModel, LogisticRegression, Mode,
};

mod blocked;
mod cg;
mod design_matrix;
mod direct;
mod kernels;
mod line_search;
mod product;

use blocked::BlockedProducts;
use design_matrix::{DesignMatrix, RowOrder};
pub(crate) use kernels::row_loss;
use kernels::{ROWS_PER_TASK, add_ridge_curvature, residuals_of_row};

/// What happened in one Newton iteration (or at the starting point, iteration 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IterationLog {
    /// Iteration number; 0 is the starting point (all parameters zero).
    pub iteration: usize,
    /// Objective `f` after the iteration (sum over samples plus the ridge term).
    pub objective: f64,
    /// `||grad f||_inf` after the iteration.
    pub gradient_norm: f64,
    /// Step length taken along the Newton direction (1 is the full step; 0 means no
    /// decrease could be found). For one-vs-rest, the largest of the per-class steps.
    pub step: f64,
    /// Whether the Hessian (or the preconditioner's subsampled Hessian) was assembled and
    /// factorised in this iteration (false at the starting point and when conjugate
    /// gradients solved the Newton system with an earlier factor, see [`DirectionSolver`]).
    pub hessian_assembled: bool,
    /// Hessian-vector products spent by conjugate gradients in this iteration.
    pub cg_products: usize,
    /// Whether the direction came from truncated CG ([`DirectionSolver::PreconditionedCg`]
    /// or [`DirectionSolver::TruncatedCg`]), which runs after an assembly too.
    pub truncated: bool,
}

impl IterationLog {
    /// How the Newton direction of this iteration was found, in words for logs:
    /// `"start"`, `"Hessian + Cholesky"`, `"truncated CG, 7 products"` or
    /// `"preconditioner assembled, truncated CG, 4 products"`.
    pub fn direction_summary(&self) -> String {
        match (self.iteration, self.truncated, self.hessian_assembled) {
            (0, _, _) => "start".to_owned(),
            (_, false, _) => "Hessian + Cholesky".to_owned(),
            (_, true, assembled) => format!(
                "{}truncated CG, {} products",
                if assembled {
                    "preconditioner assembled, "
                } else {
                    ""
                },
                self.cg_products
            ),
        }
    }
}

/// Why the Newton iteration stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Termination {
    /// The gradient tolerance was met.
    Converged,
    /// `max_iter` iterations were done without meeting the tolerance.
    MaxIterations,
    /// The line search could not decrease the objective: it found no decrease, or only a
    /// shortened step that left the objective unchanged to the last bit (typically the
    /// optimum is reached to rounding precision while the tolerance is tighter than that).
    NoProgress,
}

/// Summary of a fit: the per-iteration log and whether it converged.
#[derive(Clone, Debug, PartialEq)]
pub struct FitReport {
    /// Starting point (iteration 0) then one entry per Newton iteration.
    pub iterations: Vec<IterationLog>,
    /// True when the gradient tolerance was met.
    pub converged: bool,
    /// Why the iteration stopped.
    pub termination: Termination,
}

impl FitReport {
    /// Newton iterations done (the log minus its starting point).
    pub fn newton_iterations(&self) -> usize {
        self.iterations.len().saturating_sub(1)
    }

    /// Iterations that assembled and factorised the Hessian.
    pub fn hessian_assemblies(&self) -> usize {
        self.iterations
            .iter()
            .filter(|l| l.hessian_assembled)
            .count()
    }

    /// Hessian-vector products spent by conjugate gradients over the whole fit.
    pub fn cg_products(&self) -> usize {
        self.iterations.iter().map(|l| l.cg_products).sum()
    }
}

/// The state of a Newton fit: data, parameters and every work buffer.
///
/// Built by [`NewtonProblem::new`] (which also evaluates the starting point, all parameters
/// zero), advanced by [`NewtonProblem::newton_step`], turned into a model by
/// [`NewtonProblem::into_model`]. [`LogisticRegression::fit`] drives it; it is public so that
/// benchmarks can time single iterations and the Hessian assembly.
pub struct NewtonProblem {
    mode: Mode,
    direction_solver: DirectionSolver,
    lambda: f64,
    n_samples: usize,
    /// `D = d + 1`.
    dim: usize,
    n_classes: usize,
    standardiser: Standardiser,
    /// `n x D` design matrix (standardised features, then ones), stored or generated.
    x: DesignMatrix,
    labels: Vec<usize>,
    /// `D x K` parameters.
    theta: Vec<f64>,
    /// `K x n` logits.
    logits: Vec<f64>,
    /// `K x n` probabilities (softmax, or per-class sigmoids for one-vs-rest).
    probabilities: Vec<f64>,
    /// `K x n` change of the logits along the Newton direction.
    direction_logits: Vec<f64>,
    /// `D x K` gradient.
    gradient: Vec<f64>,
    /// Buffers of the products with `X` (logits, gradient, Hessian-vector products).
    blocked: BlockedProducts,
    /// `D x K` Newton direction.
    direction: Vec<f64>,
    /// `P x P` Hessian (full, symmetric).
    hessian: Vec<f64>,
    /// `P x P` Cholesky work matrix; after a successful undamped multinomial factorisation
    /// its lower triangle is the factor `L` of `H + S` (`S` the singular-direction shift),
    /// kept as the preconditioner of [`DirectionSolver::PreconditionedCg`].
    factor: Vec<f64>,
    /// True when `factor` holds such a preconditioner.
    factor_ready: bool,
    /// Per design column `a`: the curvature `c_a` of the singular-direction shift in
    /// `factor` (`S` adds `c_a` to every entry `((j, a), (l, a))`); 0 for columns without.
    null_shifts: Vec<f64>,
    /// Conjugate-gradient vectors (`P` each): residual, preconditioned residual, search
    /// direction and its Hessian product.
    cg: cg::Vectors,
    cholesky_scratch: MemBuffer,
    /// Line-search blocks: one (multinomial) or one per class (one-vs-rest).
    block_objectives: Vec<f64>,
    trial_objectives: Vec<f64>,
    directional_derivatives: Vec<f64>,
    block_steps: Vec<f64>,
    block_done: Vec<bool>,
    /// Step per class, derived from the block steps.
    class_steps: Vec<f64>,
    /// `tasks x blocks` partial loss sums of the parallel row passes.
    partial_losses: Vec<f64>,
    /// Packed Hessian blocks and their work buffers.
    packed: PackedHessian,
    /// With a preconditioner on fewer rows than samples ([`DirectionSolver::preconditioner_rows`]):
    /// the evenly spaced rows the preconditioning Hessian is assembled on (empty: every row).
    sub_rows: Vec<usize>,
    /// `m x D` column-major design rows of `sub_rows`.
    sub_x: Vec<f64>,
    /// `K x m` probabilities (or logits) of `sub_rows`, gathered before each assembly.
    sub_per_sample: Vec<f64>,
    /// `||grad f||_inf` at the starting point (the forcing term's reference).
    initial_gradient_norm: f64,
    /// The fit's convergence threshold on `||grad f||_inf` (`gradient_tolerance * n`).
    gradient_threshold: f64,
    /// Trust radius of truncated CG in the preconditioner's norm (infinite at the start).
    trust_radius: f64,
    /// Conjugate-gradient products read every `product_task_stride`-th task of rows (1:
    /// every row, the exact Hessian; [`DirectionSolver::product_rows`]).
    product_task_stride: usize,
    /// Where each sample's row is stored (image pairs side by side when the products read a
    /// subsample of rows in image pairs).
    row_order: RowOrder,
    iteration: usize,
}

impl std::fmt::Debug for NewtonProblem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("NewtonProblem")
            .field("mode", &self.mode)
            .field("lambda", &self.lambda)
            .field("n_samples", &self.n_samples)
            .field("n_features", &(self.dim - 1))
            .field("n_classes", &self.n_classes)
            .field("iteration", &self.iteration)
            .field("objective", &self.objective())
            .field("gradient_norm", &self.gradient_norm())
            .finish_non_exhaustive()
    }
}

impl NewtonProblem {
    /// Validates the data, standardises it (if configured), allocates every buffer and
    /// evaluates objective and gradient at the starting point (all parameters zero).
    ///
    /// # Errors
    /// As [`LogisticRegression::fit`].
    pub fn new(
        x: &Features<'_>,
        y: &[usize],
        n_classes: usize,
        config: &LogisticRegression,
    ) -> Result<Self, LearningError> {
        Self::from_rows(&DesignRows::plain(*x), y, n_classes, config)
    }

    /// [`new`](Self::new) on rows read one at a time (for instance expanded as they are
    /// read): the same problem as on the rows stored whole, without holding them beside
    /// the solver's copy.
    ///
    /// # Errors
    /// As [`LogisticRegression::fit`].
    pub fn from_rows(
        x: &DesignRows<'_>,
        y: &[usize],
        n_classes: usize,
        config: &LogisticRegression,
    ) -> Result<Self, LearningError> {
        config.validate()?;
        let n = x.n_samples();
        if n == 0 {
            return Err(LearningError::NoSamples);
        }
        check_labels(y, n, n_classes)?;
        let d = x.n_features();
        let dim = d + 1;
        let k = n_classes;
        let p = dim * k;
        let standardiser = if config.standardise {
            Standardiser::fit_rows(x)
        } else {
            Standardiser::identity(d)
        };
        let product_rows = config.direction_solver.product_rows(n);
        let order = if product_rows < n && x.has_image_pairs() {
            RowOrder::spread_pairs(n)
        } else if product_rows < n {
            RowOrder::spread(n)
        } else {
            RowOrder::input(n)
        };
        let design = DesignMatrix::new(x, &standardiser, order);
        let mut labels = vec![0; n];
        for (i, &label) in y.iter().enumerate() {
            labels[order.position(i)] = label;
        }
        let n_blocks = match config.mode {
            Mode::Multinomial => 1,
            Mode::OneVsRest => k,
        };
        let max_block = match config.mode {
            Mode::Multinomial => p,
            Mode::OneVsRest => dim,
        };
        let cholesky_scratch = MemBuffer::new(cholesky_in_place_scratch::<f64>(
            max_block,
            Par::rayon(0),
            Default::default(),
        ));
        let mut problem = Self {
            mode: config.mode,
            direction_solver: config.direction_solver,
            lambda: config.lambda,
            n_samples: n,
            dim,
            n_classes: k,
            standardiser,
            x: design,
            labels,
            theta: vec![0.0; p],
            logits: vec![0.0; k * n],
            probabilities: vec![0.0; k * n],
            direction_logits: vec![0.0; k * n],
            gradient: vec![0.0; p],
            blocked: BlockedProducts::new(n, dim, k),
            direction: vec![0.0; p],
            hessian: vec![0.0; p * p],
            factor: vec![0.0; max_block * max_block],
            factor_ready: false,
            null_shifts: vec![0.0; dim],
            cg: cg::Vectors::new(p),
            cholesky_scratch,
            block_objectives: vec![0.0; n_blocks],
            trial_objectives: vec![0.0; n_blocks],
            directional_derivatives: vec![0.0; n_blocks],
            block_steps: vec![0.0; n_blocks],
            block_done: vec![false; n_blocks],
            class_steps: vec![0.0; k],
            partial_losses: vec![0.0; n.div_ceil(ROWS_PER_TASK) * n_blocks],
            packed: PackedHessian::new(0, dim, k, config.mode),
            sub_per_sample: Vec::new(),
            sub_rows: Vec::new(),
            sub_x: Vec::new(),
            initial_gradient_norm: 0.0,
            gradient_threshold: config.gradient_tolerance * n as f64,
            trust_radius: f64::INFINITY,
            product_task_stride: Self::task_stride_for(n, product_rows),
            row_order: order,
            iteration: 0,
        };
        problem.use_preconditioner_rows(config.direction_solver.preconditioner_rows(n, p));
        problem.refresh_from_parameters();
        problem.initial_gradient_norm = problem.gradient_norm();
        Ok(problem)
    }

    /// Assembles later Hessians on `m` evenly spaced stored rows ([`RowOrder::spaced`]; all
    /// rows when `m >= n`, and in one-vs-rest mode): gathers their design rows and sizes the
    /// buffers. A generated design matrix has no stored rows to assemble on, so "all rows"
    /// then gathers every row.
    fn use_preconditioner_rows(&mut self, m: usize) {
        let (n, dim, k) = (self.n_samples, self.dim, self.n_classes);
        self.sub_rows = if m < n && self.mode == Mode::Multinomial {
            self.row_order.spaced(m)
        } else if self.x.is_generated() {
            (0..n).collect()
        } else {
            Vec::new()
        };
        let m = self.sub_rows.len();
        self.sub_x = self.x.gather(&self.sub_rows, dim);
        self.sub_per_sample = vec![0.0; m * k];
        self.packed = PackedHessian::new(self.hessian_rows(), dim, k, self.mode);
    }

    /// With [`DirectionSolver::PreconditionedCg`] on fewer rows than samples: doubles the
    /// preconditioner's rows (at most all of them), for a CG solve that spent its budget
    /// with the current ones.
    pub(super) fn grow_preconditioner(&mut self) {
        let m = self.sub_rows.len();
        if self.direction_solver == DirectionSolver::PreconditionedCg && m > 0 && m < self.n_samples
        {
            self.use_preconditioner_rows(m.saturating_mul(2));
        }
    }

    /// Number of parameters `P = (d + 1) K`.
    pub fn n_parameters(&self) -> usize {
        self.theta.len()
    }

    /// Number of samples (rows) the problem was set up on.
    pub fn n_samples(&self) -> usize {
        self.n_samples
    }

    /// Number of Newton iterations done so far.
    pub fn iteration(&self) -> usize {
        self.iteration
    }

    /// Current objective `f` (sum of the per-sample losses plus the ridge term).
    pub fn objective(&self) -> f64 {
        self.block_objectives.iter().sum()
    }

    /// `||grad f||_inf` at the current parameters.
    pub fn gradient_norm(&self) -> f64 {
        self.gradient.iter().fold(0.0, |m, g| m.max(g.abs()))
    }

    /// Current parameters, class-major: `parameters()[k * (d + 1) + a]` is the weight of
    /// standardised feature `a` for class `k`, and `a = d` the bias of class `k`.
    pub fn parameters(&self) -> &[f64] {
        &self.theta
    }

    /// Gradient of `f` at the current parameters, same layout as
    /// [`parameters`](Self::parameters).
    pub fn gradient(&self) -> &[f64] {
        &self.gradient
    }

    /// The Hessian last assembled by [`assemble_hessian`](Self::assemble_hessian) or by a
    /// Newton step that assembled one ([`IterationLog::hessian_assembled`]), `P x P`
    /// column-major, without the singular-direction correction of the Newton solve: it is
    /// exactly the second derivative of `f` at the parameters where it was assembled (not
    /// necessarily the current ones), or with a preconditioner on fewer rows than samples
    /// ([`hessian_rows`](Self::hessian_rows)) its subsampled estimate.
    pub fn hessian(&self) -> &[f64] {
        &self.hessian
    }

    /// Sets the parameters (layout of [`parameters`](Self::parameters)) and re-evaluates
    /// objective and gradient there. Used to restart from a known point (benchmarks time
    /// single iterations from the same state this way).
    ///
    /// # Errors
    /// [`LearningError::SizeMismatch`] if `theta` does not have [`n_parameters`](Self::n_parameters)
    /// entries, [`LearningError::InvalidParameter`] if one is not finite.
    pub fn set_parameters(&mut self, theta: &[f64]) -> Result<(), LearningError> {
        if theta.len() != self.theta.len() {
            return Err(LearningError::SizeMismatch {
                what: "number of Newton parameters",
                expected: self.theta.len(),
                found: theta.len(),
            });
        }
        if let Some(v) = theta.iter().find(|v| !v.is_finite()) {
            return Err(LearningError::InvalidParameter {
                name: "theta",
                value: format!("{v:?}"),
                reason: "every parameter must be finite",
            });
        }
        self.theta.copy_from_slice(theta);
        self.refresh_from_parameters();
        Ok(())
    }

    /// Floating-point operations of one Hessian assembly as actually computed (in general;
    /// when every feature weight is zero, as at the start, one Gram matrix suffices):
    /// `2 n T Q` with `T = D(D+1)/2` (packed symmetric blocks) and `Q = K(K-1)/2`
    /// (multinomial) or `K` (one-vs-rest) weight columns.
    pub fn hessian_flops(&self) -> f64 {
        self.packed.flops(self.hessian_rows())
    }

    /// Samples the Hessian is assembled on: all of them, or the preconditioner's rows
    /// ([`DirectionSolver::preconditioner_rows`], doubled by the default solver when its
    /// solves spend their budget).
    pub fn hessian_rows(&self) -> usize {
        if self.sub_rows.is_empty() {
            self.n_samples
        } else {
            self.sub_rows.len()
        }
    }

    /// Floating-point operations of the textbook assembly of the upper blocks,
    /// `2 n D^2 K(K+1)/2` (every upper block `X^T diag(w) X` as a full GEMM), for comparing
    /// with other implementations: `hessian_flops` is about 0.43 of this for the paper's
    /// size.
    pub fn hessian_flops_textbook(&self) -> f64 {
        let k = self.n_classes as f64;
        let d = self.dim as f64;
        match self.mode {
            Mode::Multinomial => self.n_samples as f64 * d * d * k * (k + 1.0),
            Mode::OneVsRest => 2.0 * self.n_samples as f64 * d * d * k,
        }
    }

    /// Log entry of the current state with the given step length.
    pub(crate) fn log(
        &self,
        step: f64,
        hessian_assembled: bool,
        cg_products: usize,
    ) -> IterationLog {
        IterationLog {
            iteration: self.iteration,
            objective: self.objective(),
            gradient_norm: self.gradient_norm(),
            step,
            hessian_assembled,
            cg_products,
            truncated: self.is_truncated(),
        }
    }

    /// Logits, losses, probabilities, objective and gradient from `theta`. At `theta = 0`
    /// (the start of every fit) the logits are 0 without a pass over the rows.
    fn refresh_from_parameters(&mut self) {
        if self.theta.iter().all(|&t| t == 0.0) {
            self.logits.fill(0.0);
        } else {
            self.blocked.logits(&self.x, &self.theta, &mut self.logits);
        }
        self.class_steps.fill(0.0);
        self.evaluate_trial();
        self.accept_trial();
    }

    /// `grad f = X^T R^T + 2 lambda [W; 0]`, the residuals `R` made from the probabilities
    /// and logits as the rows are read.
    fn compute_gradient(&mut self) {
        let (mode, k) = (self.mode, self.n_classes);
        let (logits, probabilities, labels) = (&self.logits, &self.probabilities, &self.labels);
        let residuals = |i: usize, r: &mut [f64]| {
            let row = i * k..(i + 1) * k;
            residuals_of_row(
                mode,
                labels[i],
                &logits[row.clone()],
                &probabilities[row],
                r,
            );
        };
        self.blocked
            .transpose_product(&self.x, residuals, &mut self.gradient);
        add_ridge_curvature(self.lambda, self.dim, &self.theta, &mut self.gradient);
    }

    /// One Newton iteration: the Newton direction (Hessian assembly and Cholesky solve, or
    /// preconditioned conjugate gradients: see [`DirectionSolver`]), backtracking line
    /// search, update of parameters, objective and gradient. Returns the log of the new
    /// state; a step of 0 means no decrease was found and nothing changed.
    ///
    /// # Errors
    /// [`LearningError::Singular`] if the Hessian cannot be factorised even with damping.
    pub fn newton_step(&mut self) -> Result<IterationLog, LearningError> {
        let mut truncated = None;
        let (hessian_assembled, cg_products) = if self.is_truncated() {
            let assemble = !self.factor_ready;
            if assemble {
                self.assemble_hessian();
                self.solve_newton_system()?;
            }
            let step = self.solve_by_truncated_cg(self.trust_radius);
            truncated = Some(step);
            (assemble, step.products)
        } else {
            self.assemble_hessian();
            self.solve_newton_system()?;
            (true, 0)
        };
        self.blocked
            .logits(&self.x, &self.direction, &mut self.direction_logits);
        let evaluated = self.line_search();
        let step = self.block_steps.iter().fold(0.0, |m: f64, &s| m.max(s));
        if let Some(t) = truncated {
            self.update_trust_radius(step, t);
        }
        // The trials overwrote the probabilities: take the last one if it is at
        // the final steps, else evaluate those (all zero when nothing was accepted: the
        // state as it was, recomputed to the same numbers).
        if !evaluated {
            self.evaluate_trial();
        }
        self.accept_trial();
        self.iteration += 1;
        Ok(self.log(step, hessian_assembled, cg_products))
    }

    /// The trust radius after a truncated step of length `taken.norm` (preconditioner norm)
    /// of which the line search accepted the fraction `step`: a shortened step shrinks the
    /// radius to what was accepted (at least a tenth of the direction), a full step on the
    /// boundary doubles it, a full step inside leaves it.
    fn update_trust_radius(&mut self, step: f64, taken: cg::TruncatedStep) {
        if !(taken.norm > 0.0) {
            return;
        }
        if step < 1.0 {
            self.trust_radius = step.max(0.1) * taken.norm;
        } else if taken.on_boundary {
            self.trust_radius = 2.0 * taken.norm;
        }
    }

    /// Whether directions come from truncated conjugate gradients
    /// ([`DirectionSolver::PreconditionedCg`] or [`DirectionSolver::TruncatedCg`],
    /// multinomial mode).
    fn is_truncated(&self) -> bool {
        self.direction_solver != DirectionSolver::Cholesky && self.mode == Mode::Multinomial
    }

    /// The fitted model: parameters mapped back to per-feature weights and biases, with the
    /// standardiser.
    pub fn into_model(self) -> LogisticModel {
        let d = self.dim - 1;
        let k = self.n_classes;
        let mut weights = vec![0.0; d * k];
        let mut biases = vec![0.0; k];
        for (class, params) in self.theta.chunks_exact(self.dim).enumerate() {
            for (a, &w) in params[..d].iter().enumerate() {
                weights[a * k + class] = w;
            }
            biases[class] = params[d];
        }
        LogisticModel::from_validated_parts(
            self.mode,
            self.lambda,
            self.standardiser,
            weights,
            biases,
        )
    }
}
