//! [`CameraLocalizer`]: descriptor + classifier + camera set, trained, saved and used together.

use camloc_dataset::{Dataset, PostureGroup, Protocol};
use camloc_dataset::{camera_direction_deg, direction_vector};
use camloc_features::Descriptor;
use camloc_geometry::{CameraLabel, CameraSet, Level, Matrix3, Side};
use camloc_learning::{
    DirectionHeads, DirectionSolver, Features, FitReport, IterationLog, LogisticModel,
    LogisticRegression, QuadraticExpansion,
};
use camloc_skeleton::{Landmark, NUM_LANDMARKS, PartialPose2, Pose2};
use camloc_store::{FileKind, Persist, Validate};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
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

/// Samples the preconditioning Hessian of the default quadratic model's Newton solver is
/// assembled on ([`DirectionSolver::TruncatedCg`]).
pub const DEFAULT_PRECONDITIONER_ROWS: usize = 40_000;

/// Which features the multinomial regression sees: its capacity.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Capacity {
    /// The descriptor itself: a linear model of it (the paper's).
    Linear,
    /// The descriptor and the pairwise products of its `components` leading whitened
    /// principal components ([`QuadraticExpansion`], fitted on the training descriptors): a
    /// quadratic model of the descriptor, still fitted by Newton's method.
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

/// How to train a [`CameraLocalizer`].
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
    /// [`CameraLocalizer::fit_viewpoint`]); `None`: no heads, localizations then carry no
    /// azimuth, elevation or uncertainty.
    pub viewpoint_lambda: Option<f64>,
    /// Classify (posture, camera) pairs: the coarse [`PostureGroup`] of each training
    /// sample's 3D pose (upright, low, bent) times the cameras, one multinomial model whose
    /// probabilities are summed over the postures to the cameras' (docs/conventions.md
    /// section 5). Each camera then has a linear template per posture.
    pub posture_classes: bool,
}

impl Default for TrainOptions {
    /// Joints descriptor, linear capacity, multinomial regression with [`DEFAULT_LAMBDA`]
    /// (Newton, conjugate gradients on the last Cholesky factor), dropout with one copy,
    /// mirror augmentation, viewpoint heads with [`DEFAULT_VIEWPOINT_LAMBDA`].
    fn default() -> Self {
        TrainOptions {
            descriptor: Descriptor::default(),
            capacity: Capacity::Linear,
            regression: LogisticRegression::default().with_lambda(DEFAULT_LAMBDA),
            dropout: Some(LandmarkDropout::default()),
            mirror: true,
            viewpoint_lambda: Some(DEFAULT_VIEWPOINT_LAMBDA),
            posture_classes: false,
        }
    }
}

impl TrainOptions {
    /// `self` with `capacity` and the Newton solver that suits it: for
    /// [`Capacity::Quadratic`] (hundreds of features, `(d + 1) K` in the thousands) truncated
    /// Newton-CG on a Hessian of [`DEFAULT_PRECONDITIONER_ROWS`] samples
    /// ([`DirectionSolver::TruncatedCg`]), whose assemblies cost a fraction of full ones; for
    /// [`Capacity::Linear`] the exact default ([`DirectionSolver::PreconditionedCg`]).
    pub fn with_capacity(mut self, capacity: Capacity) -> Self {
        self.capacity = capacity;
        self.regression.direction_solver = match capacity {
            Capacity::Linear => DirectionSolver::PreconditionedCg,
            Capacity::Quadratic { .. } => DirectionSolver::TruncatedCg {
                preconditioner_rows: DEFAULT_PRECONDITIONER_ROWS,
            },
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
        if let Capacity::Quadratic { components } = self.capacity {
            let most = camloc_learning::MAX_EXPANSION_COMPONENTS.min(self.descriptor.len());
            if components == 0 || components > most {
                return Err(CamlocError::InvalidOption {
                    name: "quadratic components",
                    detail: format!(
                        "must be from 1 to {most} for the {} descriptor, got {components}",
                        self.descriptor.name()
                    ),
                });
            }
        }
        Ok(())
    }
}

fn check_viewpoint_lambda(lambda: f64) -> Result<(), CamlocError> {
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
}

/// Where the camera stood, as localized from one 2D pose.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Localization {
    /// Most probable camera (Table 1 numbering for the default cameras).
    pub label: CameraLabel,
    /// Its height class.
    pub level: Level,
    /// Its side of the body.
    pub side: Side,
    /// Its rotation (rows: camera x, y, z axes in the canonical body frame).
    pub rotation: Matrix3,
    /// Probability of `label`.
    pub probability: f64,
    /// Probability of every camera, index [`CameraLabel::index`].
    pub probabilities: Vec<f64>,
    /// `label` after mirror folding (back -> front of the same level, paper section 8.1).
    pub folded_label: CameraLabel,
    /// Landmarks that were missing in the input (their descriptor values were imputed).
    pub missing: Vec<Landmark>,
    /// Continuous camera azimuth in degrees, `[0, 360)`, in the person's canonical frame
    /// (docs/conventions.md section 2: 180 = in front, 270 = the person's left, 0 = behind,
    /// 90 = the person's right); `None` when the model has no viewpoint heads.
    pub azimuth_deg: Option<f64>,
    /// Continuous camera elevation in degrees, `[-90, 90]`, positive above the person;
    /// `None` when the model has no viewpoint heads.
    pub elevation_deg: Option<f64>,
    /// Angular radius in degrees around (`azimuth_deg`, `elevation_deg`) that held about
    /// 68% of the true directions of the calibration samples with a class probability like
    /// this one's; `None` when the model has no viewpoint heads.
    pub uncertainty_deg: Option<f64>,
}

/// A trained camera localizer: descriptor, classifier and the camera set it predicts.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CameraLocalizer {
    descriptor: Descriptor,
    cameras: CameraSet,
    /// The feature expansion between descriptor and classifier ([`Capacity::Quadratic`]);
    /// `None`: the classifier sees the descriptor.
    expansion: Option<QuadraticExpansion>,
    /// The classifier: `cameras.len() * posture_groups` classes, class `g * cameras + c` being
    /// camera `c` (0-based) seen on a body of posture group `g`.
    model: LogisticModel,
    /// Posture groups the classifier's classes are split into (1: none; see
    /// [`TrainOptions::posture_classes`]).
    posture_groups: usize,
    /// Per descriptor value, the training mean used in place of undefined values.
    imputation: Vec<f64>,
    info: TrainingInfo,
    /// Continuous-viewpoint heads refining the class to a direction (`None`: not fitted).
    viewpoint: Option<DirectionHeads>,
}

impl CameraLocalizer {
    /// Trains on every sample of `dataset`. `progress` receives the Newton iteration log.
    /// With [`TrainOptions::viewpoint_lambda`], the viewpoint heads are then fitted on the
    /// same samples ([`fit_viewpoint`](Self::fit_viewpoint)).
    ///
    /// # Errors
    /// Invalid options ([`TrainOptions::validate`]); [`CamlocError::Dataset`] for a sample
    /// whose label is not a camera of the dataset or whose clip index is out of range;
    /// [`CamlocError::Inconsistent`] for an empty dataset, or with viewpoint heads one with a
    /// camera of no samples; [`CamlocError::Feature`] naming the
    /// first sample whose descriptor fails; [`CamlocError::Learning`] from the solver.
    pub fn train(
        dataset: &Dataset,
        options: &TrainOptions,
        progress: impl FnMut(&IterationLog),
    ) -> Result<(CameraLocalizer, FitReport), CamlocError> {
        options.validate()?;
        dataset.validate()?;
        let descriptor = options.descriptor;
        if dataset.samples.is_empty() {
            return Err(CamlocError::Inconsistent {
                what: "dataset",
                detail: "no samples to train on".into(),
            });
        }
        let d = descriptor.len();
        let cameras = &dataset.header.cameras;
        let posture_groups = if options.posture_classes {
            PostureGroup::ALL.len()
        } else {
            1
        };
        let mut poses: Vec<PartialPose2> = dataset.samples.iter().map(sample_pose).collect();
        let mut labels: Vec<u16> = dataset.samples.iter().map(|s| s.label).collect();
        let mut groups: Vec<usize> = dataset
            .samples
            .iter()
            .map(|s| {
                if options.posture_classes {
                    PostureGroup::of(&s.pose3).index()
                } else {
                    0
                }
            })
            .collect();
        if options.mirror {
            poses.extend(poses.iter().map(PartialPose2::mirrored).collect::<Vec<_>>());
            labels.extend(
                labels
                    .iter()
                    .map(|&l| cameras.mirror_left_right(l))
                    .collect::<Vec<_>>(),
            );
            // A mirrored body keeps its posture.
            groups.extend_from_within(..);
        }
        let (mut x, undefined) = extract_rows(&descriptor, &poses)?;
        let imputation = column_means(&x, &undefined, d);
        impute_rows(&mut x, &undefined, &imputation);
        // Labels are 1..=cameras (checked by `dataset.validate()`), mirroring keeps them so.
        let mut y: Vec<usize> = labels
            .iter()
            .zip(&groups)
            .map(|(&l, g)| g * cameras.len() + usize::from(l) - 1)
            .collect();
        if let Some(dropout) = options.dropout {
            let (extra, labels) = augment(&descriptor, &poses, &y, &dropout, &imputation)?;
            x.extend_from_slice(&extra);
            y.extend_from_slice(&labels);
        }
        // The expansion is fitted on the samples (and mirror images) before dropout.
        let expansion = match options.capacity {
            Capacity::Linear => None,
            Capacity::Quadratic { components } => Some(QuadraticExpansion::fit(
                &Features::new(&x[..poses.len() * d], d)?,
                components,
            )?),
        };
        if let Some(e) = &expansion {
            x = e.expand_rows(&Features::new(&x, d)?)?;
        }
        let width = expansion.as_ref().map_or(d, QuadraticExpansion::n_outputs);
        let features = Features::new(&x, width)?;
        let (model, report) = options.regression.fit_with_progress(
            &features,
            &y,
            dataset.header.cameras.len() * posture_groups,
            progress,
        )?;
        let info = TrainingInfo {
            camloc_version: env!("CARGO_PKG_VERSION").to_string(),
            protocol: dataset.header.protocol,
            samples: dataset.samples.len(),
            subjects: dataset.subjects().into_iter().map(|(s, _)| s).collect(),
            lambda: options.regression.lambda,
            capacity: options.capacity,
            dropout: options.dropout,
            mirror: options.mirror,
            posture_classes: options.posture_classes,
        };
        let mut localizer = CameraLocalizer {
            descriptor,
            cameras: dataset.header.cameras.clone(),
            expansion,
            model,
            posture_groups,
            imputation,
            info,
            viewpoint: None,
        };
        if let Some(lambda) = options.viewpoint_lambda {
            let n = dataset.samples.len();
            localizer.fit_viewpoint_rows(&x[..n * width], dataset, lambda)?;
        }
        Ok((localizer, report))
    }

    /// Fits (or refits) the continuous-viewpoint heads on `dataset`: per camera class, a
    /// ridge regression (weight `lambda`) from the descriptor to the unit direction of the
    /// sample's camera (from its rotation), fitted on the samples labelled with that class;
    /// then the uncertainty is calibrated on the same samples, by the class this
    /// localizer chooses and its probability. A dataset whose directions cover the sphere
    /// band (protocol `sphere`) gives heads that resolve directions between the cameras.
    ///
    /// # Errors
    /// [`CamlocError::InvalidOption`] for a bad `lambda`; [`CamlocError::Inconsistent`] when
    /// the dataset's cameras are not this model's or one of them has no samples; dataset,
    /// descriptor and solver errors as in [`train`](Self::train).
    pub fn fit_viewpoint(&mut self, dataset: &Dataset, lambda: f64) -> Result<(), CamlocError> {
        dataset.validate()?;
        if dataset.header.cameras != self.cameras {
            return Err(CamlocError::Inconsistent {
                what: "viewpoint dataset",
                detail: "its cameras are not the model's".into(),
            });
        }
        let poses: Vec<PartialPose2> = dataset.samples.iter().map(sample_pose).collect();
        let x = self.feature_rows(&poses)?;
        self.fit_viewpoint_rows(&x, dataset, lambda)
    }

    /// The classifier's feature rows of `poses` (row-major, [`feature_width`](Self::feature_width)
    /// wide): descriptors in parallel, undefined values imputed, expanded if the model has an
    /// expansion.
    pub(crate) fn feature_rows(&self, poses: &[PartialPose2]) -> Result<Vec<f64>, CamlocError> {
        let (mut x, undefined) = extract_rows(&self.descriptor, poses)?;
        impute_rows(&mut x, &undefined, &self.imputation);
        if let Some(e) = &self.expansion {
            x = e.expand_rows(&Features::new(&x, self.descriptor.len())?)?;
        }
        Ok(x)
    }

    /// The number of features the classifier and the viewpoint heads see: the descriptor's,
    /// or the expansion's outputs.
    fn feature_width(&self) -> usize {
        self.expansion
            .as_ref()
            .map_or(self.descriptor.len(), QuadraticExpansion::n_outputs)
    }

    /// [`fit_viewpoint`](Self::fit_viewpoint) on the samples' feature rows `x` (imputed and
    /// expanded).
    fn fit_viewpoint_rows(
        &mut self,
        x: &[f64],
        dataset: &Dataset,
        lambda: f64,
    ) -> Result<(), CamlocError> {
        check_viewpoint_lambda(lambda)?;
        let features = Features::new(x, self.feature_width())?;
        let directions: Vec<[f64; 3]> = dataset
            .samples
            .iter()
            .map(|s| {
                let (azimuth, elevation) = camera_direction_deg(&s.rotation);
                direction_vector(azimuth, elevation)
            })
            .collect();
        let classes: Vec<usize> = dataset
            .samples
            .iter()
            .map(|s| usize::from(s.label) - 1)
            .collect();
        if let Some(k) = (0..self.cameras.len()).find(|k| !classes.contains(k)) {
            return Err(CamlocError::Inconsistent {
                what: "viewpoint dataset",
                detail: format!(
                    "camera {} has no samples; the viewpoint heads need samples of every camera (or train without heads)",
                    k + 1
                ),
            });
        }
        let mut heads =
            DirectionHeads::fit(&features, &directions, &classes, self.cameras.len(), lambda)?;
        let mut classes = vec![0.0; self.model.n_classes()];
        let mut probabilities = vec![0.0; self.cameras.len()];
        let chosen = features
            .rows()
            .map(|row| {
                self.camera_probabilities_into(row, &mut classes, &mut probabilities)?;
                Ok(most_probable(&probabilities))
            })
            .collect::<Result<Vec<_>, CamlocError>>()?;
        heads.calibrate(&features, &chosen, &directions)?;
        self.viewpoint = Some(heads);
        Ok(())
    }

    /// The probability of every camera for the feature row `x` into `out` (one per
    /// camera): the classifier's class probabilities (into `classes`, one per class) summed
    /// over the posture groups.
    pub(crate) fn camera_probabilities_into(
        &self,
        x: &[f64],
        classes: &mut [f64],
        out: &mut [f64],
    ) -> Result<(), CamlocError> {
        self.model.predict_proba_into(x, classes)?;
        out.fill(0.0);
        for group in classes.chunks_exact(out.len()) {
            for (o, p) in out.iter_mut().zip(group) {
                *o += p;
            }
        }
        Ok(())
    }

    /// Posture groups the classifier's classes are split into (1 unless trained with
    /// [`TrainOptions::posture_classes`]).
    pub fn posture_groups(&self) -> usize {
        self.posture_groups
    }

    /// The continuous-viewpoint heads, if the model has them.
    pub fn viewpoint_heads(&self) -> Option<&DirectionHeads> {
        self.viewpoint.as_ref()
    }

    /// The descriptor the model was trained with.
    pub fn descriptor(&self) -> &Descriptor {
        &self.descriptor
    }

    /// The camera classes.
    pub fn cameras(&self) -> &CameraSet {
        &self.cameras
    }

    /// The feature expansion between descriptor and classifier, if the model has one
    /// ([`Capacity::Quadratic`]).
    pub fn expansion(&self) -> Option<&QuadraticExpansion> {
        self.expansion.as_ref()
    }

    /// The fitted classifier (on the expanded features when the model has an expansion).
    pub fn model(&self) -> &LogisticModel {
        &self.model
    }

    /// What the model was trained on.
    pub fn training_info(&self) -> &TrainingInfo {
        &self.info
    }

    /// Per descriptor value, the training mean used in place of values that depend on a
    /// missing landmark.
    pub fn imputation(&self) -> &[f64] {
        &self.imputation
    }

    /// Localizes the camera of a complete 2D pose (image coordinates, any units).
    ///
    /// # Errors
    /// [`CamlocError::Feature`] for non-finite landmarks or a degenerate torso.
    pub fn localize(&self, pose: &Pose2) -> Result<Localization, CamlocError> {
        self.localize_partial(&PartialPose2::from(*pose))
    }

    /// Localizes the camera of a 2D pose with possibly missing landmarks; values of the
    /// descriptor that depend on a missing landmark are replaced by their training mean.
    ///
    /// # Errors
    /// [`CamlocError::Feature`] when the pelvis or neck is missing, for non-finite landmarks
    /// or a degenerate torso.
    pub fn localize_partial(&self, pose: &PartialPose2) -> Result<Localization, CamlocError> {
        ROW_BUFFERS.with_borrow_mut(|buffers| {
            let RowBuffers {
                descriptor,
                undefined,
                expanded,
                classes,
            } = buffers;
            let d = self.descriptor.len();
            descriptor.resize(d, 0.0);
            undefined.resize(d, false);
            self.descriptor
                .extract_partial_into(pose, descriptor, undefined)
                .map_err(|source| CamlocError::Feature {
                    context: "input pose".into(),
                    source,
                })?;
            impute_rows(descriptor, undefined, &self.imputation);
            let x: &[f64] = match &self.expansion {
                Some(e) => {
                    expanded.resize(e.n_outputs(), 0.0);
                    e.expand_into(descriptor, expanded)?;
                    expanded
                }
                None => descriptor,
            };
            classes.resize(self.model.n_classes(), 0.0);
            let mut probabilities = vec![0.0; self.cameras.len()];
            self.camera_probabilities_into(x, classes, &mut probabilities)?;
            self.localization_from(x, probabilities, pose.missing().collect())
        })
    }

    /// Localizes many poses in parallel; one result per pose, in order.
    pub fn localize_batch(&self, poses: &[PartialPose2]) -> Vec<Result<Localization, CamlocError>> {
        poses.par_iter().map(|p| self.localize_partial(p)).collect()
    }

    fn localization_from(
        &self,
        x: &[f64],
        probabilities: Vec<f64>,
        missing: Vec<Landmark>,
    ) -> Result<Localization, CamlocError> {
        let (best, probability) = most_probable(&probabilities);
        let (mut azimuth_deg, mut elevation_deg, mut uncertainty_deg) = (None, None, None);
        if let Some(heads) = &self.viewpoint {
            let u = heads.predict(best, x)?;
            azimuth_deg = Some(u[1].atan2(u[0]).to_degrees().rem_euclid(360.0));
            elevation_deg = Some(u[2].clamp(-1.0, 1.0).asin().to_degrees());
            uncertainty_deg = Some(heads.uncertainty_deg(probability));
        }
        let label = CameraLabel::from_index(best)?;
        let view = self.cameras.get(label.get());
        let folded = self.cameras.fold_back_to_front(label.get());
        Ok(Localization {
            label,
            level: view.map_or(Level::Middle, |v| v.level),
            side: view.map_or(Side::Front, |v| v.side),
            rotation: view.map_or_else(Matrix3::identity, |v| v.rotation),
            probability,
            probabilities,
            folded_label: CameraLabel::new(folded).unwrap_or(label),
            missing,
            azimuth_deg,
            elevation_deg,
            uncertainty_deg,
        })
    }

    /// The default model embedded in this build (trained by `cargo xtask train-default` on
    /// the CMU data under the `jittered` protocol, with landmark dropout).
    ///
    /// # Errors
    /// [`CamlocError::NoDefault`] when the build embedded none; decoding errors otherwise.
    pub fn default_model() -> Result<CameraLocalizer, CamlocError> {
        let bytes = include_bytes!(concat!(env!("OUT_DIR"), "/default-model.bin"));
        if bytes.is_empty() {
            return Err(CamlocError::NoDefault("model"));
        }
        Self::from_bytes_named(bytes, "embedded default model").map_err(CamlocError::from)
    }
}

/// The localizer's invariants, run after every decode of a model file: a valid descriptor
/// and camera set, the classifier's own [`LogisticModel::validate`] (shapes against its class
/// count and feature count, finite numbers, positive scales), and descriptor, classifier,
/// imputation and cameras agreeing in size.
impl Validate for CameraLocalizer {
    type Invalid = CamlocError;

    fn validate(&self) -> Result<(), CamlocError> {
        let inconsistent = |detail: String| CamlocError::Inconsistent {
            what: "model",
            detail,
        };
        self.descriptor
            .validate()
            .map_err(|e| inconsistent(e.to_string()))?;
        self.cameras
            .validate()
            .map_err(|e| inconsistent(format!("camera set: {e}")))?;
        self.model.validate()?;
        let d = self.descriptor.len();
        if let Some(e) = &self.expansion {
            e.validate()
                .map_err(|e| inconsistent(format!("feature expansion: {e}")))?;
            if e.n_inputs() != d {
                return Err(inconsistent(format!(
                    "descriptor '{}' has {d} values, the feature expansion expects {}",
                    self.descriptor.name(),
                    e.n_inputs()
                )));
            }
        }
        let width = self.feature_width();
        if self.model.n_features() != width || self.imputation.len() != d {
            return Err(inconsistent(format!(
                "descriptor '{}' has {d} values ({width} features), classifier expects {} and imputation has {}",
                self.descriptor.name(),
                self.model.n_features(),
                self.imputation.len()
            )));
        }
        if !(1..=PostureGroup::ALL.len()).contains(&self.posture_groups)
            || self.model.n_classes() != self.cameras.len() * self.posture_groups
        {
            return Err(inconsistent(format!(
                "classifier has {} classes for {} cameras in {} posture groups",
                self.model.n_classes(),
                self.cameras.len(),
                self.posture_groups
            )));
        }
        if !self.imputation.iter().all(|v| v.is_finite()) {
            return Err(inconsistent("non-finite imputation value".into()));
        }
        if let Some(heads) = &self.viewpoint {
            heads
                .validate(self.cameras.len(), width)
                .map_err(|e| inconsistent(format!("viewpoint heads: {e}")))?;
        }
        Ok(())
    }
}

/// Model files: [`camloc_store::MODEL_KIND`] (magic `CAMLOCMD`); load with
/// [`Persist::load`], write with [`Persist::save`] (no overwrite unless asked).
impl Persist for CameraLocalizer {
    const KIND: FileKind = camloc_store::MODEL_KIND;
}

/// The most probable class and its probability (the first on ties).
pub(crate) fn most_probable(probabilities: &[f64]) -> (usize, f64) {
    probabilities
        .iter()
        .copied()
        .enumerate()
        .fold(
            (0, f64::NEG_INFINITY),
            |a, (i, p)| if p > a.1 { (i, p) } else { a },
        )
}

/// The (possibly partial) 2D pose of a dataset sample.
pub(crate) fn sample_pose(sample: &camloc_dataset::Sample) -> PartialPose2 {
    let mut pose = PartialPose2::from(sample.landmarks);
    for (i, p) in pose.points.iter_mut().enumerate() {
        if sample.missing_mask & (1 << i) != 0 {
            *p = None;
        }
    }
    pose
}

/// Descriptors of `poses` (row-major) and the flags of undefined values, in parallel.
pub(crate) fn extract_rows(
    descriptor: &Descriptor,
    poses: &[PartialPose2],
) -> Result<(Vec<f64>, Vec<bool>), CamlocError> {
    let d = descriptor.len();
    let mut x = vec![0.0; poses.len() * d];
    let mut undefined = vec![false; poses.len() * d];
    x.par_chunks_mut(d)
        .zip(undefined.par_chunks_mut(d))
        .zip(poses.par_iter())
        .enumerate()
        .try_for_each(|(i, ((row, flags), pose))| {
            descriptor
                .extract_partial_into(pose, row, flags)
                .map_err(|source| CamlocError::Feature {
                    context: format!("sample {i}"),
                    source,
                })
        })?;
    Ok((x, undefined))
}

/// Column means over defined values (0 where a column is never defined).
pub(crate) fn column_means(x: &[f64], undefined: &[bool], d: usize) -> Vec<f64> {
    let mut sums = vec![0.0; d];
    let mut counts = vec![0usize; d];
    for (row, flags) in x.chunks_exact(d).zip(undefined.chunks_exact(d)) {
        for j in 0..d {
            if !flags[j] {
                sums[j] += row[j];
                counts[j] += 1;
            }
        }
    }
    sums.iter()
        .zip(&counts)
        .map(|(s, &n)| if n > 0 { s / n as f64 } else { 0.0 })
        .collect()
}

/// The feature rows of one pose that [`CameraLocalizer::localize_partial`] fills: kept per
/// thread and reused, so that localizing a pose allocates only its result. Every call sizes
/// and overwrites them.
#[derive(Default)]
struct RowBuffers {
    /// The descriptor, then imputed.
    descriptor: Vec<f64>,
    /// Which descriptor values depend on a missing landmark.
    undefined: Vec<bool>,
    /// The expanded row, for a model with an expansion.
    expanded: Vec<f64>,
    /// The classifier's class probabilities, before they are summed over postures.
    classes: Vec<f64>,
}

thread_local! {
    static ROW_BUFFERS: std::cell::RefCell<RowBuffers> = std::cell::RefCell::default();
}

/// Replaces undefined values by the imputation values (rows of `imputation.len()`).
pub(crate) fn impute_rows(x: &mut [f64], undefined: &[bool], imputation: &[f64]) {
    let d = imputation.len().max(1);
    for (row, flags) in x.chunks_exact_mut(d).zip(undefined.chunks_exact(d)) {
        for ((v, &u), m) in row.iter_mut().zip(flags).zip(imputation) {
            if u {
                *v = *m;
            }
        }
    }
}

/// Augmented copies of the training poses with random non-torso landmarks dropped.
fn augment(
    descriptor: &Descriptor,
    poses: &[PartialPose2],
    labels: &[usize],
    dropout: &LandmarkDropout,
    imputation: &[f64],
) -> Result<(Vec<f64>, Vec<usize>), CamlocError> {
    dropout.validate()?;
    let mut rng = ChaCha8Rng::seed_from_u64(dropout.seed);
    let droppable: Vec<usize> = (0..NUM_LANDMARKS)
        .filter(|&i| i != Landmark::Pelvis.index() && i != Landmark::Neck.index())
        .collect();
    let whole = dropout.copies.floor() as usize;
    let mut chosen: Vec<usize> = (0..whole).flat_map(|_| 0..poses.len()).collect();
    let part = dropout.copies - whole as f64;
    chosen.extend((0..poses.len()).filter(|_| rng.random_bool(part.clamp(0.0, 1.0))));
    let dropped: Vec<PartialPose2> = chosen
        .iter()
        .map(|&i| {
            let mut pose = poses[i];
            let mut candidates = droppable.clone();
            for _ in 0..rng.random_range(1..=dropout.max_missing) {
                let k = rng.random_range(0..candidates.len());
                pose.points[candidates.swap_remove(k)] = None;
            }
            pose
        })
        .collect();
    let (mut x, undefined) = extract_rows(descriptor, &dropped)?;
    impute_rows(&mut x, &undefined, imputation);
    Ok((x, chosen.iter().map(|&i| labels[i]).collect()))
}
