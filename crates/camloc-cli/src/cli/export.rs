//! The files made once every pose of a run is done: `reconstruct --bvh` (one animation per
//! pose, or per person with `--sequence`) and `--html` (one page).

use std::path::{Path, PathBuf};

use camloc::geometry::CameraSet;
use camloc::mocap::{BvhOptions, BvhWriteError, write_person_bvh};
use camloc::reconstruct::FrameRate;
use camloc::store::StagedFiles;
use camloc::{Pose3, frame_slots};

use crate::html::{self, Group, ViewFrame};

use super::stream::KEEP_MAX_POSES;
use super::videos::person_sequences;
use super::{CliError, numbered_path};

/// What `reconstruct` keeps of a pose for `--bvh` and `--html`.
pub struct Kept {
    /// The pose's video frame and person (for `--sequence`).
    pub key: (Option<u64>, Option<u64>),
    /// Where it was read (`file: place`), which tells a folder's videos apart (`--sequence`).
    pub source: String,
    /// Its 3D pose (`--bvh`), `None` where it could not be reconstructed.
    pub pose: Option<Pose3>,
    /// Its record of the page (`--html`).
    pub view: Option<ViewFrame>,
}

/// The [`groups`] of the poses `kept` (`sequence`: with `--sequence`, whether the input is a
/// folder).
pub fn kept_groups(kept: &[Kept], sequence: Option<bool>, each: bool) -> Vec<(String, Vec<usize>)> {
    let keys: Vec<_> = kept.iter().map(|k| k.key).collect();
    let sources: Vec<&str> = kept.iter().map(|k| k.source.as_str()).collect();
    groups(&keys, sequence.map(|folder| (&sources[..], folder)), each)
}

/// The groups of poses a run's outputs are made of: with `sequence` (the poses' `sources` and
/// whether the input is a folder), each person's poses in frame order, a folder of videos a
/// video per file ([`person_sequences`]); without, `each` makes one group per pose, else one
/// group of every pose in input order. Each group has its name.
pub fn groups<S: AsRef<str>>(
    keys: &[(Option<u64>, Option<u64>)],
    sequence: Option<(&[S], bool)>,
    each: bool,
) -> Vec<(String, Vec<usize>)> {
    if let Some((sources, folder)) = sequence {
        let (groups, names) = person_sequences(keys, sources, folder);
        names
            .into_iter()
            .zip(groups)
            .map(|(name, (_, members))| (name, members))
            .collect()
    } else if each {
        (0..keys.len())
            .map(|n| (format!("pose {}", n + 1), vec![n]))
            .collect()
    } else {
        vec![(
            format!("all {} poses", keys.len()),
            (0..keys.len()).collect(),
        )]
    }
}

/// A person's BVH is on the video's timeline when that fills at most this many frames for
/// each frame the person has, plus [`FILL_MIN_FRAMES`] (and [`KEEP_MAX_POSES`] in all);
/// beyond, its frames play one after another: a person seen at frames 0 and 99,999 had
/// made a 60 MB file, and a dozen such persons 800 MB of memory.
const FILL_PER_FRAME: usize = 100;
/// See [`FILL_PER_FRAME`].
const FILL_MIN_FRAMES: usize = 1_000;

/// Stages the BVH files of `kept` at `out` in `staged`, one at a time as each is made (a
/// thousand people seen twice each, 1,200 frames apart, had held 692 MB of BVH text in
/// memory) (numbered as `--svg` drawings when there are several:
/// per person with `sequence`, else per pose by its position in the input): each group's
/// frames as [`write_person_bvh`] writes them (a frame that could not be reconstructed is
/// filled from the frames around it), a person's on the video's timeline ([`frame_slots`]:
/// a frame number without the person is filled too). A group without any reconstructed
/// frame is left out, with a message on standard error (the run has already failed for
/// those poses).
pub fn bvh_files(
    out: &Path,
    kept: &[Kept],
    sequence: Option<bool>,
    fps: f64,
    staged: &mut StagedFiles,
) -> Result<(), CliError> {
    let base = bvh_base(out);
    let keys: Vec<_> = kept.iter().map(|k| k.key).collect();
    let groups = kept_groups(kept, sequence, true);
    let sequence = sequence.is_some();
    if sequence {
        let names: Vec<String> = groups.iter().map(|(name, _)| name.clone()).collect();
        super::output::name_numbered_persons(&base, &names);
    }
    // Persons whose BVH plays its frames one after another, and whose BVH makes frames up:
    // the first few named.
    let mut unfilled = 0u64;
    let mut filling = 0u64;
    for (n, (name, members)) in groups.iter().enumerate() {
        // A person's frames on the video's timeline: a frame where they were not detected
        // is filled, as one that could not be reconstructed is.
        let slots = if sequence {
            let most =
                (FILL_PER_FRAME * members.len() + FILL_MIN_FRAMES).min(KEEP_MAX_POSES as usize);
            let slots = frame_slots(&keys, members, most, |m| kept[members[m]].pose.is_some());
            if slots.is_none() && members.iter().all(|&i| keys[i].0.is_some()) {
                unfilled += 1;
                if unfilled <= super::stream::ERRORS_SHOWN {
                    stderr_line!(
                        "camloc: the BVH of {name} plays its {} one after another: their \
                         frame numbers span more than {most} frames",
                        super::stream::counted(members.len() as u64, "frame")
                    );
                }
            }
            slots
        } else {
            None
        };
        let poses: Vec<Option<Pose3>> = match slots {
            Some(slots) => slots
                .iter()
                .map(|s| s.and_then(|m| kept[members[m]].pose))
                .collect(),
            None => members.iter().map(|&i| kept[i].pose).collect(),
        };
        // Frames the BVH makes up are said, with how many (a simulated animator's person
        // who left the image for 20 frames had glided through them without a word).
        let made_up = poses.iter().filter(|p| p.is_none()).count();
        if sequence && made_up > 0 && made_up < poses.len() {
            filling += 1;
            if filling <= super::stream::ERRORS_SHOWN {
                stderr_line!(
                    "camloc: warning: the BVH of {name} fills {made_up} of its {} from the \
                     frames around them (not reconstructed, or the person not detected there)",
                    super::stream::counted(poses.len() as u64, "frame")
                );
            }
        }
        // The bone lengths: `None` takes the mean limb lengths of the group's poses.
        let text = match write_person_bvh(&poses, None, &BvhOptions::at_fps(fps)) {
            Ok(text) => text,
            Err(BvhWriteError::NoFrames) => {
                if sequence {
                    stderr_line!("camloc: no BVH for {name}: none of its poses was reconstructed");
                }
                continue;
            }
            Err(e) => return Err(CliError::Export(format!("{name}: {e}"))),
        };
        staged.add(&numbered_path(&base, n, groups.len()), text.as_bytes())?;
    }
    if unfilled > super::stream::ERRORS_SHOWN {
        stderr_line!(
            "camloc: the BVHs of {unfilled} persons in all play their frames one after another"
        );
    }
    if filling > super::stream::ERRORS_SHOWN {
        stderr_line!(
            "camloc: warning: the BVHs of {filling} persons in all fill frames from the frames \
             around them"
        );
    }
    Ok(())
}

/// `pose` (pelvis at the origin, z up) moved up so that its lowest landmark is on the floor
/// (height 0): how a single pose's `--bvh` file stands.
pub fn on_the_floor(pose: Pose3) -> Pose3 {
    let floor = pose
        .points
        .iter()
        .map(|q| q[2])
        .fold(f64::INFINITY, f64::min);
    Pose3 {
        points: pose.points.map(|q| [q[0], q[1], q[2] - floor]),
    }
}

/// The path the `--bvh OUT` files are named after: `OUT`, with the extension `.bvh` when it
/// has none (so that numbered names keep it).
pub fn bvh_base(out: &Path) -> PathBuf {
    if out.extension().is_some() {
        out.to_path_buf()
    } else {
        out.with_extension("bvh")
    }
}

/// The `--html` page of `views` in `groups` ([`groups`] without `each`: with `--sequence`
/// one timeline per person), titled `title`, playing at `fps`.
pub fn html_file(
    out: &Path,
    title: &str,
    cameras: &CameraSet,
    views: &[ViewFrame],
    groups: Vec<(String, Vec<usize>)>,
    fps: f64,
) -> (PathBuf, Vec<u8>) {
    let groups: Vec<Group> = groups
        .into_iter()
        .map(|(name, frames)| Group { name, frames })
        .collect();
    let page = html::page(title, cameras, views, &groups, fps);
    (out.to_path_buf(), page.into_bytes())
}

/// Parses `--fps`: frames a second whose frame time a BVH file can hold
/// ([`camloc::frame_rate_problem`]: from one frame an hour to a million a second).
pub fn parse_fps(text: &str) -> Result<f64, String> {
    let fps = text.trim().parse::<f64>().unwrap_or(f64::NAN);
    match camloc::frame_rate_problem(fps) {
        None => Ok(fps),
        Some(problem) => Err(format!("{problem}, got {text:?}")),
    }
}

/// The frame rate `given` with `--fps` (30 when none), or [`CliError::Usage`] when it is
/// given and `timed` (the options it is for, named `takes`) is not.
pub fn fps_for(given: Option<f64>, timed: bool, takes: &str) -> Result<f64, CliError> {
    match given {
        Some(_) if !timed => Err(CliError::Usage(format!(
            "--fps is the frame rate of a video and changes nothing without {takes}"
        ))),
        Some(fps) => Ok(fps),
        None => Ok(FrameRate::default().hz()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fps_is_a_frame_rate_a_bvh_file_can_hold() {
        assert_eq!(parse_fps("25"), Ok(25.0));
        assert_eq!(parse_fps(" 29.97 "), Ok(29.97));
        for bad in ["0", "-5", "1e10", "1e-300", "nan", "inf", "x", ""] {
            assert!(parse_fps(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn groups_are_persons_poses_or_everything() {
        let keys = [(Some(2), Some(1)), (Some(1), Some(1)), (Some(1), Some(0))];
        let sources = ["v.json: poses[0]", "v.json: poses[1]", "v.json: poses[2]"];
        let members =
            |g: Vec<(String, Vec<usize>)>| g.into_iter().map(|(_, m)| m).collect::<Vec<_>>();
        let sequence = Some((&sources[..], true));
        assert_eq!(
            members(groups(&keys, sequence, true)),
            vec![vec![2], vec![1, 0]]
        );
        let none: Option<(&[&str], bool)> = None;
        assert_eq!(
            members(groups(&keys, none, true)),
            vec![vec![0], vec![1], vec![2]]
        );
        assert_eq!(members(groups(&keys, none, false)), vec![vec![0, 1, 2]]);
        assert_eq!(parse_fps("25"), Ok(25.0));
        assert!(parse_fps("0").is_err() && parse_fps("nan").is_err());
    }
}
