//! Command-line interface: argument definitions and dispatch.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use camloc::keypoints::{Invisible, KeypointFormat, KeypointRecord, ReadOptions, read_keypoints};
use camloc::store::Persist;
use camloc::{CameraLocalizer, CamlocError};
use clap::{Parser, Subcommand, ValueEnum};

mod evaluate;
mod localize;
mod reconstruct;
mod train;

/// Exit code for a failure (bad input, unreadable or invalid file, failed pose).
pub const EXIT_ERROR: u8 = 1;

const EXIT_CODES: &str = "Exit codes:
  0  success
  1  error: unreadable, malformed or invalid input, an output that exists without --force,
     or (localize, reconstruct) at least one pose that could not be processed
  2  usage error: unknown subcommand or option, missing or invalid argument";

/// Camera localization from 2D human-pose landmarks, and 3D reconstruction.
///
/// camloc tells which viewpoint on a sphere around a person (by default the 12 cameras of
/// Table 1: lower/middle/upper x front/left/back/right) a 2D pose was seen from.
#[derive(Parser)]
#[command(name = "camloc", version, about, long_about, after_help = EXIT_CODES)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Train a camera localizer on a dataset made by `cargo xtask gen-dataset`.
    #[command(after_help = EXIT_CODES)]
    Train(train::Args),
    /// Measure a model's accuracy on a labelled dataset.
    #[command(after_help = EXIT_CODES)]
    Evaluate(evaluate::Args),
    /// Localize the camera of 2D poses read from a keypoint file.
    ///
    /// Missing landmarks: null in camloc JSON, visible=0 in LSP CSV (unless --lsp-invisible
    /// use), confidence 0 in COCO; their descriptor values are imputed. The pelvis and neck are
    /// derived from the hips and shoulders when missing; a pose whose torso cannot be derived
    /// is reported as an error and the others are still localized.
    #[command(after_help = EXIT_CODES)]
    Localize(localize::Args),
    /// Reconstruct the 3D poses of a keypoint file with a PCA basis and projected matching
    /// pursuit, using the Procrustes camera (opt, default) or the classified one (classified, hybrid).
    #[command(after_help = EXIT_CODES)]
    Reconstruct(reconstruct::Args),
    /// Measure 3D error (mm, after similarity alignment) and projection error of every
    /// camera mode on a labelled dataset.
    #[command(after_help = EXIT_CODES)]
    EvaluateReconstruction(reconstruct::EvalArgs),
}

/// Runs the parsed command line, appending what goes to standard output to `out`.
pub fn run(cli: Cli, out: &mut String) -> Result<ExitCode, CamlocError> {
    match cli.command {
        Command::Train(args) => train::run(&args, out),
        Command::Evaluate(args) => evaluate::run(&args, out),
        Command::Localize(args) => localize::run(&args, out),
        Command::Reconstruct(args) => reconstruct::run(&args, out),
        Command::EvaluateReconstruction(args) => reconstruct::run_evaluation(&args, out),
    }
}

/// Input keypoint formats on the command line.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum FormatArg {
    /// camloc's 15-landmark JSON (docs/keypoints.md).
    Camloc,
    /// LSP-14 CSV: image,joint,x,y,visible.
    Lsp,
    /// COCO-17 JSON (dataset file or results list).
    Coco,
}

/// How LSP joints marked visible=0 are read.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum InvisibleArg {
    /// As missing landmarks (their descriptor values are imputed).
    Missing,
    /// With their annotated coordinates.
    Use,
}

/// Input options shared by the commands that read keypoints.
#[derive(clap::Args)]
pub struct InputArgs {
    /// Keypoint file: camloc JSON (.json), LSP-14 CSV (.csv) or COCO-17 JSON.
    #[arg(long, value_name = "FILE")]
    pub input: PathBuf,
    /// Input format [default: from the extension and content].
    #[arg(long, value_enum)]
    pub format: Option<FormatArg>,
    /// LSP joints with visible=0: treat as missing, or use their coordinates.
    #[arg(long, value_enum, default_value = "missing")]
    pub lsp_invisible: InvisibleArg,
}

impl InputArgs {
    /// Reads the keypoint records.
    pub fn read(&self) -> Result<Vec<KeypointRecord>, CamlocError> {
        let format = self.format.map(|f| match f {
            FormatArg::Camloc => KeypointFormat::Camloc,
            FormatArg::Lsp => KeypointFormat::Lsp,
            FormatArg::Coco => KeypointFormat::Coco,
        });
        let mut options = ReadOptions::default();
        options.lsp.invisible = match self.lsp_invisible {
            InvisibleArg::Missing => Invisible::Missing,
            InvisibleArg::Use => Invisible::Use,
        };
        Ok(read_keypoints(&self.input, format, &options)?)
    }
}

/// The model at `path`, or the embedded default.
pub fn load_model(path: Option<&Path>) -> Result<CameraLocalizer, CamlocError> {
    match path {
        Some(p) => Ok(CameraLocalizer::load(p)?),
        None => CameraLocalizer::default_model(),
    }
}

/// Path of the SVG for pose `index` of `count`: `out` itself for one pose, else
/// `out` with `-NNN` before the extension.
pub fn numbered_path(out: &Path, index: usize, count: usize) -> PathBuf {
    if count <= 1 {
        return out.to_path_buf();
    }
    let stem = out
        .file_stem()
        .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
    let ext = out
        .extension()
        .map_or_else(|| "svg".to_string(), |e| e.to_string_lossy().into_owned());
    out.with_file_name(format!("{stem}-{:03}.{ext}", index + 1))
}
