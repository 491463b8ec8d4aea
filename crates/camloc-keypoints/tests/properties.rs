//! Property tests: camloc JSON round trips exactly, and no input panics a reader.

mod common;

use camloc_keypoints::{
    ArrayPoseError, ImageSize, KeypointError, KeypointFormat, KeypointRecord, Layout,
    MAX_FRAME_NUMBER, NpyPoseWriter, PartialPose2, Pose3, ReadOptions, derive_torso,
    parse_keypoints, parse_keypoints_bytes, pose_from_array, read_npy_poses3, to_camloc_json,
    write_npy,
};
use common::fixture;
use proptest::prelude::*;

/// Any finite f64, or a pixel-like one.
fn coordinate() -> impl Strategy<Value = f64> {
    use proptest::num::f64::{NEGATIVE, NORMAL, POSITIVE, SUBNORMAL, ZERO};
    prop_oneof![
        POSITIVE | NEGATIVE | NORMAL | SUBNORMAL | ZERO,
        -5000.0..5000.0f64
    ]
}

fn partial_pose() -> impl Strategy<Value = PartialPose2> {
    prop::array::uniform15(prop::option::of([coordinate(), coordinate()]))
        .prop_map(|points| PartialPose2 { points })
}

/// Options under which every reader parses as far as it can (MediaPipe needs an image size;
/// 17-joint arrays need a layout).
fn any_options() -> ReadOptions {
    ReadOptions {
        image_size: Some(ImageSize {
            width: 640.0,
            height: 480.0,
        }),
        layout: Some(Layout::H36m17),
        min_score: 0.3,
        ..ReadOptions::default()
    }
}

/// Records as the camloc JSON writer takes them: any id, pose, frame and person (the source
/// and derived landmarks are not written).
fn poses() -> impl Strategy<Value = Vec<KeypointRecord>> {
    let number = || prop::option::of(0..=MAX_FRAME_NUMBER);
    prop::collection::vec((any::<String>(), partial_pose(), number(), number()), 0..5).prop_map(
        |items| {
            items
                .into_iter()
                .map(|(id, pose, frame, person)| KeypointRecord {
                    id,
                    pose,
                    derived: Vec::new(),
                    source: String::new(),
                    frame,
                    person,
                    person_is_position: false,
                })
                .collect()
        },
    )
}

proptest! {
    #[test]
    fn camloc_json_round_trip_is_identity(poses in poses()) {
        let options = ReadOptions { derive_torso: false, ..ReadOptions::default() };
        let text = to_camloc_json(&poses);
        let records = parse_keypoints(&text, "rt.json", None, &options).unwrap();
        prop_assert_eq!(records.len(), poses.len());
        for (i, (record, written)) in records.iter().zip(&poses).enumerate() {
            prop_assert_eq!(&record.id, &written.id);
            prop_assert_eq!(&record.pose, &written.pose);
            prop_assert_eq!((record.frame, record.person), (written.frame, written.person));
            prop_assert!(record.derived.is_empty());
            prop_assert_eq!(&record.source, &format!("rt.json: poses[{i}]"));
        }
    }

    #[test]
    fn camloc_json_read_with_derivation_applies_the_rule(poses in poses()) {
        let text = to_camloc_json(&poses);
        let records = parse_keypoints(&text, "rt.json", None, &ReadOptions::default()).unwrap();
        for (record, written) in records.iter().zip(&poses) {
            let mut expected = written.pose;
            let derived = derive_torso(&mut expected);
            prop_assert_eq!(&record.pose, &expected);
            prop_assert_eq!(&record.derived, &derived);
        }
    }


    #[test]
    fn npy_2d_round_trip_is_identity(poses in prop::collection::vec(partial_pose(), 0..6)) {
        let mut bytes = Vec::new();
        write_npy(&mut bytes, &poses).unwrap();
        let options = ReadOptions { derive_torso: false, ..ReadOptions::default() };
        let records = parse_keypoints_bytes(&bytes, "rt.npy", None, &options).unwrap();
        prop_assert_eq!(records.len(), poses.len());
        for (n, (record, pose)) in records.iter().zip(&poses).enumerate() {
            prop_assert_eq!(&record.pose, pose);
            prop_assert_eq!(&record.id, &n.to_string());
            prop_assert_eq!(record.frame, Some(n as u64));
        }
    }

    #[test]
    fn npy_3d_round_trip_is_identity(
        points in prop::collection::vec(prop::array::uniform15([coordinate(), coordinate(), coordinate()]), 0..6),
    ) {
        let poses: Vec<Pose3> = points.into_iter().map(Pose3::new).collect();
        let mut bytes = Vec::new();
        let mut writer = NpyPoseWriter::<_, Pose3>::new(&mut bytes, poses.len() as u64).unwrap();
        for pose in &poses {
            writer.push(pose).unwrap();
        }
        writer.finish().unwrap();
        let back = read_npy_poses3(&bytes[..], "rt.npy").unwrap();
        prop_assert_eq!(back, poses);
    }

    #[test]
    fn raw_arrays_map_like_the_npy_reader(
        layout in prop::sample::select(Layout::ALL.to_vec()),
        joints in prop::collection::vec(
            prop::option::weighted(0.8, (-1e4..1e4f64, -1e4..1e4f64, 0.0..=1.0f64)),
            33,
        ),
        channels in 2usize..4,
        min_score in 0.0..1.0f64,
    ) {
        // Missing joints are NaN, NaN (score 0.5); present ones carry their score.
        let values: Vec<f64> = joints[..layout.joint_count()]
            .iter()
            .flat_map(|j| {
                let (x, y, c) = j.unwrap_or((f64::NAN, f64::NAN, 0.5));
                [x, y, c].into_iter().take(channels)
            })
            .collect();
        let options = ReadOptions { min_score, layout: Some(layout), ..ReadOptions::default() };
        let direct = pose_from_array(layout, &values, channels, &options);
        let dims = format!("({}, {}, {})", 1, layout.joint_count(), channels);
        let mut header = format!("{{'descr': '<f8', 'fortran_order': False, 'shape': {dims}, }}");
        while !(10 + header.len() + 1).is_multiple_of(64) { header.push(' '); }
        header.push('\n');
        let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
        bytes.extend_from_slice(&(header.len() as u16).to_le_bytes());
        bytes.extend_from_slice(header.as_bytes());
        for v in &values { bytes.extend_from_slice(&v.to_le_bytes()); }
        let read = parse_keypoints_bytes(&bytes, "x.npy", None, &options);
        match (direct, read) {
            (Ok(mapped), Ok(records)) => {
                prop_assert_eq!(records.len(), 1);
                prop_assert_eq!(&records[0].pose, &mapped.pose);
                prop_assert_eq!(&records[0].derived, &mapped.derived);
                // A joint is present only if both its coordinates are numbers.
                for (j, row) in values.chunks(channels).enumerate() {
                    if let Some(l) = layout.joint_landmark(j) {
                        let present = mapped.pose.points[l.index()].is_some();
                        let numbers = !row[0].is_nan() && !row[1].is_nan();
                        let scored = channels == 2 || (row[2] > 0.0 && row[2] >= min_score);
                        prop_assert!(present == (numbers && scored) || mapped.derived.contains(&l));
                    }
                }
            }
            // Random joints can look like the other 17-joint layout: both refuse the pose.
            (Err(e @ ArrayPoseError::LayoutMismatch { .. }), Err(KeypointError::LayoutMismatch { source, .. })) => {
                prop_assert_eq!(e, source);
            }
            (direct, read) => prop_assert!(false, "valid input: {direct:?} vs {read:?}"),
        }
    }
}

proptest! {
    // Parsing is cheap: run the no-panic properties on more cases.
    #![proptest_config(ProptestConfig::with_cases(2048))]

    #[test]
    fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..512)) {
        let options = any_options();
        for name in ["x.json", "x.csv", "x", "x.npy"] {
            let _ = parse_keypoints_bytes(&bytes, name, None, &options);
        }
        for format in KeypointFormat::ALL {
            let _ = parse_keypoints_bytes(&bytes, "x", Some(format), &options);
        }
    }

    #[test]
    fn mutated_fixtures_never_panic(
        which in 0usize..13,
        edits in prop::collection::vec((any::<prop::sample::Index>(), 0u8..3, any::<u8>()), 1..8),
    ) {
        let names = [
            "example.json", "partial.json", "tiny_lsp.csv", "tiny_coco.json",
            "tiny_coco_results.json", "samples/openpose/clip_000000000001_keypoints.json",
            "samples/openpose_coco18_000000000007_keypoints.json", "samples/mmpose.json",
            "samples/mediapipe.json", "samples/mpii.json", "samples/camloc15.npy",
            "samples/h36m17_scores.npy", "bad/npy_score_out_of_range.npy",
        ];
        let mut bytes = std::fs::read(fixture(names[which])).unwrap();
        for (at, op, byte) in edits {
            let i = at.index(bytes.len() + 1);
            match op {
                0 => bytes.insert(i, byte),
                1 if i < bytes.len() => { bytes.remove(i); }
                _ if i < bytes.len() => bytes[i] = byte,
                _ => {}
            }
        }
        let options = any_options();
        let _ = parse_keypoints_bytes(&bytes, names[which], None, &options);
        for format in KeypointFormat::ALL {
            let _ = parse_keypoints_bytes(&bytes, names[which], Some(format), &options);
        }
    }

    #[test]
    fn arbitrary_text_with_format_keys_never_panics(
        text in r#"[\[\]{}",:0-9a-z_. \n-]{0,200}"#,
    ) {
        let options = any_options();
        for format in KeypointFormat::ALL {
            let _ = parse_keypoints(&text, "t", Some(format), &options);
        }
    }
}
