//! Property tests: camloc JSON round trips exactly, and no input panics a reader.

mod common;

use camloc_keypoints::{
    KeypointFormat, PartialPose2, ReadOptions, derive_torso, parse_keypoints,
    parse_keypoints_bytes, to_camloc_json,
};
use common::fixture_text;
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

fn poses() -> impl Strategy<Value = Vec<(String, PartialPose2)>> {
    prop::collection::vec((any::<String>(), partial_pose()), 0..5)
}

proptest! {
    #[test]
    fn camloc_json_round_trip_is_identity(poses in poses()) {
        let options = ReadOptions { derive_torso: false, ..ReadOptions::default() };
        let text = to_camloc_json(&poses);
        let records = parse_keypoints(&text, "rt.json", None, &options).unwrap();
        prop_assert_eq!(records.len(), poses.len());
        for (i, (record, (id, pose))) in records.iter().zip(&poses).enumerate() {
            prop_assert_eq!(&record.id, id);
            prop_assert_eq!(&record.pose, pose);
            prop_assert!(record.derived.is_empty());
            prop_assert_eq!(&record.source, &format!("rt.json: poses[{i}]"));
        }
    }

    #[test]
    fn camloc_json_read_with_derivation_applies_the_rule(poses in poses()) {
        let text = to_camloc_json(&poses);
        let records = parse_keypoints(&text, "rt.json", None, &ReadOptions::default()).unwrap();
        for (record, (_, pose)) in records.iter().zip(&poses) {
            let mut expected = *pose;
            let derived = derive_torso(&mut expected);
            prop_assert_eq!(&record.pose, &expected);
            prop_assert_eq!(&record.derived, &derived);
        }
    }

}

proptest! {
    // Parsing is cheap: run the no-panic properties on more cases.
    #![proptest_config(ProptestConfig::with_cases(2048))]

    #[test]
    fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..512)) {
        let options = ReadOptions::default();
        for name in ["x.json", "x.csv", "x"] {
            let _ = parse_keypoints_bytes(&bytes, name, None, &options);
        }
        for format in KeypointFormat::ALL {
            let _ = parse_keypoints_bytes(&bytes, "x", Some(format), &options);
        }
    }

    #[test]
    fn mutated_fixtures_never_panic(
        which in 0usize..5,
        edits in prop::collection::vec((any::<prop::sample::Index>(), 0u8..3, any::<u8>()), 1..8),
    ) {
        let names = ["example.json", "partial.json", "tiny_lsp.csv", "tiny_coco.json", "tiny_coco_results.json"];
        let mut bytes = fixture_text(names[which]).into_bytes();
        for (at, op, byte) in edits {
            let i = at.index(bytes.len() + 1);
            match op {
                0 => bytes.insert(i, byte),
                1 if i < bytes.len() => { bytes.remove(i); }
                _ if i < bytes.len() => bytes[i] = byte,
                _ => {}
            }
        }
        let options = ReadOptions::default();
        let _ = parse_keypoints_bytes(&bytes, names[which], None, &options);
        for format in KeypointFormat::ALL {
            let _ = parse_keypoints_bytes(&bytes, names[which], Some(format), &options);
        }
    }

    #[test]
    fn arbitrary_text_with_format_keys_never_panics(
        text in r#"[\[\]{}",:0-9a-z_. \n-]{0,200}"#,
    ) {
        let options = ReadOptions::default();
        for format in KeypointFormat::ALL {
            let _ = parse_keypoints(&text, "t", Some(format), &options);
        }
    }
}
