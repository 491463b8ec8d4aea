//! Training recipes: which views of the motion capture the localizer is trained on and with
//! which options. The default model's recipe ([`DEFAULT_RECIPE`]) is one of them, so that
//! `train-default`, `postures`, `report` and `compare-sklearn` train it the same way.

use camloc::dataset::{
    Augmentation, Dataset, GenerateConfig, PoseSequence, PostureGroup, Protocol,
};
use camloc::geometry::Level;
use camloc::learning::{DirectionSolver, FitReport, IterationLog};
use camloc::{CameraLocalizer, Capacity, DepthLifter, TrainOptions};

use crate::mocap_data::project;

/// Seed of the default model's dataset (jitter, noise) and dropout.
pub const DEFAULT_SEED: u64 = 1;
/// Seed of the `sphere` views the default model's viewpoint heads are fitted on (another
/// draw than the classifier's training views).
pub const VIEWPOINT_SEED: u64 = 4;
/// Seeds of the `rig` views added to the classifier's and to the heads' training views.
const RIG_SEEDS: [u64; 2] = [6, 7];
/// Frame selection by pose of the default model's dataset, millimetres of maximum per-joint
/// distance (issue 11: measured by `cargo xtask generalise`).
pub const DEFAULT_MIN_POSE_DISTANCE_MM: f64 = 100.0;
/// Camera roll of the default model's training views, degrees (photos are seldom level).
pub const DEFAULT_ROLL_DEG: f64 = 15.0;
/// The default model's recipe (issue 21: chosen by `cargo xtask postures`, docs/RESULTS.md).
pub const DEFAULT_RECIPE: &str = "posture=0.1+rig+balance=0.5+quadratic+photo=1";

/// The augmentation of the depth lifter's views: `training` with bone lengths scaled by up
/// to 20%, hip widths 0.45-1.6 and head reach 0.5-1.7, because the lifted depths follow the
/// proportions the lifter has seen and recorded skeletons differ from camloc's template by
/// more than the classifier's augmentation covers (issue 23's labs: hip half-width 0.46 and
/// 0.83, neck-to-head 0.57 and 1.64, torso 1.30 times the template's); the pelvis and the
/// neck at the hip and shoulder midpoints in every view (`midpoints`, the lifter of that
/// placement) or in none (the lifter of skeletons' own placement): one lifter of both had
/// CMU torsos 30% too deep at 45 deg of elevation (`DepthLifter::with_midpoint_lifter`).
pub fn lifter_augmentation(training: Augmentation, midpoints: bool) -> Augmentation {
    Augmentation {
        bone_scale: 0.2,
        hip_width: (0.45, 1.6),
        head_reach: (0.5, 1.7),
        photo_landmarks: if midpoints { 1.0 } else { 0.0 },
        ..training
    }
}

/// The training options of the default model: [`TrainOptions::default`] with the dropout
/// seeded, and no viewpoint heads fitted on the training views (a recipe fits them on its
/// own views).
pub fn default_options() -> TrainOptions {
    let mut options = TrainOptions {
        viewpoint_lambda: None,
        ..TrainOptions::default()
    };
    if let Some(d) = options.dropout.as_mut() {
        d.seed = DEFAULT_SEED;
    }
    options
}

/// Training views of `protocol`: Table-1 cameras, every frame, selection by pose at
/// `min_pose_distance_mm`, the augmentation `augmentation`, camera roll up to
/// [`DEFAULT_ROLL_DEG`], the given seed.
pub fn training_views(
    protocol: Protocol,
    seed: u64,
    augmentation: Augmentation,
    min_pose_distance_mm: f64,
) -> GenerateConfig {
    let mut config = GenerateConfig::new(protocol);
    config.seed = seed;
    config.stride = 1;
    config.min_pose_distance_mm = min_pose_distance_mm;
    config.augmentation = augmentation;
    config.jitter.roll_deg = DEFAULT_ROLL_DEG;
    config
}

/// A way of training the localizer, written as `+`-joined parts: `jittered` (`jittered`
/// views with the training augmentation, viewpoint heads on `sphere` views: the default
/// model's recipe before issue 21), `posture[=P]` (put a share `P` of the samples in a
/// posture, 0.25 by default), `rig[=S]` (add `rig` views of every `S`-th frame, 2 by default,
/// to the classifier's and the heads' views), `balance=B` (the camera priors' balance, 1 by
/// default), `quadratic[-K]` (the classifier's capacity), `heads=quadratic-K` (the heads' own
/// capacity), `classes` ((posture, camera) classes), `precond=N` (truncated Newton-CG
/// preconditioned on `N` samples), `products=N` (its Hessian-vector products on at least `N`
/// samples; after `quadratic`, which sets both), `lambda=L` (the classifier's ridge weight),
/// `tol=T` (its per-sample gradient tolerance), `bones=B` (the bone-length scaling bound of
/// the augmentation, 0.1 by default), `hips=LO-HI` and `head=LO-HI` (its hip width and
/// head reach ranges, 0.8-1.6 both by default), `photo=P` (its share of photo placements,
/// 0.5 by default), `no-low-below` (views of seated, squatting and kneeling bodies,
/// `PostureGroup::Low`, from the lower ring's cameras left out: a camera 22.5 deg or more
/// below a low pelvis a few metres away stands under the floor).
#[derive(Clone, Debug, PartialEq)]
pub struct Recipe {
    /// The text it was parsed from, its name in tables.
    pub name: String,
    /// The augmentation of the training views ([`Augmentation::TRAINING`] with the parts'
    /// changes).
    augmentation: Augmentation,
    /// The frame stride of the added `rig` views (`None`: none).
    rig_stride: Option<usize>,
    /// Whether views of low bodies from a camera of the lower ring are left out of the
    /// training views (`no-low-below`).
    no_low_below: bool,
    /// The training options.
    pub options: TrainOptions,
}

impl std::str::FromStr for Recipe {
    type Err = String;

    fn from_str(text: &str) -> Result<Recipe, String> {
        let mut recipe = Recipe {
            name: text.to_string(),
            augmentation: Augmentation::TRAINING,
            rig_stride: None,
            no_low_below: false,
            options: default_options(),
        };
        let number = |v: &str| {
            v.parse::<f64>()
                .map_err(|_| format!("'{v}' is not a number in recipe '{text}'"))
        };
        let range = |v: &str| {
            let (lo, hi) = v
                .split_once('-')
                .ok_or_else(|| format!("'{v}' is not a range LO-HI in recipe '{text}'"))?;
            Ok::<_, String>((number(lo)?, number(hi)?))
        };
        let augmentation = &mut recipe.augmentation;
        for part in text.split('+') {
            let (key, value) = part
                .split_once('=')
                .map_or((part, None), |(k, v)| (k, Some(v)));
            match (key, value) {
                ("jittered", None) => {}
                ("posture", v) => augmentation.posture = v.map_or(Ok(0.25), number)?,
                ("bones", Some(v)) => augmentation.bone_scale = number(v)?,
                ("hips", Some(v)) => augmentation.hip_width = range(v)?,
                ("head", Some(v)) => augmentation.head_reach = range(v)?,
                ("photo", Some(v)) => augmentation.photo_landmarks = number(v)?,
                ("rig", v) => {
                    let stride = v.map_or(Ok(2.0), number)?;
                    if !(stride >= 1.0 && stride.fract() == 0.0) {
                        return Err(format!("rig stride {stride} is not a whole number >= 1"));
                    }
                    recipe.rig_stride = Some(stride as usize);
                }
                ("balance", Some(v)) => recipe.options.camera_balance = number(v)?,
                ("lambda", Some(v)) => recipe.options.regression.lambda = number(v)?,
                ("tol", Some(v)) => recipe.options.regression.gradient_tolerance = number(v)?,
                ("classes", None) => recipe.options.posture_classes = true,
                ("no-low-below", None) => recipe.no_low_below = true,
                ("heads", Some(v)) => recipe.options.viewpoint_capacity = v.parse()?,
                ("quadratic", None) => {
                    recipe.options = recipe.options.clone().with_capacity(Capacity::Quadratic {
                        components: camloc::DEFAULT_QUADRATIC_COMPONENTS,
                    })
                }
                (k, None) if k.starts_with("quadratic-") => {
                    recipe.options = recipe.options.clone().with_capacity(k.parse()?)
                }
                ("precond", Some(v)) => {
                    let product_rows = recipe
                        .options
                        .regression
                        .direction_solver
                        .product_rows(usize::MAX);
                    recipe.options.regression.direction_solver = DirectionSolver::TruncatedCg {
                        preconditioner_rows: number(v)? as usize,
                        product_rows,
                    }
                }
                ("products", Some(v)) => {
                    let preconditioner_rows = match recipe.options.regression.direction_solver {
                        DirectionSolver::TruncatedCg {
                            preconditioner_rows,
                            ..
                        } => preconditioner_rows,
                        _ => camloc::DEFAULT_PRECONDITIONER_ROWS,
                    };
                    recipe.options.regression.direction_solver = DirectionSolver::TruncatedCg {
                        preconditioner_rows,
                        product_rows: number(v)? as usize,
                    }
                }
                _ => return Err(format!("unknown part '{part}' in recipe '{text}'")),
            }
        }
        recipe.options.validate().map_err(|e| e.to_string())?;
        GenerateConfig {
            augmentation: recipe.augmentation,
            ..GenerateConfig::new(Protocol::Jittered)
        }
        .validate()
        .map_err(|e| format!("recipe '{text}': {e}"))?;
        Ok(recipe)
    }
}

/// A localizer a [`Recipe`] trained, with what its fit reported.
pub struct Trained {
    /// The localizer, viewpoint heads fitted.
    pub localizer: CameraLocalizer,
    /// The depth lifter, fitted on the viewpoint heads' views.
    pub lifter: DepthLifter,
    /// The classifier's fit.
    pub report: FitReport,
    /// Views the classifier was trained on.
    pub training_views: usize,
    /// Views the viewpoint heads were fitted on.
    pub head_views: usize,
    /// Seconds of the classifier's fit alone.
    pub fit_seconds: f64,
}

impl Recipe {
    /// The default model's recipe, [`DEFAULT_RECIPE`].
    pub fn default_model() -> Recipe {
        DEFAULT_RECIPE
            .parse()
            .expect("the default recipe parses (checked by a test)")
    }

    /// The classifier's training views of `sequences`: `jittered` views with
    /// [`DEFAULT_SEED`], and the recipe's `rig` views appended.
    pub fn classifier_views(
        &self,
        sequences: &[PoseSequence],
        min_pose_distance_mm: f64,
    ) -> Result<Dataset, String> {
        self.views(
            sequences,
            Protocol::Jittered,
            DEFAULT_SEED,
            RIG_SEEDS[0],
            min_pose_distance_mm,
        )
    }

    /// The viewpoint heads' views of `sequences`: `sphere` views with [`VIEWPOINT_SEED`], and
    /// the recipe's `rig` views appended.
    fn head_views(
        &self,
        sequences: &[PoseSequence],
        min_pose_distance_mm: f64,
    ) -> Result<Dataset, String> {
        self.views(
            sequences,
            Protocol::Sphere,
            VIEWPOINT_SEED,
            RIG_SEEDS[1],
            min_pose_distance_mm,
        )
    }

    /// `protocol` views with `seed`, and with `rig_seed` the recipe's `rig` views appended.
    fn views(
        &self,
        sequences: &[PoseSequence],
        protocol: Protocol,
        seed: u64,
        rig_seed: u64,
        min_pose_distance_mm: f64,
    ) -> Result<Dataset, String> {
        let config = training_views(protocol, seed, self.augmentation, min_pose_distance_mm);
        let mut views = project(sequences, &config)?;
        if let Some(stride) = self.rig_stride {
            let mut rig = training_views(
                Protocol::Rig,
                rig_seed,
                self.augmentation,
                min_pose_distance_mm,
            );
            rig.stride = stride;
            let rig = project(sequences, &rig)?;
            if views.header.clips != rig.header.clips || views.header.cameras != rig.header.cameras
            {
                return Err("the rig views are of other clips or cameras".into());
            }
            views.samples.extend(rig.samples);
        }
        if self.no_low_below {
            let cameras = views.header.cameras.clone();
            views.samples.retain(|s| {
                let below = cameras
                    .get(s.label)
                    .is_some_and(|v| v.level == Level::Lower);
                !(below && PostureGroup::of(&s.pose3) == PostureGroup::Low)
            });
        }
        Ok(views)
    }

    /// Trains the localizer on `sequences` with this recipe: the classifier on
    /// [`Recipe::classifier_views`], then the viewpoint heads on `sphere` views
    /// ([`VIEWPOINT_SEED`]) and the recipe's `rig` views, at the heads' capacity; and the
    /// depth lifters of both landmark placements on the same views of wider people
    /// ([`lifter_augmentation`]; the default
    /// quadratic components and [`camloc::DEFAULT_LIFTER_LAMBDA`]). `log` sees every Newton
    /// iteration.
    pub fn train(
        &self,
        sequences: &[PoseSequence],
        min_pose_distance_mm: f64,
        log: impl FnMut(&IterationLog),
    ) -> Result<Trained, String> {
        let training = self.classifier_views(sequences, min_pose_distance_mm)?;
        let start = std::time::Instant::now();
        let (mut localizer, report) =
            CameraLocalizer::train(&training, &self.options, log).map_err(|e| e.to_string())?;
        let fit_seconds = start.elapsed().as_secs_f64();
        let heads = self.head_views(sequences, min_pose_distance_mm)?;
        localizer
            .fit_viewpoint_with_capacity(
                &heads,
                camloc::DEFAULT_VIEWPOINT_LAMBDA,
                self.options.viewpoint_capacity,
            )
            .map_err(|e| e.to_string())?;
        let head_views = heads.samples.len();
        drop(heads);
        // The same views of wider people for the lifters of both placements.
        let lifter = |midpoints: bool| {
            let recipe = Recipe {
                augmentation: lifter_augmentation(self.augmentation, midpoints),
                ..self.clone()
            };
            let views = recipe.head_views(sequences, min_pose_distance_mm)?;
            DepthLifter::fit(
                &views,
                *localizer.descriptor(),
                camloc::DEFAULT_QUADRATIC_COMPONENTS,
                camloc::DEFAULT_LIFTER_LAMBDA,
            )
            .map_err(|e| e.to_string())
        };
        let lifter = lifter(false)?
            .with_midpoint_lifter(lifter(true)?)
            .map_err(|e| e.to_string())?;
        Ok(Trained {
            localizer,
            lifter,
            report,
            training_views: training.samples.len(),
            head_views,
            fit_seconds,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_recipe_parses_and_bad_parts_are_refused() {
        let recipe = Recipe::default_model();
        assert_eq!(recipe.name, DEFAULT_RECIPE);
        for bad in [
            "posture=x",
            "rig=0",
            "rig=1.5",
            "balance=2",
            "sideways",
            "heads=cubic",
            "hips=0.5",
            "head=2-1",
            "bones=0.7",
        ] {
            assert!(bad.parse::<Recipe>().is_err(), "{bad} parsed");
        }
        let r: Recipe = "posture=0.3+rig=3+balance=0.5+heads=quadratic-10"
            .parse()
            .unwrap();
        assert_eq!((r.augmentation.posture, r.rig_stride), (0.3, Some(3)));
        assert!(!r.no_low_below && !recipe.no_low_below);
        assert!(
            "posture+no-low-below"
                .parse::<Recipe>()
                .unwrap()
                .no_low_below
        );
        assert_eq!(r.options.camera_balance, 0.5);
        assert_eq!(
            r.options.viewpoint_capacity,
            Capacity::Quadratic { components: 10 }
        );
        let r: Recipe = "bones=0.2+hips=0.5-1.6+head=0.5-1.7+photo=0.7"
            .parse()
            .unwrap();
        assert_eq!(r.augmentation.bone_scale, 0.2);
        assert_eq!(r.augmentation.hip_width, (0.5, 1.6));
        assert_eq!(r.augmentation.head_reach, (0.5, 1.7));
        assert_eq!(r.augmentation.photo_landmarks, 0.7);
    }
}
