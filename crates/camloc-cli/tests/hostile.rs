//! Regression tests of issue 22 ("hostile inputs round 2") through the binary: each failed
//! before its fix.

mod common;

use std::path::Path;
use std::process::{Command, Output};

use common::*;

/// Standard error as text.
fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Asserts that every line of standard error is shorter than 300 characters and holds no
/// control character, and returns standard error.
fn short_clean_lines(out: &Output) -> String {
    let text = stderr(out);
    for line in text.lines() {
        assert!(
            line.chars().count() < 300,
            "{} chars: {line:.400}",
            line.len()
        );
        assert!(!line.chars().any(char::is_control), "{line:?}");
    }
    text
}

/// Runs `script` with `sh -c`, the camloc binary as `$0`.
fn shell(script: &str) -> Output {
    Command::new("sh")
        .args(["-c", script, env!("CARGO_BIN_EXE_camloc")])
        .output()
        .unwrap()
}

/// A camloc JSON document of one pose with `id` and the 15 landmarks of [`FIFTEEN`].
fn pose_with_id(id: &str) -> String {
    let id = serde_json::to_string(id).unwrap();
    FIFTEEN.replace(r#""id": "p""#, &format!(r#""id": {id}"#))
}

#[test]
fn ids_names_and_shapes_are_quoted_short_and_escaped() {
    let dir = TempDir::new("hostile-quote");
    let long = "x".repeat(100_000);
    let no_torso = |id: &str| {
        let id = serde_json::to_string(id).unwrap();
        format!(r#"{{"poses": [{{"id": {id}, "landmarks": {{"head": [1, 2]}}}}]}}"#)
    };
    let mut inputs = vec![
        dir.file("long_id.json", &no_torso(&long)),
        dir.file("escape_id.json", &no_torso("a\u{1b}[31m\nb")),
        dir.file(
            "mpii.json",
            &format!(
                r#"[{{"image": "{long}", "joints": {}, "joints_vis": {}}}]"#,
                serde_json::to_string(&vec![[1.0, 2.0]; 16]).unwrap(),
                serde_json::to_string(&vec![0; 16]).unwrap()
            ),
        ),
        dir.file(
            "lsp.csv",
            &format!("image,joint,x,y,visible\n{long},head_top,1,2,1\n"),
        ),
        dir.file("bad\u{1b}[31m\nname.json", "{"),
    ];
    // An .npy header of 2,000 dimensions.
    let shape = vec!["1"; 2_000].join(", ");
    let header = format!("{{'descr': '<f8', 'fortran_order': False, 'shape': ({shape}), }}");
    let npy = npy_head(&header);
    let npy_path = dir.0.join("shape.npy");
    std::fs::write(&npy_path, npy).unwrap();
    inputs.push(npy_path.to_string_lossy().into_owned());
    for input in &inputs {
        let out = camloc(&["localize", "--input", input, "--layout", "coco17"]);
        assert_eq!(out.status.code(), Some(1), "{input:.80}: {}", stderr(&out));
        let text = short_clean_lines(&out);
        assert!(text.contains("camloc: error: "), "{text}");
    }
    // Text output escapes an id's control characters too.
    let input = dir.file("ok.json", &pose_with_id("a\u{1b}b"));
    let out = success(&camloc(&["localize", "--input", &input]));
    assert!(out.contains("a\\u{1b}b: camera"), "{out}");
    assert!(!out.contains('\u{1b}'), "{out:?}");
}

#[test]
fn drawings_of_ids_with_control_characters_are_valid_xml() {
    let dir = TempDir::new("hostile-svg-escape");
    let input = dir.file("p.json", &pose_with_id("p\u{1b}[31m\u{7}"));
    let svg = dir.0.join("p.svg");
    success(&camloc(&[
        "localize",
        "--input",
        &input,
        "--svg",
        svg.to_str().unwrap(),
    ]));
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(
        !text
            .chars()
            .any(|c| c.is_control() && !"\n\r\t".contains(c)),
        "{text}"
    );
    assert!(text.contains("p\\u{1b}[31m\\u{7}"), "{text}");
}

#[test]
fn two_outputs_at_one_file_are_refused_before_any_work() {
    let dir = TempDir::new("hostile-same-output");
    let input = dir.file("p.json", FIFTEEN);
    std::fs::create_dir(dir.0.join("sub")).unwrap();
    let at = |name: &str| dir.0.join(name).to_string_lossy().into_owned();
    std::fs::write(at("target.svg"), "old").unwrap();
    std::os::unix::fs::symlink(at("target.svg"), at("link.svg")).unwrap();
    std::fs::hard_link(at("target.svg"), at("hard.svg")).unwrap();
    // Links to an existing numbered name of another output.
    std::fs::write(at("s-002.svg"), "old").unwrap();
    std::os::unix::fs::symlink(at("s-002.svg"), at("soft-numbered.svg")).unwrap();
    std::fs::hard_link(at("s-002.svg"), at("hard-numbered.svg")).unwrap();
    let cases: Vec<Vec<String>> = vec![
        vec![
            "localize".into(),
            "--svg".into(),
            at("s.svg"),
            "--summary-svg".into(),
            at("soft-numbered.svg"),
        ],
        vec![
            "localize".into(),
            "--svg".into(),
            at("s.svg"),
            "--summary-svg".into(),
            at("hard-numbered.svg"),
        ],
        vec![
            "localize".into(),
            "--svg".into(),
            at("s.svg"),
            "--summary-svg".into(),
            at("s.svg"),
        ],
        vec![
            "localize".into(),
            "--svg".into(),
            at("s.svg"),
            "--summary-svg".into(),
            at("sub/../s.svg"),
        ],
        vec![
            "localize".into(),
            "--svg".into(),
            at("s.svg"),
            "--summary-svg".into(),
            at("s-002.svg"),
        ],
        vec![
            "localize".into(),
            "--svg".into(),
            at("link.svg"),
            "--summary-svg".into(),
            at("target.svg"),
        ],
        vec![
            "localize".into(),
            "--svg".into(),
            at("hard.svg"),
            "--summary-svg".into(),
            at("target.svg"),
        ],
        vec![
            "reconstruct".into(),
            "--npy".into(),
            at("x"),
            "--svg".into(),
            at("x"),
        ],
        // The names the writers make: `--bvh b` writes b.bvh (b-001.bvh, ... for several
        // people), `--bone-lengths-out l` l-001.json, ... for several.
        vec![
            "reconstruct".into(),
            "--bvh".into(),
            at("b"),
            "--html".into(),
            at("b.bvh"),
        ],
        vec![
            "reconstruct".into(),
            "--sequence".into(),
            "--bvh".into(),
            at("b"),
            "--html".into(),
            at("b-001.bvh"),
        ],
        vec![
            "reconstruct".into(),
            "--sequence".into(),
            "--bone-lengths-out".into(),
            at("l"),
            "--html".into(),
            at("l-001.json"),
        ],
    ];
    for case in cases {
        for force in [true, false] {
            let mut args = case.clone();
            args.extend(["--input".to_owned(), input.clone()]);
            if force {
                args.push("--force".to_owned());
            }
            let args: Vec<&str> = args.iter().map(String::as_str).collect();
            let out = camloc(&args);
            let text = short_clean_lines(&out);
            assert_eq!(out.status.code(), Some(2), "{args:?}: {text}");
            assert!(text.contains("name the same file"), "{text}");
            assert!(!text.contains("already exists"), "{text}");
            assert!(!Path::new(&at("s.svg")).exists() && !Path::new(&at("x")).exists());
            assert_eq!(std::fs::read_to_string(at("target.svg")).unwrap(), "old");
            assert_eq!(std::fs::read_to_string(at("s-002.svg")).unwrap(), "old");
        }
    }
}

/// An output that names the input file is refused even with --force (the run would replace
/// what it reads), and `-` is no output file; the input is left as it was.
#[test]
fn outputs_that_are_the_input_or_standard_input_are_refused() {
    let dir = TempDir::new("hostile-input-out");
    let original = std::fs::read_to_string(fixture("keypoints/example.json")).unwrap();
    let input = dir.file("in.json", &original);
    let same = dir
        .0
        .join(".")
        .join("in.json")
        .to_string_lossy()
        .into_owned();
    std::fs::create_dir(dir.0.join("frames")).unwrap();
    let folder_file = dir.file("frames/f_000000000001_keypoints.json", &original);
    let folder = dir.0.join("frames").to_string_lossy().into_owned();
    let model = dir.0.join("m.bin").to_string_lossy().into_owned();
    std::fs::copy(fixture("default-model.bin"), &model).unwrap();
    // A hard link elsewhere to a file of the input folder.
    let linked = dir.0.join("linked.json").to_string_lossy().into_owned();
    std::fs::hard_link(&folder_file, &linked).unwrap();
    // A file of the input folder named as a numbered output's file (a trial's --force run
    // replaced it).
    let numbered_in_folder = dir.file("frames/bl-001.json", &original);
    let numbered_out = dir.0.join("frames/bl.json").to_string_lossy().into_owned();
    let cases: [&[&str]; 10] = [
        &[
            "reconstruct",
            "--sequence",
            "--bone-lengths-out",
            &numbered_out,
            "--input",
            &folder,
        ],
        &["reconstruct", "--npy", &linked, "--input", &folder],
        &["convert", "--to", "camloc", "--out", &same],
        &["convert", "--to", "npy", "--out", "-"],
        &["reconstruct", "--npy", &input],
        &["localize", "--svg", &same],
        // The input given as the argument.
        &["localize", &input, "--svg", &same],
        &["localize", "--model", &model, "--npz", &model],
        &["reconstruct", "--html", &folder_file, "--input", &folder],
        &["evaluate", "--dataset", &model, "--svg", &model],
    ];
    for case in cases {
        let mut args = case.to_vec();
        if !case.contains(&"--input") && case[1] != input && case[0] != "evaluate" {
            args.extend(["--input", &input]);
        }
        args.push("--force");
        let out = camloc(&args);
        let text = short_clean_lines(&out);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {text}");
        assert!(
            text.contains("which the run reads") || text.contains("not standard output"),
            "{text}"
        );
        // The keypoints are "the input", however they were given.
        assert!(!text.contains("--input reads"), "{text}");
        for file in [&input, &folder_file, &numbered_in_folder] {
            assert_eq!(std::fs::read_to_string(file).unwrap(), original);
        }
    }
    assert!(!dir.0.join("-").exists());
    // Standard input redirected from the file an output names.
    #[cfg(unix)]
    {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_camloc"))
            .args(["localize", "--input", "-", "--svg", &input, "--force"])
            .stdin(std::fs::File::open(&input).unwrap())
            .output()
            .unwrap();
        let text = short_clean_lines(&out);
        assert_eq!(out.status.code(), Some(2), "{text}");
        assert!(text.contains("which the run reads"), "{text}");
        assert_eq!(std::fs::read_to_string(&input).unwrap(), original);
    }
}

/// An output named like a file of another format (`--svg view.png` would be an SVG file
/// named like a PNG image) is refused before any work; the option's own extension in any
/// case, and a name without extension, are written.
#[test]
fn outputs_named_like_another_format_are_refused() {
    let dir = TempDir::new("hostile-extension");
    let input = fixture("keypoints/example.json")
        .to_string_lossy()
        .into_owned();
    let at = |name: &str| dir.0.join(name).to_string_lossy().into_owned();
    let refused: [(&str, &str, &str); 4] = [
        ("localize", "--svg", "view.png"),
        ("localize", "--html", "page.svg"),
        ("reconstruct", "--npy", "poses.npz"),
        ("reconstruct", "--bvh", "walk.json"),
    ];
    for (command, option, name) in refused {
        let out = camloc(&[command, "--input", &input, option, &at(name), "-q"]);
        let text = short_clean_lines(&out);
        assert_eq!(out.status.code(), Some(2), "{option} {name}: {text}");
        let ext = Path::new(name).extension().unwrap().to_str().unwrap();
        assert!(
            text.contains(option) && text.contains(&format!("ends in .{ext}")),
            "{text}"
        );
        assert!(!dir.0.join(name).exists(), "{name} was written");
    }
    for name in ["VIEW.SVG", "view"] {
        let out = camloc(&["localize", "--input", &input, "--svg", &at(name), "-q"]);
        assert!(out.status.success(), "{name}: {}", stderr(&out));
    }
    assert!(dir.0.join("VIEW-001.SVG").exists() && dir.0.join("view-001.svg").exists());
    let out = camloc(&[
        "convert",
        "--input",
        &input,
        "--to",
        "npy",
        "--out",
        &at("p.json"),
    ]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("--to npy writes") && !dir.0.join("p.json").exists());
    // A model is no drawing: `train --out m.svg` is refused before the fit.
    let dataset = fixture_dataset(&dir);
    let out = camloc(&["train", "--dataset", &dataset, "--out", &at("m.svg")]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("give a name ending in .bin") && !dir.0.join("m.svg").exists());
}

/// Any existing file a numbered output may write (`d-002.svg`, `b-003.bvh`) is found before
/// any work, without --force: nothing is printed and the file is kept.
#[test]
fn existing_numbered_outputs_are_refused_before_any_work() {
    let dir = TempDir::new("hostile-numbered");
    let input = fixture("keypoints/example.json")
        .to_string_lossy()
        .into_owned();
    for (command, option, base, existing) in [
        ("localize", "--svg", "d.svg", "d-002.svg"),
        ("reconstruct", "--bvh", "b", "b-003.bvh"),
    ] {
        let kept = dir.file(existing, "old");
        let out_path = dir.0.join(base).to_string_lossy().into_owned();
        let out = camloc(&[command, "--input", &input, option, &out_path, "-q"]);
        let text = short_clean_lines(&out);
        assert_eq!(out.status.code(), Some(1), "{option}: {text}");
        assert!(text.contains(existing) && text.contains("exists"), "{text}");
        assert!(
            out.stdout.is_empty(),
            "{}",
            String::from_utf8_lossy(&out.stdout)
        );
        assert_eq!(std::fs::read_to_string(&kept).unwrap(), "old");
    }
}

/// An input whose header says it holds more poses than `--html` keeps is refused at once,
/// before any pose is read (every pose here would fail, and say so).
#[test]
fn an_input_known_to_be_too_long_for_html_is_refused_before_any_work() {
    let dir = TempDir::new("hostile-keep");
    let mut bytes =
        npy_head("{'descr': '<f8', 'fortran_order': False, 'shape': (100001, 15, 2), }");
    bytes.resize(bytes.len() + 100_001 * 15 * 2 * 8, 0);
    let input = dir.0.join("long.npy");
    std::fs::write(&input, bytes).unwrap();
    let page = dir.0.join("p.html").to_string_lossy().into_owned();
    let bvh = dir.0.join("p.bvh").to_string_lossy().into_owned();
    let input = input.to_string_lossy().into_owned();
    // With --sequence too, whose frames are kept until the end anyway.
    let cases: [&[&str]; 4] = [
        &["localize", "--html", &page],
        &["localize", "--sequence", "--html", &page],
        &["reconstruct", "--sequence", "--html", &page],
        &["reconstruct", "--sequence", "--bvh", &bvh],
    ];
    for case in cases {
        let mut args = case.to_vec();
        args.extend(["--input", &input, "-q"]);
        let out = camloc(&args);
        let text = stderr(&out);
        assert_eq!(out.status.code(), Some(1), "{case:?}: {text}");
        assert!(text.contains("more than 100000 poses"), "{case:?}: {text}");
        assert_eq!(text.lines().count(), 1, "{case:?}: {text}");
        assert!(out.stdout.is_empty() && !dir.0.join("p.html").exists());
        assert!(!dir.0.join("p.bvh").exists());
    }
}

/// An output in a folder that does not exist is refused before any work (nothing printed),
/// naming the folder.
#[test]
fn outputs_in_missing_folders_are_refused_before_any_work() {
    let dir = TempDir::new("hostile-no-folder");
    let input = fixture("keypoints/example.json")
        .to_string_lossy()
        .into_owned();
    let missing = dir.0.join("nodir");
    for (command, option, name) in [
        ("reconstruct", "--bvh", "x.bvh"),
        ("localize", "--html", "x.html"),
        ("localize", "--svg", "x.svg"),
    ] {
        let path = missing.join(name).to_string_lossy().into_owned();
        let out = camloc(&[command, "--input", &input, option, &path, "-q"]);
        let text = short_clean_lines(&out);
        assert_eq!(out.status.code(), Some(2), "{option}: {text}");
        assert!(
            text.contains("nodir") && text.contains("does not exist"),
            "{text}"
        );
        assert!(
            out.stdout.is_empty(),
            "{}",
            String::from_utf8_lossy(&out.stdout)
        );
    }
    assert!(!missing.exists());
    // A "folder" that is a file is named as such.
    let out = camloc(&[
        "localize",
        "--input",
        &input,
        "--svg",
        &format!("{input}/x.svg"),
    ]);
    let text = short_clean_lines(&out);
    assert_eq!(out.status.code(), Some(2), "{text}");
    assert!(text.contains("is not a folder"), "{text}");
}

#[test]
fn a_landmark_at_an_absurd_place_is_read_as_missing_by_localize_and_reconstruct_alike() {
    // (Both had refused the pose as a degenerate torso; it is a landmark far off the body.)
    let dir = TempDir::new("hostile-far");
    for far in ["1e12", "1e300"] {
        let input = dir.file(
            "far.json",
            &FIFTEEN.replace("[100, 200]", &format!("[{far}, 200]")),
        );
        let localized = camloc(&["localize", "--input", &input, "--jsonl"]);
        assert!(localized.status.success(), "{}", stderr(&localized));
        let out = camloc(&["reconstruct", "--input", &input, "--jsonl"]);
        assert!(out.status.success(), "{}", stderr(&out));
        let line = String::from_utf8_lossy(&out.stdout);
        assert!(line.contains(r#""imputed":["pelvis"]"#), "{line}");
    }
}

#[test]
fn thousands_of_drawings_need_few_open_files() {
    let dir = TempDir::new("hostile-many-svg");
    let pose = &FIFTEEN[r#"{"poses": ["#.len()..FIFTEEN.len() - 2];
    let poses = vec![pose; 300].join(", ");
    let input = dir.file("many.json", &format!(r#"{{"poses": [{poses}]}}"#));
    let svg = dir.0.join("many.svg");
    // At most 64 open files, far fewer than the drawings.
    let script = format!(
        "ulimit -n 64 && exec \"$0\" localize --input '{input}' --svg '{}' -q",
        svg.display()
    );
    let out = shell(&script);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(dir.0.join("many-300.svg").exists());
}

#[test]
fn a_folder_reports_entries_it_cannot_read() {
    let dir = TempDir::new("hostile-folder");
    dir.file("a.json", FIFTEEN);
    let at = |name: &str| dir.0.join(name);
    std::os::unix::fs::symlink(at("absent.json"), at("dangling.json")).unwrap();
    std::os::unix::fs::symlink("/dev/zero", at("zero.json")).unwrap();
    let fifo = Command::new("mkfifo")
        .arg(at("fifo.json"))
        .status()
        .unwrap();
    assert!(fifo.success());
    let out = camloc(&["localize", "--input", dir.0.to_str().unwrap()]);
    let text = short_clean_lines(&out);
    assert_eq!(out.status.code(), Some(1), "{text}");
    for (name, kind) in [
        ("dangling.json", "dangling symbolic link"),
        ("zero.json", "character device"),
        ("fifo.json", "FIFO"),
    ] {
        assert!(text.contains(name) && text.contains(kind), "{name}: {text}");
    }
    assert!(String::from_utf8_lossy(&out.stdout).contains("p: camera"));
}

#[test]
fn a_closed_standard_output_is_an_error() {
    let input = fixture("keypoints/example.json");
    let script = format!("exec \"$0\" localize --input '{}' >&-", input.display());
    let out = shell(&script);
    assert_clean_failure(&out, "standard output");
    // Writing to /dev/null on purpose is fine, opened for writing or, as Python's
    // `subprocess.DEVNULL` opens it, for reading and writing (which camloc refused before).
    for redirect in [">/dev/null", "1<>/dev/null"] {
        let script = format!(
            "exec \"$0\" localize --input '{}' {redirect}",
            input.display()
        );
        let out = shell(&script);
        assert!(out.status.success(), "{redirect}: {}", stderr(&out));
    }
}

#[test]
fn converting_poses_without_any_landmark_says_so() {
    let dir = TempDir::new("hostile-nan");
    let mut npy = npy_head("{'descr': '<f8', 'fortran_order': False, 'shape': (2, 15, 2), }");
    for _ in 0..2 * 15 * 2 {
        npy.extend_from_slice(&f64::NAN.to_le_bytes());
    }
    let input = dir.0.join("nan.npy");
    std::fs::write(&input, npy).unwrap();
    let output = dir.0.join("out.json");
    let out = camloc(&[
        "convert",
        "--input",
        input.to_str().unwrap(),
        "--layout",
        "camloc15",
        "--to",
        "camloc",
        "--out",
        output.to_str().unwrap(),
    ]);
    assert_clean_failure(&out, "2 of 2 poses have no landmark");
}

#[test]
fn evaluate_uses_the_embedded_model_by_default() {
    let dir = TempDir::new("hostile-evaluate");
    let dataset = fixture_dataset(&dir);
    let out = success(&camloc(&["evaluate", "--dataset", &dataset, "--json"]));
    let report: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(report["samples"].as_u64().unwrap() >= 24, "{out}");
}

#[test]
fn a_sequence_longer_than_its_cap_is_refused() {
    let dir = TempDir::new("hostile-sequence-cap");
    let pose = r#"{"landmarks": {}}"#;
    let input = dir.file(
        "empty.json",
        &format!(r#"{{"poses": [{}]}}"#, [pose; 5].join(",")),
    );
    let run = |cap: &str| {
        let args = ["localize", "--input", &input, "--sequence"];
        camloc(&[&args[..], &["--sequence-max-poses", cap]].concat())
    };
    assert_clean_failure(&run("4"), "more than 4 poses for --sequence");
    // Poses without a landmark are frames the person is missing from; a sequence of only
    // such frames is an error.
    let out = run("5");
    let text = short_clean_lines(&out);
    assert!(
        text.contains("5 of 5 poses have no landmarks (nothing detected)"),
        "{text}"
    );
    assert_eq!(out.status.code(), Some(1));
}

/// Points whose v axis points up (people upside down in the image) are warned of; the same
/// people upright are not.
#[test]
fn an_input_with_v_up_is_warned_of() {
    let dir = TempDir::new("hostile-v-up");
    let fixture =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/keypoints/example.json");
    let mut doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(fixture).unwrap()).unwrap();
    let upright = dir.file("upright.json", &doc.to_string());
    for pose in doc["poses"].as_array_mut().unwrap() {
        for point in pose["landmarks"].as_object_mut().unwrap().values_mut() {
            if let Some(v) = point[1].as_f64() {
                point[1] = (-v).into();
            }
        }
    }
    let flipped = dir.file("flipped.json", &doc.to_string());
    for command in ["localize", "reconstruct"] {
        let out = camloc(&[command, "--input", &flipped, "--jsonl", "-q"]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(
            stderr.contains("3 of 3 poses have the head below both ankles"),
            "{command}: {stderr}"
        );
        let out = camloc(&[command, "--input", &upright, "--jsonl", "-q"]);
        assert!(!String::from_utf8_lossy(&out.stderr).contains("below"));
    }
}

/// Poses whose torsos lean alike (a camera rolled about its axis) are warned of, with the turn
/// that sets them upright; the same people upright are not.
#[test]
fn a_rolled_camera_is_warned_of() {
    let dir = TempDir::new("hostile-rolled");
    let fixture =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/keypoints/example.json");
    let mut doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(fixture).unwrap()).unwrap();
    // The example's three poses twice, then turned 90 degrees clockwise as shown (v down):
    // a portrait video read as landscape.
    let poses = doc["poses"].as_array().unwrap().clone();
    doc["poses"] = poses.iter().chain(&poses).cloned().collect();
    let upright = dir.file("upright.json", &doc.to_string());
    for pose in doc["poses"].as_array_mut().unwrap() {
        for point in pose["landmarks"].as_object_mut().unwrap().values_mut() {
            if let (Some(u), Some(v)) = (point[0].as_f64(), point[1].as_f64()) {
                *point = serde_json::json!([-v, u]);
            }
        }
    }
    let rolled = dir.file("rolled.json", &doc.to_string());
    for command in ["localize", "reconstruct"] {
        let out = camloc(&[command, "--input", &rolled, "--jsonl", "-q"]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(
            stderr.contains("lean") && stderr.contains("deg counterclockwise"),
            "{command}: {stderr}"
        );
        let out = camloc(&[command, "--input", &upright, "--jsonl", "-q"]);
        assert!(!String::from_utf8_lossy(&out.stderr).contains("lean"));
    }
}
