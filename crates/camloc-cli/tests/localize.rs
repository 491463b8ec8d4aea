//! `camloc localize`: text, JSON and JSON lines, every input format, standard input, folders
//! and closed pipes.

use std::process::Command;

mod common;
use common::*;

#[path = "common/npz.rs"]
mod npz_reader;

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
    let poses: Vec<&str> = stdout.lines().filter(|l| !l.starts_with(' ')).collect();
    assert_eq!(poses.len(), 3, "{stdout}");
    // An unsure answer (probability below 0.9) names the runner-up camera, from the same
    // probabilities the JSON output gives, with its angles (which tell apart the cameras of
    // finer spheres); the single pose is such an answer.
    let mut runners_up = 0;
    for input in ["keypoints/example.json", "keypoints/single_pose.json"] {
        let input = fixture(input);
        let input = input.to_str().unwrap();
        let text = success(&camloc(&["localize", "--input", input]));
        let json = success(&camloc(&["localize", "--input", input, "--json"]));
        let objects: serde_json::Value = serde_json::from_str(&json).unwrap();
        // Each pose's text: its first line and the indented lines after it.
        let mut blocks: Vec<Vec<&str>> = Vec::new();
        for line in text.lines() {
            match blocks.last_mut() {
                Some(block) if line.starts_with(' ') => block.push(line),
                _ => blocks.push(vec![line]),
            }
        }
        for (object, block) in objects.as_array().unwrap().iter().zip(&blocks) {
            let p = object["probability"].as_f64().unwrap();
            let top = format!("{:02}", object["label"].as_u64().unwrap());
            let runner_up = object["probabilities"]
                .as_object()
                .unwrap()
                .iter()
                .filter(|(k, _)| **k != top)
                .max_by(|a, b| a.1.as_f64().unwrap().total_cmp(&b.1.as_f64().unwrap()))
                .map(|(k, _)| k.clone())
                .unwrap();
            let named = format!("  next most probable: camera {runner_up}, ");
            let line = block.iter().find(|l| l.starts_with(&named));
            assert_eq!(line.is_some(), p < 0.9, "{block:?}");
            if let Some(line) = line {
                assert!(line.contains(" side (azimuth ") && line.contains(" deg, elevation "));
                runners_up += 1;
            }
        }
    }
    assert!(runners_up > 0, "no unsure answer was checked");
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
        vec![s("yolo"), "--image-size".into(), "640,480".into()],
    ];
    for case in cases {
        let mut args = vec!["localize", "--jsonl", "--input"];
        args.extend(case.iter().map(String::as_str));
        let labels = jsonl_labels(&success(&camloc(&args)));
        assert_eq!(labels, expected, "{case:?}");
    }
    // MediaPipe and YOLO without the image size: a clear error.
    assert_clean_failure(
        &camloc(&["localize", "--input", &s("mediapipe.json")]),
        "mediapipe.json",
    );
    assert_clean_failure(
        &camloc(&["localize", "--input", &s("yolo/clip_0.txt")]),
        "clip_0.txt: YOLO coordinates are normalised",
    );
    // A folder: said once, not once a file.
    let folder = camloc(&["localize", "--input", &s("yolo")]);
    let stderr = String::from_utf8_lossy(&folder.stderr);
    assert_eq!(
        stderr.matches("coordinates are normalised").count(),
        1,
        "{stderr}"
    );
    assert_eq!(folder.status.code(), Some(1), "{stderr}");
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

/// A pose without its pelvis and right hip (which the descriptor's torso needs) is localized
/// with its torso filled in from the embedded basis, and its output names what was missing; a
/// pose with 7 landmarks is refused with that count; the drawing's caption names what was
/// missing; the `--html` page reconstructs the poses with missing landmarks in 3D too (filled
/// in with the localized camera).
#[test]
fn localize_fills_in_a_missing_torso() {
    let dir = TempDir::new("no-torso");
    let mut input: serde_json::Value = serde_json::from_str(FIFTEEN).unwrap();
    let mut partial: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(fixture("keypoints/partial.json")).unwrap())
            .unwrap();
    let poses = input["poses"].as_array_mut().unwrap();
    for name in ["pelvis", "right_hip"] {
        poses[0]["landmarks"][name] = serde_json::Value::Null;
    }
    poses.append(partial["poses"].as_array_mut().unwrap());
    let path = dir.file("poses.json", &input.to_string());
    let page = dir.0.join("page.html");
    let svg = dir.0.join("pose.svg");
    let out = camloc(&[
        "localize",
        "--input",
        &path,
        "--jsonl",
        "--html",
        page.to_str().unwrap(),
        "--svg",
        svg.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(1), "the third pose has 7 landmarks");
    let lines: Vec<serde_json::Value> = String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 3);
    assert!((1..=12).contains(&lines[0]["label"].as_u64().unwrap()));
    assert_eq!(
        lines[0]["missing"],
        serde_json::json!(["pelvis", "right_hip"])
    );
    let error = lines[2]["error"].as_str().unwrap();
    assert!(
        error.contains("pelvis") && error.contains("7 landmarks present"),
        "{error}"
    );
    let drawn = std::fs::read_to_string(dir.0.join("pose-001.svg")).unwrap();
    assert!(drawn.contains("missing: pelvis, right_hip"), "{drawn}");
    let html = std::fs::read_to_string(&page).unwrap();
    let start = html.find(r#"id="data">"#).unwrap() + 10;
    let end = start + html[start..].find("</script>").unwrap();
    let data: serde_json::Value = serde_json::from_str(&html[start..end]).unwrap();
    for (i, frame) in data["frames"].as_array().unwrap().iter().enumerate() {
        assert_eq!(frame["pose"].is_array(), i < 2, "frame {i}: {frame}");
    }
}

/// The probabilities of each pose of a JSON-lines output.
fn jsonl_probabilities(stdout: &str) -> Vec<Vec<f64>> {
    stdout
        .lines()
        .map(|line| {
            let v: serde_json::Value = serde_json::from_str(line).unwrap();
            // An object keyed "01" to "12": in camera order.
            v["probabilities"]
                .as_object()
                .unwrap()
                .values()
                .map(|p| p.as_f64().unwrap())
                .collect()
        })
        .collect()
}

/// A camloc JSON document of the example poses repeated `copies` times (ids made unique).
fn repeated_example(copies: usize) -> (String, Vec<camloc::PartialPose2>) {
    let text = std::fs::read_to_string(fixture("keypoints/example.json")).unwrap();
    let mut doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    let poses = doc["poses"].as_array().unwrap().clone();
    let mut all = Vec::new();
    for c in 0..copies {
        for pose in &poses {
            let mut pose = pose.clone();
            pose["id"] = serde_json::json!(format!("{}-{c}", pose["id"].as_str().unwrap()));
            all.push(pose);
        }
    }
    doc["poses"] = serde_json::Value::Array(all);
    let records = camloc::keypoints::read_keypoints(
        fixture("keypoints/example.json"),
        None,
        &camloc::keypoints::ReadOptions::default(),
    )
    .unwrap();
    let poses = (0..copies)
        .flat_map(|_| records.iter().map(|r| r.pose))
        .collect();
    (doc.to_string(), poses)
}

/// `--camera-height from-input` (the default) localizes every pose under the shares of the
/// camera heights the library estimates from the input's first poses: from a file, from
/// standard input and from a named pipe alike (each read once); `any` localizes each pose
/// on its own, as the library's default does. Three poses are read near eye level.
#[test]
fn the_default_estimates_the_camera_heights_from_the_input() {
    use camloc::{CameraHeight, CameraLocalizer};
    let dir = TempDir::new("from-input");
    let copies = 34;
    let (text, poses) = repeated_example(copies);
    let path = dir.file("many.json", &text);
    let any = CameraLocalizer::default_model().unwrap();
    let estimate = any.estimate_height_shares(&poses);
    assert_eq!(estimate.read, poses.len());
    let estimated = any.clone().with_camera_height(estimate.camera_height());
    assert!(matches!(estimate.camera_height(), CameraHeight::Shares(_)));
    let run = |input: &str, args: &[&str]| {
        let mut all = vec!["localize", "--input", input, "--jsonl"];
        all.extend_from_slice(args);
        jsonl_probabilities(&success(&camloc(&all)))
    };
    let close = |got: &[Vec<f64>], localizer: &CameraLocalizer| {
        assert_eq!(got.len(), poses.len());
        for (row, pose) in got.iter().zip(&poses) {
            let want = localizer.localize_partial(pose).unwrap().probabilities;
            for (g, w) in row.iter().zip(&want) {
                // JSON keeps 17 significant digits.
                assert!((g - w).abs() < 1e-12, "{g} against {w}");
            }
        }
    };
    let default = run(&path, &[]);
    close(&default, &estimated);
    // `--npz` records the shares the run used.
    let npz = dir.0.join("many.npz");
    success(&camloc(&[
        "localize",
        "--input",
        &path,
        "--npz",
        npz.to_str().unwrap(),
    ]));
    let archive = npz_reader::Npz::parse(&std::fs::read(&npz).unwrap());
    assert!(archive.names().contains(&"camera_height_shares"));
    assert_eq!(archive.descr("camera_height_shares"), "'<f8'");
    let (_, shares) = archive.array::<f64>("camera_height_shares");
    let want = estimate.shares.unwrap();
    assert_eq!(shares, [want.lower, want.middle, want.upper]);
    let (_, elevations) = archive.array::<f64>("camera_height_elevations_deg");
    let want_elevations = want.elevations_deg();
    assert!(want_elevations[1].is_some(), "{want:?}");
    for (got, want) in elevations.iter().zip(want_elevations) {
        match want {
            Some(e) => assert_eq!(*got, e),
            None => assert!(got.is_nan(), "{got}"),
        }
    }
    assert_eq!(
        archive.array::<f64>("camera_height_views").1,
        [estimate.views]
    );
    let alone = run(&path, &["--camera-height", "any"]);
    close(&alone, &any);
    assert_eq!(default, run(&path, &["--camera-height", "from-input"]));
    // The estimate moved the probabilities: the poses are not read each on its own.
    assert!(
        default
            .iter()
            .zip(&alone)
            .any(|(d, a)| d.iter().zip(a).any(|(x, y)| (x - y).abs() > 1e-6))
    );
    let stdin = camloc_with_stdin(&["localize", "--input", "-", "--jsonl"], text.as_bytes());
    assert_eq!(jsonl_probabilities(&success(&stdin)), default);
    // A named pipe is read once, as standard input is.
    let fifo = dir.0.join("pipe.json");
    let made = Command::new("mkfifo").arg(&fifo).status();
    if made.is_ok_and(|s| s.success()) {
        let writer = {
            let (fifo, text) = (fifo.clone(), text.clone());
            std::thread::spawn(move || std::fs::write(fifo, text).unwrap())
        };
        assert_eq!(run(fifo.to_str().unwrap(), &[]), default);
        writer.join().unwrap();
    }
    // Three poses are worth at most three views against the estimate's views at eye level:
    // their shares move from eye level's by at most their weight among them.
    let example = fixture("keypoints/example.json");
    let three: Vec<camloc::PartialPose2> = camloc::keypoints::read_keypoints(
        &example,
        None,
        &camloc::keypoints::ReadOptions::default(),
    )
    .unwrap()
    .iter()
    .map(|r| r.pose)
    .collect();
    let few = any.estimate_height_shares(&three);
    let centre = camloc::eye_level_shares(&any.model_height_shares());
    assert!((1.0..=3.0).contains(&few.views), "{few:?}");
    let most = few.views / (few.views + camloc::HEIGHT_SHARE_PSEUDO_VIEWS);
    for (a, b) in few.shares.unwrap().to_array().iter().zip(centre.to_array()) {
        assert!((a - b).abs() <= most, "{few:?} against {centre:?}");
    }
    let path = example.to_str().unwrap();
    assert_ne!(run(path, &[]), run(path, &["--camera-height", "any"]));
}

/// With the camera's intrinsics each pose is localized as the camera aimed at it would see it
/// (`CameraLocalizer::with_intrinsics`): the same as the library gives, different from the
/// pose as drawn when it lies far from the principal point, and unchanged without a principal
/// point (the centre of each pose's box).
#[test]
fn a_known_camera_aims_at_each_pose() {
    use camloc::keypoints::{ReadOptions, read_keypoints};
    use camloc::reconstruct::Intrinsics;
    let input = fixture("keypoints/example.json");
    let path = input.to_str().unwrap();
    let probabilities = |extra: &[&str]| -> Vec<serde_json::Value> {
        let mut args = vec![
            "localize",
            "--input",
            path,
            "--json",
            "--camera-height",
            "any",
        ];
        args.extend(extra);
        let out = camloc(&args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let objects: Vec<serde_json::Value> = serde_json::from_slice(&out.stdout).unwrap();
        objects
            .into_iter()
            .map(|o| o["probabilities"].clone())
            .collect()
    };
    let plain = probabilities(&[]);
    assert_eq!(probabilities(&["--focal-px", "500"]), plain);
    let aimed = probabilities(&["--focal-px", "500", "--principal-point", "-400,-300"]);
    assert_ne!(aimed, plain);
    let localizer = camloc::CameraLocalizer::default_model()
        .unwrap()
        .with_intrinsics(Some(Intrinsics {
            focal_px: 500.0,
            principal_point: Some([-400.0, -300.0]),
        }))
        .unwrap();
    let records = read_keypoints(&input, None, &ReadOptions::default()).unwrap();
    for (record, cli) in records.iter().zip(&aimed) {
        let own = localizer.localize_partial(&record.pose).unwrap();
        for (k, p) in own.probabilities.iter().enumerate() {
            let given = cli[format!("{:02}", k + 1)].as_f64().unwrap();
            assert!((given - p).abs() < 1e-12);
        }
    }
    let out = camloc(&["localize", "--input", path, "--principal-point", "1,2"]);
    assert_eq!(out.status.code(), Some(2));
    // A focal length alone changes nothing, and says so.
    let warning = "--focal-px without --principal-point or --image-size changes no localization";
    let stderr = |extra: &[&str]| {
        let out = camloc(&[&["localize", "--input", path, "-q"], extra].concat());
        String::from_utf8(out.stderr).unwrap()
    };
    assert!(stderr(&["--focal-px", "500"]).contains(warning));
    assert!(!stderr(&["--focal-px", "500", "--image-size", "640,480"]).contains(warning));
    assert!(!stderr(&["--focal-px", "500", "--principal-point", "1,2"]).contains(warning));
}

/// The keypoints may be the command's one argument, as ripgrep's paths are: the same answer as
/// `--input`; both at once, or neither, is a usage error (exit 2).
#[test]
fn the_input_may_be_given_as_the_argument() {
    let example = fixture("keypoints/example.json");
    let example = example.to_str().unwrap();
    for command in ["localize", "reconstruct"] {
        let flag = camloc(&[command, "-q", "--json", "--input", example]);
        let argument = camloc(&[command, "-q", "--json", example]);
        assert!(flag.status.success(), "{command}");
        assert_eq!(flag.stdout, argument.stdout, "{command}");
        let both = camloc(&[command, "--input", example, example]);
        assert_eq!(both.status.code(), Some(2), "{command}");
        let neither = camloc(&[command]);
        assert_eq!(neither.status.code(), Some(2), "{command}");
        assert!(
            String::from_utf8_lossy(&neither.stderr).contains("<--input <FILE|DIR|->|INPUT>"),
            "{command}"
        );
    }
}

/// A pose of a pelvis and a neck is localized (its camera rests on them) with a warning;
/// `reconstruct` refuses it.
#[test]
fn a_pose_of_too_few_landmarks_is_warned_of() {
    let dir = TempDir::new("few");
    let input = dir.file(
        "two.json",
        r#"{"poses":[{"landmarks":{"pelvis":[100,200],"neck":[100,100]}}]}"#,
    );
    let out = camloc(&["localize", &input]);
    assert!(out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("1 of the 1 pose(s) have a torso but fewer than 8 of the 15 landmarks"),
        "{stderr}"
    );
    let full = camloc(&[
        "localize",
        fixture("keypoints/example.json").to_str().unwrap(),
    ]);
    assert!(!String::from_utf8_lossy(&full.stderr).contains("fewer than 8"));
}

/// At `--min-score 0` (the default) a detector's output with weakly scored joints is read as
/// detected, and `localize` and `reconstruct` say so with the share; at `--min-score 0.3`, or
/// for the same detections scored strongly, nothing is said.
#[test]
fn weakly_scored_joints_at_the_default_minimum_are_said() {
    let dir = TempDir::new("weak-scores");
    let strong = std::fs::read_to_string(fixture("keypoints/tiny_coco_results.json")).unwrap();
    // The first detection's last joint (right ankle) scored 0.1.
    let weak = strong.replacen("300.1, 411.0, 0.9", "300.1, 411.0, 0.1", 1);
    assert_ne!(weak, strong);
    let weak = dir.file("weak.json", &weak);
    let strong = dir.file("strong.json", &strong);
    let warning = |args: &[&str]| warning_line(args, "score below 0.3");
    // In a folder, a file that cannot be read (first, in natural order) is left out of the
    // count, not the end of it.
    let folder = dir.0.join("folder");
    std::fs::create_dir(&folder).unwrap();
    std::fs::write(folder.join("0_broken.json"), r#"{"poses": ["#).unwrap();
    std::fs::copy(&weak, folder.join("1_weak.json")).unwrap();
    let out = camloc(&["localize", folder.to_str().unwrap(), "-q"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("0_broken.json"), "{stderr}");
    assert!(stderr.contains("score below 0.3"), "{stderr}");
    for command in ["localize", "reconstruct"] {
        let said = warning(&[command, &weak, "-q"]).expect("no warning of weak scores");
        assert!(said.contains("1 of the "), "{said}");
        assert!(said.contains("--min-score 0.3"), "{said}");
        assert_eq!(warning(&[command, &weak, "-q", "--min-score", "0.3"]), None);
        assert_eq!(warning(&[command, &strong, "-q"]), None);
    }
    // The same weak joint in an export that writes scores of 0-100: said at its scale.
    let percent = std::fs::read_to_string(&weak)
        .unwrap()
        .replace(", 0.9", ", 90.0")
        .replace(", 0.1]", ", 10.0]");
    let percent = dir.file("percent.json", &percent);
    let said = warning_line(&["localize", &percent, "-q"], "score below 30")
        .expect("no warning of weak scores of 0-100");
    assert!(said.contains("--min-score 30"), "{said}");
}

/// Pixel keypoints outside the image of `--image-size` (a portrait video's size given
/// landscape, which puts the principal point off) are warned of; the right size is not.
#[test]
fn keypoints_outside_the_given_image_are_said() {
    let example = fixture("keypoints/example.json");
    let example = example.to_str().unwrap();
    // The example's three people span u = 255 to 380 px and v = 120 to 412 px, each reaching
    // below v = 382: past an 800 x 364 image, all within a 364 x 800 one.
    for command in ["localize", "reconstruct"] {
        let said = |size: &str| {
            let out = camloc(&[
                command,
                "--input",
                example,
                "--focal-px",
                "800",
                "--image-size",
                size,
                "-q",
            ]);
            let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
            assert!(out.status.success(), "{stderr}");
            stderr.contains("image of --image-size")
        };
        assert!(said("800,364"));
        assert!(!said("364,800"));
    }
}
