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

/// Runs camloc with `stdin` as standard input.
fn camloc_with_stdin(args: &[&str], stdin: &[u8]) -> Output {
    use std::io::Write;
    let mut child = Command::new(env!("CARGO_BIN_EXE_camloc"))
        .args(args)
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("the camloc binary runs");
    let mut pipe = child.stdin.take().unwrap();
    // A reader that stops early closes the pipe: not an error of the test.
    let _ = pipe.write_all(stdin);
    drop(pipe);
    child.wait_with_output().unwrap()
}

/// Asserts success and returns standard output.
fn success(out: &Output) -> String {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "stderr: {stderr}");
    String::from_utf8(out.stdout.clone()).unwrap()
}

/// The `label` of every line of `localize --jsonl` output, in order.
fn jsonl_labels(stdout: &str) -> Vec<u64> {
    stdout
        .lines()
        .map(|line| {
            let v: serde_json::Value = serde_json::from_str(line).unwrap();
            v["label"].as_u64().unwrap()
        })
        .collect()
}

/// The labels of the three poses of example.json.
fn example_labels() -> Vec<u64> {
    let example = fixture("keypoints/example.json");
    let out = camloc(&["localize", "--input", example.to_str().unwrap(), "--jsonl"]);
    let labels = jsonl_labels(&success(&out));
    assert_eq!(labels.len(), 3);
    labels
}

/// `--jsonl` writes one object per line; `--json` one array of the same objects; the text
/// output the same cameras.
#[test]
fn jsonl_and_json_stream_the_same_objects() {
    let example = fixture("keypoints/example.json");
    let example = example.to_str().unwrap();
    let jsonl = success(&camloc(&["localize", "--input", example, "--jsonl"]));
    let lines: Vec<serde_json::Value> = jsonl
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let array: serde_json::Value = serde_json::from_str(&success(&camloc(&[
        "localize", "--input", example, "--json",
    ])))
    .unwrap();
    assert_eq!(array.as_array().unwrap(), &lines);
    let text = success(&camloc(&["localize", "--input", example]));
    for line in &lines {
        let id = line["id"].as_str().unwrap();
        let header = format!("{id}: camera {:02},", line["label"].as_u64().unwrap());
        assert!(text.contains(&header), "{header} in {text}");
    }
    let usage = camloc(&["localize", "--input", example, "--json", "--jsonl"]);
    assert_eq!(usage.status.code(), Some(2));
}

/// Every sample format (made by camloc-keypoints' tests from the poses of example.json) gives
/// the labels of example.json through the command line, with the options it needs.
#[test]
fn every_sample_format_gives_the_example_labels() {
    let expected = example_labels();
    let samples = fixture("keypoints/samples");
    let s = |name: &str| samples.join(name).to_string_lossy().into_owned();
    let cases: Vec<Vec<String>> = vec![
        vec![s("camloc15.npy")],
        vec![s("camloc15.npy"), "--layout".into(), "camloc15".into()],
        vec![s("h36m17_scores.npy"), "--layout".into(), "h36m17".into()],
        vec![s("mediapipe.json"), "--image-size".into(), "640,480".into()],
        vec![s("mmpose.json"), "--format".into(), "mmpose".into()],
        vec![s("mpii.json")],
        vec![s("openpose")],
    ];
    for case in cases {
        let mut args = vec!["localize", "--jsonl", "--input"];
        args.extend(case.iter().map(String::as_str));
        let labels = jsonl_labels(&success(&camloc(&args)));
        assert_eq!(labels, expected, "{case:?}");
    }
    // MediaPipe without the image size: one clear error.
    assert_clean_failure(
        &camloc(&["localize", "--input", &s("mediapipe.json")]),
        "mediapipe.json",
    );
}

/// `-` reads standard input, in any format told from its content (a .npy array included).
#[test]
fn standard_input_is_read() {
    let expected = example_labels();
    let json = std::fs::read(fixture("keypoints/example.json")).unwrap();
    let out = camloc_with_stdin(&["localize", "--input", "-", "--jsonl"], &json);
    assert_eq!(jsonl_labels(&success(&out)), expected);
    let npy = std::fs::read(fixture("keypoints/samples/camloc15.npy")).unwrap();
    let out = camloc_with_stdin(&["localize", "--input", "-", "--jsonl"], &npy);
    assert_eq!(jsonl_labels(&success(&out)), expected);
    let out = camloc_with_stdin(&["localize", "--input", "-"], b"{\"poses\": []}");
    assert_clean_failure(&out, "no poses in standard input");
}

/// A folder is read in natural order, sub-folders only with --recursive; a bad file is
/// reported, the others are still localized, and the exit code is 1.
#[test]
fn folders_are_read_in_order_and_a_bad_file_does_not_stop_the_rest() {
    let dir = TempDir::new("folder");
    let example = std::fs::read_to_string(fixture("keypoints/example.json")).unwrap();
    dir.file("frame_10.json", &example);
    dir.file("frame_2.json", FIFTEEN);
    std::fs::create_dir(dir.0.join("sub")).unwrap();
    std::fs::write(dir.0.join("sub/more.json"), FIFTEEN).unwrap();
    let folder = dir.0.to_str().unwrap();
    let flat = success(&camloc(&["localize", "--input", folder, "--jsonl"]));
    let ids: Vec<String> = flat
        .lines()
        .map(|l| serde_json::from_str::<serde_json::Value>(l).unwrap()["source"].to_string())
        .collect();
    assert_eq!(ids.len(), 4, "{flat}");
    assert!(ids[0].contains("frame_2.json"), "{ids:?}");
    assert!(ids[1].contains("frame_10.json"), "{ids:?}");
    let deep = success(&camloc(&[
        "localize",
        "--input",
        folder,
        "--jsonl",
        "--recursive",
    ]));
    assert_eq!(deep.lines().count(), 5);
    dir.file("frame_5.json", "{\"poses\": [");
    let out = camloc(&["localize", "--input", folder, "--jsonl"]);
    assert_clean_failure(&out, "frame_5.json");
    let lines: Vec<serde_json::Value> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 5, "four poses and the bad file: {lines:?}");
    let errors: Vec<&serde_json::Value> =
        lines.iter().filter(|l| l.get("error").is_some()).collect();
    assert_eq!(errors.len(), 1);
    assert!(
        errors[0]["error"]
            .as_str()
            .unwrap()
            .contains("frame_5.json")
    );
    // An empty folder has no poses.
    let empty = TempDir::new("empty-folder");
    assert_clean_failure(
        &camloc(&["localize", "--input", empty.0.to_str().unwrap()]),
        "no poses in",
    );
}

/// A (0, 15, 2) float64 .npy array.
fn empty_npy() -> Vec<u8> {
    let header = "{'descr': '<f8', 'fortran_order': False, 'shape': (0, 15, 2), }";
    let mut header = header.to_owned();
    while !(10 + header.len() + 1).is_multiple_of(64) {
        header.push(' ');
    }
    header.push('\n');
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend_from_slice(&(header.len() as u16).to_le_bytes());
    bytes.extend_from_slice(header.as_bytes());
    bytes
}

/// Empty inputs follow one rule in every command: exit 1 with "no poses in INPUT".
#[test]
fn empty_inputs_are_an_error_in_every_command() {
    let dir = TempDir::new("empty");
    let npy = dir.0.join("empty.npy");
    std::fs::write(&npy, empty_npy()).unwrap();
    let inputs = [
        dir.file("poses.json", r#"{"poses": []}"#),
        dir.file("header.csv", "image,joint,x,y,visible\n"),
        dir.file("coco.json", "[]"),
        npy.to_string_lossy().into_owned(),
    ];
    let out_file = dir.0.join("out.npy");
    let out_file = out_file.to_str().unwrap();
    for input in &inputs {
        for args in [
            vec!["localize", "--input", input],
            vec!["localize", "--input", input, "--json"],
            vec!["reconstruct", "--input", input, "--jsonl"],
            vec![
                "convert", "--input", input, "--to", "npy", "--out", out_file,
            ],
        ] {
            let out = camloc(&args);
            assert_clean_failure(&out, &format!("no poses in {input}"));
            assert!(out.stdout.is_empty(), "{args:?}");
        }
    }
    assert!(!Path::new(out_file).exists());
    // A dataset without samples.
    let data = fixture_dataset(&dir);
    let mut dataset = camloc::dataset::Dataset::load(Path::new(&data)).unwrap();
    dataset.samples.clear();
    let empty = dir.0.join("empty.bin");
    dataset.save(&empty, false).unwrap();
    let empty = empty.to_str().unwrap();
    let model = dir.0.join("m.bin");
    let model = model.to_str().unwrap();
    camloc::CameraLocalizer::default_model()
        .unwrap()
        .save(Path::new(model), false)
        .unwrap();
    for args in [
        vec!["evaluate", "--model", model, "--dataset", empty],
        vec!["evaluate-reconstruction", "--dataset", empty],
        vec!["train", "--dataset", empty, "--out", out_file],
    ] {
        assert_clean_failure(&camloc(&args), &format!("no poses in {empty}"));
    }
}

/// Several SVGs are all written or none: an existing one (without --force) or one that cannot
/// be replaced (a folder, even with --force) stops the run before any is written, and a failed
/// write to standard output removes them all.
#[test]
fn multi_file_svg_output_is_all_or_nothing() {
    let dir = TempDir::new("all-or-nothing");
    let example = fixture("keypoints/example.json");
    let example = example.to_str().unwrap();
    let svg = dir.0.join("view.svg");
    let svg = svg.to_str().unwrap();
    let listing = || {
        let mut names: Vec<String> = std::fs::read_dir(&dir.0)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    };
    std::fs::create_dir(dir.0.join("view-002.svg")).unwrap();
    for force in [false, true] {
        let mut args = vec!["localize", "--input", example, "--svg", svg];
        if force {
            args.push("--force");
        }
        let out = camloc(&args);
        assert_eq!(out.status.code(), Some(1), "{force}");
        assert_eq!(listing(), ["view-002.svg"], "{force}");
    }
    std::fs::remove_dir(dir.0.join("view-002.svg")).unwrap();
    // Standard output on a full device: the error is reported and no file stays.
    let full = std::fs::OpenOptions::new().write(true).open("/dev/full");
    if let Ok(full) = full {
        for command in ["localize", "reconstruct"] {
            let out = Command::new(env!("CARGO_BIN_EXE_camloc"))
                .args([command, "--input", example, "--svg", svg])
                .stdout(full.try_clone().unwrap())
                .output()
                .unwrap();
            assert_clean_failure(&out, "cannot write to standard output");
            assert!(listing().is_empty(), "{command}: {:?}", listing());
        }
    }
    let out = camloc(&["localize", "--input", example, "--svg", svg]);
    success(&out);
    assert_eq!(listing(), ["view-001.svg", "view-002.svg", "view-003.svg"]);
    // One pose: the file is not numbered.
    let one = dir.file("one.json", FIFTEEN);
    let single = dir.0.join("single.svg");
    success(&camloc(&[
        "localize",
        "--input",
        &one,
        "--svg",
        single.to_str().unwrap(),
    ]));
    assert!(single.is_file());
}

/// A reader that goes away (`camloc ... | head`) ends the run normally.
#[test]
fn a_closed_pipe_is_a_normal_end() {
    let example = fixture("keypoints/example.json");
    let mut child = Command::new(env!("CARGO_BIN_EXE_camloc"))
        .args(["localize", "--input", example.to_str().unwrap()])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// `convert` writes camloc JSON and .npy that read back to the same labels, and does not
/// overwrite without --force.
#[test]
fn convert_writes_camloc_formats_that_give_the_same_labels() {
    let expected = example_labels();
    let dir = TempDir::new("convert");
    let h36m = fixture("keypoints/samples/h36m17_scores.npy");
    let h36m = h36m.to_str().unwrap();
    for (to, name) in [("camloc", "out.json"), ("npy", "out.npy")] {
        let target = dir.0.join(name);
        let target = target.to_str().unwrap();
        let args = [
            "convert", "--input", h36m, "--layout", "h36m17", "--to", to, "--out", target,
        ];
        let stdout = success(&camloc(&args));
        assert!(stdout.contains("3 poses"), "{stdout}");
        let labels = jsonl_labels(&success(&camloc(&[
            "localize", "--input", target, "--jsonl",
        ])));
        assert_eq!(labels, expected, "{to}");
        std::fs::write(target, "mine").unwrap();
        assert_clean_failure(&camloc(&args), "already exists");
        assert_eq!(std::fs::read_to_string(target).unwrap(), "mine");
        success(&camloc(&[&args[..], &["--force"]].concat()));
        assert_ne!(std::fs::read(target).unwrap(), b"mine");
    }
}

/// `reconstruct --npy` writes (N, 15, 3) float64 metres equal to the JSON output's landmarks,
/// NaN rows for poses that could not be reconstructed.
#[test]
fn reconstruct_writes_the_3d_poses_as_npy() {
    let dir = TempDir::new("npy3");
    let example = fixture("keypoints/example.json");
    let partial = fixture("keypoints/partial.json");
    let npy = dir.0.join("poses3.npy");
    let out = camloc(&[
        "reconstruct",
        "--input",
        example.to_str().unwrap(),
        "--jsonl",
        "--npy",
        npy.to_str().unwrap(),
    ]);
    let stdout = success(&out);
    let poses =
        camloc::keypoints::read_npy_poses3(std::fs::File::open(&npy).unwrap(), "poses3").unwrap();
    assert_eq!(poses.len(), 3);
    for (line, pose) in stdout.lines().zip(&poses) {
        let v: serde_json::Value = serde_json::from_str(line).unwrap();
        for l in camloc::Landmark::ALL {
            let json: Vec<f64> = v["landmarks_m"][l.name()]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect();
            assert_eq!(json, pose.points[l.index()].to_vec(), "{}", l.name());
        }
    }
    // A pose that cannot be reconstructed (missing landmarks) is a row of NaN.
    let npy = dir.0.join("partial3.npy");
    let out = camloc(&[
        "reconstruct",
        "--input",
        partial.to_str().unwrap(),
        "--npy",
        npy.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(1));
    let bytes = std::fs::read(&npy).unwrap();
    let header_end = bytes.iter().position(|&b| b == b'\n').unwrap() + 1;
    let header = String::from_utf8_lossy(&bytes[..header_end]).into_owned();
    let rows = (bytes.len() - header_end) / (15 * 3 * 8);
    assert!(header.contains(&format!("({rows}, 15, 3")), "{header}");
    let values: Vec<f64> = bytes[header_end..]
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
        .collect();
    let nan_rows = values
        .chunks_exact(45)
        .filter(|row| row.iter().all(|v| v.is_nan()))
        .count();
    let failed = String::from_utf8_lossy(&out.stderr)
        .lines()
        .filter(|l| l.starts_with("camloc: error:"))
        .count();
    assert!(
        nan_rows >= 1 && nan_rows == failed,
        "{nan_rows} NaN rows, {failed} errors"
    );
}

/// The new reader options are checked when the command line is parsed (exit 2).
#[test]
fn reader_options_are_checked_at_parse_time() {
    let example = fixture("keypoints/example.json");
    let example = example.to_str().unwrap();
    for (option, bad) in [
        ("--min-score", "-1"),
        ("--min-score", "NaN"),
        ("--image-size", "640"),
        ("--image-size", "0,480"),
        ("--layout", "coco18"),
        ("--format", "yaml"),
    ] {
        let out = camloc(&["localize", "--input", example, option, bad]);
        assert_usage_error(&out, option);
    }
}

/// An output path that is a symbolic link is an existing file: refused without --force,
/// replaced itself (its target untouched) with it; a device is never replaced.
#[cfg(unix)]
#[test]
fn symlinks_and_devices_at_output_paths() {
    let dir = TempDir::new("links");
    let input = dir.file("p.json", FIFTEEN);
    let precious = dir.file("precious.txt", "mine");
    let link = dir.0.join("view.svg");
    std::os::unix::fs::symlink(&precious, &link).unwrap();
    let link = link.to_str().unwrap();
    let out = camloc(&["localize", "--input", &input, "--svg", link]);
    assert_clean_failure(&out, "already exists");
    success(&camloc(&[
        "localize", "--input", &input, "--svg", link, "--force",
    ]));
    assert_eq!(std::fs::read_to_string(&precious).unwrap(), "mine");
    let meta = std::fs::symlink_metadata(link).unwrap();
    assert!(meta.is_file(), "the link itself was replaced");
    assert!(std::fs::read_to_string(link).unwrap().starts_with("<svg"));
    if Path::new("/dev/null").exists() {
        let out = camloc(&[
            "localize",
            "--input",
            &input,
            "--svg",
            "/dev/null",
            "--force",
        ]);
        assert_clean_failure(&out, "not a regular file");
    }
}
