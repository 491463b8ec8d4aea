//! The error type of every reader, and where in the input an error is.

use std::fmt;

use camloc_skeleton::Landmark;

use crate::array_pose::ArrayPoseError;

/// Where in an input a problem was found.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Location {
    /// A 1-based line of a text file (CSV).
    Line(usize),
    /// A JSON path such as `poses[2].landmarks.left_knee`; the empty path is the top-level value.
    Path(String),
    /// An element of a `.npy` array: `[pose]`, `[pose, joint]` or `[pose, joint, channel]`
    /// (0-based), or the whole array's `shape` when empty.
    Array(Box<[u64]>),
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::Line(line) => write!(f, "line {line}"),
            Location::Path(path) if path.is_empty() => f.write_str("top level"),
            Location::Path(path) => write!(f, "{}", clip(path)),
            Location::Array(index) if index.is_empty() => f.write_str("shape"),
            Location::Array(index) => {
                let index: Vec<String> = index.iter().map(u64::to_string).collect();
                write!(f, "[{}]", index.join(", "))
            }
        }
    }
}

/// Everything that can go wrong while reading a keypoint file.
///
/// `file` is the name the input was read under (a path, or the `source_name` given to
/// [`parse_keypoints`](crate::parse_keypoints)); every message starts with it, followed by the
/// line or JSON path of the problem when there is one.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum KeypointError {
    /// The file could not be opened or read (missing, a directory, no permission, ...).
    #[error("{}: cannot read the file: {source}",
        file_name(.file))]
    Io {
        /// The path as given.
        file: String,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// The input holds nothing but white space.
    #[error("{}: the input is empty",
        file_name(.file))]
    Empty {
        /// Name of the input.
        file: String,
    },
    /// The input is longer than the limit for its format: [`ReadOptions::max_bytes`](crate::ReadOptions::max_bytes), and for one OpenPose frame also
    /// [`OPENPOSE_FRAME_MAX_BYTES`](crate::OPENPOSE_FRAME_MAX_BYTES).
    #[error(
        "{}: the input has at least {bytes} bytes, more than the limit of {limit} bytes ({rule})",
        file_name(.file)
    )]
    TooLarge {
        /// Name of the input.
        file: String,
        /// Size of the input in bytes (a lower bound when the size was not known in advance).
        bytes: u64,
        /// The limit in bytes.
        limit: u64,
        /// Which limit: `--max-input-bytes; Python max_input_bytes=; Rust
        /// ReadOptions::max_bytes` or `OPENPOSE_FRAME_MAX_BYTES, one frame`.
        rule: &'static str,
    },
    /// A file of a folder listing that is not a regular file once links are followed (read
    /// only when named as the input itself).
    #[error(
        "{}: is a {kind}, not a regular file (a folder's files must be regular files)",
        file_name(.file)
    )]
    NotRegular {
        /// Name of the file.
        file: String,
        /// What it is: `dangling symbolic link`, `FIFO`, `character device`, ...
        kind: &'static str,
    },
    /// The input is a file camloc wrote (a dataset, model, pose basis or depth lifter), not
    /// keypoints.
    #[error("{}: this is a camloc {what} file, not keypoints", file_name(.file))]
    CamlocFile {
        /// Name of the input.
        file: String,
        /// What kind of camloc file ("dataset", "model", ...).
        what: &'static str,
    },
    /// The input is a file of another kind that is often taken for keypoints (a ZIP archive
    /// such as an `.npz`, UTF-16 or UTF-32 text).
    #[error("{}: this is {what}, not keypoints: {hint}", file_name(.file))]
    NotKeypoints {
        /// Name of the input.
        file: String,
        /// What it is: `a ZIP archive`, `UTF-16 text`, ...
        what: &'static str,
        /// What to do instead.
        hint: &'static str,
    },
    /// The input is not valid UTF-8.
    #[error("{}: line {line}: not valid UTF-8 (invalid byte at offset {offset})",
        file_name(.file))]
    NotUtf8 {
        /// Name of the input.
        file: String,
        /// 1-based line of the first invalid byte.
        line: usize,
        /// 0-based byte offset of the first invalid byte.
        offset: usize,
    },
    /// No format was given and none could be told from the extension and the content.
    #[error(
        "{}: cannot tell the keypoint format ({}); name it: {}",
        file_name(.file),
        clip(reason),
        crate::KeypointFormat::NAMES
    )]
    UnknownFormat {
        /// Name of the input.
        file: String,
        /// What was looked at.
        reason: String,
    },
    /// The text is not JSON, or a value has a type a COCO reader cannot take (reported by the
    /// JSON parser, with line and column).
    #[error("{}: line {line}, column {column}: {}{}",
        file_name(.file), clip(message), json_hint(message, *line, *column))]
    Json {
        /// Name of the input.
        file: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The parser's message.
        message: String,
    },
    /// The CSV header does not name exactly the columns `image,joint,x,y,visible`.
    #[error(
        "{}: line {line}: the header must name the columns image,joint,x,y,visible \
         (found \"{}\"; missing: {}; unknown or repeated: {})",
        file_name(.file),
        clip(header),
        list_or_none(missing),
        header_columns(extra, *extra_count)
    )]
    CsvHeader {
        /// Name of the input.
        file: String,
        /// 1-based line of the header.
        line: usize,
        /// The header line as found.
        header: String,
        /// Required columns that are absent.
        missing: Vec<String>,
        /// Columns that are not expected, or named twice: the first [`MAX_QUOTED_ITEMS`].
        extra: Vec<String>,
        /// How many columns are not expected or named twice.
        extra_count: usize,
    },
    /// A CSV row has a different number of fields than the header.
    #[error(
        "{}: line {line}: expected {expected} comma-separated fields (as in the header), found {found}",
        file_name(.file)
    )]
    CsvFieldCount {
        /// Name of the input.
        file: String,
        /// 1-based line.
        line: usize,
        /// Number of columns in the header.
        expected: usize,
        /// Number of fields in this row.
        found: usize,
    },
    /// A CSV row names a joint the format does not have.
    #[error(
        "{}: {at}: unknown joint \"{}\" (expected one of: {expected})",
        file_name(.file),
        clip(name)
    )]
    UnknownJoint {
        /// Name of the input.
        file: String,
        /// Where.
        at: Location,
        /// The joint name as found.
        name: String,
        /// The joint names of the format, comma-separated.
        expected: String,
    },
    /// A joint is given twice for the same image.
    #[error(
        "{}: {at}: joint \"{}\" of image \"{}\" given twice (first at {first})",
        file_name(.file),
        clip(joint),
        clip(image)
    )]
    DuplicateJoint {
        /// Name of the input.
        file: String,
        /// Where the second occurrence is.
        at: Location,
        /// Where the first occurrence is.
        first: Location,
        /// The image the joint belongs to.
        image: String,
        /// The joint name.
        joint: String,
    },
    /// A JSON object has keys the format does not define (all of them are listed).
    #[error("{}", unknown_keys(file, at, keys, suggestions, allowed))]
    UnknownKeys {
        /// Name of the input.
        file: String,
        /// Path of the object.
        at: Location,
        /// The unknown keys, in the order found.
        keys: Vec<String>,
        /// Per unknown key (the first [`MAX_QUOTED_ITEMS`]), the allowed key nearest it (at
        /// most 2 letters changed, inserted or deleted, case aside, `l_` and `r_` read as
        /// `left_` and `right_`), if any.
        suggestions: Box<[Option<&'static str>]>,
        /// The allowed keys, comma-separated (the format's own list, given whole).
        allowed: String,
    },
    /// A JSON object has the same key twice.
    #[error("{}: {at}: key given twice",
        file_name(.file))]
    DuplicateKey {
        /// Name of the input.
        file: String,
        /// Path of the repeated key.
        at: Location,
    },
    /// A required JSON key is absent.
    #[error("{}: {at}: missing required key \"{key}\"{}",
        file_name(.file), if *.read_as_coco { COCO_MISSING_KEY_HINT } else { "" })]
    MissingKey {
        /// Name of the input.
        file: String,
        /// Path of the object.
        at: Location,
        /// The missing key.
        key: &'static str,
        /// The input was read as COCO keypoints, the format any JSON list of objects is taken
        /// for: another tool's JSON lacks its keys, and the message says so.
        read_as_coco: bool,
    },
    /// A JSON value has the wrong type.
    #[error("{}: {at}: expected {expected}, found {found}",
        file_name(.file))]
    WrongType {
        /// Name of the input.
        file: String,
        /// Path of the value.
        at: Location,
        /// What the format wants there.
        expected: &'static str,
        /// The JSON type found.
        found: &'static str,
    },
    /// A JSON array has the wrong number of elements (a landmark not `[u, v]`, COCO keypoints
    /// not 51 numbers, a MediaPipe frame not 33 landmarks).
    #[error("{}: {at}: expected {expected} {items} ({what}), found {found}",
        file_name(.file))]
    WrongLength {
        /// Name of the input.
        file: String,
        /// Path of the array.
        at: Location,
        /// Required length.
        expected: usize,
        /// Length found.
        found: usize,
        /// What the elements are: `numbers`, `landmarks`, `joints`, `flags`.
        items: &'static str,
        /// What the array holds.
        what: &'static str,
    },
    /// A field does not hold what it must (a coordinate that is not a number, a visibility flag
    /// other than 0 or 1, an empty image name, a wrong format tag).
    #[error("{}: {at}: {field} \"{}\" is not {expected}",
        file_name(.file), clip(text))]
    InvalidValue {
        /// Name of the input.
        file: String,
        /// Where.
        at: Location,
        /// The field (column or key).
        field: &'static str,
        /// The value as found.
        text: String,
        /// What is allowed there.
        expected: &'static str,
    },
    /// A joint layout given for a format that names or fixes its joints itself (a layout
    /// applies to `.npy` arrays and MMPose keypoints).
    #[error(
        "{}: a layout ({layout}) was given, but {format} input names or fixes its joints \
         itself: a layout applies to .npy arrays and MMPose keypoints (leave out --layout; \
         Python layout=)",
        file_name(.file)
    )]
    LayoutNotUsed {
        /// Name of the input.
        file: String,
        /// Its format's name.
        format: &'static str,
        /// The name of the layout given.
        layout: &'static str,
    },
    /// A 17-joint pose whose first five joints contradict its layout
    /// ([`contradicted`](crate::contradicted)): COCO-17 data read as
    /// Human3.6M or the reverse. `source` is [`ArrayPoseError::LayoutMismatch`].
    #[error("{}: {at}: {source} (--layout; Python layout=)", file_name(.file))]
    LayoutMismatch {
        /// Name of the input.
        file: String,
        /// Where: the pose.
        at: Location,
        /// What the joints look like.
        source: ArrayPoseError,
        /// The refused pose's place, so that outputs of one row per pose keep its row.
        place: Box<PosePlace>,
    },
    /// A row of a keypoint array with a value no pose holds (an infinity, a NaN score, one
    /// coordinate NaN): that row's error, `error` naming the file and the element; the rows
    /// after it are read.
    #[error("{error}")]
    BadRow {
        /// The error naming the file and the element.
        error: Box<KeypointError>,
        /// What is wrong, without the file and the row its place names.
        why: String,
        /// The refused row's place.
        place: Box<PosePlace>,
    },
    /// A coordinate is NaN or infinite.
    #[error("{}: {at}: {field} \"{}\" is not a finite number",
        file_name(.file), clip(text))]
    NonFinite {
        /// Name of the input.
        file: String,
        /// Where.
        at: Location,
        /// The field (column or key).
        field: &'static str,
        /// The value as found.
        text: String,
    },
    /// A camloc JSON document has a `version` this reader does not understand.
    #[error(
        "{}: {at}: unsupported camloc-keypoints version {} (this reader reads version 1, a number)",
        file_name(.file),
        clip(found)
    )]
    UnsupportedVersion {
        /// Name of the input.
        file: String,
        /// Path of the `version` key.
        at: Location,
        /// The version as found: a number, `"text" (a string)`, or the JSON type.
        found: String,
    },
    /// A keypoint score outside the range its format defines (OpenPose confidences and
    /// MediaPipe visibilities are in [0, 1], as are the scores of `(N, J, 3)` arrays).
    #[error("{}: {at}: {what} {score:?} is outside [0, 1]{hint}", file_name(.file))]
    ScoreOutOfRange {
        /// Name of the input.
        file: String,
        /// Where.
        at: Location,
        /// What the number is (`confidence`, `visibility`, `score`).
        what: &'static str,
        /// The value found.
        score: f64,
        /// A hint for the likely cause, empty or starting with `; `.
        hint: &'static str,
    },
    /// A score above [`SCORE_SCALE_LIMIT`](crate::SCORE_SCALE_LIMIT) in a format whose scores
    /// are not range-checked (COCO, MMPose) while `min_score` is in (0, 1]: the scores are on
    /// another scale (0-100) than the threshold, which would keep every joint.
    #[error(
        "{}: {at}: score {score:?} is on another scale than the minimum score {min_score:?} (0-1): \
         give the minimum on the scores' scale (--min-score; e.g. 30 for scores of 0-100)",
        file_name(.file)
    )]
    ScoreScale {
        /// Name of the input.
        file: String,
        /// Where.
        at: Location,
        /// The score found.
        score: f64,
        /// The minimum score asked for.
        min_score: f64,
    },
    /// A pose has a number of joints that the layout does not have.
    #[error("{}: {at}: {found} joints: {what}",
        file_name(.file))]
    JointCount {
        /// Name of the input.
        file: String,
        /// Where (the array's `shape`, or the JSON path of the keypoint list).
        at: Location,
        /// Number of joints found.
        found: u64,
        /// What was expected, e.g. `layout coco17 has 17` or `no layout has 13 (...)`.
        what: String,
    },
    /// A joint has one coordinate NaN and the other not (both NaN marks a missing joint).
    #[error(
        "{}: {at}: one coordinate is NaN and the other is not (NaN, NaN marks a missing joint)",
        file_name(.file)
    )]
    HalfMissing {
        /// Name of the input.
        file: String,
        /// The element `[pose, joint]`.
        at: Location,
    },
    /// The input has normalised coordinates and no image size was given.
    #[error(
        "{}: {format} coordinates are normalised to [0, 1]: give the image size in pixels \
         (--image-size W,H; Python image_size=; Rust ReadOptions::image_size)",
        file_name(.file)
    )]
    ImageSizeNeeded {
        /// Name of the input.
        file: String,
        /// The format (`MediaPipe`).
        format: &'static str,
    },
    /// A `.npy` file whose header, type, shape or length cannot be read as keypoints.
    #[error("{}: {problem}",
        file_name(.file))]
    Npy {
        /// Name of the input.
        file: String,
        /// What is wrong, e.g. `shape (4, 15) is not (N, J, 2) or (N, J, 3)`.
        problem: String,
    },
    /// Returned by [`KeypointRecord::require_torso`](crate::KeypointRecord::require_torso): the
    /// pose lacks the pelvis or the neck, and neither file nor derivation supplied it.
    #[error(
        "{}: pose \"{}\" has no {} (and it could not be derived from the hips/shoulders); \
         the torso is needed",
        file_name(origin),
        clip(id),
        landmark_list(missing)
    )]
    MissingTorso {
        /// The pose id.
        id: String,
        /// Where the pose came from ([`KeypointRecord::source`](crate::KeypointRecord::source)).
        origin: String,
        /// The missing torso landmarks (pelvis, neck or both).
        missing: Vec<Landmark>,
    },
    /// [`ReadOptions::min_score`](crate::ReadOptions::min_score) is NaN, infinite or
    /// negative: a NaN would mark every joint missing.
    #[error(
        "{}: the minimum score {value:?} is not a finite number >= 0 (ReadOptions::min_score)",
        file_name(.file)
    )]
    InvalidMinScore {
        /// The input being opened.
        file: String,
        /// The minimum score given.
        value: f64,
    },
}

pub use camloc_store::{MAX_QUOTED_CHARS, MAX_QUOTED_PATH_CHARS};

/// The most items of a list of input pieces (unknown keys, header columns) that an error message
/// names; the rest are counted (`… and 999 more`). The names shown take at most
/// [`MAX_QUOTED_CHARS`] characters in all.
pub const MAX_QUOTED_ITEMS: usize = 8;

/// The message of [`KeypointError::UnknownKeys`]: the unknown keys as [`capped_list`] gives
/// them, each with its suggestion (`"nek" (did you mean "neck"?)`; one key: `"nek", did you
/// mean "neck"?`), then the `allowed` keys when some key, shown or not, has none.
fn unknown_keys(
    file: &str,
    at: &Location,
    keys: &[String],
    suggestions: &[Option<&'static str>],
    allowed: &str,
) -> String {
    let suggestion = |i: usize| suggestions.get(i).copied().flatten();
    let list = capped_list_of(keys, keys.len(), |i, key| {
        match (suggestion(i), keys.len()) {
            (Some(s), 1) => format!("\"{key}\", did you mean \"{s}\"?"),
            (Some(s), _) => format!("\"{key}\" (did you mean \"{s}\"?)"),
            (None, _) => format!("\"{key}\""),
        }
    });
    let line = format!("{}: {at}: unknown key(s) {list}", file_name(file));
    if (0..keys.len()).all(|i| suggestion(i).is_some()) {
        line
    } else {
        format!("{line} (allowed: {allowed})")
    }
}

/// Input text as an error message quotes it (the shared rule, [`camloc_store::quoted`]): at
/// most [`MAX_QUOTED_CHARS`] characters (then `…`), control characters escaped.
pub(crate) fn clip(text: &str) -> String {
    camloc_store::quoted(text)
}

/// The name of an input as messages give it ([`camloc_store::quoted_path`]).
pub(crate) fn file_name(file: &str) -> String {
    camloc_store::quoted_path(std::path::Path::new(file))
}

/// At most [`MAX_QUOTED_ITEMS`] items (fewer when they would take more than
/// [`MAX_QUOTED_CHARS`] characters), each [`clip`]ped and formatted by `item`, separated by
/// commas, then `… and N more`.
fn capped_list(items: &[String], item: impl Fn(String) -> String) -> String {
    capped_list_of(items, items.len(), |_, text| item(text))
}

/// [`capped_list`] of the first `items` of `total`, `item` given each one's index too.
fn capped_list_of(
    items: &[String],
    total: usize,
    item: impl Fn(usize, String) -> String,
) -> String {
    let mut shown: Vec<String> = Vec::new();
    let mut length = 0;
    for (i, text) in items.iter().take(MAX_QUOTED_ITEMS).enumerate() {
        let text = item(i, clip(text));
        length += text.chars().count();
        if !shown.is_empty() && length > MAX_QUOTED_CHARS {
            break;
        }
        shown.push(text);
    }
    if total > shown.len() {
        shown.push(format!("… and {} more", total - shown.len()));
    }
    shown.join(", ")
}

/// `a, b, c`, or `none`.
fn list_or_none(items: &[String]) -> String {
    if items.is_empty() {
        "none".to_owned()
    } else {
        capped_list(items, |i| i)
    }
}

/// The first unexpected columns `items` of a CSV header's `total`, or `none`; an empty name is
/// shown as `""`, and said to be likely pandas' index (what its `to_csv` writes).
fn header_columns(items: &[String], total: usize) -> String {
    if total == 0 {
        return "none".to_owned();
    }
    let list = capped_list_of(
        items,
        total,
        |_, c| if c.is_empty() { "\"\"".into() } else { c },
    );
    if items.iter().any(String::is_empty) {
        list + "; an unnamed column is likely pandas' index: write the CSV with to_csv(index=False)"
    } else {
        list
    }
}

/// What [`KeypointError::MissingKey`] adds for an input read as COCO keypoints.
const COCO_MISSING_KEY_HINT: &str = "; read as COCO keypoints (what a JSON list of objects is \
     taken for): if it is another format, name it (--format, Python's format=)";

/// The likely causes of the JSON parser's `message` at `line` and `column`, as ` (...)`, or
/// nothing: a value it did not expect at the very start is an input that is not JSON (a CSV
/// file given `--format coco`); elsewhere a trailing comma, or `NaN` or `Infinity`, which
/// Python's `json` module writes and JSON does not have.
fn json_hint(message: &str, line: usize, column: usize) -> &'static str {
    match (message, (line, column)) {
        ("expected value", (1, 1)) => " (the input is not JSON: is its format right?)",
        ("expected value", _) => {
            " (a trailing comma, or NaN or Infinity, which Python's json module writes and \
             JSON does not have: write a missing joint as null in camloc JSON, with a score of \
             0 in a detector's format)"
        }
        _ => "",
    }
}

/// `pelvis and neck`.
fn landmark_list(items: &[Landmark]) -> String {
    items
        .iter()
        .map(|l| l.name())
        .collect::<Vec<_>>()
        .join(" and ")
}

/// Where a pose a reader refused ([`KeypointError::LayoutMismatch`]) lies in its input: the
/// fields its [`KeypointRecord`](crate::KeypointRecord) would have had, but the landmarks.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PosePlace {
    /// The pose's identifier, as its record's `id`.
    pub id: String,
    /// Where the pose is in the input, as its record's `source`.
    pub source: String,
    /// The pose's video frame, as its record's `frame`.
    pub frame: Option<u64>,
    /// The person, as its record's `person`.
    pub person: Option<u64>,
}

impl KeypointError {
    /// `true` for an error of the reading options rather than of the input
    /// ([`ImageSizeNeeded`](Self::ImageSizeNeeded), [`LayoutNotUsed`](Self::LayoutNotUsed)):
    /// every other file of a folder in that format would repeat it.
    pub fn is_option_error(&self) -> bool {
        matches!(
            self,
            KeypointError::ImageSizeNeeded { .. } | KeypointError::LayoutNotUsed { .. }
        )
    }

    /// `true` for an error of one pose whose record was read whole
    /// ([`KeypointError::LayoutMismatch`], [`KeypointError::BadRow`]): the readers pass it on
    /// in the pose's place and read on; any other error ends the input.
    pub fn is_pose_error(&self) -> bool {
        matches!(
            self,
            KeypointError::LayoutMismatch { .. } | KeypointError::BadRow { .. }
        )
    }

    /// The place of the pose a reader refused ([`is_pose_error`](Self::is_pose_error)) and
    /// why, without the file and location its place names; `None` for other errors.
    pub fn refused_pose(&self) -> Option<(&PosePlace, String)> {
        match self {
            KeypointError::LayoutMismatch { source, place, .. } => {
                Some((place, format!("{source} (--layout; Python layout=)")))
            }
            KeypointError::BadRow { why, place, .. } => Some((place, why.clone())),
            _ => None,
        }
    }

    /// [`refused_pose`](Self::refused_pose)'s place, to be completed by the reader that knows
    /// more of it (an MMPose frame's number and person).
    pub(crate) fn refused_place_mut(&mut self) -> Option<&mut PosePlace> {
        match self {
            KeypointError::LayoutMismatch { place, .. } | KeypointError::BadRow { place, .. } => {
                Some(place)
            }
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_file_and_location() {
        let e = KeypointError::UnknownKeys {
            file: "a.json".into(),
            at: Location::Path("poses[1].landmarks".into()),
            keys: vec!["nose".into(), "left_kne".into()],
            suggestions: Box::new([None, None]),
            allowed: "pelvis, left_hip".into(),
        };
        assert_eq!(
            e.to_string(),
            "a.json: poses[1].landmarks: unknown key(s) \"nose\", \"left_kne\" (allowed: pelvis, left_hip)"
        );
        let e = KeypointError::CsvHeader {
            file: "b.csv".into(),
            line: 1,
            header: "image,joint,x,y".into(),
            missing: vec!["visible".into()],
            extra: vec![],
            extra_count: 0,
        };
        let msg = e.to_string();
        assert!(msg.starts_with("b.csv: line 1: "), "{msg}");
        assert!(
            msg.contains("missing: visible; unknown or repeated: none"),
            "{msg}"
        );
        assert_eq!(Location::Path(String::new()).to_string(), "top level");
    }

    /// Misspelt keys of a long file name, long unknown keys, escaped ones: the line stays
    /// bounded (a 700-character line before), the allowed keys listed whenever a key, shown or
    /// not, has no suggestion.
    #[test]
    fn many_unknown_keys_keep_the_line_bounded() {
        // Eight names (neck to right wrist) misspelt; the 15 allowed.
        let names: Vec<&'static str> = Landmark::ALL[7..].iter().map(|l| l.name()).collect();
        let allowed = Landmark::ALL.map(|l| l.name()).join(", ");
        let message = |keys: Vec<String>, suggestions: Vec<Option<&'static str>>| {
            KeypointError::UnknownKeys {
                file: format!("{}.json", "n".repeat(150)),
                at: Location::Path("poses[1234567].landmarks".into()),
                keys,
                suggestions: suggestions.into(),
                allowed: allowed.clone(),
            }
            .to_string()
        };
        let misspelt = message(
            names.iter().map(|n| format!("{n}x")).collect(),
            names.iter().map(|&n| Some(n)).collect(),
        );
        assert!(misspelt.chars().count() < 300, "{misspelt}");
        assert!(
            misspelt.contains("\"neckx\" (did you mean \"neck\"?), ")
                && !misspelt.contains("allowed"),
            "{misspelt}"
        );
        for key in ["x".repeat(500), "\u{1b}".repeat(500)] {
            let long = message(vec![key; 8], vec![None; 8]);
            assert!(long.chars().count() < 500, "{long}");
            assert!(
                long.ends_with(&format!("… and 7 more (allowed: {allowed})")),
                "{long}"
            );
        }
        // Keys without a suggestion hidden behind suggested ones still bring the list.
        let hidden = message(
            ["nek", "hed", "l_wrst", "confidence", "nose"]
                .map(String::from)
                .to_vec(),
            vec![Some("neck"), Some("head"), Some("left_wrist"), None, None],
        );
        assert!(hidden.contains("more (allowed: "), "{hidden}");
        let e = KeypointError::UnknownKeys {
            file: "a.json".into(),
            at: Location::Path("poses[0].landmarks".into()),
            keys: vec!["nek".into(), "nose".into()],
            suggestions: Box::new([Some("neck"), None]),
            allowed: "neck, head".into(),
        };
        assert_eq!(
            e.to_string(),
            "a.json: poses[0].landmarks: unknown key(s) \"nek\" (did you mean \"neck\"?), \"nose\" (allowed: neck, head)"
        );
    }
}
