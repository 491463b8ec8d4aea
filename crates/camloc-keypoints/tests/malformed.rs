//! Every malformed input gives the expected error, with the place of the problem.

mod common;

use camloc_keypoints::{
    ImageSize, KeypointError, KeypointFormat, Layout, Location, ReadOptions, parse_keypoints,
    parse_keypoints_bytes, read_keypoints,
};
use camloc_store::quoted_path;
use common::fixture;

fn read_bad(name: &str, format: Option<KeypointFormat>) -> KeypointError {
    let path = fixture(&format!("bad/{name}"));
    match read_keypoints(&path, format, &ReadOptions::default()) {
        Ok(records) => panic!("{name}: expected an error, read {} records", records.len()),
        Err(e) => {
            // Every message starts with the file it is about (as messages quote file names).
            assert!(
                e.to_string().starts_with(&quoted_path(&path)),
                "{name}: {e}"
            );
            e
        }
    }
}

fn line(n: usize) -> Location {
    Location::Line(n)
}

fn path(p: &str) -> Location {
    Location::Path(p.to_owned())
}

#[test]
fn empty_inputs() {
    assert!(matches!(
        read_bad("empty.json", None),
        KeypointError::Empty { .. }
    ));
    assert!(matches!(
        read_bad("blank.csv", None),
        KeypointError::Empty { .. }
    ));
    for format in KeypointFormat::ALL {
        let read = parse_keypoints(" \n", "x", Some(format), &ReadOptions::default());
        match format {
            // A YOLO frame where nobody was detected.
            KeypointFormat::Yolo => assert_eq!(read.unwrap(), []),
            _ => assert!(matches!(read, Err(KeypointError::Empty { .. })), "{format}"),
        }
    }
}

#[test]
fn csv_header_with_four_columns() {
    let e = read_bad("header_4_columns.csv", None);
    assert!(
        matches!(&e, KeypointError::CsvHeader { line: 1, missing, extra, .. } if missing == &["visible"] && extra.is_empty()),
        "{e:?}"
    );
}

#[test]
fn csv_row_with_extra_field() {
    let e = read_bad("row_field_count.csv", None);
    assert!(
        matches!(
            e,
            KeypointError::CsvFieldCount {
                line: 4,
                expected: 5,
                found: 6,
                ..
            }
        ),
        "{e:?}"
    );
}

#[test]
fn csv_unknown_joint() {
    let e = read_bad("unknown_joint.csv", None);
    assert!(
        matches!(&e, KeypointError::UnknownJoint { at, name, .. } if *at == line(3) && name == "left_toe"),
        "{e:?}"
    );
    assert!(
        e.to_string().contains("head_top"),
        "the message lists the known joints: {e}"
    );
}

#[test]
fn csv_joint_given_twice_for_one_image() {
    let e = read_bad("duplicate_joint.csv", None);
    assert!(
        matches!(&e, KeypointError::DuplicateJoint { at, first, image, joint, .. }
            if *at == line(5) && *first == line(2) && image == "im1" && joint == "neck"),
        "{e:?}"
    );
}

#[test]
fn csv_non_numeric_and_non_finite_coordinates() {
    let e = read_bad("non_numeric.csv", None);
    assert!(
        matches!(&e, KeypointError::InvalidValue { at, field: "x", text, .. } if *at == line(3) && text == "abc"),
        "{e:?}"
    );
    let e = read_bad("non_finite.csv", None);
    assert!(
        matches!(&e, KeypointError::NonFinite { at, field: "y", .. } if *at == line(4)),
        "{e:?}"
    );
    for bad in ["inf", "-infinity", "1e999"] {
        let text = format!("image,joint,x,y,visible\nim,neck,{bad},1,1\n");
        let e = parse_keypoints(&text, "t.csv", None, &ReadOptions::default()).unwrap_err();
        assert!(
            matches!(&e, KeypointError::NonFinite { at, field: "x", .. } if *at == line(2)),
            "{bad}: {e:?}"
        );
    }
}

#[test]
fn csv_visibility_must_be_zero_or_one() {
    let e = read_bad("visible_flag.csv", None);
    assert!(
        matches!(&e, KeypointError::InvalidValue { at, field: "visible", .. } if *at == line(2)),
        "{e:?}"
    );
}

#[test]
fn csv_empty_image_name() {
    let e = parse_keypoints(
        "image,joint,x,y,visible\n ,neck,1,1,1\n",
        "t.csv",
        None,
        &ReadOptions::default(),
    )
    .unwrap_err();
    assert!(
        matches!(&e, KeypointError::InvalidValue { at, field: "image", .. } if *at == line(2)),
        "{e:?}"
    );
}

#[test]
fn non_utf8_is_reported_with_its_line() {
    let e = read_bad("not_utf8.csv", None);
    assert!(matches!(e, KeypointError::NotUtf8 { line: 3, .. }), "{e:?}");
    let e = parse_keypoints_bytes(
        b"{\"poses\": [\xc3]}",
        "b.json",
        None,
        &ReadOptions::default(),
    )
    .unwrap_err();
    assert!(
        matches!(
            e,
            KeypointError::NotUtf8 {
                line: 1,
                offset: 11,
                ..
            }
        ),
        "{e:?}"
    );
}

#[test]
fn json_syntax_error_has_line_and_column() {
    let e = read_bad("syntax.json", None);
    assert!(
        matches!(e, KeypointError::Json { line: 5, column, .. } if column > 0),
        "{e:?}"
    );
}

#[test]
fn camloc_unknown_landmarks_are_all_named() {
    let e = read_bad("unknown_landmark.json", None);
    assert!(
        matches!(&e, KeypointError::UnknownKeys { at, keys, .. } if *at == path("poses[1].landmarks") && keys == &["nose", "left_kne"]),
        "{e:?}"
    );
    let msg = e.to_string();
    assert!(
        msg.contains("\"nose\", \"left_kne\"") && msg.contains("left_knee"),
        "{msg}"
    );
}

#[test]
fn camloc_landmark_given_twice() {
    let e = read_bad("duplicate_landmark.json", None);
    assert!(
        matches!(&e, KeypointError::DuplicateKey { at, .. } if *at == path("poses[0].landmarks.neck")),
        "{e:?}"
    );
}

#[test]
fn camloc_landmark_not_u_v() {
    let e = read_bad("landmark_length.json", None);
    assert!(
        matches!(&e, KeypointError::WrongLength { at, expected: 2, found: 3, .. } if *at == path("poses[2].landmarks.left_knee")),
        "{e:?}"
    );
    let e = read_bad("landmark_not_number.json", None);
    assert!(
        matches!(&e, KeypointError::WrongType { at, expected: "a number", found: "a string", .. } if *at == path("poses[0].landmarks.head[0]")),
        "{e:?}"
    );
}

#[test]
fn camloc_version_and_format_tag_are_checked() {
    let e = read_bad("wrong_version.json", None);
    assert!(
        matches!(&e, KeypointError::UnsupportedVersion { at, found, .. } if *at == path("version") && found == "2"),
        "{e:?}"
    );
    let e = read_bad("wrong_format_tag.json", None);
    assert!(
        matches!(&e, KeypointError::InvalidValue { at, field: "format", text, .. } if *at == path("format") && text == "openpose"),
        "{e:?}"
    );
}

#[test]
fn json_that_is_not_an_object() {
    // Nothing tells the format ...
    assert!(matches!(
        read_bad("top_level_number.json", None),
        KeypointError::UnknownFormat { .. }
    ));
    // ... and once named, the shape is wrong at the top level.
    let e = read_bad("top_level_number.json", Some(KeypointFormat::Camloc));
    assert!(
        matches!(&e, KeypointError::WrongType { at, found: "a number", .. } if *at == path("")),
        "{e:?}"
    );
    assert!(e.to_string().contains("top level"), "{e}");
    let e = read_bad("top_level_number.json", Some(KeypointFormat::Coco));
    assert!(
        matches!(&e, KeypointError::WrongType { at, found: "a number", .. } if *at == path("")),
        "{e:?}"
    );
}

#[test]
fn coco_keypoints_must_be_51_numbers() {
    let e = read_bad("coco_keypoints_length.json", None);
    assert!(
        matches!(&e, KeypointError::WrongLength { at, expected: 51, found: 48, .. } if *at == path("annotations[1].keypoints")),
        "{e:?}"
    );
    let e = read_bad("coco_keypoint_type.json", None);
    assert!(
        matches!(&e, KeypointError::WrongType { at, found: "a string", .. } if *at == path("annotations[0].keypoints[4]")),
        "{e:?}"
    );
}

#[test]
fn coco_entry_without_image_id() {
    let e = read_bad("coco_missing_image_id.json", None);
    assert!(
        matches!(&e, KeypointError::MissingKey { at, key: "image_id", .. } if *at == path("[0]")),
        "{e:?}"
    );
}

#[test]
fn coco_dataset_without_annotations() {
    let e = parse_keypoints(
        r#"{"images": [], "keypoints": 1}"#,
        "c.json",
        None,
        &ReadOptions::default(),
    )
    .unwrap_err();
    assert!(
        matches!(
            e,
            KeypointError::MissingKey {
                key: "annotations",
                ..
            }
        ),
        "{e:?}"
    );
}

#[test]
fn unknown_format() {
    let e = read_bad("unknown_format.txt", None);
    assert!(
        matches!(&e, KeypointError::UnknownFormat { reason, .. } if reason.contains(".txt")),
        "{e:?}"
    );
}

#[test]
fn missing_file_and_directory() {
    let missing = fixture("bad/no_such_file.json");
    let e = read_keypoints(&missing, None, &ReadOptions::default()).unwrap_err();
    assert!(
        matches!(&e, KeypointError::Io { source, .. } if source.kind() == std::io::ErrorKind::NotFound),
        "{e:?}"
    );
    assert!(e.to_string().contains("no_such_file.json"), "{e}");
    let e = read_keypoints(fixture("bad"), None, &ReadOptions::default()).unwrap_err();
    assert!(matches!(e, KeypointError::Io { .. }), "{e:?}");
}

#[test]
fn inputs_over_the_size_limit_are_refused() {
    let options = ReadOptions {
        max_bytes: 100,
        ..ReadOptions::default()
    };
    let e = read_keypoints(fixture("example.json"), None, &options).unwrap_err();
    assert!(
        matches!(e, KeypointError::TooLarge { limit: 100, bytes, .. } if bytes > 100),
        "{e:?}"
    );
    let e = parse_keypoints(&"x".repeat(101), "t.csv", None, &options).unwrap_err();
    assert!(
        matches!(e, KeypointError::TooLarge { bytes: 101, .. }),
        "{e:?}"
    );
}

#[test]
fn endless_special_file_is_cut_at_the_limit() {
    let zero = std::path::Path::new("/dev/zero");
    if !zero.exists() {
        println!("skipping: /dev/zero not found");
        return;
    }
    let options = ReadOptions {
        max_bytes: 1 << 16,
        ..ReadOptions::default()
    };
    let e = read_keypoints(zero, Some(KeypointFormat::Lsp), &options).unwrap_err();
    assert!(
        matches!(e, KeypointError::TooLarge { bytes, .. } if bytes == (1 << 16) + 1),
        "{e:?}"
    );
}

#[test]
fn deep_nesting_and_huge_numbers_do_not_crash() {
    // With an image size, so that MediaPipe reads its frames too.
    let options = ReadOptions {
        image_size: Some("640,480".parse().unwrap()),
        ..ReadOptions::default()
    };
    let nested = |prefix: &str, suffix: &str| {
        format!(
            "{prefix}{}{}{suffix}",
            "[".repeat(100_000),
            "]".repeat(100_000)
        )
    };
    for (text, format) in [
        (nested(r#"{"poses": "#, "}"), KeypointFormat::Camloc),
        // A list of lists is MediaPipe's list of frames.
        (nested("", ""), KeypointFormat::MediaPipe),
        (
            nested(r#"{"annotations": [{"image_id": 1, "keypoints": "#, "}]}"),
            KeypointFormat::Coco,
        ),
    ] {
        let e = parse_keypoints(&text, "deep.json", None, &options).unwrap_err();
        assert_eq!(
            KeypointFormat::from_extension_and_content(Some("json"), &text),
            Some(format)
        );
        assert!(
            matches!(e, KeypointError::Json { line: 1, .. }),
            "{format}: {e:?}"
        );
    }
    // Fields the COCO reader skips are skipped however deep they are.
    let skipped = nested(r#"{"annotations": [{"segmentation": "#, "}]}");
    let e = parse_keypoints(&skipped, "deep.json", None, &options).unwrap_err();
    assert!(
        matches!(
            e,
            KeypointError::MissingKey {
                key: "image_id",
                ..
            }
        ),
        "{e:?}"
    );
    let huge = r#"{"poses": [{"landmarks": {"neck": [1e400, 0]}}]}"#;
    let e = parse_keypoints(huge, "huge.json", None, &options).unwrap_err();
    assert!(matches!(e, KeypointError::Json { line: 1, .. }), "{e:?}");
    // Many rows are fine: the reader is linear.
    let mut csv = String::from("image,joint,x,y,visible\n");
    for i in 0..20_000 {
        csv.push_str(&format!("im{i},neck,{i},1.5,1\n"));
    }
    assert_eq!(
        parse_keypoints(&csv, "many.csv", None, &options)
            .unwrap()
            .len(),
        20_000
    );
}

/// Reads `bad/<name>` with `options`, checking that the error is one short line naming the file.
fn read_bad_with(name: &str, format: Option<KeypointFormat>, options: &ReadOptions) -> String {
    let path = fixture(&format!("bad/{name}"));
    match read_keypoints(&path, format, options) {
        Ok(records) => panic!("{name}: expected an error, read {} records", records.len()),
        Err(e) => {
            let message = e.to_string();
            let file = quoted_path(&path);
            assert!(message.starts_with(&file), "{name}: {message}");
            assert!(!message.contains('\n'), "{name}: {message}");
            let after_file = message.len() - file.len();
            assert!(after_file < 240, "{name}: {message}");
            message[file.len()..].to_owned()
        }
    }
}

/// Options for the new formats' malformed files: an image size (MediaPipe needs one).
fn with_size() -> ReadOptions {
    ReadOptions {
        image_size: Some(ImageSize {
            width: 640.0,
            height: 480.0,
        }),
        ..ReadOptions::default()
    }
}

#[test]
fn detector_formats_report_file_and_place() {
    use KeypointFormat::*;
    let options = with_size();
    // (file, format to name or None to detect, what the message says after the file name)
    let cases: [(&str, Option<KeypointFormat>, &str); 18] = [
        (
            "openpose_truncated_000000000003_keypoints.json",
            None,
            ": line 1, column 200: EOF while parsing",
        ),
        (
            "openpose_length_keypoints.json",
            None,
            ": people[0].pose_keypoints_2d: expected 75 numbers (BODY_25 x, y, c triples, or 54 for COCO-18), found 74",
        ),
        (
            "openpose_empty_keypoints.json",
            None,
            ": people[0].pose_keypoints_2d: expected 75 numbers (BODY_25 x, y, c triples, or 54 for COCO-18), found 0",
        ),
        (
            "openpose_confidence_keypoints.json",
            None,
            ": people[0].pose_keypoints_2d[5]: confidence 1.5 is outside [0, 1]",
        ),
        (
            "openpose_no_people_keypoints.json",
            Some(OpenPose),
            ": top level: missing required key \"people\"",
        ),
        (
            "mmpose_scores_length.json",
            None,
            ": [0].keypoint_scores: expected 17 numbers (one score per keypoint), found 16",
        ),
        (
            "mmpose_point_length.json",
            Some(MmPose),
            ": [0].keypoints[5]: expected 2 numbers ([x, y]), found 3",
        ),
        (
            "mmpose_13_joints.json",
            None,
            ": instance_info[0].instances[0].keypoints: 13 joints: no layout has 13",
        ),
        (
            "mmpose_no_instances.json",
            Some(MmPose),
            ": top level: missing required key \"instance_info\"",
        ),
        (
            "mediapipe_32_landmarks.json",
            None,
            ": [1]: expected 33 landmarks (MediaPipe Pose, or null for a frame without a person), found 32",
        ),
        (
            "mediapipe_visibility.json",
            None,
            ": [1][11].visibility: visibility 1.2 is outside [0, 1]",
        ),
        (
            "mediapipe_unknown_key.json",
            None,
            ": [0][0]: unknown key(s) \"visibilty\"",
        ),
        (
            "mediapipe_empty_frame.json",
            None,
            ": [0]: expected 33 landmarks (MediaPipe Pose, or null for a frame without a person), found 0",
        ),
        (
            "mediapipe_world_landmarks.json",
            None,
            ": [0]: landmarks \"hips' midpoint (0.0000, 0.0000)\" is not pose_landmarks",
        ),
        (
            "mpii_joints_vis.json",
            None,
            ": [0].joints_vis[7]: joints_vis \"2\" is not 0 or 1",
        ),
        (
            "mpii_15_joints.json",
            None,
            ": [0].joints: expected 16 joints (MPII [x, y]), found 15",
        ),
        (
            "mpii_missing_joints.json",
            Some(Mpii),
            ": [0]: missing required key \"joints\"",
        ),
        (
            "npy_truncated.npy",
            None,
            ": the file has 828 bytes, but a <f8 array of shape (3, 15, 2) needs 848 (truncated?)",
        ),
    ];
    for (name, format, expected) in cases {
        let message = read_bad_with(name, format, &options);
        assert!(
            message.starts_with(expected),
            "{name}:\n  got      {message}\n  expected {expected}"
        );
    }
}

#[test]
fn npy_arrays_report_file_and_element() {
    let options = ReadOptions::default();
    let cases = [
        (
            "npy_nan.npy",
            ": [0, 3]: one coordinate is NaN and the other is not (NaN, NaN marks a missing joint)",
        ),
        (
            "npy_inf.npy",
            ": [0, 5, 1]: coordinate \"inf\" is not a finite number",
        ),
        (
            "npy_score_out_of_range.npy",
            ": [0, 4, 2]: score 1.5 is outside [0, 1]; (N, J, 3) keypoint arrays hold x, y, score",
        ),
        (
            "npy_shape_2d.npy",
            ": shape (1, 30) is not (N, J, 2) or (N, J, 3)",
        ),
        (
            "npy_13_joints.npy",
            ": shape: 13 joints: no layout has 13 (layouts: coco17 17,",
        ),
        (
            "npy_17_joints.npy",
            ": shape: 17 joints: that can be coco17 or h36m17: name the layout",
        ),
        ("npy_int32.npy", ": dtype <i4 is not float64 or float32"),
        (
            "npy_shape_overflow.npy",
            ": the header's shape is not a tuple of sizes with a product below 2^64",
        ),
        (
            "npy_header_length.npy",
            ": the header claims 4294967295 bytes, more than 10000",
        ),
    ];
    for (name, expected) in cases {
        let message = read_bad_with(name, None, &options);
        assert!(
            message.starts_with(expected),
            "{name}:\n  got      {message}\n  expected {expected}"
        );
    }
    // A layout that does not match the array.
    let options = ReadOptions {
        layout: Some(Layout::Coco17),
        ..ReadOptions::default()
    };
    let message = read_bad_with("npy_13_joints.npy", Some(KeypointFormat::Npy), &options);
    assert!(
        message.starts_with(": shape: 13 joints: layout coco17 has 17"),
        "{message}"
    );
}

#[test]
fn a_truncated_npy_stream_fails_at_the_pose_where_the_data_end() {
    let bytes = std::fs::read(fixture("bad/npy_truncated.npy")).unwrap();
    let stream = camloc_keypoints::open_keypoints_reader(
        std::io::Cursor::new(bytes),
        "-",
        None,
        None,
        &ReadOptions::default(),
    )
    .unwrap();
    let results: Vec<_> = stream.collect();
    assert_eq!(results.len(), 3, "two poses, then the error, then nothing");
    assert!(results[0].is_ok() && results[1].is_ok());
    let e = results[2].as_ref().unwrap_err().to_string();
    assert_eq!(e, "-: [2]: the data end inside pose 2 of 3 (truncated?)");
}

#[test]
fn a_folder_with_a_bad_file_reports_it_and_goes_on() {
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("openpose_folder");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("nested")).unwrap();
    let samples = fixture("samples/openpose");
    for entry in std::fs::read_dir(&samples).unwrap() {
        let path = entry.unwrap().path();
        std::fs::copy(&path, dir.join(path.file_name().unwrap())).unwrap();
    }
    std::fs::copy(
        fixture("bad/openpose_confidence_keypoints.json"),
        dir.join("clip_000000000001b_keypoints.json"),
    )
    .unwrap();
    std::fs::copy(
        fixture("samples/openpose/clip_000000000000_keypoints.json"),
        dir.join("nested/clip_000000000010_keypoints.json"),
    )
    .unwrap();
    std::fs::write(dir.join("notes.txt"), "not keypoints").unwrap();
    let options = ReadOptions::default();
    let results: Vec<_> = camloc_keypoints::read_folder(&dir, None, &options, false)
        .unwrap()
        .map(|(path, result)| {
            (
                path.file_name().unwrap().to_string_lossy().into_owned(),
                result.map(|r| r.len()).map_err(|e| e.to_string()),
            )
        })
        .collect();
    let names: Vec<&str> = results.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        [
            "clip_000000000000_keypoints.json",
            "clip_000000000001_keypoints.json",
            "clip_000000000001b_keypoints.json",
            "clip_000000000002_keypoints.json"
        ]
    );
    assert_eq!(results[0].1, Ok(1));
    assert_eq!(results[1].1, Ok(2));
    let e = results[2].1.as_ref().unwrap_err();
    assert!(
        e.contains("clip_000000000001b_keypoints.json: people[0]"),
        "{e}"
    );
    assert_eq!(results[3].1, Ok(0));
    // Recursive: the nested file comes too, in natural order of the whole path.
    let recursive = camloc_keypoints::keypoint_files(&dir, true).unwrap();
    assert_eq!(recursive.len(), 5);
    assert!(recursive[4].ends_with("nested/clip_000000000010_keypoints.json"));
    // A missing folder is an error of its own.
    assert!(camloc_keypoints::read_folder(dir.join("absent"), None, &options, false).is_err());
}

/// The length of an error message (issue 15: messages cap what they quote).
fn message_of(text: &str, name: &str, format: Option<KeypointFormat>) -> String {
    let e = parse_keypoints(text, name, format, &ReadOptions::default()).unwrap_err();
    let message = e.to_string();
    assert!(!message.contains('\n'), "{message}");
    message
}

#[test]
fn errors_quote_at_most_a_short_piece_of_huge_input() {
    let huge = "k".repeat(50 << 20);
    // An unknown 50 MB key.
    let text = format!(r#"{{"poses": [{{"landmarks": {{"{huge}": [1, 2]}}}}]}}"#);
    let m = message_of(&text, "key.json", None);
    assert!(m.len() < 400, "{m}");
    assert!(
        m.contains(&format!(
            "\"{}…\"",
            "k".repeat(camloc_keypoints::MAX_QUOTED_CHARS)
        )),
        "{m}"
    );
    drop(text);
    // A 50 MB line without a newline, as a CSV header and as a field.
    let m = message_of(&huge, "line.csv", None);
    assert!(m.len() < 400, "{m}");
    let text = format!("image,joint,x,y,visible\nim1,neck,{huge},1,1");
    let m = message_of(&text, "field.csv", None);
    assert!(m.len() < 400 && m.contains("line 2"), "{m}");
    // A 50 MB string where a COCO annotation belongs (the JSON parser quotes it).
    let text = format!(r#"["{huge}"]"#);
    let m = message_of(&text, "coco.json", Some(KeypointFormat::Coco));
    assert!(m.len() < 400, "{m}");
    drop(huge);
    // A header of a million columns, and a million unknown keys.
    let columns: String = (0..1_000_000).map(|i| format!("c{i},")).collect();
    let m = message_of(&columns, "wide.csv", None);
    assert!(m.len() < 1200, "{} chars", m.len());
    // 1,000,000 named columns and an empty one after the last comma.
    assert!(m.contains("and 999993 more"), "{m}");
    let keys: Vec<String> = (0..40_000).map(|i| format!(r#""k{i}": null"#)).collect();
    let text = format!(r#"{{"landmarks": {{{}}}}}"#, keys.join(","));
    let m = message_of(&text, "keys.json", None);
    assert!(m.len() < 1200 && m.contains("and 39992 more"), "{m}");
    // A million keys are more values than one entry may hold (MAX_ENTRY_VALUES).
    let keys: Vec<String> = (0..1_000_000).map(|i| format!(r#""k{i}": null"#)).collect();
    let text = format!(r#"{{"landmarks": {{{}}}}}"#, keys.join(","));
    let m = message_of(&text, "keys.json", None);
    assert!(m.len() < 300 && m.contains("MAX_ENTRY_VALUES"), "{m}");
    // Control characters in quoted input are escaped: the message stays on one line.
    let m = message_of("image,joint,x,y,visible\nim1,ne\nck,1,1,1", "nl.csv", None);
    assert!(!m.contains('\n'), "{m}");
    let m = message_of(r#"{"landmarks": {"a\nb": null}}"#, "nl.json", None);
    assert!(m.contains(r#""a\nb""#), "{m}");
}

#[test]
fn openpose_frames_have_their_own_size_cap() {
    let limit = camloc_keypoints::OPENPOSE_FRAME_MAX_BYTES;
    let text = format!(
        r#"{{"people": [], "pad": "{}"}}"#,
        " ".repeat(limit as usize)
    );
    for format in [None, Some(KeypointFormat::OpenPose)] {
        let e = parse_keypoints(&text, "frame.json", format, &ReadOptions::default()).unwrap_err();
        assert!(
            matches!(e, KeypointError::TooLarge { limit: l, rule, .. } if l == limit && rule.contains("OPENPOSE")),
            "{e:?}"
        );
    }
    // A frame of known size whose format is found from its content is refused before it is
    // read (it was read, its poses given, and then cut at the limit), with its own size.
    let frame = format!(
        r#"{{"people": [{{"pose_keypoints_2d": [{}]}}], "pad": "{}"}}"#,
        vec!["1.0"; 54].join(", "),
        " ".repeat(limit as usize)
    );
    let size = frame.len() as u64;
    let opened = camloc_keypoints::open_keypoints_reader(
        std::io::Cursor::new(frame.into_bytes()),
        "f_000000000001_keypoints.json",
        Some(size),
        None,
        &ReadOptions::default(),
    );
    assert!(
        matches!(&opened, Err(KeypointError::TooLarge { bytes, limit: l, .. }) if *bytes == size && *l == limit),
        "{:?}",
        opened.err()
    );
    // An .npy header that promises more poses than the file holds is refused before reading.
    let bytes = std::fs::read(fixture("bad/npy_truncated.npy")).unwrap();
    let mut promised = bytes.clone();
    let at = promised.windows(2).position(|w| w == b"(3").unwrap();
    promised[at + 1] = b'9';
    let e =
        camloc_keypoints::parse_keypoints_bytes(&promised, "p.npy", None, &ReadOptions::default())
            .unwrap_err();
    assert!(e.to_string().contains("needs 2288 (truncated?)"), "{e}");
}
