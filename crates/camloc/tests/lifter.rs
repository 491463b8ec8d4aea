//! DepthLifter: its depth convention against the refinement's (true depths give back the true
//! pose), fitting on synthetic views, mirror-symmetric depths, save/load and refusal of bad
//! files, and the embedded lifter in `PoseReconstructor`.

use camloc::dataset::{ClipInfo, GenerateConfig, PoseSequence, Protocol, generate};
use camloc::geometry::CameraLabel;
use camloc::reconstruct::{
    BoneLengths, CameraMode, Given, ReconstructConfig, Reconstructor, mpjpe_after_similarity,
};
use camloc::skeleton::mirror_landmark_index;
use camloc::store::Persist;
use camloc::{
    CameraLocalizer, DepthLifter, Descriptor, ModeKind, PartialPose2, PoseReconstructor,
    default_basis, depth_targets,
};

#[path = "common/swinging.rs"]
mod swinging;
use swinging::pose;

fn views(seed: u64) -> camloc::dataset::Dataset {
    let sequences: Vec<PoseSequence> = (0..3)
        .map(|subject| PoseSequence {
            clip: ClipInfo::new(subject.to_string(), format!("{subject}_01")),
            frames: (0..40u32)
                .map(|f| (f, pose(f as f64 * 0.15 + subject as f64)))
                .collect(),
        })
        .collect();
    let mut config = GenerateConfig::new(Protocol::Sphere);
    config.seed = seed;
    config.min_pose_distance_mm = 0.0;
    generate(&sequences, &config, &|_, _| {}).unwrap()
}

/// The lifted pose of the refinement (2D at the given depths, turned into the body frame by
/// the camera) is the true pose when the depths are the true ones: an orthographic view of
/// a pose outside the basis, with its true lengths given, comes back within a millimetre,
/// whereas the pursuit's pose does not. The refinement's camera is weak perspective, as the
/// view is (no distance estimated). The joint limits are off: this pose's knees bend both
/// ways, which the limits would take for a limb read the wrong way in depth and flip.
#[test]
fn true_depths_give_back_the_true_pose() {
    let dataset = views(5);
    let mut config = ReconstructConfig::default();
    config.refinement.distance = None;
    config.joint_limits = false;
    let reconstructor = Reconstructor::new(default_basis().unwrap(), config).unwrap();
    let mut worst_lifted: f64 = 0.0;
    let mut pursuit_total = 0.0;
    let samples: Vec<_> = dataset.samples.iter().step_by(17).take(12).collect();
    for s in &samples {
        let rotation = s.rotation;
        // An orthographic view of the true pose: u = row 1 . X, v = row 2 . X.
        let mut view = s.landmarks;
        for (p, x) in view.points.iter_mut().zip(&s.pose3.points) {
            let q = rotation * nalgebra::Vector3::from(*x);
            *p = [q.x, q.y];
        }
        let given = Given {
            lengths: Some(BoneLengths::of_pose(&s.pose3).unwrap()),
            intrinsics: None,
        };
        let mode = CameraMode::Hybrid(rotation);
        let depths = depth_targets(s);
        let lifted = reconstructor
            .reconstruct_lifted(&view, &mode, 1, &given, Some(&depths))
            .unwrap();
        let plain = reconstructor
            .reconstruct_lifted(&view, &mode, 1, &given, None)
            .unwrap();
        worst_lifted = worst_lifted.max(mpjpe_after_similarity(&lifted[0].pose, &s.pose3));
        pursuit_total += mpjpe_after_similarity(&plain[0].pose, &s.pose3);
    }
    assert!(worst_lifted < 1.0, "lifted: {worst_lifted} mm");
    let pursuit = pursuit_total / samples.len() as f64;
    assert!(pursuit > 5.0, "the pursuit alone: {pursuit} mm");
}

/// A lifter fitted on some views predicts the depths of other views of the same motion far
/// better than a flat pose, round-trips through its file and refuses a corrupted one.
#[test]
fn a_fitted_lifter_predicts_depths_and_round_trips() {
    let train = views(1);
    let test = views(2);
    let lifter = DepthLifter::fit(&train, Descriptor::default(), 8, 1.0).unwrap();
    assert_eq!(lifter.n_classes(), 12);
    let (mut lifted, mut flat) = (0.0, 0.0);
    for s in &test.samples {
        let truth = depth_targets(s);
        let z = lifter
            .depths(&s.landmarks, usize::from(s.label) - 1)
            .unwrap();
        lifted += truth
            .iter()
            .zip(&z)
            .map(|(a, b)| (a - b).powi(2))
            .sum::<f64>();
        flat += truth.iter().map(|a| a * a).sum::<f64>();
    }
    assert!(lifted < 0.25 * flat, "lifted {lifted}, flat {flat}");
    let bytes = lifter.to_bytes().unwrap();
    let back = DepthLifter::from_bytes(&bytes).unwrap();
    assert_eq!(back, lifter);
    let mut bad = bytes.clone();
    let last = bad.len() - 1;
    bad[last] ^= 0x55;
    assert!(DepthLifter::from_bytes(&bad).is_err());
    assert!(lifter.depths(&test.samples[0].landmarks, 12).is_err());
}

/// The mirror-symmetric depths of a view and of its mirror image (the image mirrored, left
/// and right swapped, seen by the mirrored camera class) are mirror images of each other.
/// (Whether they predict better is measured on held-out CMU subjects, docs/RESULTS.md: these
/// few synthetic views' lifter has not seen a mirrored body.)
#[test]
fn a_mirrored_view_gets_the_mirrored_depths() {
    let lifter = DepthLifter::fit(&views(1), Descriptor::default(), 8, 1.0).unwrap();
    let test = views(2);
    let cameras = &test.header.cameras;
    let mut largest = 0.0f64;
    for s in &test.samples {
        let label = CameraLabel::new(s.label).unwrap();
        let mirrored = CameraLabel::new(cameras.mirror_left_right(s.label)).unwrap();
        let z = lifter
            .mirror_symmetric_depths(&s.landmarks, cameras, label)
            .unwrap();
        let m = lifter
            .mirror_symmetric_depths(&s.landmarks.mirrored(), cameras, mirrored)
            .unwrap();
        for (i, depth) in z.iter().enumerate() {
            largest = largest.max((depth - m[mirror_landmark_index(i)]).abs());
        }
    }
    assert!(largest < 1e-12, "mirrored depths off by {largest:e}");
}

/// The embedded lifter is the embedded model's: it loads, has its cameras, and a
/// reconstructor with it gives a different pose than without it for the same input.
#[test]
fn the_embedded_lifter_starts_the_refinement_of_hybrid() {
    let lifter = match DepthLifter::default_lifter() {
        Ok(l) => l,
        Err(e) => panic!("the embedded lifter: {e}"),
    };
    let localizer = CameraLocalizer::default_model().unwrap();
    assert_eq!(lifter.n_classes(), localizer.cameras().len());
    let without = PoseReconstructor::new(default_basis().unwrap())
        .unwrap()
        .with_localizer(localizer)
        .with_mode(ModeKind::Hybrid)
        .unwrap();
    let with = without.clone().with_lifter(lifter);
    let s = &views(3).samples[7];
    let input = PartialPose2::from(s.landmarks);
    let a = with.reconstruct(&input).unwrap().reconstruction.pose;
    let b = without.reconstruct(&input).unwrap().reconstruction.pose;
    assert!(mpjpe_after_similarity(&a, &b) > 0.1);
    // `opt` has no class: the lifter is not used.
    let opt = with.clone().with_mode(ModeKind::Opt).unwrap();
    let c = opt.reconstruct(&input).unwrap().reconstruction.pose;
    let d = without
        .with_mode(ModeKind::Opt)
        .unwrap()
        .reconstruct(&input)
        .unwrap()
        .reconstruction
        .pose;
    assert_eq!(c, d);
}

/// In a sequence, estimated lengths come from the poses the refinement starts from: with
/// the true depths lifted they are nearer the true proportions than from the pursuit's poses,
/// and the lifted depths change the poses.
#[test]
fn a_sequence_takes_its_lengths_and_its_poses_from_the_lifted_depths() {
    let dataset = views(6);
    let reconstructor =
        Reconstructor::new(default_basis().unwrap(), ReconstructConfig::default()).unwrap();
    let samples: Vec<_> = dataset.samples.iter().take(8).collect();
    let frames: Vec<_> = samples
        .iter()
        .map(|s| (s.landmarks, CameraMode::Hybrid(s.rotation)))
        .collect();
    let depths: Vec<_> = samples.iter().map(|s| Some(depth_targets(s))).collect();
    let given = Given::default();
    let plain = reconstructor.reconstruct_sequence(&frames, &given).unwrap();
    let lifted = reconstructor
        .reconstruct_sequence_lifted(&frames, &depths, &given)
        .unwrap();
    // The frames' own limb lengths, averaged (the test poses bend their limbs a little).
    let truth = BoneLengths::from_array(std::array::from_fn(|limb| {
        samples
            .iter()
            .map(|s| s.pose3.limb_length(limb))
            .sum::<f64>()
            / samples.len() as f64
    }))
    .unwrap();
    let error = |l: &BoneLengths| {
        let e = l.relative_errors(&truth);
        e.iter().map(|x| x.abs()).sum::<f64>() / e.len() as f64
    };
    let (from_pursuit, from_lifted) = (error(&plain.lengths), error(&lifted.lengths));
    eprintln!("mean length error: from the pursuit {from_pursuit:.4}, lifted {from_lifted:.4}");
    assert!(
        from_lifted < from_pursuit,
        "lifted {from_lifted:.4} against pursuit {from_pursuit:.4}"
    );
    let moved: f64 = plain
        .frames
        .iter()
        .zip(&lifted.frames)
        .map(|(a, b)| mpjpe_after_similarity(&a.as_ref().unwrap().pose, &b.as_ref().unwrap().pose))
        .sum();
    assert!(moved > 1.0, "{moved} mm");
}

/// With lifted depths, `reflected` says whether a hypothesis started from the lifted depths
/// mirrored: the preferred one (the lifter's reading) never, the second always, and no frame
/// of a sequence (each starts from its lifted depths, whichever of the pursuit's two depth
/// readings the sequence's path chose; before, the flag was the pursuit's and toggled from
/// frame to frame with the pose unchanged).
#[test]
fn the_lifter_s_reading_is_not_the_reflected_hypothesis() {
    let with = PoseReconstructor::new(default_basis().unwrap())
        .unwrap()
        .with_localizer(CameraLocalizer::default_model().unwrap())
        .with_mode(ModeKind::Hybrid)
        .unwrap()
        .with_lifter(DepthLifter::default_lifter().unwrap());
    let inputs: Vec<PartialPose2> = views(4)
        .samples
        .iter()
        .take(24)
        .map(|s| PartialPose2::from(s.landmarks))
        .collect();
    for input in &inputs {
        let r = with.reconstruct_hypotheses(input, 2).unwrap();
        assert!(!r.reconstruction.reflected);
        assert_eq!(r.alternatives.len(), 1);
        assert!(r.alternatives[0].reflected);
    }
    let sequence = with.reconstruct_sequence(&inputs).unwrap();
    for frame in &sequence.frames {
        assert!(!frame.as_ref().unwrap().reconstruction.reflected);
    }
}

/// The elevation of the camera direction (pelvis to camera) of a rotation whose rows are the
/// camera's axes in the body frame, degrees.
fn camera_elevation(rotation: &camloc::geometry::Matrix3) -> f64 {
    (-rotation[(2, 2)]).clamp(-1.0, 1.0).asin().to_degrees()
}

/// `hybrid` from lifted depths levels the pose to the localizer's elevation: the
/// reconstruction's camera stands where the localization says, single poses and sequence
/// frames alike (the latter at the sequence's smoothed elevations), the image fit unchanged;
/// without the lifter nothing is levelled.
#[test]
fn hybrid_from_lifted_depths_is_levelled_to_the_localizer_s_elevation() {
    let lifter = DepthLifter::default_lifter().unwrap();
    let without = PoseReconstructor::new(default_basis().unwrap())
        .unwrap()
        .with_localizer(CameraLocalizer::default_model().unwrap())
        .with_mode(ModeKind::Hybrid)
        .unwrap();
    let with = without.clone().with_lifter(lifter);
    let dataset = views(3);
    let inputs: Vec<PartialPose2> = dataset
        .samples
        .iter()
        .take(7)
        .map(|s| PartialPose2::from(s.landmarks))
        .collect();
    for input in &inputs {
        let r = with.reconstruct(input).unwrap();
        let localized = r.localization.as_ref().unwrap().elevation_deg.unwrap();
        let elevation = camera_elevation(&r.reconstruction.camera.rotation);
        assert!(
            (elevation - localized).abs() < 1e-6,
            "{elevation} {localized}"
        );
        let rotation = &r.reconstruction.camera.rotation;
        assert!((rotation.determinant() - 1.0).abs() < 1e-9);
    }
    let sequence = with.reconstruct_sequence(&inputs).unwrap();
    let elevations: Vec<(f64, f64)> = sequence
        .frames
        .iter()
        .map(|f| {
            let f = f.as_ref().unwrap();
            let l = f.localization.as_ref().unwrap();
            (l.azimuth_deg.unwrap(), l.elevation_deg.unwrap())
        })
        .collect();
    let smoothed = camloc::smooth_viewpoints(
        &[],
        &elevations.iter().map(|v| Some(*v)).collect::<Vec<_>>(),
        camloc::reconstruct::FrameRate::default(),
    );
    for (f, s) in sequence.frames.iter().zip(&smoothed) {
        let elevation = camera_elevation(&f.as_ref().unwrap().reconstruction.camera.rotation);
        assert!((elevation - s.unwrap().1).abs() < 1e-6);
    }
    // Without the lifter the refined camera stays where the refinement put it.
    let plain = without.reconstruct(&inputs[0]).unwrap();
    let localized = plain.localization.as_ref().unwrap().elevation_deg.unwrap();
    assert!((camera_elevation(&plain.reconstruction.camera.rotation) - localized).abs() > 1e-3);
}

/// Views of `pose` with the pelvis raised `up` metres above where `pose` puts it (`None`: the
/// pelvis at the mid-hip point and the neck at the mid-shoulder point, as detectors place
/// them).
fn placed_views(seed: u64, up: Option<f64>) -> camloc::dataset::Dataset {
    let mut data = views(seed);
    for s in &mut data.samples {
        let mut placed = match up {
            Some(up) => {
                let mut p = s.pose3;
                p.points[0][2] += up;
                p
            }
            None => camloc::dataset::annotated(&s.pose3, 1.0),
        };
        std::mem::swap(&mut s.pose3, &mut placed);
        for (p, x) in s.landmarks.points.iter_mut().zip(&s.pose3.points) {
            let q = s.rotation * nalgebra::Vector3::from(*x);
            *p = [q.x, q.y];
        }
    }
    data
}

/// A lifter with a midpoint lifter lifts a pose whose pelvis and neck sit at the hip and
/// shoulder midpoints by the midpoint lifter and a pose whose pelvis sits well above them by
/// its own heads, refuses as a midpoint lifter one with a midpoint lifter of its own, takes a
/// second one in place of the first, and round-trips through its file with both.
#[test]
fn each_placement_is_lifted_by_its_own_lifter() {
    let own = DepthLifter::fit(&placed_views(1, Some(0.1)), Descriptor::default(), 8, 1.0).unwrap();
    let midpoints =
        DepthLifter::fit(&placed_views(1, None), Descriptor::default(), 8, 1.0).unwrap();
    let both = own.clone().with_midpoint_lifter(midpoints.clone()).unwrap();
    for (test, alone) in [
        (placed_views(2, Some(0.1)), &own),
        (placed_views(2, None), &midpoints),
    ] {
        for s in test.samples.iter().step_by(7) {
            let class = usize::from(s.label) - 1;
            assert_eq!(
                both.depths(&s.landmarks, class).unwrap(),
                alone.depths(&s.landmarks, class).unwrap()
            );
        }
    }
    // Another midpoint lifter replaces the first.
    let again = both.clone().with_midpoint_lifter(own.clone()).unwrap();
    assert_eq!(again.midpoint_lifter(), Some(&own));
    assert!(own.clone().with_midpoint_lifter(both.clone()).is_err());
    let back = DepthLifter::from_bytes(&both.to_bytes().unwrap()).unwrap();
    assert_eq!(back, both);
    assert_eq!(back.midpoint_lifter(), Some(&midpoints));
    let (split_own, split_midpoints) = back.split_midpoint_lifter();
    assert_eq!((split_own, split_midpoints), (own, Some(midpoints)));
}
