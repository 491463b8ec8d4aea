//! Errors of the learning crate.

/// What can go wrong when validating data, fitting, predicting, cross-validating or
/// validating a decoded model.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum LearningError {
    /// The feature matrix has no columns.
    #[error("feature matrix has zero features per sample")]
    NoFeatures,
    /// A flat feature buffer whose length is not a multiple of the number of features.
    #[error(
        "feature buffer of length {len} is not a whole number of rows of {n_features} features"
    )]
    RaggedFeatures {
        /// Length of the flat buffer.
        len: usize,
        /// Requested number of features per row.
        n_features: usize,
    },
    /// A non-finite feature value.
    #[error("feature value at row {row}, column {column} is not finite ({value:?})")]
    NonFinite {
        /// Sample (row) index.
        row: usize,
        /// Feature (column) index.
        column: usize,
        /// The offending value.
        value: f64,
    },
    /// Fitting needs at least one sample.
    #[error("cannot fit on zero samples")]
    NoSamples,
    /// Two inputs that must have matching sizes do not.
    #[error("{what}: expected {expected}, got {found}")]
    SizeMismatch {
        /// Which input.
        what: &'static str,
        /// The size that was expected.
        expected: usize,
        /// The size that was given.
        found: usize,
    },
    /// A class label that is not below the number of classes.
    #[error("label {label} at row {row} is out of range: there are {n_classes} classes")]
    LabelOutOfRange {
        /// Sample (row) index.
        row: usize,
        /// The offending label.
        label: usize,
        /// Number of classes.
        n_classes: usize,
    },
    /// Classification needs at least two classes.
    #[error("need at least 2 classes, got {n_classes}")]
    TooFewClasses {
        /// Requested number of classes.
        n_classes: usize,
    },
    /// A hyper-parameter outside its domain.
    #[error("invalid parameter `{name}` = {value}: {reason}")]
    InvalidParameter {
        /// Parameter name.
        name: &'static str,
        /// Its value, as text.
        value: String,
        /// What the valid domain is.
        reason: &'static str,
    },
    /// The Hessian could not be factorised even after damping.
    #[error(
        "Newton iteration {iteration}: Hessian not positive definite even with damping {damping:e}"
    )]
    Singular {
        /// Newton iteration (1-based) at which it happened.
        iteration: usize,
        /// The largest diagonal damping that was tried.
        damping: f64,
    },
    /// A logit that is NaN at prediction (an overflow of opposite signs in the linear part).
    #[error("logit of class {class} is NaN: the linear model overflowed on this input")]
    NanLogit {
        /// Class whose logit is NaN.
        class: usize,
    },
    /// Cross-validation needs at least as many distinct groups as folds.
    #[error("grouped cross-validation needs at least {folds} distinct groups, found {groups}")]
    TooFewGroups {
        /// Distinct groups found.
        groups: usize,
        /// Requested folds.
        folds: usize,
    },
    /// A numerical routine failed (the text names it).
    #[error("numerical failure: {0}")]
    Numerical(&'static str),
    /// Cross-validation was given no candidate configuration.
    #[error("cross-validation needs at least one candidate configuration")]
    NoCandidates,
}
