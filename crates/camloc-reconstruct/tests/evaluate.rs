//! The evaluation helper.

mod common;

use camloc_geometry::WeakPerspective;
use camloc_reconstruct::{
    BasisConfig, BasisKind, CameraMode, EvalSample, ModeKind, Pipeline, PoseBasis,
    ReconstructConfig, Reconstructor, evaluate, evaluate_with_pipeline,
};
use camloc_skeleton::Pose2;

/// Samples in the span of a 10-component basis, exactly projected; every third one has no
/// classified rotation, the last one a NaN landmark.
fn setup() -> (Reconstructor, Vec<EvalSample>) {
    let basis = PoseBasis::fit(
        &common::training_set(1500, 21),
        &BasisConfig {
            n_components: 10,
            kind: BasisKind::Pca,
            ..BasisConfig::default()
        },
    )
    .unwrap();
    let mut rng = common::rng(5);
    let mut samples: Vec<EvalSample> = (0..24)
        .map(|i| {
            let (truth, _) =
                common::pose_in_span(&basis, &mut rng, 10, basis.anthropometric_target());
            let true_rotation = common::random_rotation(&mut rng, 45.0);
            let camera = WeakPerspective {
                scale: 120.0,
                rotation: true_rotation,
                translation: [60.0, 80.0],
            };
            EvalSample {
                pose2: Pose2::new(camera.project(&truth.points)),
                truth,
                true_rotation,
                classified_rotation: (i % 3 != 0).then(|| common::random_rotation(&mut rng, 45.0)),
            }
        })
        .collect();
    if let Some(last) = samples.last_mut() {
        last.pose2.points[5][0] = f64::NAN;
    }
    let reconstructor = Reconstructor::new(
        basis,
        ReconstructConfig {
            max_basis: 10,
            min_relative_decrease: 0.0,
            alternation_tolerance: 0.0,
            max_alternations: 500,
            ..common::without_priors()
        },
    )
    .unwrap();
    (reconstructor, samples)
}

#[test]
fn report_counts_and_oracle_accuracy() {
    let (reconstructor, samples) = setup();
    let report = evaluate(&samples, &reconstructor, &ModeKind::ALL);
    assert_eq!(report.samples, 24);
    assert_eq!(
        report.modes.iter().map(|m| m.mode).collect::<Vec<_>>(),
        ModeKind::ALL.to_vec()
    );
    for m in &report.modes {
        assert_eq!(m.evaluated + m.failures + m.unavailable, 24, "{:?}", m.mode);
        assert_eq!(m.failures, 1, "{:?}: the NaN sample", m.mode);
        let needs_class = matches!(m.mode, ModeKind::Classified | ModeKind::Hybrid);
        assert_eq!(m.unavailable, if needs_class { 8 } else { 0 });
        let mean = m.mean_pa_mpjpe_mm.unwrap();
        let median = m.median_pa_mpjpe_mm.unwrap();
        assert!(mean >= 0.0 && median >= 0.0);
        match m.mode {
            ModeKind::Opt => assert_eq!(m.beats_opt_share, None),
            _ => assert!((0.0..=1.0).contains(&m.beats_opt_share.unwrap())),
        }
        assert!((0.0..=1.0).contains(&m.reflected_share.unwrap()));
    }
    // Oracle camera, poses in the span: exact recovery.
    let oracle = &report.modes[2];
    assert!(oracle.mean_pa_mpjpe_mm.unwrap() < 1e-3, "{oracle:?}");
    assert!(oracle.mean_rms_error_torsos.unwrap() < 1e-6);
    assert!(oracle.mean_projection_error_eq12.unwrap() < 1e-6);
    // Deterministic whatever the thread scheduling.
    assert_eq!(evaluate(&samples, &reconstructor, &ModeKind::ALL), report);
    let table = report.to_string();
    for name in ["opt", "classified", "oracle", "hybrid"] {
        assert!(table.contains(name), "{table}");
    }
}

#[test]
fn opt_is_the_reference_even_when_not_requested() {
    let (reconstructor, samples) = setup();
    let report = evaluate(
        &samples[..9],
        &reconstructor,
        &[ModeKind::Oracle, ModeKind::Oracle],
    );
    assert_eq!(report.modes.len(), 1);
    assert_eq!(report.modes[0].mode, ModeKind::Oracle);
    assert!(report.modes[0].beats_opt_share.is_some());
    let empty = evaluate(&[], &reconstructor, &[ModeKind::Opt]);
    assert_eq!(empty.modes[0].evaluated, 0);
    assert_eq!(empty.modes[0].mean_pa_mpjpe_mm, None);
}

/// A pipeline is measured as the modes are: one that reconstructs with the `opt` camera gets
/// `opt`'s row, and one that fails on some samples counts them as failures.
#[test]
fn a_pipeline_is_measured_beside_the_modes() {
    let (reconstructor, samples) = setup();
    let as_opt = |pose: &Pose2| reconstructor.reconstruct(pose, &CameraMode::Opt).ok();
    let pipeline = Pipeline {
        name: "opt again".into(),
        mode: ModeKind::Opt,
        run: &as_opt,
    };
    let report = evaluate_with_pipeline(&samples, &reconstructor, &ModeKind::ALL, Some(&pipeline));
    let measured = report.pipeline.as_ref().unwrap();
    assert_eq!(measured.name, "opt again");
    let opt = &report.modes[0];
    assert_eq!(measured.report.mean_pa_mpjpe_mm, opt.mean_pa_mpjpe_mm);
    assert_eq!(measured.report.failures, opt.failures);
    // Compared with `opt`, it never beats it (the same errors are not strictly lower).
    assert_eq!(measured.report.beats_opt_share, Some(0.0));
    assert!(
        report
            .to_string()
            .lines()
            .last()
            .unwrap()
            .starts_with("opt again ")
    );
    // Without a pipeline, the report has none, and the JSON no key for it.
    let bare = evaluate(&samples, &reconstructor, &ModeKind::ALL);
    assert_eq!(bare.pipeline, None);
    let failing = |pose: &Pose2| (pose.points[0][0] > 60.0).then(|| as_opt(pose)).flatten();
    let pipeline = Pipeline {
        name: "half".into(),
        mode: ModeKind::Opt,
        run: &failing,
    };
    let half = evaluate_with_pipeline(&samples, &reconstructor, &[], Some(&pipeline));
    let half = half.pipeline.unwrap().report;
    assert!(half.failures > opt.failures, "{half:?}");
    assert_eq!(half.evaluated + half.failures, samples.len());
}

/// A sample whose true pose has no extent (a forged dataset's all-zero poses, which scored
/// 0.0 mm) is not measured: it counts as a failure.
#[test]
fn a_true_pose_of_no_extent_is_not_measured() {
    let (reconstructor, mut samples) = setup();
    samples.truncate(3);
    samples[1].truth.points = [[0.0; 3]; camloc_skeleton::NUM_LANDMARKS];
    let report = evaluate(&samples, &reconstructor, &[ModeKind::Opt]);
    assert_eq!(report.modes[0].evaluated, 2);
    assert_eq!(report.modes[0].failures, 1);
    // That sample alone: nothing measured.
    samples.truncate(2);
    samples.remove(0);
    let report = evaluate(&samples, &reconstructor, &[ModeKind::Opt]);
    assert_eq!(report.modes[0].mean_pa_mpjpe_mm, None);
}
