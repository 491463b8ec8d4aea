//! `train`, `evaluate`, `reconstruct` and `evaluate-reconstruction` succeed on fixture data.

use camloc::store::Persist;
use std::path::Path;
use std::process::Command;

mod common;
use common::*;

/// train, evaluate, reconstruct and evaluate-reconstruction succeed on a fixture dataset, and
/// what they print agrees with the files they read and write.
#[test]
fn train_evaluate_and_reconstruct_succeed_on_fixture_data() {
    let dir = TempDir::new("success");
    let data = fixture_dataset(&dir);
    let model = dir.0.join("model.bin");
    let model = model.to_str().unwrap();
    let out = camloc(&[
        "train",
        "--dataset",
        &data,
        "--out",
        model,
        "--descriptor",
        "landmarks",
        "--lambda",
        "0.5",
        "--dropout",
        "0.5",
        "--capacity",
        "quadratic-4",
        "--quiet",
    ]);
    assert!(success(&out).starts_with("wrote "));
    // A fixture dataset has a few views per camera, fewer than its heads' features.
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("fewer training views than the") && stderr.contains("camera(s) 01 ("),
        "{stderr}"
    );
    let trained = camloc::CameraLocalizer::load(Path::new(model)).unwrap();
    assert_eq!(trained.descriptor().name(), "landmarks");
    assert_eq!(trained.training_info().lambda, 0.5);
    assert_eq!(
        trained.training_info().capacity,
        camloc::Capacity::Quadratic { components: 4 }
    );

    let out = camloc(&["evaluate", "--model", model, "--dataset", &data, "--json"]);
    let e: serde_json::Value = serde_json::from_str(&success(&out)).unwrap();
    let dataset = camloc::dataset::Dataset::load(Path::new(&data)).unwrap();
    assert_eq!(e["samples"].as_u64(), Some(dataset.samples.len() as u64));
    let accuracy = e["accuracy"].as_f64().unwrap();
    assert!((0.0..=1.0).contains(&accuracy));
    let confusion: u64 = e["confusion"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|row| row.as_array().unwrap())
        .map(|c| c.as_u64().unwrap())
        .sum();
    assert_eq!(confusion, dataset.samples.len() as u64);
    // Levels are named as everywhere else (lower case, as `localize --json` writes them).
    let levels: Vec<&str> = e["per_level"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| l["level"].as_str().unwrap())
        .collect();
    assert_eq!(levels, ["lower", "middle", "upper"]);
    assert_eq!(e["per_ring"].as_array().map(Vec::len), Some(3));
    // The prior the run localized under, and from-input's estimate.
    assert_eq!(e["camera_height"], "from-input");
    let shares = e["camera_height_shares"].as_array().unwrap();
    let total: f64 = shares.iter().map(|s| s.as_f64().unwrap()).sum();
    assert!((total - 1.0).abs() < 1e-9, "{shares:?}");
    // The trained model has viewpoint heads: their errors against the true directions.
    let median = e["viewpoint"]["median_error_deg"].as_f64().unwrap();
    assert!((0.0..=180.0).contains(&median), "{median}");
    let text = camloc(&["evaluate", "--model", model, "--dataset", &data]);
    assert!(text.status.success());
    let text = String::from_utf8_lossy(&text.stdout);
    assert!(text.contains(&format!("accuracy:         {:.2}%", 100.0 * accuracy)));
    assert!(
        text.contains(&format!("viewpoint:        median {median:.1} deg off")),
        "{text}"
    );
    // Table 1's rings are its levels: no lines of their own.
    assert!(!text.contains("per ring:"), "{text}");

    let input = fixture("keypoints/example.json");
    let input = input.to_str().unwrap();
    let out = camloc(&[
        "reconstruct",
        "--model",
        model,
        "--input",
        input,
        "--camera",
        "classified",
        "--json",
    ]);
    let poses: serde_json::Value = serde_json::from_str(&success(&out)).unwrap();
    let poses = poses.as_array().unwrap();
    assert_eq!(poses.len(), 3);
    // The localization is `localize`'s: its label, probability and continuous viewpoint.
    let localize = ["localize", "--model", model, "--input", input, "--json"];
    let localized: serde_json::Value = serde_json::from_str(&success(&camloc(&localize))).unwrap();
    for (p, l) in poses.iter().zip(localized.as_array().unwrap()) {
        assert_eq!(p["classified_label"], l["label"]);
        for key in ["probability", "azimuth_deg", "elevation_deg"] {
            assert!(p[key].is_f64(), "{key}: {p}");
            assert_eq!(p[key], l[key], "{key}");
        }
    }
    for p in poses {
        assert_eq!(p["camera_mode"], "classified");
        let label = p["classified_label"].as_u64().unwrap();
        assert!((1..=12).contains(&label));
        assert_eq!(p["landmarks_m"].as_object().unwrap().len(), 15);
        assert!(p.get("alternatives").is_none(), "one hypothesis by default");
    }

    // Without --camera: hybrid, for single poses as for sequences.
    for extra in [None, Some("--sequence")] {
        let mut args = vec!["reconstruct", "--input", input, "--json"];
        args.extend(extra);
        let poses: serde_json::Value = serde_json::from_str(&success(&camloc(&args))).unwrap();
        for p in poses.as_array().unwrap() {
            assert_eq!(p["camera_mode"], "hybrid", "{extra:?}");
        }
    }

    // --hypotheses 2: the depth mirror beside the preferred one, both scored; hybrid has 2
    // solves of 2 each, 1 with the lifter (its rotation held at the localized viewpoint).
    for (camera, lifter, n) in [("opt", true, 2), ("hybrid", false, 4), ("hybrid", true, 2)] {
        let mut args = vec![
            "reconstruct",
            "--input",
            input,
            "--camera",
            camera,
            "--hypotheses",
            "4",
            "--json",
        ];
        if !lifter {
            args.push("--no-lifter");
        }
        let out = camloc(&args);
        let poses: serde_json::Value = serde_json::from_str(&success(&out)).unwrap();
        for p in poses.as_array().unwrap() {
            let alternatives = p["alternatives"].as_array().unwrap();
            assert_eq!(alternatives.len(), n - 1, "{camera}");
            let reflected = std::iter::once(p)
                .chain(alternatives)
                .filter(|h| h["reflected"].as_bool().unwrap())
                .count();
            assert_eq!(reflected, n / 2, "{camera}");
            for h in std::iter::once(p).chain(alternatives) {
                assert!(h["projection_error"].as_f64().unwrap() >= 0.0);
                assert!(h["limit_violation_rad"].as_f64().unwrap() >= 0.0);
                assert_eq!(h["landmarks_m"].as_object().unwrap().len(), 15);
            }
        }
    }
    let text = camloc(&["reconstruct", "--input", input, "--hypotheses", "2"]);
    assert!(text.status.success());
    let text = String::from_utf8_lossy(&text.stdout);
    assert_eq!(
        text.matches("  alternative 1; reprojection error").count(),
        3,
        "{text}"
    );
    let zero = camloc(&["reconstruct", "--input", input, "--hypotheses", "0"]);
    assert!(!zero.status.success());

    let out = camloc(&[
        "evaluate-reconstruction",
        "--model",
        model,
        "--dataset",
        &data,
        "--json",
    ]);
    let report: serde_json::Value = serde_json::from_str(&success(&out)).unwrap();
    assert!(report.is_object(), "{report}");
    // Camera modes are named as `--camera` names them.
    assert!(report.to_string().contains("\"hybrid\""), "{report}");
    assert!(!report.to_string().contains("\"Hybrid\""), "{report}");
    // The last row is `reconstruct`'s default pipeline, on every sample the modes had.
    let modes = report["modes"].as_array().unwrap();
    let pipeline = &report["pipeline"];
    assert_eq!(pipeline["name"], "reconstruct: hybrid + lifter", "{report}");
    assert_eq!(pipeline["mode"], "hybrid", "{report}");
    let counted = |row: &serde_json::Value| {
        ["evaluated", "failures", "unavailable"]
            .iter()
            .filter_map(|k| row[k].as_u64())
            .sum::<u64>()
    };
    assert_eq!(counted(pipeline), counted(&modes[0]), "{report}");
    assert!(
        pipeline["mean_pa_mpjpe_mm"].as_f64().unwrap() > 0.0,
        "{report}"
    );
    let text = camloc(&[
        "evaluate-reconstruction",
        "--model",
        model,
        "--dataset",
        &data,
        "-q",
    ]);
    let text = success(&text);
    assert!(
        text.lines()
            .last()
            .unwrap()
            .starts_with("reconstruct: hybrid + lifter "),
        "{text}"
    );
    let bare = camloc(&[
        "evaluate-reconstruction",
        "--model",
        model,
        "--dataset",
        &data,
        "--no-lifter",
        "--json",
    ]);
    let bare: serde_json::Value = serde_json::from_str(&success(&bare)).unwrap();
    assert_eq!(bare["pipeline"]["name"], "reconstruct: hybrid", "{bare}");

    // The model is moved into place only after standard output was written.
    if let Ok(full) = std::fs::OpenOptions::new().write(true).open("/dev/full") {
        let second = dir.0.join("second.bin");
        let out = Command::new(env!("CARGO_BIN_EXE_camloc"))
            .args([
                "train",
                "--dataset",
                &data,
                "--out",
                second.to_str().unwrap(),
                "--quiet",
            ])
            .stdout(full)
            .output()
            .unwrap();
        // (train also reports what it trains on, on standard error.)
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{stderr}");
        assert!(stderr.contains("camloc: error: cannot write to standard output"));
        assert!(!second.exists());
    }
}

/// `reconstruct` fills in missing landmarks from the localized camera and says which; a pose
/// without a pelvis is still refused, naming it; the drawing leaves the missing landmarks
/// out of the input and names them in its caption.
#[test]
fn reconstruct_fills_in_missing_landmarks() {
    let dir = TempDir::new("filled");
    let partial = fixture("keypoints/partial.json");
    let svg = dir.0.join("filled.svg");
    let out = camloc(&[
        "reconstruct",
        "--input",
        partial.to_str().unwrap(),
        "--jsonl",
        "--svg",
        svg.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(1), "the second pose has no pelvis");
    let stdout = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<serde_json::Value> = stdout
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 2);
    assert_eq!(
        lines[0]["imputed"],
        serde_json::json!(["right_elbow", "right_wrist"])
    );
    for l in camloc::Landmark::ALL {
        let p = lines[0]["landmarks_m"][l.name()].as_array().unwrap();
        assert!(p.iter().all(|x| x.as_f64().unwrap().is_finite()));
    }
    assert!(
        lines[1]["error"].as_str().unwrap().contains("pelvis"),
        "{}",
        lines[1]
    );
    // `opt` fills them in too (with the embedded model's localization).
    let opt = camloc(&[
        "reconstruct",
        "--input",
        partial.to_str().unwrap(),
        "--jsonl",
        "--camera",
        "opt",
    ]);
    let first: serde_json::Value =
        serde_json::from_str(String::from_utf8_lossy(&opt.stdout).lines().next().unwrap()).unwrap();
    assert_eq!(
        first["imputed"],
        serde_json::json!(["right_elbow", "right_wrist"]),
        "{first}"
    );
    // Two poses in the input: the drawings are numbered, the failed pose has none.
    assert!(!dir.0.join("filled-002.svg").exists());
    let drawn = std::fs::read_to_string(dir.0.join("filled-001.svg")).unwrap();
    assert!(drawn.contains("filled in: right_elbow, right_wrist"));
    // Only the input's 12 limbs with both ends present are drawn as its pale band: 14 minus
    // the two of the right arm's missing ends.
    assert_eq!(
        drawn.matches(r#"stroke-opacity="0.3""#).count(),
        12,
        "{drawn}"
    );
}

/// A pose that fails keeps its frame and person numbers in the JSON outputs, as the poses
/// that succeed have them (an OpenPose frame whose person has only the nose and a wrist).
#[test]
fn failed_poses_keep_their_frame_and_person_in_json() {
    let dir = TempDir::new("failed-frame");
    let frames = dir.0.join("frames");
    std::fs::create_dir(&frames).unwrap();
    let mut keypoints = vec![0.0; 75];
    for (joint, [u, v]) in [(0, [100.0, 50.0]), (4, [130.0, 150.0])] {
        keypoints[3 * joint..3 * joint + 3].copy_from_slice(&[u, v, 0.9]);
    }
    let frame = serde_json::json!({"people": [{"pose_keypoints_2d": keypoints}]});
    std::fs::write(
        frames.join("v_000000000007_keypoints.json"),
        frame.to_string(),
    )
    .unwrap();
    for command in ["localize", "reconstruct"] {
        let out = camloc(&[command, "--input", frames.to_str().unwrap(), "--jsonl"]);
        assert_eq!(out.status.code(), Some(1), "{command}");
        let object: serde_json::Value =
            serde_json::from_str(String::from_utf8_lossy(&out.stdout).trim()).unwrap();
        assert!(object["error"].is_string(), "{object}");
        assert_eq!(
            (object["frame"].as_u64(), object["person"].as_u64()),
            (Some(7), Some(0)),
            "{command}: {object}"
        );
    }
}

/// `--camera-height eye-level` with a model whose cameras are all in the middle ring changes
/// nothing, and says so.
#[test]
fn a_camera_height_that_cannot_apply_is_warned_of() {
    use camloc::dataset::{GenerateConfig, Protocol, generate, load_mocap_folders};
    use camloc::store::Persist;
    let dir = TempDir::new("height-middle");
    let (sequences, _) =
        load_mocap_folders(&[fixture("mocap")], &mut |_| {}, &mut |_, _, _| {}).unwrap();
    let mut config = GenerateConfig::new(Protocol::Jittered);
    config.cameras = camloc::CameraSet::sphere(4, &[-20.0, 20.0]).unwrap();
    let data = dir.0.join("middle.bin");
    generate(&sequences, &config, &|_, _| {})
        .unwrap()
        .save(&data, false)
        .unwrap();
    let model = dir.0.join("middle-model.bin");
    let (data, model) = (data.to_str().unwrap(), model.to_str().unwrap());
    success(&camloc(&[
        "train",
        "--dataset",
        data,
        "--out",
        model,
        "--no-viewpoint",
        "-q",
    ]));
    let input = fixture("keypoints/example.json");
    let run = |height: &str| {
        let args = [
            "localize",
            "--input",
            input.to_str().unwrap(),
            "--model",
            model,
            "--camera-height",
            height,
        ];
        camloc(&args)
    };
    let (any, eye) = (run("any"), run("eye-level"));
    assert_eq!(any.stdout, eye.stdout);
    assert!(!String::from_utf8_lossy(&any.stderr).contains("changes nothing"));
    let stderr = String::from_utf8_lossy(&eye.stderr);
    assert!(
        stderr.contains("changes nothing for this model: all of its cameras"),
        "{stderr}"
    );
    // This model's 8 cameras are not Table 1's: `reconstruct` says it goes without the
    // embedded lifter, and refuses a lifter of 12 classes before any pose (each pose had
    // failed on its own, and `evaluate-reconstruction` had exited 0 with every pose failed).
    let reconstruct = |extra: &[&str]| {
        let mut args = vec![
            "reconstruct",
            "--input",
            input.to_str().unwrap(),
            "--model",
            model,
        ];
        args.extend(extra);
        camloc(&args)
    };
    let without = reconstruct(&["-q"]);
    success(&without);
    let stderr = String::from_utf8_lossy(&without.stderr);
    assert!(
        stderr.contains("serves Table 1's cameras, and this model's 8 cameras are others"),
        "{stderr}"
    );
    let lifter = fixture("default-lifter.bin");
    let refused = reconstruct(&["--lifter", lifter.to_str().unwrap()]);
    assert_eq!(refused.status.code(), Some(1));
    assert!(refused.stdout.is_empty());
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert!(
        stderr.contains("has 12 camera classes, the model 8 cameras"),
        "{stderr}"
    );
}

/// A camera without samples in the dataset has no accuracy: null in `evaluate --json`, `-` in
/// the text (it was 0.00, which read as every sample wrong); the others keep theirs.
#[test]
fn a_camera_without_samples_has_no_accuracy() {
    let dir = TempDir::new("no-camera-one");
    let data = fixture_dataset(&dir);
    let mut dataset = camloc::dataset::Dataset::load(Path::new(&data)).unwrap();
    dataset.samples.retain(|s| s.label != 1);
    let path = dir.0.join("no-camera-one.bin");
    dataset.save(&path, false).unwrap();
    let path = path.to_str().unwrap();
    let out = camloc(&["evaluate", "--dataset", path, "--json"]);
    let e: serde_json::Value = serde_json::from_str(&success(&out)).unwrap();
    let cameras = e["per_camera"].as_array().unwrap();
    assert_eq!(cameras[0]["samples"].as_u64(), Some(0));
    assert!(cameras[0]["accuracy"].is_null(), "{}", cameras[0]);
    assert!(cameras[1..].iter().all(|c| c["accuracy"].is_f64()));
    let text = success(&camloc(&["evaluate", "--dataset", path]));
    let line = text
        .lines()
        .find(|l| l.trim_start().starts_with("01 "))
        .unwrap();
    assert!(line.trim_end().ends_with(" -"), "{line}");
}

/// `train` takes several `--dataset`s and trains on them together (the message counts every
/// sample once per file); a dataset of another camera set is refused, naming it, and no model
/// is written.
#[test]
fn train_joins_several_datasets_of_one_camera_set() {
    let dir = TempDir::new("joined");
    let data = fixture_dataset(&dir);
    let samples = camloc::dataset::Dataset::load(Path::new(&data))
        .unwrap()
        .samples
        .len();
    let model = dir.0.join("model.bin").to_string_lossy().into_owned();
    let args = |second: &str| {
        let base = [
            "train",
            "--dataset",
            &data,
            "--dataset",
            second,
            "--out",
            &model,
        ];
        camloc(&[&base[..], &["--no-viewpoint", "--force"]].concat())
    };
    let out = args(&data);
    assert!(success(&out).starts_with("wrote "));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains(&format!("training on {} samples", 2 * samples)),
        "{stderr}"
    );
    std::fs::remove_file(&model).unwrap();
    let mut other = camloc::dataset::Dataset::load(Path::new(&data)).unwrap();
    other.header.cameras = camloc::CameraSet::sphere(4, &[-45.0, 0.0]).unwrap();
    other.samples.retain(|s| s.label <= 8);
    let other_path = dir.0.join("other.bin").to_string_lossy().into_owned();
    other.save(Path::new(&other_path), false).unwrap();
    let out = args(&other_path);
    assert_clean_failure(&out, "other.bin");
    assert!(String::from_utf8_lossy(&out.stderr).contains("12 cameras"));
    assert!(!Path::new(&model).exists());
}

/// `evaluate`'s text for a sphere of several middle rings: a line per ring, and its cameras,
/// whose level and side names repeat, with their angles.
#[test]
fn evaluate_prints_a_finer_spheres_rings_and_angles() {
    use camloc::dataset::{GenerateConfig, Protocol, generate, load_mocap_folders};
    let dir = TempDir::new("rings");
    let (sequences, _) =
        load_mocap_folders(&[fixture("mocap")], &mut |_| {}, &mut |_, _, _| {}).unwrap();
    let mut config = GenerateConfig::new(Protocol::Jittered);
    config.cameras = camloc::CameraSet::sphere(8, &[-20.0, 0.0, 20.0, 40.0]).unwrap();
    let data = dir.0.join("fine.bin");
    generate(&sequences, &config, &|_, _| {})
        .unwrap()
        .save(&data, false)
        .unwrap();
    let data = data.to_str().unwrap();
    let model = dir.0.join("fine-model.bin");
    let model = model.to_str().unwrap();
    let train = ["train", "--dataset", data, "--out", model, "--no-viewpoint"];
    success(&camloc(&[&train[..], &["-q"]].concat()));
    let text = success(&camloc(&["evaluate", "--model", model, "--dataset", data]));
    for line in [
        "per ring:",
        "   -20.0 deg ",
        "    +0.0 deg ",
        "   +40.0 deg ",
    ] {
        assert!(text.contains(line), "{line:?} in {text}");
    }
    assert!(text.contains("02 middle left (az 225, el -20)"), "{text}");
    assert!(text.contains("03 middle left (az 270, el -20)"), "{text}");
}

/// `evaluate` scores samples with missing landmarks as `localize` answers them (filled in), and
/// with `--no-fill` as the library's `evaluate` does (their descriptor values at the training
/// means).
#[test]
fn evaluate_fills_missing_landmarks_unless_told_not_to() {
    use camloc::dataset::{GenerateConfig, Protocol, generate, load_mocap_folders};
    let dir = TempDir::new("no-fill");
    let (sequences, _) =
        load_mocap_folders(&[fixture("mocap")], &mut |_| {}, &mut |_, _, _| {}).unwrap();
    let mut config = GenerateConfig::new(Protocol::Jittered);
    config.drop_landmarks = 4;
    let dataset = generate(&sequences, &config, &|_, _| {}).unwrap();
    let path = dir.0.join("partial.bin");
    dataset.save(&path, false).unwrap();
    let path = path.to_str().unwrap();
    let accuracy = |extra: &[&str]| {
        let args = [
            "evaluate",
            "--dataset",
            path,
            "--json",
            "--camera-height",
            "any",
        ];
        let json: serde_json::Value =
            serde_json::from_str(&success(&camloc(&[&args[..], extra].concat()))).unwrap();
        json["accuracy"].as_f64().unwrap()
    };
    let localizer = camloc::CameraLocalizer::default_model().unwrap();
    let means = camloc::evaluate(&localizer, &dataset).unwrap().accuracy;
    assert_eq!(accuracy(&["--no-fill"]), means);
    let basis = camloc::PoseReconstructor::new(camloc::default_basis().unwrap()).unwrap();
    let filled = camloc::evaluate_filled(&localizer, &dataset, basis.reconstructor());
    assert_eq!(accuracy(&[]), filled.unwrap().accuracy);
    // On these views the two differ (4 of 15 landmarks missing).
    assert_ne!(accuracy(&[]), means);
}
