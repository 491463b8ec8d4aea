//! Files as detectors and their users write them (a simulated user's trial): MediaPipe frames
//! wrapped in objects, COCO dataset annotations without keypoints, OpenPose's older key, and
//! the near misses that must be refused rather than read wrongly.

use camloc_keypoints::{ImageSize, KeypointError, KeypointFormat, ReadOptions, parse_keypoints};

/// 33 MediaPipe landmarks of a standing person (normalised), as JSON text.
fn mediapipe_frame(scale: f64) -> String {
    let landmarks: Vec<String> = (0..33)
        .map(|k| {
            let x = 0.4 + 0.005 * f64::from(k % 2) + 0.002 * f64::from(k);
            let y = 0.2 + 0.018 * f64::from(k);
            format!(
                r#"{{"x": {}, "y": {}, "z": 0.0, "visibility": 0.9}}"#,
                x * scale,
                y * scale
            )
        })
        .collect();
    format!("[{}]", landmarks.join(", "))
}

fn with_size() -> ReadOptions {
    ReadOptions {
        image_size: Some(ImageSize {
            width: 1920.0,
            height: 1080.0,
        }),
        ..ReadOptions::default()
    }
}

#[test]
fn mediapipe_frames_wrapped_in_objects_read_as_plain_ones() {
    let frame = mediapipe_frame(1.0);
    let plain = format!("[{frame}, null, {frame}]");
    let want = parse_keypoints(&plain, "mp.json", None, &with_size()).unwrap();
    assert_eq!(want.len(), 2);
    // protobuf's MessageToDict of each result, and a list of numbered frames (detected as
    // MediaPipe, not as camloc JSON, whose `landmarks` is an object).
    let message = format!(r#"[{{"landmark": {frame}}}, null, {{"landmark": {frame}}}]"#);
    let wrapped = format!(
        r#"[{{"frame": 0, "landmarks": {frame}, "time_ms": 0}},
            {{"frame": 1, "landmarks": null}},
            {{"frame": 2, "landmarks": {frame}}}]"#
    );
    for text in [&message, &wrapped] {
        assert_eq!(
            KeypointFormat::from_extension_and_content(Some("json"), text),
            Some(KeypointFormat::MediaPipe)
        );
        let got = parse_keypoints(text, "mp.json", None, &with_size()).unwrap();
        assert_eq!(got.len(), 2, "{text}");
        for (g, w) in got.iter().zip(&want) {
            assert_eq!(g.pose, w.pose);
            assert_eq!(g.frame, w.frame);
        }
    }
    // One result on its own.
    let one = parse_keypoints(
        &format!(r#"{{"landmark": {frame}}}"#),
        "one.json",
        Some(KeypointFormat::MediaPipe),
        &with_size(),
    )
    .unwrap();
    assert_eq!(one.len(), 1);
    assert_eq!(one[0].pose, want[0].pose);
}

#[test]
fn mediapipe_coordinates_in_pixels_are_refused() {
    let pixels = format!("[{}]", mediapipe_frame(1000.0));
    let e = parse_keypoints(&pixels, "px.json", None, &with_size()).unwrap_err();
    let message = e.to_string();
    assert!(matches!(e, KeypointError::InvalidValue { .. }), "{e:?}");
    assert!(message.contains("--image-size 1,1"), "{message}");
    // Landmarks a little outside the image are MediaPipe's guesses, and read.
    let outside = format!("[{}]", mediapipe_frame(1.6));
    assert_eq!(
        parse_keypoints(&outside, "out.json", None, &with_size())
            .unwrap()
            .len(),
        1
    );
}

#[test]
fn coco_annotations_without_keypoints_are_skipped() {
    let keypoints: Vec<String> = (0..17)
        .map(|k| format!("{}, {}, 2", 100 + 3 * k, 50 + 20 * k))
        .collect();
    let zeros = vec!["0"; 51].join(", ");
    let text = format!(
        r#"{{"images": [], "annotations": [
            {{"image_id": 1, "id": 10, "num_keypoints": 17, "iscrowd": 0, "keypoints": [{}]}},
            {{"image_id": 1, "id": 11, "num_keypoints": 0, "iscrowd": 0, "keypoints": [{zeros}]}},
            {{"image_id": 2, "id": 12, "iscrowd": 1, "segmentation": {{"counts": []}},
              "num_keypoints": 0, "keypoints": [{zeros}]}}]}}"#,
        keypoints.join(", ")
    );
    let records = parse_keypoints(&text, "val.json", None, &ReadOptions::default()).unwrap();
    let ids: Vec<&str> = records.iter().map(|r| r.id.as_str()).collect();
    assert_eq!(ids, ["1/10"]);
}

#[test]
fn openpose_s_older_key_is_read_and_a_declared_body25_insists() {
    let coco18: Vec<String> = (0..18)
        .map(|k| format!("{}, {}, 0.9", 300 + 2 * k, 100 + 20 * k))
        .collect();
    let new = format!(
        r#"{{"people": [{{"pose_keypoints_2d": [{}]}}]}}"#,
        coco18.join(", ")
    );
    let old = new.replace("pose_keypoints_2d", "pose_keypoints");
    let name = "video_000000000004_keypoints.json";
    let options = ReadOptions::default();
    let want = parse_keypoints(&new, name, None, &options).unwrap();
    let got = parse_keypoints(&old, name, None, &options).unwrap();
    assert_eq!(got[0].pose, want[0].pose);
    assert_eq!(got[0].frame, Some(4));
    // COCO-18 people with --layout body25: refused, not read as COCO-18 regardless.
    let body25 = ReadOptions {
        layout: Some("body25".parse().unwrap()),
        ..ReadOptions::default()
    };
    let e = parse_keypoints(&new, name, None, &body25).unwrap_err();
    assert!(e.to_string().contains("leave out --layout"), "{e}");
}

#[test]
fn a_misspelt_landmark_is_named_with_the_one_meant() {
    let read = |landmarks: &str| {
        let text = format!(r#"{{"id": "a", "landmarks": {{"pelvis": [1, 2], {landmarks}}}}}"#);
        parse_keypoints(&text, "a.json", None, &ReadOptions::default())
            .unwrap_err()
            .to_string()
    };
    let message = read(r#""Left_Kne": [3, 4]"#);
    assert!(
        message.contains(r#""Left_Kne", did you mean "left_knee"?"#),
        "{message}"
    );
    // Nothing within two letters: the list alone, whole.
    let message = read(r#""nose": [3, 4]"#);
    assert!(!message.contains("did you mean"), "{message}");
    assert!(
        message.contains("left_wrist, right_shoulder, right_elbow, right_wrist)"),
        "{message}"
    );
    // Each unknown key its own, `l_` read as `left_`.
    let message = read(r#""nek": [3, 4], "l_wrist": [5, 6], "nose": [7, 8]"#);
    assert!(
        message.contains(
            r#""nek" (did you mean "neck"?), "l_wrist" (did you mean "left_wrist"?), "nose" (allowed: "#
        ),
        "{message}"
    );
}

/// CSV as spreadsheets and pandas write it: quoted fields are read as the bare ones; an index
/// column (an unnamed first column) is refused with what it likely is.
#[test]
fn lsp_csv_from_spreadsheets_and_pandas() {
    let joints = [
        "right_ankle",
        "right_knee",
        "right_hip",
        "left_hip",
        "left_knee",
        "left_ankle",
        "right_wrist",
        "right_elbow",
        "right_shoulder",
        "left_shoulder",
        "left_elbow",
        "left_wrist",
        "neck",
        "head_top",
    ];
    let rows = |quote: &str, index: bool| {
        let mut text = if index {
            ",image,joint,x,y,visible\n"
        } else {
            "image,joint,x,y,visible\n"
        }
        .to_string();
        for (k, joint) in joints.iter().enumerate() {
            let prefix = if index {
                format!("{k},")
            } else {
                String::new()
            };
            let (x, y) = (100.0 + 3.0 * k as f64, 50.0 + 20.0 * (k % 7) as f64);
            text += &format!("{prefix}{quote}im1{quote},{quote}{joint}{quote},{x},{y},1\n");
        }
        text
    };
    let read = |text: &str| parse_keypoints(text, "p.csv", None, &ReadOptions::default());
    let bare = read(&rows("", false)).unwrap();
    let quoted = read(&rows("\"", false)).unwrap();
    assert_eq!(bare.len(), 1);
    assert_eq!(bare[0].pose, quoted[0].pose);
    assert_eq!(quoted[0].id, "im1");
    let e = read(&rows("", true)).unwrap_err().to_string();
    assert!(
        e.contains("unknown or repeated: \"\"; an unnamed column is likely pandas' index"),
        "{e}"
    );
}

/// MediaPipe needs the image size, but a truncated or empty list is refused for what it is
/// first (a hostile-input trial's `[[` had been asked for an image size): the size is asked
/// for at the first frame with landmarks.
#[test]
fn mediapipe_asks_for_the_image_size_only_for_a_frame_with_landmarks() {
    let none = ReadOptions::default();
    let truncated = parse_keypoints("[[", "mp.json", None, &none).unwrap_err();
    assert!(
        !matches!(truncated, KeypointError::ImageSizeNeeded { .. }),
        "{truncated}"
    );
    assert!(truncated.to_string().contains("EOF"), "{truncated}");
    assert!(
        parse_keypoints("[null, null]", "mp.json", None, &none)
            .unwrap()
            .is_empty()
    );
    let frame = format!("[null, {}]", mediapipe_frame(1.0));
    let e = parse_keypoints(&frame, "mp.json", None, &none).unwrap_err();
    assert!(matches!(e, KeypointError::ImageSizeNeeded { .. }), "{e}");
    assert_eq!(
        parse_keypoints(&frame, "mp.json", None, &with_size())
            .unwrap()
            .len(),
        1
    );
}
