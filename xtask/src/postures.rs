//! `cargo xtask postures`: how the localizer holds on seated and low postures and on cameras
//! that stand like real ones (issue 21). Compares training recipes on
//! * the held-out subjects under `jittered`, `sphere` (inside the class boxes) and `rig`,
//!   per motion category, with the mean signed elevation error;
//! * the posture clips (sit, squat, kneel, crawl) left out by subject, in folds;
//! * the posture clips when no posture clip is trained on at all (leave-posture-out);
//!
//! each test set read as one input and each band of true elevation as one
//! ([`crate::height_inputs`]); and, as a reference row, the camera fitted to each view's true 3D pose.
//!
//! Prints markdown tables; writes nothing.

use std::fmt::Write;
use std::path::PathBuf;
use std::time::Instant;

use camloc::dataset::{Dataset, GenerateConfig, MotionCategory, PoseSequence, Protocol, annotated};
use camloc::{
    CameraHeight, CameraLocalizer, CameraSet, EYE_LEVEL_WEIGHT, HEIGHT_SHARE_MAX_POSES,
    HEIGHT_SHARE_PSEUDO_VIEWS,
};

use crate::height_inputs;
use crate::mocap_data::{load_split, project};
use crate::progress::newton_line;
use crate::proportions::people::{HEAD_FACTOR, LIMB_FACTOR, factors, rescale};
use crate::recipe::Recipe;
use crate::view_scores::{
    Summary, ViewOutcome, categories_in, elevation_bands, known_pose_outcomes, outcomes,
};

/// Arguments of `postures`.
#[derive(clap::Args)]
pub struct Args {
    /// Motion capture folders [default: ../shared/data/cmu].
    #[arg(long = "mocap", value_name = "DIR")]
    pub mocap: Vec<PathBuf>,
    /// Held-out subjects of the protocol comparison.
    #[arg(long, value_delimiter = ',', default_value = crate::generalise::TEST_SUBJECTS)]
    pub test_subjects: Vec<String>,
    /// Subjects left out of everything (neither trained nor tested on): with the real
    /// held-out subjects here and some training subjects as `--test-subjects`, recipes are
    /// compared on validation subjects without looking at the test subjects.
    #[arg(long, value_delimiter = ',', value_name = "SUBJECTS")]
    pub exclude_subjects: Vec<String>,
    /// Recipes compared, each `+`-joined parts: `jittered` (the recipe before issue 21),
    /// `posture[=SHARE]` (0.25), `rig[=STRIDE]` (2), `balance=B` (1), `quadratic[-K]`,
    /// `heads=quadratic-K`, `classes`, `lambda=L`, `tol=T`, `precond=N`, `products=N`,
    /// `no-low-below` (no views of low bodies from the lower ring), and the augmentation's
    /// `bones=B` (0.1), `hips=LO-HI` (0.8-1.6), `head=LO-HI` (0.8-1.6), `photo=P` (0.5); e.g.
    /// `posture+rig+balance=0.5`.
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
    /// Print every Newton iteration of every fit on standard error.
    #[arg(long)]
    pub log_iterations: bool,
    /// Frame selection by pose, millimetres (the default model's).
    #[arg(long, default_value_t = crate::recipe::DEFAULT_MIN_POSE_DISTANCE_MM, value_name = "MM")]
    pub min_pose_distance: f64,
}

/// The posture parts' test views of `clips`: `jittered` (seed 2) and `rig` (seed 5).
fn test_views(clips: &[PoseSequence], args: &Args) -> Result<[Dataset; 2], String> {
    Ok([
        project(clips, &views(Protocol::Jittered, 2, args))?,
        project(clips, &views(Protocol::Rig, 5, args))?,
    ])
}

/// Test views: `protocol`, `seed`, selection by pose, no augmentation.
fn views(protocol: Protocol, seed: u64, args: &Args) -> GenerateConfig {
    let mut c = GenerateConfig::new(protocol);
    c.seed = seed;
    c.min_pose_distance_mm = args.min_pose_distance;
    c
}

/// Trains `recipe` on `sequences`, saying how long it took on standard error.
fn train(
    sequences: &[PoseSequence],
    recipe: &Recipe,
    args: &Args,
) -> Result<(CameraLocalizer, f64), String> {
    let start = Instant::now();
    let trained = recipe.train(sequences, args.min_pose_distance, |log| {
        if args.log_iterations {
            eprintln!("{}", newton_line(log, start.elapsed().as_secs_f64()));
        }
    })?;
    eprintln!(
        "  {}: {} training views, {} Newton iterations, {:.1} s",
        recipe.name,
        trained.training_views,
        trained.report.newton_iterations(),
        start.elapsed().as_secs_f64()
    );
    Ok((trained.localizer, start.elapsed().as_secs_f64()))
}

/// Seed of the skeletons of [`other_skeletons`].
const OTHER_SKELETON_SEED: u64 = 21;

/// `sequences` as people of other proportions annotated in another convention: each clip's
/// limbs rescaled by its own random factors (each limb type x [`LIMB_FACTOR`], the
/// neck-to-head distance x [`HEAD_FACTOR`]: the proportions test's people, drawn per clip),
/// then the landmarks placed as photo annotations and lab skeletons place them (the neck at
/// the mid-shoulder point, the pelvis at the mid-hip point, the head kept relative to the
/// neck).
fn other_skeletons(sequences: &[PoseSequence]) -> Vec<PoseSequence> {
    sequences
        .iter()
        .map(|s| {
            let f = factors(&s.clip.name, OTHER_SKELETON_SEED);
            let mut s = s.clone();
            for (_, pose) in &mut s.frames {
                *pose = annotated(&rescale(pose, &f), 1.0);
            }
            s
        })
        .collect()
}

/// The sequences of posture clips (sit, squat, kneel, crawl) among `sequences`.
fn posture_clips(sequences: &[PoseSequence]) -> Vec<PoseSequence> {
    sequences
        .iter()
        .filter(|s| s.clip.category.is_posture())
        .cloned()
        .collect()
}

/// The name of the rows of [`known_pose_outcomes`]: the camera fitted to the true 3D pose.
const KNOWN_POSE: &str = "true 3D pose, Procrustes camera";

/// The row of the last recipe's localizer under the prior `CameraHeight::EyeLevel`.
const EYE_LEVEL: &str = "the last recipe with `--camera-height eye-level`";

/// The row of the last recipe's localizer with the camera heights' shares estimated from
/// each test set as one input (`CameraLocalizer::estimate_height_shares`: its first
/// `HEIGHT_SHARE_MAX_POSES` views, as `camloc localize` reads them).
const FROM_INPUT: &str =
    "the last recipe with `--camera-height from-input` (the command line's default)";

/// The row of [`FROM_INPUT`]'s estimate without the input's mean elevations.
const FROM_INPUT_SHARES: &str = "the last recipe with `--camera-height from-input`, the heights' shares alone (before the input's mean elevations)";

/// The row of the last recipe with each band of true elevation one input.
const BANDS: &str = "the last recipe with `--camera-height from-input`, each band of true elevation (below) one input, as a fixed camera's footage";

/// [`BANDS`] without the inputs' mean elevations.
const BANDS_SHARES: &str = "the same, the heights' shares alone";

/// One table's rows: each row's name (a recipe's, [`FROM_INPUT`], [`EYE_LEVEL`] or
/// [`KNOWN_POSE`]) and outcomes.
type Rows<'a> = Vec<(&'a str, Vec<ViewOutcome>)>;

/// Per test set of `tests`, its table rows: one per recipe of `args` (a localizer trained on
/// `train_seqs`; `trained` hears the recipe and the seconds of each training), the last
/// recipe's with the camera heights estimated from the test set ([`FROM_INPUT`], and
/// [`FROM_INPUT_SHARES`] without the middle elevation), from each band of true elevation
/// ([`BANDS`], [`BANDS_SHARES`]) and under the eye-level prior ([`EYE_LEVEL`]), then the
/// [`KNOWN_POSE`] reference.
fn score<'a>(
    train_seqs: &[PoseSequence],
    tests: &[&Dataset],
    args: &'a Args,
    mut trained: impl FnMut(&Recipe, f64),
) -> Result<Vec<Rows<'a>>, String> {
    let mut rows = vec![Vec::new(); tests.len()];
    let mut last = None;
    for recipe in &args.recipes {
        let (localizer, seconds) = train(train_seqs, recipe, args)?;
        trained(recipe, seconds);
        for (row, test) in rows.iter_mut().zip(tests) {
            row.push((recipe.name.as_str(), outcomes(&localizer, test)?));
        }
        last = Some(localizer);
    }
    if let Some(localizer) = last {
        for (row, test) in rows.iter_mut().zip(tests) {
            let estimate = localizer.estimate_height_shares_of(test);
            eprintln!(
                "  camera heights of {} test views: {estimate:?}",
                test.samples.len()
            );
            for (name, shares_alone) in [(FROM_INPUT, false), (FROM_INPUT_SHARES, true)] {
                let estimated = localizer
                    .clone()
                    .with_camera_height(height_inputs::prior(&estimate, shares_alone));
                row.push((name, outcomes(&estimated, test)?));
            }
            for (name, shares_alone) in [(BANDS, false), (BANDS_SHARES, true)] {
                row.push((
                    name,
                    height_inputs::band_outcomes(&localizer, test, shares_alone)?,
                ));
            }
        }
        let eye_level = localizer.with_camera_height(CameraHeight::EyeLevel);
        for (row, test) in rows.iter_mut().zip(tests) {
            row.push((EYE_LEVEL, outcomes(&eye_level, test)?));
        }
    }
    let cameras = CameraSet::table1();
    for (row, test) in rows.iter_mut().zip(tests) {
        row.push((KNOWN_POSE, known_pose_outcomes(&cameras, test)?));
    }
    Ok(rows)
}

/// Table rows of `outcomes` per row name (a recipe's, or [`KNOWN_POSE`]): all, the posture
/// categories together, seated (category sit), low frames, then each other category.
fn rows(md: &mut String, title: &str, results: &[(&str, Vec<ViewOutcome>)]) {
    let Some((_, first)) = results.first() else {
        return;
    };
    let mut categories = categories_in(first);
    categories.retain(|c| *c != MotionCategory::Sit);
    let _ = writeln!(md, "\n{title}\n");
    let mut header =
        "| recipe | all | inside the class boxes | postures | sit | low frames |".to_string();
    for c in &categories {
        let _ = write!(header, " {} |", c.name());
    }
    let _ = writeln!(md, "{header}");
    let _ = writeln!(md, "|{}", "---|".repeat(6 + categories.len()));
    for (name, out) in results {
        let mut line = format!(
            "| {name} | {} | {} | {} | {} | {} |",
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

/// Runs `postures`: prints each part's tables as it ends.
pub fn run(args: &Args) -> Result<(), String> {
    measure(args, &mut |part| {
        print!("{part}");
        let _ = std::io::Write::flush(&mut std::io::stdout());
    })
}

/// Measures what `postures` measures, handing `emit` the markdown of each part as it ends.
pub fn measure(args: &Args, emit: &mut dyn FnMut(&str)) -> Result<(), String> {
    let started = Instant::now();
    let mut md = String::new();
    let (mut train_seqs, test_seqs) = load_split(&args.mocap, &args.test_subjects)?;
    train_seqs.retain(|s| !args.exclude_subjects.contains(&s.clip.subject));
    let _ = writeln!(
        md,
        "Cells: 12-class accuracy (level accuracy, median viewpoint error, mean signed elevation error, the share of views whose viewpoint error is within the uncertainty camloc reported (calibrated to hold about 68%; none for the true-pose reference), views). Held-out subjects {}; selection by pose at {} mm.",
        args.test_subjects.join(", "),
        args.min_pose_distance
    );
    let _ = writeln!(
        md,
        "`other skeletons`: the same subjects as people of other proportions annotated in another convention, as recorded lab skeletons and detectors are (each clip's limb types x U({}, {}), its neck-to-head distance x U({}, {}), then the neck at the mid-shoulder point and the pelvis at the mid-hip point).",
        LIMB_FACTOR.0, LIMB_FACTOR.1, HEAD_FACTOR.0, HEAD_FACTOR.1
    );
    // 1. Held-out subjects under three protocols.
    let [jittered, rig] = test_views(&test_seqs, args)?;
    let mut sphere = project(&test_seqs, &views(Protocol::Sphere, 3, args))?;
    sphere.samples.retain(|s| s.in_class_box);
    let [jittered_others, rig_others] = test_views(&other_skeletons(&test_seqs), args)?;
    let tests = [&jittered, &sphere, &rig, &jittered_others, &rig_others];
    let per_protocol = score(&train_seqs, &tests, args, |recipe, seconds| {
        let _ = writeln!(md, "\n{}: trained in {seconds:.1} s.", recipe.name);
    })?;
    for (name, results) in [
        "jittered",
        "sphere, inside the class boxes",
        "rig",
        "jittered, other skeletons",
        "rig, other skeletons",
    ]
    .iter()
    .zip(&per_protocol)
    {
        rows(&mut md, &format!("Held-out subjects, `{name}`:"), results);
    }
    elevation_bands(
        &mut md,
        "Held-out subjects, `rig`, by the camera's true elevation above the pelvis (the middle ring's band ends at 22.5 deg):",
        &per_protocol[2],
    );
    emit(&std::mem::take(&mut md));
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
        // Per protocol (`jittered`, `rig`) and row, the outcomes pooled over the folds.
        let mut results: Vec<Rows> = Vec::new();
        for held in &folds {
            let (train_part, test_part): (Vec<PoseSequence>, Vec<PoseSequence>) = all
                .iter()
                .cloned()
                .partition(|s| !held.contains(&s.clip.subject));
            let [jittered, rig] = test_views(&posture_clips(&test_part), args)?;
            let fold = score(&train_part, &[&jittered, &rig], args, |_, _| {})?;
            if results.is_empty() {
                results = fold;
                continue;
            }
            for (pooled, rows) in results.iter_mut().zip(fold) {
                for ((_, pooled), (_, row)) in pooled.iter_mut().zip(rows) {
                    pooled.extend(row);
                }
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
        elevation_bands(
            &mut md,
            "Posture clips of held-out subjects, `rig`, by the camera's true elevation above the pelvis:",
            &results[1],
        );
        emit(&std::mem::take(&mut md));
    }
    // 3. Leave-posture-out.
    if !args.no_leave_posture_out {
        let (train_part, test_part): (Vec<PoseSequence>, Vec<PoseSequence>) = all
            .iter()
            .cloned()
            .partition(|s| !s.clip.category.is_posture());
        let [jittered, rig] = test_views(&test_part, args)?;
        let results = score(&train_part, &[&jittered, &rig], args, |_, _| {})?;
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
    emit(&std::mem::take(&mut md));
    Ok(())
}

/// The `report` section of issue 21: `postures` with the recipe before issue 21 (`jittered`)
/// and the default model's ([`crate::recipe::DEFAULT_RECIPE`]), on the generalisation split,
/// leave-subject-out in `folds` and leave-posture-out.
pub fn report_section(mocap: &[PathBuf], folds: usize) -> Result<String, String> {
    eprintln!("postures: the recipe before issue 21 against the default model's");
    let args = Args {
        mocap: mocap.to_vec(),
        test_subjects: crate::generalise::TEST_SUBJECTS
            .split(',')
            .map(String::from)
            .collect(),
        recipes: vec!["jittered".parse()?, Recipe::default_model()],
        folds,
        no_leave_posture_out: false,
        log_iterations: false,
        exclude_subjects: Vec::new(),
        min_pose_distance: crate::recipe::DEFAULT_MIN_POSE_DISTANCE_MM,
    };
    let mut md = format!(
        "## Seated and low postures, studio cameras\n\nOutput of `cargo xtask postures \
         --recipes jittered,{} --folds {folds}` (the same code). `jittered` is the default \
         model's recipe before issue 21 (`jittered` views only); `{}` is today's \
         ([conventions.md](conventions.md) sections 5 and 7): a tenth of the samples put in a \
         posture, `rig` views of every other frame added to the classifier's and the viewpoint \
         heads' views, the camera priors balanced halfway, viewpoint heads of their own \
         quadratic capacity. `rig` = cameras fixed in a room at 1.0-2.2 m, aimed at its centre, \
         the person walking within 2 m of it; its truth is the camera's direction, so views \
         near a class boundary count; `inside the class boxes` keeps the views whose direction \
         lies in the Table-1 box of its class. `low frames` = pelvis below 0.9 leg lengths. \
         The recipe rows localize each view on its own (`--camera-height any`). \
         `{FROM_INPUT}` is today's model given each table's test views as one input: it \
         estimates how the input's cameras divide among the three heights from all its views \
         (`CameraLocalizer::estimate_height_shares`: its first {HEIGHT_SHARE_MAX_POSES} \
         views, each weighing the share of an independent view it is worth (a video's \
         frames little), expectation-maximisation with the model's probabilities held fixed, \
         {HEIGHT_SHARE_PSEUDO_VIEWS} views of a camera at eye level added), then localizes \
         every view under those shares, each middle-ring viewpoint regressing toward the \
         input's middle cameras' mean elevation instead of the training's, estimated with the \
         heads' pull toward their training's elevations undone (`HeightShares::elevations_deg`, conventions.md \
         section 5), as `camloc localize` and Python's `Localizer` do by default with the \
         poses of one input or call. `{FROM_INPUT_SHARES}` is the same without that move. \
         `{BANDS}` reads the views of each band of true elevation of the last table of a \
         section as one input, as one camera's footage is (a fixed camera sees a person at a \
         narrow band of elevations); `{BANDS_SHARES}` without the move. \
         `{EYE_LEVEL}` is today's model told that the camera stands at about eye level \
         (`camloc localize --camera-height eye-level`, `CameraHeight::EyeLevel`: a \
         middle-ring camera {EYE_LEVEL_WEIGHT} times as likely a priori), what a user filming \
         with a tripod, a phone or a studio camera can say. \
         `{KNOWN_POSE}` is no localizer but a reference: the weak-perspective camera fitted \
         to each view's true 3D pose (eq. 3), classed by its ring and side. It knows what no \
         localizer reading the 2D knows, so its errors are the protocol's own (2D noise, \
         perspective, lens distortion, views near a class boundary): a localizer can beat it \
         only where it has learnt those effects.\n\n",
        crate::recipe::DEFAULT_RECIPE,
        crate::recipe::DEFAULT_RECIPE
    );
    measure(&args, &mut |part| {
        eprint!(".");
        md.push_str(part);
    })?;
    md.push('\n');
    Ok(md)
}
