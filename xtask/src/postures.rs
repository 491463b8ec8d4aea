//! `cargo xtask postures`: how the localizer holds on seated and low postures and on cameras
//! that stand like real ones (issue 21). Compares training recipes on
//! * the held-out subjects under `jittered`, `sphere` (inside the class boxes) and `rig`,
//!   per motion category, with the mean signed elevation error;
//! * the posture clips (sit, squat, kneel, crawl) left out by subject, in folds;
//! * the posture clips when no posture clip is trained on at all (leave-posture-out).
//!
//! Prints markdown tables; writes nothing.

use std::fmt::Write;
use std::path::PathBuf;
use std::time::Instant;

use camloc::dataset::{
    Augmentation, Dataset, GenerateConfig, MotionCategory, PoseSequence, Protocol,
};
use camloc::{CameraLocalizer, Capacity, TrainOptions};

use crate::mocap_data::{load_split, project};
use crate::view_scores::{Summary, ViewOutcome, categories_in, outcomes};

/// A way of training the localizer that `postures` compares, written as `+`-joined parts:
/// `jittered` (the default model's recipe before issue 21: `jittered` views with the
/// training augmentation, viewpoint heads on `sphere` views), `posture[=P]` (put a share
/// `P` of the samples in a posture, 0.25 by default), `rig[=S]` (add `rig` views of every
/// `S`-th frame, 2 by default, to the classifier's and the heads' views), `balance=B` (the
/// camera priors' balance, 1 by default), `quadratic[-K]` (the classifier's capacity),
/// `heads=quadratic-K` (the heads' own capacity), `classes` ((posture, camera) classes).
#[derive(Clone, Debug, PartialEq)]
pub struct Recipe {
    /// The text it was parsed from, its name in the tables.
    name: String,
    /// The share of samples put in a posture.
    posture: f64,
    /// The frame stride of the added `rig` views (`None`: none).
    rig_stride: Option<usize>,
    /// The training options.
    options: TrainOptions,
}

impl std::str::FromStr for Recipe {
    type Err = String;

    fn from_str(text: &str) -> Result<Recipe, String> {
        let mut recipe = Recipe {
            name: text.to_string(),
            posture: 0.0,
            rig_stride: None,
            options: TrainOptions {
                viewpoint_lambda: None,
                ..crate::train_default::default_options()
            },
        };
        let number = |v: &str| {
            v.parse::<f64>()
                .map_err(|_| format!("'{v}' is not a number in recipe '{text}'"))
        };
        for part in text.split('+') {
            let (key, value) = part
                .split_once('=')
                .map_or((part, None), |(k, v)| (k, Some(v)));
            match (key, value) {
                ("jittered", None) => {}
                ("posture", v) => recipe.posture = v.map_or(Ok(0.25), number)?,
                ("rig", v) => recipe.rig_stride = Some(v.map_or(Ok(2.0), number)? as usize),
                ("balance", Some(v)) => recipe.options.camera_balance = number(v)?,
                ("classes", None) => recipe.options.posture_classes = true,
                ("heads", Some(v)) => recipe.options.viewpoint_capacity = v.parse()?,
                ("quadratic", None) => {
                    recipe.options = recipe.options.clone().with_capacity(Capacity::Quadratic {
                        components: camloc::DEFAULT_QUADRATIC_COMPONENTS,
                    })
                }
                (k, None) if k.starts_with("quadratic-") => {
                    recipe.options = recipe.options.clone().with_capacity(k.parse()?)
                }
                _ => return Err(format!("unknown part '{part}' in recipe '{text}'")),
            }
        }
        recipe.options.validate().map_err(|e| e.to_string())?;
        Ok(recipe)
    }
}

/// Arguments of `postures`.
#[derive(clap::Args)]
pub struct Args {
    /// Motion capture folders [default: ../shared/data/cmu].
    #[arg(long = "mocap", value_name = "DIR")]
    pub mocap: Vec<PathBuf>,
    /// Held-out subjects of the protocol comparison.
    #[arg(long, value_delimiter = ',', default_value = crate::generalise::TEST_SUBJECTS)]
    pub test_subjects: Vec<String>,
    /// Recipes compared (see `Recipe`: `+`-joined parts such as
    /// `posture+rig+heads=quadratic-30`).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "jittered,posture,posture+rig"
    )]
    pub recipes: Vec<Recipe>,
    /// Folds of the leave-subject-out over the subjects with posture clips (0: skip it).
    #[arg(long, default_value_t = 3)]
    pub folds: usize,
    /// Skip the leave-posture-out part.
    #[arg(long)]
    pub no_leave_posture_out: bool,
    /// Frame selection by pose, millimetres (the default model's).
    #[arg(long, default_value_t = crate::train_default::DEFAULT_MIN_POSE_DISTANCE_MM, value_name = "MM")]
    pub min_pose_distance: f64,
}

/// Dataset settings: `protocol`, `seed`, selection by pose, and with `augment` the training
/// augmentation with `posture` and camera roll up to 15 deg (as the default model's).
fn views(protocol: Protocol, seed: u64, args: &Args, augment: Option<f64>) -> GenerateConfig {
    let mut c = GenerateConfig::new(protocol);
    c.seed = seed;
    c.min_pose_distance_mm = args.min_pose_distance;
    if let Some(posture) = augment {
        c.augmentation = Augmentation {
            posture,
            ..Augmentation::TRAINING
        };
        c.jitter.roll_deg = crate::train_default::DEFAULT_ROLL_DEG;
    }
    c
}

/// `a` with the samples of `b` appended (both made from the same sequences).
fn append(mut a: Dataset, b: Dataset) -> Result<Dataset, String> {
    if a.header.clips != b.header.clips || a.header.cameras != b.header.cameras {
        return Err("cannot append views of other clips or cameras".into());
    }
    a.samples.extend(b.samples);
    Ok(a)
}

/// Trains `recipe` on `sequences`: the classifier on its training views, then the viewpoint
/// heads on its head views.
fn train(
    sequences: &[PoseSequence],
    recipe: &Recipe,
    args: &Args,
) -> Result<(CameraLocalizer, f64), String> {
    let start = Instant::now();
    let posture = Some(recipe.posture);
    let mut training = project(sequences, &views(Protocol::Jittered, 1, args, posture))?;
    let mut heads = project(sequences, &views(Protocol::Sphere, 4, args, posture))?;
    if let Some(stride) = recipe.rig_stride {
        let mut rig = views(Protocol::Rig, 6, args, posture);
        rig.stride = stride;
        training = append(training, project(sequences, &rig)?)?;
        rig.seed = 7;
        heads = append(heads, project(sequences, &rig)?)?;
    }
    let options = &recipe.options;
    let (mut localizer, report) =
        CameraLocalizer::train(&training, options, |_| {}).map_err(|e| e.to_string())?;
    localizer
        .fit_viewpoint_with_capacity(
            &heads,
            camloc::DEFAULT_VIEWPOINT_LAMBDA,
            options.viewpoint_capacity,
        )
        .map_err(|e| e.to_string())?;
    eprintln!(
        "  {}: {} training views, {} Newton iterations, {:.1} s",
        recipe.name,
        training.samples.len(),
        report.newton_iterations(),
        start.elapsed().as_secs_f64()
    );
    Ok((localizer, start.elapsed().as_secs_f64()))
}

/// The sequences of posture clips (sit, squat, kneel, crawl) among `sequences`.
fn posture_clips(sequences: &[PoseSequence]) -> Vec<PoseSequence> {
    sequences
        .iter()
        .filter(|s| s.clip.category.is_posture())
        .cloned()
        .collect()
}

/// Table rows of `outcomes` per recipe: all, the posture categories together, seated
/// (category sit), low frames, then each category.
fn rows(md: &mut String, title: &str, results: &[(&Recipe, Vec<ViewOutcome>)]) {
    let Some((_, first)) = results.first() else {
        return;
    };
    let categories = categories_in(first);
    let _ = writeln!(md, "\n{title}\n");
    let mut header =
        "| recipe | all | inside the class boxes | postures | sit | low frames |".to_string();
    for c in &categories {
        let _ = write!(header, " {} |", c.name());
    }
    let _ = writeln!(md, "{header}");
    let _ = writeln!(md, "|{}", "---|".repeat(6 + categories.len()));
    for (recipe, out) in results {
        let mut line = format!(
            "| {} | {} | {} | {} | {} | {} |",
            recipe.name,
            Summary::of(out, |_| true).cell(),
            Summary::of(out, |o| o.inside).cell(),
            Summary::of(out, |o| o.category.is_posture()).cell(),
            Summary::of(out, |o| o.category == MotionCategory::Sit).cell(),
            Summary::of(out, |o| o.low).cell()
        );
        for c in &categories {
            let _ = write!(line, " {} |", Summary::of(out, |o| o.category == *c).cell());
        }
        let _ = writeln!(md, "{line}");
    }
}

/// Runs `postures`.
pub fn run(args: &Args) -> Result<(), String> {
    let started = Instant::now();
    let mut md = String::new();
    let (train_seqs, test_seqs) = load_split(&args.mocap, &args.test_subjects)?;
    let _ = writeln!(
        md,
        "Cells: 12-class accuracy (level accuracy, median viewpoint error, mean signed elevation error, views). Held-out subjects {}; selection by pose at {} mm.",
        args.test_subjects.join(", "),
        args.min_pose_distance
    );
    // 1. Held-out subjects under three protocols.
    let jittered = project(&test_seqs, &views(Protocol::Jittered, 2, args, None))?;
    let mut sphere = project(&test_seqs, &views(Protocol::Sphere, 3, args, None))?;
    sphere.samples.retain(|s| s.in_class_box);
    let rig = project(&test_seqs, &views(Protocol::Rig, 5, args, None))?;
    let mut per_protocol: Vec<Vec<(&Recipe, Vec<ViewOutcome>)>> = vec![Vec::new(); 3];
    for recipe in &args.recipes {
        let (localizer, seconds) = train(&train_seqs, recipe, args)?;
        let _ = writeln!(md, "\n{}: trained in {seconds:.1} s.", recipe.name);
        for (k, test) in [&jittered, &sphere, &rig].into_iter().enumerate() {
            per_protocol[k].push((recipe, outcomes(&localizer, test)?));
        }
    }
    for (name, results) in ["jittered", "sphere, inside the class boxes", "rig"]
        .iter()
        .zip(&per_protocol)
    {
        rows(&mut md, &format!("Held-out subjects, `{name}`:"), results);
    }
    flush(&mut md);
    let all: Vec<PoseSequence> = train_seqs.into_iter().chain(test_seqs).collect();
    // 2. Posture clips, leave-subject-out in folds.
    if args.folds > 0 {
        let mut subjects: Vec<String> = posture_clips(&all)
            .into_iter()
            .map(|s| s.clip.subject)
            .collect();
        subjects.sort();
        subjects.dedup();
        let folds: Vec<Vec<String>> = (0..args.folds.min(subjects.len()))
            .map(|f| {
                subjects
                    .iter()
                    .skip(f)
                    .step_by(args.folds)
                    .cloned()
                    .collect()
            })
            .collect();
        let mut results: [Vec<(&Recipe, Vec<ViewOutcome>)>; 2] = Default::default();
        for recipe in &args.recipes {
            let mut pooled: [Vec<ViewOutcome>; 2] = Default::default();
            for held in &folds {
                let (train_part, test_part): (Vec<PoseSequence>, Vec<PoseSequence>) = all
                    .iter()
                    .cloned()
                    .partition(|s| !held.contains(&s.clip.subject));
                let test_part = posture_clips(&test_part);
                let (localizer, _) = train(&train_part, recipe, args)?;
                for (k, protocol) in [Protocol::Jittered, Protocol::Rig].into_iter().enumerate() {
                    let test = project(&test_part, &views(protocol, 2 + 3 * k as u64, args, None))?;
                    pooled[k].extend(outcomes(&localizer, &test)?);
                }
            }
            for (k, p) in pooled.into_iter().enumerate() {
                results[k].push((recipe, p));
            }
        }
        let _ = writeln!(
            md,
            "\nPosture clips, leave-subject-out: {} folds over subjects {} (each fold trained on every other subject).",
            folds.len(),
            subjects.join(", ")
        );
        for (name, r) in ["jittered", "rig"].iter().zip(&results) {
            rows(
                &mut md,
                &format!("Posture clips of held-out subjects, `{name}`:"),
                r,
            );
        }
        flush(&mut md);
    }
    // 3. Leave-posture-out.
    if !args.no_leave_posture_out {
        let (train_part, test_part): (Vec<PoseSequence>, Vec<PoseSequence>) = all
            .iter()
            .cloned()
            .partition(|s| !s.clip.category.is_posture());
        let mut results: [Vec<(&Recipe, Vec<ViewOutcome>)>; 2] = Default::default();
        for recipe in &args.recipes {
            let (localizer, _) = train(&train_part, recipe, args)?;
            for (k, protocol) in [Protocol::Jittered, Protocol::Rig].into_iter().enumerate() {
                let test = project(&test_part, &views(protocol, 2 + 3 * k as u64, args, None))?;
                results[k].push((recipe, outcomes(&localizer, &test)?));
            }
        }
        let _ = writeln!(
            md,
            "\nLeave-posture-out: trained on every subject without any posture clip ({} clips left out).",
            test_part.len()
        );
        for (name, r) in ["jittered", "rig"].iter().zip(&results) {
            rows(
                &mut md,
                &format!("Posture clips, none trained on, `{name}`:"),
                r,
            );
        }
    }
    let _ = writeln!(md, "\nTotal {:.0} s.", started.elapsed().as_secs_f64());
    flush(&mut md);
    Ok(())
}

/// Prints what `md` holds so far (a long run shows each part as it ends) and empties it.
fn flush(md: &mut String) {
    print!("{md}");
    let _ = std::io::Write::flush(&mut std::io::stdout());
    md.clear();
}
