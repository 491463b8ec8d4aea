//! The supported formats and their detection.

use std::fmt;
use std::ops::RangeInclusive;
use std::str::FromStr;

use crate::error::KeypointError;

/// A keypoint file format this crate reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum KeypointFormat {
    /// camloc JSON, the project's own format (see the crate documentation).
    Camloc,
    /// LSP-14 CSV: `image,joint,x,y,visible`, one row per joint.
    Lsp,
    /// COCO-17 JSON: a dataset file with `annotations`, or a results list.
    Coco,
    /// OpenPose JSON, one file per frame: `people[].pose_keypoints_2d` (BODY_25 or COCO-18).
    OpenPose,
    /// MMPose predictions: `keypoints` as `[[x, y], ...]` plus `keypoint_scores`.
    MmPose,
    /// MediaPipe Pose: a list of frames of 33 `{x, y, z, visibility}` normalised landmarks.
    MediaPipe,
    /// A NumPy `.npy` array of shape (N, J, 2) or (N, J, 3) in a [`Layout`](crate::Layout).
    Npy,
    /// MPII annotations in their common JSON form: `[{"image", "joints", "joints_vis"}]`.
    Mpii,
    /// Ultralytics YOLO pose text, one `.txt` file per image or frame: a line per person of
    /// class, box and 17 COCO keypoints, normalised.
    Yolo,
}

impl KeypointFormat {
    /// All formats.
    pub const ALL: [KeypointFormat; 9] = [
        KeypointFormat::Camloc,
        KeypointFormat::Lsp,
        KeypointFormat::Coco,
        KeypointFormat::OpenPose,
        KeypointFormat::MmPose,
        KeypointFormat::MediaPipe,
        KeypointFormat::Npy,
        KeypointFormat::Mpii,
        KeypointFormat::Yolo,
    ];

    /// The names of [`KeypointFormat::ALL`], comma-separated (for messages and help texts).
    pub const NAMES: &'static str =
        "camloc, lsp, coco, openpose, mmpose, mediapipe, npy, mpii, yolo";

    /// Short lower-case name (`camloc`, `lsp`, `coco`, `openpose`, `mmpose`, `mediapipe`, `npy`,
    /// `mpii`, `yolo`), as accepted by [`str::parse`].
    pub const fn name(self) -> &'static str {
        match self {
            KeypointFormat::Camloc => "camloc",
            KeypointFormat::Lsp => "lsp",
            KeypointFormat::Coco => "coco",
            KeypointFormat::OpenPose => "openpose",
            KeypointFormat::MmPose => "mmpose",
            KeypointFormat::MediaPipe => "mediapipe",
            KeypointFormat::Npy => "npy",
            KeypointFormat::Mpii => "mpii",
            KeypointFormat::Yolo => "yolo",
        }
    }

    /// `true` for the JSON formats (all but LSP CSV, `.npy` arrays and YOLO text).
    pub const fn is_json(self) -> bool {
        !matches!(
            self,
            KeypointFormat::Lsp | KeypointFormat::Npy | KeypointFormat::Yolo
        )
    }

    /// Guesses the format of a file from its extension (without the dot, any case) and content.
    ///
    /// * `npy` → [`Npy`](KeypointFormat::Npy). (Text cannot start with NumPy's magic bytes
    ///   `\x93NUMPY`; the byte readers, e.g. [`parse_keypoints_bytes`](crate::parse_keypoints_bytes),
    ///   recognise arrays by them before looking at text.)
    /// * `csv` → [`Lsp`](KeypointFormat::Lsp).
    /// * `json`, or any other or no extension when the content starts with `{` or `[`: by the
    ///   first of these object keys found: `"people"` → OpenPose; `"poses"`, or `"landmarks"`
    ///   holding an object → camloc; `"keypoint_scores"`, `"instance_info"` or `"instances"`
    ///   → MMPose;
    ///   `"joints_vis"`, or `"center"` and `"scale"` without `"keypoints"` or `"image_id"` (the
    ///   test split, which has no joints) → MPII; `"visibility"` or `"x"`, `"landmark"` or
    ///   `"landmarks"` holding a list, or a list whose first element is a list or `null` →
    ///   MediaPipe; `"annotations"` or `"keypoints"`, or any other top-level list →
    ///   COCO.
    /// * `txt` not starting with `{` or `[`: LSP CSV when its first line names LSP's columns,
    ///   else [`Yolo`](KeypointFormat::Yolo) when that line is numbers or the text is blank.
    /// * Other extensions: content whose first non-blank line names the columns `image` and
    ///   `joint` is LSP CSV; one of 39-41 or 56-58 numbers is YOLO pose text.
    ///
    /// Returns `None` when nothing matches. Only looks at the text; it does not validate it.
    pub fn from_extension_and_content(
        extension: Option<&str>,
        content: &str,
    ) -> Option<KeypointFormat> {
        let content = content.trim_start_matches('\u{feff}').trim_start();
        let extension = extension.map(str::to_ascii_lowercase);
        match extension.as_deref() {
            Some("npy") => Some(KeypointFormat::Npy),
            Some("csv") => Some(KeypointFormat::Lsp),
            // A YOLO frame where nobody was detected is an empty file.
            Some("txt") if content.is_empty() => Some(KeypointFormat::Yolo),
            Some("txt") if !content.starts_with(['{', '[']) => {
                sniff_csv(content).or_else(|| sniff_yolo(content, 1..=usize::MAX))
            }
            Some("json") => sniff_json(content),
            _ if content.starts_with(['{', '[']) => sniff_json(content),
            _ => sniff_csv(content).or_else(|| sniff_yolo(content, 39..=58)),
        }
    }
}

/// The first bytes of every `.npy` file.
pub(crate) const NPY_MAGIC: &[u8] = b"\x93NUMPY";

/// The JSON format of `content` (leading white space removed).
fn sniff_json(content: &str) -> Option<KeypointFormat> {
    use KeypointFormat::*;
    let any = |keys: &[&str]| keys.iter().any(|k| has_key(content, k));
    let list_of_lists = content
        .strip_prefix('[')
        .is_some_and(|rest| rest.trim_start().starts_with(['[', 'n']));
    // MediaPipe frames wrapped in objects hold a list of landmarks; camloc's an object.
    let landmark_lists = ["landmarks", "landmark"]
        .iter()
        .any(|k| value_starts(content, k, '['));
    if any(&["people"]) {
        Some(OpenPose)
    } else if any(&["poses"]) || (any(&["landmarks"]) && !landmark_lists) {
        Some(Camloc)
    } else if any(&["keypoint_scores", "instance_info", "instances"]) {
        Some(MmPose)
    } else if any(&["joints_vis"])
        // MPII's test split: its entries have a person's box but no joints.
        || (any(&["center"]) && any(&["scale"]) && !any(&["keypoints", "image_id"]))
    {
        Some(Mpii)
    } else if list_of_lists || landmark_lists || any(&["visibility", "x"]) {
        Some(MediaPipe)
    } else if content.starts_with('[') || any(&["annotations", "keypoints"]) {
        Some(Coco)
    } else {
        None
    }
}

/// `true` when `"key"` appears followed by `:` (an object key, not a string value).
fn has_key(content: &str, key: &str) -> bool {
    key_values(content, key).next().is_some()
}

/// `true` when `"key"` appears as an object key whose value starts with `start`.
fn value_starts(content: &str, key: &str, start: char) -> bool {
    key_values(content, key).any(|value| value.starts_with(start))
}

/// The text after each `"key":` of `content` (white space removed).
fn key_values<'a>(content: &'a str, key: &str) -> impl Iterator<Item = &'a str> {
    let quoted = format!("\"{key}\"");
    let after: Vec<usize> = content
        .match_indices(&quoted)
        .map(|(at, _)| at + quoted.len())
        .collect();
    after.into_iter().filter_map(move |at| {
        content[at..]
            .trim_start()
            .strip_prefix(':')
            .map(str::trim_start)
    })
}

/// LSP CSV when the first non-blank line has `image` and `joint` columns.
fn sniff_csv(content: &str) -> Option<KeypointFormat> {
    let header = content.lines().find(|l| !l.trim().is_empty())?;
    let has = |column: &str| crate::lsp::csv_fields(header).any(|c| c.eq_ignore_ascii_case(column));
    (has("image") && has("joint")).then_some(KeypointFormat::Lsp)
}

/// YOLO pose text when the first non-blank line is numbers, as many as `counts` allows
/// (without an extension: 39-41 or 56-58, a class, a box and 17 keypoints of 2 or 3 numbers,
/// then at most a confidence and a track id).
fn sniff_yolo(content: &str, counts: RangeInclusive<usize>) -> Option<KeypointFormat> {
    let line = content.lines().find(|l| !l.trim().is_empty())?;
    let words: Vec<&str> = line.split_whitespace().collect();
    let numbers = words.iter().all(|w| w.parse::<f64>().is_ok());
    let shaped = counts.contains(&words.len()) && !matches!(words.len(), 42..=55);
    (numbers && shaped).then_some(KeypointFormat::Yolo)
}

impl fmt::Display for KeypointFormat {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A format name that is not one of [`KeypointFormat::NAMES`].
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "unknown keypoint format \"{}\" (expected one of: {})",
    crate::error::clip(.0),
    KeypointFormat::NAMES
)]
pub struct UnknownFormatName(pub String);

impl FromStr for KeypointFormat {
    type Err = UnknownFormatName;

    /// Parses a name of [`KeypointFormat::name`], ignoring ASCII case.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        KeypointFormat::ALL
            .into_iter()
            .find(|f| f.name().eq_ignore_ascii_case(s.trim()))
            .ok_or_else(|| UnknownFormatName(s.to_owned()))
    }
}

/// [`KeypointError::CamlocFile`] when `start` (an input's first bytes) begins with the magic
/// bytes of a file camloc writes (`camloc_store::KINDS`);
/// [`KeypointError::NotKeypoints`] when it begins as a ZIP archive (an `.npz`) or text in
/// UTF-16 (with or without a byte-order mark) or UTF-32 does.
pub(crate) fn not_keypoints(start: &[u8], file: &str) -> Option<KeypointError> {
    if let Some(kind) = camloc_store::KINDS
        .iter()
        .find(|k| start.starts_with(&k.magic))
    {
        return Some(KeypointError::CamlocFile {
            file: file.to_owned(),
            what: kind.what,
        });
    }
    // (UTF-32's little-endian mark begins as UTF-16's.)
    let (what, hint) = if start.starts_with(b"PK\x03\x04") {
        (
            "a ZIP archive",
            "an .npz holds several .npy arrays: give the one of keypoints",
        )
    } else if start.starts_with(b"\xFF\xFE\0\0") || start.starts_with(b"\0\0\xFE\xFF") {
        ("UTF-32 text", "save it as UTF-8")
    } else if start.starts_with(b"\xFF\xFE") || start.starts_with(b"\xFE\xFF") || utf16(start) {
        ("UTF-16 text", "save it as UTF-8")
    } else {
        return None;
    };
    Some(KeypointError::NotKeypoints {
        file: file.to_owned(),
        what,
        hint,
    })
}

/// `true` when `start` begins as UTF-16 text without a byte-order mark: two ASCII characters
/// (a JSON document's `{` or `[` and the next), each beside a zero byte.
fn utf16(start: &[u8]) -> bool {
    let ascii = |b: u8| (0x09..0x7F).contains(&b);
    match start {
        [a, 0, b, 0, ..] | [0, a, 0, b, ..] => ascii(*a) && ascii(*b),
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn detection_by_extension_and_content() {
        use KeypointFormat::*;
        let detect = KeypointFormat::from_extension_and_content;
        assert_eq!(detect(Some("CSV"), "{}"), Some(Lsp));
        assert_eq!(
            detect(
                Some("json"),
                r#"{"format": "camloc-keypoints", "poses": []}"#
            ),
            Some(Camloc)
        );
        assert_eq!(
            detect(Some("json"), "\u{feff} {\"landmarks\" : {}}"),
            Some(Camloc)
        );
        assert_eq!(
            detect(Some("json"), r#"{"images": [], "annotations": []}"#),
            Some(Coco)
        );
        assert_eq!(detect(Some("json"), r#"  [{"image_id": 1}]"#), Some(Coco));
        // A string value is not a key.
        assert_eq!(
            detect(Some("json"), r#"{"id": "poses", "annotations": []}"#),
            Some(Coco)
        );
        assert_eq!(detect(Some("json"), r#"{"a": 1}"#), None);
        assert_eq!(detect(None, "\n image, joint,x,y,visible\n"), Some(Lsp));
        assert_eq!(detect(Some("txt"), r#"{"poses": []}"#), Some(Camloc));
        assert_eq!(detect(Some("txt"), ""), Some(Yolo));
        assert_eq!(detect(None, &format!("0{}", " 0.5".repeat(55))), Some(Yolo));
        assert_eq!(detect(None, &format!("0{}", " 0.5".repeat(50))), None);
        assert_eq!(detect(None, "hello"), None);
        assert_eq!(detect(Some("NPY"), ""), Some(Npy));
        assert_eq!(
            detect(Some("json"), r#"{"version": 1.3, "people": []}"#),
            Some(OpenPose)
        );
        assert_eq!(
            detect(
                Some("json"),
                r#"[{"keypoints": [], "keypoint_scores": []}]"#
            ),
            Some(MmPose)
        );
        assert_eq!(
            detect(None, r#"{"meta_info": {}, "instance_info": []}"#),
            Some(MmPose)
        );
        assert_eq!(
            detect(Some("json"), r#"[{"image": "a.jpg", "joints_vis": []}]"#),
            Some(KeypointFormat::Mpii)
        );
        assert_eq!(
            detect(
                Some("json"),
                r#"[{"image": "a.jpg", "center": [1, 2], "scale": 1.0}]"#
            ),
            Some(Mpii)
        );
        assert_eq!(detect(Some("json"), " [ [{\"x\": 0.5}]]"), Some(MediaPipe));
        assert_eq!(detect(Some("json"), "[null, []]"), Some(MediaPipe));
        assert_eq!(
            detect(Some("json"), r#"[{"x": 0.5, "y": 1}]"#),
            Some(MediaPipe)
        );
        assert_eq!(detect(None, ""), None);
    }

    #[test]
    fn names_round_trip() {
        for f in KeypointFormat::ALL {
            assert_eq!(f.name().parse::<KeypointFormat>(), Ok(f));
            assert_eq!(
                f.to_string().to_uppercase().parse::<KeypointFormat>(),
                Ok(f)
            );
        }
        assert!("mpii16".parse::<KeypointFormat>().is_err());
    }
}
