//! Output files: never overwritten without --force, all or nothing, links and devices handled
//! by one rule; `convert` and `reconstruct --npy` write what reads back.

use std::path::Path;
use std::process::Command;

mod common;
use common::*;

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

/// When several outputs exist already, the refusal names them all (a simulated animator
/// removed the one named, ran again and met the next); with one, that one as before; nothing
/// is written, and `--force` writes them.
#[test]
fn several_existing_outputs_are_named_at_once() {
    let dir = TempDir::new("several");
    let example = fixture("keypoints/example.json");
    let (bvh, lengths) = (dir.0.join("x.bvh"), dir.0.join("x_bl.json"));
    let args = |force: bool| {
        let mut args = vec![
            "reconstruct".to_string(),
            "--input".into(),
            example.to_string_lossy().into_owned(),
            "--sequence".into(),
            "--bvh".into(),
            bvh.to_string_lossy().into_owned(),
            "--bone-lengths-out".into(),
            lengths.to_string_lossy().into_owned(),
            "-q".into(),
        ];
        if force {
            args.push("--force".into());
        }
        args
    };
    let run = |force: bool| camloc(&args(force).iter().map(String::as_str).collect::<Vec<_>>());
    std::fs::write(&bvh, "mine").unwrap();
    std::fs::write(&lengths, "mine too").unwrap();
    let out = run(false);
    assert_clean_failure(&out, "x_bl.json, ");
    assert_clean_failure(&out, "x.bvh: already exist (pass --force to overwrite them");
    assert_eq!(std::fs::read_to_string(&bvh).unwrap(), "mine");
    std::fs::remove_file(&bvh).unwrap();
    assert_clean_failure(&run(false), "x_bl.json: already exists (pass --force");
    assert!(!bvh.exists());
    assert!(run(true).status.success());
    assert!(
        std::fs::read_to_string(&bvh)
            .unwrap()
            .starts_with("HIERARCHY")
    );
    // One existing file is refused before any work too: before a missing model is looked for.
    let out = camloc(&[
        "reconstruct",
        "--input",
        example.to_str().unwrap(),
        "--model",
        dir.0.join("absent.bin").to_str().unwrap(),
        "--bvh",
        bvh.to_str().unwrap(),
    ]);
    assert_clean_failure(&out, "x.bvh: already exists (pass --force");
    // Folders in the way are refused as folders (never replaced, even with --force), not as
    // files to remove.
    let (first, second) = (dir.0.join("f.npy"), dir.0.join("g.html"));
    std::fs::create_dir(&first).unwrap();
    std::fs::create_dir(&second).unwrap();
    for force in [false, true] {
        let mut args = vec![
            "reconstruct",
            "--input",
            example.to_str().unwrap(),
            "--npy",
            first.to_str().unwrap(),
            "--html",
            second.to_str().unwrap(),
        ];
        if force {
            args.push("--force");
        }
        let out = camloc(&args);
        assert_clean_failure(&out, "f.npy: is a directory, not a regular file");
        assert!(!String::from_utf8_lossy(&out.stderr).contains("remove them"));
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
        // The help and the version, which clap writes, too.
        for args in [&["--help"][..], &["localize", "--help"], &["--version"]] {
            let out = Command::new(env!("CARGO_BIN_EXE_camloc"))
                .args(args)
                .stdout(full.try_clone().unwrap())
                .output()
                .unwrap();
            let stderr = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(1), "{args:?}: {stderr}");
            assert!(
                stderr.contains("cannot write to standard output"),
                "{stderr}"
            );
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
    // A pose that cannot be reconstructed (no pelvis) is a row of NaN.
    let npy = dir.0.join("partial3.npy");
    let out = camloc(&[
        "reconstruct",
        "--input",
        partial.to_str().unwrap(),
        "--npy",
        npy.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(1));
    let (header, values) = read_npy_f64(&npy);
    let rows = values.len() / (15 * 3);
    assert!(header.contains(&format!("({rows}, 15, 3")), "{header}");
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

/// An existing file with one of an output's numbered names refuses the run (the count of
/// poses is known only at the end) with a message that says whose numbered file it is.
#[test]
fn an_existing_numbered_file_is_named_as_one() {
    let dir = TempDir::new("numbered");
    let example = fixture("keypoints/example.json");
    let svg = dir.0.join("two.svg");
    let numbered = dir.0.join("two-001.svg");
    std::fs::write(&numbered, "mine").unwrap();
    let args = [
        "localize",
        "--input",
        example.to_str().unwrap(),
        "--svg",
        svg.to_str().unwrap(),
        "-q",
    ];
    let out = camloc(&args);
    assert_clean_failure(&out, "two-001.svg: already exists, a numbered file of");
    assert_eq!(std::fs::read_to_string(&numbered).unwrap(), "mine");
    success(&camloc(&[&args[..], &["--force"]].concat()));
    assert_ne!(std::fs::read(&numbered).unwrap(), b"mine");
}
