//! `camloc localize --npz`: the archive read back (zip and `.npy` entries checked byte by byte)
//! holds the values of the JSON lines of the same run; existing files are not replaced without
//! `--force`.

use camloc::skeleton::{Landmark, NUM_LANDMARKS};
use serde_json::Value;

mod common;
use common::*;

#[path = "common/npz.rs"]
mod npz_reader;
use npz_reader::Npz;

/// The arrays of an archive, in the order they are written, with their NumPy types.
const ARRAYS: [(&str, &str); 16] = [
    ("label", "'<u2'"),
    ("folded_label", "'<u2'"),
    ("probabilities", "'<f8'"),
    ("azimuth_deg", "'<f8'"),
    ("elevation_deg", "'<f8'"),
    ("uncertainty_deg", "'<f8'"),
    ("failed", "'|b1'"),
    ("missing", "'|b1'"),
    ("derived", "'|b1'"),
    ("frame", "'<i8'"),
    ("person", "'<i8'"),
    ("id_utf8", "'|u1'"),
    ("id_end", "'<u8'"),
    ("camera_height_shares", "'<f8'"),
    ("camera_height_elevations_deg", "'<f8'"),
    ("camera_height_views", "'<f8'"),
];

/// `x` as it reads back from the JSON text serde_json writes for it: equal to a number parsed
/// from the JSON output exactly when both are the same `f64` (serde_json's float parsing is not
/// always correctly rounded, so the two sides go through the same parser).
fn via_json(x: f64) -> f64 {
    serde_json::from_str(&serde_json::to_string(&x).unwrap()).unwrap()
}

/// The JSON number `v`, or NaN for an absent field.
fn number(v: &Value) -> f64 {
    v.as_f64().unwrap_or(f64::NAN)
}

fn same(npz: f64, json: &Value) -> bool {
    let json = number(json);
    (npz.is_nan() && json.is_nan()) || via_json(npz) == json
}

/// Landmark names as flags in camloc15 order.
fn flags(names: &Value) -> Vec<bool> {
    let mut flags = vec![false; NUM_LANDMARKS];
    for name in names.as_array().unwrap() {
        flags[Landmark::from_name(name.as_str().unwrap()).unwrap().index()] = true;
    }
    flags
}

/// Runs `localize --input INPUT --jsonl --npz OUT` and checks every row of the archive against
/// the JSON line of the same pose; returns the number of poses and of failed ones.
fn check_against_json(input: &str, out: &std::path::Path) -> (usize, usize) {
    let run = camloc(&[
        "localize",
        "--input",
        input,
        "--jsonl",
        "--npz",
        out.to_str().unwrap(),
    ]);
    assert!(
        matches!(run.status.code(), Some(0 | 1)),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let lines: Vec<Value> = String::from_utf8(run.stdout)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let npz = Npz::parse(&std::fs::read(out).unwrap());
    let mut names: Vec<&str> = ARRAYS.iter().map(|(name, _)| *name).collect();
    names.sort_unstable();
    assert_eq!(npz.names(), names);
    for (name, descr) in ARRAYS {
        assert_eq!(npz.descr(name), descr, "{name}");
    }
    let n = lines.len();
    // The heights' shares the run used: none for these small inputs, else three summing to 1.
    let (shares_shape, shares) = npz.array::<f64>("camera_height_shares");
    assert_eq!(shares_shape, [3]);
    let total: f64 = shares.iter().sum();
    assert!(
        shares.iter().all(|s| s.is_nan()) || (total - 1.0).abs() < 1e-12,
        "{shares:?}"
    );
    let (label_shape, label) = npz.array::<u16>("label");
    let (p_shape, p) = npz.array::<f64>("probabilities");
    let (missing_shape, missing) = npz.array::<bool>("missing");
    let (_, derived) = npz.array::<bool>("derived");
    let (_, folded) = npz.array::<u16>("folded_label");
    let (_, failed) = npz.array::<bool>("failed");
    let (_, frame) = npz.array::<i64>("frame");
    let (_, person) = npz.array::<i64>("person");
    let (_, id_utf8) = npz.array::<u8>("id_utf8");
    let (id_shape, id_end) = npz.array::<u64>("id_end");
    assert_eq!(label_shape, [n as u64]);
    assert_eq!(id_shape, [n as u64]);
    assert_eq!(p_shape, [n as u64, 12]);
    assert_eq!(missing_shape, [n as u64, NUM_LANDMARKS as u64]);
    assert_eq!(id_end.last().copied().unwrap_or(0), id_utf8.len() as u64);
    let degrees = ["azimuth_deg", "elevation_deg", "uncertainty_deg"].map(|name| {
        let (shape, values) = npz.array::<f64>(name);
        assert_eq!(shape, [n as u64], "{name}");
        (name, values)
    });
    let mut failures = 0;
    let mut start = 0;
    for (i, line) in lines.iter().enumerate() {
        let end = id_end[i] as usize;
        let id = std::str::from_utf8(&id_utf8[start..end]).unwrap();
        start = end;
        assert_eq!(id, line["id"].as_str().unwrap(), "pose {i}");
        let place = |key: &str| line.get(key).and_then(Value::as_i64).unwrap_or(-1);
        assert_eq!(frame[i], place("frame"), "pose {i}");
        assert_eq!(person[i], place("person"), "pose {i}");
        let row = &p[i * 12..(i + 1) * 12];
        if line.get("error").is_some() {
            failures += 1;
            assert!(failed[i] && label[i] == 0 && folded[i] == 0, "pose {i}");
            assert!(row.iter().all(|x| x.is_nan()), "pose {i}");
            assert!(degrees.iter().all(|(_, d)| d[i].is_nan()), "pose {i}");
            continue;
        }
        assert!(!failed[i], "pose {i}");
        assert_eq!(u64::from(label[i]), line["label"].as_u64().unwrap());
        assert_eq!(u64::from(folded[i]), line["folded_label"].as_u64().unwrap());
        for (k, value) in row.iter().enumerate() {
            let json = &line["probabilities"][format!("{:02}", k + 1)];
            assert!(same(*value, json), "pose {i} camera {}", k + 1);
        }
        for (name, values) in &degrees {
            assert!(same(values[i], &line[*name]), "pose {i} {name}");
        }
        let row = |flags: &[bool]| flags[i * NUM_LANDMARKS..(i + 1) * NUM_LANDMARKS].to_vec();
        assert_eq!(row(&missing), flags(&line["missing"]), "pose {i}");
        assert_eq!(row(&derived), flags(&line["derived"]), "pose {i}");
    }
    (n, failures)
}

/// The example poses, one of them without its head, ids JSON must escape, and a pose without
/// a torso (it fails: a row of NaN marked failed).
fn mixed_input(dir: &TempDir) -> String {
    let example = std::fs::read_to_string(fixture("keypoints/example.json")).unwrap();
    let mut doc: Value = serde_json::from_str(&example).unwrap();
    let poses = doc["poses"].as_array_mut().unwrap();
    let mut headless = poses[1].clone();
    headless["id"] = "é \"quoted\" \\ 人 🙂\n".into();
    headless["landmarks"]
        .as_object_mut()
        .unwrap()
        .remove("head");
    poses.push(headless);
    poses.push(serde_json::json!({"id": "", "landmarks": {"head": [10.0, 20.0]}}));
    poses.push(poses[0].clone());
    dir.file("mixed.json", &doc.to_string())
}

/// The number of rows of the archive at `path`.
fn rows(path: impl AsRef<std::path::Path>) -> u64 {
    let npz = Npz::parse(&std::fs::read(path).unwrap());
    npz.array::<u16>("label").0[0]
}

#[test]
fn the_archive_holds_the_values_of_the_json_lines() {
    let dir = TempDir::new("npz-json");
    let input = mixed_input(&dir);
    let (poses, failures) = check_against_json(&input, &dir.0.join("mixed.npz"));
    assert_eq!((poses, failures), (6, 1));
}

/// A folder of OpenPose frames: frames and persons, pelvis and neck derived.
#[test]
fn frames_persons_and_derived_landmarks_of_a_folder_are_kept() {
    let dir = TempDir::new("npz-folder");
    let input = fixture("keypoints/samples/openpose");
    let out = dir.0.join("frames.npz");
    let (poses, _) = check_against_json(input.to_str().unwrap(), &out);
    let npz = Npz::parse(&std::fs::read(&out).unwrap());
    assert!(poses > 1);
    assert!(npz.array::<i64>("person").1.iter().any(|&p| p > 0));
    assert!(npz.array::<bool>("derived").1.iter().any(|&d| d));
}

#[test]
fn nothing_is_printed_per_pose_unless_json_is_asked_for() {
    let dir = TempDir::new("npz-quiet");
    let input = mixed_input(&dir);
    let out = dir.0.join("a.npz");
    let run = camloc(&[
        "localize",
        "--input",
        &input,
        "--npz",
        out.to_str().unwrap(),
    ]);
    assert_eq!(run.status.code(), Some(1), "one pose fails");
    assert!(run.stdout.is_empty());
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(
        stderr.contains("1 of 6 poses could not be localized"),
        "{stderr}"
    );
    assert_eq!(rows(&out), 6);
}

#[test]
fn an_existing_file_is_replaced_only_with_force() {
    let dir = TempDir::new("npz-force");
    let input = fixture("keypoints/example.json");
    let input = input.to_str().unwrap();
    let out = dir.file("kept.npz", "not an archive");
    let run = camloc(&["localize", "--input", input, "--npz", &out, "--jsonl"]);
    assert_clean_failure(&run, "kept.npz");
    assert!(run.stdout.is_empty(), "refused before any work");
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "not an archive");
    let run = camloc(&["localize", "--input", input, "--npz", &out, "--force"]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert_eq!(rows(&out), 3);
}

#[test]
fn npz_and_svg_may_not_name_one_file() {
    let dir = TempDir::new("npz-same");
    let input = fixture("keypoints/example.json");
    let out = dir.0.join("x.npz");
    let out = out.to_str().unwrap();
    let run = camloc(&[
        "localize",
        "--input",
        input.to_str().unwrap(),
        "--npz",
        out,
        "--summary-svg",
        out,
    ]);
    assert_eq!(run.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&run.stderr).contains("name the same file"));
    assert!(!dir.0.join("x.npz").exists());
}

/// A standing person facing the camera in Human3.6M's 17 joints (pixels, y down): the
/// pelvis, right leg, left hip (first five), left leg, spine, thorax, nose, head top, arms.
const H36M_STANDING: [[f64; 2]; 17] = [
    [100.0, 130.0],
    [85.0, 130.0],
    [84.0, 185.0],
    [83.0, 240.0],
    [115.0, 130.0],
    [116.0, 185.0],
    [117.0, 240.0],
    [100.0, 90.0],
    [100.0, 50.0],
    [100.0, 20.0],
    [100.0, 5.0],
    [125.0, 50.0],
    [130.0, 90.0],
    [132.0, 125.0],
    [75.0, 50.0],
    [70.0, 90.0],
    [68.0, 125.0],
];

/// A pose the reader refuses (declared Human3.6M, its first five joints gathered as a face's)
/// keeps its row: marked failed in `--npz`, an error object with its id and frame in JSON (in
/// its frame's place with `--sequence`), a NaN row in `reconstruct --npy` and `convert`, with or
/// without `--sequence`; the rows after it stay the rows of their poses.
#[test]
fn a_pose_the_reader_refuses_keeps_its_row() {
    let dir = TempDir::new("npz-refused");
    let mut face = H36M_STANDING;
    for (j, point) in face.iter_mut().take(5).enumerate() {
        *point = [100.0 + 2.0 * j as f64, 20.0 - j as f64];
    }
    let mut bytes = npy_head("{'descr': '<f8', 'fortran_order': False, 'shape': (3, 17, 2), }");
    for pose in [H36M_STANDING, face, H36M_STANDING] {
        bytes.extend(pose.as_flattened().iter().flat_map(|v| v.to_le_bytes()));
    }
    let input = dir.0.join("h36m.npy");
    std::fs::write(&input, bytes).unwrap();
    let input = input.to_str().unwrap();
    let npz = dir.0.join("h36m.npz");
    let run = camloc(&["localize", "--input", input, "--layout", "h36m17"]);
    assert_eq!(run.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(stderr.contains("error: 1 ("), "{stderr}");
    assert!(
        stderr.contains("h36m.npy: [1]): the first five joints"),
        "{stderr}"
    );
    let lines = success_or_failure_lines(&[
        "localize", "--input", input, "--layout", "h36m17", "--jsonl",
    ]);
    assert_eq!(lines.len(), 3);
    assert_eq!(
        (lines[1]["id"].as_str(), lines[1]["frame"].as_u64()),
        (Some("1"), Some(1))
    );
    assert!(
        lines[1]["error"]
            .as_str()
            .unwrap()
            .contains("likely coco17")
    );
    assert_eq!(lines[2]["frame"].as_u64(), Some(2));
    let npz_out = camloc(&[
        "localize",
        "--input",
        input,
        "--layout",
        "h36m17",
        "--npz",
        npz.to_str().unwrap(),
    ]);
    assert_eq!(npz_out.status.code(), Some(1));
    let archive = Npz::parse(&std::fs::read(&npz).unwrap());
    assert_eq!(archive.array::<bool>("failed").1, [false, true, false]);
    assert_eq!(archive.array::<i64>("frame").1, [0, 1, 2]);
    // With --sequence, in its frame's place (it had been written first).
    for command in ["localize", "reconstruct"] {
        let lines = success_or_failure_lines(&[
            command,
            "-q",
            "--input",
            input,
            "--layout",
            "h36m17",
            "--sequence",
            "--jsonl",
        ]);
        let frames: Vec<(u64, bool)> = lines
            .iter()
            .map(|l| (l["frame"].as_u64().unwrap(), l.get("error").is_some()))
            .collect();
        assert_eq!(frames, [(0, false), (1, true), (2, false)], "{command}");
    }
    // `convert` writes it in its place without landmarks.
    let converted = dir.0.join("converted.npy");
    let run = camloc(&[
        "convert",
        "--input",
        input,
        "--layout",
        "h36m17",
        "--to",
        "npy",
        "--out",
        converted.to_str().unwrap(),
    ]);
    assert_eq!(run.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&run.stderr).contains("written without landmarks"));
    let (_, values) = read_npy_f64(&converted);
    let empty: Vec<bool> = values
        .chunks_exact(30)
        .map(|r| r.iter().all(|v| v.is_nan()))
        .collect();
    assert_eq!(empty, [false, true, false]);
    for sequence in [false, true] {
        let npy = dir.0.join(format!("poses3-{sequence}.npy"));
        let mut args = vec![
            "reconstruct",
            "-q",
            "--input",
            input,
            "--layout",
            "h36m17",
            "--npy",
        ];
        args.push(npy.to_str().unwrap());
        if sequence {
            args.push("--sequence");
        }
        assert_eq!(camloc(&args).status.code(), Some(1));
        let (_, values) = read_npy_f64(&npy);
        assert_eq!(values.len(), 3 * 15 * 3, "sequence {sequence}");
        let nan_rows: Vec<bool> = values
            .chunks_exact(45)
            .map(|row| row.iter().all(|v| v.is_nan()))
            .collect();
        assert_eq!(nan_rows, [false, true, false], "sequence {sequence}");
    }
}

/// The JSON lines a run with `args` writes, whether it succeeded or some poses failed.
fn success_or_failure_lines(args: &[&str]) -> Vec<Value> {
    let run = camloc(args);
    assert!(matches!(run.status.code(), Some(0 | 1)));
    String::from_utf8(run.stdout)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}
