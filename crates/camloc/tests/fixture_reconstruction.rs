//! The fixture mocap (planar skeletons: side views project every landmark onto one line)
//! reconstructs in every camera mode, with a bounded eq. 12 error. Before, `opt` and `hybrid`
//! failed on the 18 side views (degenerate Procrustes camera) and the edge-on bounding boxes
//! (width ~1e-16) gave eq. 12 errors of ~4e14.

use std::path::PathBuf;

use camloc::dataset::{GenerateConfig, Protocol, generate, load_mocap_folders};
use camloc::{CameraLocalizer, PoseReconstructor, default_basis};

#[test]
fn fixture_mocap_reconstructs_in_every_mode() {
    let folder = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/mocap");
    let (sequences, _) = load_mocap_folders(&[folder], &mut |_| {}, &mut |_, _, _| {}).unwrap();
    let mut config = GenerateConfig::new(Protocol::Canonical);
    config.stride = 10;
    config.min_pose_distance_mm = 0.0;
    let dataset = generate(&sequences, &config, &|_, _| {}).unwrap();
    assert_eq!(dataset.samples.len(), 36);
    let report = PoseReconstructor::new(default_basis().unwrap())
        .unwrap()
        .with_localizer(CameraLocalizer::default_model().unwrap())
        .evaluate(&dataset)
        .unwrap();
    for mode in &report.modes {
        assert_eq!(mode.failures, 0, "{:?} failed on some samples", mode.mode);
        if mode.evaluated > 0 {
            let eq12 = mode.mean_projection_error_eq12.unwrap();
            assert!(eq12 < 5.0, "{:?}: eq. 12 {eq12}", mode.mode);
        }
    }
}
