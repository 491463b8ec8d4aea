//! A live input (a detector writing to camloc's standard input and waiting): with
//! `--camera-height any` its poses are answered as they come, while it still writes, where a
//! batch had waited for 4,096 poses or the input's end (a simulated robot's 30 fps stream: the
//! first answer after 134.7 s).

mod common;

use std::io::{BufRead, BufReader, Write};
use std::process::{Command, Stdio};
use std::sync::mpsc::channel;
use std::time::Duration;

use common::fixture;

#[test]
fn a_live_stream_is_answered_while_it_is_still_written() {
    let example: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(fixture("keypoints/example.json")).unwrap())
            .unwrap();
    let pose = |i: usize| {
        let mut p = example["poses"][i % 3].clone();
        p["id"] = format!("p{i}").into();
        p.to_string()
    };
    let mut child = Command::new(env!("CARGO_BIN_EXE_camloc"))
        .args([
            "localize",
            "--input",
            "-",
            "--jsonl",
            "--camera-height",
            "any",
            "-q",
        ])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("the camloc binary runs");
    let stdout = child.stdout.take().unwrap();
    let (lines, answers) = channel();
    let reader = std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines() {
            if lines.send(line.unwrap()).is_err() {
                break;
            }
        }
    });
    // More than the 64 KiB the format is read from, then the writer waits.
    let mut stdin = child.stdin.take().unwrap();
    let first = 300;
    let mut text = String::from("{\"format\": \"camloc-keypoints\", \"version\": 1, \"poses\": [");
    for i in 0..first {
        text.push_str(&pose(i));
        text.push_str(",\n");
    }
    assert!(text.len() > 1 << 16, "{} bytes", text.len());
    stdin.write_all(text.as_bytes()).unwrap();
    stdin.flush().unwrap();
    // Answers for most of those poses come before anything more is written.
    let mut answered = 0;
    while answered < first - 10 {
        match answers.recv_timeout(Duration::from_secs(60)) {
            Ok(_) => answered += 1,
            Err(_) => panic!("only {answered} of {first} poses answered while the input waits"),
        }
    }
    // One more pose, then the end of the document and of the input.
    stdin
        .write_all(format!("{}]}}\n", pose(first)).as_bytes())
        .unwrap();
    drop(stdin);
    let status = child.wait().unwrap();
    reader.join().unwrap();
    let rest: Vec<String> = answers.try_iter().collect();
    assert!(status.success());
    assert_eq!(answered + rest.len(), first + 1);
}
