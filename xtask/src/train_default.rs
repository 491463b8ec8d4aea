//! `cargo xtask train-default`: the default model and reconstruction basis embedded in the
//! `camloc` binary.

use std::path::{Path, PathBuf};
use std::time::Instant;

use camloc::dataset::PoseSequence;
use camloc::reconstruct::{BasisConfig, PoseBasis};
use camloc::store::Persist;

use crate::mocap_data::{basis_poses, categorise, load_sequences};
use crate::progress::newton_line;
use crate::recipe::{DEFAULT_MIN_POSE_DISTANCE_MM, Recipe};

/// Arguments of `train-default`.
#[derive(clap::Args)]
pub struct Args {
    /// Motion capture folders [default: $CAMLOC_DATA/cmu, else ../shared/data/cmu].
    #[arg(long = "mocap", value_name = "DIR")]
    pub mocap: Vec<PathBuf>,
    /// Where to write the model (a relative path is taken from the repository's root, as
    /// the defaults are, wherever xtask runs).
    #[arg(
        long,
        default_value = "fixtures/default-model.bin",
        value_name = "FILE"
    )]
    pub out: PathBuf,
    /// Where to write the reconstruction basis (relative: from the repository's root).
    #[arg(
        long,
        default_value = "fixtures/default-basis.bin",
        value_name = "FILE"
    )]
    pub basis_out: PathBuf,
    /// Where to write the depth lifter, trained with the model (relative: from the
    /// repository's root); the lifter of poses whose pelvis and neck sit at the hip and
    /// shoulder midpoints goes beside it, `-midpoints` added to its name.
    #[arg(
        long,
        default_value = "fixtures/default-lifter.bin",
        value_name = "FILE"
    )]
    pub lifter_out: PathBuf,
    /// Overwrite the output if it exists.
    #[arg(long)]
    pub force: bool,
    /// Only the reconstruction basis (the model and the lifter are left as they are).
    #[arg(long)]
    pub basis_only: bool,
}

/// Runs `train-default`.
pub fn run(args: &Args) -> Result<(), String> {
    let start = Instant::now();
    let out = crate::workspace_root().join(&args.out);
    let basis_out = crate::workspace_root().join(&args.basis_out);
    let lifter_out = crate::workspace_root().join(&args.lifter_out);
    let midpoints_out = midpoint_lifter_path(&lifter_out);
    for path in [&out, &basis_out, &lifter_out, &midpoints_out] {
        if path.exists() && !args.force {
            return Err(format!(
                "{}: already exists (pass --force to replace the defaults)",
                path.display()
            ));
        }
    }
    let (mut sequences, _, _) = load_sequences(&args.mocap)?;
    categorise(&mut sequences, &args.mocap, None)?;
    if !args.basis_only {
        train_model(args, &sequences, &out, [&lifter_out, &midpoints_out])?;
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

/// Trains the default model ([`Recipe::default_model`]) on `sequences` and writes it to `out`,
/// and its depth lifters to `lifter_out` and `midpoints_out` (skeletons' own placement of the
/// pelvis and the neck, and the midpoint placement: [`midpoint_lifter_path`]).
fn train_model(
    args: &Args,
    sequences: &[PoseSequence],
    out: &Path,
    [lifter_out, midpoints_out]: [&Path; 2],
) -> Result<(), String> {
    let start = Instant::now();
    let recipe = Recipe::default_model();
    eprintln!(
        "training the default model (recipe {}) on {} subjects",
        recipe.name,
        sequences
            .iter()
            .map(|s| &s.clip.subject)
            .collect::<std::collections::BTreeSet<_>>()
            .len()
    );
    let trained = recipe.train(sequences, DEFAULT_MIN_POSE_DISTANCE_MM, |log| {
        eprintln!("{}", newton_line(log, start.elapsed().as_secs_f64()));
    })?;
    if !trained.report.converged {
        return Err("the Newton solver did not converge; the default model was not written".into());
    }
    let localizer = trained.localizer;
    println!(
        "classifier fit {:.1} s ({} Newton iterations, {} views); viewpoint heads on {} views",
        trained.fit_seconds,
        trained.report.newton_iterations(),
        trained.training_views,
        trained.head_views
    );
    localizer.save(out, args.force).map_err(|e| e.to_string())?;
    println!(
        "wrote {} ({} bytes, descriptor {}, lambda {}) in {:.1} s",
        out.display(),
        std::fs::metadata(out).map(|m| m.len()).unwrap_or(0),
        localizer.descriptor().name(),
        recipe.options.regression.lambda,
        start.elapsed().as_secs_f64()
    );
    let (lifter, midpoints) = trained.lifter.split_midpoint_lifter();
    let midpoints = midpoints.ok_or("the recipe trained no midpoint lifter")?;
    for (lifter, path, what) in [
        (&lifter, lifter_out, "skeletons' own placement"),
        (
            &midpoints,
            midpoints_out,
            "pelvis and neck at the midpoints",
        ),
    ] {
        lifter.save(path, args.force).map_err(|e| e.to_string())?;
        println!(
            "wrote {} ({} bytes, depth lifter of {} camera classes, {what})",
            path.display(),
            std::fs::metadata(path).map(|m| m.len()).unwrap_or(0),
            lifter.n_classes()
        );
    }
    Ok(())
}

/// Where the midpoint placement's lifter of the lifter file `lifter` goes: beside it,
/// `-midpoints` added to its stem (`default-lifter.bin` -> `default-lifter-midpoints.bin`, as
/// the build embeds them).
fn midpoint_lifter_path(lifter: &Path) -> PathBuf {
    let stem = lifter.file_stem().unwrap_or_default().to_string_lossy();
    let name = match lifter.extension() {
        Some(ext) => format!("{stem}-midpoints.{}", ext.to_string_lossy()),
        None => format!("{stem}-midpoints"),
    };
    lifter.with_file_name(name)
}
