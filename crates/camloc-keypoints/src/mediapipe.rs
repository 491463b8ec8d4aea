//! MediaPipe Pose: a list of frames, each a list of 33 landmarks `{x, y, z, visibility}` with
//! `x`, `y` normalised to [0, 1] by the image width and height.

use crate::error::{KeypointError, Location};
use crate::json::{
    self, Json, array, check_keys, get, index_path, key_path, number, object, required, unit_score,
};
use crate::layout::{MEDIAPIPE33, keeps};
use crate::record::{KeypointRecord, from_joints};
use crate::{ImageSize, ReadOptions};

/// Keys of one landmark object (`presence` is written by MediaPipe's Tasks API).
const LANDMARK_KEYS: [&str; 5] = ["x", "y", "z", "visibility", "presence"];

/// Reads MediaPipe Pose landmarks (BOM already removed, known not to be blank).
pub(crate) fn parse(
    text: &str,
    file: &str,
    options: &ReadOptions,
) -> Result<Vec<KeypointRecord>, KeypointError> {
    let root: Json = json::parse(text, file)?;
    let Some(size) = options.image_size else {
        return Err(KeypointError::ImageSizeNeeded {
            file: file.to_owned(),
            format: "MediaPipe",
        });
    };
    let items = array(&root, "a list of frames (lists of 33 landmarks)", file, "")?;
    // A bare list of landmark objects is one frame.
    if matches!(items.first(), Some(Json::Object(_))) {
        return Ok(vec![frame(items, "", 0, size, file, options)?]);
    }
    items
        .iter()
        .enumerate()
        .filter(|(_, f)| !matches!(f, Json::Null))
        .map(|(i, f)| {
            let path = index_path("", i);
            let landmarks = array(f, "a list of 33 landmarks, or null", file, &path)?;
            frame(landmarks, &path, i, size, file, options)
        })
        .collect()
}

/// The frame `index` at `path`.
fn frame(
    landmarks: &[Json],
    path: &str,
    index: usize,
    size: ImageSize,
    file: &str,
    options: &ReadOptions,
) -> Result<KeypointRecord, KeypointError> {
    if landmarks.len() != MEDIAPIPE33.len() {
        return Err(KeypointError::WrongLength {
            file: file.to_owned(),
            at: Location::Path(path.to_owned()),
            expected: MEDIAPIPE33.len(),
            found: landmarks.len(),
            items: "landmarks",
            what: "MediaPipe Pose, or null for a frame without a person",
        });
    }
    let mut points = Vec::with_capacity(landmarks.len());
    for (k, landmark) in landmarks.iter().enumerate() {
        let path = index_path(path, k);
        let fields = object(landmark, "a landmark {x, y, z, visibility}", file, &path)?;
        check_keys(fields, &LANDMARK_KEYS, file, &path)?;
        let x = number(
            required(fields, "x", file, &path)?,
            file,
            &key_path(&path, "x"),
        )?;
        let y = number(
            required(fields, "y", file, &path)?,
            file,
            &key_path(&path, "y"),
        )?;
        if let Some(z) = get(fields, "z") {
            number(z, file, &key_path(&path, "z"))?;
        }
        let mut kept = true;
        for key in ["visibility", "presence"] {
            if let Some(value) = get(fields, key) {
                let at = key_path(&path, key);
                let score = unit_score(number(value, file, &at)?, key, file, &at)?;
                kept &= key == "presence" || keeps(score, options);
            }
        }
        points.push(kept.then_some([x * size.width, y * size.height]));
    }
    Ok(KeypointRecord {
        frame: Some(index as u64),
        ..from_joints(&MEDIAPIPE33, points, index.to_string(), file, path, options)
    })
}
