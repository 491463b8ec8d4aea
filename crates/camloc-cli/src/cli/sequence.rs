//! `camloc localize --sequence`: every pose is localized (in parallel batches), then the frames
//! of each person are smoothed with [`SequenceModel`] and written in order of person and frame,
//! with one timeline drawing per person for `--svg` (and the per-frame cameras of the whole
//! input for `--summary-svg`).
//!
//! A sequence needs all its frames before it can be smoothed: the run keeps, per pose, its id,
//! source, frame, person, the 12 class probabilities and the landmarks in single precision (a
//! failure keeps the number of its message, each distinct message once), and refuses an input
//! of more than `--sequence-max-poses` poses (1,000,000 by default) when it gets there; with
//! the smoothing and the limbs swapped back, about 1.3 KB a pose (docs/cli.md).

use std::collections::HashMap;
use std::fmt::Write;
use std::path::Path;
use std::process::ExitCode;

use camloc::keypoints::KeypointRecord;
use camloc::reconstruct::FrameRate;
use camloc::skeleton::NUM_LANDMARKS;
use camloc::{
    CameraLabel, Landmark, LeftOut, Localization, PartialPose2, SequenceModel, SideChain,
    SmoothedFrame, TorsoAnchor, Viewpoint, identity_jumps, smooth_viewpoints,
};
use indicatif::ProgressBar;
use rayon::prelude::*;
use serde::Serialize;

use crate::html::ViewFrame;
use crate::svg;

use super::export;
use super::input::Inputs;
use super::output::Out;
use super::stream::{
    BATCH, Emitter, Format, Summary, check_kept, check_kept_input, counted, json_line,
    nothing_detected, report_pose_error,
};
use super::{CliError, Locator, numbered_path};
use camloc::store::{StagedFiles, escaped};

/// One localized (or failed) pose of a sequence: what is kept until the sequence is smoothed
/// (at most 250 bytes, with the id, source and probabilities on the heap).
struct Frame {
    /// The pose's landmarks (single precision, NaN where missing), for the limbs a detector
    /// swapped left for right ([`sides_swapped_back`]).
    points: [[f32; 2]; NUM_LANDMARKS],
    /// The chains swapped back ([`camloc::SideChain::ALL`] order, bit per chain).
    swapped_sides: u8,
    /// The landmarks missing (or far off the others) and filled in to localize the pose, and
    /// those derived from others (bit per landmark index), as `localize` names them.
    missing: u16,
    derived: u16,
    id: Box<str>,
    source: Box<str>,
    frame: Option<u64>,
    person: Option<u64>,
    /// Whether `person` is only the pose's position among its frame's poses
    /// ([`KeypointRecord::person_is_position`]).
    person_is_position: bool,
    /// The pose's [`TorsoAnchor`] (pelvis x, y and torso length, single precision), for
    /// [`warn_of_identity_jumps`].
    anchor: Option<[f32; 3]>,
    /// The localization's continuous viewpoint (azimuth, elevation, its uncertainty;
    /// degrees, single precision), for [`smooth_viewpoints`].
    viewpoint: Option<[f32; 3]>,
    /// The most probable camera and every camera's probability, or the number of the failure's
    /// message in [`Failures`].
    result: Result<Cameras, u32>,
}

/// A localization's most probable camera and every camera's probability.
type Cameras = (CameraLabel, Box<[f64]>);

impl Frame {
    /// The pose kept, in double precision.
    fn pose(&self) -> PartialPose2 {
        PartialPose2 {
            points: self.points.map(|[x, y]| {
                (x.is_finite() && y.is_finite()).then(|| [f64::from(x), f64::from(y)])
            }),
        }
    }

    /// The pose's [`TorsoAnchor`], in double precision.
    fn torso_anchor(&self) -> Option<TorsoAnchor> {
        self.anchor.map(|[x, y, torso]| TorsoAnchor {
            pelvis: [f64::from(x), f64::from(y)],
            torso: f64::from(torso),
        })
    }

    /// The most probable camera and its probability.
    fn best(&self) -> Option<(CameraLabel, f64)> {
        let (label, p) = self.result.as_ref().ok()?;
        Some((*label, p.get(label.index()).copied().unwrap_or(f64::NAN)))
    }
}

/// The distinct failure messages of a run (thousands of poses without a torso share one).
#[derive(Default)]
struct Failures {
    messages: Vec<String>,
    numbers: HashMap<String, u32>,
}

impl Failures {
    /// The number of `message`.
    fn number(&mut self, message: String) -> u32 {
        if let Some(&n) = self.numbers.get(&message) {
            return n;
        }
        let n = u32::try_from(self.messages.len()).unwrap_or(u32::MAX);
        self.messages.push(message.clone());
        self.numbers.insert(message, n);
        n
    }

    /// The message numbered `n`.
    fn message(&self, n: u32) -> &str {
        self.messages.get(n as usize).map_or("", String::as_str)
    }
}

/// One frame of `localize --sequence --json` / `--jsonl`.
#[derive(Serialize)]
struct FrameJson<'a> {
    id: &'a str,
    source: &'a str,
    #[serde(skip_serializing_if = "Option::is_none")]
    frame: Option<u64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    person: Option<u64>,
    /// Left out of the person's smoothing (a second pose of a frame, another person's
    /// detection); absent when not.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    left_out_of_sequence: bool,
    #[serde(skip_serializing_if = "Option::is_none")]
    label: Option<CameraLabel>,
    #[serde(skip_serializing_if = "Option::is_none")]
    probability: Option<f64>,
    /// Single precision, as each frame keeps it (about 1e-5 deg), and printed as such.
    #[serde(skip_serializing_if = "Option::is_none")]
    azimuth_deg: Option<f32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    elevation_deg: Option<f32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    uncertainty_deg: Option<f32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    error: Option<&'a str>,
    /// The chains whose left and right sides were swapped back before the frame was localized.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    swapped_sides: Vec<&'static str>,
    /// As `localize` names them: landmarks missing and filled in, landmarks derived.
    missing: Vec<&'static str>,
    derived: Vec<&'static str>,
    smoothed_label: Option<CameraLabel>,
    smoothed_probability: Option<f64>,
    /// Single precision: smoothed from the frames' single-precision angles.
    smoothed_azimuth_deg: Option<f32>,
    smoothed_elevation_deg: Option<f32>,
}

/// The options of a sequence run: `--svg` (one timeline per person), `--summary-svg`,
/// `--force` and `--sequence-max-poses`.
pub struct SequenceOptions<'a> {
    /// `--svg`: the timelines (numbered when there are several people).
    pub svg: Option<&'a Path>,
    /// `--summary-svg`: the per-frame cameras of the whole input.
    pub summary: Option<&'a Path>,
    /// `--force`: replace existing files.
    pub force: bool,
    /// `--sequence-max-poses`: the most poses kept.
    pub max_poses: u64,
    /// `--html` and its play rate: one page, one timeline per person.
    pub html: Option<(&'a Path, f64)>,
    /// `--fps`: the video's frames a second, the time scale of the smoothing and of the
    /// windows that judge frames ([`FrameRate`]).
    pub rate: FrameRate,
}

/// The page's record of a pose from its localization or failure (`None` without `--html`).
pub type PageFrame<'a> =
    dyn Fn(&KeypointRecord, Option<&Localization>, Option<String>) -> Option<ViewFrame> + Sync + 'a;

/// Runs `camloc localize --sequence` (see the module docs), writing `files`.
pub fn run(
    locator: Locator<'_>,
    mut inputs: Inputs,
    out: &mut Out,
    format: Format,
    files: &SequenceOptions,
    bar: &ProgressBar,
    page: &PageFrame,
) -> Result<ExitCode, CliError> {
    let localizer = locator.localizer;
    let (svg_out, summary_out, force) = (files.svg, files.summary, files.force);
    let mut views: Vec<ViewFrame> = Vec::new();
    // The timelines' targets (refused before any work if they existed, `targets::check`),
    // looked at again after the run (`warn_left_over`).
    let numbered =
        svg_out.map_or_else(Vec::new, |svg| super::targets::numbered_targets(svg, "svg"));
    let mut emit = Emitter::new(format);
    check_kept_input(files.html.is_some(), &inputs)?;
    let mut summary = Summary {
        conventions: camloc::InputConventions::aimed(localizer.intrinsics()),
        min_score: inputs.min_score(),
        outside_image: super::outside_image::OutsideImage::new(
            inputs.image_size(),
            localizer.intrinsics(),
        ),
        ..Summary::default()
    };
    let mut frames: Vec<Frame> = Vec::new();
    let mut failures = Failures::default();
    loop {
        let batch: Vec<_> = inputs.by_ref().take(BATCH).collect();
        if batch.is_empty() {
            break;
        }
        let results: Vec<_> = batch
            .par_iter()
            .map(|item| {
                let record = item.as_ref().ok()?;
                let (result, view, viewpoint, missing) = localized(&locator, page, record);
                Some((record, result, view, viewpoint, missing))
            })
            .collect();
        for (item, frame) in batch.iter().zip(results) {
            // A pose the reader refused is a failed frame in its place, without landmarks.
            let refused_record;
            let (record, result, view, viewpoint, missing, refused) = match (item, frame) {
                (_, Some((record, result, view, viewpoint, missing))) => {
                    (record, result, view, viewpoint, missing, false)
                }
                (Err(e), None) => match KeypointRecord::of_refused_pose(e) {
                    Some((record, message)) => {
                        refused_record = record;
                        (&refused_record, Err(message), None, None, 0, true)
                    }
                    None => {
                        emit.file_error(out, &mut summary, bar, e)?;
                        continue;
                    }
                },
                (Ok(_), None) => continue,
            };
            views.extend(view);
            if summary.poses == files.max_poses {
                return Err(CliError::TooManyPoses(files.max_poses));
            }
            check_kept(files.html.is_some(), summary.poses + 1)?;
            let result = result.map_err(|message| {
                if !refused && nothing_detected(&record.pose) {
                    summary.undetected += 1;
                    return failures.number(message);
                }
                summary.failed_poses += 1;
                report_pose_error(bar, &record.id, &record.source, &message);
                failures.number(message)
            });
            summary.count(&record.pose);
            frames.push(Frame {
                points: record
                    .pose
                    .points
                    .map(|p| p.map_or([f32::NAN; 2], |[x, y]| [x as f32, y as f32])),
                swapped_sides: 0,
                missing,
                derived: Landmark::mask_of(&record.derived),
                id: record.id.as_str().into(),
                source: record.source.as_str().into(),
                frame: record.frame,
                person: record.person,
                person_is_position: record.person_is_position,
                anchor: TorsoAnchor::of(&record.pose)
                    .map(|a| [a.pelvis[0] as f32, a.pelvis[1] as f32, a.torso as f32]),
                viewpoint,
                result,
            });
        }
        bar.inc(batch.len() as u64);
    }
    bar.finish_and_clear();
    if summary.poses == 0 && summary.failed_files == 0 {
        return Err(inputs.no_poses());
    }
    emit.end_if_unread(out, inputs.check_read_to_end(summary.failed_files))?;
    let model = SequenceModel::with_default_switch(localizer.cameras());
    let mut keys: Vec<_> = frames.iter().map(|f| (f.frame, f.person)).collect();
    let sources: Vec<&str> = frames.iter().map(|f| &*f.source).collect();
    let (groups, names) = super::videos::followed_sequences(
        &mut keys,
        &sources,
        inputs.is_folder(),
        |i| frames[i].person_is_position,
        |i| frames[i].torso_anchor(),
        files.rate,
    );
    for (frame, key) in frames.iter_mut().zip(&keys) {
        frame.person = key.1;
    }
    if let Some(svg) = svg_out {
        super::output::name_numbered_persons(svg, &names);
    }
    let mut staged = StagedFiles::new(force);
    for (n, (person, members)) in groups.iter().enumerate() {
        let numbers = frame_numbers(&keys, members);
        let anchors: Vec<Option<TorsoAnchor>> =
            members.iter().map(|&i| frames[i].torso_anchor()).collect();
        let left_out_frames = left_out_of_sequence(
            *person,
            &numbers,
            &anchors,
            files.rate,
            "left out of the person's smoothing (its smoothed camera comes from the frames \
             around it, and it has no smoothed viewpoint)",
        );
        let left_out = left_out_frames.mask(members.len());
        // The limbs a detector swapped left for right (in the frames kept): swapped back and
        // localized again.
        let mut poses: Vec<PartialPose2> = members.iter().map(|&i| frames[i].pose()).collect();
        let sides = sides_swapped_back(*person, &numbers, &mut poses, &left_out, files.rate);
        for ((&i, pose), &bits) in members.iter().zip(&poses).zip(&sides) {
            if bits == 0 {
                continue;
            }
            let frame = &mut frames[i];
            let record = KeypointRecord {
                id: frame.id.to_string(),
                pose: *pose,
                derived: Vec::new(),
                source: frame.source.to_string(),
                frame: frame.frame,
                person: frame.person,
                person_is_position: false,
            };
            let (result, view, viewpoint, missing) = localized(&locator, page, &record);
            if let (Some(kept), Some(view)) = (views.get_mut(i), view) {
                *kept = view;
            }
            frame.swapped_sides = bits;
            frame.viewpoint = viewpoint;
            frame.missing = missing;
            frame.result = result.map_err(|message| failures.number(message));
        }
        let viewpoints: Vec<Option<Viewpoint>> = members
            .iter()
            .zip(&left_out)
            .map(|(&i, &left)| {
                (frames[i].viewpoint)
                    .filter(|_| !left)
                    .map(|[a, e, _]| (f64::from(a), f64::from(e)))
            })
            .collect();
        let smoothed_viewpoints = smooth_viewpoints(&numbers, &viewpoints, files.rate);
        let probabilities: Vec<Option<&[f64]>> = members
            .iter()
            .zip(&left_out)
            .map(|(&i, &left)| {
                (frames[i].result.as_ref().ok())
                    .filter(|_| !left)
                    .map(|r| &r.1[..])
            })
            .collect();
        // A person none of whose frames was localized has no smoothed camera: the model's
        // flat frames alone would name camera 1 at 1/K.
        let smoothed = if probabilities.iter().any(Option::is_some) {
            model.smooth(&probabilities)?
        } else {
            Vec::new()
        };
        for (k, &i) in members.iter().enumerate() {
            let s = smoothed.get(k);
            let smoothed = (s, smoothed_viewpoints[k]);
            let text = frame_output(format, &frames[i], left_out[k], smoothed, &failures);
            emit.write(out, &text)?;
            if let (Some(view), Some(s)) = (views.get_mut(i), s) {
                view.set_smoothed(s.label, smoothed_viewpoints[k]);
            }
        }
        if let Some(svg) = svg_out {
            // The person's frames: a second pose of a frame (another's) has no place on the
            // time line; an outlier frame keeps its slot.
            let kept: Vec<usize> = (0..members.len())
                .filter(|k| left_out_frames.second_poses.binary_search(k).is_err())
                .collect();
            let raw: Vec<Option<CameraLabel>> = kept
                .iter()
                .map(|&k| frames[members[k]].best().map(|b| b.0))
                .collect();
            let kept_smoothed: Vec<SmoothedFrame> = kept
                .iter()
                .filter_map(|&k| smoothed.get(k).cloned())
                .collect();
            // (The person's name: a folder of videos names the file too.)
            let title = format!(
                "{}: {}, {}",
                inputs.name(),
                names[n],
                counted(kept.len() as u64, "frame")
            );
            // Frame numbers, else the position in the input (as the outputs' `frame`).
            let number = |k: usize| frames[members[k]].frame.unwrap_or(members[k] as u64);
            let ends = [kept.first(), kept.last()].map(|m| m.map_or(0, |&k| number(k)));
            let drawing =
                svg::timeline_svg(localizer.cameras(), &raw, &kept_smoothed, ends, &title);
            staged.add(&numbered_path(svg, n, groups.len()), drawing.as_bytes())?;
        }
    }
    if let Some(path) = summary_out {
        let mut counts = vec![0u64; localizer.cameras().len()];
        for frame in &frames {
            if let Some(count) = frame.best().and_then(|b| counts.get_mut(b.0.index())) {
                *count += 1;
            }
        }
        let title = format!(
            "per-frame cameras of {} (the smoothed ones: --svg's timelines)",
            inputs.name()
        );
        let drawing = svg::summary_svg(localizer.cameras(), &counts, &title);
        staged.add(path, drawing.as_bytes())?;
    }
    if let Some((html, fps)) = files.html {
        let title = format!("camloc localize --sequence: {}", inputs.name());
        let groups = groups.iter().zip(&names);
        let groups = groups.map(|((_, members), name)| (name.clone(), members.clone()));
        let (path, bytes) = export::html_file(
            html,
            &title,
            localizer.cameras(),
            &views,
            groups.collect(),
            fps,
        );
        staged.add(&path, &bytes)?;
    }
    emit.end(out)?;
    out.flush()?;
    let written = staged.commit()?;
    super::targets::warn_left_over(&numbered, &written);
    Ok(summary.exit_code("localized"))
}

/// The frames of `person` (their `frames` numbers and `anchors`, in time order, at `rate`; a
/// frame's poses in input order) that are left out of the person's sequence
/// ([`camloc::left_out_of_sequence`]), with a warning on standard error saying that each is
/// `treated` so, and the warning of [`warn_of_identity_jumps`] over the frames kept.
pub fn left_out_of_sequence(
    person: u64,
    frames: &[Option<u64>],
    anchors: &[Option<TorsoAnchor>],
    rate: FrameRate,
    treated: &str,
) -> LeftOut {
    let left_out = camloc::left_out_of_sequence(frames, anchors, rate);
    let at = |m: usize| frame_name(frames, m);
    if let Some(&first) = left_out.second_poses.first() {
        let seconds = left_out.second_poses.len();
        stderr_line!(
            "camloc: warning: person {person}: {} share{} a frame with another pose (first at \
             {}): of a frame's poses the one nearest where the person is expected is the \
             person's, each other is {treated}",
            counted(seconds as u64, "pose"),
            if seconds == 1 { "s" } else { "" },
            at(first)
        );
    }
    if let Some(&first) = left_out.outliers.first() {
        let count = left_out.outliers.len();
        let stretches = 1 + left_out
            .outliers
            .windows(2)
            .filter(|w| w[1] > w[0] + 1)
            .count();
        let (verb, pronoun, each) = if count == 1 {
            ("lies", "it", "it is")
        } else {
            ("lie", "them", "each is")
        };
        let in_stretches = if stretches > 1 && stretches < count {
            format!(" in {stretches} stretches")
        } else {
            String::new()
        };
        let poses = if count == 1 { "pose" } else { "poses" };
        stderr_line!(
            "camloc: warning: person {person}: the {poses} of {}{in_stretches} {verb} apart \
             from the frames before and after {pronoun} (first at {}: another person's \
             detection, or a misplaced one?): {each} {treated}",
            counted(count as u64, "frame"),
            at(first)
        );
    }
    warn_of_identity_jumps(person, frames, &left_out.kept_anchors(anchors));
    left_out
}

/// A pose's localization as a sequence keeps it (the camera and probabilities, or the error's
/// message), the page's record of it (`None` without `--html`), its continuous viewpoint
/// with its uncertainty (single precision) and its missing landmarks (bit per index).
fn localized(
    locator: &Locator<'_>,
    page: &PageFrame,
    record: &KeypointRecord,
) -> (
    Result<Cameras, String>,
    Option<ViewFrame>,
    Option<[f32; 3]>,
    u16,
) {
    let found = locator.localize(&record.pose);
    let view = match &found {
        Ok(loc) => page(record, Some(loc), None),
        Err(e) => page(record, None, Some(e.to_string())),
    };
    let viewpoint = found.as_ref().ok().and_then(|loc| {
        let viewpoint = [loc.azimuth_deg?, loc.elevation_deg?, loc.uncertainty_deg?];
        Some(viewpoint.map(|v| v as f32))
    });
    let missing = found
        .as_ref()
        .map_or(0, |loc| Landmark::mask_of(&loc.missing));
    let result = found
        .map(|loc| (loc.label, loc.probabilities.into_boxed_slice()))
        .map_err(|e| e.to_string());
    (result, view, viewpoint, missing)
}

/// The names of the landmarks whose bits are set in `mask`, in index order.
fn landmark_names(mask: u16) -> Vec<&'static str> {
    Landmark::in_mask(mask).map(Landmark::name).collect()
}

/// Swaps back in `poses` of `person` (their `frames` numbers, in time order, at `rate`; the
/// frames `left_out` of the sequence aside) the limbs a detector swapped for a few frames
/// ([`camloc::swap_sides_back`]), with a warning on standard error per chain; per frame, the
/// chains swapped back (bit `c` for [`SideChain::ALL`]`[c]`, named by [`side_names`]).
pub fn sides_swapped_back(
    person: u64,
    frames: &[Option<u64>],
    poses: &mut [PartialPose2],
    left_out: &[bool],
    rate: FrameRate,
) -> Vec<u8> {
    let mut bits = vec![0u8; poses.len()];
    for (c, (chain, swapped)) in camloc::swap_sides_back(frames, poses, left_out, rate)
        .into_iter()
        .enumerate()
    {
        let Some(&first) = swapped.first() else {
            continue;
        };
        for &m in &swapped {
            bits[m] |= 1 << c;
        }
        stderr_line!(
            "camloc: warning: person {person}: the left and right {} of {} are swapped against \
             the frames around them (first at {}: a detector's confusion?): they are swapped \
             back (`swapped_sides` in the JSON output)",
            chain.name(),
            counted(swapped.len() as u64, "frame"),
            frame_name(frames, first)
        );
    }
    bits
}

/// The names of the chains of `bits` ([`sides_swapped_back`]).
pub fn side_names(bits: u8) -> Vec<&'static str> {
    SideChain::ALL
        .iter()
        .enumerate()
        .filter(|(c, _)| bits & (1 << c) != 0)
        .map(|(_, chain)| chain.name())
        .collect()
}

/// How a warning names the frame at position `m` of a person's frames (`frames` their
/// numbers): by its number, else by its place among the person's poses, counted from 0 as
/// the input's `poses[i]` are.
pub fn frame_name(frames: &[Option<u64>], m: usize) -> String {
    match frames[m] {
        Some(frame) => format!("frame {frame}"),
        None => format!("the person's pose {m} (counted from 0)"),
    }
}

/// The frame numbers of the records at `members` (their `keys`' first part).
pub fn frame_numbers(keys: &[(Option<u64>, Option<u64>)], members: &[usize]) -> Vec<Option<u64>> {
    members.iter().map(|&i| keys[i].0).collect()
}

/// Warns on standard error when the frames of `person` (their `frames` numbers and
/// `anchors`, in time order) jump across the image or change size as one person cannot
/// ([`identity_jumps`]): a detector's order of people (OpenPose's `people[i]`) changed, or two
/// people share an id, and one person's smoothing, bone lengths and animation would mix them.
/// The first [`ERRORS_SHOWN`](super::stream::ERRORS_SHOWN) persons of a run are named one
/// by one, then one line says the rest are not ([`JUMP_WARNINGS`](super::stream::JUMP_WARNINGS)).
fn warn_of_identity_jumps(person: u64, frames: &[Option<u64>], anchors: &[Option<TorsoAnchor>]) {
    let jumps = identity_jumps(frames, anchors);
    let Some(&first) = jumps.first() else {
        return;
    };
    let at = frame_name(frames, first);
    let hidden = ProgressBar::hidden();
    super::stream::report_capped(&super::stream::JUMP_WARNINGS, &hidden, || {
        format!(
            "warning: person {person}: the pose jumps across the image or changes size \
         from one frame to the next {} (first at {at}): these may be several people \
         (the detector's order of people changed?), or not consecutive frames of a video; \
         several people need an id each (`person` in camloc JSON, `track_id` in COCO or \
         MMPose, `person_id` in OpenPose)",
            if jumps.len() == 1 {
                "once".to_owned()
            } else {
                format!("{} times", jumps.len())
            }
        )
    });
}

/// The output of one frame: a JSON object (no newline) or a line of text; `left_out`: the
/// frame is left out of its person's smoothing; `s` is the frame's smoothed camera and
/// smoothed viewpoint.
fn frame_output(
    format: Format,
    frame: &Frame,
    left_out: bool,
    (s, viewpoint): (Option<&SmoothedFrame>, Option<Viewpoint>),
    failures: &Failures,
) -> String {
    let raw = frame.best();
    if format.is_json() {
        return json_line(&FrameJson {
            id: &frame.id,
            source: &frame.source,
            frame: frame.frame,
            person: frame.person,
            left_out_of_sequence: left_out,
            label: raw.map(|r| r.0),
            probability: raw.map(|r| r.1),
            azimuth_deg: frame.viewpoint.map(|v| v[0]),
            elevation_deg: frame.viewpoint.map(|v| v[1]),
            uncertainty_deg: frame.viewpoint.map(|v| v[2]),
            error: frame.result.as_ref().err().map(|&n| failures.message(n)),
            swapped_sides: side_names(frame.swapped_sides),
            missing: landmark_names(frame.missing),
            derived: landmark_names(frame.derived),
            smoothed_label: s.map(|s| s.label),
            smoothed_probability: s.map(|s| s.probability),
            smoothed_azimuth_deg: viewpoint.map(|v| v.0 as f32),
            smoothed_elevation_deg: viewpoint.map(|v| v.1 as f32),
        });
    }
    let mut text = String::new();
    let _ = write!(text, "{}", escaped(&frame.id));
    if let Some(f) = frame.frame {
        let _ = write!(text, " frame {f}");
    }
    if let Some(p) = frame.person {
        let _ = write!(text, " person {p}");
    }
    if left_out {
        text.push_str(" (left out of the sequence)");
    }
    match raw {
        Some((label, p)) => {
            let _ = write!(text, ": camera {label} ({p:.3})");
            if let Some([azimuth, elevation, uncertainty]) = frame.viewpoint {
                let _ = write!(
                    text,
                    ", viewpoint azimuth {azimuth:.1} deg, elevation {elevation:.1} deg, \
                     +- {uncertainty:.1} deg"
                );
            }
        }
        None => text.push_str(": not localized"),
    }
    match s {
        Some(s) => {
            let _ = write!(text, ", smoothed camera {} ({:.3})", s.label, s.probability);
            if let Some((azimuth, elevation)) = viewpoint {
                let _ = write!(
                    text,
                    ", smoothed viewpoint azimuth {azimuth:.1} deg, elevation {elevation:.1} deg"
                );
            }
            text.push('\n');
        }
        None => text.push_str(", no smoothed camera (no frame of the person was localized)\n"),
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_kept_frame_is_small() {
        assert!(std::mem::size_of::<Frame>() <= 250);
    }
}
