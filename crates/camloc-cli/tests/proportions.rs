//! `camloc reconstruct` in the person's own proportions: `--bone-lengths`, `--sequence` with
//! `--bone-lengths-out`, `--focal-px`, and their refusals.

mod common;
#[path = "common/walk.rs"]
mod walk;

use camloc::reconstruct::BONE_KEYS as KEYS;
use camloc::store::Persist;
use serde_json::Value;

use common::{TempDir, camloc, fixture, success};
use walk::walk_document;

/// The path of `name` in `dir` (not created).
fn path(dir: &TempDir, name: &str) -> String {
    dir.0.join(name).to_string_lossy().into_owned()
}

fn example() -> String {
    fixture("keypoints/example.json")
        .to_string_lossy()
        .into_owned()
}

const LENGTHS: [f64; 14] = [
    0.11, 0.44, 0.41, 0.11, 0.44, 0.41, 0.52, 0.16, 0.19, 0.30, 0.27, 0.19, 0.30, 0.27,
];

/// A bone lengths document with `lengths` (and the header).
fn document(lengths: &[f64]) -> String {
    let named: serde_json::Map<String, Value> = KEYS
        .iter()
        .zip(lengths)
        .map(|(k, l)| (k.to_string(), Value::from(*l)))
        .collect();
    serde_json::json!({"format": "camloc-bone-lengths", "version": 1, "unit": "m", "lengths": named})
        .to_string()
}

/// The `bone_lengths_m` of every pose of a JSON Lines output, in [`KEYS`] order.
fn lengths_of(stdout: &[u8]) -> Vec<Vec<f64>> {
    String::from_utf8_lossy(stdout)
        .lines()
        .map(|line| {
            let v: Value = serde_json::from_str(line).unwrap();
            KEYS.iter()
                .map(|k| v["bone_lengths_m"][k].as_f64().unwrap())
                .collect()
        })
        .collect()
}

#[test]
fn given_bone_lengths_are_what_every_pose_has() {
    let dir = TempDir::new("prop-given");
    let file = dir.file("lengths.json", &document(&LENGTHS));
    let out = camloc(&[
        "reconstruct",
        "--input",
        &example(),
        "--bone-lengths",
        &file,
        "--jsonl",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let poses = lengths_of(&out.stdout);
    assert_eq!(poses.len(), 3);
    for pose in &poses {
        for (got, want) in pose.iter().zip(LENGTHS) {
            assert!((got - want).abs() < 1e-9, "{got} vs {want}");
        }
    }
    // Estimated lengths differ from pose to pose (no shared person without --sequence).
    let free = camloc(&["reconstruct", "--input", &example(), "--jsonl"]);
    assert!(free.status.success());
    let free = lengths_of(&free.stdout);
    assert_ne!(free[0], free[1]);
}

#[test]
fn a_sequence_shares_one_set_of_lengths_and_writes_them() {
    let dir = TempDir::new("prop-sequence");
    let (lengths_out, npy) = (path(&dir, "person.json"), path(&dir, "poses.npy"));
    let args = [
        "reconstruct",
        "--input",
        &example(),
        "--sequence",
        "--jsonl",
        "--bone-lengths-out",
        &lengths_out,
        "--npy",
        &npy,
    ];
    let out = camloc(&args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let poses = lengths_of(&out.stdout);
    assert_eq!(poses.len(), 3);
    let written: Value =
        serde_json::from_str(&std::fs::read_to_string(&lengths_out).unwrap()).unwrap();
    assert_eq!(written["format"], "camloc-bone-lengths");
    // Whose lengths they are (a folder of videos' numbered files say it), not read back.
    assert_eq!(written["person"], "person 0", "{written}");
    for pose in &poses {
        for (got, key) in pose.iter().zip(KEYS) {
            let want = written["lengths"][key].as_f64().unwrap();
            assert!((got - want).abs() < 1e-9, "{key}: {got} vs {want}");
        }
    }
    // (3, 15, 3) float64: the header and 3 * 45 numbers.
    let bytes = std::fs::read(&npy).unwrap();
    assert!(bytes.len() > 3 * 45 * 8 && bytes.len() < 3 * 45 * 8 + 256);
    // Nothing is overwritten without --force; the written lengths read back as input.
    let again = camloc(&args);
    assert!(!again.status.success());
    let reread = camloc(&[
        "reconstruct",
        "--input",
        &example(),
        "--bone-lengths",
        &lengths_out,
    ]);
    assert!(
        reread.status.success(),
        "{}",
        String::from_utf8_lossy(&reread.stderr)
    );
}

/// The standing height of lengths in [`KEYS`] order: the legs over 0.491.
fn standing_height(lengths: &[f64]) -> f64 {
    (lengths[1] + lengths[2] + lengths[4] + lengths[5]) / 2.0 / 0.491
}

#[test]
fn a_person_height_scales_every_answer_and_the_sequence_lengths() {
    let dir = TempDir::new("prop-height");
    let lengths_out = path(&dir, "person.json");
    let out = camloc(&[
        "reconstruct",
        "--input",
        &example(),
        "--person-height",
        "1.62",
        "--jsonl",
    ]);
    let poses = lengths_of(success(&out).as_bytes());
    assert_eq!(poses.len(), 3);
    for pose in &poses {
        assert!((standing_height(pose) - 1.62).abs() < 1e-9, "{pose:?}");
    }
    let sequence = camloc(&[
        "reconstruct",
        "--input",
        &example(),
        "--sequence",
        "--person-height",
        "0.95",
        "--bone-lengths-out",
        &lengths_out,
    ]);
    success(&sequence);
    let written: Value =
        serde_json::from_str(&std::fs::read_to_string(&lengths_out).unwrap()).unwrap();
    let lengths: Vec<f64> = KEYS
        .iter()
        .map(|k| written["lengths"][k].as_f64().unwrap())
        .collect();
    assert!(
        (standing_height(&lengths) - 0.95).abs() < 1e-4,
        "{lengths:?}"
    );
    // The lengths written for the tallest and the smallest heights are read back (2.6 m came
    // back as 2.6000000000000005 and was refused).
    for height in ["2.6", "0.5"] {
        let written = path(&dir, &format!("person-{height}.json"));
        success(&camloc(&[
            "reconstruct",
            "--input",
            &example(),
            "--sequence",
            "--person-height",
            height,
            "--bone-lengths-out",
            &written,
        ]));
        success(&camloc(&[
            "reconstruct",
            "--input",
            &example(),
            "--bone-lengths",
            &written,
        ]));
    }
    // Centimetres are refused with the metres they meant; given lengths give the size.
    let cm = camloc(&[
        "reconstruct",
        "--input",
        &example(),
        "--person-height",
        "175",
    ]);
    assert_eq!(cm.status.code(), Some(2));
    let message = String::from_utf8_lossy(&cm.stderr);
    assert!(message.contains("175 cm is 1.75 m"), "{message}");
    // A negative value is the option's (not another option), a tiny one is shown short.
    for (value, shown) in [("-1.7", "-1.7 m is not"), ("1e-300", "1e-300 m is not")] {
        let out = camloc(&[
            "reconstruct",
            "--input",
            &example(),
            "--person-height",
            value,
        ]);
        assert_eq!(out.status.code(), Some(2));
        let message = String::from_utf8_lossy(&out.stderr);
        assert!(message.contains(shown), "{message}");
    }
    let file = dir.file("lengths.json", &document(&LENGTHS));
    let both = camloc(&[
        "reconstruct",
        "--input",
        &example(),
        "--person-height",
        "1.7",
        "--bone-lengths",
        &file,
    ]);
    assert!(!both.status.success());
    assert!(String::from_utf8_lossy(&both.stderr).contains("cannot be used with"));
}

#[test]
fn a_focal_length_adds_the_perspective_camera() {
    let out = camloc(&[
        "reconstruct",
        "--input",
        &example(),
        "--focal-px",
        "800",
        "--principal-point",
        "320,240",
        "--jsonl",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for line in String::from_utf8_lossy(&out.stdout).lines() {
        let v: Value = serde_json::from_str(line).unwrap();
        assert_eq!(v["perspective"]["focal_px"], 800.0);
        assert!(v["perspective"]["translation_m"][2].as_f64().unwrap() > 0.0);
    }
    for bad in ["0", "-5", "nan", "inf", "x"] {
        let out = camloc(&["reconstruct", "--input", &example(), "--focal-px", bad]);
        assert!(!out.status.success(), "--focal-px {bad} accepted");
    }
    let out = camloc(&[
        "reconstruct",
        "--input",
        &example(),
        "--principal-point",
        "1,2",
    ]);
    assert!(
        !out.status.success(),
        "--principal-point without --focal-px"
    );
    // A focal length alone puts each pose's principal point at its own box, and says so.
    let warning = "--focal-px without --principal-point or --image-size: each pose's principal";
    let stderr = |extra: &[&str]| {
        let out = camloc(&[&["reconstruct", "--input", &example(), "-q"], extra].concat());
        assert!(out.status.success());
        String::from_utf8(out.stderr).unwrap()
    };
    assert!(stderr(&["--focal-px", "800"]).contains(warning));
    assert!(!stderr(&["--focal-px", "800", "--image-size", "640,480"]).contains(warning));
    assert!(!stderr(&["--focal-px", "800", "--principal-point", "1,2"]).contains(warning));
}

#[test]
fn bad_bone_lengths_files_are_refused_with_what_and_where() {
    let dir = TempDir::new("prop-bad");
    let mut centimetres = LENGTHS;
    centimetres[6] = 52.0;
    let missing = document(&LENGTHS).replace("\"torso\"", "\"trunk\"");
    let two_missing = document(&LENGTHS[..6]);
    let all_centimetres = LENGTHS.map(|l| 100.0 * l);
    // A short person's lengths in feet pass every limb's range but make a person of 4.6 m (a
    // simulated animator's file made one of 5.6 m); a taller one's torso is past the range.
    let short_in_feet = LENGTHS.map(|l| 0.8 * l / 0.3048);
    let all_feet = LENGTHS.map(|l| l / 0.3048);
    let cases = [
        (
            document(&short_in_feet),
            "m tall, taller than a person (2.6 m at most; lengths are in metres; they look like \
             feet: divide by 3.28)",
        ),
        (document(&all_feet), "all 14 look like feet: divide by 3.28"),
        (document(&centimetres), "torso"),
        (missing, "trunk"),
        (
            two_missing,
            "missing limb(s) \"torso\", \"neck_head\", \"left_collar\"",
        ),
        (
            format!("{{\"lengths\": {}}}", Value::from(LENGTHS.to_vec())),
            "expected an object of the 14 limbs' lengths by name",
        ),
        (
            document(&all_centimetres),
            "look like centimetres: divide by 100",
        ),
        (
            Value::from(LENGTHS.to_vec()).to_string(),
            "the document is a list",
        ),
        ("{\"lengths\": ".to_string(), "line 1"),
        (
            document(&LENGTHS).replace("\"unit\":\"m\"", "\"unit\":\"mm\""),
            "unit",
        ),
        ("x".repeat(70_000), "larger than"),
    ];
    for (n, (text, named)) in cases.iter().enumerate() {
        let file = dir.file(&format!("bad-{n}.json"), text);
        let out = camloc(&[
            "reconstruct",
            "--input",
            &example(),
            "--bone-lengths",
            &file,
        ]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "case {n} accepted");
        assert!(stderr.contains(named), "case {n}: {stderr}");
        assert!(stderr.contains("bad-"), "case {n} names no file: {stderr}");
    }
    let out = camloc(&[
        "reconstruct",
        "--input",
        &example(),
        "--bone-lengths",
        &path(&dir, "absent.json"),
    ]);
    assert!(!out.status.success());
    // A byte-order mark, as some editors write, is no error.
    let marked = dir.file("bom.json", &format!("\u{feff}{}", document(&LENGTHS)));
    let out = camloc(&[
        "reconstruct",
        "--input",
        &example(),
        "--bone-lengths",
        &marked,
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The embedded depth lifter is the default of `hybrid`; `--no-lifter` gives the pursuit's
/// pose (another answer), `--lifter FILE` with the embedded lifter saved to a file and
/// `--model FILE` with the embedded model's file the default's answer, the embedded lifter of
/// skeletons' own placement alone (its file in fixtures/, without the midpoint placement's)
/// another one for the example's detector landmarks, and a lifter with `--camera opt` or a
/// file of another kind is refused.
#[test]
fn the_depth_lifter_is_the_default_and_can_be_chosen_or_refused() {
    let example = example();
    let run = |extra: &[&str]| {
        let mut args: Vec<&str> = vec!["reconstruct", "--input", &example, "--jsonl"];
        args.extend_from_slice(extra);
        camloc(&args)
    };
    let dir = TempDir::new("lifter-choice");
    let lifter = dir.0.join("both.bin");
    camloc::DepthLifter::default_lifter()
        .unwrap()
        .save(&lifter, false)
        .unwrap();
    let lifter = lifter.to_string_lossy().into_owned();
    let default = run(&[]);
    assert!(default.status.success());
    let explicit = run(&["--lifter", &lifter]);
    assert_eq!(default.stdout, explicit.stdout);
    let own_only = fixture("default-lifter.bin").to_string_lossy().into_owned();
    let own_only = run(&["--lifter", &own_only]);
    assert!(own_only.status.success());
    assert_ne!(default.stdout, own_only.stdout);
    let without = run(&["--no-lifter"]);
    assert!(without.status.success());
    assert_ne!(default.stdout, without.stdout);
    let opt = run(&["--camera", "opt", "--lifter", &lifter]);
    assert!(!opt.status.success());
    assert!(String::from_utf8_lossy(&opt.stderr).contains("--lifter"));
    let model = fixture("default-model.bin").to_string_lossy().into_owned();
    // A model file of Table 1's cameras keeps the lifter (as Python's reconstruct does).
    assert_eq!(run(&["--model", &model]).stdout, default.stdout);
    let wrong = run(&["--lifter", &model]);
    assert!(!wrong.status.success());
    assert!(String::from_utf8_lossy(&wrong.stderr).contains("depth lifter"));
}

/// `fixtures/keypoints/example.json` with the poses at `broken` cut to their head (no torso
/// and too few landmarks to fill one in: they cannot be reconstructed), written to `dir`.
fn with_broken_poses(dir: &TempDir, broken: &[usize]) -> String {
    let mut doc: Value =
        serde_json::from_str(&std::fs::read_to_string(example()).unwrap()).unwrap();
    for &i in broken {
        let head = doc["poses"][i]["landmarks"]["head"].clone();
        doc["poses"][i]["landmarks"] = serde_json::json!({ "head": head });
    }
    let out = path(dir, "broken.json");
    std::fs::write(&out, doc.to_string()).unwrap();
    out
}

#[test]
fn sequence_drawings_are_numbered_by_input_position_and_failed_people_get_no_lengths() {
    let dir = TempDir::new("broken-sequence");
    // The middle pose fails: the drawings are the first and the third, as without --sequence.
    let input = with_broken_poses(&dir, &[1]);
    let svg = path(&dir, "r.svg");
    let out = camloc(&[
        "reconstruct",
        "--input",
        &input,
        "--sequence",
        "--svg",
        &svg,
        "-q",
    ]);
    assert_eq!(
        out.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let exists = |name: &str| dir.0.join(name).exists();
    assert!(exists("r-001.svg") && !exists("r-002.svg") && exists("r-003.svg"));
    // Every pose fails: no lengths file (they would be the prior's), and the user is told.
    let input = with_broken_poses(&dir, &[0, 1, 2]);
    let lengths = path(&dir, "lengths.json");
    let out = camloc(&[
        "reconstruct",
        "--input",
        &input,
        "--sequence",
        "--bone-lengths-out",
        &lengths,
        "-q",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(!exists("lengths.json"));
    assert!(stderr.contains("no bone lengths for person 0"), "{stderr}");
}

/// With `--sequence`, bone lengths that fit the person's frames worse than lengths estimated
/// from them (a simulated animator's file with the thighs and forearms swapped) are warned of;
/// the person's own estimated lengths given back are not.
#[test]
fn given_lengths_that_fit_the_frames_worse_than_estimated_ones_are_warned_of() {
    let dir = TempDir::new("prop-fit");
    let input = dir.file("walk.json", &walk_document(0..20).to_string());
    let own = path(&dir, "own.json");
    success(&camloc(&[
        "reconstruct",
        "--input",
        &input,
        "--sequence",
        "--bone-lengths-out",
        &own,
        "-q",
    ]));
    let run = |lengths: &str| {
        let out = camloc(&[
            "reconstruct",
            "--input",
            &input,
            "--sequence",
            "--bone-lengths",
            lengths,
            "-q",
        ]);
        assert!(out.status.success());
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    let said = "the bone lengths given fit its 20 frames worse than lengths estimated from them";
    let own_run = run(&own);
    assert!(!own_run.contains(said), "{own_run}");
    let mut swapped = LENGTHS;
    swapped.swap(1, 10);
    swapped.swap(4, 13);
    let warned = run(&dir.file("swapped.json", &document(&swapped)));
    assert!(warned.contains(said), "{warned}");
    // The text output's person line gives both errors.
    let text = success(&camloc(&[
        "reconstruct",
        "--input",
        &input,
        "--sequence",
        "--bone-lengths",
        &own,
    ]));
    let person = text.lines().find(|l| l.starts_with("person 0 (20 frames)"));
    assert!(
        person.is_some_and(|l| l.contains("(given; median reprojection error ")),
        "{text}"
    );
}
