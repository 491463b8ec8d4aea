//! MediaPipe Pose: a list of frames, each a list of 33 landmarks `{x, y, z, visibility}` with
//! `x`, `y` normalised to [0, 1] by the image width and height.

use serde::de::SeqAccess;

use crate::emit::{Sink, TopLevel};
use crate::error::{KeypointError, Location};
use crate::json::{
    Json, array, check_keys, get, index_path, key_path, number, object, required, unit_score,
};
use crate::layout::{MEDIAPIPE33, keeps};
use crate::record::{KeypointRecord, from_joints};
use crate::{ImageSize, ReadOptions};

/// Keys of one landmark object (`presence` is written by MediaPipe's Tasks API).
const LANDMARK_KEYS: [&str; 5] = ["x", "y", "z", "visibility", "presence"];

/// MediaPipe Pose: a list of frames (each a list of 33 landmarks, or `null`), read one frame at
/// a time, or one bare frame (a list of landmark objects).
pub(crate) struct Frames;

impl TopLevel for Frames {
    const EXPECTED: &'static str = "a list of frames (lists of 33 landmarks)";

    fn list<'de, A: SeqAccess<'de>>(self, mut seq: A, sink: &mut Sink) -> Result<(), A::Error> {
        let (file, options) = (sink.file, sink.options);
        let Some(size) = options.image_size else {
            let format = "MediaPipe";
            let file = file.to_owned();
            return Err(sink.fail(KeypointError::ImageSizeNeeded { file, format }));
        };
        let Some(first) = seq.next_element::<Json>()? else {
            return Ok(());
        };
        if let Json::Object(_) = first {
            // A bare list of landmark objects is one frame: keep one more landmark than a frame
            // has (for the error), count the rest.
            let mut landmarks = vec![first];
            let mut found = 1;
            while let Some(landmark) = seq.next_element::<Json>()? {
                if landmarks.len() <= MEDIAPIPE33.len() {
                    landmarks.push(landmark);
                }
                found += 1;
            }
            let record = frame(&landmarks, found, "", 0, size, file, options);
            return sink.send(record);
        }
        let (mut value, mut i) = (first, 0);
        loop {
            if !matches!(value, Json::Null) {
                let path = index_path("", i);
                let record = array(&value, "a list of 33 landmarks, or null", file, &path)
                    .and_then(|landmarks| {
                        frame(landmarks, landmarks.len(), &path, i, size, file, options)
                    });
                sink.send(record)?;
            }
            i += 1;
            match seq.next_element::<Json>()? {
                Some(next) => value = next,
                None => return Ok(()),
            }
        }
    }
}

/// The frame `index` at `path`, of `found` landmarks (the first of which are `landmarks`).
fn frame(
    landmarks: &[Json],
    found: usize,
    path: &str,
    index: usize,
    size: ImageSize,
    file: &str,
    options: &ReadOptions,
) -> Result<KeypointRecord, KeypointError> {
    if found != MEDIAPIPE33.len() {
        return Err(KeypointError::WrongLength {
            file: file.to_owned(),
            at: Location::Path(path.to_owned()),
            expected: MEDIAPIPE33.len(),
            found,
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
