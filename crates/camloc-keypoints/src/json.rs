//! A JSON tree that keeps object keys in order, duplicates included (so that a landmark given
//! twice is an error rather than silently overwritten), and helpers that report problems with
//! their JSON path.

use std::cell::Cell;
use std::collections::HashSet;
use std::fmt;

use serde::de::{self, Deserialize, DeserializeSeed, Deserializer, MapAccess, SeqAccess, Visitor};

use crate::error::{KeypointError, Location};

/// A parsed JSON value.
#[derive(Debug)]
pub(crate) enum Json {
    Null,
    /// A boolean (COCO's `iscrowd` may be written `true`).
    Bool(bool),
    /// Kept as `serde_json::Number` so that integer ids print exactly.
    Number(serde_json::Number),
    String(String),
    Array(Vec<Json>),
    /// Keys in input order, duplicates kept.
    Object(Vec<(String, Json)>),
}

impl Json {
    /// The JSON type, as used in error messages.
    pub(crate) fn kind(&self) -> &'static str {
        match self {
            Json::Null => "null",
            Json::Bool(_) => "a boolean",
            Json::Number(_) => "a number",
            Json::String(_) => "a string",
            Json::Array(_) => "an array",
            Json::Object(_) => "an object",
        }
    }
}

/// The most JSON values (numbers, strings, `null`s, arrays, objects, counted with everything
/// they hold) that one entry of an input may have: a pose, an instance, a frame, an annotation,
/// a person. Reading stops with an error at the next value, so that one hostile keypoint list
/// of millions of numbers is refused after about 4 MiB rather than held.
pub const MAX_ENTRY_VALUES: usize = 1 << 16;

impl<'de> Deserialize<'de> for Json {
    /// Parses one entry: at most [`MAX_ENTRY_VALUES`] values.
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let budget = Cell::new(MAX_ENTRY_VALUES);
        Bounded(&budget).deserialize(deserializer)
    }
}

/// Parses a [`Json`] value, taking one from the budget for each value.
struct Bounded<'b>(&'b Cell<usize>);

impl Bounded<'_> {
    /// Counts one value, or fails once the budget is spent.
    fn take<E: de::Error>(&self) -> Result<(), E> {
        match self.0.get().checked_sub(1) {
            Some(left) => {
                self.0.set(left);
                Ok(())
            }
            None => Err(E::custom(format_args!(
                "more than {MAX_ENTRY_VALUES} values in one entry (MAX_ENTRY_VALUES)"
            ))),
        }
    }
}

impl<'de> DeserializeSeed<'de> for Bounded<'_> {
    type Value = Json;

    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<Json, D::Error> {
        deserializer.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for Bounded<'_> {
    type Value = Json;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a JSON value")
    }

    fn visit_unit<E: de::Error>(self) -> Result<Json, E> {
        self.take()?;
        Ok(Json::Null)
    }

    fn visit_bool<E: de::Error>(self, value: bool) -> Result<Json, E> {
        self.take()?;
        Ok(Json::Bool(value))
    }

    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Json, E> {
        self.take()?;
        Ok(Json::Number(v.into()))
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Json, E> {
        self.take()?;
        Ok(Json::Number(v.into()))
    }

    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Json, E> {
        self.take()?;
        finite(v).map(Json::Number)
    }

    fn visit_str<E: de::Error>(self, v: &str) -> Result<Json, E> {
        self.take()?;
        Ok(Json::String(v.to_owned()))
    }

    fn visit_string<E: de::Error>(self, v: String) -> Result<Json, E> {
        self.take()?;
        Ok(Json::String(v))
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Json, A::Error> {
        self.take()?;
        let mut items = Vec::new();
        while let Some(item) = seq.next_element_seed(Bounded(self.0))? {
            items.push(item);
        }
        Ok(Json::Array(items))
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Json, A::Error> {
        self.take()?;
        let mut fields = Vec::new();
        while let Some(key) = map.next_key::<String>()? {
            fields.push((key, map.next_value_seed(Bounded(self.0))?));
        }
        Ok(Json::Object(fields))
    }
}

/// A finite `f64` as a JSON number (serde_json never gives others; refused all the same).
fn finite<E: de::Error>(v: f64) -> Result<serde_json::Number, E> {
    serde_json::Number::from_f64(v).ok_or_else(|| E::custom("number is not finite"))
}

/// A parser error as [`KeypointError::Json`], its line and column moved out of the message.
pub(crate) fn syntax_error(e: &serde_json::Error, file: &str) -> KeypointError {
    let full = e.to_string();
    let suffix = format!(" at line {} column {}", e.line(), e.column());
    let message = full.strip_suffix(&suffix).unwrap_or(&full).to_owned();
    KeypointError::Json {
        file: file.to_owned(),
        line: e.line(),
        column: e.column(),
        message,
    }
}

/// A JSON value parsed (numbers and nesting checked as for [`Json`]) but not kept: only its
/// type survives, as an empty [`Json`] of the same kind, so that a skipped value still gives
/// the right [`Json::kind`] in messages.
pub(crate) struct Skipped(pub(crate) Json);

impl<'de> Deserialize<'de> for Skipped {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_any(SkipVisitor).map(Skipped)
    }
}

/// The visitor of [`Skipped`], for the values other readers skip.
pub(crate) struct SkipVisitor;

impl<'de> Visitor<'de> for SkipVisitor {
    type Value = Json;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a JSON value")
    }

    fn visit_unit<E: de::Error>(self) -> Result<Json, E> {
        Ok(Json::Null)
    }

    fn visit_bool<E: de::Error>(self, value: bool) -> Result<Json, E> {
        Ok(Json::Bool(value))
    }

    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Json, E> {
        Ok(Json::Number(v.into()))
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Json, E> {
        Ok(Json::Number(v.into()))
    }

    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Json, E> {
        finite(v).map(Json::Number)
    }

    fn visit_str<E: de::Error>(self, _: &str) -> Result<Json, E> {
        Ok(Json::String(String::new()))
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Json, A::Error> {
        while seq.next_element::<Skipped>()?.is_some() {}
        Ok(Json::Array(Vec::new()))
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Json, A::Error> {
        while map.next_entry::<de::IgnoredAny, Skipped>()?.is_some() {}
        Ok(Json::Object(Vec::new()))
    }
}

/// Path of key `key` inside the object at `parent`.
pub(crate) fn key_path(parent: &str, key: &str) -> String {
    if parent.is_empty() {
        key.to_owned()
    } else {
        format!("{parent}.{key}")
    }
}

/// Path of element `index` of the array at `parent`.
pub(crate) fn index_path(parent: &str, index: usize) -> String {
    format!("{parent}[{index}]")
}

/// Objects of at most this many keys are checked for a repeated key pair by pair.
const SHORT_OBJECT_KEYS: usize = 16;

/// Of `allowed`, the key nearest `key` (case aside, a leading `l_` or `r_` read as `left_` or
/// `right_`) if at most 2 letters must be changed, inserted or deleted to make it (a typo:
/// `nek` for `neck`, `Left_Knee` for `left_knee`, `l_wrist` for `left_wrist`).
fn nearest(key: &str, allowed: &[&'static str]) -> Option<&'static str> {
    let key = key.to_lowercase();
    let key = match (key.strip_prefix("l_"), key.strip_prefix("r_")) {
        (Some(rest), _) => format!("left_{rest}"),
        (_, Some(rest)) => format!("right_{rest}"),
        _ => key,
    };
    let key: Vec<char> = key.chars().take(64).collect();
    allowed
        .iter()
        .map(|&a| (a, edit_distance(&key, &a.chars().collect::<Vec<_>>())))
        .filter(|&(_, d)| d <= 2)
        .min_by_key(|&(_, d)| d)
        .map(|(a, _)| a)
}

/// The fewest letters changed, inserted or deleted to turn `a` into `b` (Levenshtein).
fn edit_distance(a: &[char], b: &[char]) -> usize {
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.iter().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let above = row[j + 1];
            row[j + 1] = (above + 1)
                .min(row[j] + 1)
                .min(diagonal + usize::from(ca != cb));
            diagonal = above;
        }
    }
    row[b.len()]
}

/// Checks that the object at `path` uses only `allowed` keys, each at most once.
///
/// Every unknown key is named in the error. Once all keys are known, a repeat is found within
/// the first `allowed.len() + 1` keys, so the check is cheap even on hostile input.
pub(crate) fn check_keys(
    fields: &[(String, Json)],
    allowed: &[&'static str],
    file: &str,
    path: &str,
) -> Result<(), KeypointError> {
    let unknown: Vec<String> = fields
        .iter()
        .filter(|(k, _)| !allowed.contains(&k.as_str()))
        .map(|(k, _)| k.clone())
        .collect();
    if !unknown.is_empty() {
        // (The keys a message names: a hostile object may have millions.)
        let suggestions = unknown
            .iter()
            .take(crate::error::MAX_QUOTED_ITEMS)
            .map(|key| nearest(key, allowed))
            .collect();
        return Err(KeypointError::UnknownKeys {
            file: file.to_owned(),
            at: Location::Path(path.to_owned()),
            keys: unknown,
            suggestions,
            allowed: allowed.join(", "),
        });
    }
    // The first key that repeats one before it (a set for long objects: linear time).
    let repeated = if fields.len() <= SHORT_OBJECT_KEYS {
        (1..fields.len()).find(|&i| fields[..i].iter().any(|(k, _)| *k == fields[i].0))
    } else {
        let mut seen = HashSet::with_capacity(fields.len());
        fields.iter().position(|(k, _)| !seen.insert(k.as_str()))
    };
    match repeated {
        Some(i) => Err(KeypointError::DuplicateKey {
            file: file.to_owned(),
            at: Location::Path(key_path(path, &fields[i].0)),
        }),
        None => Ok(()),
    }
}

/// The value of `key` in `fields`, if present.
pub(crate) fn get<'a>(fields: &'a [(String, Json)], key: &str) -> Option<&'a Json> {
    fields.iter().find(|(k, _)| k == key).map(|(_, v)| v)
}

/// The value of `key` in the object at `path`, if present; a key given twice is
/// [`KeypointError::DuplicateKey`] (no first-one-wins), for objects whose other keys are not
/// checked.
pub(crate) fn optional<'a>(
    fields: &'a [(String, Json)],
    key: &str,
    file: &str,
    path: &str,
) -> Result<Option<&'a Json>, KeypointError> {
    let mut found = fields.iter().filter(|(k, _)| k == key).map(|(_, v)| v);
    let first = found.next();
    if found.next().is_some() {
        return Err(KeypointError::DuplicateKey {
            file: file.to_owned(),
            at: Location::Path(key_path(path, key)),
        });
    }
    Ok(first)
}

/// The integer `value` (a frame or person number, 0 to [`MAX_FRAME_NUMBER`](crate::MAX_FRAME_NUMBER)) of the key `field` at `path`.
pub(crate) fn count_number(
    value: &Json,
    field: &'static str,
    file: &str,
    path: &str,
) -> Result<u64, KeypointError> {
    match value {
        Json::Number(n) => n
            .as_u64()
            .filter(|&v| v <= crate::MAX_FRAME_NUMBER)
            .ok_or_else(|| KeypointError::InvalidValue {
                file: file.to_owned(),
                at: Location::Path(path.to_owned()),
                field,
                text: n.to_string(),
                expected: "an integer from 0 to 2^63 - 1",
            }),
        other => Err(wrong_type(file, path, "an integer", other)),
    }
}

/// A person number a tracker wrote beside the keypoints (a `track_id`): the value when it is
/// an integer from 0 to [`MAX_FRAME_NUMBER`](crate::MAX_FRAME_NUMBER), written as a number
/// (`7`, or `7.0` as scripts write floats) or as a string of digits (`"7"`), else `None` (the
/// `-1` some trackers write for an untracked detection, a name), which leaves the record
/// without one.
pub(crate) fn tracking_number(value: &Json) -> Option<u64> {
    match value {
        Json::Number(n) => n
            .as_u64()
            .or_else(|| {
                n.as_f64()
                    .filter(|v| v.fract() == 0.0 && *v >= 0.0 && *v < 2f64.powi(63))
                    .map(|v| v as u64)
            })
            .filter(|&v| v <= crate::MAX_FRAME_NUMBER),
        Json::String(s) if !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit()) => s
            .parse::<u64>()
            .ok()
            .filter(|&v| v <= crate::MAX_FRAME_NUMBER),
        _ => None,
    }
}

/// A frame number a detector wrote beside the keypoints (COCO's `image_id`): as
/// [`tracking_number`], and for an image's file name (`"frame_000012.jpg"`,
/// `"000012_cam2.png"`, `"cam2_frame_13.jpg"`) the longest run of digits before its extension
/// (the last of equally long ones: a frame counter is usually the longest number in the
/// name, a camera or take number shorter); `None` for a string without digits.
pub(crate) fn frame_number(value: &Json) -> Option<u64> {
    match value {
        Json::String(s) => {
            let stem = s.rsplit(['/', '\\']).next().unwrap_or(s);
            let stem = stem.rsplit_once('.').map_or(stem, |(stem, _)| stem);
            stem.split(|c: char| !c.is_ascii_digit())
                .filter(|run| !run.is_empty())
                .fold(None, |best: Option<&str>, run| match best {
                    Some(b) if b.len() > run.len() => Some(b),
                    _ => Some(run),
                })?
                .parse::<u64>()
                .ok()
                .filter(|&v| v <= crate::MAX_FRAME_NUMBER)
        }
        other => tracking_number(other),
    }
}

/// A [`KeypointError::WrongType`] for `found` at `path`.
pub(crate) fn wrong_type(
    file: &str,
    path: &str,
    expected: &'static str,
    found: &Json,
) -> KeypointError {
    KeypointError::WrongType {
        file: file.to_owned(),
        at: Location::Path(path.to_owned()),
        expected,
        found: found.kind(),
    }
}

/// The `N` numbers of the array `value` at `path`.
pub(crate) fn number_array<const N: usize>(
    value: &Json,
    what: &'static str,
    file: &str,
    path: &str,
) -> Result<[f64; N], KeypointError> {
    let items = array(value, what, file, path)?;
    let wrong_length = || KeypointError::WrongLength {
        file: file.to_owned(),
        at: Location::Path(path.to_owned()),
        expected: N,
        found: items.len(),
        items: "numbers",
        what,
    };
    // Checked first so that a wrong length is reported before any element type.
    if items.len() != N {
        return Err(wrong_length());
    }
    numbers(value, what, file, path)?
        .try_into()
        .map_err(|_| wrong_length())
}

/// The elements of the array `value` at `path` (`what` describes it in the error otherwise).
pub(crate) fn array<'a>(
    value: &'a Json,
    what: &'static str,
    file: &str,
    path: &str,
) -> Result<&'a [Json], KeypointError> {
    match value {
        Json::Array(items) => Ok(items),
        other => Err(wrong_type(file, path, what, other)),
    }
}

/// The fields of the object `value` at `path` (`what` describes it in the error otherwise).
pub(crate) fn object<'a>(
    value: &'a Json,
    what: &'static str,
    file: &str,
    path: &str,
) -> Result<&'a [(String, Json)], KeypointError> {
    match value {
        Json::Object(fields) => Ok(fields),
        other => Err(wrong_type(file, path, what, other)),
    }
}

/// The value of the required key `key` of the object at `path`, given once.
pub(crate) fn required<'a>(
    fields: &'a [(String, Json)],
    key: &'static str,
    file: &str,
    path: &str,
) -> Result<&'a Json, KeypointError> {
    optional(fields, key, file, path)?.ok_or_else(|| KeypointError::MissingKey {
        file: file.to_owned(),
        at: Location::Path(path.to_owned()),
        key,
        read_as_coco: false,
    })
}

/// The finite number `value` at `path`.
pub(crate) fn number(value: &Json, file: &str, path: &str) -> Result<f64, KeypointError> {
    match value {
        Json::Number(n) => {
            n.as_f64()
                .filter(|x| x.is_finite())
                .ok_or_else(|| KeypointError::NonFinite {
                    file: file.to_owned(),
                    at: Location::Path(path.to_owned()),
                    field: "number",
                    text: n.to_string(),
                })
        }
        other => Err(wrong_type(file, path, "a number", other)),
    }
}

/// The finite numbers of the array `value` at `path`, any length.
pub(crate) fn numbers(
    value: &Json,
    what: &'static str,
    file: &str,
    path: &str,
) -> Result<Vec<f64>, KeypointError> {
    array(value, what, file, path)?
        .iter()
        .enumerate()
        .map(|(i, item)| number(item, file, &index_path(path, i)))
        .collect()
}

/// Checks that `score` (found at `path`) lies in [0, 1], the range of OpenPose confidences and
/// MediaPipe visibilities.
pub(crate) fn unit_score(
    score: f64,
    what: &'static str,
    file: &str,
    path: &str,
) -> Result<f64, KeypointError> {
    if (0.0..=1.0).contains(&score) {
        Ok(score)
    } else {
        Err(KeypointError::ScoreOutOfRange {
            file: file.to_owned(),
            at: Location::Path(path.to_owned()),
            what,
            score,
            hint: "",
        })
    }
}

/// Checks that `score` (found at `path`, in a format whose scores are not range-checked) is on
/// the scale of [`ReadOptions::min_score`](crate::ReadOptions::min_score): a minimum in
/// (0, 1] with a score above [`SCORE_SCALE_LIMIT`](crate::SCORE_SCALE_LIMIT) is
/// [`KeypointError::ScoreScale`].
pub(crate) fn score_on_threshold_scale(
    score: f64,
    options: &crate::ReadOptions,
    file: &str,
    path: &str,
) -> Result<(), KeypointError> {
    let threshold = options.min_score;
    if threshold > 0.0 && threshold <= 1.0 && score > crate::SCORE_SCALE_LIMIT {
        Err(KeypointError::ScoreScale {
            file: file.to_owned(),
            at: Location::Path(path.to_owned()),
            score,
            min_score: threshold,
        })
    } else {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keeps_duplicate_keys_and_integer_ids() {
        let v: Json =
            serde_json::from_str(r#"{"a": 1, "a": [2.5, null], "b": 18446744073709551615}"#)
                .unwrap();
        let Json::Object(fields) = &v else {
            panic!("{v:?}")
        };
        assert_eq!(fields.len(), 3);
        assert_eq!(fields[0].0, "a");
        assert_eq!(fields[1].0, "a");
        let Json::Number(n) = &fields[2].1 else {
            panic!()
        };
        assert_eq!(n.to_string(), "18446744073709551615");
        let err = check_keys(fields, &["a", "b"], "t", "x").unwrap_err();
        assert!(
            matches!(err, KeypointError::DuplicateKey { at: Location::Path(p), .. } if p == "x.a")
        );
    }

    #[test]
    fn json_errors_carry_line_and_column_once() {
        let err = serde_json::from_str::<Json>("{\n  \"a\": [1,\n}").unwrap_err();
        let err = syntax_error(&err, "f.json");
        let KeypointError::Json { line, message, .. } = &err else {
            panic!("{err:?}")
        };
        assert_eq!(*line, 3);
        assert!(!message.contains("at line"), "{message}");
    }

    #[test]
    fn an_unexpected_value_names_its_likely_cause() {
        let message = |text: &str| {
            let err = serde_json::from_str::<Json>(text).unwrap_err();
            syntax_error(&err, "f.json").to_string()
        };
        let nan = message("{\"neck\": [NaN, 1]}");
        assert!(nan.contains("NaN or Infinity"), "{nan}");
        let csv = message("image,joint,x,y,visible");
        assert!(csv.contains("the input is not JSON"), "{csv}");
        let other = message("{\"a\": [1 2]}");
        assert!(
            !other.contains("NaN") && !other.contains("not JSON"),
            "{other}"
        );
    }

    #[test]
    fn paths_compose() {
        assert_eq!(key_path("", "poses"), "poses");
        assert_eq!(
            key_path(&index_path("poses", 2), "landmarks"),
            "poses[2].landmarks"
        );
        assert_eq!(index_path("", 4), "[4]");
    }
}
