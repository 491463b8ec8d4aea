//! The videos of an input read as frames of video: one file or standard input is one video;
//! so is a folder of files of one frame each (OpenPose's frame files), whereas a folder whose
//! files hold several frames each (a `.npy` array or a camloc JSON file per camera) holds a
//! video per file, each numbering its frames from 0, which read as one video had every
//! camera's frames smoothed as the first's (a simulated lab user's four corner cameras: 77,
//! 43, 21 and 1% right after smoothing, 85-91% frame by frame).

/// The videos of records with `keys` (`(frame, person)` of each record, in input order) read
/// from `sources` (each record's `file: place`; `folder`: the input is a folder): each file of
/// a folder whose files are videos of their own (any holding poses of two frame numbers or
/// more: its name and its records' positions), else one video of every record (a file,
/// standard input, or a folder of files of one frame each, OpenPose's frame files).
pub fn videos_of<'a, S: AsRef<str>>(
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
    // Each file's place in `videos`: a folder of 40,000 frame files had been searched file by
    // file for every record (11.7 s for `localize --sequence`, 1.1 s without).
    let mut place = std::collections::HashMap::new();
    for (i, source) in sources.iter().enumerate() {
        let file = file_of(source.as_ref());
        let k = *place.entry(file).or_insert_with(|| {
            videos.push((file, Vec::new()));
            videos.len() - 1
        });
        videos[k].1.push(i);
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
