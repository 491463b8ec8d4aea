//! Runs cut short and runs after runs: an interrupt removes the unfinished files, a cut-off
//! input writes none, `--force` names the files an earlier run left, and a flood of failed
//! poses is not listed line by line.

mod common;

#[cfg(unix)]
use std::os::unix::process::ExitStatusExt;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::{TempDir, assert_clean_failure, camloc, success};

/// A camloc JSON input of `n` copies of the pose of `common::FIFTEEN`, each moved a little so
/// that the drawings differ; `broken` of them (the last ones) with only a neck, which no
/// command can take.
fn poses_json(n: usize, broken: usize) -> String {
    let poses: Vec<String> = (0..n)
        .map(|i| {
            if i >= n - broken {
                return format!(r#"{{"id": "b{i}", "landmarks": {{"neck": [100, 140]}}}}"#);
            }
            let dx = i as f64 * 0.01;
            format!(
                r#"{{"id": "p{i}", "landmarks": {{
  "pelvis": [{}, 200], "left_hip": [110, 205], "left_knee": [112, 260], "left_ankle": [113, 320],
  "right_hip": [90, 205], "right_knee": [88, 262], "right_ankle": [87, 322], "neck": [100, 140],
  "head": [100, 115], "left_shoulder": [118, 145], "left_elbow": [125, 175], "left_wrist": [128, 200],
  "right_shoulder": [82, 145], "right_elbow": [75, 175], "right_wrist": [72, 200]}}}}"#,
                100.0 + dx
            )
        })
        .collect();
    format!(r#"{{"poses": [{}]}}"#, poses.join(",\n"))
}

/// Whether `program ARGS` runs and succeeds here (a tool the test needs, a namespace it may
/// make); a test that needs it is skipped, visibly, when it does not.
#[cfg(unix)]
fn works(program: &str, args: &[&str]) -> bool {
    let status = Command::new(program)
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status();
    status.is_ok_and(|s| s.success())
}

/// A folder named after `name` with an input of 3,000 poses (enough drawings to interrupt
/// while they are written) and an empty output folder `out` in it.
#[cfg(unix)]
fn many_poses(name: &str) -> (TempDir, String, std::path::PathBuf) {
    let dir = TempDir::new(name);
    let input = dir.file("many.json", &poses_json(3000, 0));
    let out = dir.0.join("out");
    std::fs::create_dir(&out).unwrap();
    (dir, input, out)
}

/// The names in `dir`, hidden ones included, sorted.
fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// Starts `camloc localize --input INPUT --svg OUT/v.svg --force --quiet` (through `wrapper`,
/// e.g. `nohup`, when given; standard error to `stderr`), waits until it writes temporaries,
/// sends it `signal` (`kill -SIGNAL`) and waits for its end; returns how it ended and its
/// standard error (empty unless piped). A run that has not ended two minutes after the
/// signal fails the test: it hung.
#[cfg(unix)]
fn signalled(
    input: &str,
    out: &Path,
    wrapper: Option<&str>,
    stderr: Stdio,
    signal: &str,
) -> (std::process::ExitStatus, String) {
    let camloc = env!("CARGO_BIN_EXE_camloc");
    let mut command = match wrapper {
        Some(wrapper) => {
            let mut command = Command::new(wrapper);
            command.arg(camloc);
            command
        }
        None => Command::new(camloc),
    };
    let mut child = command
        .args(["localize", "--input", input, "--svg"])
        .arg(out.join("v.svg"))
        .args(["--force", "--quiet"])
        .stdout(Stdio::null())
        .stderr(stderr)
        .spawn()
        .unwrap();
    let waiting = |what: &str, child: &mut std::process::Child, until: &dyn Fn() -> bool| {
        let start = Instant::now();
        while !until() {
            assert!(
                start.elapsed() < Duration::from_secs(120),
                "{what} within two minutes"
            );
            if child.try_wait().unwrap().is_some() {
                return false;
            }
            std::thread::sleep(Duration::from_millis(5));
        }
        true
    };
    let temporaries = || listing(out).iter().filter(|n| n.ends_with(".tmp")).count() >= 10;
    let writing = waiting("temporaries", &mut child, &temporaries);
    assert!(writing, "the run wrote no temporaries before it ended");
    let killed = Command::new("kill")
        .args([&format!("-{signal}"), &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let ended = || false;
    waiting("the end of the run", &mut child, &ended);
    let out = child.wait_with_output().unwrap();
    (
        out.status,
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// SIGTERM (handled as Ctrl-C is; SIGINT itself is not sent, since a test run in the
/// background of a shell script inherits it ignored) while a run's drawings are being
/// written: the run ends killed by the signal (as a shell expects, to stop a loop), with a
/// message and none of its temporary files (`.NAME.XXXXXX.tmp`) left; a file the run would
/// have replaced with `--force` is untouched. With a standard error that cannot be written
/// (a closed terminal), the run ends the same way and does not hang.
#[cfg(unix)]
#[test]
fn an_interrupt_removes_the_unfinished_files() {
    let (_dir, input, out) = many_poses("interrupt");
    std::fs::write(out.join("v-001.svg"), "mine").unwrap();
    let (status, stderr) = signalled(&input, &out, None, Stdio::piped(), "TERM");
    assert_eq!(status.signal(), Some(15), "{status:?} {stderr}");
    assert!(stderr.contains("camloc: interrupted; removing"), "{stderr}");
    assert_eq!(listing(&out), ["v-001.svg"], "{stderr}");
    assert_eq!(
        std::fs::read_to_string(out.join("v-001.svg")).unwrap(),
        "mine"
    );
    if let Ok(full) = std::fs::OpenOptions::new().write(true).open("/dev/full") {
        let (status, _) = signalled(&input, &out, None, Stdio::from(full), "TERM");
        assert_eq!(status.signal(), Some(15), "{status:?}");
        assert_eq!(listing(&out), ["v-001.svg"]);
    }
}

/// A run started with `SIGHUP` ignored (`nohup`, a terminal that closes later) keeps it
/// ignored: it ends normally and writes its files.
#[cfg(unix)]
#[test]
fn a_run_under_nohup_outlives_its_terminal() {
    if !works("nohup", &["true"]) {
        eprintln!("skipped: no nohup command");
        return;
    }
    let (_dir, input, out) = many_poses("nohup");
    let (status, stderr) = signalled(&input, &out, Some("nohup"), Stdio::piped(), "HUP");
    assert_eq!(status.code(), Some(0), "{stderr}");
    let names = listing(&out);
    assert_eq!(names.len(), 3000, "{stderr}");
    assert!(names.iter().all(|n| !n.starts_with('.')));
}

/// A single input file cut off in the middle gives no output file (its rows would end early
/// with nothing to say so), with the read error and a message saying so.
#[test]
fn a_cut_off_input_writes_no_file() {
    let dir = TempDir::new("cut-off");
    // Large enough to be read as a stream (a small file is parsed whole when opened).
    let whole = poses_json(3000, 0);
    let input = dir.file("cut.json", &whole[..whole.len() / 2]);
    let npz = dir.0.join("rows.npz");
    let npy = dir.0.join("poses.npy");
    let runs: [&[&str]; 3] = [
        &[
            "localize",
            "--input",
            &input,
            "--npz",
            npz.to_str().unwrap(),
        ],
        &[
            "reconstruct",
            "--input",
            &input,
            "--sequence",
            "--npy",
            npy.to_str().unwrap(),
        ],
        &[
            "convert",
            "--input",
            &input,
            "--to",
            "npy",
            "--out",
            npy.to_str().unwrap(),
        ],
    ];
    for args in runs {
        let out = camloc(args);
        assert_clean_failure(&out, "could not be read to its end");
        assert_eq!(listing(&dir.0), ["cut.json"], "{args:?}");
    }
    // Standard output stays one JSON document: the poses read, then the error, then `]`;
    // with --sequence (which prints after the whole input is read) the error alone.
    let out = camloc(&["localize", "--input", &input, "--json"]);
    assert_clean_failure(&out, "could not be read to its end");
    let printed: Vec<serde_json::Value> = serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&out.stdout)));
    assert!(printed.len() > 1, "{printed:?}");
    assert!(printed.last().unwrap().get("error").is_some());
    for command in ["localize", "reconstruct"] {
        let out = camloc(&[command, "--input", &input, "--sequence", "--json", "-q"]);
        assert_clean_failure(&out, "could not be read to its end");
        let printed: Vec<serde_json::Value> = serde_json::from_slice(&out.stdout)
            .unwrap_or_else(|e| panic!("{command}: {e}: {}", String::from_utf8_lossy(&out.stdout)));
        assert!(
            printed.last().unwrap().get("error").is_some(),
            "{printed:?}"
        );
    }
    // The whole file is written.
    let input = dir.file("whole.json", &whole);
    success(&camloc(&[
        "localize",
        "--input",
        &input,
        "--npz",
        npz.to_str().unwrap(),
    ]));
    assert!(npz.is_file());
}

/// With `--force`, files named like a numbered output that the run did not write are left
/// and named in a warning; a run that replaces them all warns of nothing.
#[test]
fn force_names_the_files_an_earlier_run_left() {
    let dir = TempDir::new("left-over");
    let five = dir.file("five.json", &poses_json(5, 0));
    let three = dir.file("three.json", &poses_json(3, 0));
    let svg = dir.0.join("v.svg");
    let svg = svg.to_str().unwrap();
    let run = |input: &str| camloc(&["localize", "--input", input, "--svg", svg, "--force"]);
    let out = run(&five);
    success(&out);
    assert!(!String::from_utf8_lossy(&out.stderr).contains("warning"));
    let out = run(&three);
    success(&out);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("2 files named like this run's outputs")
            && stderr.contains("v-004.svg")
            && stderr.contains("v-005.svg"),
        "{stderr}"
    );
    let out = run(&five);
    success(&out);
    assert!(!String::from_utf8_lossy(&out.stderr).contains("warning"));
}

/// Past 20 failed poses, the rest are counted, not listed; the JSON output has every one.
#[test]
fn many_failed_poses_are_counted_not_listed() {
    let dir = TempDir::new("many-failed");
    let input = dir.file("broken.json", &poses_json(30, 26));
    let out = camloc(&["localize", "--input", &input, "--jsonl"]);
    assert_clean_failure(&out, "26 of 30 poses could not be localized");
    let stderr = String::from_utf8_lossy(&out.stderr);
    let listed = stderr
        .lines()
        .filter(|l| l.starts_with("camloc: error: b") || l.starts_with("camloc: error: \"b"))
        .count();
    assert_eq!(listed, 20, "{stderr}");
    assert!(stderr.contains("are not listed"), "{stderr}");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        stdout.lines().filter(|l| l.contains("\"error\"")).count(),
        26
    );
}

/// As the first process of a PID namespace (a container started without an init process),
/// where the kernel does not let a default action kill the process, an interrupted run still
/// removes its temporaries and ends with 128 + the signal's number (it ended with SIGSEGV
/// when its handler re-raised the signal and then aborted). Skipped where `unshare --pid`
/// is not allowed.
#[cfg(target_os = "linux")]
#[test]
fn the_first_process_of_a_container_ends_with_the_signals_status() {
    if !works("unshare", &["--pid", "--fork", "true"]) {
        eprintln!("skipped: unshare --pid is not allowed here");
        return;
    }
    let (_dir, input, out) = many_poses("pid-one");
    // `unshare` waits for camloc, its child and the namespace's first process, and exits with
    // its status; the signal goes to camloc.
    let mut unshare = Command::new("unshare")
        .args(["--pid", "--fork", env!("CARGO_BIN_EXE_camloc")])
        .args(["localize", "--input", &input, "--svg"])
        .arg(out.join("v.svg"))
        .arg("--quiet")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let start = Instant::now();
    let children = format!("/proc/{0}/task/{0}/children", unshare.id());
    let camloc = loop {
        let writing = listing(&out).iter().any(|n| n.ends_with(".tmp"));
        let child = std::fs::read_to_string(&children).unwrap_or_default();
        if let (true, Some(pid)) = (writing, child.split_whitespace().next()) {
            break pid.to_owned();
        }
        assert!(start.elapsed() < Duration::from_secs(120), "no temporaries");
        assert!(unshare.try_wait().unwrap().is_none(), "the run ended first");
        std::thread::sleep(Duration::from_millis(5));
    };
    assert!(
        Command::new("kill")
            .args(["-TERM", &camloc])
            .status()
            .unwrap()
            .success()
    );
    let status = unshare.wait().unwrap();
    assert_eq!(status.code(), Some(128 + 15), "{status:?}");
    assert_eq!(listing(&out), Vec::<String>::new());
}

/// A standard error that cannot be written loses the messages, not the run: failed poses
/// (whose errors go to standard error) with standard error on `/dev/full` still give exit 1
/// and the output file.
#[test]
fn an_unwritable_standard_error_loses_only_the_messages() {
    let Ok(full) = std::fs::OpenOptions::new().write(true).open("/dev/full") else {
        eprintln!("skipped: no /dev/full");
        return;
    };
    let dir = TempDir::new("stderr-full");
    let input = dir.file("some-broken.json", &poses_json(30, 5));
    let npz = dir.0.join("rows.npz");
    let out = Command::new(env!("CARGO_BIN_EXE_camloc"))
        .args(["localize", "--input", &input, "--npz"])
        .arg(&npz)
        .stdout(Stdio::null())
        .stderr(full)
        .status()
        .unwrap();
    assert_eq!(out.code(), Some(1), "{out:?}");
    assert!(npz.is_file());
}
