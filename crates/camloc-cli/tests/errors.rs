//! The `camloc` binary answers bad input with a non-zero exit and one clear line, never a
//! panic; out-of-range options are usage errors; empty inputs are one rule.

use camloc::store::Persist;
use std::path::{Path, PathBuf};

mod common;
use common::*;

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
    // 7 landmarks: the neck is missing and cannot be derived without both shoulders, and
    // too few landmarks are left to fill the torso in.
    let seven = dir.file(
        "seven.json",
        &FIFTEEN
            .replace(r#""neck": [100, 140],"#, "")
            .replace(r#""left_ankle": [113, 320],"#, "")
            .replace(r#""head": [100, 115],"#, "")
            .replace(r#""left_shoulder": [118, 145],"#, "")
            .replace(r#""left_elbow": [125, 175], "left_wrist": [128, 200],"#, "")
            .replace(r#""right_elbow": [75, 175], "right_wrist": [72, 200]"#, "")
            .replace(
                r#""right_shoulder": [82, 145], "#,
                r#""right_shoulder": [82, 145]"#,
            ),
    );
    let refused = camloc(&["localize", "--input", &seven]);
    assert_clean_failure(&refused, "neck");
    assert!(String::from_utf8_lossy(&refused.stderr).contains("7 landmarks present"));
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
    for bad in ["-1", "NaN", "inf", "-inf", "x", "1e308", "1.1e12"] {
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
    let out_model = dir.0.join("trained.bin").to_string_lossy().into_owned();
    camloc::CameraLocalizer::default_model()
        .unwrap()
        .save(Path::new(model), false)
        .unwrap();
    for args in [
        vec!["evaluate", "--model", model, "--dataset", empty],
        vec!["evaluate-reconstruction", "--dataset", empty],
        vec!["train", "--dataset", empty, "--out", &out_model],
    ] {
        assert_clean_failure(&camloc(&args), &format!("no poses in {empty}"));
    }
    // Samples none of which can be measured (true 3D poses of 1e300 m, finite, so valid):
    // an error that says so, not a table of failures with exit 0.
    let mut far = camloc::dataset::Dataset::load(Path::new(&data)).unwrap();
    for sample in &mut far.samples {
        for point in &mut sample.pose3.points {
            point[0] = 1e300 * (point[0] + 1.0);
        }
    }
    let far_path = dir.0.join("far.bin");
    far.save(&far_path, false).unwrap();
    let out = camloc(&[
        "evaluate-reconstruction",
        "-q",
        "--dataset",
        far_path.to_str().unwrap(),
    ]);
    assert_clean_failure(&out, "cannot be compared with its true 3D pose");
    assert!(out.stdout.is_empty());
    // No complete sample at all (every sample with a landmark missing): said too.
    let mut partial = camloc::dataset::Dataset::load(Path::new(&data)).unwrap();
    for sample in &mut partial.samples {
        sample.missing_mask = 1 << 3;
    }
    let partial_path = dir.0.join("partial.bin");
    partial.save(&partial_path, false).unwrap();
    let partial_path = partial_path.to_str().unwrap();
    let out = camloc(&["evaluate-reconstruction", "-q", "--dataset", partial_path]);
    assert_clean_failure(&out, "samples is complete");
}

/// A folder whose poses are all in sub-folders has no poses without --recursive, and the
/// message says so; with it, they are read.
#[test]
fn a_folder_of_sub_folders_points_to_recursive() {
    let dir = TempDir::new("sub-folders");
    std::fs::create_dir(dir.0.join("clip")).unwrap();
    std::fs::copy(
        fixture("keypoints/example.json"),
        dir.0.join("clip").join("poses.json"),
    )
    .unwrap();
    let folder = dir.0.to_string_lossy().into_owned();
    let out = camloc(&["localize", "--input", &folder]);
    assert_clean_failure(&out, "(its sub-folders are read with --recursive)");
    success(&camloc(&["localize", "--input", &folder, "--recursive"]));
    // A folder without sub-folders gets no hint.
    let empty = TempDir::new("no-sub-folders");
    let out = camloc(&["localize", "--input", &empty.0.to_string_lossy()]);
    assert!(!String::from_utf8_lossy(&out.stderr).contains("--recursive"));
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
    // Names in any case, as Python takes them.
    let out = camloc(&[
        "localize", "--input", example, "--format", "CAMLOC", "--layout", "Camloc15", "-q",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// A threshold that empties every pose (scores from 0 to 1, `--min-score 30`) is asked about
/// in the run's summary, as when a sequence's every frame is empty; a threshold on the
/// input's scale fails no pose.
#[test]
fn every_pose_emptied_by_min_score_asks_about_its_scale() {
    let mmpose = fixture("keypoints/samples/mmpose.json");
    let mmpose = mmpose.to_str().unwrap();
    let hint = "is --min-score on the scale of the input's scores, or above all of them?";
    for command in ["localize", "reconstruct"] {
        let out = camloc(&[command, "--input", mmpose, "--min-score", "30", "-q"]);
        assert_clean_failure(&out, hint);
        let out = camloc(&[command, "--input", mmpose, "--min-score", "0.3", "-q"]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{stderr}");
        assert!(!stderr.contains(hint), "{stderr}");
    }
}

/// A 14-joint array in camloc's order (the pelvis left out) read as LSP-14, a simulated
/// animator's mistake, is reconstructed with most joints bent past the limits, and a warning
/// says so, alone and as a sequence; the same poses in the right order say nothing.
#[test]
fn landmarks_in_another_order_than_the_layout_are_warned_of() {
    let dir = TempDir::new("order");
    let example = dir.0.join("example.npy");
    success(&camloc(&[
        "convert",
        "--input",
        fixture("keypoints/example.json").to_str().unwrap(),
        "--to",
        "npy",
        "--out",
        example.to_str().unwrap(),
    ]));
    let (_, values) = read_npy_f64(&example);
    // 12 poses: the 3 examples 4 times, each coordinate moved by up to 2 px.
    let poses: Vec<f64> = (0..4)
        .flat_map(|copy| {
            values
                .iter()
                .enumerate()
                .map(move |(i, v)| v + 2.0 * ((i * 7 + copy * 13) as f64).sin())
        })
        .collect();
    let write = |name: &str, joints: usize, values: Vec<f64>| {
        let mut bytes = npy_head(&format!(
            "{{'descr': '<f8', 'fortran_order': False, 'shape': (12, {joints}, 2), }}"
        ));
        values.iter().for_each(|v| bytes.extend(v.to_le_bytes()));
        let path = dir.0.join(name);
        std::fs::write(&path, bytes).unwrap();
        path.to_string_lossy().into_owned()
    };
    // camloc's landmark 0 is the pelvis.
    let without_pelvis: Vec<f64> = poses
        .chunks_exact(30)
        .flat_map(|pose| pose[2..].to_vec())
        .collect();
    let wrong = write("wrong.npy", 14, without_pelvis);
    let right = write("right.npy", 15, poses);
    let said = "of 12 poses were reconstructed with joints bent past the limits";
    for extra in [&[][..], &["--sequence"]] {
        let mut wrong_args = vec!["reconstruct", "--input", &wrong, "--layout", "lsp14", "-q"];
        wrong_args.extend(extra);
        let warned = warning_line(&wrong_args, said).expect("no warning");
        assert!(warned.contains("--layout names the layout"), "{warned}");
        let mut right_args = vec!["reconstruct", "--input", &right, "-q"];
        right_args.extend(extra);
        assert_eq!(warning_line(&right_args, said), None);
    }
}
