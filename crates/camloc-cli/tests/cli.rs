//! The `camloc` binary answers bad input with a non-zero exit and one clear line, never a
//! panic.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use camloc::store::Persist;

fn camloc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_camloc"))
        .args(args)
        .output()
        .expect("the camloc binary runs")
}

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures")
        .join(name)
}

struct TempDir(PathBuf);

impl TempDir {
    fn new(name: &str) -> TempDir {
        let dir = std::env::temp_dir().join(format!("camloc-cli-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        TempDir(dir)
    }
    fn file(&self, name: &str, content: &str) -> String {
        let p = self.0.join(name);
        std::fs::write(&p, content).unwrap();
        p.to_string_lossy().into_owned()
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Asserts a failure with exit code 1, no panic, and a message naming `expected`.
fn assert_clean_failure(out: &Output, expected: &str) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "stderr: {stderr}");
    assert!(!stderr.contains("panicked"), "panic: {stderr}");
    assert!(!stderr.contains("RUST_BACKTRACE"), "panic: {stderr}");
    let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
    assert!(!lines.is_empty(), "no message");
    assert!(
        lines.iter().all(|l| l.starts_with("camloc:")),
        "every stderr line is a camloc message: {stderr}"
    );
    assert!(
        stderr.contains(expected),
        "expected '{expected}' in: {stderr}"
    );
}

const FIFTEEN: &str = r#"{"poses": [{"id": "p", "landmarks": {
  "pelvis": [100, 200], "left_hip": [110, 205], "left_knee": [112, 260], "left_ankle": [113, 320],
  "right_hip": [90, 205], "right_knee": [88, 262], "right_ankle": [87, 322], "neck": [100, 140],
  "head": [100, 115], "left_shoulder": [118, 145], "left_elbow": [125, 175], "left_wrist": [128, 200],
  "right_shoulder": [82, 145], "right_elbow": [75, 175], "right_wrist": [72, 200]}}]}"#;

#[test]
fn the_example_is_localized() {
    let out = camloc(&[
        "localize",
        "--input",
        fixture("keypoints/example.json").to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(stdout.matches("probability").count(), 3, "{stdout}");
}

#[test]
fn json_output_has_one_object_per_pose_with_probabilities_summing_to_one() {
    let dir = TempDir::new("json");
    let input = dir.file("p.json", FIFTEEN);
    let out = camloc(&["localize", "--input", &input, "--json"]);
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let poses = v.as_array().unwrap();
    assert_eq!(poses.len(), 1);
    let p = &poses[0];
    let total: f64 = p["probabilities"]
        .as_object()
        .unwrap()
        .values()
        .map(|x| x.as_f64().unwrap())
        .sum();
    assert!((total - 1.0).abs() < 1e-9);
    let label = p["label"].as_u64().unwrap();
    assert!((1..=12).contains(&label));
    assert_eq!(p["rotation"].as_array().unwrap().len(), 3);
    let azimuth = p["azimuth_deg"].as_f64().unwrap();
    let elevation = p["elevation_deg"].as_f64().unwrap();
    let uncertainty = p["uncertainty_deg"].as_f64().unwrap();
    assert!((0.0..360.0).contains(&azimuth), "{azimuth}");
    assert!((-90.0..=90.0).contains(&elevation), "{elevation}");
    assert!((0.0..=180.0).contains(&uncertainty), "{uncertainty}");
}

#[test]
fn svg_is_written_and_not_overwritten_without_force() {
    let dir = TempDir::new("svg");
    let input = dir.file("p.json", FIFTEEN);
    let svg = dir.0.join("out.svg");
    let svg = svg.to_str().unwrap();
    let out = camloc(&["localize", "--input", &input, "--svg", svg]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let drawing = std::fs::read_to_string(svg).unwrap();
    assert!(drawing.starts_with("<svg") && drawing.trim_end().ends_with("</svg>"));
    std::fs::write(svg, "mine").unwrap();
    let out = camloc(&["localize", "--input", &input, "--svg", svg]);
    assert_clean_failure(&out, "already exists");
    assert_eq!(std::fs::read_to_string(svg).unwrap(), "mine");
    let out = camloc(&["localize", "--input", &input, "--svg", svg, "--force"]);
    assert!(out.status.success());
}

#[test]
fn bad_inputs_fail_cleanly() {
    let dir = TempDir::new("bad");
    let missing = dir.0.join("nope.json");
    assert_clean_failure(
        &camloc(&["localize", "--input", missing.to_str().unwrap()]),
        "nope.json",
    );
    let wrong_columns = dir.file("w.csv", "image,joint,x,y\nim1,neck,1,2\n");
    assert_clean_failure(&camloc(&["localize", "--input", &wrong_columns]), "w.csv");
    let nan = dir.file("nan.json", &FIFTEEN.replace("[100, 140]", "[NaN, 140]"));
    assert_clean_failure(&camloc(&["localize", "--input", &nan]), "nan.json");
    let nan_csv = dir.file("nan.csv", "image,joint,x,y,visible\nim1,neck,nan,2,1\n");
    assert_clean_failure(&camloc(&["localize", "--input", &nan_csv]), "nan.csv");
    // 14 landmarks: the neck is missing and cannot be derived without both shoulders.
    let fourteen = dir.file(
        "fourteen.json",
        &FIFTEEN
            .replace(r#""neck": [100, 140],"#, "")
            .replace(r#""left_shoulder": [118, 145],"#, ""),
    );
    assert_clean_failure(&camloc(&["localize", "--input", &fourteen]), "neck");
    let empty = dir.file("empty.json", "");
    assert_clean_failure(&camloc(&["localize", "--input", &empty]), "empty.json");
    let not_a_model = dir.file("model.bin", "hello");
    assert_clean_failure(
        &camloc(&["localize", "--model", &not_a_model, "--input", &nan]),
        "not a camloc model",
    );
    assert_clean_failure(
        &camloc(&[
            "evaluate",
            "--model",
            &not_a_model,
            "--dataset",
            &not_a_model,
        ]),
        "not a camloc model",
    );
    assert_clean_failure(
        &camloc(&[
            "train",
            "--dataset",
            &not_a_model,
            "--out",
            dir.0.join("m.bin").to_str().unwrap(),
        ]),
        "not a camloc dataset",
    );
    let usage = camloc(&["localize"]);
    assert_eq!(usage.status.code(), Some(2));
}

#[test]
fn help_documents_exit_codes() {
    let out = camloc(&["--help"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("Exit codes"), "{text}");
    for sub in ["train", "evaluate", "localize"] {
        let out = camloc(&[sub, "--help"]);
        assert!(out.status.success());
        assert!(String::from_utf8_lossy(&out.stdout).contains("Exit codes"));
    }
}

/// Every malformed keypoint fixture, fed to every subcommand that reads keypoints, gives exit
/// code 1 and camloc messages only; malformed model and dataset files likewise for the
/// subcommands that read those.
#[test]
fn every_malformed_file_fails_cleanly_in_every_subcommand() {
    let bad_dir = fixture("keypoints/bad");
    let mut bad: Vec<PathBuf> = std::fs::read_dir(&bad_dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    bad.sort();
    assert!(bad.len() >= 12, "at least a dozen malformed fixtures");
    for file in &bad {
        let name = file.file_name().unwrap().to_string_lossy().into_owned();
        let path = file.to_str().unwrap();
        for sub in ["localize", "reconstruct"] {
            let out = camloc(&[sub, "--input", path]);
            assert_clean_failure(&out, &name);
        }
    }
    let dir = TempDir::new("bad-binary");
    let truncated_model = {
        let bytes = camloc::CameraLocalizer::default_model()
            .unwrap()
            .to_bytes()
            .unwrap();
        let p = dir.0.join("truncated-model.bin");
        std::fs::write(&p, &bytes[..bytes.len() / 2]).unwrap();
        p
    };
    let binaries = [
        dir.file("empty.bin", ""),
        dir.file("text.bin", "image,joint,x,y,visible\n"),
        truncated_model.to_string_lossy().into_owned(),
    ];
    let input = fixture("keypoints/example.json");
    let input = input.to_str().unwrap();
    let out_model = dir.0.join("m.bin");
    let out_model = out_model.to_str().unwrap();
    for file in &binaries {
        let name = Path::new(file)
            .file_name()
            .unwrap()
            .to_string_lossy()
            .into_owned();
        for args in [
            vec!["localize", "--model", file, "--input", input],
            vec!["reconstruct", "--model", file, "--input", input],
            vec!["reconstruct", "--basis", file, "--input", input],
            vec!["evaluate", "--model", file, "--dataset", file],
            vec!["evaluate-reconstruction", "--dataset", file],
            vec!["train", "--dataset", file, "--out", out_model],
        ] {
            let out = camloc(&args);
            let stderr = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(1), "{args:?}: {stderr}");
            assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
            assert_eq!(stderr.lines().count(), 1, "{args:?} ({name}): {stderr}");
        }
    }
    assert!(
        !Path::new(out_model).exists(),
        "no model written from bad input"
    );
}

/// Asserts a usage error: exit code 2, clap's message naming `option`, no panic.
fn assert_usage_error(out: &Output, option: &str) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "stderr: {stderr}");
    assert!(!stderr.contains("panicked"), "panic: {stderr}");
    assert!(stderr.contains("invalid value"), "{stderr}");
    assert!(stderr.contains(option), "expected '{option}' in: {stderr}");
}

/// Numeric options are checked when the command line is parsed: out-of-range values are usage
/// errors (exit 2, as the help promises), before any file is read or any output checked.
#[test]
fn out_of_range_options_are_usage_errors() {
    let dir = TempDir::new("bounds");
    let existing = dir.file("exists.bin", "mine");
    let dataset = dir.0.join("no-such-dataset.bin");
    let dataset = dataset.to_str().unwrap();
    let train = |extra: &[&str]| {
        let mut args = vec!["train", "--dataset", dataset, "--out", &existing];
        args.extend_from_slice(extra);
        camloc(&args)
    };
    for bad in ["-1", "NaN", "inf", "-inf", "x"] {
        assert_usage_error(&train(&["--lambda", bad]), "--lambda");
    }
    for bad in ["-1", "nan", "1e15", "10.5", "inf", "many"] {
        assert_usage_error(&train(&["--dropout", bad]), "--dropout");
    }
    // The descriptor is checked by clap, before the output-exists check.
    assert_usage_error(&train(&["--descriptor", "nope"]), "--descriptor");
    let input = fixture("keypoints/example.json");
    assert_usage_error(
        &camloc(&[
            "reconstruct",
            "--input",
            input.to_str().unwrap(),
            "--camera",
            "oracle",
        ]),
        "--camera",
    );
    // In range, the same command gets past parsing and stops at the existing output (exit 1).
    assert_clean_failure(
        &train(&["--lambda", "0", "--dropout", "10"]),
        "already exists",
    );
    assert_eq!(std::fs::read_to_string(&existing).unwrap(), "mine");
}

/// A tiny labelled dataset made through the library from the project's mocap fixtures.
fn fixture_dataset(dir: &TempDir) -> String {
    use camloc::dataset::{GenerateConfig, Protocol, generate, load_mocap_folders};
    let (sequences, _) =
        load_mocap_folders(&[fixture("mocap")], &mut |_| {}, &mut |_, _, _| {}).unwrap();
    let mut config = GenerateConfig::new(Protocol::Jittered);
    config.seed = 7;
    let dataset = generate(&sequences, &config, &|_, _| {}).unwrap();
    assert!(dataset.samples.len() >= 24, "{}", dataset.samples.len());
    let path = dir.0.join("data.bin");
    dataset.save(&path, false).unwrap();
    path.to_string_lossy().into_owned()
}

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
        "--quiet",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(String::from_utf8_lossy(&out.stdout).starts_with("wrote "));
    let trained = camloc::CameraLocalizer::load(Path::new(model)).unwrap();
    assert_eq!(trained.descriptor().name(), "landmarks");
    assert_eq!(trained.training_info().lambda, 0.5);

    let out = camloc(&["evaluate", "--model", model, "--dataset", &data, "--json"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let e: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
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
    let text = camloc(&["evaluate", "--model", model, "--dataset", &data]);
    assert!(text.status.success());
    assert!(
        String::from_utf8_lossy(&text.stdout)
            .contains(&format!("accuracy:         {:.2}%", 100.0 * accuracy))
    );

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
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let poses: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let poses = poses.as_array().unwrap();
    assert_eq!(poses.len(), 3);
    for p in poses {
        assert_eq!(p["camera_mode"], "classified");
        let label = p["classified_label"].as_u64().unwrap();
        assert!((1..=12).contains(&label));
        assert_eq!(p["landmarks_m"].as_object().unwrap().len(), 15);
    }

    let out = camloc(&[
        "evaluate-reconstruction",
        "--model",
        model,
        "--dataset",
        &data,
        "--json",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(report.is_object(), "{report}");
}
