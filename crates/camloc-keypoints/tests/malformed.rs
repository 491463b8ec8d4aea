//! Every malformed input gives the expected error, with the place of the problem.

mod common;

use camloc_keypoints::{
    KeypointError, KeypointFormat, Location, ReadOptions, parse_keypoints, parse_keypoints_bytes,
    read_keypoints,
};
use common::fixture;

fn read_bad(name: &str, format: Option<KeypointFormat>) -> KeypointError {
    let path = fixture(&format!("bad/{name}"));
    match read_keypoints(&path, format, &ReadOptions::default()) {
        Ok(records) => panic!("{name}: expected an error, read {} records", records.len()),
        Err(e) => {
            // Every message starts with the file it is about.
            assert!(
                e.to_string().starts_with(&path.display().to_string()),
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
        let e = parse_keypoints(" \n", "x", Some(format), &ReadOptions::default()).unwrap_err();
        assert!(matches!(e, KeypointError::Empty { .. }), "{format}: {e:?}");
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
    assert!(matches!(e, KeypointError::Json { line: 1, .. }), "{e:?}");
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
    let options = ReadOptions::default();
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
