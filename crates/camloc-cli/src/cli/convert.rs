//! `camloc convert`.

use std::path::PathBuf;
use std::process::ExitCode;

use camloc::keypoints::{KeypointRecord, to_camloc_json};
use camloc::reconstruct::FrameRate;
use camloc::store::{StagedFiles, escaped};
use camloc::{PartialPose2, follow_records};
use clap::ValueEnum;

use super::input::Inputs;
use super::output::{NpyStage, RowFile};
use super::stream::{Summary, counted, nothing_detected, report_pose_error};
use super::{CliError, EXIT_ERROR, InputArgs, Out, ProgressArgs, progress, targets};

/// camloc's own keypoint formats.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum Target {
    /// camloc JSON (docs/keypoints.md): ids kept, every landmark key, null for missing ones;
    /// people a detector numbered by their order in the frame (OpenPose, MMPose without
    /// `track_id`, YOLO) followed from frame to frame as `--sequence` follows them (30 fps).
    Camloc,
    /// A (N, 15, 2) float64 .npy array in the camloc15 layout, NaN, NaN for a missing
    /// landmark; row n is the n-th pose read (ids are not kept).
    Npy,
}

/// Arguments of `camloc convert`.
#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub input: InputArgs,
    /// The format to write.
    #[arg(long, value_enum, value_name = "FORMAT")]
    pub to: Target,
    /// Output file (refuses to overwrite unless --force).
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
    /// Overwrite --out if it exists.
    #[arg(long)]
    pub force: bool,
    #[command(flatten)]
    pub progress: ProgressArgs,
}

/// Runs `camloc convert`. The landmarks written are the ones read, with the pelvis and neck
/// derived where the input lacks them (as `localize` sees them). `.npy` output is written as
/// the poses are read; camloc JSON holds the poses in memory until the end.
pub fn run(args: &Args, out: &mut Out) -> Result<ExitCode, CliError> {
    targets::check(
        [(Some(args.out.as_path()), "--out", None)],
        &[("the input", Some(args.input.path()))],
        args.force,
    )?;
    match args.to {
        Target::Camloc => {
            targets::check_format(&args.out, "--to camloc", "camloc JSON", &["json"])?
        }
        Target::Npy => {
            targets::check_format(&args.out, "--to npy", "a NumPy .npy array", &["npy"])?
        }
    }
    let mut inputs = Inputs::open(&args.input)?;
    let bar = progress::counter(args.progress.quiet, inputs.len_hint(), "convert", "poses");
    let mut staged = StagedFiles::new(args.force);
    let mut summary = Summary {
        min_score: inputs.min_score(),
        ..Summary::default()
    };
    let mut npy = match args.to {
        Target::Npy => Some(Box::new(NpyStage::<PartialPose2>::new(&args.out)?)),
        Target::Camloc => None,
    };
    let mut poses: Vec<KeypointRecord> = Vec::new();
    let mut empty = 0u64;
    for item in inputs.by_ref() {
        bar.inc(1);
        match item {
            Ok(record) => {
                summary.poses += 1;
                if nothing_detected(&record.pose) {
                    empty += 1;
                    let message = "no landmark (every joint missing); written as such";
                    report_pose_error(&bar, &record.id, &record.source, message);
                }
                match &mut npy {
                    Some(npy) => npy.push(&record, Some(&record.pose))?,
                    None => poses.push(record),
                }
            }
            // A pose refused for its layout is written in its place without landmarks.
            Err(e) => match KeypointRecord::of_refused_pose(&e) {
                Some((record, message)) => {
                    summary.poses += 1;
                    summary.failed_poses += 1;
                    let message = format!("{message}; written without landmarks");
                    report_pose_error(&bar, &record.id, &record.source, &message);
                    match &mut npy {
                        Some(npy) => npy.push(&record, Some(&record.pose))?,
                        None => poses.push(record),
                    }
                }
                None => {
                    summary.failed_files += 1;
                    super::stream::report_error(&super::stream::FILE_ERRORS, &bar, || {
                        e.to_string()
                    });
                }
            },
        }
    }
    bar.finish_and_clear();
    if summary.poses == 0 && summary.failed_files == 0 {
        return Err(inputs.no_poses());
    }
    inputs.check_read_to_end(summary.failed_files)?;
    match npy {
        Some(npy) => npy.finish(&mut staged)?,
        None => {
            // camloc JSON's `person` is an identity: people a detector numbered by their
            // order in the frame are followed, as `--sequence` follows them.
            let followed = follow_records(&mut poses, inputs.is_folder(), FrameRate::default());
            for warning in followed.warnings() {
                stderr_line!("camloc: warning: {warning}");
            }
            staged.add(&args.out, to_camloc_json(&poses).as_bytes())?;
        }
    }
    out.write(&format!(
        "wrote {} ({}, {})\n",
        escaped(&args.out.display().to_string()),
        counted(summary.poses, "pose"),
        match args.to {
            Target::Camloc => "camloc JSON",
            Target::Npy => "(N, 15, 2) float64 .npy",
        }
    ))?;
    out.flush()?;
    staged.commit()?;
    let code = summary.exit_code("converted");
    if empty > 0 {
        stderr_line!(
            "camloc: {empty} of {} poses have no landmark",
            summary.poses
        );
        return Ok(ExitCode::from(EXIT_ERROR));
    }
    Ok(code)
}
