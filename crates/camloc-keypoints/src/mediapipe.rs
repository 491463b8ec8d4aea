//! MediaPipe Pose: a list of frames, each a list of 33 landmarks `{x, y, z, visibility}` with
//! `x`, `y` normalised to [0, 1] by the image width and height, or such a list in an object
//! (`{"landmark": [...]}`, `{"frame": n, "landmarks": [...]}`).

use serde::Deserialize;
use serde::de::value::MapAccessDeserializer;
use serde::de::{MapAccess, SeqAccess};

use crate::emit::{Sink, TopLevel};
use crate::error::{KeypointError, Location};
use crate::json::{
    Json, array, check_keys, get, index_path, key_path, number, object, required, tracking_number,
    unit_score, wrong_type,
};
use crate::layout::{MEDIAPIPE33, keeps};
use crate::normalised::check_normalised;
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
        // The image size is asked for at the first frame holding a list of landmarks (its
        // length is checked after): a truncated or empty input's own error comes first.
        let Some(first) = seq.next_element::<Json>()? else {
            return Ok(());
        };
        // A list of landmark objects (an "x" key) is one bare frame; other objects are
        // frames wrapped in objects.
        if let Json::Object(fields) = &first
            && get(fields, "x").is_some()
        {
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
            let size = image_size(sink)?;
            let record = frame(&landmarks, found, "", 0, size, file, options);
            return sink.send(record);
        }
        let (mut value, mut i) = (first, 0);
        loop {
            if !matches!(value, Json::Null) {
                let path = index_path("", i);
                // (A wrapped frame without landmarks has nobody, as a null frame.)
                match frame_landmarks(&value, i, file, &path) {
                    Ok(Some((list, at, n))) => {
                        let size = image_size(sink)?;
                        sink.send(frame(list, list.len(), &at, n, size, file, options))?;
                    }
                    Ok(None) => {}
                    Err(e) => sink.send(Err(e))?,
                }
            }
            i += 1;
            match seq.next_element::<Json>()? {
                Some(next) => value = next,
                None => return Ok(()),
            }
        }
    }

    /// One frame as an object (`{"landmark": [...]}`, protobuf's `MessageToDict` of one
    /// result): frame 0.
    fn object<'de, A: MapAccess<'de>>(self, map: A, sink: &mut Sink) -> Result<(), A::Error> {
        let (file, options) = (sink.file, sink.options);
        let value = Json::deserialize(MapAccessDeserializer::new(map))?;
        match frame_landmarks(&value, 0, file, "") {
            Ok(Some((list, at, n))) => {
                let size = image_size(sink)?;
                sink.send(frame(list, list.len(), &at, n, size, file, options))
            }
            Ok(None) => Ok(()),
            Err(e) => sink.send(Err(e)),
        }
    }
}

/// The image size that scales the coordinates (`--image-size`), or the reading's error
/// without one.
fn image_size<E: serde::de::Error>(sink: &mut Sink) -> Result<ImageSize, E> {
    match sink.options.image_size {
        Some(size) => Ok(size),
        None => {
            let (format, file) = ("MediaPipe", sink.file.to_owned());
            Err(sink.fail(KeypointError::ImageSizeNeeded { file, format }))
        }
    }
}

/// A frame's landmarks, the JSON path of their list and the frame's number.
type FrameLandmarks<'a> = (&'a [Json], String, usize);

/// What a frame of a list may be: its 33 landmarks, or an object holding them.
const FRAME: &str = "a list of 33 landmarks, an object with one (\"landmark\" or \"landmarks\"), \
                     or null";

/// The landmarks of the frame `value` at `path`, the `index`-th of the list: the list itself,
/// or the list of an object's `landmark` (protobuf's `MessageToDict` of a
/// `NormalizedLandmarkList`) or `landmarks` key, one of them (a frame wrapped with its number:
/// a `frame` key, at most once, must be a frame number and is the frame's number, else the
/// frame's place in the list counts; other keys are the user's and ignored); with the path of
/// the list and the frame's number. `None` for an object whose landmarks are `null` (nobody in
/// the frame).
fn frame_landmarks<'a>(
    value: &'a Json,
    index: usize,
    file: &str,
    path: &str,
) -> Result<Option<FrameLandmarks<'a>>, KeypointError> {
    let Json::Object(fields) = value else {
        return Ok(Some((
            array(value, FRAME, file, path)?,
            path.to_owned(),
            index,
        )));
    };
    let mut lists = fields
        .iter()
        .filter(|(key, _)| key == "landmark" || key == "landmarks");
    let (Some((key, list)), None) = (lists.next(), lists.next()) else {
        return Err(wrong_type(file, path, FRAME, value));
    };
    let at = key_path(path, key);
    if fields.iter().filter(|(key, _)| key == "frame").count() > 1 {
        return Err(KeypointError::DuplicateKey {
            file: file.to_owned(),
            at: Location::Path(key_path(path, "frame")),
        });
    }
    let number = match get(fields, "frame") {
        None => index,
        Some(frame) => tracking_number(frame)
            .and_then(|n| usize::try_from(n).ok())
            .ok_or_else(|| KeypointError::InvalidValue {
                file: file.to_owned(),
                at: Location::Path(key_path(path, "frame")),
                field: "frame",
                text: match frame {
                    Json::Number(n) => n.to_string(),
                    Json::String(text) => text.clone(),
                    other => other.kind().to_owned(),
                },
                expected: "a frame number (a whole number from 0)",
            })?,
    };
    if let Json::Null = list {
        return Ok(None);
    }
    let list = array(list, "a list of 33 landmarks, or null", file, &at)?;
    Ok(Some((list, at, number)))
}

/// Landmarks 23 and 24 of MediaPipe Pose, the hips.
const HIPS: [usize; 2] = [23, 24];

/// How near (in the landmarks' units) the hips' midpoint must be to (0, 0), with landmarks on
/// both sides of it, for a frame to be `pose_world_landmarks` (0.005): metres about the hips'
/// midpoint, which MediaPipe places at the origin, where a person's image coordinates keep the
/// hips inside the picture.
const WORLD_ORIGIN_REACH: f64 = 0.005;

/// [`KeypointError::InvalidValue`] for the frame at `path` whose `coordinates` (its 33
/// landmarks' x and y) are MediaPipe's `pose_world_landmarks` (metres centred on the hips'
/// midpoint, negative above and to one side of them) rather than `pose_landmarks`: read as
/// image coordinates they had given a camera with no warning.
fn check_not_world(coordinates: &[[f64; 2]], file: &str, path: &str) -> Result<(), KeypointError> {
    let [a, b] = HIPS.map(|h| coordinates[h]);
    let mid = [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0];
    let negative = |c: usize| coordinates.iter().any(|xy| xy[c] < -WORLD_ORIGIN_REACH);
    if mid[0].hypot(mid[1]) > WORLD_ORIGIN_REACH || !(negative(0) && negative(1)) {
        return Ok(());
    }
    Err(KeypointError::InvalidValue {
        file: file.to_owned(),
        at: Location::Path(path.to_owned()),
        field: "landmarks",
        text: format!("hips' midpoint ({:.4}, {:.4})", mid[0], mid[1]),
        expected: "pose_landmarks: these are centred on the hips, as pose_world_landmarks (metres) \
                   are; write results.pose_landmarks, normalised to the image",
    })
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
    let mut coordinates = Vec::with_capacity(landmarks.len());
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
        coordinates.push([x, y]);
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
    check_not_world(&coordinates, file, path)?;
    check_normalised(&coordinates, size, file, Location::Path(path.to_owned()))?;
    Ok(KeypointRecord {
        frame: Some(index as u64),
        ..from_joints(&MEDIAPIPE33, points, index.to_string(), file, path, options)
    })
}
