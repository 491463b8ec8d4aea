//! `cargo xtask train-default`: the default model and reconstruction basis embedded in the
//! `camloc` binary.

use std::path::PathBuf;
use std::time::Instant;

use camloc::dataset::{Augmentation, GenerateConfig, PoseSequence, Protocol};
use camloc::reconstruct::{BasisConfig, PoseBasis};
use camloc::store::Persist;
use camloc::{CameraLocalizer, TrainOptions};

use crate::mocap_data::{basis_poses, categorise, load_sequences, project};

/// Seed of the default model's dataset (jitter, noise) and dropout.
pub const DEFAULT_SEED: u64 = 1;
/// Seed of the `sphere` views the default model's viewpoint heads are fitted on (another
/// draw than the classifier's training views).
pub const VIEWPOINT_SEED: u64 = 4;
/// Frame stride of the default model's dataset (every frame; selection by pose decides).
pub const DEFAULT_STRIDE: usize = 1;
/// Frame selection by pose of the default model's dataset, millimetres of maximum per-joint
/// distance (issue 11: measured by `cargo xtask generalise`).
pub const DEFAULT_MIN_POSE_DISTANCE_MM: f64 = 100.0;
/// Camera roll of the default model's training views, degrees (photos are seldom level).
pub const DEFAULT_ROLL_DEG: f64 = 15.0;

/// Arguments of `train-default`.
#[derive(clap::Args)]
pub struct Args {
    /// Motion capture folders [default: $CAMLOC_DATA/cmu, else ../shared/data/cmu].
    #[arg(long = "mocap", value_name = "DIR")]
    pub mocap: Vec<PathBuf>,
    /// Where to write the model.
    #[arg(
        long,
        default_value = "fixtures/default-model.bin",
        value_name = "FILE"
    )]
    pub out: PathBuf,
    /// Where to write the reconstruction basis.
    #[arg(
        long,
        default_value = "fixtures/default-basis.bin",
        value_name = "FILE"
    )]
    pub basis_out: PathBuf,
    /// Overwrite the output if it exists.
    #[arg(long)]
    pub force: bool,
    /// Only the reconstruction basis (the model is left as it is).
    #[arg(long)]
    pub basis_only: bool,
}

/// The training options of the default model (also used for the report's "default" row):
/// [`TrainOptions::default`] with the dropout seeded, and no viewpoint heads fitted on the
/// training views (they are fitted by [`fit_default_viewpoint`] on `sphere` views).
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

/// The dataset settings of `protocol` for the default model: Table-1 cameras, every frame,
/// selection by pose at [`DEFAULT_MIN_POSE_DISTANCE_MM`], training augmentation and camera
/// roll up to [`DEFAULT_ROLL_DEG`], the given seed.
fn training_views(protocol: Protocol, seed: u64) -> GenerateConfig {
    let mut config = GenerateConfig::new(protocol);
    config.seed = seed;
    config.stride = DEFAULT_STRIDE;
    config.min_pose_distance_mm = DEFAULT_MIN_POSE_DISTANCE_MM;
    config.augmentation = Augmentation::TRAINING;
    config.jitter.roll_deg = DEFAULT_ROLL_DEG;
    config
}

/// The dataset settings of the default model: `jittered` training views
/// ([`training_views`]) with [`DEFAULT_SEED`].
pub fn default_dataset_config() -> GenerateConfig {
    training_views(Protocol::Jittered, DEFAULT_SEED)
}

/// Fits the default viewpoint heads of `localizer` ([`camloc::DEFAULT_VIEWPOINT_LAMBDA`])
/// on `sphere` training views of `sequences` with [`VIEWPOINT_SEED`]; returns their number.
pub fn fit_default_viewpoint(
    localizer: &mut CameraLocalizer,
    sequences: &[PoseSequence],
) -> Result<usize, String> {
    let views = project(sequences, &training_views(Protocol::Sphere, VIEWPOINT_SEED))?;
    localizer
        .fit_viewpoint(&views, camloc::DEFAULT_VIEWPOINT_LAMBDA)
        .map_err(|e| e.to_string())?;
    Ok(views.samples.len())
}

/// Runs `train-default`.
pub fn run(args: &Args) -> Result<(), String> {
    let start = Instant::now();
    let out = crate::workspace_root().join(&args.out);
    let basis_out = crate::workspace_root().join(&args.basis_out);
    let written: &[&PathBuf] = if args.basis_only {
        &[&basis_out]
    } else {
        &[&out, &basis_out]
    };
    for path in written {
        if path.exists() && !args.force {
            return Err(format!(
                "{}: already exists (pass --force to replace the defaults)",
                path.display()
            ));
        }
    }
    let (mut sequences, _, _) = load_sequences(&args.mocap)?;
    categorise(&mut sequences, &args.mocap, None);
    if !args.basis_only {
        train_model(args, &sequences, &out)?;
    }
    let poses: Vec<camloc::Pose3> = basis_poses(&sequences, DEFAULT_MIN_POSE_DISTANCE_MM)
        .into_iter()
        .map(|(p, _)| p)
        .collect();
    let basis = PoseBasis::fit(&poses, &BasisConfig::default()).map_err(|e| e.to_string())?;
    basis
        .save(&basis_out, args.force)
        .map_err(|e| e.to_string())?;
    println!(
        "wrote {} ({} components explaining {:.1}% of the variance of {} poses) in {:.1} s",
        basis_out.display(),
        basis.n_components(),
        100.0 * basis.explained_variance_ratio(),
        poses.len(),
        start.elapsed().as_secs_f64()
    );
    println!("rebuild the binary (cargo build --release -p camloc-cli) to embed it");
    Ok(())
}

/// Trains the default model on `sequences` and writes it to `out`.
fn train_model(args: &Args, sequences: &[PoseSequence], out: &PathBuf) -> Result<(), String> {
    let start = Instant::now();
    let dataset = project(sequences, &default_dataset_config())?;
    for (category, n) in dataset.samples_per_category() {
        eprintln!("  {}: {n} samples", category.name());
    }
    let options = default_options();
    eprintln!(
        "training the default model on {} samples of {} subjects",
        dataset.samples.len(),
        dataset.subjects().len()
    );
    let fit_start = Instant::now();
    let (mut localizer, report) = CameraLocalizer::train(&dataset, &options, |log| {
        eprintln!(
            "  newton {:>3}: objective {:.6e}  |grad|_inf {:.3e}  ({})",
            log.iteration,
            log.objective,
            log.gradient_norm,
            log.direction_summary()
        );
    })
    .map_err(|e| e.to_string())?;
    if !report.converged {
        return Err("the Newton solver did not converge; the default model was not written".into());
    }
    let fit_seconds = fit_start.elapsed().as_secs_f64();
    let head_start = Instant::now();
    let views = fit_default_viewpoint(&mut localizer, sequences)?;
    println!(
        "classifier fit {fit_seconds:.1} s ({} Newton iterations); viewpoint heads on {views} sphere views {:.1} s",
        report.newton_iterations(),
        head_start.elapsed().as_secs_f64()
    );
    localizer.save(out, args.force).map_err(|e| e.to_string())?;
    println!(
        "wrote {} ({} bytes, descriptor {}, lambda {}, {} samples) in {:.1} s",
        out.display(),
        std::fs::metadata(out).map(|m| m.len()).unwrap_or(0),
        localizer.descriptor().name(),
        options.regression.lambda,
        dataset.samples.len(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}
