//! L2-regularised multinomial logistic regression solved by Newton's method (docs/conventions.md
//! section 5, the paper's section 7), built for speed.
//!
//! * [`Features`] wraps a row-major `n x d` buffer of raw features (validated: sizes,
//!   finite values).
//! * [`LogisticRegression`] holds the hyper-parameters and [`fit`](LogisticRegression::fit)s a
//!   [`LogisticModel`], returning a [`FitReport`] with the per-iteration log.
//! * [`LogisticModel`] predicts from raw features (the standardiser is stored inside),
//!   allocation-free with [`LogisticModel::predict_proba_into`], in parallel with
//!   [`LogisticModel::predict_proba_batch`]; it is stored inside the files of the crates
//!   that use it, which run its [`camloc_store::Validate`] check after decoding.
//! * Prediction ([`LogisticModel`]'s logits, [`RidgeModel`], the components of
//!   [`QuadraticExpansion`]) runs one kernel, a linear map on raw features with the
//!   standardisation folded into its weights, packed so that each block of 4 features meets
//!   each output's 4 weights in one stream; the arithmetic is written once on `pulp`'s SIMD
//!   vectors and runs with AVX2 and FMA where the CPU has them (chosen at run time), else one
//!   value at a time. The two agree up to rounding.
//! * [`RidgeModel`] (multi-output ridge regression) and [`DirectionHeads`] (one ridge
//!   regression of a unit direction per class, with a calibrated uncertainty and an
//!   [`ElevationFit`] per class) refine a class into a continuous direction.
//! * [`QuadraticExpansion`] maps features to themselves and the pairwise products of their
//!   leading whitened principal components, so that the same learner fits a quadratic model.
//! * [`cross_validate_grouped`] selects hyper-parameters by k-fold cross-validation with
//!   groups (subjects) kept within one fold.
//!
//! # Objective
//!
//! Multinomial (default), eq. 8 and 11, with the full `(d + 1) K` parametrisation:
//! `f(W, b) = -sum_i log softmax(W x_i + b)_{y_i} + lambda ||W||_F^2`, the bias not
//! penalised. One-vs-rest (eq. 9) fits one binary problem per class. See
//! [`LogisticRegression`] for the exact definitions and the stopping rule, and the
//! [`newton`] module for how the Hessian is assembled.
//!
//! # Example
//!
//! ```
//! use camloc_learning::{Features, LogisticRegression};
//!
//! // Two features, three well-separated classes.
//! let data = [0.0, 0.1, 0.2, 0.0, 5.0, 5.1, 5.2, 5.0, -5.0, 5.0, -5.1, 5.2];
//! let labels = [0, 0, 1, 1, 2, 2];
//! let x = Features::new(&data, 2)?;
//! let (model, report) = LogisticRegression::default().fit(&x, &labels, 3)?;
//! assert!(report.converged);
//! let p = model.predict_proba(&[5.1, 5.1])?;
//! assert_eq!(model.predict(&[5.1, 5.1])?, 1);
//! assert!((p.iter().sum::<f64>() - 1.0).abs() < 1e-12);
//! # Ok::<(), camloc_learning::LearningError>(())
//! ```

mod config;
mod cv;
mod data;
mod design;
mod elevation_fit;
mod error;
mod expansion;
mod fit;
mod hessian;
mod kernel;
mod model;
pub mod newton;
mod ridge;
mod softmax;
mod standardise;

pub use config::{
    DirectionSolver, LogisticRegression, MAX_LAMBDA, MIN_PRECONDITIONER_ROWS, Mode,
    PRECONDITIONER_ROWS_PER_PARAMETER,
};
pub use cv::{CandidateScore, CvReport, cross_validate_grouped, group_k_fold};
pub use data::Features;
pub use design::DesignRows;
pub use elevation_fit::{
    ELEVATION_FIT_MAX_ERROR_DEG, ELEVATION_FIT_MIN_SAMPLES, ELEVATION_FIT_MIN_SLOPE, ElevationFit,
};
pub use error::LearningError;
pub use expansion::{COMPONENT_LIMIT, MAX_EXPANSION_COMPONENTS, QuadraticExpansion};
pub use model::LogisticModel;
pub use newton::{FitReport, IterationLog, NewtonProblem, Termination};
pub use ridge::{CONFIDENCE_BINS, DirectionHeads, RidgeModel, angle_deg};
pub use softmax::softmax_in_place;
pub use standardise::Standardiser;
