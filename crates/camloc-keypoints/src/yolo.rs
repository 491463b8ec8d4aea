//! Ultralytics YOLO pose text files (`save_txt`, and the labels of YOLO pose datasets): one
//! file per image or video frame, one line per person: the class, the person's box (centre x,
//! centre y, width, height), the 17 COCO keypoints as `x y v` (or `x y`), then, from a
//! prediction, the box's confidence (`save_conf`) and a tracker's id (`track`). Coordinates
//! are normalised to [0, 1] by the image's width and height.

use crate::error::{KeypointError, Location};
use crate::layout::{COCO17, keeps};
use crate::normalised::check_normalised;
use crate::openpose::{name_without, trailing_number};
use crate::record::{KeypointRecord, from_joints};
use crate::{ImageSize, ReadOptions};

/// Numbers before the keypoints on a line: the class and the box's four.
const BOX_NUMBERS: usize = 5;

/// What a line holds, for [`KeypointError::WrongLength`].
const LINE: &str = "a class, a box's 4 numbers, 17 keypoints as x y v (56) or x y (39), then \
                    at most a confidence and a track id";

/// The records of the YOLO pose text `text` of the file named `file`: one per non-blank line,
/// person `n` of the file's frame (its line among the people, or the tracker's id when the
/// line ends in one), the frame the digits that end the file's name (`video_12.txt` → 12).
/// Keypoints whose visibility or confidence is 0 or below [`ReadOptions::min_score`], or at
/// (0, 0) (where Ultralytics puts keypoints whose confidence is below 0.5), are missing. A
/// line's last number after the keypoints is a track id when it is written as digits alone
/// (a confidence written `0` or `1` would be read as one; `1.000000` is a confidence), a
/// confidence otherwise; two are the confidence and the id (the id a whole number).
///
/// # Errors
/// [`KeypointError::ImageSizeNeeded`] without [`ReadOptions::image_size`];
/// [`KeypointError::InvalidValue`] for a value that is not a finite number, a track id
/// beyond 2^63 - 1, or coordinates that are pixels rather than normalised; [`KeypointError::WrongLength`] for a line of
/// another count of numbers.
pub(crate) fn parse(
    text: &str,
    file: &str,
    options: &ReadOptions,
) -> Result<Vec<KeypointRecord>, KeypointError> {
    let Some(size) = options.image_size else {
        return Err(KeypointError::ImageSizeNeeded {
            file: file.to_owned(),
            format: "YOLO",
        });
    };
    let stem = name_without(file, ".txt");
    let frame = stem.and_then(trailing_number);
    let frame_name = match (frame, stem) {
        (Some(frame), _) => frame.to_string(),
        (None, Some(stem)) => stem.to_owned(),
        (None, None) => file.to_owned(),
    };
    let mut records = Vec::new();
    for (n, line) in text.lines().enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let at = Location::Line(n + 1);
        let person = records.len();
        let record = person_record(line, at, person, &frame_name, size, file, options)?;
        records.push(KeypointRecord { frame, ..record });
    }
    Ok(records)
}

/// The person of the line `line` at `at`, the `person`-th of its frame `frame_name`.
fn person_record(
    line: &str,
    at: Location,
    person: usize,
    frame_name: &str,
    size: ImageSize,
    file: &str,
    options: &ReadOptions,
) -> Result<KeypointRecord, KeypointError> {
    let wrong_length = |found: usize| KeypointError::WrongLength {
        file: file.to_owned(),
        at: at.clone(),
        expected: BOX_NUMBERS + 3 * COCO17.len(),
        found,
        items: "numbers",
        what: LINE,
    };
    // No more words are held than a line can have: a line of millions is counted, not split.
    let most = BOX_NUMBERS + 3 * COCO17.len() + 2;
    let words: Vec<&str> = line.split_whitespace().take(most + 1).collect();
    if words.len() > most {
        return Err(wrong_length(line.split_whitespace().count()));
    }
    let values = (words.iter())
        .map(|word| {
            word.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| KeypointError::InvalidValue {
                    file: file.to_owned(),
                    at: at.clone(),
                    field: "value",
                    text: (*word).to_owned(),
                    expected: "a finite number",
                })
        })
        .collect::<Result<Vec<f64>, _>>()?;
    let found = values.len();
    let per_keypoint = match found.checked_sub(BOX_NUMBERS) {
        Some(rest) if (3 * COCO17.len()..=3 * COCO17.len() + 2).contains(&rest) => 3,
        Some(rest) if (2 * COCO17.len()..=2 * COCO17.len() + 2).contains(&rest) => 2,
        _ => return Err(wrong_length(found)),
    };
    let keypoints_end = BOX_NUMBERS + per_keypoint * COCO17.len();
    let keypoints = &values[BOX_NUMBERS..keypoints_end];
    // A single last number is the id only when written as one (digits alone): `1.000000` is a
    // confidence of 1 (a simulated user's frame had become a person of its own).
    let word = words[words.len() - 1];
    let digits = word.bytes().all(|b| b.is_ascii_digit());
    let track = match values[keypoints_end..] {
        [_, id] | [id]
            if id.fract() == 0.0 && id >= 0.0 && (digits || found > keypoints_end + 1) =>
        {
            // As every format's ids: a number JSON and `.npz` outputs keep as given, read as
            // written (a float holds whole numbers exactly only up to 2^53: two ids beyond
            // would have been one person).
            let exact = match word.parse::<u64>() {
                Ok(n) => Some(n).filter(|&n| n <= crate::MAX_FRAME_NUMBER),
                Err(_) => (id <= (1u64 << 53) as f64).then_some(id as u64),
            };
            let Some(id) = exact else {
                return Err(KeypointError::InvalidValue {
                    file: file.to_owned(),
                    at,
                    field: "track id",
                    text: crate::error::clip(word),
                    expected: "an integer from 0 to 2^63 - 1 (written out beyond 2^53)",
                });
            };
            Some(id)
        }
        _ => None,
    };
    let mut points = Vec::with_capacity(COCO17.len());
    let mut present = Vec::with_capacity(COCO17.len());
    for keypoint in keypoints.chunks_exact(per_keypoint) {
        let (x, y) = (keypoint[0], keypoint[1]);
        // Ultralytics writes (0, 0), keeping the confidence, for keypoints it is less than
        // 0.5 sure of: the image's corner would be read as the joint.
        let kept = (x, y) != (0.0, 0.0) && keypoint.get(2).is_none_or(|&s| keeps(s, options));
        if kept {
            present.push([x, y]);
        }
        points.push(kept.then_some([x * size.width, y * size.height]));
    }
    check_normalised(&present, size, file, at.clone())?;
    let path = at.to_string();
    Ok(KeypointRecord {
        person: Some(track.unwrap_or(person as u64)),
        person_is_position: track.is_none(),
        ..from_joints(
            &COCO17,
            points,
            format!("{frame_name}/{person}"),
            file,
            &path,
            options,
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A line of `class box keypoints extra`: the keypoints of a standing person facing the
    /// camera, normalised, with visibility 2 (or without when `!visible`).
    fn line(visible: bool, extra: &str) -> String {
        let mut words = vec!["0".to_string(), "0.5 0.5 0.2 0.8".to_string()];
        for k in 0..17 {
            let x = if k % 2 == 0 { "0.45" } else { "0.55" };
            words.push(format!("{x} {:.2}", 0.15 + 0.04 * f64::from(k)));
            if visible {
                words.push("2".into());
            }
        }
        if !extra.is_empty() {
            words.push(extra.into());
        }
        words.join(" ")
    }

    fn options() -> ReadOptions {
        ReadOptions {
            image_size: Some(ImageSize {
                width: 1000.0,
                height: 500.0,
            }),
            ..ReadOptions::default()
        }
    }

    #[test]
    fn lines_are_people_of_the_frame_the_file_name_numbers() {
        let text = format!("{}\n\n{}\n", line(true, ""), line(false, "0.91 7"));
        let records = parse(&text, "runs/pose/labels/clip_12.txt", &options()).unwrap();
        assert_eq!(records.len(), 2);
        assert_eq!(records[0].frame, Some(12));
        assert_eq!((records[0].person, records[1].person), (Some(0), Some(7)));
        assert_eq!(records[0].id, "12/0");
        // Keypoint 11 (left hip) at (0.55, 0.59) of a 1000 x 500 image.
        let hip = records[0].pose.points[camloc_skeleton::Landmark::LeftHip.index()].unwrap();
        assert!(
            (hip[0] - 550.0).abs() < 1e-9 && (hip[1] - 295.0).abs() < 1e-9,
            "{hip:?}"
        );
        assert_eq!(records[0].pose, records[1].pose);
        // An id beyond 2^63 - 1 (which JSON and `.npz` could not give back) is refused.
        let text = line(true, "0.9 99999999999999999999999");
        let e = parse(&text, "clip_0.txt", &options())
            .unwrap_err()
            .to_string();
        assert!(e.contains("track id") && e.contains("2^63 - 1"), "{e}");
        // Ids are read as written: 2^63 - 1 and 2^53 + 1 exactly.
        for id in [crate::MAX_FRAME_NUMBER, (1 << 53) + 1] {
            let large = line(true, &format!("0.9 {id}"));
            let records = parse(&large, "clip_0.txt", &options()).unwrap();
            assert_eq!(records[0].person, Some(id));
        }
        let e = parse(&line(true, "0.9 1e300"), "clip_0.txt", &options()).unwrap_err();
        assert!(e.to_string().contains("track id"), "{e}");
        // A last number alone is an id when written as digits, a confidence otherwise (a
        // confidence of 1 written `1.000000` had made its frame a person of its own).
        let text = format!("{}\n{}\n", line(true, "1.000000"), line(true, "4"));
        let records = parse(&text, "clip_0.txt", &options()).unwrap();
        assert_eq!((records[0].person, records[1].person), (Some(0), Some(4)));
    }

    #[test]
    fn hidden_keypoints_are_missing_and_bad_lines_are_errors() {
        let hidden = line(true, "").replacen("0.55 0.59 2", "0.55 0.59 0", 1);
        let record = &parse(&hidden, "f.txt", &options()).unwrap()[0];
        assert!(record.pose.points[camloc_skeleton::Landmark::LeftHip.index()].is_none());
        let zeroed = line(true, "").replacen("0.55 0.59 2", "0 0 0.3", 1);
        let record = &parse(&zeroed, "f.txt", &options()).unwrap()[0];
        assert!(record.pose.points[camloc_skeleton::Landmark::LeftHip.index()].is_none());
        // A person of 17 unlabelled keypoints is a pose without landmarks, not a panic.
        let nobody = format!("0 0.5 0.5 0.2 0.8{}", " 0 0 0".repeat(17));
        let record = &parse(&nobody, "f.txt", &options()).unwrap()[0];
        assert!(record.pose.points.iter().all(Option::is_none));
        let short = "0 0.5 0.5 0.2 0.8 0.1 0.2";
        let e = parse(short, "f.txt", &options()).unwrap_err().to_string();
        assert!(e.contains("line 1") && e.contains("found 7"), "{e}");
        // A line of more words than any line has is counted, not split into them all.
        let long = format!("{} x{}", line(true, "0.9 3"), " 0".repeat(100_000));
        let e = parse(&long, "f.txt", &options()).unwrap_err().to_string();
        assert!(e.contains("line 1") && e.contains("found 100059"), "{e}");
        let nan = line(true, "").replacen("0.45", "nan", 1);
        let e = parse(&nan, "f.txt", &options()).unwrap_err().to_string();
        assert!(e.contains("\"nan\" is not a finite number"), "{e}");
        let e = parse(&line(true, ""), "f.txt", &ReadOptions::default()).unwrap_err();
        assert!(e.to_string().contains("--image-size"), "{e}");
        let pixels = line(true, "")
            .replace("0.45 ", "450 ")
            .replace("0.55 ", "550 ");
        let e = parse(&pixels, "f.txt", &options()).unwrap_err().to_string();
        assert!(e.contains("normalised"), "{e}");
    }
}
