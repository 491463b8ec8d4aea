//! Command-line interface: argument definitions and dispatch.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use camloc::dataset::Dataset;
use camloc::keypoints::{ImageSize, Invisible, KeypointError, KeypointFormat, Layout, ReadOptions};
use camloc::store::{Persist, StagedFiles, StoreError};
use camloc::{
    CameraHeight, CameraLocalizer, CamlocError, DepthLifter, Localization, PartialPose2,
    PoseReconstructor, default_basis,
};
use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use clap::{Parser, Subcommand, ValueEnum};

mod camera;
mod convert;
mod evaluate;
mod export;
mod heights;
mod image_size_check;
mod input;
mod localize;
mod localize_json;
mod localize_npz;
mod npz;
pub mod output;
mod outside_image;
mod person_solve;
mod progress;
mod reconstruct;
mod reconstruct_output;
mod reconstruct_sequence;
mod sequence;
mod stream;
mod targets;
mod train;
mod videos;
mod weak_scores;

pub use output::Out;

/// Exit code for a failure (bad input, unreadable or invalid file, failed pose).
pub const EXIT_ERROR: u8 = 1;

/// Exit code for a usage error (clap's, and [`CliError::Usage`]).
pub const EXIT_USAGE: u8 = 2;

const EXIT_CODES: &str = "Exit codes:
  0  success
  1  error: unreadable, malformed or invalid input, an input without any pose, an output
     that exists without --force, a failed write to standard output, or (localize,
     reconstruct, convert) at least one pose or file of a folder that could not be processed
  2  usage error: unknown subcommand or option, missing or invalid argument, two
     outputs at one file
  Ctrl-C, SIGTERM, SIGHUP or SIGQUIT: the unfinished output files are removed, then the run
     ends killed by the signal (a shell reports 128 + its number: 130 for Ctrl-C); a signal
     the run was started with ignored (nohup) stays ignored

An input with no pose at all (an empty pose list, a header-only CSV, an empty .npy array, a
folder without poses, a dataset without samples) is an error: \"no poses in INPUT\", exit 1.";

/// Camera localization from 2D human-pose landmarks, and 3D reconstruction.
///
/// Camloc tells which viewpoint on a sphere around a person (by default the 12 cameras of
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
    /// Localize the camera of 2D poses read from a keypoint file, a folder or standard input.
    ///
    /// Missing landmarks (null in camloc JSON, visible=0 in LSP CSV unless --lsp-invisible use,
    /// a score of 0 or below --min-score, NaN in .npy) are filled in from the embedded pose
    /// basis seen by camera hypotheses, the answer's probabilities tempered for each one filled
    /// in (docs/conventions.md section 6, "Filled-in poses"; a few hundred microseconds a pose).
    /// The pelvis and neck are derived from the hips and shoulders when missing. With fewer than
    /// 8 landmarks present a pose with a torso is localized from the descriptor values'
    /// training means (a guess, warned of), one without is reported as an error while the
    /// others are still localized.
    ///
    /// Poses are read, localized (in parallel) and written in batches, so memory does not grow
    /// with the input; use --jsonl for one JSON object per line, --npz for NumPy arrays.
    #[command(after_help = EXIT_CODES)]
    Localize(localize::Args),
    /// Reconstruct the 3D poses of a keypoint input with a pose basis and projected matching
    /// pursuit, using the camera of the localized viewpoint (hybrid, default), the classified
    /// one (classified) or the Procrustes camera (opt).
    ///
    /// Poses are read, reconstructed (in parallel) and written in batches. Missing landmarks
    /// are filled in from the pose basis seen by the localized camera and named in the output
    /// (`imputed`), after the pose is localized with them filled in as `localize` does. A pose
    /// with missing landmarks is refused with fewer than 8 present (most of its 3D would be the
    /// basis's guess; with --sequence, counted after short gaps are filled in from the frames
    /// around them).
    #[command(after_help = EXIT_CODES)]
    Reconstruct(reconstruct::Args),
    /// Measure 3D error (PA-MPJPE: mm, after similarity alignment) and projection error on a
    /// labelled dataset made by `cargo xtask gen-dataset`.
    ///
    /// One row for each of the pursuit's camera modes alone (opt, classified, oracle with the true
    /// rotation, hybrid; no depth lifter, the template's bone lengths), and a last row for what
    /// `reconstruct` gives by default (hybrid with the depth lifter and the bone lengths
    /// estimated).
    #[command(after_help = EXIT_CODES)]
    EvaluateReconstruction(reconstruct::EvalArgs),
    /// Write any readable keypoint input in camloc's own formats.
    ///
    /// Camloc JSON or a (N, 15, 2) float64 .npy array (NaN, NaN for a missing landmark).
    #[command(after_help = EXIT_CODES)]
    Convert(convert::Args),
}

/// Everything that ends a command with exit code 1.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// A library error (input, model, dataset, output file).
    #[error(transparent)]
    Camloc(#[from] CamlocError),
    /// Standard output could not be written (other than a closed pipe).
    #[error("cannot write to standard output: {0}")]
    Stdout(#[source] std::io::Error),
    /// The arguments cannot work together (exit code 2, as clap's usage errors), e.g. two
    /// outputs at one file.
    #[error("{0}")]
    Usage(String),
    /// `localize --sequence` met more poses than it may keep.
    #[error(
        "more than {0} poses for --sequence, which keeps every pose until the end (localize: \
         about 1.3 KB a pose; reconstruct: 12-15 KB a frame while a person's frames are \
         solved): run parts of the input by \
         person or by time apart (camloc JSON keeps the `frame` numbers), or raise \
         --sequence-max-poses if the memory is there (docs/cli.md, Sequences)"
    )]
    TooManyPoses(u64),
    /// `--bvh` or `--html` met more poses than they may keep.
    #[error(
        "more than {0} poses for --bvh or --html, which keep every pose until the end: split \
         the input"
    )]
    TooManyKept(u64),
    /// A file made at the end of a run (`--bvh`) could not be made.
    #[error("{0}")]
    Export(String),
    /// The input, one file or standard input, could not be read to its end (the error was
    /// reported): no output file is written.
    #[error(
        "{} could not be read to its end (the error above); no output file was written",
        camloc::store::quoted_path(Path::new(.0))
    )]
    NotReadToEnd(String),
    /// The input holds no pose at all (the rule for empty inputs, see `camloc --help`).
    #[error("no poses in {}{}", camloc::store::quoted_path(Path::new(.0)), .1)]
    NoPoses(String, &'static str),
    /// A file with one of the numbered names of an output exists and overwriting was not
    /// requested (checked before any work: how many files a run writes is known at its end).
    #[error(
        "{}: already exists, a numbered file of {} (several poses write OUT-001, OUT-002, ...; \
         their count is known only at the end): pass --force to overwrite it, or remove it",
        camloc::store::quoted_path(.path),
        camloc::store::quoted_path(.out)
    )]
    NumberedExists {
        /// The existing numbered file.
        path: PathBuf,
        /// The output it is a numbered file of.
        out: PathBuf,
    },
    /// Several of the files a run would write exist and overwriting was not requested
    /// (checked before any work; the first [`SEVERAL_EXIST_NAMED`] are named).
    #[error("{}: already exist (pass --force to overwrite them, or remove them)", several_named(.0))]
    SeveralExist(Vec<PathBuf>),
}

/// How many existing files [`CliError::SeveralExist`] names.
pub const SEVERAL_EXIST_NAMED: usize = 10;

/// `paths`, quoted and comma-separated, the first [`SEVERAL_EXIST_NAMED`] of them and how many
/// more.
fn several_named(paths: &[PathBuf]) -> String {
    let mut named: Vec<String> = paths
        .iter()
        .take(SEVERAL_EXIST_NAMED)
        .map(|p| camloc::store::quoted_path(p))
        .collect();
    if paths.len() > SEVERAL_EXIST_NAMED {
        named.push(format!("and {} more", paths.len() - SEVERAL_EXIST_NAMED));
    }
    named.join(", ")
}

impl From<KeypointError> for CliError {
    fn from(e: KeypointError) -> Self {
        CliError::Camloc(e.into())
    }
}

impl From<StoreError> for CliError {
    fn from(e: StoreError) -> Self {
        CliError::Camloc(e.into())
    }
}

/// Runs the parsed command line, writing what goes to standard output to `out`.
pub fn run(cli: Cli, out: &mut Out) -> Result<ExitCode, CliError> {
    match cli.command {
        Command::Train(args) => train::run(&args, out),
        Command::Evaluate(args) => evaluate::run(&args, out),
        Command::Localize(args) => localize::run(&args, out),
        Command::Reconstruct(args) => reconstruct::run(&args, out),
        Command::EvaluateReconstruction(args) => reconstruct::run_evaluation(&args, out),
        Command::Convert(args) => convert::run(&args, out),
    }
}

/// How LSP joints marked visible=0 are read.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum InvisibleArg {
    /// As missing landmarks (filled in from the pose basis, docs/conventions.md section 6).
    Missing,
    /// With their annotated coordinates; a coordinate <= 0 is a placeholder of a joint that was
    /// not annotated, which stays missing (docs/keypoints.md).
    Use,
}

/// `--format` values with their help.
fn format_values() -> Vec<PossibleValue> {
    KeypointFormat::ALL
        .into_iter()
        .map(|f| {
            PossibleValue::new(f.name()).help(match f {
                KeypointFormat::Camloc => "camloc's 15-landmark JSON (docs/keypoints.md)",
                KeypointFormat::Lsp => "LSP-14 CSV: image,joint,x,y,visible",
                KeypointFormat::Coco => "COCO-17 JSON (dataset file or results list)",
                KeypointFormat::OpenPose => {
                    "OpenPose JSON, one file per frame (BODY_25 or COCO-18)"
                }
                KeypointFormat::MmPose => "MMPose predictions (keypoints + keypoint_scores)",
                KeypointFormat::MediaPipe => {
                    "MediaPipe Pose 33 normalised landmarks (needs --image-size)"
                }
                KeypointFormat::Npy => "NumPy array (N, J, 2) or (N, J, 3) in a --layout",
                KeypointFormat::Mpii => "MPII annotations JSON (image, joints, joints_vis)",
                KeypointFormat::Yolo => {
                    "Ultralytics YOLO pose .txt, one file per frame (COCO-17; needs --image-size)"
                }
            })
        })
        .collect()
}

/// `--layout` values with their help.
fn layout_values() -> Vec<PossibleValue> {
    Layout::ALL
        .into_iter()
        .map(|l| {
            PossibleValue::new(l.name()).help(match l {
                Layout::Coco17 => "COCO-17 (17 joints)",
                Layout::H36m17 => "Human3.6M (17 joints)",
                Layout::Body25 => "OpenPose BODY_25 (25 joints)",
                Layout::Mpii16 => "MPII (16 joints)",
                Layout::Lsp14 => "LSP (14 joints, joints.mat order)",
                Layout::Camloc15 => "camloc's 15 landmarks, pelvis first",
                Layout::Mediapipe33 => {
                    "MediaPipe Pose (33 landmarks; pixels: the normalised x, y times the image's \
                     width and height)"
                }
            })
        })
        .collect()
}

/// Parses `--min-score`: a finite number >= 0.
fn parse_min_score(text: &str) -> Result<f64, String> {
    text.trim()
        .parse::<f64>()
        .ok()
        .filter(|s| s.is_finite() && *s >= 0.0)
        .ok_or_else(|| format!("not a finite number >= 0: {text:?}"))
}

/// Where the keypoints are: `--input PATH` or the command's one argument (one of them).
#[derive(clap::Args)]
#[group(required = true, multiple = false)]
pub struct KeypointsPath {
    /// Keypoints: a file, a folder (its .json, .csv and .npy files, or YOLO's .txt files
    /// when it has none of those, in natural order; a bad file is reported and the others are
    /// read, exit 1 at the end) or - for standard input.
    #[arg(long = "input", value_name = "FILE|DIR|-")]
    input_flag: Option<PathBuf>,
    /// The keypoints as the command's one argument, the same as --input (`camloc COMMAND
    /// poses.json`).
    #[arg(value_name = "INPUT")]
    input_path: Option<PathBuf>,
}

/// Input options shared by the commands that read keypoints.
#[derive(clap::Args)]
pub struct InputArgs {
    #[command(flatten)]
    keypoints: KeypointsPath,
    /// Input format, any case [default: from the extension and content, for each file].
    #[arg(long, value_name = "NAME", ignore_case = true,
          value_parser = PossibleValuesParser::new(format_values())
              .try_map(|s| s.parse::<KeypointFormat>()))]
    pub format: Option<KeypointFormat>,
    /// Joint layout of .npy arrays (and MMPose keypoints) [default: from the joint count; 17 joints
    /// need it named in .npy arrays, MMPose's are coco17].
    ///
    /// A 17-joint pose whose first five joints are not the layout's (COCO-17's face, Human3.6M's
    /// pelvis and legs) is refused with the likely layout. Any case, as in Python.
    #[arg(long, value_name = "NAME", ignore_case = true,
          value_parser = PossibleValuesParser::new(layout_values())
              .try_map(|s| s.parse::<Layout>()))]
    pub layout: Option<Layout>,
    /// Joints whose score is below S are missing (COCO, OpenPose, MMPose, MediaPipe, YOLO, (N, J,
    /// 3) .npy).
    ///
    /// A score of 0 is always missing. A finite number >= 0. For a detector's output try 0.3:
    /// its weak joints are often misplaced, and missing ones are filled in (with --sequence from
    /// the frames around a short gap); a simulated user's flickering COCO-17 detector came out
    /// 6-13 mm closer (PA-MPJPE) with a third of the jitter at 0.3 than at 0. Single frames of
    /// seated people whose legs a desk hides came out worse (the legs filled in standing: 110
    /// against 78 mm in another's office views; with --sequence 62 against 66). At 0, `localize`
    /// and `reconstruct` warn when 1% or more of the landmarks of a file's (or folder's) first
    /// 2,000 poses score below 0.3 (below 30 for scores of 0-100; not for standard input).
    #[arg(long, value_name = "S", default_value_t = 0.0, value_parser = parse_min_score,
          allow_hyphen_values = true)]
    pub min_score: f64,
    /// Image size in pixels that normalised coordinates are scaled by (MediaPipe, YOLO), e.g.
    /// 1920,1080 (or 1920x1080).
    ///
    /// Width first: a portrait phone video is 1080,1920 (`localize` and `reconstruct` warn when
    /// a file's or folder's first 60 poses, 10 or more solved, fit a body better the
    /// other way round; not for standard input).
    ///
    /// In `localize` and `reconstruct`, `--focal-px` also takes its centre as the principal point
    /// (a warning says when half the pixel poses or more reach past the image and all fit it
    /// turned).
    #[arg(long, value_name = "W,H", value_parser = |s: &str| s.parse::<ImageSize>(),
          allow_hyphen_values = true)]
    pub image_size: Option<ImageSize>,
    /// With a folder --input: read its sub-folders too.
    #[arg(long)]
    pub recursive: bool,
    /// LSP joints with visible=0: treat as missing, or use their coordinates.
    #[arg(long, value_enum, default_value = "missing")]
    pub lsp_invisible: InvisibleArg,
    /// Refuse a text input (JSON, CSV) longer than N bytes (1 GiB by default; .npy arrays are not
    /// limited).
    ///
    /// The JSON readers stream what they read, so a larger limit costs them no memory (a 1.15 GB
    /// camloc JSON file of 2.3 million poses went through `localize` in 46 MB); CSV and YOLO
    /// text is held whole.
    #[arg(long, value_name = "N", default_value_t = ReadOptions::DEFAULT_MAX_BYTES,
          value_parser = clap::value_parser!(u64).range(1..))]
    pub max_input_bytes: u64,
}

impl InputArgs {
    /// The keypoints' path (`-` for standard input), given as --input or as the argument.
    pub fn path(&self) -> &Path {
        // clap requires exactly one of the two.
        self.keypoints
            .input_flag
            .as_deref()
            .or(self.keypoints.input_path.as_deref())
            .unwrap_or(Path::new("-"))
    }

    /// Whether the keypoints come from standard input (the path `-`), which is read once:
    /// the checks that read an input's first poses again leave it alone.
    pub fn is_standard_input(&self) -> bool {
        self.path() == Path::new("-")
    }

    /// The reader options these arguments ask for.
    pub fn options(&self) -> ReadOptions {
        let mut options = ReadOptions {
            min_score: self.min_score,
            image_size: self.image_size,
            layout: self.layout,
            max_bytes: self.max_input_bytes,
            ..ReadOptions::default()
        };
        options.lsp.invisible = match self.lsp_invisible {
            InvisibleArg::Missing => Invisible::Missing,
            InvisibleArg::Use => Invisible::Use,
        };
        options
    }
}

/// `--json` and `--jsonl` of the commands that stream one result per pose.
#[derive(clap::Args)]
pub struct FormatArgs {
    /// Print one JSON array with one object per pose (streamed: written as poses are done).
    #[arg(long, conflicts_with = "jsonl")]
    pub json: bool,
    /// Print one JSON object per line, each as soon as its pose is done (for large inputs and
    /// streams: from standard input or a named pipe with `--camera-height any`, poses are
    /// answered as they come; without `--format`, once the input's first 64 KiB are read).
    #[arg(long)]
    pub jsonl: bool,
}

impl FormatArgs {
    /// The output format the flags ask for.
    pub fn format(&self) -> stream::Format {
        stream::Format::from_flags(self.json, self.jsonl)
    }
}

/// `--force` of the commands that write output files.
#[derive(clap::Args)]
pub struct ForceArgs {
    /// Replace existing output files.
    ///
    /// A symbolic link at an output path is replaced by the new file (never written through; its
    /// target is untouched); a directory, device or FIFO is refused even with --force.
    #[arg(long)]
    pub force: bool,
}

/// Options of the commands that show progress.
#[derive(clap::Args)]
pub struct ProgressArgs {
    /// No progress bar on standard error, nor (commands that localize) the camera heights
    /// `--camera-height from-input` estimated, nor (`reconstruct --bvh`) the note that the
    /// people have the length prior's size (all shown only when standard error is a terminal).
    #[arg(long, short)]
    pub quiet: bool,
}

/// Loads a labelled dataset; one without samples is [`CliError::NoPoses`] (the empty-input
/// rule).
pub fn load_dataset(path: &Path) -> Result<Dataset, CliError> {
    let dataset = Dataset::load(path).map_err(CamlocError::from)?;
    if dataset.samples.is_empty() {
        return Err(CliError::NoPoses(path.display().to_string(), ""));
    }
    Ok(dataset)
}

/// `--camera-height`: what is known of the camera's height before seeing the poses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum CameraHeightArg {
    /// The shares of the three heights among the input's cameras and its middle cameras' mean
    /// elevation, estimated from its first 20,000 poses before any is localized, starting from
    /// a camera at eye level: each pose's answer then depends on the others.
    FromInput,
    /// Nothing known: the model's own priors; each pose is localized on its own.
    Any,
    /// A tripod, handheld phone or studio camera at about a standing person's eye level, a
    /// few metres away: a middle-ring camera is 8 times as likely a priori.
    EyeLevel,
}

/// The `--camera-height` option of the commands that localize.
#[derive(clap::Args)]
pub struct CameraHeightArgs {
    /// What is known of the camera's height, as a prior over the cameras that reweighs the model's
    /// probabilities (docs/conventions.md section 5, "What the caller knows of the camera").
    ///
    /// `from-input` first reads the input's first 20,000 poses and estimates how its cameras divide
    /// among the three heights (a video or a studio's views: mostly one) and how high its middle
    /// cameras stand, then localizes every pose under those shares, each middle-ring viewpoint
    /// regressing toward that elevation, not the training's (give one camera's footage per
    /// input; a photo or a short clip: about as `eye-level`; `reconstruct --camera opt`: no
    /// estimate); `any` localizes each pose on its own; `eye-level` suits studios, tripods and
    /// phones: on views of such cameras it turns more of the level mistakes near the middle
    /// ring's edge into right answers, and it costs views from far above or below.
    #[arg(long, value_enum, default_value = "from-input", value_name = "HEIGHT")]
    pub camera_height: CameraHeightArg,
}

impl CameraHeightArgs {
    /// The library's prior for the option before the input is read (`from-input`: the
    /// model's own, until [`heights::for_input`] estimates the input's).
    pub fn height(&self) -> CameraHeight {
        match self.camera_height {
            CameraHeightArg::Any | CameraHeightArg::FromInput => CameraHeight::Any,
            CameraHeightArg::EyeLevel => CameraHeight::EyeLevel,
        }
    }
}

/// `path`, which `option` names, when it exists; else an error that names the option (the
/// file system's own message names only the path).
pub fn existing<'a>(path: &'a Path, option: &'static str) -> Result<&'a Path, CamlocError> {
    if path.exists() {
        Ok(path)
    } else {
        Err(CamlocError::InvalidOption {
            name: option,
            detail: format!("{} does not exist", camloc::store::quoted_path(path)),
        })
    }
}

/// The model at `path`, or the embedded default, localizing under the prior `height`.
pub fn load_model(
    path: Option<&Path>,
    height: &CameraHeightArgs,
) -> Result<CameraLocalizer, CamlocError> {
    let localizer = match path {
        Some(p) => CameraLocalizer::load(existing(p, "--model")?)?,
        None => CameraLocalizer::default_model()?,
    };
    // A prior over the rings changes nothing when the model's cameras are all in one ring.
    let middle = localizer
        .cameras()
        .viewpoints()
        .iter()
        .filter(|v| v.level == camloc::Level::Middle)
        .count();
    if height.height() != CameraHeight::Any && (middle == 0 || middle == localizer.cameras().len())
    {
        stderr_line!(
            "camloc: warning: --camera-height {} changes nothing for this model: {} of its \
             cameras are in the middle ring",
            height.height(),
            if middle == 0 { "none" } else { "all" }
        );
    }
    Ok(localizer.with_camera_height(height.height()))
}

/// The depth lifter that goes with the model `path` names, whose cameras are `cameras`: the
/// embedded lifter with the embedded model (`None`) and with any model of Table 1's cameras
/// ([`DepthLifter::serves`]; as Python's `reconstruct` does with such a localizer), none with
/// a model of other cameras.
pub fn lifter_for_model(
    path: Option<&Path>,
    cameras: &camloc::geometry::CameraSet,
) -> Result<Option<DepthLifter>, CamlocError> {
    (path.is_none() || DepthLifter::serves(cameras))
        .then(DepthLifter::default_lifter)
        .transpose()
}

/// The embedded basis with the default pursuit settings: it fills in the torso of a pose that
/// lacks one for localization ([`Locator`]) and reconstructs the `--html` pages'
/// skeletons. `None` when this build embedded no basis.
pub fn embedded_basis() -> Option<PoseReconstructor> {
    default_basis().and_then(PoseReconstructor::new).ok()
}

/// A camera localizer and the basis that fills in the torso of a pose that lacks one
/// ([`CameraLocalizer::localize_filled`]; without a basis such poses are refused).
#[derive(Clone, Copy)]
pub struct Locator<'a> {
    /// The camera localizer.
    pub localizer: &'a CameraLocalizer,
    /// The basis that fills in missing torsos, if the build has one.
    pub filler: Option<&'a PoseReconstructor>,
}

impl Locator<'_> {
    /// The localization of `pose`.
    pub fn localize(&self, pose: &PartialPose2) -> Result<Localization, CamlocError> {
        match self.filler {
            Some(filler) => self.localizer.localize_filled(pose, filler.reconstructor()),
            None => self.localizer.localize_partial(pose),
        }
    }
}

/// Path of the SVG for pose `index` of `count`: `out` itself for one pose, else
/// `out` with `-NNN` before the extension, the number padded with zeros to three digits or
/// to as many as `count` has (`-0001` ... `-2000`), so that the names sort in number order.
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
    let width = count.to_string().len().max(3);
    out.with_file_name(format!("{stem}-{:0width$}.{ext}", index + 1))
}

/// Gives the files of `out` staged as they were computed (`drawn`: the pose's index and the
/// staged file's number, named by [`numbered_path`] for 2 poses, as the count is known only
/// at the end) their names for `count` poses: `out` itself for one pose, wider numbers past
/// 999.
pub fn rename_numbered(
    staged: &mut StagedFiles,
    out: &Path,
    drawn: &[(usize, usize)],
    count: usize,
) {
    if count == 1 {
        if let Some(&(0, at)) = drawn.first() {
            staged.retarget(at, out);
        }
    } else if count > 999 {
        for &(index, at) in drawn {
            staged.retarget(at, &numbered_path(out, index, count));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbered_names_sort_in_number_order() {
        let out = Path::new("d/v.svg");
        assert_eq!(numbered_path(out, 0, 1), out);
        assert_eq!(numbered_path(out, 0, 2), Path::new("d/v-001.svg"));
        assert_eq!(numbered_path(out, 998, 999), Path::new("d/v-999.svg"));
        assert_eq!(numbered_path(out, 0, 1000), Path::new("d/v-0001.svg"));
        assert_eq!(numbered_path(out, 1999, 2000), Path::new("d/v-2000.svg"));
        let names: Vec<PathBuf> = (0..1200).map(|i| numbered_path(out, i, 1200)).collect();
        assert!(names.windows(2).all(|w| w[0] < w[1]));
        assert_eq!(numbered_path(Path::new("v"), 2, 3), Path::new("v-003.svg"));
    }
}
