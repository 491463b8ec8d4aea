//! Reconstruction of poses with missing landmarks through the facade: filled in with the
//! localized camera, reported, and refused where nothing can be filled in.

mod common;

use camloc::reconstruct::{ReconstructError, mpjpe_after_similarity};
use camloc::{
    CameraLocalizer, CamlocError, DepthLifter, Landmark, MIN_PRESENT_FOR_FILL, ModeKind,
    PartialPose2, PoseReconstructor, default_basis,
};

/// The example's complete poses (image coordinates).
fn example_poses() -> Vec<PartialPose2> {
    common::example_records()
        .into_iter()
        .map(|r| r.pose)
        .collect()
}

fn reconstructor(mode: ModeKind) -> PoseReconstructor {
    PoseReconstructor::new(default_basis().unwrap())
        .unwrap()
        .with_localizer(CameraLocalizer::default_model().unwrap())
        .with_lifter(DepthLifter::default_lifter().unwrap())
        .with_mode(mode)
        .unwrap()
}

/// A pose without its right forearm is reconstructed in every mode, says what was filled in,
/// and stays within 100 mm of the complete pose's reconstruction (no depth flip, no collapse;
/// 31-80 mm measured, most of it the two missing landmarks); a sequence fills in each frame.
/// `opt`, whose camera no localization settles, within 150 mm: the third pose (drawn for a
/// camera above the front, its level a near tie) came out 136 mm away once the viewpoint
/// heads were fitted on mirror images too (the fill is seen from the localized viewpoint, and
/// the pursuit then preferred the other reading in depth); on the 154 complete LSP poses
/// without their right forearm, `opt` was a median 133 mm from the complete poses' 3D, 137
/// before, `hybrid` 109 and 107.
#[test]
fn missing_landmarks_are_filled_in_and_reported() {
    let poses = example_poses();
    assert!(poses.iter().all(|p| p.complete().is_some()));
    for mode in [ModeKind::Opt, ModeKind::Classified, ModeKind::Hybrid] {
        let rec = reconstructor(mode);
        for pose in &poses {
            let complete = rec.reconstruct(pose).unwrap();
            assert!(complete.imputed.is_empty());
            let mut partial = *pose;
            partial.points[Landmark::RightElbow.index()] = None;
            partial.points[Landmark::RightWrist.index()] = None;
            let filled = rec.reconstruct(&partial).unwrap();
            assert_eq!(filled.imputed, [Landmark::RightElbow, Landmark::RightWrist]);
            assert_eq!(filled.localization.is_some(), mode != ModeKind::Opt);
            let apart =
                mpjpe_after_similarity(&filled.reconstruction.pose, &complete.reconstruction.pose);
            eprintln!("{}: {apart:.1} mm from the complete pose's", mode.name());
            let bound = if mode == ModeKind::Opt { 150.0 } else { 100.0 };
            assert!(apart < bound, "{}: {apart:.1} mm", mode.name());
        }
    }
    let mut frames = poses.clone();
    frames[1].points[Landmark::LeftKnee.index()] = None;
    let sequence = reconstructor(ModeKind::Hybrid)
        .reconstruct_sequence(&frames)
        .unwrap();
    let imputed: Vec<Vec<Landmark>> = sequence
        .frames
        .iter()
        .map(|f| f.as_ref().unwrap().imputed.clone())
        .collect();
    assert_eq!(imputed, [vec![], vec![Landmark::LeftKnee], vec![]]);
}

/// Without a localizer nothing fills the missing landmarks in, and a missing pelvis with too
/// few landmarks to fill the torso in is refused by the localization: both are errors that
/// name the cause.
#[test]
fn what_cannot_be_filled_in_is_refused() {
    let mut partial = example_poses()[0];
    partial.points[Landmark::LeftAnkle.index()] = None;
    let alone = PoseReconstructor::new(default_basis().unwrap()).unwrap();
    match alone.reconstruct(&partial) {
        Err(CamlocError::InvalidOption { detail, .. }) => {
            assert!(
                detail.contains("left_ankle") && detail.contains("localizer"),
                "{detail}"
            )
        }
        other => panic!("{other:?}"),
    }
    // The default model's descriptor stands in the hips' midpoint for a missing pelvis;
    // without a hip too, the torso is filled in from the basis (given enough landmarks).
    partial.points[Landmark::Pelvis.index()] = None;
    partial.points[Landmark::LeftHip.index()] = None;
    let filled = reconstructor(ModeKind::Hybrid)
        .reconstruct(&partial)
        .unwrap();
    assert_eq!(
        filled.imputed,
        [Landmark::Pelvis, Landmark::LeftHip, Landmark::LeftAnkle]
    );
    // With fewer than MIN_PRESENT_FOR_FILL landmarks there is no torso to fill in.
    let mut sparse = partial;
    for l in [
        Landmark::RightAnkle,
        Landmark::LeftKnee,
        Landmark::RightKnee,
        Landmark::LeftWrist,
        Landmark::RightWrist,
    ] {
        sparse.points[l.index()] = None;
    }
    assert_eq!(
        sparse.points.iter().flatten().count(),
        MIN_PRESENT_FOR_FILL - 1
    );
    let error = reconstructor(ModeKind::Hybrid)
        .reconstruct(&sparse)
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("pelvis") && error.contains("7 landmarks present"),
        "{error}"
    );
    // With the torso but fewer than MIN_PRESENT_FOR_FILL landmarks, the pose is localized
    // (its probabilities say how little it shows) but not reconstructed: most of its 3D
    // would be the basis's guess.
    let mut torso_only = sparse;
    torso_only.points[Landmark::Pelvis.index()] =
        example_poses()[0].points[Landmark::Pelvis.index()];
    torso_only.points[Landmark::Head.index()] = None;
    assert_eq!(
        torso_only.points.iter().flatten().count(),
        MIN_PRESENT_FOR_FILL - 1
    );
    let refused = reconstructor(ModeKind::Hybrid)
        .reconstruct(&torso_only)
        .unwrap_err();
    assert!(
        matches!(
            refused,
            CamlocError::Reconstruct {
                source: ReconstructError::TooFewLandmarks {
                    present: 7,
                    needed: MIN_PRESENT_FOR_FILL
                },
                ..
            }
        ),
        "{refused}"
    );
    assert!(
        CameraLocalizer::default_model()
            .unwrap()
            .localize_partial(&torso_only)
            .is_ok()
    );
}
