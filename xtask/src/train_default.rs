//! `cargo xtask train-default`: the default model and reconstruction basis embedded in the
//! `camloc` binary.

use std::path::PathBuf;
use std::time::Instant;

use camloc::dataset::{GenerateConfig, Protocol};
use camloc::reconstruct::{BasisConfig, PoseBasis};
use camloc::store::Persist;
use camloc::{CameraLocalizer, TrainOptions};

use crate::gen_dataset::{load_sequences, project};

/// Seed of the default model's dataset (jitter, noise) and dropout.
pub const DEFAULT_SEED: u64 = 1;
/// Frame stride of the default model's dataset.
pub const DEFAULT_STRIDE: usize = 10;

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
}

/// The training options of the default model (also used for the report's "default" row).
pub fn default_options() -> TrainOptions {
    let mut options = TrainOptions::default();
    if let Some(d) = options.dropout.as_mut() {
        d.seed = DEFAULT_SEED;
    }
    options
}

/// The dataset settings of the default model: `jittered`, Table-1 cameras.
pub fn default_dataset_config() -> GenerateConfig {
    let mut config = GenerateConfig::new(Protocol::Jittered);
    config.seed = DEFAULT_SEED;
    config.stride = DEFAULT_STRIDE;
    config
}

/// Runs `train-default`.
pub fn run(args: &Args) -> Result<(), String> {
    let start = Instant::now();
    let out = crate::workspace_root().join(&args.out);
    let basis_out = crate::workspace_root().join(&args.basis_out);
    for path in [&out, &basis_out] {
        if path.exists() && !args.force {
            return Err(format!(
                "{}: already exists (pass --force to replace the defaults)",
                path.display()
            ));
        }
    }
    let (sequences, _, _) = load_sequences(&args.mocap)?;
    let dataset = project(&sequences, &default_dataset_config())?;
    let options = default_options();
    eprintln!(
        "training the default model on {} samples of {} subjects",
        dataset.samples.len(),
        dataset.subjects().len()
    );
    let (localizer, report) = CameraLocalizer::train(&dataset, &options, |log| {
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
    localizer
        .save(&out, args.force)
        .map_err(|e| e.to_string())?;
    println!(
        "wrote {} ({} bytes, descriptor {}, lambda {}, {} samples) in {:.1} s",
        out.display(),
        std::fs::metadata(&out).map(|m| m.len()).unwrap_or(0),
        localizer.descriptor().name(),
        options.regression.lambda,
        dataset.samples.len(),
        start.elapsed().as_secs_f64()
    );
    let poses = dataset.unique_poses();
    let basis = PoseBasis::fit(&poses, &BasisConfig::default()).map_err(|e| e.to_string())?;
    basis
        .save(&basis_out, args.force)
        .map_err(|e| e.to_string())?;
    println!(
        "wrote {} ({} components explaining {:.1}% of the variance of {} poses)",
        basis_out.display(),
        basis.n_components(),
        100.0 * basis.explained_variance_ratio(),
        poses.len()
    );
    println!("rebuild the binary (cargo build --release -p camloc-cli) to embed it");
    Ok(())
}
