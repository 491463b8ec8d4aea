//! The videos of a `--sequence` input: one file or standard input is one video; so is a
//! folder of files of one frame each (OpenPose's frame files), whereas a folder whose files
//! hold several frames each (a `.npy` array or a camloc JSON file per camera) holds a video
//! per file, each numbering its frames from 0, which read as one video had every camera's
//! frames smoothed as the first's (a simulated lab user's four corner cameras: 77, 43, 21 and
//! 1% right after smoothing, 85-91% frame by frame).

use camloc::sequences;

use super::sequence::warn_of_repeated_frames;

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
    for (file, records) in videos(keys, sources, folder) {
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

/// Warns of the poses that repeat a frame and person of their video
/// ([`warn_of_repeated_frames`], the videos of [`person_sequences`]).
pub fn warn_of_repeats<S: AsRef<str>>(
    keys: &[(Option<u64>, Option<u64>)],
    sources: &[S],
    folder: bool,
) {
    for (_, records) in videos(keys, sources, folder) {
        let video_keys: Vec<_> = records.iter().map(|&i| keys[i]).collect();
        warn_of_repeated_frames(&video_keys);
    }
}

/// The videos of the records: each file of a folder whose files are videos of their own
/// ([`file_videos`]: its name and its records' positions), else one video of every record.
fn videos<'a, S: AsRef<str>>(
    keys: &[(Option<u64>, Option<u64>)],
    sources: &'a [S],
    folder: bool,
) -> Vec<(Option<&'a str>, Vec<usize>)> {
    match folder.then(|| file_videos(keys, sources)).flatten() {
        Some(videos) => videos.into_iter().map(|(f, r)| (Some(f), r)).collect(),
        None => vec![(None, (0..keys.len()).collect())],
    }
}

/// The records of each file of a folder (the file's name, its records' positions, files in
/// the order they were read) when any file holds poses of two frame numbers or more (a video
/// of its own); `None` when every file is one frame (the folder is one video).
fn file_videos<'a, S: AsRef<str>>(
    keys: &[(Option<u64>, Option<u64>)],
    sources: &'a [S],
) -> Option<Vec<(&'a str, Vec<usize>)>> {
    let mut videos: Vec<(&str, Vec<usize>)> = Vec::new();
    for (i, source) in sources.iter().enumerate() {
        let file = file_of(source.as_ref());
        match videos.iter_mut().rev().find(|(f, _)| *f == file) {
            Some((_, records)) => records.push(i),
            None => videos.push((file, vec![i])),
        }
    }
    let several_frames = |records: &Vec<usize>| {
        let mut frames = records.iter().filter_map(|&i| keys[i].0);
        frames
            .next()
            .is_some_and(|first| frames.any(|frame| frame != first))
    };
    videos
        .iter()
        .any(|(_, records)| several_frames(records))
        .then_some(videos)
}

/// The file of a record's `source` (`file: place`; a place has no `": "`).
fn file_of(source: &str) -> &str {
    source.rsplit_once(": ").map_or(source, |(file, _)| file)
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
