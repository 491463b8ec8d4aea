//! The people's sequences of a `--sequence` input (untracked people followed) and the
//! warnings of its repeated frames, video by video ([`camloc::videos_of`]: a file, or a folder of frame files, is one video; a
//! folder of files of several frames each is a video per file).

use camloc::reconstruct::FrameRate;
use camloc::{TorsoAnchor, follow_untracked, sequences, videos_of};

use super::stream::counted;

/// The people's sequences of the poses with `keys` (`(frame, person)` of each record, in
/// input order) read from `sources` (each record's `file: place`; `folder`: the input is a
/// folder), as [`camloc::sequences`] gives them (the person, the records in frame order) with
/// each one's name for files and messages (`person 3`, or `person 3 of cam_a.npy` when the
/// folder's files are videos of their own).
pub fn person_sequences<S: AsRef<str>>(
    keys: &[(Option<u64>, Option<u64>)],
    sources: &[S],
    folder: bool,
) -> (Vec<(u64, Vec<usize>)>, Vec<String>) {
    let (mut groups, mut names) = (Vec::new(), Vec::new());
    for (file, records) in videos_of(keys, sources, folder) {
        let video_keys: Vec<_> = records.iter().map(|&i| keys[i]).collect();
        for (person, members) in sequences(&video_keys) {
            names.push(match file {
                Some(file) => format!("person {person} of {file}"),
                None => format!("person {person}"),
            });
            groups.push((person, members.iter().map(|&m| records[m]).collect()));
        }
    }
    (groups, names)
}

/// The people's sequences of a `--sequence` input, as both commands make them: the poses that
/// repeat a frame and person of their video warned of ([`warn_of_repeats`]), the poses whose
/// person is only their position in the frame (`positional(i)`) given the persons followed
/// from `anchor(i)` at `rate` ([`camloc::follow_untracked`], its warnings on standard error,
/// `keys` rewritten), then [`person_sequences`] of the `keys`.
pub fn followed_sequences<S: AsRef<str>>(
    keys: &mut [(Option<u64>, Option<u64>)],
    sources: &[S],
    folder: bool,
    positional: impl Fn(usize) -> bool,
    anchor: impl Fn(usize) -> Option<TorsoAnchor>,
    rate: FrameRate,
) -> (Vec<(u64, Vec<usize>)>, Vec<String>) {
    warn_of_repeats(keys, sources, folder);
    let followed = follow_untracked(keys, sources, folder, positional, anchor, rate);
    for warning in followed.warnings() {
        stderr_line!("camloc: warning: {warning}");
    }
    person_sequences(keys, sources, folder)
}

/// Warns of the poses that repeat a frame and person of their video
/// ([`warn_of_repeated_frames`], the videos of [`person_sequences`]).
fn warn_of_repeats<S: AsRef<str>>(
    keys: &[(Option<u64>, Option<u64>)],
    sources: &[S],
    folder: bool,
) {
    for (_, records) in videos_of(keys, sources, folder) {
        let video_keys: Vec<_> = records.iter().map(|&i| keys[i]).collect();
        warn_of_repeated_frames(&video_keys);
    }
}

/// Warns on standard error when a (frame, person) key is held by more than one pose: the
/// poses of several videos (two cameras' folders read with `--recursive`), or several people
/// of a frame without person ids (COCO results without `track_id`), would be smoothed as one
/// person.
pub fn warn_of_repeated_frames(keys: &[(Option<u64>, Option<u64>)]) {
    let mut seen = std::collections::HashSet::new();
    let repeated: Vec<&(Option<u64>, Option<u64>)> = keys
        .iter()
        .filter(|(frame, _)| frame.is_some())
        .filter(|key| !seen.insert(**key))
        .collect();
    let Some(&&(Some(frame), person)) = repeated.first() else {
        return;
    };
    let (first, cause) = match person {
        Some(person) => (
            format!("person {person}, frame {frame}"),
            "one track id given to two detections of a frame, or several videos in one \
             input (a folder of several videos' frame files)? give one video per run",
        ),
        None => (
            format!("frame {frame}"),
            "a detector's duplicate or false detection (of a frame's poses the one nearest \
             the person is the person's), several people without person ids, or several \
             videos in one input? give one video per run and each person an id (`person` in \
             camloc JSON, `track_id` in COCO or MMPose)",
        ),
    };
    stderr_line!(
        "camloc: warning: {} repeat{} the frame and person numbers of an earlier pose (first: \
         {first}; {cause})",
        counted(repeated.len() as u64, "pose"),
        if repeated.len() == 1 { "s" } else { "" }
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_folder_of_videos_is_a_video_per_file_and_of_frames_one_video() {
        // Two cameras' arrays of three frames each, one person without an id.
        let keys: Vec<_> = (0..6).map(|i| (Some(i % 3), None)).collect();
        let sources = [
            "a.npy: [0]",
            "a.npy: [1]",
            "a.npy: [2]",
            "b.npy: [0]",
            "b.npy: [1]",
        ];
        let sources: Vec<&str> = sources.into_iter().chain(["b.npy: [2]"]).collect();
        let (groups, names) = person_sequences(&keys, &sources, true);
        assert_eq!(groups, vec![(0, vec![0, 1, 2]), (0, vec![3, 4, 5])]);
        assert_eq!(names, ["person 0 of a.npy", "person 0 of b.npy"]);
        // Not a folder: one video.
        let (groups, names) = person_sequences(&keys, &sources, false);
        assert_eq!(groups.len(), 1);
        assert_eq!(names, ["person 0"]);
        // Frame files (one frame each, the frame from the name): one video.
        let frames: Vec<_> = (0..3).map(|i| (Some(i), Some(0))).collect();
        let files = [
            "f_0.json: people[0]",
            "f_1.json: people[0]",
            "f_2.json: people[0]",
        ];
        let (groups, _) = person_sequences(&frames, &files, true);
        assert_eq!(groups, vec![(0, vec![0, 1, 2])]);
    }
}
