//! What the conjugate-gradient solvers of the Newton direction report back to the Newton
//! iteration.

/// What [`NewtonProblem::solve_by_cg`](crate::NewtonProblem::solve_by_cg) did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum CgOutcome {
    /// CG was not attempted (no reusable factor, or another solver): assemble and factorise.
    NotTried,
    /// `direction` holds the Newton direction, after `products` Hessian-vector products.
    Solved {
        /// Hessian-vector products spent.
        products: usize,
    },
    /// CG gave up after `products` products (budget spent, too slow a rate, or a
    /// non-positive curvature): `direction` is meaningless, the caller assembles and
    /// factorises the Hessian instead.
    GaveUp {
        /// Hessian-vector products spent.
        products: usize,
    },
}

/// What [`NewtonProblem::solve_by_truncated_cg`](crate::NewtonProblem::solve_by_truncated_cg)
/// did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct TruncatedStep {
    /// Hessian-vector products spent.
    pub(super) products: usize,
    /// Norm of the direction in the preconditioner's metric, `sqrt(d^T M d)`.
    pub(super) norm: f64,
    /// Whether the direction ends on the trust radius.
    pub(super) on_boundary: bool,
}
