//! Poses whose torso is incomplete (a hip, and so the pelvis, or a shoulder, and so the neck,
//! missing: what a detector or an annotator gives for an occluded hip) are localized with the
//! torso filled in from the embedded basis (`CameraLocalizer::localize_filled`), on CMU poses
//! seen by the studio cameras of the `rig` protocol. Skipped, visibly, without the data.

use camloc::dataset::{GenerateConfig, Protocol, generate, load_mocap_folders};
use camloc::{CameraLocalizer, Landmark, PartialPose2, PoseReconstructor, default_basis};

/// Views tried (every n-th generated view, so that they spread over clips and cameras).
const VIEWS: usize = 1500;

/// Localized with the pelvis and one hip (alternately left and right) missing, the camera
/// class is right nearly as often as with the complete pose (the embedded model and basis
/// were trained on these subjects, so this checks the fill, not generalisation; held-out
/// subjects are measured by `cargo xtask report`), and the same poses are refused by
/// `localize_partial`, which cannot make a torso. Likewise with the neck and one shoulder.
#[test]
fn a_missing_hip_or_shoulder_is_filled_in_and_the_camera_found() {
    let Some(cmu) = camloc::skeleton::data::data_path_or_skip(
        "cmu",
        "camloc::a_missing_hip_or_shoulder_is_filled_in_and_the_camera_found",
    ) else {
        return;
    };
    let (sequences, _) = load_mocap_folders(&[cmu], &mut |_| {}, &mut |_, _, _| {}).unwrap();
    let mut config = GenerateConfig::new(Protocol::Rig);
    config.stride = 10;
    config.seed = 7;
    let dataset = generate(&sequences, &config, &|_, _| {}).unwrap();
    let step = (dataset.samples.len() / VIEWS).max(1);
    let localizer = CameraLocalizer::default_model().unwrap();
    let filler = PoseReconstructor::new(default_basis().unwrap()).unwrap();
    let cases = [
        [Landmark::Pelvis, Landmark::LeftHip],
        [Landmark::Pelvis, Landmark::RightHip],
        [Landmark::Neck, Landmark::LeftShoulder],
        [Landmark::Neck, Landmark::RightShoulder],
    ];
    let (mut views, mut complete, mut filled) = (0usize, 0usize, [0usize; 2]);
    for (i, sample) in dataset.samples.iter().step_by(step).enumerate() {
        let pose = PartialPose2::from(sample.landmarks);
        let right = |label: u16| usize::from(label == sample.label);
        views += 1;
        complete += right(localizer.localize_partial(&pose).unwrap().label.get());
        for (end, pair) in [&cases[i % 2], &cases[2 + i % 2]].into_iter().enumerate() {
            let mut partial = pose;
            for l in pair {
                partial.points[l.index()] = None;
            }
            let refused = localizer.localize_partial(&partial).unwrap_err();
            assert!(refused.to_string().contains(pair[0].name()), "{refused}");
            let found = localizer
                .localize_filled(&partial, filler.reconstructor())
                .unwrap();
            assert_eq!(found.missing, pair.to_vec());
            filled[end] += right(found.label.get());
        }
    }
    let share = |n: usize| n as f64 / views as f64;
    eprintln!(
        "{views} rig views: complete {:.1}%, pelvis and a hip filled in {:.1}%, neck and a \
         shoulder {:.1}%",
        100.0 * share(complete),
        100.0 * share(filled[0]),
        100.0 * share(filled[1])
    );
    assert!(views >= 1000, "{views} views");
    for (what, n) in [
        ("pelvis and hip", filled[0]),
        ("neck and shoulder", filled[1]),
    ] {
        assert!(
            share(n) >= share(complete) - 0.05,
            "{what}: {:.1}% against {:.1}% complete",
            100.0 * share(n),
            100.0 * share(complete)
        );
    }
}
