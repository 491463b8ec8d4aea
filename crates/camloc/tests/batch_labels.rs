//! `CameraLocalizer::predict_labels` over many poses (labelled in parallel): the labels of
//! single poses, and errors naming the pose by its index in the whole input.

mod common;

use camloc::{CameraLocalizer, PartialPose2};

/// More poses than the parallel tasks of a 2-core machine take at once.
const MANY: usize = 10_000;

/// The example poses (fixtures/keypoints/example.json), each moved by a deterministic
/// pseudo-random offset of up to 3 px per coordinate, `n` of them in turn.
fn varied_examples(n: usize) -> Vec<PartialPose2> {
    let records = common::example_records();
    let mut state: u64 = 0x2545_f491_4f6c_dd1d;
    let mut offset = move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 6.0
    };
    (0..n)
        .map(|i| {
            let mut pose = records[i % records.len()].pose;
            for p in pose.points.iter_mut().flatten() {
                p[0] += offset();
                p[1] += offset();
            }
            pose
        })
        .collect()
}

#[test]
fn labels_of_many_poses_match_single_poses() {
    let localizer = CameraLocalizer::default_model().unwrap();
    let poses = varied_examples(MANY);
    let labels = localizer.predict_labels(&poses).unwrap();
    assert_eq!(labels.len(), poses.len());
    for (i, (pose, label)) in poses.iter().zip(&labels).enumerate() {
        assert_eq!(
            localizer.localize_partial(pose).unwrap().label,
            *label,
            "pose {i}"
        );
    }
}

#[test]
fn a_bad_pose_far_into_the_input_is_named_by_its_index() {
    let localizer = CameraLocalizer::default_model().unwrap();
    let mut poses = varied_examples(MANY);
    let bad = MANY - 13;
    let first = poses[bad].points.iter().flatten().next().copied().unwrap();
    for p in poses[bad].points.iter_mut().flatten() {
        *p = first;
    }
    let err = localizer.predict_labels(&poses).unwrap_err().to_string();
    assert!(err.contains(&format!("sample {bad}")), "{err}");
}
