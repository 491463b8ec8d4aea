//! The skeleton refinement: given and estimated bone lengths, sequences, full perspective.

mod common;

use camloc_geometry::{Perspective, Vector3, WeakPerspective, look_at_origin, sphere_point};
use camloc_reconstruct::{
    BoneLengths, CameraMode, DistancePrior, Given, Intrinsics, LiftedDepths, PoseBasis,
    ReconstructConfig, ReconstructError, Reconstruction, Reconstructor, depths_along_axis,
    mpjpe_after_similarity,
};
use camloc_skeleton::{LIMBS, Landmark, NUM_LIMBS, Pose2, Pose3};
use rand::Rng;

fn basis() -> &'static PoseBasis {
    common::small_basis()
}

fn reconstructor() -> Reconstructor {
    Reconstructor::new(basis().clone(), ReconstructConfig::default()).unwrap()
}

/// The unit direction of each limb of `pose`.
fn directions(pose: &Pose3) -> [Vector3; NUM_LIMBS] {
    std::array::from_fn(|b| {
        let (p, c) = LIMBS[b];
        (Vector3::from(pose.get(c)) - Vector3::from(pose.get(p))).normalize()
    })
}

/// The skeleton with limb `lengths` along `directions`, pelvis at the origin.
fn build(lengths: &BoneLengths, directions: &[Vector3; NUM_LIMBS]) -> Pose3 {
    let mut points = [[0.0; 3]; 15];
    for (b, (parent, child)) in LIMBS.iter().enumerate() {
        let end = Vector3::from(points[parent.index()]) + directions[b] * lengths.as_array()[b];
        points[child.index()] = end.into();
    }
    Pose3::new(points)
}

/// The template's lengths, each limb type scaled by a factor in 0.8..1.2 (left and right
/// alike), drawn from `seed`.
fn person(seed: u64) -> BoneLengths {
    let mut rng = common::rng(seed);
    let types: [f64; 8] = std::array::from_fn(|_| rng.random_range(0.8..1.2));
    let kind = [0, 1, 2, 0, 1, 2, 3, 4, 5, 6, 7, 5, 6, 7];
    let template = reconstructor().template_lengths().unwrap().as_array();
    BoneLengths::from_array(std::array::from_fn(|b| template[b] * types[kind[b]])).unwrap()
}

/// `frames` poses of a smooth motion (bone directions turning from one random pose's to
/// another's) of the person with `lengths`.
fn motion(lengths: &BoneLengths, frames: usize, seed: u64) -> Vec<Pose3> {
    let mut rng = common::rng(seed);
    let (a, b) = (
        directions(&common::random_pose(&mut rng)),
        directions(&common::random_pose(&mut rng)),
    );
    (0..frames)
        .map(|t| {
            let s = t as f64 / (frames - 1) as f64;
            let d = std::array::from_fn(|k| (a[k] * (1.0 - s) + b[k] * s).normalize());
            build(lengths, &d)
        })
        .collect()
}

/// `pose` seen by a weak-perspective camera at `rotation`, 250 image units a metre.
fn seen(pose: &Pose3, rotation: camloc_geometry::Matrix3) -> Pose2 {
    let camera = WeakPerspective {
        scale: 250.0,
        rotation,
        translation: [320.0, 240.0],
    };
    Pose2::new(camera.project(&pose.points))
}

/// Each of `poses` seen by [`seen`] at `rotation`, with the `opt` camera: a sequence's frames.
fn opt_frames(poses: &[Pose3], rotation: camloc_geometry::Matrix3) -> Vec<(Pose2, CameraMode)> {
    poses
        .iter()
        .map(|p| (seen(p, rotation), CameraMode::Opt))
        .collect()
}

#[test]
fn given_lengths_are_what_every_reconstruction_has() {
    let lengths = person(1);
    let rotation = look_at_origin(sphere_point(200.0, 10.0, 1.0)).unwrap();
    let poses = motion(&lengths, 12, 2);
    let rec = reconstructor();
    let given = Given {
        lengths: Some(lengths),
        intrinsics: None,
    };
    let one = rec
        .reconstruct_with(&seen(&poses[0], rotation), &CameraMode::Opt, 2, &given)
        .unwrap();
    assert_eq!(one.len(), 2);
    let frames = opt_frames(&poses, rotation);
    let sequence = rec.reconstruct_sequence(&frames, &given).unwrap();
    assert_eq!(sequence.lengths, lengths);
    let all = one
        .iter()
        .chain(sequence.frames.iter().map(|f| f.as_ref().unwrap()));
    for r in all {
        let got = BoneLengths::of_pose(&r.pose).unwrap().as_array();
        for (g, l) in got.iter().zip(lengths.as_array()) {
            assert!((g - l).abs() < 1e-9 * l, "{g} vs {l}");
        }
        assert!(r.projection_error.is_finite());
    }
}

#[test]
fn a_sequence_recovers_proportions_the_template_does_not_have() {
    let rec = reconstructor();
    let template = rec.template_lengths().unwrap();
    let mean_error = |estimate: &BoneLengths, truth: &BoneLengths| {
        estimate
            .relative_errors(truth)
            .iter()
            .map(|e| e.abs())
            .sum::<f64>()
            / NUM_LIMBS as f64
    };
    let (mut template_error, mut estimated_error) = (0.0, 0.0);
    for seed in 0..3 {
        let truth = person(10 + seed);
        let poses = motion(&truth, 40, 20 + seed);
        let rotation = look_at_origin(sphere_point(30.0 + 100.0 * seed as f64, 5.0, 1.0)).unwrap();
        let frames = opt_frames(&poses, rotation);
        let sequence = rec
            .reconstruct_sequence(&frames, &Given::default())
            .unwrap();
        assert!(sequence.frames.iter().all(Result::is_ok));
        template_error += mean_error(&template, &truth) / 3.0;
        estimated_error += mean_error(&sequence.lengths, &truth) / 3.0;
        for (r, p) in sequence.frames.iter().zip(&poses) {
            let r = r.as_ref().unwrap();
            // Every frame has the person's estimated lengths.
            let got = BoneLengths::of_pose(&r.pose).unwrap();
            assert!(mean_error(&got, &sequence.lengths) < 1e-9);
            assert!(mpjpe_after_similarity(&r.pose, p).is_finite());
        }
    }
    assert!(
        estimated_error < 0.75 * template_error,
        "estimated {estimated_error}, template {template_error}"
    );
}

/// A sequence's lengths are estimated without the temporal smoothness (which, holding
/// each bone's direction near its neighbours', biased them), and its poses are then fitted
/// with the smoothness and those lengths.
#[test]
fn sequence_lengths_come_from_the_fit_without_smoothness() {
    let truth = person(5);
    let poses = motion(&truth, 30, 6);
    let rotation = look_at_origin(sphere_point(120.0, 8.0, 1.0)).unwrap();
    let frames = opt_frames(&poses, rotation);
    let smooth = reconstructor()
        .reconstruct_sequence(&frames, &Given::default())
        .unwrap();
    let mut config = ReconstructConfig::default();
    assert!(config.refinement.smoothness > 0.0);
    config.refinement.smoothness = 0.0;
    let plain = Reconstructor::new(basis().clone(), config)
        .unwrap()
        .reconstruct_sequence(&frames, &Given::default())
        .unwrap();
    assert_eq!(smooth.lengths, plain.lengths);
    let moved = smooth
        .frames
        .iter()
        .zip(&plain.frames)
        .map(|(a, b)| mpjpe_after_similarity(&a.as_ref().unwrap().pose, &b.as_ref().unwrap().pose))
        .fold(0.0, f64::max);
    assert!(moved > 1e-6, "the smoothness changed no pose");
}

/// A sequence's estimated lengths are held nearer the prior's mean by `sequence_prior`
/// (its frames share their errors); a one-frame sequence keeps the single frame's prior, and
/// a value below 1 is refused.
#[test]
fn the_sequence_prior_holds_estimated_lengths_nearer_the_prior() {
    let truth = person(8);
    let poses = motion(&truth, 25, 9);
    let rotation = look_at_origin(sphere_point(150.0, 12.0, 1.0)).unwrap();
    let frames = opt_frames(&poses, rotation);
    let with = |sequence_prior: f64, frames: &[(Pose2, CameraMode)]| {
        let mut config = ReconstructConfig::default();
        config.refinement.sequence_prior = sequence_prior;
        Reconstructor::new(basis().clone(), config)
            .unwrap()
            .reconstruct_sequence(frames, &Given::default())
            .unwrap()
            .lengths
    };
    let template = reconstructor().template_lengths().unwrap();
    let from_template = |l: &BoneLengths| {
        l.relative_errors(&template)
            .iter()
            .map(|e| e.abs())
            .sum::<f64>()
            / NUM_LIMBS as f64
    };
    let (loose, tight) = (with(1.0, &frames), with(5.0, &frames));
    assert!(
        from_template(&tight) < 0.9 * from_template(&loose),
        "tight {} vs loose {}",
        from_template(&tight),
        from_template(&loose)
    );
    assert_eq!(with(1.0, &frames[..1]), with(5.0, &frames[..1]));
    let mut config = ReconstructConfig::default();
    config.refinement.sequence_prior = 0.5;
    assert!(matches!(
        Reconstructor::new(basis().clone(), config),
        Err(ReconstructError::InvalidConfig { .. })
    ));
}

/// Beyond `length_evidence_frames` frames the length prior keeps pace with the frames: a
/// view held still for 240 frames gets the lengths of 60 such frames, where a prior that
/// stops growing lets the repeated frames pull the lengths further away; a value below 1 is
/// refused.
#[test]
fn a_long_sequence_weighs_its_frames_against_the_prior_as_a_window_does() {
    let pose = motion(&person(4), 2, 5)[0];
    let rotation = look_at_origin(sphere_point(265.0, 8.0, 1.0)).unwrap();
    let view = opt_frames(&[pose], rotation)[0];
    let lengths = |evidence_frames: f64, frames: usize| {
        let mut config = ReconstructConfig::default();
        config.refinement.length_evidence_frames = evidence_frames;
        Reconstructor::new(basis().clone(), config)
            .unwrap()
            .reconstruct_sequence(&vec![view; frames], &Given::default())
            .unwrap()
            .lengths
    };
    let apart = |a: &BoneLengths, b: &BoneLengths| {
        a.relative_errors(b)
            .iter()
            .fold(0.0f64, |m, e| m.max(e.abs()))
    };
    let window = lengths(60.0, 60);
    let kept = apart(&lengths(60.0, 240), &window);
    let unbounded = apart(&lengths(1e12, 240), &lengths(1e12, 60));
    // The solver stops at a relative cost change of 1e-6: the same lengths to a few 0.1%.
    assert!(
        kept < 0.005,
        "240 frames moved a limb by {kept} from 60 frames' lengths"
    );
    assert!(
        unbounded > 10.0 * kept.max(1e-4),
        "without the bound 240 frames moved a limb by only {unbounded}"
    );
    let mut config = ReconstructConfig::default();
    config.refinement.length_evidence_frames = 0.5;
    assert!(matches!(
        Reconstructor::new(basis().clone(), config),
        Err(ReconstructError::InvalidConfig { .. })
    ));
}

/// A single frame started from a lifted pose without intrinsics holds its bone
/// directions with `lifted_direction_sigma`; one started from the pursuit's pose, a lifted
/// one under full perspective, and a sequence, with `direction_sigma`; a zero deviation is
/// refused.
#[test]
fn lifted_single_frames_have_their_own_direction_deviation() {
    let poses = motion(&person(6), 8, 7);
    let rotation = look_at_origin(sphere_point(120.0, 10.0, 1.0)).unwrap();
    let frames = opt_frames(&poses, rotation);
    let depths = depths_along_axis(&poses[0], &rotation);
    let with = |pursuit: f64, lifted: f64| {
        let mut config = ReconstructConfig::default();
        config.refinement.direction_sigma = pursuit;
        config.refinement.lifted_direction_sigma = lifted;
        Reconstructor::new(basis().clone(), config)
    };
    let focal = Given {
        lengths: None,
        intrinsics: Some(Intrinsics {
            focal_px: 2000.0,
            principal_point: Some([320.0, 240.0]),
        }),
    };
    // The first frame from the pursuit's pose, from the lifted one, from the lifted one with
    // a focal length, in the sequence.
    let run = |pursuit: f64, lifted: f64| {
        let rec = with(pursuit, lifted).unwrap();
        let single = |given: &Given, d: Option<&LiftedDepths>| {
            rec.reconstruct_lifted(&frames[0].0, &CameraMode::Opt, 1, given, d)
                .unwrap()
                .remove(0)
                .pose
        };
        let sequence = rec
            .reconstruct_sequence(&frames, &Given::default())
            .unwrap();
        [
            single(&Given::default(), None),
            single(&Given::default(), Some(&depths)),
            single(&focal, Some(&depths)),
            sequence.frames[0].as_ref().unwrap().pose,
        ]
    };
    let changed = |a: &[Pose3; 4], b: &[Pose3; 4]| -> Vec<bool> {
        a.iter().zip(b).map(|(x, y)| x != y).collect()
    };
    let shipped = run(0.15, 0.1);
    assert_eq!(
        changed(&shipped, &run(0.03, 0.1)),
        [true, false, true, true]
    );
    assert_eq!(
        changed(&shipped, &run(0.15, 0.03)),
        [false, true, false, false]
    );
    for (pursuit, lifted) in [(0.0, 0.1), (0.15, 0.0)] {
        assert!(matches!(
            with(pursuit, lifted),
            Err(ReconstructError::InvalidConfig { .. })
        ));
    }
}

#[test]
fn a_known_focal_length_fits_a_close_camera_in_full_perspective() {
    // A pose the basis spans, with its own lengths given.
    let mut rng = common::rng(3);
    let (pose, _) = common::pose_in_span(basis(), &mut rng, 6, basis().anthropometric_target());
    let lengths = BoneLengths::of_pose(&pose).unwrap();
    // 2.2 m away with a wide lens: strong perspective.
    let centre = sphere_point(160.0, 15.0, 2.2);
    let camera = Perspective {
        rotation: look_at_origin(centre).unwrap(),
        centre,
        focal: 600.0,
    };
    let mut points = camera.project(&pose.points).unwrap();
    for p in &mut points {
        p[0] += 320.0;
        p[1] += 240.0;
    }
    let pose2 = Pose2::new(points);
    let rec = reconstructor();
    let weak = Given {
        lengths: Some(lengths),
        intrinsics: None,
    };
    let full = Given {
        intrinsics: Some(Intrinsics {
            focal_px: 600.0,
            principal_point: Some([320.0, 240.0]),
        }),
        ..weak
    };
    // Weak perspective: no intrinsics, no distance estimated.
    let mut config = ReconstructConfig::default();
    config.refinement.distance = None;
    let a = &Reconstructor::new(basis().clone(), config)
        .unwrap()
        .reconstruct_with(&pose2, &CameraMode::Opt, 1, &weak)
        .unwrap()[0];
    let b = &rec
        .reconstruct_with(&pose2, &CameraMode::Opt, 1, &full)
        .unwrap()[0];
    assert!(a.perspective.is_none());
    let perspective = b.perspective.as_ref().unwrap();
    assert!(b.projection_error < a.projection_error, "{b:?} {a:?}");
    // The projection error is that of the perspective camera.
    let projected = perspective.project(&b.pose.points).unwrap();
    let error: f64 = projected
        .iter()
        .zip(&points)
        .map(|(p, q)| (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2))
        .sum::<f64>()
        .sqrt();
    assert!((error - b.projection_error).abs() < 1e-6 * (1.0 + error));
    // With the true lengths the depth is absolute: the pelvis is about 2.2 m away.
    let depth = perspective.translation[2];
    assert!((depth - 2.2).abs() < 0.25, "depth {depth}");
    // A focal length under a pixel (5e-324 had put the pose an infinite number of focal
    // lengths off the axis).
    for focal_px in [-1.0, 0.0, 5e-324, 0.5] {
        let bad = Given {
            intrinsics: Some(Intrinsics {
                focal_px,
                principal_point: None,
            }),
            ..weak
        };
        assert!(matches!(
            rec.reconstruct_with(&pose2, &CameraMode::Opt, 1, &bad),
            Err(ReconstructError::InvalidConfig { .. })
        ));
    }
    // The same pose in normalised image coordinates (divided by the image width) with the
    // focal length in pixels: refused, single frame and sequence alike.
    let normalised = Pose2::new(points.map(|p| [p[0] / 640.0, p[1] / 640.0]));
    assert!(matches!(
        rec.reconstruct_with(&normalised, &CameraMode::Opt, 1, &full),
        Err(ReconstructError::ScaleMismatch { .. })
    ));
    // A focal length or principal point wrong by orders of magnitude: refused, where they
    // gave non-finite cameras.
    for (focal_px, principal_point) in [(2.0, None), (1000.0, Some([1e308, 1e308]))] {
        let wrong = Given {
            intrinsics: Some(Intrinsics {
                focal_px,
                principal_point,
            }),
            ..weak
        };
        assert!(matches!(
            rec.reconstruct_with(&pose2, &CameraMode::Opt, 1, &wrong),
            Err(ReconstructError::OutsideView { .. })
        ));
    }
    let frames = [(normalised, CameraMode::Opt), (pose2, CameraMode::Opt)];
    let sequence = rec.reconstruct_sequence(&frames, &full).unwrap();
    assert!(matches!(
        sequence.frames[0],
        Err(ReconstructError::ScaleMismatch { .. })
    ));
    assert!(sequence.frames[1].is_ok());
}

#[test]
fn a_failed_frame_is_reported_and_the_others_are_reconstructed() {
    let lengths = person(5);
    let rotation = look_at_origin(sphere_point(90.0, 0.0, 1.0)).unwrap();
    let mut frames = opt_frames(&motion(&lengths, 8, 6), rotation);
    frames[3].0.points[4][1] = f64::NAN;
    let sequence = reconstructor()
        .reconstruct_sequence(&frames, &Given::default())
        .unwrap();
    assert_eq!(sequence.frames.len(), 8);
    for (t, f) in sequence.frames.iter().enumerate() {
        assert_eq!(f.is_err(), t == 3, "frame {t}: {f:?}");
    }
    let empty = reconstructor()
        .reconstruct_sequence(&[], &Given::default())
        .unwrap();
    assert!(empty.frames.is_empty());
}

/// `poses` seen by a perspective camera `distance_m` metres from the pelvis (400 px a metre
/// at the pelvis), as a sequence's frames with the `hybrid` camera started from the true rotation,
/// and each frame's true lifted depths.
fn perspective_frames(
    poses: &[Pose3],
    distance_m: f64,
) -> (Vec<(Pose2, CameraMode)>, Vec<Option<LiftedDepths>>) {
    let centre = sphere_point(30.0, 10.0, distance_m);
    let rotation = look_at_origin(centre).unwrap();
    let camera = Perspective {
        rotation,
        centre,
        focal: 400.0 * distance_m,
    };
    poses
        .iter()
        .map(|p| {
            let pose2 = Pose2::new(camera.project(&p.points).unwrap());
            (
                (pose2, CameraMode::Hybrid(rotation)),
                Some(depths_along_axis(p, &rotation)),
            )
        })
        .unzip()
}

/// The mean PA-MPJPE (mm) of `truth`'s frames reconstructed with `config` from `seen`
/// and the true lengths: one by one, and as a sequence.
fn perspective_errors(
    config: &ReconstructConfig,
    seen: &(Vec<(Pose2, CameraMode)>, Vec<Option<LiftedDepths>>),
    truth: &[Pose3],
) -> [f64; 2] {
    let rec = Reconstructor::new(basis().clone(), config.clone()).unwrap();
    let given = Given {
        lengths: Some(BoneLengths::of_pose(&truth[0]).unwrap()),
        intrinsics: None,
    };
    let (frames, depths) = seen;
    let n = truth.len() as f64;
    let single: f64 = frames
        .iter()
        .zip(depths)
        .zip(truth)
        .map(|(((pose2, mode), d), t)| {
            let r = rec
                .reconstruct_lifted(pose2, mode, 1, &given, d.as_ref())
                .unwrap()
                .remove(0);
            mpjpe_after_similarity(&r.pose, t) / n
        })
        .sum();
    let sequence = rec
        .reconstruct_sequence_lifted(frames, depths, &given)
        .unwrap();
    let joint: f64 = sequence
        .frames
        .iter()
        .zip(truth)
        .map(|(f, t)| mpjpe_after_similarity(&f.as_ref().unwrap().pose, t) / n)
        .sum();
    [single, joint]
}

/// Without intrinsics the camera's distance is an unknown of the refinement: frames from a
/// close camera are reconstructed better than by weak perspective, one by one and as a
/// sequence, and the camera at that distance is reported (the projection error is its);
/// frames from a far one are reconstructed about as well, and an out-of-range prior is
/// refused.
#[test]
fn the_camera_distance_is_estimated_without_intrinsics() {
    let poses = motion(&person(7), 10, 8);
    let with = ReconstructConfig::default();
    assert!(with.refinement.distance.is_some());
    let mut without = with.clone();
    without.refinement.distance = None;
    let near = perspective_frames(&poses, 2.5);
    let (a, b) = (
        perspective_errors(&with, &near, &poses),
        perspective_errors(&without, &near, &poses),
    );
    for k in 0..2 {
        assert!(
            a[k] < 0.85 * b[k],
            "near: PA-MPJPE {a:?} mm against {b:?} mm"
        );
    }
    // The camera at the estimated distance is reported, and the projection error is its.
    let rec = Reconstructor::new(basis().clone(), with.clone()).unwrap();
    let given = Given {
        lengths: Some(BoneLengths::of_pose(&poses[0]).unwrap()),
        intrinsics: None,
    };
    let ((pose2, mode), depths) = (&near.0[0], &near.1[0]);
    let r = rec
        .reconstruct_lifted(pose2, mode, 1, &given, depths.as_ref())
        .unwrap()
        .remove(0);
    let camera = r.perspective.as_ref().expect("a perspective camera");
    let distance = camera.translation[2];
    assert!(distance > 1.0 && distance < 20.0, "distance {distance} m");
    let error = r
        .reprojection()
        .iter()
        .zip(&pose2.points)
        .map(|(p, q)| (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2))
        .sum::<f64>()
        .sqrt();
    assert!((error - r.projection_error).abs() < 1e-6 * (1.0 + error));
    let weak = Reconstructor::new(basis().clone(), without.clone())
        .unwrap()
        .reconstruct_lifted(pose2, mode, 1, &given, depths.as_ref())
        .unwrap()
        .remove(0);
    assert!(weak.perspective.is_none());
    let far = perspective_frames(&poses, 100.0);
    let (a, b) = (
        perspective_errors(&with, &far, &poses),
        perspective_errors(&without, &far, &poses),
    );
    for k in 0..2 {
        assert!(a[k] < b[k] + 3.0, "far: PA-MPJPE {a:?} mm against {b:?} mm");
    }
    for prior in [
        DistancePrior {
            mean_per_m: -0.1,
            sigma_per_m: 0.1,
        },
        DistancePrior {
            mean_per_m: 0.1,
            sigma_per_m: 0.0,
        },
        DistancePrior {
            mean_per_m: f64::NAN,
            sigma_per_m: 0.1,
        },
    ] {
        let mut config = with.clone();
        config.refinement.distance = Some(prior);
        assert!(matches!(
            Reconstructor::new(basis().clone(), config),
            Err(ReconstructError::InvalidConfig { .. })
        ));
    }
}

/// With lifted depths, the first hypothesis of the other depth reflection starts from the
/// depths mirrored, so that it is the lifted pose's own depth mirror (every hypothesis used
/// to start from the same lifted pose and ended within centimetres of the first): its
/// torso's, that is; its limbs, bent the wrong way by the mirror, are flipped back into the
/// joint limits (`JointLimits::flip_depths`).
#[test]
fn the_other_reflection_of_a_lifted_pose_is_its_depth_mirror() {
    const TORSO: [Landmark; 7] = [
        Landmark::Pelvis,
        Landmark::LeftHip,
        Landmark::RightHip,
        Landmark::Neck,
        Landmark::Head,
        Landmark::LeftShoulder,
        Landmark::RightShoulder,
    ];
    let poses = motion(&person(3), 4, 5);
    let (frames, depths) = perspective_frames(&poses, 100.0);
    let rec = reconstructor();
    let given = Given::default();
    for ((pose2, mode), depths) in frames.iter().zip(&depths) {
        let all = rec
            .reconstruct_lifted(pose2, mode, 4, &given, depths.as_ref())
            .unwrap();
        assert_eq!(all.len(), 4);
        // Camera-frame depths about the pelvis.
        let depth_of = |r: &Reconstruction| -> Vec<f64> {
            let pelvis = r.camera.rotation * Vector3::from(r.pose.points[0]);
            TORSO
                .iter()
                .map(|l| (r.camera.rotation * Vector3::from(r.pose.get(*l)) - pelvis).z)
                .collect()
        };
        let first = depth_of(&all[0]);
        let other = all
            .iter()
            .position(|r| r.reflected != all[0].reflected)
            .expect("a hypothesis of the other reflection");
        let mirror = depth_of(&all[other]);
        let spread = first.iter().map(|z| z.abs()).fold(0.0, f64::max);
        let off = first
            .iter()
            .zip(&mirror)
            .map(|(a, b)| (a + b).abs())
            .fold(0.0, f64::max);
        assert!(
            // Not mirrored, `off` would be twice the spread.
            spread > 0.1 && off < 0.35 * spread,
            "depths {first:?} against {mirror:?}"
        );
    }
}
