//! What the command-line tests share: running the binary, temporary folders, fixtures and
//! the assertions on exit codes and messages.
// Each test file uses only part of this module.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use camloc::store::Persist;

pub fn camloc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_camloc"))
        .args(args)
        .output()
        .expect("the camloc binary runs")
}

pub fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures")
        .join(name)
}

pub struct TempDir(pub PathBuf);

impl TempDir {
    pub fn new(name: &str) -> TempDir {
        let dir = std::env::temp_dir().join(format!("camloc-cli-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        TempDir(dir)
    }
    pub fn file(&self, name: &str, content: &str) -> String {
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
pub fn assert_clean_failure(out: &Output, expected: &str) {
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

pub const FIFTEEN: &str = r#"{"poses": [{"id": "p", "landmarks": {
  "pelvis": [100, 200], "left_hip": [110, 205], "left_knee": [112, 260], "left_ankle": [113, 320],
  "right_hip": [90, 205], "right_knee": [88, 262], "right_ankle": [87, 322], "neck": [100, 140],
  "head": [100, 115], "left_shoulder": [118, 145], "left_elbow": [125, 175], "left_wrist": [128, 200],
  "right_shoulder": [82, 145], "right_elbow": [75, 175], "right_wrist": [72, 200]}}]}"#;

/// Asserts a usage error: exit code 2, clap's message naming `option`, no panic.
pub fn assert_usage_error(out: &Output, option: &str) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "stderr: {stderr}");
    assert!(!stderr.contains("panicked"), "panic: {stderr}");
    assert!(stderr.contains("invalid value"), "{stderr}");
    assert!(stderr.contains(option), "expected '{option}' in: {stderr}");
}

/// A tiny labelled dataset made through the library from the project's mocap fixtures.
pub fn fixture_dataset(dir: &TempDir) -> String {
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

/// Runs camloc with `stdin` as standard input.
pub fn camloc_with_stdin(args: &[&str], stdin: &[u8]) -> Output {
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
pub fn success(out: &Output) -> String {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "stderr: {stderr}");
    String::from_utf8(out.stdout.clone()).unwrap()
}

/// The `label` of every line of `localize --jsonl` output, in order.
pub fn jsonl_labels(stdout: &str) -> Vec<u64> {
    stdout
        .lines()
        .map(|line| {
            let v: serde_json::Value = serde_json::from_str(line).unwrap();
            v["label"].as_u64().unwrap()
        })
        .collect()
}

/// The labels of the three poses of example.json.
pub fn example_labels() -> Vec<u64> {
    let example = fixture("keypoints/example.json");
    let out = camloc(&["localize", "--input", example.to_str().unwrap(), "--jsonl"]);
    let labels = jsonl_labels(&success(&out));
    assert_eq!(labels.len(), 3);
    labels
}

/// A (0, 15, 2) float64 .npy array.
pub fn empty_npy() -> Vec<u8> {
    npy_head("{'descr': '<f8', 'fortran_order': False, 'shape': (0, 15, 2), }")
}

/// The header line (up to its newline) and the little-endian float64 values of the version 1
/// .npy file at `path`, as the command line writes them.
pub fn read_npy_f64(path: &Path) -> (String, Vec<f64>) {
    let bytes = std::fs::read(path).unwrap();
    let header_end = bytes.iter().position(|&b| b == b'\n').unwrap() + 1;
    let header = String::from_utf8_lossy(&bytes[..header_end]).into_owned();
    let values = bytes[header_end..]
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
        .collect();
    (header, values)
}

/// The magic, version, length and `header` (padded as NumPy pads it) of a version 1 .npy file.
pub fn npy_head(header: &str) -> Vec<u8> {
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

/// Runs camloc with `args`, which must succeed, and returns the first line of its standard
/// error that contains `text` (a warning), if any.
pub fn warning_line(args: &[&str], text: &str) -> Option<String> {
    let out = camloc(args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    stderr.lines().find(|l| l.contains(text)).map(str::to_owned)
}
