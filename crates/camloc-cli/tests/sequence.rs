//! `camloc localize --sequence`: a folder of OpenPose frames (made here from the fixture poses)
//! with a turn and a few corrupted frames is smoothed back to the viewpoint of each part, and
//! the timeline drawings are written all or nothing.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

fn camloc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_camloc"))
        .args(args)
        .output()
        .expect("the camloc binary runs")
}

/// A fresh folder under the system's temporary folder, removed when dropped.
struct TempDir(PathBuf);

impl TempDir {
    fn new(name: &str) -> TempDir {
        let dir = std::env::temp_dir().join(format!("camloc-seq-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        TempDir(dir)
    }
    fn path(&self, name: &str) -> String {
        self.0.join(name).to_string_lossy().into_owned()
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// The BODY_25 `pose_keypoints_2d` of the three fixture poses (front standing, left-side
/// walking, upper front reaching), from the OpenPose samples.
fn fixture_people() -> Vec<Value> {
    let dir =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/keypoints/samples/openpose");
    let mut people = Vec::new();
    for n in 0..2 {
        let file = dir.join(format!("clip_00000000000{n}_keypoints.json"));
        let json: Value = serde_json::from_str(&std::fs::read_to_string(file).unwrap()).unwrap();
        for person in json["people"].as_array().unwrap() {
            people.push(person["pose_keypoints_2d"].clone());
        }
    }
    assert_eq!(people.len(), 3);
    people
}

/// BODY_25 keypoints moved `dx` px to the right (undetected points stay at 0): the fixture's
/// poses overlap (20 px apart, as one detection's duplicate would), so people of one frame
/// are moved apart.
fn moved_right(keypoints: &Value, dx: f64) -> Value {
    let mut out = keypoints.clone();
    for (i, v) in out.as_array_mut().unwrap().iter_mut().enumerate() {
        let x = v.as_f64().unwrap();
        if i % 3 == 0 && x != 0.0 {
            *v = (x + dx).into();
        }
    }
    out
}

/// BODY_25 keypoints (x, y, score triples) with every left point and its right twin swapped.
fn left_right_swapped(keypoints: &Value) -> Value {
    let mut out = keypoints.clone();
    let pairs = [
        (2, 5),
        (3, 6),
        (4, 7),
        (9, 12),
        (10, 13),
        (11, 14),
        (15, 16),
        (17, 18),
        (19, 22),
        (20, 23),
        (21, 24),
    ];
    for (left, right) in pairs {
        for c in 0..3 {
            out[left * 3 + c] = keypoints[right * 3 + c].clone();
            out[right * 3 + c] = keypoints[left * 3 + c].clone();
        }
    }
    out
}

/// Writes frame `t` of a video holding the given people's keypoints.
fn write_frame(dir: &TempDir, t: usize, people: &[&Value]) {
    let untracked: Vec<(&Value, i64)> = people.iter().map(|&k| (k, -1)).collect();
    write_frame_with_ids(dir, t, &untracked);
}

/// `camloc localize --sequence --jsonl -q` of the frame files in `dir`, which must succeed: its
/// output and its standard error.
fn localized_video(dir: &TempDir) -> (Output, String) {
    let out = camloc(&[
        "localize",
        "--input",
        &dir.path(""),
        "--sequence",
        "-q",
        "--jsonl",
    ]);
    assert!(out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    (out, stderr)
}

/// An OpenPose frame file of `people`, each with its `person_id` (-1: untracked).
fn write_frame_with_ids(dir: &TempDir, t: usize, people: &[(&Value, i64)]) {
    let people: Vec<Value> = people
        .iter()
        .map(|(k, id)| serde_json::json!({ "person_id": [id], "pose_keypoints_2d": k }))
        .collect();
    let json = serde_json::json!({ "version": 1.3, "people": people });
    std::fs::write(
        dir.path(&format!("video_{t:012}_keypoints.json")),
        json.to_string(),
    )
    .unwrap();
}

fn json_lines(out: &Output) -> Vec<Value> {
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

/// The per-pose labels of the three fixture poses, as `camloc localize` gives them.
/// `name` names the scratch folder (tests run in parallel).
fn raw_labels(people: &[Value], name: &str) -> Vec<Value> {
    let dir = TempDir::new(name);
    for (t, k) in people.iter().enumerate() {
        write_frame(&dir, t, &[k]);
    }
    let out = camloc(&["localize", "--input", &dir.path(""), "--jsonl"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    json_lines(&out)
        .iter()
        .map(|o| o["label"].clone())
        .collect()
}

#[test]
fn a_turn_with_corrupted_frames_is_smoothed() {
    let mut people = fixture_people();
    // The corrupted frames: the front pose with its left and right points swapped, which is
    // how that body looks from behind (the fixture's third pose, drawn from above, is too
    // near the front camera's level to be told apart from it reliably).
    people[2] = left_right_swapped(&people[0]);
    let labels = raw_labels(&people, "raw-turn");
    // The corrupted frames are seen from another camera than both parts.
    assert_ne!(labels[2], labels[0]);
    assert_ne!(labels[2], labels[1]);
    assert_ne!(labels[0], labels[1]);
    let dir = TempDir::new("turn");
    let frames = dir.path("frames");
    std::fs::create_dir(&frames).unwrap();
    let frames_dir = TempDir(PathBuf::from(&frames));
    // Frames 0..80 front, 80..200 the person turned to show the left side; isolated frames of
    // the third pose, and one frame whose pose has no torso and too few joints (7) to fill
    // one in (it cannot be localized).
    let corrupted = [13, 41, 42 + 20, 120, 157];
    let broken = 99;
    let mut torso_less = people[1].clone();
    for joint in [1, 2, 3, 4, 5, 8, 9, 12] {
        torso_less[joint * 3 + 2] = serde_json::json!(0.0);
    }
    for t in 0..200 {
        let part = usize::from(t >= 80);
        let k = if corrupted.contains(&t) {
            &people[2]
        } else if t == broken {
            &torso_less
        } else {
            &people[part]
        };
        write_frame(&frames_dir, t, &[k]);
    }
    let svg = dir.path("timeline.svg");
    let out = camloc(&[
        "localize",
        "--input",
        &frames,
        "--sequence",
        "--jsonl",
        "--svg",
        &svg,
        "--quiet",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    // The torso-less frame is a failed pose: reported, exit 1, the run completes.
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("1 of 200 poses"), "{stderr}");
    let objects = json_lines(&out);
    assert_eq!(objects.len(), 200);
    for (t, o) in objects.iter().enumerate() {
        assert_eq!(o["frame"].as_u64(), Some(t as u64));
        let expected = &labels[usize::from(t >= 80)];
        assert_eq!(&o["smoothed_label"], expected, "frame {t}: {o}");
        let p = o["smoothed_probability"].as_f64().unwrap();
        assert!(p > 0.5 && p <= 1.0, "frame {t}: {o}");
        if corrupted.contains(&t) {
            // Read as is, or, where its limbs are swapped back (the corruption is the front
            // pose's left and right swapped), the front pose again in the front part; a
            // stranger pose in the side part.
            match o.get("swapped_sides") {
                None => assert_eq!(o["label"], labels[2], "frame {t}: {o}"),
                Some(sides) if t < 80 => {
                    assert_eq!(
                        sides,
                        &serde_json::json!(["legs", "arms"]),
                        "frame {t}: {o}"
                    );
                    assert_eq!(o["label"], labels[0], "frame {t}: {o}");
                }
                Some(_) => {}
            }
        } else if t == broken {
            assert!(o["label"].is_null() && o["error"].is_string(), "{o}");
        } else {
            assert_eq!(&o["label"], expected, "frame {t}");
        }
        // Each localized frame's own viewpoint has its uncertainty, as `localize` gives it.
        let uncertainty = o["uncertainty_deg"].as_f64();
        assert_eq!(uncertainty.is_some(), t != broken, "frame {t}: {o}");
        assert!(
            uncertainty.is_none_or(|u| u > 0.0 && u < 180.0),
            "frame {t}: {o}"
        );
        // The smoothed viewpoint: none for the frame that was not localized; the frame's own
        // where the 7 frames around it are the same pose; nearer the part's than its own at
        // a corrupted frame.
        let viewpoint = |o: &Value, key: &str| {
            let (a, e) = (
                &o[format!("{key}azimuth_deg")],
                &o[format!("{key}elevation_deg")],
            );
            a.as_f64().zip(e.as_f64())
        };
        let smoothed = viewpoint(o, "smoothed_");
        let window = t.saturating_sub(3)..=(t + 3).min(199);
        let steady = window
            .clone()
            .all(|u| !corrupted.contains(&u) && u != broken && (u >= 80) == (t >= 80));
        if t == broken {
            assert_eq!(smoothed, None, "{o}");
        } else if steady {
            let (own, smoothed) = (viewpoint(o, "").unwrap(), smoothed.unwrap());
            assert!((own.0 - smoothed.0).abs() < 1e-3 && (own.1 - smoothed.1).abs() < 1e-3);
        } else if corrupted.contains(&t) {
            let part = viewpoint(&objects[t - 2], "").unwrap();
            let own = viewpoint(o, "").unwrap();
            let off = |v: (f64, f64)| ((v.0 - part.0 + 540.0).rem_euclid(360.0) - 180.0).abs();
            // Swapped back, the frame is the part's pose again (the mirror-symmetric model
            // gives it the part's viewpoint); read as it is, the smoothing takes it nearer.
            let (own, smoothed) = (off(own), off(smoothed.unwrap()));
            assert!(
                smoothed < own || (own < 1e-3 && smoothed < 1e-3),
                "frame {t}: {o}"
            );
        }
    }
    let drawing = std::fs::read_to_string(&svg).unwrap();
    assert!(drawing.starts_with("<svg") && drawing.trim_end().ends_with("</svg>"));
    assert!(drawing.contains("person 0, 200 frames"), "{drawing}");
    // The axis names the first and last frame numbers.
    assert!(drawing.contains(">frame 0<") && drawing.contains(">frame 199<"));
    // The timeline exists now: without --force it is refused and left as it is.
    let again = camloc(&[
        "localize",
        "--input",
        &frames,
        "--sequence",
        "--svg",
        &svg,
        "--quiet",
    ]);
    assert_eq!(again.status.code(), Some(1));
    assert_eq!(std::fs::read_to_string(&svg).unwrap(), drawing);
}

#[test]
fn persons_are_separate_sequences() {
    let people = fixture_people();
    let labels = raw_labels(&people, "raw-persons");
    let dir = TempDir::new("persons");
    let frames = dir.path("frames");
    std::fs::create_dir(&frames).unwrap();
    let frames_dir = TempDir(PathBuf::from(&frames));
    // Person 0 is seen from the front, person 1 from the left, in every frame.
    let beside = moved_right(&people[1], 300.0);
    for t in 0..30 {
        write_frame(&frames_dir, t, &[&people[0], &beside]);
    }
    let svg = dir.path("people.svg");
    let out = camloc(&[
        "localize",
        "--input",
        &frames,
        "--sequence",
        "--json",
        "--svg",
        &svg,
        "--quiet",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let objects: Vec<Value> = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(objects.len(), 60);
    for (n, o) in objects.iter().enumerate() {
        let person = n / 30;
        assert_eq!(o["person"].as_u64(), Some(person as u64), "{o}");
        assert_eq!(o["frame"].as_u64(), Some((n % 30) as u64), "{o}");
        assert_eq!(o["smoothed_label"], labels[person]);
    }
    for n in 1..=2 {
        let drawing = std::fs::read_to_string(dir.path(&format!("people-00{n}.svg"))).unwrap();
        assert!(drawing.contains(&format!("person {}, 30 frames", n - 1)));
    }
    assert!(!Path::new(&svg).exists());
}

/// A person none of whose frames can be localized (only a hip and a knee seen) gets no
/// smoothed camera: null in JSON, said so in text; the other person is smoothed as usual.
#[test]
fn a_person_never_localized_has_no_smoothed_camera() {
    let people = fixture_people();
    let dir = TempDir::new("never");
    let frames = dir.path("frames");
    std::fs::create_dir(&frames).unwrap();
    let frames_dir = TempDir(PathBuf::from(&frames));
    let mut hidden = people[1].clone();
    for joint in 0..25 {
        if joint != 9 && joint != 10 {
            hidden[joint * 3 + 2] = serde_json::json!(0.0);
        }
    }
    for t in 0..5 {
        write_frame(&frames_dir, t, &[&people[0], &hidden]);
    }
    let out = camloc(&["localize", "--input", &frames, "--sequence", "--jsonl"]);
    assert_eq!(out.status.code(), Some(1));
    let objects = json_lines(&out);
    assert_eq!(objects.len(), 10);
    for o in &objects {
        let never = o["person"].as_u64() == Some(1);
        assert_eq!(o["smoothed_label"].is_null(), never, "{o}");
        assert_eq!(o["smoothed_probability"].is_null(), never, "{o}");
    }
    let text = camloc(&["localize", "--input", &frames, "--sequence"]);
    let stdout = String::from_utf8_lossy(&text.stdout);
    assert_eq!(stdout.matches("no smoothed camera").count(), 5, "{stdout}");
}

/// Two videos' frames read as one input (two folders with `--recursive`) hold the same frame
/// and person numbers: the user is warned that they are taken as one person's.
#[test]
fn repeated_frame_numbers_are_warned_of() {
    let people = fixture_people();
    let dir = TempDir::new("repeated");
    for camera in ["a", "b"] {
        let folder = TempDir(dir.0.join(camera));
        std::fs::create_dir(&folder.0).unwrap();
        for t in 0..3 {
            write_frame(&folder, t, &[&people[0]]);
        }
        std::mem::forget(folder);
    }
    let root = dir.path("");
    let out = camloc(&[
        "localize",
        "--input",
        &root,
        "--recursive",
        "--sequence",
        "-q",
    ]);
    assert!(out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("3 poses repeat the frame and person numbers"),
        "{stderr}"
    );
    let once = camloc(&["localize", "--input", &dir.path("a"), "--sequence", "-q"]);
    assert!(!String::from_utf8_lossy(&once.stderr).contains("repeat"));
}

/// The fixture video's frame 1 has a second pose, left out of person 0's sequence: the
/// person's timeline has its two frames, not a third slot with the left-out pose's camera.
#[test]
fn a_pose_left_out_of_a_sequence_is_not_on_its_timeline() {
    let dir = TempDir::new("left-out-timeline");
    let fixture =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/keypoints/samples/openpose");
    let svg = dir.path("timeline.svg");
    let out = camloc(&[
        "localize",
        "--input",
        &fixture.to_string_lossy(),
        "--sequence",
        "--svg",
        &svg,
        "-q",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let drawing = std::fs::read_to_string(&svg).unwrap();
    assert!(drawing.contains("person 0, 2 frames"), "{drawing}");
    // A frame whose pose jumps far from the frames around it is an outlier, left out of the
    // smoothing but not of the time line: 40 frames, 40 slots.
    let people = fixture_people();
    let video = TempDir::new("outlier-timeline");
    let far = moved_right(&people[0], 900.0);
    for t in 0..40 {
        write_frame(&video, t, &[if t == 20 { &far } else { &people[0] }]);
    }
    let svg = video.path("timeline.svg");
    let out = camloc(&[
        "localize",
        "--input",
        &video.path(""),
        "--sequence",
        "--svg",
        &svg,
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success() && stderr.contains("apart from"),
        "{stderr}"
    );
    let drawing = std::fs::read_to_string(&svg).unwrap();
    assert!(drawing.contains("person 0, 40 frames"), "{drawing}");
}

/// OpenPose without tracking numbers people in the detector's order, which changes as people
/// come and go: camloc follows each person by where it is, so a change of that order leaves
/// every person's frames its own; a tracker's ids are kept as given, and ids that swap two
/// people are warned of as a jump.
#[test]
fn untracked_people_are_followed_and_tracked_ids_kept() {
    let people = fixture_people();
    // Another person 600 px to the right.
    let other = moved_right(&people[0], 600.0);
    for tracked in [false, true] {
        let dir = TempDir::new(if tracked { "tracked" } else { "untracked" });
        for t in 0..8 {
            let order = if t < 4 {
                [&people[0], &other]
            } else {
                [&other, &people[0]]
            };
            let listed: Vec<(&Value, i64)> = order
                .into_iter()
                .enumerate()
                .map(|(p, k)| (k, if tracked { p as i64 } else { -1 }))
                .collect();
            write_frame_with_ids(&dir, t, &listed);
        }
        let (out, stderr) = localized_video(&dir);
        for line in json_lines(&out) {
            let (frame, person) = (line["frame"].as_u64().unwrap(), line["person"].as_u64());
            let listed = line["source"].as_str().unwrap().ends_with("people[0]");
            // Untracked: person 0 is the pose listed first in frame 0 throughout.
            let expected = if tracked || frame < 4 {
                !listed
            } else {
                listed
            };
            assert_eq!(person, Some(u64::from(expected)), "{line}");
        }
        if tracked {
            for person in [0, 1] {
                assert!(
                    stderr.contains(&format!(
                        "person {person}: the pose jumps across the image or changes size \
                         from one frame to the next once (first at frame 4)"
                    )),
                    "{stderr}"
                );
            }
        } else {
            assert!(!stderr.contains("jumps"), "{stderr}");
        }
        // `convert` writes the persons followed (camloc JSON's `person` is an identity).
        let out_dir = TempDir::new(if tracked {
            "tracked-out"
        } else {
            "untracked-out"
        });
        let json = out_dir.path("converted.json");
        let out = camloc(&[
            "convert",
            "--input",
            &dir.path(""),
            "--to",
            "camloc",
            "--out",
            &json,
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let converted: Value =
            serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
        let poses = converted["poses"].as_array().unwrap();
        assert_eq!(poses.len(), 16);
        for pose in poses {
            let (frame, person) = (pose["frame"].as_u64().unwrap(), pose["person"].as_u64());
            let listed = pose["id"].as_str().unwrap().ends_with("/0");
            let expected = if tracked || frame < 4 {
                !listed
            } else {
                listed
            };
            assert_eq!(person, Some(u64::from(expected)), "{pose}");
        }
    }
}

/// Untracked people followed: a detection seen in 2 frames of a 40-frame video (a false
/// detection on the background) is named as a brief person, and a walker who vanishes and
/// reappears nearly five torsos further on a few frames later, beside another walker (a
/// person the following lost), as a person that may continue the first.
#[test]
fn brief_persons_and_lost_ones_are_warned_of() {
    let walker = fixture_people().swap_remove(0);
    let (other, false_detection) = (moved_right(&walker, 900.0), moved_right(&walker, 1800.0));
    let dir = TempDir::new("brief-and-lost");
    for t in 0..40 {
        // The walker moves 2 px a frame; it is missed at frames 20-23 and reappears 400 px
        // to the right, beyond its reach.
        let shift = 2.0 * t as f64 + if t >= 24 { 400.0 } else { 0.0 };
        let here = moved_right(&walker, shift);
        let mut people: Vec<&Value> = vec![&other];
        if !(20..24).contains(&t) {
            people.insert(0, &here);
        }
        if t == 10 || t == 11 {
            people.push(&false_detection);
        }
        write_frame(&dir, t, &people);
    }
    let (_, stderr) = localized_video(&dir);
    assert!(
        stderr.contains("persons seen for under a third of a second: person 2 (2 poses)"),
        "{stderr}"
    );
    assert!(
        stderr.contains("person 3 (from frame 24) after person 0 (to frame 19)"),
        "{stderr}"
    );
}

/// A COCO results list of a video: `image_id` is the frame and `track_id` the person, so two
/// tracked people are two sequences; without `track_id` they are one, which is warned of.
#[test]
fn coco_track_ids_keep_people_apart() {
    let fixture = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/keypoints/tiny_coco_results.json");
    let results: Value = serde_json::from_str(&std::fs::read_to_string(fixture).unwrap()).unwrap();
    let (a, b) = (&results[0]["keypoints"], &results[1]["keypoints"]);
    let dir = TempDir::new("coco-tracks");
    for tracked in [true, false] {
        let entries: Vec<Value> = (0..3)
            .flat_map(|t| {
                [(a, 5), (b, 9)].map(|(k, track)| {
                    let mut e =
                        serde_json::json!({"image_id": t, "category_id": 1, "keypoints": k});
                    if tracked {
                        e["track_id"] = track.into();
                    }
                    e
                })
            })
            .collect();
        let file = dir.path(&format!("results-{tracked}.json"));
        std::fs::write(&file, Value::from(entries).to_string()).unwrap();
        let out = camloc(&["localize", "--input", &file, "--sequence", "--jsonl", "-q"]);
        assert!(out.status.success());
        let objects = json_lines(&out);
        let stderr = String::from_utf8_lossy(&out.stderr);
        if tracked {
            let keys: Vec<(u64, u64)> = objects
                .iter()
                .map(|o| (o["person"].as_u64().unwrap(), o["frame"].as_u64().unwrap()))
                .collect();
            assert_eq!(keys, [(5, 0), (5, 1), (5, 2), (9, 0), (9, 1), (9, 2)]);
            assert!(stderr.is_empty(), "{stderr}");
        } else {
            assert!(objects.iter().all(|o| o["person"].is_null()));
            assert!(
                stderr.contains("3 poses repeat the frame and person numbers"),
                "{stderr}"
            );
        }
    }
}

/// A frame without a single landmark (nothing detected) is a frame the person is missing from,
/// not a failure: noted once, its JSON object says so, the exit code stays 0, for `localize`
/// and `reconstruct` alike; outside `--sequence` it is a failed pose.
#[test]
fn frames_with_nothing_detected_are_gaps_of_a_sequence() {
    let fixture =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/keypoints/example.json");
    let mut doc: Value = serde_json::from_str(&std::fs::read_to_string(fixture).unwrap()).unwrap();
    let first = doc["poses"][0]["landmarks"].clone();
    let poses: Vec<Value> = (0..6)
        .map(|t| {
            let mut landmarks = if t == 3 {
                serde_json::json!({})
            } else {
                first.clone()
            };
            if t == 2 {
                landmarks.as_object_mut().unwrap().remove("left_wrist");
            }
            serde_json::json!({"id": format!("f{t}"), "frame": t, "landmarks": landmarks})
        })
        .collect();
    doc["poses"] = poses.into();
    let dir = TempDir::new("nothing");
    let file = dir.path("video.json");
    std::fs::write(&file, doc.to_string()).unwrap();
    for command in ["localize", "reconstruct"] {
        let out = camloc(&[command, "--input", &file, "--sequence", "--jsonl", "-q"]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{command}: {stderr}");
        assert!(
            stderr.contains("1 of 6 poses have no landmarks (nothing detected)"),
            "{command}: {stderr}"
        );
        let objects = json_lines(&out);
        let gap = objects.iter().find(|o| o["id"] == "f3").unwrap();
        let error = gap["error"].as_str().unwrap();
        assert!(
            error.ends_with("the pose has no landmarks (nothing detected)"),
            "{gap}"
        );
        if command == "localize" {
            // Each frame names what `localize` names: the landmarks missing and filled in.
            let f2 = objects.iter().find(|o| o["id"] == "f2").unwrap();
            assert_eq!(f2["missing"], serde_json::json!(["left_wrist"]), "{f2}");
            let f0 = objects.iter().find(|o| o["id"] == "f0").unwrap();
            assert_eq!(f0["missing"], serde_json::json!([]), "{f0}");
        }
        let single = camloc(&[command, "--input", &file, "--jsonl", "-q"]);
        assert_eq!(single.status.code(), Some(1), "{command}");
    }
}

/// A folder whose files are videos of their own (a camera's `.npy` array each, rows numbered
/// from 0) is a video per file: no poses repeat, and each file's frames are smoothed as when
/// it is read alone (they had been one video, every camera's smoothed camera the first's).
#[test]
fn a_folder_of_videos_is_smoothed_a_video_per_file() {
    let dir = TempDir::new("videos");
    let take = TempDir(dir.0.join("take"));
    std::fs::create_dir(&take.0).unwrap();
    let example: Value = serde_json::from_str(
        &std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../fixtures/keypoints/example.json"
        ))
        .unwrap(),
    )
    .unwrap();
    for (camera, reversed) in [("a", false), ("b", true)] {
        let mut poses = example["poses"].as_array().unwrap().clone();
        if reversed {
            poses.reverse();
        }
        let json = dir.path(&format!("{camera}.json"));
        std::fs::write(&json, serde_json::json!({ "poses": poses }).to_string()).unwrap();
        let npy = take.0.join(format!("{camera}.npy"));
        let out = camloc(&[
            "convert",
            "--input",
            &json,
            "--to",
            "npy",
            "--out",
            npy.to_str().unwrap(),
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    // Each pose's camera height on its own (`any`): under the default `from-input` the
    // folder is one input whose middle cameras' mean elevation moves every file's viewpoints,
    // hence its 3D, a little from what the file alone gives.
    for command in ["localize", "reconstruct"] {
        let folder = camloc(&[
            command,
            "--input",
            &dir.path("take"),
            "--sequence",
            "--jsonl",
            "-q",
            "--camera-height",
            "any",
        ]);
        let stderr = String::from_utf8_lossy(&folder.stderr);
        assert!(folder.status.success(), "{stderr}");
        assert!(!stderr.contains("repeat"), "{stderr}");
        let objects = json_lines(&folder);
        assert_eq!(objects.len(), 6);
        for camera in ["a", "b"] {
            let npy = take.0.join(format!("{camera}.npy"));
            let alone = camloc(&[
                command,
                "--input",
                npy.to_str().unwrap(),
                "--sequence",
                "--jsonl",
                "-q",
                "--camera-height",
                "any",
            ]);
            let key = if command == "localize" {
                "smoothed_label"
            } else {
                "landmarks_m"
            };
            let from_folder: Vec<&Value> = objects
                .iter()
                .filter(|o| {
                    o["source"]
                        .as_str()
                        .unwrap()
                        .contains(&format!("{camera}.npy"))
                })
                .map(|o| &o[key])
                .collect();
            let alone = json_lines(&alone);
            let alone: Vec<&Value> = alone.iter().map(|o| &o[key]).collect();
            assert_eq!(from_folder, alone, "{command} {camera}");
        }
    }
    // An animation per file's person, of that file's frames.
    let bvh = dir.path("take.bvh");
    let out = camloc(&[
        "reconstruct",
        "--input",
        &dir.path("take"),
        "--sequence",
        "--bvh",
        &bvh,
        "-q",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for n in ["001", "002"] {
        let text = std::fs::read_to_string(dir.path(&format!("take-{n}.bvh"))).unwrap();
        assert!(text.contains("Frames: 3"), "{n}");
    }
    drop(take);
}
