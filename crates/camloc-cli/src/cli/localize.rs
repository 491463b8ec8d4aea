//! `camloc localize`.

use std::fmt::Write;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use camloc::keypoints::KeypointRecord;
use camloc::reconstruct::FrameRate;
use camloc::{CameraLocalizer, CamlocError, Localization, ModeKind};

use camloc::store::escaped;

use crate::html::ViewFrame;
use crate::svg;

use super::camera::IntrinsicsArgs;
use super::export;
use super::heights;
use super::image_size_check;
use super::localize_json::LocalizationJson;
use super::localize_npz::LocalizationArrays;
use super::sequence;
use super::stream::{self, Done, Failed, Files, SummaryDrawing};
use super::weak_scores;
use super::{
    CameraHeightArgs, CliError, ForceArgs, FormatArgs, InputArgs, Locator, Out, ProgressArgs,
    embedded_basis, lifter_for_model, progress, targets,
};

/// Arguments of `camloc localize`.
#[derive(clap::Args)]
pub struct Args {
    /// Model file [default: the model embedded in this binary].
    #[arg(long, value_name = "MODEL")]
    pub model: Option<PathBuf>,
    #[command(flatten)]
    pub height: CameraHeightArgs,
    #[command(flatten)]
    pub input: InputArgs,
    #[command(flatten)]
    pub intrinsics: IntrinsicsArgs,
    #[command(flatten)]
    pub format: FormatArgs,
    /// Draw each pose and its predicted viewpoint as SVG to this file (several poses: FILE-001.svg,
    /// FILE-002.svg, ...).
    ///
    /// With --sequence, one timeline per person instead. All files are written at the end, or none.
    #[arg(long, value_name = "OUT")]
    pub svg: Option<PathBuf>,
    /// Treat the input as the frames of a video.
    ///
    /// Group the poses by person, order them by frame and smooth the viewpoint over time (a hidden
    /// Markov model over the cameras, the mean direction over 7 frames). Output (per frame, by
    /// person then frame) has the raw and the smoothed camera and viewpoint; a person whose pose
    /// jumps across the image (two people under one id) is warned of, and legs or arms a detector
    /// swapped left for right for a few frames are swapped back (docs/cli.md, section Sequences).
    /// Every frame's 12 probabilities and landmarks are kept until the end.
    #[arg(long)]
    pub sequence: bool,
    /// With --sequence: refuse an input of more than N poses (each is kept until the end:
    /// about 1.3 KB a pose, docs/cli.md).
    #[arg(
        long,
        value_name = "N",
        default_value_t = 1_000_000,
        requires = "sequence"
    )]
    pub sequence_max_poses: u64,
    /// Draw where the cameras of the whole input fall (the cameras as an azimuth by
    /// elevation grid, shaded by the share of poses) as SVG to this file.
    #[arg(long, value_name = "OUT")]
    pub summary_svg: Option<PathBuf>,
    /// Write one self-contained interactive page (no network needed).
    ///
    /// Per pose the 2D input, the camera sphere with each camera's probability and the continuous
    /// direction with its uncertainty, and the 3D skeleton `camloc reconstruct` gives with the same
    /// model (drag to turn, wheel to zoom) with its reprojection; a timeline to play and scrub
    /// (with --sequence, per person, with the smoothed camera). It reconstructs every pose, so the
    /// run takes about as long as `camloc reconstruct` (over 100 times a plain localize), and the
    /// page holds every pose (about 2.5 KB each; at most 100,000 poses: split larger inputs).
    #[arg(long, value_name = "OUT")]
    pub html: Option<PathBuf>,
    /// Frames per second of the input video (only with --sequence or --html: a usage error
    /// without) [default: 30].
    ///
    /// With --sequence the time scale of the smoothing over frames (7 frames at 30 frames a second,
    /// as long in time at faster rates up to 1,000: give the video's rate), and the page's play
    /// rate.
    #[arg(long, value_name = "FPS", value_parser = export::parse_fps, allow_hyphen_values = true)]
    pub fps: Option<f64>,
    /// Write the results as NumPy arrays to this .npz archive (numpy.load reads it without pickle),
    /// row n for the n-th pose read.
    ///
    /// Label, folded_label, probabilities, azimuth_deg, elevation_deg, uncertainty_deg, failed,
    /// missing, derived, frame, person, the ids as id_utf8 and id_end, camera_height_shares,
    /// camera_height_elevations_deg and camera_height_views (the run's estimate, its middle-ring
    /// cameras' mean elevation and the independent views it counted, NaN without one;
    /// docs/cli.md gives their types and shapes). Written at the end of the run, or not at
    /// all. Nothing is printed per pose unless --json or --jsonl asks for it. Not with --sequence
    /// (whose smoothed cameras have no arrays here: use --jsonl).
    #[arg(long, value_name = "OUT", conflicts_with = "sequence")]
    pub npz: Option<PathBuf>,
    #[command(flatten)]
    pub force: ForceArgs,
    #[command(flatten)]
    pub progress: ProgressArgs,
}

impl Args {
    /// The video's frame rate (`--fps`, 30 by default); a usage error when it is given
    /// without --sequence or --html, which it changes nothing without.
    fn fps(&self) -> Result<f64, CliError> {
        export::fps_for(
            self.fps,
            self.sequence || self.html.is_some(),
            "--sequence or --html",
        )
    }
}

/// Runs `camloc localize`.
pub fn run(args: &Args, out: &mut Out) -> Result<ExitCode, CliError> {
    let fps = args.fps()?;
    let outputs = [
        (args.svg.as_deref(), "--svg", Some("svg")),
        (args.summary_svg.as_deref(), "--summary-svg", None),
        (args.html.as_deref(), "--html", None),
        (args.npz.as_deref(), "--npz", None),
    ];
    targets::check(
        outputs,
        &[
            ("the input", Some(args.input.path())),
            ("--model", args.model.as_deref()),
        ],
        args.force.force,
    )?;
    let intrinsics = args.intrinsics.intrinsics(args.input.image_size);
    if intrinsics.is_some_and(|k| k.principal_point.is_none()) {
        stderr_line!(
            "camloc: warning: --focal-px without --principal-point or --image-size changes no \
             localization: the aim at the person needs where the optical axis meets the image"
        );
    }
    weak_scores::warn_of_weak_scores(&args.input);
    image_size_check::warn_of_image_scale(&args.input, None);
    let (localizer, inputs, estimate) = heights::load_for_input(
        args.model.as_deref(),
        &args.height,
        &args.input,
        intrinsics,
        args.progress.quiet,
    )?;
    let format = args.format.format();
    // Poses per predicted camera, for --summary-svg.
    let counts: Arc<Vec<AtomicU64>> = Arc::new(
        (0..localizer.cameras().len())
            .map(|_| AtomicU64::new(0))
            .collect(),
    );
    let summary = args.summary_svg.clone().map(|path| {
        let (cameras, counts, name) = (
            localizer.cameras().clone(),
            Arc::clone(&counts),
            inputs.name().to_owned(),
        );
        let draw: SummaryDrawing = Box::new(move || {
            let counts: Vec<u64> = counts.iter().map(|c| c.load(Ordering::Relaxed)).collect();
            svg::summary_svg(&cameras, &counts, &format!("cameras of {name}"))
        });
        (path, draw)
    });
    // The embedded basis fills in missing torsos and gives the page's 3D skeletons.
    let basis = embedded_basis();
    let locator = Locator {
        localizer: &localizer,
        filler: basis.as_ref(),
    };
    // The page's 3D skeletons are what `camloc reconstruct` gives with the same model: the
    // `hybrid` camera, with the embedded depth lifter when the model is the embedded one.
    let page_reconstructor = match &args.html {
        Some(_) => {
            let reconstructor = basis
                .clone()
                .ok_or(CamlocError::NoDefault("basis"))?
                .with_localizer(localizer.clone());
            let mut reconstructor =
                match lifter_for_model(args.model.as_deref(), localizer.cameras())? {
                    Some(lifter) => reconstructor.with_lifter(lifter),
                    None => reconstructor,
                };
            if let Some(intrinsics) = intrinsics {
                reconstructor = reconstructor.with_intrinsics(intrinsics)?;
            }
            Some(reconstructor.with_mode(ModeKind::Hybrid)?)
        }
        None => None,
    };
    let view = |record: &KeypointRecord, loc: Option<&Localization>, error: Option<String>| {
        page_reconstructor.as_ref().map(|r| {
            let found = r.reconstruct(&record.pose);
            let error = error.or_else(|| found.as_ref().err().map(|e| format!("3D: {e}")));
            let reconstruction = found.ok().map(|f| f.reconstruction);
            ViewFrame::new(record, loc, reconstruction.as_ref(), error)
        })
    };
    let finish = args.html.clone().map(|html| {
        let cameras = localizer.cameras().clone();
        let title = format!("camloc localize: {}", inputs.name());
        let make: stream::Finish<ViewFrame> = Box::new(move |views: Vec<ViewFrame>, staged| {
            let keys = vec![(None, None); views.len()];
            let groups = export::groups::<&str>(&keys, None, false);
            let (path, page) = export::html_file(&html, &title, &cameras, &views, groups, fps);
            staged.add(&path, &page)?;
            Ok(())
        });
        (vec![args.html.clone().unwrap_or_default()], make)
    });
    let rows = match &args.npz {
        Some(npz) => Some(Box::new(LocalizationArrays::new(
            npz,
            localizer.cameras().len(),
            localizer.camera_height(),
            estimate.map_or(f64::NAN, |e| e.reported_views()),
        )?) as _),
        None => None,
    };
    let files = Files::<Localization, ViewFrame> {
        svg: args.svg.clone(),
        rows,
        summary,
        finish,
        force: args.force.force,
    };
    // Text per pose, unless --npz is the output and no JSON was asked for.
    let print = format.is_json() || args.npz.is_none();
    let objects = LocalizationJson::new(localizer.cameras());
    let bar = progress::counter(args.progress.quiet, inputs.len_hint(), "localize", "poses");
    if args.sequence {
        let files = sequence::SequenceOptions {
            svg: args.svg.as_deref(),
            summary: args.summary_svg.as_deref(),
            force: args.force.force,
            max_poses: args.sequence_max_poses,
            html: args.html.as_deref().map(|path| (path, fps)),
            rate: FrameRate::new(fps).map_err(|e| CamlocError::InvalidOption {
                name: "--fps",
                detail: e.to_string(),
            })?,
        };
        return sequence::run(locator, inputs, out, format, &files, &bar, &view);
    }
    let summary = stream::run(
        inputs,
        out,
        format,
        files,
        &bar,
        localizer.intrinsics(),
        |record| {
            let loc = locator.localize(&record.pose).map_err(|e| {
                let message = e.to_string();
                Failed {
                    keep: view(record, None, Some(message.clone())).map(Box::new),
                    message,
                }
            })?;
            if let Some(count) = counts.get(loc.label.index()) {
                count.fetch_add(1, Ordering::Relaxed);
            }
            let text = if !print {
                String::new()
            } else if format.is_json() {
                objects.object(record, &loc)
            } else {
                localization_text(&localizer, record, &loc)
            };
            let svg = args.svg.as_ref().map(|_| {
                let mut caption = format!(
                    "{}: camera {} ({} {}), p = {:.2}",
                    record.id,
                    loc.label,
                    loc.level.name(),
                    loc.side.name(),
                    loc.probability
                );
                // The runner-up of a close call.
                let next = (loc.probabilities.iter().enumerate())
                    .filter(|&(k, _)| k != loc.label.index())
                    .max_by(|a, b| a.1.total_cmp(b.1));
                if let Some((k, &p)) = next.filter(|(_, p)| **p >= svg::SHOWN_PROBABILITY) {
                    let _ = write!(caption, "; next {:02}, p = {p:.2}", k + 1);
                }
                if !loc.missing.is_empty() {
                    let names: Vec<&str> = loc.missing.iter().map(|l| l.name()).collect();
                    let _ = write!(caption, "; missing: {}", names.join(", "));
                }
                svg::localization_svg(
                    &record.pose,
                    localizer.cameras(),
                    &loc.probabilities,
                    loc.label,
                    svg::Direction::of(&loc),
                    &caption,
                )
            });
            Ok(Done {
                text,
                svg,
                keep: view(record, Some(&loc), None),
                row: args.npz.as_ref().map(|_| loc),
            })
        },
    )?;
    Ok(summary.exit_code("localized"))
}

fn rotation_rows(loc: &Localization) -> [[f64; 3]; 3] {
    let r = &loc.rotation;
    [
        [r[(0, 0)], r[(0, 1)], r[(0, 2)]],
        [r[(1, 0)], r[(1, 1)], r[(1, 2)]],
        [r[(2, 0)], r[(2, 1)], r[(2, 2)]],
    ]
}

/// Below this probability of the most probable camera, the text output also names the
/// second most probable one.
const SURE: f64 = 0.9;

/// The line naming the second most probable camera and its probability, when the most
/// probable one's is below [`SURE`].
fn runner_up_text(localizer: &CameraLocalizer, loc: &Localization) -> Option<String> {
    // As printed (three decimals): a 0.8996 shown as 0.900 is sure enough.
    if (1000.0 * loc.probability).round() >= 1000.0 * SURE {
        return None;
    }
    let (index, p) = loc
        .probabilities
        .iter()
        .enumerate()
        .filter(|&(i, _)| i != loc.label.index())
        .max_by(|a, b| a.1.total_cmp(b.1))?;
    let view = localizer.cameras().viewpoints().get(index)?;
    Some(format!(
        "  next most probable: camera {}, {} level, {} side{}, probability {p:.3}\n",
        view.label_text(),
        view.level.name(),
        view.side.name(),
        angles_in_words(view)
    ))
}

/// A camera's angles as the text output gives them, ` (azimuth 270 deg, elevation 0 deg)`:
/// what tells apart the cameras of a sphere of several rings in a level or more than 4
/// azimuths, whose level and side names repeat.
fn angles_in_words(view: &camloc::geometry::Viewpoint) -> String {
    format!(
        " (azimuth {:.0} deg, elevation {:.0} deg)",
        view.azimuth_deg, view.elevation_deg
    )
}

fn localization_text(
    localizer: &CameraLocalizer,
    record: &KeypointRecord,
    loc: &Localization,
) -> String {
    let mut out = String::new();
    let view = localizer.cameras().get(loc.label.get());
    let where_ = view.map_or_else(String::new, angles_in_words);
    let _ = writeln!(
        out,
        "{}: camera {}, {} level, {} side{where_}, probability {:.3}",
        escaped(&record.id),
        loc.label,
        loc.level.name(),
        loc.side.name(),
        loc.probability
    );
    if let Some(line) = runner_up_text(localizer, loc) {
        out.push_str(&line);
    }
    if loc.folded_label != loc.label {
        let _ = writeln!(out, "  mirror-folded camera: {}", loc.folded_label);
    }
    if let (Some(a), Some(e), Some(u)) = (loc.azimuth_deg, loc.elevation_deg, loc.uncertainty_deg) {
        let _ = writeln!(
            out,
            "  viewpoint: azimuth {a:.1} deg, elevation {e:.1} deg, +- {u:.1} deg"
        );
    }
    // The class's own camera (Table 1's with the default model), not the viewpoint above:
    // named so.
    let _ = writeln!(
        out,
        "  camera {}'s rotation (the class's; rows: its axes in the person's frame):",
        loc.label
    );
    for row in rotation_rows(loc) {
        let _ = writeln!(out, "    [{:>7.4} {:>7.4} {:>7.4}]", row[0], row[1], row[2]);
    }
    if !record.derived.is_empty() {
        let names: Vec<&str> = record.derived.iter().map(|l| l.name()).collect();
        let _ = writeln!(out, "  derived: {}", names.join(", "));
    }
    if !loc.missing.is_empty() {
        let names: Vec<&str> = loc.missing.iter().map(|l| l.name()).collect();
        let _ = writeln!(out, "  missing (imputed): {}", names.join(", "));
    }
    out
}
