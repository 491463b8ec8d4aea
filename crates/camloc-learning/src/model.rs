//! The fitted classifier: standardiser, weights and biases, and prediction.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::data::{check_finite_row, check_labels};
use crate::newton::row_loss;
use crate::softmax::{one_vs_rest_in_place, softmax_in_place};
use crate::standardise::{RawLinear, Standardiser};
use crate::{Features, LearningError, Mode};
use camloc_store::Validate;

/// A fitted logistic-regression classifier over `n_features` raw features and `n_classes`
/// classes.
///
/// Self-contained: it keeps the standardiser fitted on the training data, so every method
/// takes raw features (the same units the training features had). Logits are
/// `z_k = b_k + sum_j W[j][k] (x_j - mean_j) / scale_j`.
#[derive(Clone, Debug, PartialEq)]
pub struct LogisticModel {
    parameters: Parameters,
    /// The logits on raw features (standardisation folded in), derived from `parameters`.
    raw: RawLinear,
}

/// What a [`LogisticModel`] stores; the rest is derived from it on decoding.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
struct Parameters {
    mode: Mode,
    lambda: f64,
    standardiser: Standardiser,
    n_classes: usize,
    /// Feature-major `n_features x n_classes`: `weights[j * n_classes + k]`.
    weights: Vec<f64>,
    biases: Vec<f64>,
}

impl Serialize for LogisticModel {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        self.parameters.serialize(serializer)
    }
}

impl<'de> Deserialize<'de> for LogisticModel {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        Parameters::deserialize(deserializer).map(LogisticModel::from_parameters)
    }
}

impl LogisticModel {
    /// Builds a model from its parts (e.g. coefficients fitted elsewhere).
    ///
    /// `weights` is feature-major, `weights[j * n_classes + k]` being the weight of
    /// standardised feature `j` for class `k`; `biases` has one entry per class;
    /// `lambda` is the ridge weight the model was (or is deemed) fitted with, used by
    /// [`objective`](Self::objective).
    ///
    /// # Errors
    /// [`LearningError::TooFewClasses`] for fewer than 2 biases,
    /// [`LearningError::SizeMismatch`] if `weights` is not `n_features * n_classes` long,
    /// [`LearningError::InvalidParameter`] for a non-finite weight, bias or lambda (or a
    /// negative lambda).
    pub fn new(
        mode: Mode,
        lambda: f64,
        standardiser: Standardiser,
        weights: Vec<f64>,
        biases: Vec<f64>,
    ) -> Result<Self, LearningError> {
        let model = Self::from_validated_parts(mode, lambda, standardiser, weights, biases);
        model.validate()?;
        Ok(model)
    }

    /// Assembles a model from parts known to be consistent (the Newton solver's output).
    pub(crate) fn from_validated_parts(
        mode: Mode,
        lambda: f64,
        standardiser: Standardiser,
        weights: Vec<f64>,
        biases: Vec<f64>,
    ) -> Self {
        Self::from_parameters(Parameters {
            mode,
            lambda,
            standardiser,
            n_classes: biases.len(),
            weights,
            biases,
        })
    }

    /// The model of `parameters`, with the logits on raw features derived from them.
    fn from_parameters(parameters: Parameters) -> Self {
        let p = &parameters;
        let raw = Self::fold(&p.standardiser, &p.weights, &p.biases);
        LogisticModel { parameters, raw }
    }

    /// The logits on raw features: feature-major `weights` on standardised features with the
    /// standardisation folded in.
    fn fold(standardiser: &Standardiser, weights: &[f64], biases: &[f64]) -> RawLinear {
        let k = biases.len();
        RawLinear::fold(
            standardiser,
            |j, c| weights.get(j * k + c).copied().unwrap_or(0.0),
            weights.len(),
            biases,
        )
    }

    /// This model with `shift[k]` added to the bias (logit) of every class `k`: a change of
    /// the class priors, `p(k | x)` reweighted by `exp(shift[k])` and renormalised.
    ///
    /// # Errors
    /// [`LearningError::SizeMismatch`] unless `shift` has one entry per class,
    /// [`LearningError::InvalidParameter`] for a non-finite shifted bias.
    pub fn with_bias_shift(mut self, shift: &[f64]) -> Result<Self, LearningError> {
        if shift.len() != self.parameters.n_classes {
            return Err(LearningError::SizeMismatch {
                what: "bias shift (one per class)",
                expected: self.parameters.n_classes,
                found: shift.len(),
            });
        }
        for (b, s) in self.parameters.biases.iter_mut().zip(shift) {
            *b += s;
        }
        let model = Self::from_parameters(self.parameters);
        model.validate()?;
        Ok(model)
    }

    /// Checks every invariant (sizes, finite values, a valid standardiser): used by
    /// [`new`](Self::new) and, through [`Validate`], after decoding a stored model (also one
    /// nested in another file).
    ///
    /// # Errors
    /// The first violated invariant, as in [`new`](Self::new), and
    /// [`LearningError::NoFeatures`] for a model of zero features.
    pub fn validate(&self) -> Result<(), LearningError> {
        self.parameters.standardiser.validate()?;
        if self.n_features() == 0 {
            return Err(LearningError::NoFeatures);
        }
        if self.parameters.n_classes < 2 {
            return Err(LearningError::TooFewClasses {
                n_classes: self.parameters.n_classes,
            });
        }
        if self.parameters.biases.len() != self.parameters.n_classes {
            return Err(LearningError::SizeMismatch {
                what: "model biases (one per class)",
                expected: self.parameters.n_classes,
                found: self.parameters.biases.len(),
            });
        }
        let expected = self.n_features().checked_mul(self.parameters.n_classes);
        if expected != Some(self.parameters.weights.len()) {
            let expected = expected.unwrap_or(usize::MAX);
            return Err(LearningError::SizeMismatch {
                what: "model weights (n_features * n_classes)",
                expected,
                found: self.parameters.weights.len(),
            });
        }
        if !(self.parameters.lambda.is_finite() && self.parameters.lambda >= 0.0) {
            return Err(LearningError::InvalidParameter {
                name: "lambda",
                value: format!("{:?}", self.parameters.lambda),
                reason: "must be finite and >= 0",
            });
        }
        all_finite(
            "model coefficient",
            &self.parameters.weights,
            &self.parameters.biases,
        )
    }

    /// Number of raw input features.
    pub fn n_features(&self) -> usize {
        self.parameters.standardiser.n_features()
    }

    /// Number of classes.
    pub fn n_classes(&self) -> usize {
        self.parameters.n_classes
    }

    /// Multinomial or one-vs-rest.
    pub fn mode(&self) -> Mode {
        self.parameters.mode
    }

    /// Ridge weight the model was fitted with.
    pub fn lambda(&self) -> f64 {
        self.parameters.lambda
    }

    /// The feature standardiser applied before the linear part.
    pub fn standardiser(&self) -> &Standardiser {
        &self.parameters.standardiser
    }

    /// Weights on the standardised features, feature-major:
    /// `weights()[j * n_classes() + k]` is feature `j`, class `k`.
    pub fn weights(&self) -> &[f64] {
        &self.parameters.weights
    }

    /// One bias per class.
    pub fn biases(&self) -> &[f64] {
        &self.parameters.biases
    }

    /// Checks that `x` has `n_features` values.
    fn check_sample(&self, x: &[f64]) -> Result<(), LearningError> {
        if x.len() != self.n_features() {
            return Err(LearningError::SizeMismatch {
                what: "number of features of the sample",
                expected: self.n_features(),
                found: x.len(),
            });
        }
        Ok(())
    }

    /// Checks that an output slice has one entry per class.
    fn check_output(&self, out: &[f64]) -> Result<(), LearningError> {
        if out.len() != self.parameters.n_classes {
            return Err(LearningError::SizeMismatch {
                what: "output length (one per class)",
                expected: self.parameters.n_classes,
                found: out.len(),
            });
        }
        Ok(())
    }

    /// Logits of one raw sample into `out` (one per class), without allocating: softmax
    /// inputs for [`Mode::Multinomial`], per-class binary logits for [`Mode::OneVsRest`].
    ///
    /// # Errors
    /// [`LearningError::SizeMismatch`] for a sample or output of the wrong length,
    /// [`LearningError::NonFinite`] (row 0) for a non-finite feature (`out` is then
    /// overwritten with unspecified values).
    pub fn decision_function_into(&self, x: &[f64], out: &mut [f64]) -> Result<(), LearningError> {
        self.check_sample(x)?;
        self.check_output(out)?;
        self.logits_unchecked(x, out);
        // A non-finite feature makes every logit non-finite (its weight times it is infinite
        // or NaN), so the features are only searched when a logit is.
        if !out.iter().all(|z| z.is_finite()) {
            check_finite_row(x, 0, x.len().max(1))?;
        }
        Ok(())
    }

    /// Logits of a sample whose sizes have been checked.
    #[inline]
    fn logits_unchecked(&self, x: &[f64], out: &mut [f64]) {
        self.raw.apply_into(x, out);
    }

    /// Logits of one raw sample (see [`decision_function_into`](Self::decision_function_into)).
    ///
    /// # Errors
    /// As [`decision_function_into`](Self::decision_function_into).
    pub fn decision_function(&self, x: &[f64]) -> Result<Vec<f64>, LearningError> {
        let mut out = vec![0.0; self.parameters.n_classes];
        self.decision_function_into(x, &mut out)?;
        Ok(out)
    }

    /// Class probabilities of one raw sample into `out`, without allocating. They are
    /// non-negative and sum to 1 (within rounding), for any finite input.
    ///
    /// # Errors
    /// As [`decision_function_into`](Self::decision_function_into), plus
    /// [`LearningError::NanLogit`] if the linear part overflows to NaN.
    pub fn predict_proba_into(&self, x: &[f64], out: &mut [f64]) -> Result<(), LearningError> {
        self.decision_function_into(x, out)?;
        if let Some(class) = out.iter().position(|z| z.is_nan()) {
            return Err(LearningError::NanLogit { class });
        }
        match self.parameters.mode {
            Mode::Multinomial => softmax_in_place(out),
            Mode::OneVsRest => one_vs_rest_in_place(out),
        }
        Ok(())
    }

    /// Class probabilities of one raw sample (see [`predict_proba_into`](Self::predict_proba_into)).
    ///
    /// # Errors
    /// As [`predict_proba_into`](Self::predict_proba_into).
    pub fn predict_proba(&self, x: &[f64]) -> Result<Vec<f64>, LearningError> {
        let mut out = vec![0.0; self.parameters.n_classes];
        self.predict_proba_into(x, &mut out)?;
        Ok(out)
    }

    /// Most probable class of one raw sample (lowest index on ties).
    ///
    /// # Errors
    /// As [`predict_proba_into`](Self::predict_proba_into).
    pub fn predict(&self, x: &[f64]) -> Result<usize, LearningError> {
        Ok(argmax(&self.predict_proba(x)?))
    }

    /// Class probabilities of every sample, row-major `n_samples x n_classes`, computed in
    /// parallel (rayon); each row is bit-identical to [`predict_proba`](Self::predict_proba)
    /// on that sample.
    ///
    /// # Errors
    /// [`LearningError::SizeMismatch`] if `x` does not have `n_features` columns,
    /// [`LearningError::NanLogit`] as for a single sample.
    pub fn predict_proba_batch(&self, x: &Features<'_>) -> Result<Vec<f64>, LearningError> {
        if x.n_features() != self.n_features() {
            return Err(LearningError::SizeMismatch {
                what: "number of feature columns",
                expected: self.n_features(),
                found: x.n_features(),
            });
        }
        let mut out = vec![0.0; x.n_samples() * self.parameters.n_classes];
        out.par_chunks_mut(self.parameters.n_classes)
            .zip(x.data().par_chunks(x.n_features()))
            .try_for_each(|(o, row)| self.predict_proba_into(row, o))?;
        Ok(out)
    }

    /// Most probable class of every sample (see [`predict_proba_batch`](Self::predict_proba_batch)).
    ///
    /// # Errors
    /// As [`predict_proba_batch`](Self::predict_proba_batch).
    pub fn predict_batch(&self, x: &Features<'_>) -> Result<Vec<usize>, LearningError> {
        Ok(self
            .predict_proba_batch(x)?
            .chunks_exact(self.parameters.n_classes)
            .map(argmax)
            .collect())
    }

    /// Fraction of samples whose predicted class equals the label, in `[0, 1]` (0 for no
    /// samples).
    ///
    /// # Errors
    /// As [`predict_proba_batch`](Self::predict_proba_batch), plus label errors as in
    /// [`LogisticRegression::fit`](crate::LogisticRegression::fit).
    pub fn accuracy(&self, x: &Features<'_>, y: &[usize]) -> Result<f64, LearningError> {
        check_labels(y, x.n_samples(), self.parameters.n_classes)?;
        let predicted = self.predict_batch(x)?;
        let correct = predicted.iter().zip(y).filter(|(p, t)| p == t).count();
        Ok(if y.is_empty() {
            0.0
        } else {
            correct as f64 / y.len() as f64
        })
    }

    /// The training objective of this model on `(x, y)`: the per-sample losses summed plus
    /// `lambda ||W||^2` (see [`LogisticRegression`](crate::LogisticRegression) for both
    /// modes), with the model's own standardisation. After a fit it equals the objective
    /// reported in the last [`IterationLog`](crate::IterationLog) up to rounding.
    ///
    /// # Errors
    /// As [`accuracy`](Self::accuracy).
    pub fn objective(&self, x: &Features<'_>, y: &[usize]) -> Result<f64, LearningError> {
        check_labels(y, x.n_samples(), self.parameters.n_classes)?;
        if x.n_features() != self.n_features() {
            return Err(LearningError::SizeMismatch {
                what: "number of feature columns",
                expected: self.n_features(),
                found: x.n_features(),
            });
        }
        let n_blocks = match self.parameters.mode {
            Mode::Multinomial => 1,
            Mode::OneVsRest => self.parameters.n_classes,
        };
        let mut logits = vec![0.0; self.parameters.n_classes];
        let mut partial = vec![0.0; n_blocks];
        for (row, &label) in x.rows().zip(y) {
            self.logits_unchecked(row, &mut logits);
            row_loss(
                self.parameters.mode,
                label,
                self.parameters.n_classes,
                |c| logits[c],
                &mut partial,
            );
        }
        let ridge: f64 =
            self.parameters.weights.iter().map(|w| w * w).sum::<f64>() * self.parameters.lambda;
        Ok(partial.iter().sum::<f64>() + ridge)
    }
}

/// The model's invariants, run after every decode of a stored model (the containing file's
/// own [`Validate`] calls it).
impl Validate for LogisticModel {
    type Invalid = LearningError;

    fn validate(&self) -> Result<(), LearningError> {
        LogisticModel::validate(self)
    }
}

/// Index of the largest value (first one on ties; 0 for an empty slice).
fn argmax(values: &[f64]) -> usize {
    values
        .iter()
        .enumerate()
        .fold((0, f64::NEG_INFINITY), |(bi, bv), (i, &v)| {
            if v > bv { (i, v) } else { (bi, bv) }
        })
        .0
}

/// Checks that every weight and bias is finite; the error names the parameter `name` and the
/// first offending value.
pub(crate) fn all_finite(
    name: &'static str,
    weights: &[f64],
    biases: &[f64],
) -> Result<(), LearningError> {
    match weights.iter().chain(biases).find(|v| !v.is_finite()) {
        Some(v) => Err(LearningError::InvalidParameter {
            name,
            value: format!("{v:?}"),
            reason: "every weight and bias must be finite",
        }),
        None => Ok(()),
    }
}
