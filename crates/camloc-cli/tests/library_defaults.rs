//! The library's defaults (`PoseReconstructor::default_reconstructor`, the camera heights
//! estimated from the input) give the command line's answers: a user of the crate who follows
//! its documentation gets `camloc localize` and `camloc reconstruct` (a trial's library user
//! found `localize_partial` refusing 150 of 400 photos that the command line localized, and
//! the reconstruction's defaults 0.45 m apart from the command line's).

use camloc::keypoints::{ReadOptions, read_keypoints};
use camloc::{CameraHeight, Landmark, PartialPose2, PoseReconstructor};
use serde_json::Value;

mod common;
use common::{TempDir, camloc, fixture};

/// The poses of both fixtures (complete ones, ones without a pelvis or an arm) and the
/// example's without their pelvis and left hip (which `localize_partial` refuses and the
/// command line fills in), written in `dir`.
fn inputs(dir: &TempDir) -> Vec<std::path::PathBuf> {
    let example = fixture("keypoints/example.json");
    let mut document: Value =
        serde_json::from_str(&std::fs::read_to_string(&example).unwrap()).unwrap();
    for pose in document["poses"].as_array_mut().unwrap() {
        pose["landmarks"]["left_hip"] = Value::Null;
        pose["landmarks"]["pelvis"] = Value::Null;
    }
    let hipless = dir.file("hipless.json", &document.to_string());
    // 120 poses (the example's, moved and jittered by up to 2 px).
    let mut document: Value =
        serde_json::from_str(&std::fs::read_to_string(&example).unwrap()).unwrap();
    let originals = document["poses"].as_array().unwrap().clone();
    let mut seed = 11u64;
    let mut jitter = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        4.0 * ((seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5)
    };
    let many: Vec<Value> = (0..120)
        .map(|n| {
            let mut pose = originals[n % originals.len()].clone();
            pose["id"] = format!("copy-{n}").into();
            for point in pose["landmarks"].as_object_mut().unwrap().values_mut() {
                if let Some(xy) = point.as_array_mut() {
                    for (k, c) in xy.iter_mut().enumerate() {
                        let shift = if k == 0 { 3.0 * n as f64 } else { 0.0 };
                        *c = (c.as_f64().unwrap() + shift + jitter()).into();
                    }
                }
            }
            pose
        })
        .collect();
    document["poses"] = many.into();
    let many = dir.file("many.json", &document.to_string());
    vec![
        example,
        fixture("keypoints/partial.json"),
        std::path::PathBuf::from(hipless),
        std::path::PathBuf::from(many),
    ]
}

#[test]
fn the_library_defaults_give_the_command_lines_localizations_and_poses() {
    let dir = TempDir::new("library-defaults");
    for input in inputs(&dir) {
        let path = input.to_str().unwrap();
        let records = read_keypoints(&input, None, &ReadOptions::default()).unwrap();
        let poses: Vec<PartialPose2> = records.iter().map(|r| r.pose).collect();
        let reconstructor = PoseReconstructor::default_reconstructor()
            .unwrap()
            .with_camera_height_from(&poses);
        // The prior is the input's own, not `any`, unless no pose has a torso to estimate it.
        let estimated = reconstructor.localizer().unwrap().camera_height();
        let with_torso = camloc::CameraLocalizer::default_model()
            .unwrap()
            .estimate_height_shares(&poses)
            .localized;
        assert_eq!(
            matches!(estimated, CameraHeight::Shares(_)),
            with_torso > 0,
            "{path}: {estimated:?}"
        );
        // Printed also when a pose fails (an object with its error; exit 1).
        let json = |command: &str| -> Vec<Value> {
            let out = camloc(&[command, "--input", path, "--json"]);
            serde_json::from_slice(&out.stdout).unwrap()
        };
        let (localized, reconstructed) = (json("localize"), json("reconstruct"));
        assert_eq!(localized.len(), poses.len());
        for ((pose, cli), cli3d) in poses.iter().zip(&localized).zip(&reconstructed) {
            if input.ends_with("hipless.json") {
                assert!(
                    reconstructor
                        .localizer()
                        .unwrap()
                        .localize_partial(pose)
                        .is_err()
                );
            }
            let Ok(own) = reconstructor.localize(pose) else {
                assert!(
                    cli["error"].is_string() && cli3d["error"].is_string(),
                    "{path}"
                );
                assert!(reconstructor.reconstruct(pose).is_err());
                continue;
            };
            assert_eq!(cli["label"], u64::from(own.label.get()), "{path}");
            let close = |key: &str, value: Option<f64>| {
                let value = value.unwrap_or(f64::NAN);
                assert!(
                    (cli[key].as_f64().unwrap() - value).abs() < 1e-9,
                    "{path} {key}"
                );
            };
            close("probability", Some(own.probability));
            close("azimuth_deg", own.azimuth_deg);
            close("elevation_deg", own.elevation_deg);
            let result = reconstructor.reconstruct(pose).unwrap();
            for landmark in Landmark::ALL {
                let cli_point = &cli3d["landmarks_m"][landmark.name()];
                let point = result.reconstruction.pose.get(landmark);
                for k in 0..3 {
                    let cli_value = cli_point[k].as_f64().unwrap();
                    assert!((cli_value - point[k]).abs() < 1e-9, "{path} {landmark:?}");
                }
            }
        }
    }
}
