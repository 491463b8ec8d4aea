//! OpenPose JSON (`--write_json`): one file per frame, `people[].pose_keypoints_2d` (OpenPose
//! 1.0 and 1.1: `pose_keypoints`) as x, y, c triples, BODY_25 (75 numbers) or COCO-18 (54
//! numbers).

use std::path::Path;

use serde::de::{MapAccess, SeqAccess};

use crate::ReadOptions;
use crate::emit::{self, ListReader, Sink, TopLevel};
use crate::error::{KeypointError, Location};
use crate::json::{
    Json, get, index_path, key_path, numbers, object, optional, required, tracking_number,
    unit_score,
};
use crate::layout::{COCO18, Joint, Layout, keeps};
use crate::record::{KeypointRecord, from_joints};

/// The largest OpenPose frame file read, in bytes (16 MiB): one frame of about 2,000 people
/// with face and hand keypoints. Larger inputs give
/// [`KeypointError::TooLarge`](crate::KeypointError::TooLarge).
pub const OPENPOSE_FRAME_MAX_BYTES: u64 = 16 << 20;

/// The frame index in an OpenPose file name: the digits that end its stem once `.json` and
/// `_keypoints` are removed (`video_000000000012_keypoints.json` → 12). `None` when the name
/// does not end in `.json` (OpenPose writes no other; a pipe such as `/dev/fd/63` has no
/// frame), when the stem does not end in digits, or when their number is above
/// [`MAX_FRAME_NUMBER`](crate::MAX_FRAME_NUMBER).
pub fn frame_index(file_name: &str) -> Option<u64> {
    let stem = name_without(file_name, ".json")?;
    trailing_number(stem.strip_suffix("_keypoints").unwrap_or(stem))
}

/// The file name of the path `file_name` without `extension` (`.json`, any case); `None` when
/// it does not end in it or is not UTF-8.
pub(crate) fn name_without<'a>(file_name: &'a str, extension: &str) -> Option<&'a str> {
    strip_suffix_ignore_case(Path::new(file_name).file_name()?.to_str()?, extension)
}

/// The number the digits at the end of `stem` make, when there are some and it is at most
/// [`MAX_FRAME_NUMBER`](crate::MAX_FRAME_NUMBER): a video frame's number in its file's name.
pub(crate) fn trailing_number(stem: &str) -> Option<u64> {
    let digits = stem.len() - stem.trim_end_matches(|c: char| c.is_ascii_digit()).len();
    stem[stem.len() - digits..]
        .parse()
        .ok()
        .filter(|&n| n <= crate::MAX_FRAME_NUMBER)
}

/// `text` without `suffix`, compared ignoring ASCII case.
fn strip_suffix_ignore_case<'a>(text: &'a str, suffix: &str) -> Option<&'a str> {
    let cut = text.len().checked_sub(suffix.len())?;
    (text.is_char_boundary(cut) && text[cut..].eq_ignore_ascii_case(suffix)).then(|| &text[..cut])
}

/// One OpenPose frame: an object whose `people` are read one at a time (other keys skipped).
pub(crate) struct Frame;

impl TopLevel for Frame {
    const EXPECTED: &'static str = "an object with \"people\"";

    fn object<'de, A: MapAccess<'de>>(self, map: A, sink: &mut Sink) -> Result<(), A::Error> {
        emit::object_with_list(map, sink, "people", "an array of people", People)
    }
}

/// The `people` of a frame, one person at a time.
struct People;

impl ListReader for People {
    fn read<'de, A: SeqAccess<'de>>(self, seq: A, sink: &mut Sink) -> Result<(), A::Error> {
        let (file, options) = (sink.file, sink.options);
        let frame = frame_index(file);
        let frame_name = match frame {
            Some(frame) => frame.to_string(),
            None => Path::new(file)
                .file_stem()
                .map_or_else(|| file.to_owned(), |s| s.to_string_lossy().into_owned()),
        };
        emit::entries(seq, sink, |person, p| {
            let record = person_record(&person, p, &frame_name, file, options)?;
            Ok(Some(KeypointRecord { frame, ..record }))
        })
    }
}

/// Person `p` of the frame named `frame_name`.
fn person_record(
    person: &Json,
    p: usize,
    frame_name: &str,
    file: &str,
    options: &ReadOptions,
) -> Result<KeypointRecord, KeypointError> {
    let path = index_path("people", p);
    let fields = object(person, "a person object", file, &path)?;
    // OpenPose 1.0 and 1.1 named the keypoints `pose_keypoints`.
    let key = match get(fields, "pose_keypoints_2d") {
        None if get(fields, "pose_keypoints").is_some() => "pose_keypoints",
        _ => "pose_keypoints_2d",
    };
    let kp_path = key_path(&path, key);
    let values = numbers(
        required(fields, key, file, &path)?,
        "an array of x, y, c numbers",
        file,
        &kp_path,
    )?;
    // `--layout body25` (the format's own) says which of the two a person must have.
    let body25_only = options.layout == Some(Layout::Body25);
    let table: &[Joint] = match values.len() {
        75 => Layout::Body25.joints(),
        54 if !body25_only => &COCO18,
        found => {
            return Err(KeypointError::WrongLength {
                file: file.to_owned(),
                at: Location::Path(kp_path),
                expected: 75,
                found,
                items: "numbers",
                what: if body25_only {
                    "BODY_25 x, y, c triples, as --layout body25 says; 54 are COCO-18's: leave \
                     out --layout"
                } else {
                    "BODY_25 x, y, c triples, or 54 for COCO-18"
                },
            });
        }
    };
    let mut points = Vec::with_capacity(table.len());
    for (k, xyc) in values.chunks_exact(3).enumerate() {
        let c_path = index_path(&kp_path, 3 * k + 2);
        let c = unit_score(xyc[2], "confidence", file, &c_path)?;
        points.push(keeps(c, options).then_some([xyc[0], xyc[1]]));
    }
    // OpenPose's tracker writes its id as `person_id: [7]` (`[-1]` without tracking).
    let tracked = optional(fields, "person_id", file, &path)?.and_then(|id| match id {
        Json::Array(ids) => ids.first().and_then(tracking_number),
        other => tracking_number(other),
    });
    Ok(KeypointRecord {
        person: Some(tracked.unwrap_or(p as u64)),
        person_is_position: tracked.is_none(),
        ..from_joints(
            table,
            points,
            format!("{frame_name}/{p}"),
            file,
            &path,
            options,
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_index_from_file_names() {
        assert_eq!(
            frame_index("out/video_000000000012_keypoints.json"),
            Some(12)
        );
        assert_eq!(frame_index("frame_7.JSON"), Some(7));
        assert_eq!(frame_index("12.json"), Some(12));
        assert_eq!(frame_index("video_keypoints.json"), None);
        assert_eq!(frame_index("/dev/fd/63"), None);
        assert_eq!(
            frame_index("a_99999999999999999999999_keypoints.json"),
            None
        );
        assert_eq!(frame_index("é.json"), None);
        assert_eq!(frame_index(""), None);
    }

    /// A tracker's `person_id` is the pose's person; `[-1]` (no tracking) or none leaves the
    /// position in `people`.
    #[test]
    fn tracked_people_keep_their_ids() {
        let kp = vec!["1.0"; 75].join(", ");
        let text = format!(
            r#"{{"people": [{{"person_id": [-1], "pose_keypoints_2d": [{kp}]}},
                            {{"person_id": [7], "pose_keypoints_2d": [{kp}]}},
                            {{"pose_keypoints_2d": [{kp}]}}]}}"#
        );
        let records = crate::parse_keypoints(
            &text,
            "v_000000000003_keypoints.json",
            Some(crate::KeypointFormat::OpenPose),
            &ReadOptions::default(),
        )
        .unwrap();
        let keys: Vec<_> = records.iter().map(|r| (r.frame, r.person)).collect();
        assert_eq!(
            keys,
            [(Some(3), Some(0)), (Some(3), Some(7)), (Some(3), Some(2))]
        );
    }
}
