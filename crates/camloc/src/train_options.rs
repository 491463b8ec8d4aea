//! How to train a [`CameraLocalizer`](crate::CameraLocalizer) ([`TrainOptions`]: descriptor,
//! capacity, regression, augmentation, viewpoint heads) and what a model was trained on
//! ([`TrainingInfo`]).

use camloc_dataset::Protocol;
use camloc_features::Descriptor;
use camloc_learning::{DirectionSolver, LogisticRegression};
use camloc_skeleton::NUM_LANDMARKS;
use serde::{Deserialize, Serialize};

use crate::CamlocError;

/// Largest number of dropout copies [`TrainOptions::validate`] accepts: each copy adds as many
/// descriptor rows as the training set has samples (with mirroring, twice that), so the bound
/// keeps memory within about eleven times that of the plain training set.
pub const MAX_DROPOUT_COPIES: f64 = 10.0;

/// Random landmark dropout used in training so that localization copes with missing
/// landmarks: `copies` augmented copies of the training set are appended, in each of which
/// every sample loses between 1 and `max_missing` random non-torso landmarks (whose descriptor
/// values are imputed, as at prediction time).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct LandmarkDropout {
    /// Number of augmented copies of the training set, 0 to [`MAX_DROPOUT_COPIES`]
    /// (fractions allowed: 0.5 = half of the samples, chosen at random).
    pub copies: f64,
    /// Most landmarks dropped from one sample (1..=13).
    pub max_missing: usize,
    /// Random seed.
    pub seed: u64,
}

impl LandmarkDropout {
    /// Checks the settings: `copies` finite in `0..=MAX_DROPOUT_COPIES`, `max_missing` in
    /// `1..=13` (every landmark but the pelvis and neck).
    ///
    /// # Errors
    /// [`CamlocError::InvalidOption`] naming the setting.
    pub fn validate(&self) -> Result<(), CamlocError> {
        if !(self.copies >= 0.0 && self.copies <= MAX_DROPOUT_COPIES) {
            return Err(CamlocError::InvalidOption {
                name: "dropout copies",
                detail: format!(
                    "must be a number from 0 to {MAX_DROPOUT_COPIES}, got {}",
                    self.copies
                ),
            });
        }
        if self.max_missing == 0 || self.max_missing > NUM_LANDMARKS - 2 {
            return Err(CamlocError::InvalidOption {
                name: "dropout max_missing",
                detail: format!(
                    "must be from 1 to {}, got {}",
                    NUM_LANDMARKS - 2,
                    self.max_missing
                ),
            });
        }
        Ok(())
    }
}

impl Default for LandmarkDropout {
    /// One augmented copy with up to 3 missing landmarks, seed 0.
    fn default() -> Self {
        LandmarkDropout {
            copies: 1.0,
            max_missing: 3,
            seed: 0,
        }
    }
}

/// Default ridge weight lambda of the localizer (on the sum of per-sample losses), chosen by
/// cross-validation grouped by subject on the CMU data (docs/RESULTS.md).
pub const DEFAULT_LAMBDA: f64 = 1.0;

/// Default ridge weight of the continuous-viewpoint heads ([`TrainOptions::viewpoint_lambda`]),
/// measured by `cargo xtask generalise` (issue 11).
pub const DEFAULT_VIEWPOINT_LAMBDA: f64 = 1.0;

/// Principal components of the default quadratic expansion ([`Capacity::Quadratic`]),
/// measured by `cargo xtask generalise` (docs/RESULTS.md).
pub const DEFAULT_QUADRATIC_COMPONENTS: usize = 30;

/// Default ridge weight lambda of a quadratic classifier ([`Capacity::Quadratic`], on the sum
/// of per-sample losses): its hundreds of features need more weight than the linear model's
/// [`DEFAULT_LAMBDA`]. Chosen on validation subjects (training subjects held out of the fit,
/// issue 21): lambda 100 scored within half a point of lambda 1 and fitted 4x faster.
pub const DEFAULT_QUADRATIC_LAMBDA: f64 = 100.0;

/// Gradient tolerance per sample of a quadratic classifier's fit. Chosen on validation
/// subjects (training subjects held out of the fit, `cargo xtask postures --test-subjects
/// 114,13,75,07,14`): tolerances 1e-4, 3e-4 and 1e-3 scored within 0.05 points of each other
/// on `jittered`, `sphere`, `rig` and its seated and low poses, with 13, 9 and 6 Newton
/// iterations (78.0, 53.4 and 28.7 s); the default model's fit stops after 9 iterations,
/// where 1e-4 took 37 (docs/RESULTS.md).
pub const QUADRATIC_GRADIENT_TOLERANCE: f64 = 1e-3;

/// Samples the preconditioning Hessian of the default quadratic model's Newton solver is
/// assembled on ([`DirectionSolver::TruncatedCg`]).
pub const DEFAULT_PRECONDITIONER_ROWS: usize = 40_000;

/// Samples (at least) whose Hessian the conjugate-gradient products of the default quadratic
/// model's Newton solver read ([`DirectionSolver::TruncatedCg`]'s `product_rows`): about an
/// eighth of the default model's 1.27 million rows, the gradient, objective and line search
/// on every row. The rows are mirror image pairs, and the subsample keeps each row with its
/// image, so that the fit stays mirror-symmetric as the exact one does (docs/RESULTS.md,
/// Performance: 2x faster, the same validation accuracy).
pub const DEFAULT_PRODUCT_ROWS: usize = 160_000;

/// Which features the multinomial regression sees: its capacity.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Capacity {
    /// The descriptor itself: a linear model of it (the paper's).
    Linear,
    /// The descriptor and the pairwise products of its `components` leading whitened
    /// principal components ([`QuadraticExpansion`](camloc_learning::QuadraticExpansion),
    /// fitted on the training descriptors): a quadratic model of the descriptor, still fitted
    /// by Newton's method.
    Quadratic {
        /// Principal components whose products are added (1 to the descriptor's length, at
        /// most 64).
        components: usize,
    },
}

impl Capacity {
    /// Short name: `linear` or `quadratic-<components>`.
    pub fn name(&self) -> String {
        match self {
            Capacity::Linear => "linear".into(),
            Capacity::Quadratic { components } => format!("quadratic-{components}"),
        }
    }
}

impl std::fmt::Display for Capacity {
    /// [`Capacity::name`].
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.name())
    }
}

impl std::str::FromStr for Capacity {
    type Err = String;

    /// Parses [`Capacity::name`]: `linear` or `quadratic-K` with `K` from 1 to 64.
    fn from_str(text: &str) -> Result<Capacity, String> {
        if text == "linear" {
            return Ok(Capacity::Linear);
        }
        match text.strip_prefix("quadratic-").map(str::parse::<usize>) {
            Some(Ok(components))
                if (1..=camloc_learning::MAX_EXPANSION_COMPONENTS).contains(&components) =>
            {
                Ok(Capacity::Quadratic { components })
            }
            _ => Err(format!(
                "expected 'linear' or 'quadratic-K' with K from 1 to {}, got '{text}'",
                camloc_learning::MAX_EXPANSION_COMPONENTS
            )),
        }
    }
}

/// How to train a [`CameraLocalizer`](crate::CameraLocalizer).
#[derive(Clone, Debug, PartialEq)]
pub struct TrainOptions {
    /// The pose descriptor (default: [`Descriptor::Joints`]).
    pub descriptor: Descriptor,
    /// The features the classifier sees (default: [`Capacity::Linear`]; see
    /// [`with_capacity`](Self::with_capacity)).
    pub capacity: Capacity,
    /// The classifier and its Newton solver settings.
    pub regression: LogisticRegression,
    /// Landmark dropout augmentation (`None`: train on the samples as they are).
    pub dropout: Option<LandmarkDropout>,
    /// Add the left-right mirror image of every sample, labelled with the mirrored camera
    /// (an exact augmentation: the mirrored image is what the mirrored camera sees of the
    /// mirrored person), so that predictions respect the body's symmetry.
    pub mirror: bool,
    /// Ridge weight of the continuous-viewpoint heads fitted on the training samples (see
    /// [`CameraLocalizer::fit_viewpoint`](crate::CameraLocalizer::fit_viewpoint)); `None`: no
    /// heads, localizations then carry no azimuth, elevation or uncertainty.
    pub viewpoint_lambda: Option<f64>,
    /// Classify (posture, camera) pairs: the coarse [`PostureGroup`] of each training
    /// sample's 3D pose (upright, low, bent) times the cameras, one multinomial model whose
    /// probabilities are summed over the postures to the cameras' (docs/conventions.md
    /// section 5). Each camera then has a linear template per posture.
    ///
    /// [`PostureGroup`]: camloc_dataset::PostureGroup
    pub posture_classes: bool,
    /// How far the camera priors move from the training data's towards even ones, from 0
    /// (as the training views are spread) to 1 (every camera equally likely a priori): after
    /// the fit, each class's bias is lowered by this times the log of its camera's share of
    /// the training rows relative to an even share. Training views of studio cameras, nearly
    /// all in the middle ring, tilt predictions towards that ring unless balanced.
    pub camera_balance: f64,
    /// What the viewpoint heads see when training fits them: [`Capacity::Linear`], the
    /// classifier's features; [`Capacity::Quadratic`], their own quadratic expansion of the
    /// descriptor ([`CameraLocalizer::fit_viewpoint_with_capacity`]).
    ///
    /// [`CameraLocalizer::fit_viewpoint_with_capacity`]: crate::CameraLocalizer::fit_viewpoint_with_capacity
    pub viewpoint_capacity: Capacity,
}

impl Default for TrainOptions {
    /// Joints descriptor, linear capacity, multinomial regression with [`DEFAULT_LAMBDA`]
    /// (truncated Newton: conjugate gradients on Hessian-vector products, preconditioned by a
    /// subsampled Hessian; [`DirectionSolver::PreconditionedCg`]), dropout with one copy,
    /// mirror augmentation, viewpoint heads with [`DEFAULT_VIEWPOINT_LAMBDA`], cameras
    /// balanced a priori, no posture classes.
    fn default() -> Self {
        TrainOptions {
            descriptor: Descriptor::default(),
            capacity: Capacity::Linear,
            regression: LogisticRegression::default().with_lambda(DEFAULT_LAMBDA),
            dropout: Some(LandmarkDropout::default()),
            mirror: true,
            viewpoint_lambda: Some(DEFAULT_VIEWPOINT_LAMBDA),
            posture_classes: false,
            camera_balance: 1.0,
            viewpoint_capacity: Capacity::Linear,
        }
    }
}

impl TrainOptions {
    /// `self` with `capacity` and the regression settings that suit it (set the lambda
    /// after this call to choose another): for [`Capacity::Quadratic`] (hundreds of
    /// features, `(d + 1) K` in the thousands) lambda [`DEFAULT_QUADRATIC_LAMBDA`], gradient
    /// tolerance [`QUADRATIC_GRADIENT_TOLERANCE`] and truncated Newton-CG on a Hessian of
    /// [`DEFAULT_PRECONDITIONER_ROWS`] samples and products on [`DEFAULT_PRODUCT_ROWS`]
    /// ([`DirectionSolver::TruncatedCg`]), whose assemblies cost a fraction of full ones;
    /// for [`Capacity::Linear`] the defaults ([`DEFAULT_LAMBDA`],
    /// [`LogisticRegression::default`]'s tolerance, [`DirectionSolver::PreconditionedCg`],
    /// whose preconditioner is sized to the problem).
    pub fn with_capacity(mut self, capacity: Capacity) -> Self {
        self.capacity = capacity;
        let linear = LogisticRegression::default();
        (
            self.regression.lambda,
            self.regression.gradient_tolerance,
            self.regression.direction_solver,
        ) = match capacity {
            Capacity::Linear => (
                DEFAULT_LAMBDA,
                linear.gradient_tolerance,
                DirectionSolver::PreconditionedCg,
            ),
            Capacity::Quadratic { .. } => (
                DEFAULT_QUADRATIC_LAMBDA,
                QUADRATIC_GRADIENT_TOLERANCE,
                DirectionSolver::TruncatedCg {
                    preconditioner_rows: DEFAULT_PRECONDITIONER_ROWS,
                    product_rows: DEFAULT_PRODUCT_ROWS,
                },
            ),
        };
        self
    }

    /// Checks every setting: the descriptor's, the regression's (lambda finite and >= 0,
    /// tolerances), the dropout's ([`LandmarkDropout::validate`]) and the viewpoint heads'
    /// lambda (finite and >= 0). Training calls it first.
    ///
    /// # Errors
    /// [`CamlocError::Feature`] for descriptor settings, [`CamlocError::Learning`] for
    /// regression settings, [`CamlocError::InvalidOption`] for dropout and viewpoint settings.
    pub fn validate(&self) -> Result<(), CamlocError> {
        self.descriptor
            .validate()
            .map_err(|source| CamlocError::Feature {
                context: "descriptor settings".into(),
                source,
            })?;
        self.regression.validate()?;
        if let Some(dropout) = &self.dropout {
            dropout.validate()?;
        }
        if let Some(lambda) = self.viewpoint_lambda {
            check_viewpoint_lambda(lambda)?;
        }
        if !(0.0..=1.0).contains(&self.camera_balance) {
            return Err(CamlocError::InvalidOption {
                name: "camera balance",
                detail: format!("must be from 0 to 1, got {}", self.camera_balance),
            });
        }
        for (name, capacity) in [
            ("quadratic components", self.capacity),
            ("viewpoint quadratic components", self.viewpoint_capacity),
        ] {
            if let Capacity::Quadratic { components } = capacity {
                let most = camloc_learning::MAX_EXPANSION_COMPONENTS.min(self.descriptor.len());
                if components == 0 || components > most {
                    return Err(CamlocError::InvalidOption {
                        name,
                        detail: format!(
                            "must be from 1 to {most} for the {} descriptor, got {components}",
                            self.descriptor.name()
                        ),
                    });
                }
            }
        }
        Ok(())
    }
}

/// Checks a [`TrainOptions::viewpoint_lambda`]: finite and >= 0, else
/// [`CamlocError::InvalidOption`].
pub(crate) fn check_viewpoint_lambda(lambda: f64) -> Result<(), CamlocError> {
    if lambda.is_finite() && lambda >= 0.0 {
        Ok(())
    } else {
        Err(CamlocError::InvalidOption {
            name: "viewpoint lambda",
            detail: format!("{lambda}: must be finite and >= 0"),
        })
    }
}

/// What a model was trained on (kept in the model file for `camloc` to report).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TrainingInfo {
    /// camloc version that trained the model.
    pub camloc_version: String,
    /// Protocol of the training dataset.
    pub protocol: Protocol,
    /// Training samples (before augmentation).
    pub samples: usize,
    /// Training subjects.
    pub subjects: Vec<String>,
    /// Regression settings.
    pub lambda: f64,
    /// The classifier's capacity.
    pub capacity: Capacity,
    /// Dropout used, if any.
    pub dropout: Option<LandmarkDropout>,
    /// Whether mirror augmentation was used.
    pub mirror: bool,
    /// Whether the classifier classifies (posture, camera) pairs
    /// ([`TrainOptions::posture_classes`]).
    pub posture_classes: bool,
    /// How far the camera priors were balanced ([`TrainOptions::camera_balance`]).
    pub camera_balance: f64,
    /// The model's own prior of each camera (one per camera, summing to 1): the share of
    /// the training rows it had, raised to `1 - camera_balance` and normalised (the balance's
    /// bias shift leaves that prior in the classifier's probabilities). What
    /// [`CameraHeight::Shares`](crate::CameraHeight::Shares) is weighed against.
    pub camera_priors: Vec<f64>,
}
