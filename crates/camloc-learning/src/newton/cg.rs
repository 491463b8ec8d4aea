//! The truncated Newton direction by conjugate gradients on Hessian-vector products (module
//! `product`; exact, or on an evenly spaced subsample of the rows), preconditioned by the
//! Cholesky factor of an earlier, subsampled Hessian
//! ([`DirectionSolver::PreconditionedCg`](crate::DirectionSolver::PreconditionedCg) and
//! [`DirectionSolver::TruncatedCg`](crate::DirectionSolver::TruncatedCg)).
//!
//! The system is the one the direct solve factorises, `(H + S) d = -g`, `S` the
//! singular-direction shift recorded with the factor (the gradient is orthogonal to the
//! null space of `H`, so `S` does not change the solution). A product costs one pass over
//! `X` (`4 n D K` flops) instead of the `2 n T Q` of an assembly.
//!
//! Stopping: at the forcing term, `r^T M^-1 r <= eta^2 r_0^T M^-1 r_0` with `M` the
//! preconditioner; when the residual `r = -g - (H + S) d` (the gradient that the quadratic
//! model predicts after the step) is a quarter of the fit's convergence threshold in the
//! infinity norm; at the trust radius; or when the budget of products (about the cost of an
//! assembly) is spent, in which case the factor is marked stale.

use faer::MatMut;
use faer::dyn_stack::MemStack;
use faer::linalg::cholesky::llt::solve::solve_in_place;
use faer::{MatRef, Par};

use super::NewtonProblem;
use crate::hessian::dot;

/// Smallest forcing term: the relative accuracy of a direct solve.
const CG_TOLERANCE: f64 = 1e-10;
/// Fewest products CG may spend, whatever the cost model says (small problems).
const MIN_BUDGET: usize = 10;
/// How many times the flops of a Hessian-vector product cost, in time, relative to the
/// flops of an assembly, for the budget. The blocked products run at about 0.8 of the
/// assembly's flop rate (module `blocked`); 2 lets a solve spend about half the time of an
/// assembly before the factor is refreshed.
const PRODUCT_COST_WEIGHT: f64 = 2.0;

/// What [`NewtonProblem::solve_by_truncated_cg`] did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct TruncatedStep {
    /// Hessian-vector products spent.
    pub(super) products: usize,
    /// Norm of the direction in the preconditioner's metric, `sqrt(d^T M d)`.
    pub(super) norm: f64,
    /// Whether the direction ends on the trust radius.
    pub(super) on_boundary: bool,
}

/// The conjugate-gradient work vectors, `P` entries each.
#[derive(Debug)]
pub(super) struct Vectors {
    residual: Vec<f64>,
    preconditioned: Vec<f64>,
    /// The search direction `v` of the next Hessian-vector product.
    pub(super) search: Vec<f64>,
    /// The product `H v` (module `product`), then `(H + S) v`.
    pub(super) product: Vec<f64>,
}

impl Vectors {
    /// Zeroed vectors for `p` parameters.
    pub(super) fn new(p: usize) -> Self {
        Self {
            residual: vec![0.0; p],
            preconditioned: vec![0.0; p],
            search: vec![0.0; p],
            product: vec![0.0; p],
        }
    }
}

impl NewtonProblem {
    /// Most products one CG solve may spend: the time of an assembly and factorisation,
    /// by the flop counts and [`PRODUCT_COST_WEIGHT`], at least [`MIN_BUDGET`].
    fn cg_budget(&self) -> usize {
        let p = self.theta.len() as f64;
        let assembly = self.hessian_flops() + p * p * p / 3.0;
        let product =
            self.hessian_vector_product_flops() / self.product_task_stride as f64 + 2.0 * p * p;
        let budget = assembly / (PRODUCT_COST_WEIGHT * product);
        if budget.is_finite() {
            (budget as usize).max(MIN_BUDGET)
        } else {
            MIN_BUDGET
        }
    }

    /// `cg.preconditioned = M^-1 cg.residual`, `M = L L^T` the kept factor.
    fn precondition(&mut self) {
        let p = self.theta.len();
        self.cg.preconditioned.copy_from_slice(&self.cg.residual);
        let factor = MatRef::from_column_major_slice(&self.factor[..p * p], p, p);
        solve_in_place(
            factor,
            MatMut::from_column_major_slice_mut(&mut self.cg.preconditioned, p, 1),
            Par::Seq,
            MemStack::new(&mut self.cholesky_scratch),
        );
    }

    /// `cg.product = (H + S) cg.search` with the Hessian `H` at the current parameters
    /// (exact, or on the subsample of `product_rows`) and `S` the singular-direction shift
    /// recorded with the factor.
    fn hessian_times_search(&mut self) {
        self.multiply_by_hessian(self.product_task_stride);
        let dim = self.dim;
        let (v, product) = (&self.cg.search, &mut self.cg.product);
        // S v: c_a times the sum over classes of v's entries for column a, in every class.
        for (a, &c) in self.null_shifts.iter().enumerate() {
            if c != 0.0 {
                let total: f64 = v.iter().skip(a).step_by(dim).sum();
                for out in product.iter_mut().skip(a).step_by(dim) {
                    *out += c * total;
                }
            }
        }
    }

    /// Starts preconditioned CG from the zero direction on `H d = -g`: residual `-g`, its
    /// preconditioned copy as the first search direction; returns `r^T M^-1 r`.
    fn start_cg(&mut self) -> f64 {
        for (r, g) in self.cg.residual.iter_mut().zip(&self.gradient) {
            *r = -g;
        }
        self.direction.fill(0.0);
        self.precondition();
        self.cg.search.copy_from_slice(&self.cg.preconditioned);
        dot(&self.cg.residual, &self.cg.preconditioned)
    }

    /// One CG step of length `alpha` along the search direction (whose Hessian product is
    /// in `product`): updates direction and residual, preconditions the residual; returns the
    /// new `r^T M^-1 r`.
    fn cg_step(&mut self, alpha: f64) -> f64 {
        for (d, &s) in self.direction.iter_mut().zip(&self.cg.search) {
            *d += alpha * s;
        }
        for (r, &q) in self.cg.residual.iter_mut().zip(&self.cg.product) {
            *r -= alpha * q;
        }
        self.precondition();
        dot(&self.cg.residual, &self.cg.preconditioned)
    }

    /// Whether the CG residual `r = -g - H d`, which is the gradient the quadratic model
    /// predicts after the step, is already well inside the fit's convergence threshold
    /// (a quarter of it, in the infinity norm): solving further would not change whether
    /// the next iterate converges.
    fn residual_meets_tolerance(&self) -> bool {
        let largest = self
            .cg
            .residual
            .iter()
            .fold(0.0, |m: f64, r| m.max(r.abs()));
        largest <= 0.25 * self.gradient_threshold
    }

    /// The next search direction `M^-1 r + beta p`.
    fn next_search(&mut self, beta: f64) {
        for (s, &z) in self.cg.search.iter_mut().zip(&self.cg.preconditioned) {
            *s = z + beta * *s;
        }
    }

    /// The truncated Newton direction of [`DirectionSolver::TruncatedCg`]: preconditioned
    /// CG from zero until `r^T M^-1 r <= eta^2 r_0^T M^-1 r_0` with the forcing term
    /// `eta = min(0.5, sqrt(||g|| / ||g_0||))` (at least [`CG_TOLERANCE`]), until the
    /// iterate reaches the trust radius in the norm of `M` (Steihaug: the direction then ends
    /// on the boundary), or until the budget is spent, in which case the factor is marked
    /// stale so that the next iteration assembles a fresh one. Every iterate of CG from zero
    /// on a positive definite system is a descent direction; should a curvature not be
    /// positive, the direction is the preconditioned negative gradient `M^-1 (-g)` (descent
    /// too, `M` being positive definite). Needs `factor_ready`; returns the products spent,
    /// the direction's `M`-norm and whether it ended on the boundary.
    ///
    /// [`DirectionSolver::TruncatedCg`]: crate::DirectionSolver::TruncatedCg
    pub(super) fn solve_by_truncated_cg(&mut self, radius: f64) -> TruncatedStep {
        let budget = self.cg_budget();
        let ratio = self.gradient_norm() / self.initial_gradient_norm;
        let eta = if ratio.is_finite() {
            ratio.sqrt().clamp(CG_TOLERANCE, 0.5)
        } else {
            0.5
        };
        let mut rz = self.start_cg();
        let target = eta * eta * rz;
        // M-norm recurrences (Steihaug): d^T M d, d^T M p, p^T M p.
        let (mut dmd, mut dmp, mut pmp) = (0.0, 0.0, rz);
        let mut step = TruncatedStep {
            products: 0,
            norm: 0.0,
            on_boundary: false,
        };
        if !(rz > 0.0) {
            // Zero gradient: nothing to do.
            return step;
        }
        for products in 1..=budget {
            step.products = products;
            self.hessian_times_search();
            let curvature = dot(&self.cg.search, &self.cg.product);
            let alpha = rz / curvature;
            let beyond = dmd + 2.0 * alpha * dmp + alpha * alpha * pmp > radius * radius;
            if !(curvature > 0.0) || beyond {
                if curvature > 0.0 || products == 1 {
                    // To the boundary along the search direction (from the last iterate).
                    let tau = if radius.is_finite() {
                        (-dmp + (dmp * dmp + pmp * (radius * radius - dmd)).max(0.0).sqrt()) / pmp
                    } else {
                        1.0
                    };
                    for (d, &s) in self.direction.iter_mut().zip(&self.cg.search) {
                        *d += tau * s;
                    }
                    dmd += 2.0 * tau * dmp + tau * tau * pmp;
                }
                if !(curvature > 0.0) {
                    self.factor_ready = false;
                }
                step.norm = dmd.max(0.0).sqrt();
                step.on_boundary = beyond;
                return step;
            }
            dmd += 2.0 * alpha * dmp + alpha * alpha * pmp;
            let next = self.cg_step(alpha);
            if next <= target || self.residual_meets_tolerance() {
                step.norm = dmd.max(0.0).sqrt();
                return step;
            }
            let beta = next / rz;
            self.next_search(beta);
            dmp = beta * (dmp + alpha * pmp);
            pmp = next + beta * beta * pmp;
            rz = next;
        }
        self.factor_ready = false;
        self.grow_preconditioner();
        step.norm = dmd.max(0.0).sqrt();
        step
    }
}
