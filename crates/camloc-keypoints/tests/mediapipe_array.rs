//! MediaPipe Pose's 33 landmarks as an array (`Layout::Mediapipe33`): read as the MediaPipe
//! file they were made from.

mod common;

use camloc_keypoints::{Layout, ReadOptions, read_keypoints};
use common::{SAMPLE_IMAGE as IMAGE, fixture};
use serde_json::Value;

/// An array of MediaPipe's 33 landmarks in pixels (`--layout mediapipe33`: the normalised
/// coordinates times the image's sides, the visibility as the score) reads as the MediaPipe
/// file it was made from reads with the image size.
#[test]
fn a_mediapipe33_array_reads_as_its_mediapipe_file() {
    let options = ReadOptions {
        image_size: Some(IMAGE),
        ..ReadOptions::default()
    };
    let from_file = read_keypoints(fixture("samples/mediapipe.json"), None, &options).unwrap();
    let document: Value =
        serde_json::from_str(&std::fs::read_to_string(fixture("samples/mediapipe.json")).unwrap())
            .unwrap();
    let frames: Vec<&Vec<Value>> = document
        .as_array()
        .unwrap()
        .iter()
        .filter_map(Value::as_array)
        .collect();
    let numbers: Vec<f64> = frames
        .iter()
        .flat_map(|frame| frame.iter())
        .flat_map(|l| {
            let v = |k: &str| l[k].as_f64().unwrap();
            [v("x") * IMAGE.width, v("y") * IMAGE.height, v("visibility")]
        })
        .collect();
    let header = format!(
        "{{'descr': '<f8', 'fortran_order': False, 'shape': ({}, 33, 3), }}",
        frames.len()
    );
    let pad = 64 - (10 + header.len() + 1) % 64;
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend(((header.len() + pad + 1) as u16).to_le_bytes());
    bytes.extend(header.bytes().chain(std::iter::repeat_n(b' ', pad)));
    bytes.push(b'\n');
    bytes.extend(numbers.iter().flat_map(|v| v.to_le_bytes()));
    let array = ReadOptions {
        layout: Some(Layout::Mediapipe33),
        ..ReadOptions::default()
    };
    let from_array =
        camloc_keypoints::parse_keypoints_bytes(&bytes, "mp.npy", None, &array).unwrap();
    assert_eq!(from_array.len(), from_file.len());
    for (a, f) in from_array.iter().zip(&from_file) {
        for (p, q) in a.pose.points.iter().zip(&f.pose.points) {
            match (p, q) {
                (Some(p), Some(q)) => {
                    assert!((p[0] - q[0]).abs() < 1e-9 && (p[1] - q[1]).abs() < 1e-9)
                }
                _ => assert_eq!(p, q),
            }
        }
        assert_eq!(a.derived, f.derived);
    }
    // MediaPipe's own four numbers a landmark are refused with the way to save them.
    let four = bytes.windows(5).position(|w| w == b", 3),").unwrap();
    let mut wrong = bytes.clone();
    wrong[four + 2] = b'4';
    let e = camloc_keypoints::parse_keypoints_bytes(&wrong, "mp.npy", None, &array).unwrap_err();
    assert!(
        e.to_string()
            .contains("MediaPipe's (x, y, z, visibility)? save x, y and visibility"),
        "{e}"
    );
    // Without the layout, 33 joints are MediaPipe's.
    let guessed =
        camloc_keypoints::parse_keypoints_bytes(&bytes, "mp.npy", None, &ReadOptions::default())
            .unwrap();
    assert_eq!(guessed.len(), from_file.len());
}
