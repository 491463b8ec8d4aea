//! `cargo xtask generalise`: how the localizer holds on motions and subjects it was not
//! trained on (issue 11): accuracy per motion category on held-out subjects,
//! leave-one-category-out, the `sphere` protocol, the continuous viewpoint, and each
//! descriptor with a linear and a quadratic classifier. Prints markdown tables; writes nothing.

use std::collections::BTreeMap;
use std::fmt::Write;
use std::path::PathBuf;
use std::time::Instant;

use camloc::PartialPose2;
use camloc::dataset::{
    Augmentation, Dataset, GenerateConfig, MotionCategory, PoseSequence, Protocol,
    camera_direction_deg, direction_vector,
};
use camloc::learning::{LogisticRegression, angle_deg};
use camloc::{CameraLocalizer, Capacity, Descriptor, TrainOptions, cross_validate, evaluate};

use crate::mocap_data::{load_split, project};
use crate::progress::newton_line;

/// Held-out subjects of `generalise` (old and new ones), comma-separated.
pub const TEST_SUBJECTS: &str = "06,09,16,17,35,47,113,127,141";

/// Arguments of `generalise`.
#[derive(clap::Args)]
pub struct Args {
    /// Motion capture folders [default: ../shared/data/cmu].
    #[arg(long = "mocap", value_name = "DIR")]
    pub mocap: Vec<PathBuf>,
    /// Frame selection by pose, millimetres of maximum per-joint distance (the default
    /// model's).
    #[arg(long, default_value_t = crate::recipe::DEFAULT_MIN_POSE_DISTANCE_MM, value_name = "MM")]
    pub min_pose_distance: f64,
    /// Held-out subjects (never trained on; old and new ones).
    #[arg(long, value_delimiter = ',', default_value = TEST_SUBJECTS)]
    pub test_subjects: Vec<String>,
    /// Descriptors compared (joints, landmarks, paper).
    #[arg(long, value_delimiter = ',', default_value = "joints")]
    pub descriptors: Vec<String>,
    /// Classifier capacities compared with each descriptor: `linear`, or `quadratic-K` (the
    /// descriptor and the products of its K leading whitened principal components).
    #[arg(long, value_delimiter = ',', default_value = "linear,quadratic-30",
          value_parser = str::parse::<Capacity>)]
    pub capacities: Vec<Capacity>,
    /// Ridge weights tried by cross-validation grouped by subject on the training subjects.
    #[arg(long, value_delimiter = ',', default_value = "1,10,100")]
    pub lambdas: Vec<f64>,
    /// Folds of that cross-validation (0: no cross-validation, the first lambda).
    #[arg(long, default_value_t = 3)]
    pub folds: usize,
    /// Also run leave-one-category-out (with the first descriptor and capacity).
    #[arg(long)]
    pub loco: bool,
    /// Training augmentation: `none`; `people` (bone lengths and photo landmark
    /// placements); `training` (those, and new poses: hip and shoulder widths, limb
    /// rotations, upper bodies of other poses). Any but `none` also rolls the training
    /// cameras up to 15 deg.
    #[arg(long, value_enum, default_value = "training")]
    pub augmentation: AugmentationChoice,
    /// Add this many copies of landmark dropout in training (0: none; the default model
    /// has 1).
    #[arg(long, default_value_t = 1.0)]
    pub dropout: f64,
    /// Ridge weight of the continuous-viewpoint heads.
    #[arg(long, default_value_t = 1.0)]
    pub head_lambda: f64,
}

fn true_directions(data: &Dataset) -> Vec<[f64; 3]> {
    data.samples
        .iter()
        .map(|s| {
            let (a, e) = camera_direction_deg(&s.rotation);
            direction_vector(a, e)
        })
        .collect()
}

/// Continuous-viewpoint errors of a localizer with viewpoint heads on one test set.
pub struct ViewpointErrors {
    /// Median angular error of the heads' direction, degrees.
    pub median_deg: f64,
    /// Share of poses whose heads' direction is more than 45 deg off, percent.
    pub beyond_45: f64,
    /// Share of poses within the stated uncertainty, percent.
    pub within_uncertainty: f64,
    /// Median angular error of the chosen class's centre, degrees.
    pub centre_median_deg: f64,
    /// Share of poses whose class centre is more than 45 deg off, percent.
    pub centre_beyond_45: f64,
    /// Accuracy of labelling by the camera of the heads' direction (its ring and side), percent.
    pub relabelled: f64,
}

impl std::fmt::Display for ViewpointErrors {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "heads: median {:.1} deg, {:.2}% beyond 45 deg, {:.1}% within the stated uncertainty; class centre: median {:.1} deg, {:.2}% beyond 45 deg; label = camera of the heads' direction: {:.2}% correct",
            self.median_deg,
            self.beyond_45,
            self.within_uncertainty,
            self.centre_median_deg,
            self.centre_beyond_45,
            self.relabelled
        )
    }
}

/// Median error, share beyond 45 deg, share within the stated uncertainty, of the
/// localizer's continuous viewpoint and of the chosen class centre, on `data`.
pub fn viewpoint_errors(
    localizer: &CameraLocalizer,
    data: &Dataset,
) -> Result<ViewpointErrors, String> {
    let truth = true_directions(data);
    let poses: Vec<PartialPose2> = data
        .samples
        .iter()
        .map(|s| PartialPose2::from(s.landmarks))
        .collect();
    let mut head_err = Vec::new();
    let mut centre_err = Vec::new();
    let mut covered = 0usize;
    let mut relabelled = 0usize;
    for ((result, t), s) in localizer
        .localize_batch(&poses)
        .into_iter()
        .zip(&truth)
        .zip(&data.samples)
    {
        let l = result.map_err(|e| e.to_string())?;
        let (Some(az), Some(el), Some(radius)) =
            (l.azimuth_deg, l.elevation_deg, l.uncertainty_deg)
        else {
            return Err("the localizer has no viewpoint heads".into());
        };
        let u = direction_vector(az, el);
        relabelled += usize::from(localizer.cameras().by_ring_and_side(az, el).label == s.label);
        let e = angle_deg(&u, t);
        covered += usize::from(e <= radius);
        head_err.push(e);
        let v = &localizer.cameras().viewpoints()[l.label.index()];
        centre_err.push(angle_deg(
            &direction_vector(v.azimuth_deg, v.elevation_deg),
            t,
        ));
    }
    let stats = |e: &mut Vec<f64>| {
        let median = camloc::reconstruct::median(e).unwrap_or(f64::NAN);
        let beyond = e.iter().filter(|&&v| v > 45.0).count() as f64 / e.len() as f64;
        (median, 100.0 * beyond)
    };
    let (median_deg, beyond_45) = stats(&mut head_err);
    let (centre_median_deg, centre_beyond_45) = stats(&mut centre_err);
    Ok(ViewpointErrors {
        median_deg,
        beyond_45,
        within_uncertainty: 100.0 * covered as f64 / head_err.len() as f64,
        centre_median_deg,
        centre_beyond_45,
        relabelled: 100.0 * relabelled as f64 / head_err.len() as f64,
    })
}

/// The training augmentations `generalise` compares.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum AugmentationChoice {
    /// No augmentation, training cameras rolled as the test ones.
    None,
    /// [`Augmentation::PEOPLE`].
    People,
    /// [`Augmentation::TRAINING`].
    Training,
}

impl AugmentationChoice {
    /// The dataset augmentation, `None` for [`AugmentationChoice::None`].
    pub fn augmentation(self) -> Option<Augmentation> {
        match self {
            AugmentationChoice::None => None,
            AugmentationChoice::People => Some(Augmentation::PEOPLE),
            AugmentationChoice::Training => Some(Augmentation::TRAINING),
        }
    }
}

/// Dataset settings: `protocol`, `seed`, the selection by pose of `args`, and `augmentation`
/// (with camera roll up to 15 deg) if given.
fn config(
    protocol: Protocol,
    seed: u64,
    args: &Args,
    augmentation: Option<Augmentation>,
) -> GenerateConfig {
    let mut c = GenerateConfig::new(protocol);
    c.seed = seed;
    c.min_pose_distance_mm = args.min_pose_distance;
    if let Some(a) = augmentation {
        c.augmentation = a;
        c.jitter.roll_deg = 15.0;
    }
    c
}

fn accuracy_by_category(
    localizer: &CameraLocalizer,
    test: &Dataset,
) -> Result<Vec<(MotionCategory, usize, f64)>, String> {
    let mut out = Vec::new();
    for (category, n) in test.samples_per_category() {
        let (_, part) = test.split_by_category(category);
        let e = evaluate(localizer, &part).map_err(|e| e.to_string())?;
        out.push((category, n, e.accuracy));
    }
    Ok(out)
}

fn train(train: &Dataset, options: &TrainOptions) -> Result<(CameraLocalizer, f64, usize), String> {
    let start = Instant::now();
    let (localizer, report) = CameraLocalizer::train(train, options, |log| {
        eprintln!("{}", newton_line(log, start.elapsed().as_secs_f64()))
    })
    .map_err(|e| e.to_string())?;
    Ok((
        localizer,
        start.elapsed().as_secs_f64(),
        report.newton_iterations(),
    ))
}

/// Runs `generalise`: prints [`measure`]'s tables.
pub fn run(args: &Args) -> Result<(), String> {
    print!("{}", measure(args)?.markdown);
    Ok(())
}

/// What one descriptor achieved in [`measure`].
pub struct Outcome {
    /// Accuracy on the jittered views of the held-out subjects (fraction).
    pub jittered: f64,
    /// Per motion category: test samples and accuracy (fraction) on the same views.
    pub categories: Vec<(MotionCategory, usize, f64)>,
    /// Accuracy on the sphere views inside the class boxes (fraction).
    pub sphere_inside: f64,
    /// Continuous-viewpoint errors on the jittered views.
    pub viewpoint_jittered: ViewpointErrors,
    /// Continuous-viewpoint errors on the sphere views.
    pub viewpoint_sphere: ViewpointErrors,
}

/// Everything [`measure`] printed, and its key numbers.
pub struct Measured {
    /// The markdown tables.
    pub markdown: String,
    /// One per descriptor, in order.
    pub outcomes: Vec<Outcome>,
    /// Leave-one-category-out accuracy (sample-weighted, fraction) per descriptor; empty
    /// without `--loco`.
    pub loco: Vec<f64>,
}

/// Measures everything `generalise` reports.
pub fn measure(args: &Args) -> Result<Measured, String> {
    let mut outcomes = Vec::new();
    let mut loco = Vec::new();
    let started = Instant::now();
    let mut md = String::new();
    let (train_seqs, test_seqs) = load_split(&args.mocap, &args.test_subjects)?;
    let train_set = project(
        &train_seqs,
        &config(
            Protocol::Jittered,
            1,
            args,
            args.augmentation.augmentation(),
        ),
    )?;
    let test_set = project(&test_seqs, &config(Protocol::Jittered, 2, args, None))?;
    let sphere_set = project(&test_seqs, &config(Protocol::Sphere, 3, args, None))?;
    let _ = writeln!(
        md,
        "Training: {} samples of subjects {}; test: {} jittered and {} sphere samples of held-out subjects {}; min pose distance {} mm, augmentation {}, dropout copies {}.\n",
        train_set.samples.len(),
        train_set
            .subjects()
            .iter()
            .map(|(s, _)| s.as_str())
            .collect::<Vec<_>>()
            .join(", "),
        test_set.samples.len(),
        sphere_set.samples.len(),
        args.test_subjects.join(", "),
        args.min_pose_distance,
        args.augmentation
            .augmentation()
            .map_or("none".to_string(), |a| format!("{a:?}")),
        args.dropout
    );
    let mut per_cat_train: BTreeMap<MotionCategory, usize> = BTreeMap::new();
    for (c, n) in train_set.samples_per_category() {
        per_cat_train.insert(c, n);
    }
    let _ = writeln!(
        md,
        "| descriptor | capacity | features | lambda (CV) | CV accuracy (linear) | fit time | iterations | jittered | sphere, all | sphere, inside class boxes | per category (jittered) |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|---|---|");
    let mut chosen_options = Vec::new();
    let mut names = Vec::new();
    let models = args
        .descriptors
        .iter()
        .flat_map(|d| args.capacities.iter().map(move |c| (d, *c)));
    for (descriptor_name, capacity) in models {
        let descriptor = Descriptor::from_name(descriptor_name).map_err(|e| e.to_string())?;
        let name = format!("{descriptor_name}, {}", capacity.name());
        let candidates: Vec<LogisticRegression> = args
            .lambdas
            .iter()
            .map(|&l| LogisticRegression::default().with_lambda(l))
            .collect();
        let (regression, cv_accuracy) = if args.folds >= 2 && candidates.len() > 1 {
            let cvs = cross_validate(&train_set, &[descriptor], &candidates, args.folds)
                .map_err(|e| e.to_string())?;
            let best = cvs
                .first()
                .and_then(|c| c.report.best_candidate())
                .ok_or("no CV candidate")?;
            for c in &cvs[0].report.candidates {
                eprintln!(
                    "{name}: lambda {} CV {:.4}",
                    c.config.lambda, c.mean_accuracy
                );
            }
            (best.config.clone(), Some(best.mean_accuracy))
        } else {
            (candidates[0].clone(), None)
        };
        let mut options = TrainOptions {
            descriptor,
            regression: regression.clone(),
            dropout: (args.dropout > 0.0).then(|| camloc::LandmarkDropout {
                copies: args.dropout,
                ..Default::default()
            }),
            mirror: true,
            viewpoint_lambda: None,
            ..TrainOptions::default()
        }
        .with_capacity(capacity);
        // The lambdas are cross-validated on the linear model; a quadratic one keeps its own.
        if capacity == Capacity::Linear {
            options.regression = regression;
        }
        let (localizer, seconds, iterations) = train(&train_set, &options)?;
        let jit = evaluate(&localizer, &test_set).map_err(|e| e.to_string())?;
        let sph = evaluate(&localizer, &sphere_set).map_err(|e| e.to_string())?;
        let inside = Dataset {
            header: sphere_set.header.clone(),
            samples: sphere_set
                .samples
                .iter()
                .filter(|s| s.in_class_box)
                .cloned()
                .collect(),
        };
        let ins = evaluate(&localizer, &inside).map_err(|e| e.to_string())?;
        let categories = accuracy_by_category(&localizer, &test_set)?;
        let cats = categories
            .iter()
            .map(|(c, n, a)| format!("{} {:.2}% ({n})", c.name(), 100.0 * a))
            .collect::<Vec<_>>()
            .join("; ");
        let _ = writeln!(
            md,
            "| {descriptor_name} | {} | {} | {} | {} | {seconds:.1} s | {iterations} | {:.2}% | {:.2}% | {:.2}% ({} samples) | {cats} |",
            capacity.name(),
            localizer.model().n_features(),
            options.regression.lambda,
            cv_accuracy.map_or("-".into(), |a| format!("{:.2}%", 100.0 * a)),
            100.0 * jit.accuracy,
            100.0 * sph.accuracy,
            100.0 * ins.accuracy,
            inside.samples.len()
        );
        let _ = writeln!(
            md,
            "\n{name}, jittered test: folded (back -> front) {:.2}%; per level, exact camera / right level: {}",
            100.0 * jit.accuracy_folded,
            jit.per_level
                .iter()
                .map(|l| format!(
                    "{} {:.2}% / {:.2}%",
                    l.level.name(),
                    100.0 * l.accuracy,
                    100.0 * l.level_accuracy
                ))
                .collect::<Vec<_>>()
                .join(", ")
        );
        // Continuous viewpoint: heads fitted on sphere-protocol views of the training
        // subjects (directions everywhere in the band), calibrated on jittered training views.
        let sphere_train = project(
            &train_seqs,
            &config(Protocol::Sphere, 4, args, args.augmentation.augmentation()),
        )?;
        let mut localizer = localizer;
        let (jittered, sphere_inside) = (jit.accuracy, ins.accuracy);
        localizer
            .fit_viewpoint(&sphere_train, args.head_lambda)
            .map_err(|e| e.to_string())?;
        let viewpoint_jittered = viewpoint_errors(&localizer, &test_set)?;
        let viewpoint_sphere = viewpoint_errors(&localizer, &sphere_set)?;
        let _ = writeln!(
            md,
            "\n{name}, continuous viewpoint (heads lambda {}): jittered test: {}; sphere test: {}\n",
            args.head_lambda, viewpoint_jittered, viewpoint_sphere
        );
        outcomes.push(Outcome {
            jittered,
            categories,
            sphere_inside,
            viewpoint_jittered,
            viewpoint_sphere,
        });
        chosen_options.push(options);
        names.push(name);
    }
    if args.loco {
        let _ = writeln!(
            md,
            "\nLeave-one-category-out (all subjects; train without the category, test on it, jittered):\n"
        );
        let all_seqs: Vec<PoseSequence> = train_seqs.iter().chain(&test_seqs).cloned().collect();
        let all_train = project(
            &all_seqs,
            &config(
                Protocol::Jittered,
                1,
                args,
                args.augmentation.augmentation(),
            ),
        )?;
        let all_test = project(&all_seqs, &config(Protocol::Jittered, 2, args, None))?;
        chosen_options.truncate(1);
        let _ = writeln!(
            md,
            "| category | test samples | {} |",
            names.first().map_or("", String::as_str)
        );
        let _ = writeln!(md, "|---|---|---|");
        let mut means = vec![0.0; chosen_options.len()];
        let mut count = 0usize;
        for (category, _) in all_test.samples_per_category() {
            let (train_part, _) = all_train.split_by_category(category);
            let (_, test_part) = all_test.split_by_category(category);
            let mut cells = Vec::new();
            for (k, options) in chosen_options.iter().enumerate() {
                let (localizer, _, _) = train(&train_part, options)?;
                let e = evaluate(&localizer, &test_part).map_err(|e| e.to_string())?;
                means[k] += e.accuracy * test_part.samples.len() as f64;
                cells.push(format!("{:.2}%", 100.0 * e.accuracy));
            }
            count += test_part.samples.len();
            let _ = writeln!(
                md,
                "| {} | {} | {} |",
                category.name(),
                test_part.samples.len(),
                cells.join(" | ")
            );
        }
        let _ = writeln!(
            md,
            "| all (sample-weighted) | {count} | {} |",
            means
                .iter()
                .map(|m| format!("{:.2}%", 100.0 * m / count.max(1) as f64))
                .collect::<Vec<_>>()
                .join(" | ")
        );
        loco = means.iter().map(|m| m / count.max(1) as f64).collect();
    }
    let _ = writeln!(md, "\nTotal {:.0} s.", started.elapsed().as_secs_f64());
    Ok(Measured {
        markdown: md,
        outcomes,
        loco,
    })
}
