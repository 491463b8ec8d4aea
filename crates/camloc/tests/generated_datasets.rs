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
