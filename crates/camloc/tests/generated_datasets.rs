//! Every dataset camloc makes trains: the fixture mocap under the `canonical` protocol holds
//! views whose 2D torso vanishes (a camera looking along it), which generation leaves out
//! and counts instead of letting training abort on them (issue 22 item 13).

use std::path::PathBuf;

use camloc::dataset::{GenerateConfig, Protocol, generate, load_mocap_folders};
use camloc::{CameraLocalizer, Descriptor, TrainOptions, evaluate};

#[test]
fn canonical_views_of_the_fixture_mocap_train_with_every_descriptor() {
    let fixtures = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/mocap"));
    let (sequences, _) = load_mocap_folders(&[fixtures], &mut |_| {}, &mut |_, _, _| {}).unwrap();
    let dataset = generate(
        &sequences,
        &GenerateConfig::new(Protocol::Canonical),
        &|_, _| {},
    )
    .unwrap();
    for descriptor in [Descriptor::Joints, Descriptor::Landmarks] {
        let options = TrainOptions {
            descriptor,
            dropout: None,
            mirror: false,
            ..TrainOptions::default()
        };
        let (localizer, _) = CameraLocalizer::train(&dataset, &options, |_| {}).unwrap();
        evaluate(&localizer, &dataset).unwrap();
    }
    assert!(
        dataset.header.undescribable_views > 0,
        "the fixture's canonical views hold a degenerate torso"
    );
}

/// A dataset without views of some camera (here `rig` views of the fixture mocap: tripod
/// cameras, nearly all in the middle ring) trains without viewpoint heads, and with them is
/// refused before the classifier's fit, naming a camera it lacks.
#[test]
fn a_dataset_missing_a_camera_trains_without_heads_and_is_refused_with_them_at_once() {
    let fixtures = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/mocap"));
    let (sequences, _) = load_mocap_folders(&[fixtures], &mut |_| {}, &mut |_, _, _| {}).unwrap();
    let dataset = generate(&sequences, &GenerateConfig::new(Protocol::Rig), &|_, _| {}).unwrap();
    let options = TrainOptions {
        dropout: None,
        ..TrainOptions::default()
    };
    let mut iterations = 0;
    let err = CameraLocalizer::train(&dataset, &options, |_| iterations += 1).unwrap_err();
    assert_eq!(iterations, 0, "refused before the fit");
    assert!(
        err.to_string().contains("has no samples") && err.to_string().contains("--no-viewpoint"),
        "{err}"
    );
    let without = TrainOptions {
        viewpoint_lambda: None,
        ..options
    };
    let (localizer, _) = CameraLocalizer::train(&dataset, &without, |_| {}).unwrap();
    assert!(localizer.viewpoint_heads().is_none());
}
