//! `camloc reconstruct --sequence`: every pose is read and kept (its id, source, frame,
//! person and 2D landmarks), grouped by person and ordered by frame as `localize --sequence`
//! groups them ([`person_sequences`](super::videos::person_sequences): a folder of videos a
//! video per file), and each person's frames are reconstructed together
//! ([`PoseReconstructor::reconstruct_sequence`]: shared bone lengths, depths chosen over
//! time, smoothness). Frames are written by person then frame; `.npy` rows stay in input
//! order; `--bone-lengths-out` gets each person's lengths; `--bvh` one animation per person
//! (its frames have the person's shared lengths) and `--html` one page.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use camloc::keypoints::KeypointRecord;
use camloc::store::StagedFiles;
use camloc::{ModeKind, Pose3, PoseReconstruction, PoseReconstructor};
use indicatif::ProgressBar;

use crate::html::ViewFrame;

use super::export::Kept;
use super::input::Inputs;
use super::output::{NpyStage, Out};
use super::person_solve::{PARALLEL_FRAMES, Prepared, Solved, solve_persons};
use super::reconstruct_output::{PoseMeta, lengths_text, pose_output, pose_svg};
use super::stream::{
    Emitter, Finish, Format, Summary, check_kept, check_kept_input, counted, nothing_detected,
    report_pose_error,
};
use super::{CliError, numbered_path};

/// What the `--html` page shows of one frame: its record, its reconstruction (with the
/// localization it used, if any) or the error.
pub type ViewOf<'a> =
    &'a dyn Fn(&KeypointRecord, Option<&PoseReconstruction>, Option<String>) -> Option<ViewFrame>;

/// The options of a sequence run.
pub struct Options<'a> {
    /// `--camera`.
    pub choice: ModeKind,
    /// `--svg`: one drawing per frame (numbered in output order when there are several).
    pub svg: Option<&'a Path>,
    /// `--npy`: one row per pose read, in input order.
    pub npy: Option<&'a Path>,
    /// `--bone-lengths-out`: each person's lengths.
    pub lengths_out: Option<&'a Path>,
    /// `--force`.
    pub force: bool,
    /// `--sequence-max-poses`.
    pub max_poses: u64,
    /// The `--bvh` and `--html` files: the paths they may take and how they are made from
    /// every frame.
    pub finish: Option<(Vec<PathBuf>, Finish<Kept>)>,
    /// The page's record of a frame.
    pub view: ViewOf<'a>,
    /// Whether the `--bvh` poses are placed in the camera's world (root motion,
    /// `PoseReconstructor::place_in_world`) rather than each at the origin in the body frame.
    pub root_motion: bool,
}

/// The numbered names of `--bone-lengths-out` take `.json` when the name has no extension.
fn lengths_base(out: &Path, count: usize) -> PathBuf {
    if out.extension().is_none() && count > 1 {
        out.with_extension("json")
    } else {
        out.to_path_buf()
    }
}

/// Runs `camloc reconstruct --sequence` (see the module docs).
pub fn run(
    reconstructor: &PoseReconstructor,
    mut inputs: Inputs,
    out: &mut Out,
    format: Format,
    options: Options,
    bar: &ProgressBar,
) -> Result<ExitCode, CliError> {
    // The numbered outputs' targets (refused before any work if they existed,
    // `targets::check`), looked at again after the run (`warn_left_over`).
    let mut numbered = Vec::new();
    if let Some(svg) = options.svg {
        numbered.extend(super::targets::numbered_targets(svg, "svg"));
    }
    if let Some(path) = options.lengths_out {
        numbered.extend(super::targets::numbered_targets(path, "json"));
    }
    numbered.extend(
        options
            .finish
            .iter()
            .flat_map(|(paths, _)| paths.iter().cloned()),
    );
    let keeps = options.finish.is_some();
    check_kept_input(keeps, &inputs)?;
    let mut emit = Emitter::new(format);
    let mut summary = Summary {
        conventions: camloc::InputConventions::aimed(reconstructor.given().intrinsics),
        min_score: inputs.min_score(),
        outside_image: super::outside_image::OutsideImage::new(
            inputs.image_size(),
            reconstructor.given().intrinsics,
        ),
        ..Summary::default()
    };
    let mut kept: Vec<KeypointRecord> = Vec::new();
    // The poses the reader refused (kept in their places without landmarks) and why.
    let mut refused: HashMap<usize, String> = HashMap::new();
    for item in inputs.by_ref() {
        let record = match item {
            Err(e) => match KeypointRecord::of_refused_pose(&e) {
                Some((record, message)) => {
                    report_pose_error(bar, &record.id, &record.source, &message);
                    refused.insert(kept.len(), message);
                    Ok(record)
                }
                None => Err(e),
            },
            Ok(record) => Ok(record),
        };
        match record {
            Err(e) => emit.file_error(out, &mut summary, bar, &e)?,
            Ok(record) => {
                if summary.poses == options.max_poses {
                    return Err(CliError::TooManyPoses(options.max_poses));
                }
                check_kept(keeps, summary.poses + 1)?;
                summary.count(&record.pose);
                kept.push(record);
                bar.inc(1);
            }
        }
    }
    bar.finish_and_clear();
    if summary.poses == 0 && summary.failed_files == 0 {
        return Err(inputs.no_poses());
    }
    emit.end_if_unread(out, inputs.check_read_to_end(summary.failed_files))?;
    let mut keys: Vec<_> = kept.iter().map(|k| (k.frame, k.person)).collect();
    let sources: Vec<&str> = kept.iter().map(|k| k.source.as_str()).collect();
    let (groups, names) = super::videos::followed_sequences(
        &mut keys,
        &sources,
        inputs.is_folder(),
        |i| kept[i].person_is_position,
        |i| camloc::TorsoAnchor::of(&kept[i].pose),
        reconstructor.frame_rate(),
    );
    for (record, key) in kept.iter_mut().zip(&keys) {
        record.person = key.1;
    }
    if let Some(path) = options.lengths_out {
        super::output::name_numbered_persons(&lengths_base(path, groups.len()), &names);
    }
    let mut staged = StagedFiles::new(options.force);
    let mut rows: Vec<Option<Pose3>> =
        vec![None; if options.npy.is_some() { kept.len() } else { 0 }];
    let mut exported: Vec<Kept> = Vec::new();
    // The staged drawings: (pose index, staged file).
    let mut drawn: Vec<(usize, usize)> = Vec::new();
    let mut limits = camloc::LimitCount::default();
    let mut next = 0;
    while next < groups.len() {
        // Persons of a few frames each are solved side by side, in groups of at most
        // PARALLEL_FRAMES frames; a larger person alone.
        let mut end = next + 1;
        let mut frames_in_group = groups[next].1.len();
        while let Some((_, members)) = groups.get(end)
            && frames_in_group + members.len() <= PARALLEL_FRAMES
        {
            frames_in_group += members.len();
            end += 1;
        }
        let group = &groups[next..end];
        let prepared: Vec<Prepared> = group
            .iter()
            .map(|(person, members)| {
                let numbers = super::sequence::frame_numbers(&keys, members);
                let poses = members.iter().map(|&i| kept[i].pose).collect();
                Prepared::of(*person, numbers, poses, reconstructor)
            })
            .collect();
        // The solve of a long sequence takes a while (20,000 frames: tens of seconds) and
        // counts nothing: a spinner says whose it is, when the reading's bar was shown.
        let solving = if bar.is_hidden() {
            ProgressBar::hidden()
        } else {
            let frames = counted(frames_in_group as u64, "frame");
            let whose = match group {
                [(person, _)] => {
                    format!(
                        "person {person} ({} of {}, {frames})",
                        next + 1,
                        groups.len()
                    )
                }
                _ => format!(
                    "persons {} to {} of {} ({frames})",
                    next + 1,
                    end,
                    groups.len()
                ),
            };
            super::progress::spinner(false, &format!("reconstructing {whose}"))
        };
        let solved = solve_persons(
            reconstructor,
            &prepared,
            options.finish.is_some(),
            options.root_motion,
        );
        solving.finish_and_clear();
        for (k, ((person, members), (prepared, solved))) in group
            .iter()
            .zip(prepared.into_iter().zip(solved))
            .enumerate()
        {
            let n = next + k;
            let Prepared {
                numbers,
                swapped_sides,
                left_out,
                ..
            } = prepared;
            let Solved {
                frames,
                lengths,
                lengths_fit,
                animated,
                reconstructed,
            } = solved;
            if let Some(said) = lengths_fit.and_then(|fit| fit.warning()) {
                stderr_line!(
                    "camloc: warning: {}: {said} (--bone-lengths; without it the lengths are \
                     estimated)",
                    names[n]
                );
            }
            super::person_solve::warn_of_sinking(&names[n], &numbers, &animated);
            let in_sequence: Vec<usize> = (0..members.len()).filter(|&m| !left_out[m]).collect();
            // A failed sequence is reported once on standard error, not once per frame (the
            // JSON outputs still hold an error object per frame).
            let whole_failed = lengths.is_none();
            if let (true, Some(&first)) = (whole_failed, in_sequence.first()) {
                let message = frames[first].as_ref().err();
                report_pose_error(
                    bar,
                    &format!(
                        "person {person}, {}",
                        counted(in_sequence.len() as u64, "frame")
                    ),
                    &kept[members[first]].source,
                    message.map_or("", String::as_str),
                );
            }
            let often = camloc::often_filled_frames(&frames, &numbers, reconstructor.frame_rate());
            super::person_solve::warn_of_filled(
                &names[n],
                often,
                reconstructor.given().lengths.is_some(),
            );
            let outputs = members.iter().zip(frames).zip(animated).zip(left_out);
            for ((((&i, frame), pose), left), &sides) in outputs.zip(&swapped_sides) {
                let k = &kept[i];
                if options.finish.is_some() {
                    let (r, error) = match &frame {
                        Ok(r) => (Some(r), None),
                        Err(message) => (None, Some(message.clone())),
                    };
                    exported.push(Kept {
                        key: (k.frame, k.person),
                        source: k.source.clone(),
                        pose,
                        view: (options.view)(k, r, error),
                    });
                }
                match frame {
                    Ok(r) => {
                        let meta = PoseMeta {
                            id: &k.id,
                            source: &k.source,
                            frame: k.frame,
                            person: k.person,
                            left_out: left,
                            swapped_sides: &super::sequence::side_names(sides),
                        };
                        limits.add(r.reconstruction.outside_limits_rad);
                        emit.write(out, &pose_output(format, &meta, options.choice, &r))?;
                        if let Some(svg) = options.svg {
                            let drawing = pose_svg(&k.pose, &k.id, options.choice, &r);
                            // Numbered by the pose's position in the input, as without
                            // --sequence; an input of one pose is renamed to `svg` below.
                            let path = numbered_path(svg, i, 2);
                            drawn.push((i, staged.add(&path, drawing.as_bytes())?));
                        }
                        if let Some(row) = rows.get_mut(i) {
                            *row = Some(r.reconstruction.pose);
                        }
                    }
                    Err(message) => {
                        let message = refused.get(&i).cloned().unwrap_or(message);
                        if refused.contains_key(&i) {
                            summary.failed_poses += 1;
                        } else if nothing_detected(&k.pose) {
                            summary.undetected += 1;
                        } else {
                            summary.failed_poses += 1;
                            if !whole_failed || left {
                                report_pose_error(bar, &k.id, &k.source, &message);
                            }
                        }
                        emit.pose_error(out, k, &message)?;
                    }
                }
            }
            if let (Some(_), 0) = (&lengths, reconstructed) {
                stderr_line!(
                    "camloc: no bone lengths for person {person}: none of its frames was reconstructed"
                );
            }
            if let Some(lengths) = lengths.filter(|_| reconstructed > 0) {
                if format == Format::Text {
                    emit.write(
                        out,
                        &format!(
                            "person {person} ({}): bone lengths (m): {}{}\n",
                            counted(members.len() as u64, "frame"),
                            lengths_text(&lengths),
                            lengths_fit.map_or_else(String::new, |fit| format!(
                                " (given; median reprojection error {:.2} with them, {:.2} with \
                                 lengths estimated from the frames)",
                                fit.given, fit.estimated
                            ))
                        ),
                    )?;
                }
                if let Some(path) = options.lengths_out {
                    staged.add(
                        &numbered_path(&lengths_base(path, groups.len()), n, groups.len()),
                        lengths.to_json_string_of(Some(&names[n])).as_bytes(),
                    )?;
                }
            }
        }
        next = end;
    }
    emit.end(out)?;
    out.flush()?;
    super::reconstruct_output::warn_of_limits(limits);
    if let Some(mut npy) = NpyStage::<Pose3>::boxed(options.npy)? {
        for (record, row) in kept.iter().zip(&rows) {
            npy.push(record, row.as_ref())?;
        }
        npy.finish(&mut staged)?;
    }
    if let Some(svg) = options.svg {
        super::rename_numbered(&mut staged, svg, &drawn, kept.len());
    }
    if let Some((_, finish)) = options.finish {
        finish(exported, &mut staged)?;
    }
    let written = staged.commit()?;
    super::targets::warn_left_over(&numbered, &written);
    Ok(summary.exit_code("reconstructed"))
}
