//! End-to-end properties of projected matching pursuit on synthetic poses.

mod common;

use camloc_geometry::{Matrix3, Vector3, WeakPerspective, check_rotation};
use camloc_reconstruct::{
    BBOX_FLOOR_IN_TORSOS, CameraMode, EQUAL_FIT_TOLERANCE, LengthTarget, PoseBasis,
    ReconstructConfig, ReconstructError, Reconstructor, projection_error_eq12_bbox,
    sum_squared_limb_lengths,
};
use camloc_skeleton::{Pose2, Pose3};
use proptest::prelude::*;

fn basis() -> &'static PoseBasis {
    common::small_basis()
}

fn reconstructor(config: ReconstructConfig) -> Reconstructor {
    Reconstructor::new(basis().clone(), config).unwrap()
}

/// Projects `pose` with a camera at `rotation`, 250 image units per metre, offset.
fn project(pose: &Pose3, rotation: Matrix3) -> Pose2 {
    let camera = WeakPerspective {
        scale: 250.0,
        rotation,
        translation: [400.0, 300.0],
    };
    Pose2::new(camera.project(&pose.points))
}

fn max_distance(a: &Pose3, b: &Pose3) -> f64 {
    a.points
        .iter()
        .zip(&b.points)
        .map(|(p, q)| (Vector3::from(*p) - Vector3::from(*q)).norm())
        .fold(0.0, f64::max)
}

fn all_modes(rotation: Matrix3, other: Matrix3) -> [CameraMode; 4] {
    [
        CameraMode::Opt,
        CameraMode::Classified(other),
        CameraMode::Oracle(rotation),
        CameraMode::Hybrid(other),
    ]
}

/// The check of `oracle_recovers_a_pose_in_the_span` for one seed. The alternation converges
/// linearly, slowly for some poses: 2,000 alternations per added component bring the worst of
/// 20,000 seeds to 1e-12 m (500 left seed 4424 at 8e-7 m).
fn check_oracle_recovery(seed: u64) -> Result<(), TestCaseError> {
    let mut rng = common::rng(seed);
    let (truth, _) = common::pose_in_span(
        basis(),
        &mut rng,
        basis().n_components(),
        basis().anthropometric_target(),
    );
    let rotation = common::random_rotation(&mut rng, 60.0);
    let rec = reconstructor(ReconstructConfig {
        max_basis: basis().n_components(),
        min_relative_decrease: 0.0,
        alternation_tolerance: 0.0,
        max_alternations: 2000,
        ..common::without_priors()
    });
    let out = rec
        .reconstruct(&project(&truth, rotation), &CameraMode::Oracle(rotation))
        .unwrap();
    let mirrored = Pose3::new(truth.points.map(|p| {
        let x = Vector3::from(p);
        let axis: Vector3 = rotation.row(2).transpose();
        (x - axis * (2.0 * axis.dot(&x))).into()
    }));
    let error = max_distance(&out.pose, &truth).min(max_distance(&out.pose, &mirrored));
    prop_assert!(
        error < 1e-6,
        "seed {seed}: joint error {error} m, projection error {}",
        out.projection_error
    );
    prop_assert!(
        (out.camera.scale - 250.0).abs() < 1e-4,
        "seed {seed}: scale {}",
        out.camera.scale
    );
    Ok(())
}

/// Seeds that once failed the property: 4424 converged slowly; 9282 and 19148 took a
/// negative scale (the image turned by 180 degrees) before fixed-rotation fits were kept
/// positive.
#[test]
fn oracle_recovers_the_poses_that_once_failed() {
    for seed in [4424, 9282, 19148] {
        check_oracle_recovery(seed).unwrap();
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]

    /// Oracle camera, a pose inside the basis span on the anthropometric target, exact
    /// projection: the pose comes back, up to the depth reflection.
    #[test]
    fn oracle_recovers_a_pose_in_the_span(seed in 0u64..1_000_000) {
        check_oracle_recovery(seed)?;
    }

    /// Every mode: the anthropometric constraint holds to 1e-9, the reported projection error is
    /// the camera's actual reprojection error, the camera is a proper rotation (the given one in
    /// fixed modes), the selection respects `max_basis` and reproduces the pose.
    #[test]
    fn reconstructions_are_consistent(seed in 0u64..1_000_000, mean_target in any::<bool>()) {
        let mut rng = common::rng(seed);
        let truth = common::random_pose(&mut rng);
        let rotation = common::random_rotation(&mut rng, 45.0);
        let other = common::random_rotation(&mut rng, 45.0);
        let config = ReconstructConfig {
            max_basis: 7,
            length_target: if mean_target { LengthTarget::Mean } else { LengthTarget::TrainingAverage },
            ..common::without_priors()
        };
        let rec = reconstructor(config);
        let expected_sum = if mean_target {
            sum_squared_limb_lengths(&basis().mean())
        } else {
            basis().anthropometric_target()
        };
        prop_assert!((rec.length_target() - expected_sum).abs() < 1e-12);
        let pose2 = project(&truth, rotation);
        for mode in all_modes(rotation, other) {
            let out = rec.reconstruct(&pose2, &mode).unwrap();
            prop_assert!((sum_squared_limb_lengths(&out.pose) - expected_sum).abs() < 1e-9,
                "{}: limb sum {} vs {}", mode.name(), sum_squared_limb_lengths(&out.pose), expected_sum);
            let actual = out.camera.squared_error(&out.pose.points, &pose2.points).unwrap().sqrt();
            prop_assert!((actual - out.projection_error).abs() <= 1e-9 * (1.0 + actual));
            prop_assert!(check_rotation(&out.camera.rotation, 1e-9).is_ok());
            match mode {
                CameraMode::Classified(r) | CameraMode::Oracle(r) => prop_assert_eq!(out.camera.rotation, r),
                _ => {}
            }
            prop_assert!(!out.selected.is_empty() && out.selected.len() <= 7);
            prop_assert_eq!(out.selected.len(), out.coefficients.len());
            let mut unique = out.selected.clone();
            unique.sort_unstable();
            unique.dedup();
            prop_assert_eq!(unique.len(), out.selected.len());
            let mut w = vec![0.0; basis().n_components()];
            for (&j, &c) in out.selected.iter().zip(&out.coefficients) {
                w[j] = c;
            }
            prop_assert!(max_distance(&basis().pose(&w).unwrap(), &out.pose) < 1e-12);
            prop_assert!(out.iterations >= out.selected.len());
        }
    }

    /// Trying the depth-reflected hypothesis never leaves a larger projection error, and the
    /// hybrid refinement never ends above the fixed-rotation solution it starts from.
    #[test]
    fn reflection_and_hybrid_never_increase_the_error(seed in 0u64..1_000_000) {
        let mut rng = common::rng(seed);
        let truth = common::random_pose(&mut rng);
        let rotation = common::random_rotation(&mut rng, 45.0);
        let classified = common::random_rotation(&mut rng, 45.0);
        let pose2 = project(&truth, rotation);
        let with = reconstructor(common::without_priors());
        let without = reconstructor(ReconstructConfig { try_depth_reflection: false, ..common::without_priors() });
        for mode in all_modes(rotation, classified) {
            let a = with.reconstruct(&pose2, &mode).unwrap();
            let b = without.reconstruct(&pose2, &mode).unwrap();
            prop_assert!(a.projection_error <= b.projection_error * (1.0 + 1e-12), "{}", mode.name());
            prop_assert!(!b.reflected);
            if !a.reflected {
                // The primary hypothesis is the same computation in both runs.
                prop_assert_eq!(&a.selected, &b.selected);
            }
        }
        let fixed = with.reconstruct(&pose2, &CameraMode::Classified(classified)).unwrap();
        let hybrid = with.reconstruct(&pose2, &CameraMode::Hybrid(classified)).unwrap();
        prop_assert!(hybrid.projection_error <= fixed.projection_error * (1.0 + 1e-12));
    }

    /// The 2D input's units and origin do not matter: scaling and shifting it scales and
    /// shifts the camera and leaves the 3D pose unchanged.
    #[test]
    fn image_similarity_invariance(seed in 0u64..1_000_000, a in 0.01f64..100.0,
                                   tx in -1000.0f64..1000.0, ty in -1000.0f64..1000.0) {
        let mut rng = common::rng(seed);
        let truth = common::random_pose(&mut rng);
        let rotation = common::random_rotation(&mut rng, 45.0);
        let pose2 = project(&truth, rotation);
        let moved = Pose2::new(pose2.points.map(|p| [a * p[0] + tx, a * p[1] + ty]));
        let rec = reconstructor(common::without_priors());
        for mode in [CameraMode::Opt, CameraMode::Oracle(rotation)] {
            let x = rec.reconstruct(&pose2, &mode).unwrap();
            let y = rec.reconstruct(&moved, &mode).unwrap();
            prop_assert!(max_distance(&x.pose, &y.pose) < 1e-6, "{}", mode.name());
            prop_assert!((y.camera.scale - a * x.camera.scale).abs() < 1e-6 * y.camera.scale.abs());
            prop_assert!((y.projection_error - a * x.projection_error).abs() < 1e-6 * (1.0 + y.projection_error));
        }
    }
}

#[test]
fn bad_input_is_a_typed_error() {
    let rec = reconstructor(common::without_priors());
    let mut rng = common::rng(3);
    let truth = common::random_pose(&mut rng);
    let rotation = common::random_rotation(&mut rng, 45.0);
    let good = project(&truth, rotation);

    let mut nan = good;
    nan.points[11][1] = f64::NAN;
    assert!(matches!(
        rec.reconstruct(&nan, &CameraMode::Opt),
        Err(ReconstructError::NonFiniteInput { landmark: 11, .. })
    ));
    let mut no_torso = good;
    no_torso.points[7] = no_torso.points[0];
    assert!(matches!(
        rec.reconstruct(&no_torso, &CameraMode::Oracle(rotation)),
        Err(ReconstructError::DegenerateInput(_))
    ));
    let point = Pose2::new([[3.0, 4.0]; 15]);
    assert!(matches!(
        rec.reconstruct(&point, &CameraMode::Opt),
        Err(ReconstructError::DegenerateInput(_))
    ));
    let reflection = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, -1.0));
    assert!(matches!(
        rec.reconstruct(&good, &CameraMode::Classified(reflection)),
        Err(ReconstructError::InvalidRotation {
            mode: "classified",
            ..
        })
    ));
    assert!(matches!(
        rec.reconstruct(&good, &CameraMode::Hybrid(rotation * 2.0)),
        Err(ReconstructError::InvalidRotation { mode: "hybrid", .. })
    ));
    // Collinear landmarks (an edge-on view): Procrustes completes the camera's second axis,
    // so even this reconstructs, to finite numbers.
    let line = Pose2::new(std::array::from_fn(|i| [i as f64, 2.0 * i as f64]));
    let r = rec.reconstruct(&line, &CameraMode::Opt).unwrap();
    assert!(r.pose.is_finite() && r.projection_error.is_finite());
}

#[test]
fn invalid_configs_are_refused() {
    let bad = [
        ReconstructConfig {
            max_basis: 0,
            ..common::without_priors()
        },
        ReconstructConfig {
            max_alternations: 0,
            ..common::without_priors()
        },
        ReconstructConfig {
            alternation_tolerance: 1.0,
            ..common::without_priors()
        },
        ReconstructConfig {
            min_relative_decrease: f64::NAN,
            ..common::without_priors()
        },
    ];
    for config in bad {
        assert!(matches!(
            Reconstructor::new(basis().clone(), config),
            Err(ReconstructError::InvalidConfig { .. })
        ));
    }
}

#[test]
fn extreme_scales_reconstruct_like_ordinary_ones() {
    let rec = reconstructor(common::without_priors());
    let mut rng = common::rng(11);
    let truth = common::random_pose(&mut rng);
    let rotation = common::random_rotation(&mut rng, 45.0);
    let good = project(&truth, rotation);
    for mode in all_modes(rotation, rotation) {
        let reference = rec.reconstruct(&good, &mode).unwrap();
        let base = projection_error_eq12_bbox(&good, &reference).unwrap();
        for k in [1e154, 1e-200, 2f64.powi(600), 1e300 / 700.0] {
            let scaled = Pose2::new(good.points.map(|p| [p[0] * k, p[1] * k]));
            let r = rec
                .reconstruct(&scaled, &mode)
                .unwrap_or_else(|e| panic!("{} x {k:e}: {e}", mode.name()));
            assert!(
                max_distance(&r.pose, &reference.pose) < 1e-6,
                "{} x {k:e}: the 3D pose changed",
                mode.name()
            );
            let relative = r.projection_error / (reference.projection_error * k);
            assert!(
                (relative - 1.0).abs() < 1e-6 || reference.projection_error < 1e-9,
                "{} x {k:e}: projection error {} vs {}",
                mode.name(),
                r.projection_error,
                reference.projection_error * k
            );
            // Eq. 12 has units of 1 / image unit.
            let eq12 = projection_error_eq12_bbox(&scaled, &r).unwrap();
            assert!(eq12.is_finite(), "{} x {k:e}: eq. 12 {eq12}", mode.name());
            assert!(
                (eq12 * k / base - 1.0).abs() < 1e-4 || base < 1e-12,
                "{} x {k:e}: eq. 12 {eq12} vs {}",
                mode.name(),
                base / k
            );
        }
    }
}

#[test]
fn eq12_is_bounded_for_an_edge_on_pose() {
    let rec = reconstructor(common::without_priors());
    let mut rng = common::rng(5);
    let truth = common::random_pose(&mut rng);
    let rotation = common::random_rotation(&mut rng, 30.0);
    let mut flat = project(&truth, rotation);
    // Squash the image horizontally to a width of 1e-12 image units (a planar skeleton seen
    // edge-on): the box is degenerate, the torso is not.
    let u0 = flat.points[0][0];
    for p in &mut flat.points {
        p[0] = u0 + (p[0] - u0) * 1e-14;
    }
    // Opt places a camera on collinear landmarks too (the fixture mocap's planar skeletons
    // seen from the side failed with a degenerate Procrustes camera before).
    let opt = rec.reconstruct(&flat, &CameraMode::Opt).unwrap();
    assert!(opt.pose.is_finite());
    assert!(projection_error_eq12_bbox(&flat, &opt).unwrap() < 1.0);
    let recon = rec
        .reconstruct(&flat, &CameraMode::Oracle(rotation))
        .unwrap();
    let eq12 = projection_error_eq12_bbox(&flat, &recon).unwrap();
    let (w, h) = camloc_reconstruct::bounding_box(&flat);
    assert!(w < 1e-10, "width {w}");
    let torso = flat.torso_length();
    let floor = BBOX_FLOOR_IN_TORSOS * torso;
    let norm = recon.projection_error;
    assert!(
        (eq12 - norm / floor / h.max(floor)).abs() <= 1e-9 * eq12,
        "eq. 12 {eq12} is the residual over the floored box"
    );
    assert!(eq12 < 1.0, "eq. 12 {eq12} blew up");
    let mut no_torso = flat;
    no_torso.points[7] = no_torso.points[0];
    assert!(projection_error_eq12_bbox(&no_torso, &recon).is_err());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// `reconstruct_hypotheses` keeps at most `max`, puts `reconstruct`'s answer first, and
    /// orders them by the pursuit's projection error except where two fit within
    /// `EQUAL_FIT_TOLERANCE` of each other, where the smaller joint-limit violation wins
    /// (the refinement, which keeps that order, is off so that the errors are the
    /// pursuit's).
    #[test]
    fn hypotheses_are_ranked_by_fit_then_by_the_joint_limit_prior(seed in 0u64..1_000_000) {
        let mut rng = common::rng(seed);
        let truth = common::random_pose(&mut rng);
        let rotation = common::random_rotation(&mut rng, 45.0);
        let pose2 = project(&truth, rotation);
        let mut config = ReconstructConfig::default();
        config.refinement.estimate_lengths = false;
        let rec = reconstructor(config);
        for mode in [CameraMode::Opt, CameraMode::Hybrid(rotation)] {
            let all = rec.reconstruct_hypotheses(&pose2, &mode, 8).unwrap();
            let expected = if matches!(mode, CameraMode::Hybrid(_)) { 4 } else { 2 };
            prop_assert_eq!(all.len(), expected);
            prop_assert_eq!(all.iter().filter(|h| h.reflected).count(), expected / 2);
            let one = rec.reconstruct_hypotheses(&pose2, &mode, 1).unwrap();
            prop_assert_eq!(one.len(), 1);
            prop_assert_eq!(&one[0].pose.points, &all[0].pose.points);
            let best = rec.reconstruct(&pose2, &mode).unwrap();
            prop_assert_eq!(&best.pose.points, &all[0].pose.points);
            for pair in all.windows(2) {
                let (a, b) = (pair[0].projection_error, pair[1].projection_error);
                let close = (a - b).abs() <= EQUAL_FIT_TOLERANCE * a.max(b);
                if close {
                    prop_assert!(
                        pair[0].limit_violation_rad <= pair[1].limit_violation_rad
                            || a <= b,
                        "{} before {}", a, b
                    );
                } else {
                    prop_assert!(a < b, "{} before {}", a, b);
                }
            }
        }
    }
}
