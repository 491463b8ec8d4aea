//! The prior over the camera's height (`CameraHeight`): it reweighs the model's camera
//! probabilities in every path (single poses, many labels, evaluation) but not the lookup of
//! the uncertainty, is not saved with the model, and on views of studio cameras (`rig`, skipped visibly without the data) `eye-level`
//! finds the camera more often while views from far above or below pay for it. The shares of
//! the heights estimated from an input (`HeightShares`) follow what the input holds.

mod common;

use camloc::dataset::{
    Dataset, GenerateConfig, PoseSequence, Protocol, generate, load_mocap_folders,
};
use camloc::store::Persist;
use camloc::{
    CameraHeight, CameraLocalizer, EYE_LEVEL_WEIGHT, HEIGHT_SHARE_MAX_POSES, HeightShares,
    Landmark, Level, PartialPose2, evaluate, eye_level_shares,
};

/// Views of each protocol tried (every n-th generated view, spread over clips and cameras).
const VIEWS: usize = 3000;

#[test]
fn eye_level_reweighs_the_middle_ring_in_every_path_and_is_not_saved() {
    let any = CameraLocalizer::default_model().unwrap();
    assert_eq!(any.camera_height(), CameraHeight::Any);
    let eye = any.clone().with_camera_height(CameraHeight::EyeLevel);
    let poses: Vec<PartialPose2> = common::example_records().iter().map(|r| r.pose).collect();
    let middle: Vec<bool> = any
        .cameras()
        .viewpoints()
        .iter()
        .map(|v| v.level == Level::Middle)
        .collect();
    for pose in &poses {
        let (a, e) = (
            any.localize_partial(pose).unwrap(),
            eye.localize_partial(pose).unwrap(),
        );
        let weighed: Vec<f64> = a
            .probabilities
            .iter()
            .zip(&middle)
            .map(|(p, m)| if *m { p * EYE_LEVEL_WEIGHT } else { *p })
            .collect();
        let total: f64 = weighed.iter().sum();
        for (got, want) in e.probabilities.iter().zip(&weighed) {
            assert!((got - want / total).abs() < 1e-12, "{got} against {want}");
        }
        assert!((e.probability - e.probabilities[e.label.index()]).abs() < 1e-15);
        // The uncertainty is looked up by the model's own probability of the chosen camera,
        // the one it was calibrated on, not by the reweighed one.
        let heads = any.viewpoint_heads().unwrap();
        let own = a.probabilities[e.label.index()];
        assert_eq!(e.uncertainty_deg, Some(heads.uncertainty_deg(own)));
        if e.label == a.label {
            assert_eq!(e.uncertainty_deg, a.uncertainty_deg);
        }
    }
    let labels: Vec<_> = poses
        .iter()
        .map(|p| eye.localize_partial(p).unwrap().label)
        .collect();
    assert_eq!(eye.predict_labels(&poses).unwrap(), labels);
    // A prior of the footage, not of the model: the file is the same and loads as `any`.
    let dir = tempfile::tempdir().unwrap();
    let (a_path, e_path) = (dir.path().join("any.bin"), dir.path().join("eye.bin"));
    any.save(&a_path, false).unwrap();
    eye.save(&e_path, false).unwrap();
    assert_eq!(
        std::fs::read(&a_path).unwrap(),
        std::fs::read(&e_path).unwrap()
    );
    assert_eq!(
        CameraLocalizer::load(&e_path).unwrap().camera_height(),
        CameraHeight::Any
    );
}

/// About [`VIEWS`] `rig` views of `sequences` (every n-th generated view), then as many
/// `sphere` views inside the class boxes of the upper and lower rings, drawn from `seed`.
fn studio_and_far_views(sequences: &[PoseSequence], seed: u64) -> [(Protocol, Dataset); 2] {
    [Protocol::Rig, Protocol::Sphere].map(|protocol| {
        let mut config = GenerateConfig::new(protocol);
        config.stride = 10;
        config.seed = seed;
        let mut dataset = generate(sequences, &config, &|_, _| {}).unwrap();
        if protocol == Protocol::Sphere {
            let cameras = dataset.header.cameras.clone();
            dataset.samples.retain(|s| {
                s.in_class_box
                    && cameras
                        .get(s.label)
                        .is_some_and(|v| v.level != Level::Middle)
            });
        }
        let step = (dataset.samples.len() / VIEWS).max(1);
        dataset.samples = dataset.samples.into_iter().step_by(step).collect();
        (protocol, dataset)
    })
}

/// On the `rig` views and the far `sphere` views of the CMU data ([`studio_and_far_views`],
/// `seed`), the prior `prior` gives for each set: the prior, the embedded model's accuracy
/// under its own priors and under that prior (printed, naming `test`). `None`, skipped
/// visibly, without the data.
fn accuracies_against_any(
    test: &str,
    seed: u64,
    prior: impl Fn(&CameraLocalizer, &Dataset) -> CameraHeight,
) -> Option<[(CameraHeight, f64, f64); 2]> {
    let cmu = camloc::skeleton::data::data_path_or_skip("cmu", test)?;
    let (sequences, _) = load_mocap_folders(&[cmu], &mut |_| {}, &mut |_, _, _| {}).unwrap();
    let any = CameraLocalizer::default_model().unwrap();
    Some(
        studio_and_far_views(&sequences, seed).map(|(protocol, dataset)| {
            let height = prior(&any, &dataset);
            let other = any.clone().with_camera_height(height);
            let (a, o) = (
                evaluate(&any, &dataset).unwrap().accuracy,
                evaluate(&other, &dataset).unwrap().accuracy,
            );
            eprintln!(
                "{protocol:?}: {} views, any {:.2}%, {height:?} {:.2}%",
                dataset.samples.len(),
                100.0 * a,
                100.0 * o
            );
            assert!(dataset.samples.len() >= 1000, "{}", dataset.samples.len());
            (height, a, o)
        }),
    )
}

/// On `rig` views (tripod cameras 1.0-2.2 m high: nearly all in the middle ring) the
/// eye-level prior gets the camera right more often than the model's own priors, and on
/// `sphere` views inside the class boxes of the upper and lower rings less often. The embedded
/// model was trained on these subjects (held-out subjects: docs/RESULTS.md), so this checks
/// the direction of the trade, not its size.
#[test]
fn eye_level_helps_studio_views_and_costs_views_from_above_and_below() {
    let Some([(_, rig_any, rig_eye), (_, far_any, far_eye)]) = accuracies_against_any(
        "camloc::eye_level_helps_studio_views_and_costs_views_from_above_and_below",
        11,
        |_, _| CameraHeight::EyeLevel,
    ) else {
        return;
    };
    assert!(
        rig_eye > rig_any,
        "rig: {rig_eye} with eye-level against {rig_any}"
    );
    assert!(
        far_eye < far_any,
        "upper and lower rings: {far_eye} with eye-level against {far_any}"
    );
}

/// The model's stored priors are a distribution over its cameras; shares equal to the model's
/// own change no probability; too few poses give no estimate (each pose on its own), enough
/// give one, and only the first `HEIGHT_SHARE_MAX_POSES` are read.
#[test]
fn the_models_own_shares_change_nothing_and_small_inputs_get_no_estimate() {
    let any = CameraLocalizer::default_model().unwrap();
    let priors = &any.training_info().camera_priors;
    assert_eq!(priors.len(), any.cameras().len());
    assert!((priors.iter().sum::<f64>() - 1.0).abs() < 1e-9);
    let share = |level: Level| -> f64 {
        priors
            .iter()
            .zip(any.cameras().viewpoints())
            .filter(|(_, v)| v.level == level)
            .map(|(p, _)| p)
            .sum()
    };
    let own = HeightShares::new(
        share(Level::Lower),
        share(Level::Middle),
        share(Level::Upper),
    )
    .unwrap();
    let same = any.clone().with_camera_height(CameraHeight::Shares(own));
    let poses: Vec<PartialPose2> = common::example_records().iter().map(|r| r.pose).collect();
    for pose in &poses {
        let (a, s) = (
            any.localize_partial(pose).unwrap(),
            same.localize_partial(pose).unwrap(),
        );
        for (x, y) in a.probabilities.iter().zip(&s.probabilities) {
            assert!((x - y).abs() < 1e-12, "{x} against {y}");
        }
    }
    // Three poses move the shares little from eye level's; none that can be localized give
    // none (each pose on its own).
    let few = any.estimate_height_shares(&poses);
    assert_eq!((few.read, few.localized), (3, 3));
    let centre = eye_level_shares(&any.model_height_shares());
    let shares = few.shares.expect("three poses");
    assert!(
        (shares.middle - centre.middle).abs() < 3.0 / 13.0,
        "{few:?}"
    );
    assert_eq!(few.camera_height(), CameraHeight::Shares(shares));
    let mut broken = poses[0];
    broken.points[Landmark::Pelvis as usize] = Some([f64::NAN, 0.0]);
    let nothing = any.estimate_height_shares(&[broken]);
    assert_eq!((nothing.shares, nothing.localized), (None, 0));
    assert_eq!(nothing.camera_height(), CameraHeight::Any);
    // More poses (and one that cannot be localized, left out).
    let mut many: Vec<PartialPose2> = poses.iter().cycle().take(100).copied().collect();
    assert!(any.localize_partial(&broken).is_err());
    many.push(broken);
    let enough = any.estimate_height_shares(&many);
    assert_eq!((enough.read, enough.localized), (101, 100));
    let shares = enough.shares.expect("enough poses");
    assert!((shares.lower + shares.middle + shares.upper - 1.0).abs() < 1e-12);
    assert_eq!(enough.camera_height(), CameraHeight::Shares(shares));
    // Only the first poses are read.
    let long: Vec<PartialPose2> = poses
        .iter()
        .cycle()
        .take(HEIGHT_SHARE_MAX_POSES + 7)
        .copied()
        .collect();
    assert_eq!(
        any.estimate_height_shares(&long).read,
        HEIGHT_SHARE_MAX_POSES
    );
}

/// On `rig` views the estimate finds nearly every camera in the middle ring and localizing
/// under it finds the camera more often than the model's own priors; on `sphere` views of the
/// upper and lower rings it finds few middle cameras and does not lose to the model's priors
/// either (skipped visibly without the data; the embedded model was trained on these
/// subjects, so this checks directions, not sizes).
#[test]
fn shares_from_the_input_follow_studio_views_and_views_from_above_and_below() {
    let Some([rig, far]) = accuracies_against_any(
        "camloc::shares_from_the_input_follow_studio_views_and_views_from_above_and_below",
        12,
        |any, dataset| any.estimate_height_shares_of(dataset).camera_height(),
    ) else {
        return;
    };
    let middle = |height: CameraHeight| match height {
        CameraHeight::Shares(shares) => shares.middle,
        other => panic!("no shares: {other:?}"),
    };
    let (shares, any, estimated) = rig;
    assert!(middle(shares) > 0.9, "{shares:?}");
    assert!(estimated > any, "{estimated} against {any}");
    let (shares, any, estimated) = far;
    assert!(middle(shares) < 0.2, "{shares:?}");
    assert!(estimated >= any, "{estimated} against {any}");
}
