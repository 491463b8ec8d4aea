//! A person's standing height given (`PoseReconstructor::with_person_height`): the estimated
//! lengths keep their proportions and every answer is scaled, with its camera, to the height;
//! the image is unchanged.

mod common;
#[path = "common/hybrid.rs"]
mod hybrid;
#[path = "common/moving.rs"]
mod moving;

use camloc::reconstruct::{BoneLengths, Reconstruction};
use camloc::{PartialPose2, PoseReconstructor};

fn frames() -> Vec<PartialPose2> {
    moving::frames(8)
}

fn reconstructor() -> PoseReconstructor {
    hybrid::hybrid_reconstructor()
}

/// `a` is `b` made `factor` times as large: the pose about its pelvis, the weak-perspective
/// scale divided, the same image.
fn assert_scaled(a: &Reconstruction, b: &Reconstruction, factor: f64) {
    for (p, q) in a.pose.points.iter().zip(&b.pose.points) {
        for axis in 0..3 {
            let expected = b.pose.points[0][axis] + (q[axis] - b.pose.points[0][axis]) * factor;
            assert!(
                (p[axis] - expected).abs() < 1e-12,
                "{p:?} against {q:?} x {factor}"
            );
        }
    }
    assert!((a.camera.scale * factor - b.camera.scale).abs() < 1e-9 * b.camera.scale);
    for (p, q) in a.reprojection().iter().zip(&b.reprojection()) {
        assert!((p[0] - q[0]).abs() < 1e-9 && (p[1] - q[1]).abs() < 1e-9);
    }
    assert_eq!(a.projection_error, b.projection_error);
}

#[test]
fn a_single_pose_is_scaled_to_the_height_and_seen_as_before() {
    let frame = frames()[0];
    let own = reconstructor().reconstruct(&frame).unwrap().reconstruction;
    for height_m in [0.9, 1.85] {
        let tall = reconstructor()
            .with_person_height(height_m)
            .unwrap()
            .reconstruct(&frame)
            .unwrap()
            .reconstruction;
        let lengths = BoneLengths::of_pose(&tall.pose).unwrap();
        assert!((lengths.standing_height_m() - height_m).abs() < 1e-12);
        let own_height = BoneLengths::of_pose(&own.pose).unwrap().standing_height_m();
        assert_scaled(&tall, &own, height_m / own_height);
    }
}

#[test]
fn a_sequence_shares_one_scale_for_its_lengths_and_frames() {
    let frames = frames();
    let own = reconstructor().reconstruct_sequence(&frames).unwrap();
    let tall = reconstructor()
        .with_person_height(1.2)
        .unwrap()
        .reconstruct_sequence(&frames)
        .unwrap();
    assert!((tall.lengths.standing_height_m() - 1.2).abs() < 1e-12);
    let factor = 1.2 / own.lengths.standing_height_m();
    assert_ne!(factor, 1.0);
    for (a, b) in tall.frames.iter().zip(&own.frames) {
        assert_scaled(
            &a.as_ref().unwrap().reconstruction,
            &b.as_ref().unwrap().reconstruction,
            factor,
        );
    }
}

#[test]
fn a_height_out_of_range_or_beside_given_lengths_is_refused() {
    for wrong in [f64::NAN, 0.2, 175.0, f64::INFINITY] {
        let message = reconstructor()
            .with_person_height(wrong)
            .unwrap_err()
            .to_string();
        assert!(message.contains("standing height"), "{message}");
    }
    let message = reconstructor()
        .with_person_height(175.0)
        .unwrap_err()
        .to_string();
    assert!(message.contains("175 cm is 1.75 m"), "{message}");
    let lengths = BoneLengths::from_array([0.3; 14]).unwrap();
    let given = reconstructor().with_bone_lengths(lengths);
    assert!(given.with_person_height(1.7).is_err());
    // Lengths given after a height give the size: the height is dropped.
    let later = reconstructor()
        .with_person_height(1.7)
        .unwrap()
        .with_bone_lengths(lengths);
    assert_eq!(later.person_height_m(), None);
}
