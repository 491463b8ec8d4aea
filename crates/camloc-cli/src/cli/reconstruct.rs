//! `camloc reconstruct` and `camloc evaluate-reconstruction`.

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Mutex;

use camloc::keypoints::KeypointRecord;
use camloc::reconstruct::{BoneLengths, PoseBasis};
use camloc::store::Persist;
use camloc::{
    CameraLocalizer, CamlocError, DepthLifter, ModeKind, Pose3, PoseReconstruction,
    PoseReconstructor, default_basis,
};
use clap::builder::{PossibleValue, TypedValueParser};

use super::camera::IntrinsicsArgs;
use super::export::{self, Kept};
use super::heights;
use super::image_size_check;
use super::input::Inputs;
use super::output::NpyStage;
use super::reconstruct_output::{PoseMeta, pose_output, pose_svg};
use super::reconstruct_sequence;
use super::stream::{self, Done, Failed, Files};
use super::weak_scores;
use super::{
    CameraHeightArg, CameraHeightArgs, CliError, ForceArgs, FormatArgs, InputArgs, Out,
    ProgressArgs, lifter_for_model, load_dataset, load_model, progress, targets,
};
use crate::html::ViewFrame;

/// The camera modes `reconstruct` offers (the library's [`ModeKind`] without `oracle`, which
/// needs the true camera), with their help.
fn camera_modes() -> [PossibleValue; 3] {
    [
        PossibleValue::new("opt").help(
            "Procrustes camera re-estimated at every step (Ramakrishna et al.): no faster than \
             hybrid with the embedded model, less accurate (docs/RESULTS.md: 73.6 against 55.8 \
             mm on rescaled held-out people filmed by the rig); the mode without a localizer",
        ),
        PossibleValue::new("classified").help(
            "The pursuit's rotation fixed to the classified Table-1 camera (the paper's section \
             8.2); the final skeleton refinement, as in every mode, then adjusts the camera by \
             a few degrees. Best when the camera is one of the 12 viewpoints",
        ),
        PossibleValue::new("hybrid").help(
            "The localized viewpoint (the continuous direction, else the classified camera) \
             as the start, refined by Procrustes (with the embedded model's depth lifter, held \
             and refined with the skeleton): the lowest 3D error measured (docs/RESULTS.md); \
             the default",
        ),
    ]
}

/// The camera mode of a run: `--camera`, else `hybrid`, the lower 3D error in
/// docs/RESULTS.md (held-out CMU subjects, rescaled people, sequences; the paragraph after
/// docs/measured.md's table says why), and with the embedded lifter no slower than
/// `opt` (5,000 COCO poses on 2 cores: 1.20 s against 1.31 s).
fn camera_of(args: &Args) -> ModeKind {
    args.camera.unwrap_or(ModeKind::Hybrid)
}

/// Parses `--camera` (clap has already checked the name against [`camera_modes`]).
fn parse_camera(text: &str) -> Result<ModeKind, String> {
    ModeKind::ALL
        .into_iter()
        .find(|m| m.name() == text && *m != ModeKind::Oracle)
        .ok_or_else(|| format!("unknown camera mode {text:?}"))
}

/// Arguments of `camloc reconstruct`.
#[derive(clap::Args)]
pub struct Args {
    /// Model file for the classified camera [default: the embedded model].
    #[arg(long, value_name = "MODEL")]
    pub model: Option<PathBuf>,
    #[command(flatten)]
    pub height: CameraHeightArgs,
    /// Depth lifter file (`DepthLifter::save`'s, one lifter or with its lifter of pelvis and neck
    /// at the hip and shoulder midpoints).
    ///
    /// The refinement of `classified` and `hybrid` starts from the depths it predicts for the
    /// classified camera (docs/conventions.md section 6) [default: the embedded lifters of both
    /// placements, with any model of Table 1's cameras; none with a --model of other cameras].
    #[arg(long, value_name = "LIFTER", conflicts_with = "no_lifter")]
    pub lifter: Option<PathBuf>,
    /// Reconstruct without a depth lifter (the pose basis's pose starts the refinement, as
    /// before the lifter).
    #[arg(long)]
    pub no_lifter: bool,
    /// Pose basis file [default: the embedded basis].
    #[arg(long, value_name = "BASIS")]
    pub basis: Option<PathBuf>,
    #[command(flatten)]
    pub input: InputArgs,
    /// Which camera to reconstruct with [default: hybrid].
    #[arg(long, value_name = "MODE",
          value_parser = clap::builder::PossibleValuesParser::new(camera_modes())
              .try_map(|s| parse_camera(&s)))]
    pub camera: Option<ModeKind>,
    /// Keep up to N hypotheses per pose, N from 1 to 4.
    ///
    /// Where the 2D fits two poses about equally (the mirror in depth), the one within the learned
    /// joint-angle limits comes first; the others follow in the text output and under
    /// "alternatives" in JSON, each with its reprojection error and limit violation. Each solve has
    /// 2 (as found and depth-reflected); hybrid runs 2 solves, 1 with the lifter (its default),
    /// where the first is the lifted pose and the first of the other reflection its mirror in
    /// depth. The .npy and SVG outputs hold the first.
    #[arg(long, default_value_t = 1, value_name = "N",
          value_parser = clap::value_parser!(u8).range(1..=4))]
    pub hypotheses: u8,
    /// The person's bone lengths, metres (a JSON file: docs/cli.md).
    ///
    /// Every pose is reconstructed with exactly these. Without it the lengths are estimated from
    /// the 2D under a prior learned from motion capture (with --sequence, one set per person).
    #[arg(long, value_name = "FILE")]
    pub bone_lengths: Option<PathBuf>,
    /// The person's standing height, metres (soles to the top of the head).
    ///
    /// The estimated lengths keep their proportions and are scaled, with each pose and its camera,
    /// so that the legs (thigh plus shin) are 0.491 of it (Winter's proportions); the image is
    /// unchanged. With --sequence, and in the BVH, walks and jumps then have real distances (with
    /// --focal-px too). Every person of the input gets this height; the rule is an adult's (a young
    /// child comes out about 12% large: docs/cli.md). Without it the size is the prior's (legs of
    /// about 1.7 m people): one camera cannot tell a child near it from an adult farther away.
    #[arg(long, value_name = "METRES", conflicts_with = "bone_lengths",
          value_parser = parse_person_height, allow_hyphen_values = true)]
    pub person_height: Option<f64>,
    #[command(flatten)]
    pub intrinsics: IntrinsicsArgs,
    /// Treat the input as the frames of a video.
    ///
    /// Group the poses by person, order them by frame, and reconstruct each person's frames
    /// together: one set of bone lengths per person, the depths chosen consistently over time,
    /// temporal smoothness (a person whose pose jumps across the image, two people under one id, is
    /// warned of; another person's frames are left out, and legs or arms a detector swapped left
    /// for right for a few frames are swapped back: docs/cli.md, section Sequences). Output (per
    /// frame, by person then frame) as without it; the .npy rows stay in input order. Every pose is
    /// kept until its person is done (about 3 KB a pose), and a person's frames take about 12-15 KB
    /// each while they are solved together (20,000 frames: about 300 MB).
    #[arg(long, conflicts_with = "hypotheses")]
    pub sequence: bool,
    /// With --sequence: refuse an input of more than N poses.
    ///
    /// A person's frames take about 12-15 KB each while they are solved together (100,000 frames:
    /// 1.2 GB), hence a fifth of `localize --sequence`'s default.
    #[arg(
        long,
        value_name = "N",
        default_value_t = 200_000,
        requires = "sequence"
    )]
    pub sequence_max_poses: u64,
    /// With --sequence: write each person's bone lengths (given or estimated; the JSON form
    /// of --bone-lengths) to this file (several people: FILE-001.json, ...).
    #[arg(long, value_name = "OUT", requires = "sequence")]
    pub bone_lengths_out: Option<PathBuf>,
    #[command(flatten)]
    pub format: FormatArgs,
    /// Write the 3D poses as a (N, 15, 3) float64 .npy array in metres (camloc15 layout, the
    /// canonical frame).
    ///
    /// Row n is the n-th pose read, NaN where it could not be reconstructed.
    #[arg(long, value_name = "OUT")]
    pub npy: Option<PathBuf>,
    /// Draw input, reprojection and three views of the 3D pose as SVG to this file (several poses:
    /// FILE-001.svg, ...).
    ///
    /// All files are written at the end, or none.
    #[arg(long, value_name = "OUT")]
    pub svg: Option<PathBuf>,
    /// Write the 3D poses as a BVH animation (centimetres, y up; Blender: import with scale 0.01)
    /// for Blender, MotionBuilder and other 3D packages.
    ///
    /// One file per pose (FILE-001.bvh, ... when there are several), or with --sequence one per
    /// person. Bone lengths are the mean limb lengths of the file's poses (with --sequence: the
    /// person's shared lengths, given or estimated); each frame keeps its limb directions. A frame
    /// that could not be reconstructed turns from the frame before to the one after (holds at the
    /// ends), and with --sequence so does a frame number the person is missing from. With
    /// --sequence the person moves and turns as the camera saw them, for a camera that stood still
    /// (root motion, planted feet kept in place, on the floor; --bvh-in-place for a camera that
    /// moved); one pose stands on the floor, its pelvis above the origin.
    #[arg(long, value_name = "OUT")]
    pub bvh: Option<PathBuf>,
    /// With --sequence and --bvh: no root motion.
    ///
    /// Every frame's pelvis above the origin, facing one way, at the height root motion gives it
    /// (feet on the floor; for footage from a camera that panned or moved, whose motion would
    /// become the person's).
    #[arg(long, requires = "bvh", requires = "sequence")]
    pub bvh_in_place: bool,
    /// Write one self-contained interactive page (no network needed).
    ///
    /// Per pose the 2D input and reprojection, the 3D skeleton (drag to turn, wheel to zoom) and
    /// the camera sphere with each camera's probability and the continuous direction (from the
    /// localizer: --model), with a timeline to play and scrub. The page holds every pose (about 2.5
    /// KB each; at most 100,000 poses: split larger inputs).
    #[arg(long, value_name = "OUT")]
    pub html: Option<PathBuf>,
    /// Frames per second of the input video (only with --sequence, --bvh or --html: a usage error
    /// without) [default: 30].
    ///
    /// With --sequence the time scale of the smoothing over frames (its windows are 1/30 s and
    /// longer, as long in time at rates up to 1,000: give the video's rate), the BVH frame time
    /// and the page's play rate.
    #[arg(long, value_name = "FPS", value_parser = export::parse_fps, allow_hyphen_values = true)]
    pub fps: Option<f64>,
    #[command(flatten)]
    pub force: ForceArgs,
    #[command(flatten)]
    pub progress: ProgressArgs,
}

impl Args {
    /// The video's frame rate (`--fps`, 30 by default); a usage error when it is given
    /// without --sequence, --bvh or --html, which it changes nothing without.
    fn fps(&self) -> Result<f64, CliError> {
        export::fps_for(
            self.fps,
            self.sequence || self.bvh.is_some() || self.html.is_some(),
            "--sequence, --bvh or --html",
        )
    }
}

/// Arguments of `camloc evaluate-reconstruction`.
#[derive(clap::Args)]
pub struct EvalArgs {
    /// Labelled dataset with 3D poses (from `cargo xtask gen-dataset`).
    #[arg(long, value_name = "FILE")]
    pub dataset: PathBuf,
    /// Model file for the classified camera [default: the embedded model].
    #[arg(long, value_name = "MODEL")]
    pub model: Option<PathBuf>,
    #[command(flatten)]
    pub height: CameraHeightArgs,
    /// Pose basis file [default: the embedded basis].
    #[arg(long, value_name = "BASIS")]
    pub basis: Option<PathBuf>,
    /// Depth lifter of the last row, `reconstruct`'s own pipeline [default: the embedded
    /// lifter, with any model of Table 1's cameras; none with a --model of other cameras].
    #[arg(long, value_name = "LIFTER", conflicts_with = "no_lifter")]
    pub lifter: Option<PathBuf>,
    /// Measure `reconstruct --no-lifter` in the last row.
    #[arg(long)]
    pub no_lifter: bool,
    /// Print one JSON object (keys: samples; modes, one object per mode; pipeline, the last
    /// row's).
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub progress: ProgressArgs,
}

fn load_basis(path: Option<&std::path::Path>) -> Result<PoseBasis, CamlocError> {
    match path {
        Some(p) => Ok(PoseBasis::load(super::existing(p, "--basis")?)?),
        None => default_basis(),
    }
}

/// Any value as pretty JSON.
fn to_json<T: serde::Serialize>(value: &T) -> Result<String, CamlocError> {
    serde_json::to_string_pretty(value).map_err(|e| CamlocError::InvalidOption {
        name: "json",
        detail: e.to_string(),
    })
}

/// The depth lifter `--lifter` / `--no-lifter` ask for: none with `none`, the file `path`
/// (refused before any pose when its number of camera classes is not the model's: a lifter
/// file does not record its cameras, so only their number is checked), else the embedded one
/// for `model`'s `cameras` ([`lifter_for_model`]; a model of other cameras than Table 1's gets
/// none, said on standard error).
fn chosen_lifter(
    path: Option<&std::path::Path>,
    none: bool,
    model: Option<&std::path::Path>,
    cameras: &camloc::geometry::CameraSet,
) -> Result<Option<DepthLifter>, CamlocError> {
    match path {
        _ if none => Ok(None),
        Some(path) => {
            let lifter = DepthLifter::load(super::existing(path, "--lifter")?)?;
            if lifter.n_classes() != cameras.len() {
                return Err(CamlocError::InvalidOption {
                    name: "--lifter",
                    detail: format!(
                        "{} has {} camera classes, the model {} cameras",
                        camloc::store::quoted_path(path),
                        lifter.n_classes(),
                        cameras.len()
                    ),
                });
            }
            Ok(Some(lifter))
        }
        None => {
            let lifter = lifter_for_model(model, cameras)?;
            if lifter.is_none() {
                stderr_line!(
                    "camloc: warning: the embedded depth lifter serves Table 1's cameras, \
                     and this model's {} cameras are others: the 3D comes without it (as \
                     --no-lifter; give --lifter a lifter of these cameras)",
                    cameras.len()
                );
            }
            Ok(lifter)
        }
    }
}

/// The reconstructor `args` ask for: basis, camera mode, localizer, given bone lengths,
/// intrinsics and the video's frame rate `fps`.
fn reconstructor(
    args: &Args,
    localizer: CameraLocalizer,
    fps: f64,
) -> Result<PoseReconstructor, CliError> {
    let choice = camera_of(args);
    // Every mode has the localizer: `opt` does not localize complete poses, but it fills in
    // missing landmarks with the localized camera.
    let cameras = localizer.cameras().clone();
    let mut reconstructor = PoseReconstructor::new(load_basis(args.basis.as_deref())?)?
        .with_localizer(localizer)
        .with_mode(choice)?;
    if args.lifter.is_some() && choice == ModeKind::Opt {
        return Err(CamlocError::InvalidOption {
            name: "--lifter",
            detail: "the lifter needs the classified camera: use --camera classified or hybrid"
                .into(),
        }
        .into());
    }
    let lifter = chosen_lifter(
        args.lifter.as_deref(),
        args.no_lifter || choice == ModeKind::Opt,
        args.model.as_deref(),
        &cameras,
    )?;
    if let Some(lifter) = lifter {
        reconstructor = reconstructor.with_lifter(lifter);
    }
    if let Some(path) = &args.bone_lengths {
        let lengths = BoneLengths::read_json(path).map_err(|e| CamlocError::Reconstruct {
            context: "--bone-lengths".into(),
            source: e.into(),
        })?;
        reconstructor = reconstructor.with_bone_lengths(lengths);
    }
    if let Some(height_m) = args.person_height {
        reconstructor = reconstructor.with_person_height(height_m)?;
    }
    reconstructor = reconstructor.with_frame_rate(fps)?;
    if let Some(intrinsics) = args.intrinsics.intrinsics(args.input.image_size) {
        reconstructor = reconstructor.with_intrinsics(intrinsics)?;
    }
    Ok(reconstructor)
}

/// Runs `camloc reconstruct`.
pub fn run(args: &Args, out: &mut Out) -> Result<ExitCode, CliError> {
    let fps = args.fps()?;
    // The files as the writers name them: `--bvh OUT` writes OUT.bvh when OUT has no
    // extension; the numbered names of several files take .svg, .json and .bvh.
    let bvh = args.bvh.as_deref().map(export::bvh_base);
    let outputs = [
        (args.npy.as_deref(), "--npy", None),
        (args.svg.as_deref(), "--svg", Some("svg")),
        (
            args.bone_lengths_out.as_deref(),
            "--bone-lengths-out",
            Some("json"),
        ),
        (bvh.as_deref(), "--bvh", Some("bvh")),
        (args.html.as_deref(), "--html", None),
    ];
    targets::check(
        outputs,
        &[
            ("the input", Some(args.input.path())),
            ("--model", args.model.as_deref()),
            ("--lifter", args.lifter.as_deref()),
            ("--basis", args.basis.as_deref()),
            ("--bone-lengths", args.bone_lengths.as_deref()),
        ],
        args.force.force,
    )?;
    let choice = camera_of(args);
    // `opt` localizes no complete pose: the input's camera heights are not estimated for it.
    let camera_height = match (choice, args.height.camera_height) {
        (ModeKind::Opt, CameraHeightArg::FromInput) => CameraHeightArg::Any,
        (_, given) => given,
    };
    let height = CameraHeightArgs { camera_height };
    let intrinsics = args.intrinsics.intrinsics(args.input.image_size);
    if intrinsics.is_some_and(|k| k.principal_point.is_none()) {
        stderr_line!(
            "camloc: warning: --focal-px without --principal-point or --image-size: each pose's \
             principal point is the centre of its own landmarks' box, so its `perspective` \
             camera (translation_m) places it on the optical axis, not where it stands in the image"
        );
    }
    weak_scores::warn_of_weak_scores(&args.input);
    let (localizer, inputs, _) = heights::load_for_input(
        args.model.as_deref(),
        &height,
        &args.input,
        intrinsics,
        args.progress.quiet,
    )?;
    let reconstructor = reconstructor(args, localizer, fps)?;
    image_size_check::warn_of_image_scale(&args.input, Some(&reconstructor));
    // The page shows the cameras' probabilities: the reconstructor's localizer.
    let page_localizer = args.html.as_ref().and(reconstructor.localizer());
    let format = args.format.format();
    let finish = finish(args, fps, &inputs, page_localizer);
    // The localization a reconstruction used (classified, hybrid), else the page's own.
    let view = |record: &KeypointRecord, r: Option<&PoseReconstruction>, error: Option<String>| {
        page_localizer.map(|localizer| {
            let localization = r.and_then(|r| r.localization.clone()).or_else(|| {
                localizer
                    .localize_filled(&record.pose, reconstructor.reconstructor())
                    .ok()
            });
            let reconstruction = r.map(|r| &r.reconstruction);
            ViewFrame::new(record, localization.as_ref(), reconstruction, error)
        })
    };
    let bar = progress::counter(
        args.progress.quiet,
        inputs.len_hint(),
        "reconstruct",
        "poses",
    );
    if args.sequence {
        let options = reconstruct_sequence::Options {
            choice,
            svg: args.svg.as_deref(),
            npy: args.npy.as_deref(),
            lengths_out: args.bone_lengths_out.as_deref(),
            force: args.force.force,
            max_poses: args.sequence_max_poses,
            finish,
            view: &view,
            root_motion: !args.bvh_in_place,
        };
        return reconstruct_sequence::run(&reconstructor, inputs, out, format, options, &bar);
    }
    let files = Files::<Pose3, Kept> {
        svg: args.svg.clone(),
        rows: NpyStage::boxed(args.npy.as_deref())?,
        summary: None,
        finish,
        force: args.force.force,
    };
    let most = reconstructor.most_hypotheses();
    if usize::from(args.hypotheses) > most {
        stderr_line!(
            "camloc: warning: --hypotheses {}: this camera mode keeps at most {most} (one \
             solve, as found and reflected in depth); `--camera hybrid --no-lifter` solves \
             twice, for up to 4",
            args.hypotheses
        );
    }
    let keep = args.bvh.is_some() || args.html.is_some();
    let aim = reconstructor.given().intrinsics;
    let filled = Mutex::new((
        camloc::FilledCount::default(),
        camloc::LimitCount::default(),
    ));
    let summary = stream::run(inputs, out, format, files, &bar, aim, |record| {
        let result = reconstructor
            .reconstruct_hypotheses(&record.pose, usize::from(args.hypotheses))
            .map_err(|e| {
                let message = e.to_string();
                Failed {
                    keep: keep.then(|| {
                        Box::new(Kept {
                            key: (record.frame, record.person),
                            source: record.source.clone(),
                            pose: None,
                            view: view(record, None, Some(message.clone())),
                        })
                    }),
                    message,
                }
            })?;
        let meta = PoseMeta {
            id: &record.id,
            source: &record.source,
            frame: record.frame,
            person: record.person,
            left_out: false,
            swapped_sides: &[],
        };
        if let Ok(mut count) = filled.lock() {
            count.0.add(&result.imputed);
            count.1.add(result.reconstruction.outside_limits_rad);
        }
        let r = &result.reconstruction;
        Ok(Done {
            text: pose_output(format, &meta, choice, &result),
            svg: args
                .svg
                .as_ref()
                .map(|_| pose_svg(&record.pose, &record.id, choice, &result)),
            row: args.npy.as_ref().map(|_| r.pose),
            keep: keep.then(|| Kept {
                key: (record.frame, record.person),
                source: record.source.clone(),
                pose: Some(export::on_the_floor(r.pose)),
                view: view(record, Some(&result), None),
            }),
        })
    })?;
    let (filled, limits) = filled.into_inner().unwrap_or_default();
    if let Some(said) = filled.summary() {
        stderr_line!(
            "camloc: warning: {said}: their 3D is the pose basis's guess (`imputed` in JSON); \
             check them before using their joints; a video's short gaps are filled from the \
             frames around with --sequence"
        );
    }
    super::reconstruct_output::warn_of_limits(limits);
    Ok(summary.exit_code("reconstructed"))
}

/// The `--bvh` and `--html` files of a run at `fps` frames a second, made from what it kept
/// of every pose.
fn finish(
    args: &Args,
    fps: f64,
    inputs: &Inputs,
    page_localizer: Option<&CameraLocalizer>,
) -> Option<(Vec<PathBuf>, stream::Finish<Kept>)> {
    if args.bvh.is_none() && args.html.is_none() {
        return None;
    }
    // One camera cannot tell a size: a simulated animator's shortest actor came out 10% large,
    // and the distances walked with it, without a word.
    let sized = args.person_height.is_some() || args.bone_lengths.is_some();
    if args.bvh.is_some() && !sized && super::progress::shown(args.progress.quiet) {
        stderr_line!(
            "camloc: the BVH's people have the length prior's size (about 1.7 m tall{}): \
             --person-height or --bone-lengths gives a person's own",
            if args.sequence {
                ", their distances walked too"
            } else {
                ""
            }
        );
    }
    let mut paths = Vec::new();
    if let Some(bvh) = &args.bvh {
        let base = export::bvh_base(bvh);
        paths.extend(super::targets::numbered_targets(&base, "bvh"));
    }
    paths.extend(args.html.clone());
    let (bvh, html) = (args.bvh.clone(), args.html.clone());
    // With --sequence, whether the input is a folder (whose files may be videos of their own).
    let sequence = args.sequence.then(|| inputs.is_folder());
    let cameras = page_localizer.map(|l| l.cameras().clone());
    let title = format!(
        "camloc reconstruct{}: {}",
        if sequence.is_some() {
            " --sequence"
        } else {
            ""
        },
        inputs.name()
    );
    let make: stream::Finish<Kept> = Box::new(move |kept: Vec<Kept>, staged| {
        if let Some(bvh) = &bvh {
            export::bvh_files(bvh, &kept, sequence, fps, staged)?;
        }
        if let (Some(html), Some(cameras)) = (&html, &cameras) {
            let groups = export::kept_groups(&kept, sequence, false);
            let views: Vec<ViewFrame> = kept.into_iter().filter_map(|k| k.view).collect();
            let (path, page) = export::html_file(html, &title, cameras, &views, groups, fps);
            staged.add(&path, &page)?;
        }
        Ok(())
    });
    Some((paths, make))
}

/// Runs `camloc evaluate-reconstruction`.
pub fn run_evaluation(args: &EvalArgs, out: &mut Out) -> Result<ExitCode, CliError> {
    let basis = load_basis(args.basis.as_deref())?;
    let localizer = load_model(args.model.as_deref(), &args.height)?;
    let dataset = load_dataset(&args.dataset)?;
    let localizer = heights::for_dataset(localizer, &args.height, &dataset, args.progress.quiet);
    let lifter = chosen_lifter(
        args.lifter.as_deref(),
        args.no_lifter,
        args.model.as_deref(),
        localizer.cameras(),
    )?;
    // The last row is `reconstruct`'s default pipeline: `hybrid`, the lifter, bone lengths
    // estimated.
    let mut reconstructor = PoseReconstructor::new(basis)?
        .with_localizer(localizer)
        .with_mode(ModeKind::Hybrid)?;
    if let Some(lifter) = lifter {
        reconstructor = reconstructor.with_lifter(lifter);
    }
    let bar = progress::spinner(
        args.progress.quiet,
        &format!(
            "reconstructing {} samples with every camera mode and as `reconstruct` does",
            dataset.samples.len()
        ),
    );
    let report = reconstructor.evaluate_with_own_pipeline(&dataset);
    bar.finish_and_clear();
    let report = report?;
    // No complete sample (each has missing landmarks: `gen-dataset --drop-landmarks`), or
    // no row measured any: an error that says why, not a table of zeros or failures.
    if report.samples == 0 {
        return Err(CamlocError::Inconsistent {
            what: "dataset",
            detail: format!(
                "{}: none of its {} samples is complete (the 3D error is measured on samples \
                 with every landmark)",
                camloc::store::quoted_path(&args.dataset),
                dataset.samples.len()
            ),
        }
        .into());
    }
    let measured = report.modes.iter().map(|m| m.evaluated);
    if measured
        .chain(report.pipeline.iter().map(|p| p.report.evaluated))
        .all(|n| n == 0)
    {
        let first = dataset.samples.iter().find(|s| s.missing_mask == 0);
        let why = match first.map(|s| reconstructor.reconstruct(&s.landmarks.into())) {
            Some(Err(e)) => format!(" (the first: {e})"),
            Some(Ok(_)) => " (the first is reconstructed but cannot be compared with its true \
                            3D pose: are those in metres?)"
                .to_string(),
            None => String::new(),
        };
        return Err(CamlocError::Inconsistent {
            what: "dataset",
            detail: format!(
                "none of its {} complete samples could be reconstructed and measured in any \
                 camera mode{why}",
                report.samples
            ),
        }
        .into());
    }
    if args.json {
        out.write(&format!("{}\n", to_json(&report)?))?;
    } else {
        out.write(&report.to_string())?;
    }
    out.flush()?;
    Ok(ExitCode::SUCCESS)
}

/// `--person-height`: a standing height in metres ([`camloc::person_height_problem`]).
fn parse_person_height(text: &str) -> Result<f64, String> {
    let height_m: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("not a number of metres: {text:?}"))?;
    match camloc::person_height_problem(height_m) {
        Some(problem) => Err(problem),
        None => Ok(height_m),
    }
}
