//! `reconstruct --bvh` and `--html`: the BVH files read back (camloc's reader) to the
//! reconstructed landmarks within 1 mm, one file per pose or per person with `--sequence`; the
//! page loads in a real headless browser without script errors and draws the skeleton (skipped,
//! visibly, without Chromium).

mod common;
#[path = "common/walk.rs"]
mod walk;

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use camloc::Pose3;
use camloc::dataset::max_joint_distance_mm;
use camloc::mocap::{BVH_CENTIMETRE, read_bvh_with_unit};
use camloc::skeleton::{Landmark, mean_limb_lengths};
use common::{TempDir, assert_clean_failure, camloc, fixture};
use serde_json::Value;
use walk::{WALK_STEP_PX, walk_document};

/// The 3D pose of one `reconstruct --json` object.
fn landmarks(object: &Value) -> Pose3 {
    Pose3::new(std::array::from_fn(|i| {
        let p = &object["landmarks_m"][Landmark::ALL[i].name()];
        std::array::from_fn(|k| p[k].as_f64().unwrap())
    }))
}

fn success(out: &std::process::Output) -> Vec<Value> {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

#[test]
fn each_pose_is_a_bvh_that_reads_back_to_its_landmarks() {
    let dir = TempDir::new("bvh-poses");
    let bvh = dir.0.join("pose.bvh");
    let input = fixture("keypoints/example.json");
    let out = camloc(&[
        "reconstruct",
        "--input",
        input.to_str().unwrap(),
        "--json",
        "--bvh",
        bvh.to_str().unwrap(),
        "--fps",
        "25",
    ]);
    let objects = success(&out);
    assert_eq!(objects.len(), 3);
    for (n, object) in objects.iter().enumerate() {
        let clip = read_bvh_with_unit(dir.0.join(format!("pose-00{}.bvh", n + 1)), BVH_CENTIMETRE)
            .unwrap();
        assert_eq!(clip.frames.len(), 1);
        assert!((clip.frame_time_s - 0.04).abs() < 1e-9);
        // Standing on the floor, the pelvis above the origin.
        let error = max_joint_distance_mm(&clip.frames[0], &standing(object)) / 1000.0;
        assert!(error < 1e-3, "pose {n}: {error} m");
    }
    assert!(!bvh.exists());
    // --fps times a sequence or an animation: alone it is refused; with --sequence it keeps
    // the smoothing's windows in time, so the answers differ from 30 frames a second's.
    let path = input.to_str().unwrap();
    for (command, takes) in [
        ("reconstruct", "without --sequence, --bvh or --html"),
        ("localize", "without --sequence or --html"),
    ] {
        let alone = camloc(&[command, "--input", path, "--fps", "60"]);
        let stderr = String::from_utf8_lossy(&alone.stderr);
        assert_eq!(alone.status.code(), Some(2), "{stderr}");
        assert!(stderr.contains(takes), "{stderr}");
    }
    let at = |fps: &str| {
        success(&camloc(&[
            "reconstruct",
            "--input",
            path,
            "--json",
            "--sequence",
            "--fps",
            fps,
        ]))
    };
    let (slow, fast) = (at("30"), at("120"));
    assert_eq!(slow.len(), fast.len());
    assert_ne!(slow[1]["landmarks_m"], fast[1]["landmarks_m"]);
    assert_eq!(slow, at("24"));
    // The files exist now: without --force the run is refused before any work.
    let again = camloc(&[
        "reconstruct",
        "--input",
        input.to_str().unwrap(),
        "--bvh",
        bvh.to_str().unwrap(),
    ]);
    assert_clean_failure(&again, "pose-001.bvh");
    // Also when OUT has no extension (the files take .bvh): refused before any pose is done.
    let bare = camloc(&[
        "reconstruct",
        "--input",
        input.to_str().unwrap(),
        "--bvh",
        dir.0.join("pose").to_str().unwrap(),
    ]);
    assert_clean_failure(&bare, "pose-001.bvh");
    assert!(
        bare.stdout.is_empty(),
        "{}",
        String::from_utf8_lossy(&bare.stdout)
    );
    let same = camloc(&[
        "reconstruct",
        "--input",
        input.to_str().unwrap(),
        "--bvh",
        bvh.to_str().unwrap(),
        "--html",
        dir.0.join("pose-002.bvh").to_str().unwrap(),
    ]);
    assert_eq!(same.status.code(), Some(2));
    // An input of one pose: one file of one frame at OUT itself (.bvh added to a bare name).
    let one = dir.0.join("one.json");
    let text = std::fs::read_to_string(&input).unwrap();
    let mut json: Value = serde_json::from_str(&text).unwrap();
    json["poses"].as_array_mut().unwrap().truncate(1);
    std::fs::write(&one, json.to_string()).unwrap();
    let single = dir.0.join("single");
    let out = camloc(&[
        "reconstruct",
        "--input",
        one.to_str().unwrap(),
        "--json",
        "--bvh",
        single.to_str().unwrap(),
    ]);
    let objects = success(&out);
    let clip = read_bvh_with_unit(single.with_extension("bvh"), BVH_CENTIMETRE).unwrap();
    assert_eq!(clip.frames.len(), 1);
    assert!(max_joint_distance_mm(&clip.frames[0], &standing(&objects[0])) < 1.0);
}

/// A single pose's BVH frame: the pose of one `reconstruct --json` object lifted so that its
/// lowest landmark stands on the floor (height 0), the pelvis above the origin.
fn standing(object: &Value) -> Pose3 {
    let pose = landmarks(object);
    let floor = pose
        .points
        .iter()
        .map(|q| q[2])
        .fold(f64::INFINITY, f64::min);
    Pose3::new(pose.points.map(|q| [q[0], q[1], q[2] - floor]))
}

/// A folder of OpenPose frames: `frames` frames of two people (the first two fixture poses,
/// the second 300 px to the right, each frame's keypoints moved a little so that the frames
/// differ).
fn video(dir: &TempDir, frames: usize) -> String {
    let samples = fixture("keypoints/samples/openpose");
    let mut people = Vec::new();
    for n in 0..2 {
        let file = samples.join(format!("clip_00000000000{n}_keypoints.json"));
        let json: Value = serde_json::from_str(&std::fs::read_to_string(file).unwrap()).unwrap();
        people.extend(json["people"].as_array().unwrap().iter().cloned());
    }
    let folder = dir.0.join("video");
    std::fs::create_dir(&folder).unwrap();
    for t in 0..frames {
        let moved: Vec<Value> = people[..2]
            .iter()
            .enumerate()
            .map(|(n, p)| {
                let k: Vec<Value> = p["pose_keypoints_2d"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .enumerate()
                    .map(|(i, v)| {
                        let v = v.as_f64().unwrap();
                        // x and y move, scores stay.
                        let wobble = match i % 3 {
                            2 => 0.0,
                            0 => 3.0 * ((t + i) as f64).sin() + 300.0 * n as f64,
                            _ => 3.0 * ((t + i) as f64).sin(),
                        };
                        Value::from(v + if v > 0.0 { wobble } else { 0.0 })
                    })
                    .collect();
                serde_json::json!({ "pose_keypoints_2d": k })
            })
            .collect();
        let json = serde_json::json!({ "version": 1.3, "people": moved });
        std::fs::write(
            folder.join(format!("v_{t:012}_keypoints.json")),
            json.to_string(),
        )
        .unwrap();
    }
    folder.to_string_lossy().into_owned()
}

#[test]
fn a_sequence_is_one_bvh_per_person_with_shared_lengths() {
    let dir = TempDir::new("bvh-sequence");
    let folder = video(&dir, 12);
    let bvh = dir.0.join("people.bvh");
    let out = camloc(&[
        "reconstruct",
        "--input",
        &folder,
        "--json",
        "--sequence",
        "--bvh",
        bvh.to_str().unwrap(),
        "--bvh-in-place",
        "--quiet",
    ]);
    let objects = success(&out);
    assert_eq!(objects.len(), 24);
    for person in 0..2u64 {
        let mut mine: Vec<&Value> = objects
            .iter()
            .filter(|o| o["person"].as_u64() == Some(person))
            .collect();
        mine.sort_by_key(|o| o["frame"].as_u64());
        let poses: Vec<Pose3> = mine.iter().map(|o| landmarks(o)).collect();
        let lengths = mean_limb_lengths(&poses).unwrap();
        let file = dir.0.join(format!("people-00{}.bvh", person + 1));
        let clip = read_bvh_with_unit(&file, BVH_CENTIMETRE).unwrap();
        assert_eq!(clip.frames.len(), 12);
        // In place: the pose as reconstructed, its pelvis above the origin at the height
        // root motion gives it.
        for (t, (read, pose)) in clip.frames.iter().zip(&poses).enumerate() {
            let height = read.get(Landmark::Pelvis)[2];
            assert!(
                height > 0.3,
                "person {person} frame {t}: pelvis at {height} m"
            );
            let lifted = Pose3::new(pose.points.map(|q| [q[0], q[1], q[2] + height]));
            let expected = lifted.with_limb_lengths(&lengths).unwrap();
            let error = max_joint_distance_mm(read, &expected) / 1000.0;
            assert!(error < 1e-3, "person {person} frame {t}: {error} m");
        }
    }
}

/// A person walking across the image of a camera that stands still: with `--sequence` the
/// BVH's root moves across the floor by the image distance over the camera's scale and stays
/// at the pelvis's height above the feet; `--bvh-in-place` keeps it at the origin.
#[test]
fn a_sequence_s_bvh_moves_as_the_camera_saw_the_person() {
    let dir = TempDir::new("bvh-root-motion");
    let (frames, step_px) = (20usize, WALK_STEP_PX);
    let input = walk_across(&dir, 0..frames);
    let (moving, still) = (dir.0.join("moving.bvh"), dir.0.join("still.bvh"));
    let run = |bvh: &Path, extra: &[&str]| {
        let mut args = vec!["reconstruct", "--input", &input, "--json", "--sequence"];
        args.extend(["--bvh", bvh.to_str().unwrap(), "--quiet"]);
        args.extend(extra);
        success(&camloc(&args))
    };
    let objects = run(&moving, &[]);
    run(&still, &["--bvh-in-place"]);
    // The weak-perspective scale, pixels per metre at the pelvis.
    let scale: f64 = objects
        .iter()
        .map(|o| o["camera"]["scale"].as_f64().unwrap())
        .sum::<f64>()
        / frames as f64;
    let expected = step_px * (frames - 1) as f64 / scale;
    let clip = read_bvh_with_unit(&moving, BVH_CENTIMETRE).unwrap();
    let pelvis = |pose: &Pose3| pose.get(Landmark::Pelvis);
    let (first, last) = (pelvis(&clip.frames[0]), pelvis(&clip.frames[frames - 1]));
    let across = ((last[0] - first[0]).powi(2) + (last[1] - first[1]).powi(2)).sqrt();
    assert!(
        (across / expected - 1.0).abs() < 0.1,
        "moved {across:.3} m across the floor, expected {expected:.3} m"
    );
    // Feet on the floor, the pelvis above them.
    let lowest = clip
        .frames
        .iter()
        .flat_map(|f| f.points.iter().map(|p| p[2]))
        .fold(f64::INFINITY, f64::min);
    assert!(lowest.abs() < 1e-3, "lowest landmark at {lowest} m");
    assert!(first[2] > 0.5, "pelvis at {} m", first[2]);
    // In place: the pelvis above the origin, the feet on the floor (no planted feet here: the
    // lowest landmark).
    let still = read_bvh_with_unit(&still, BVH_CENTIMETRE).unwrap();
    let lowest = still
        .frames
        .iter()
        .flat_map(|f| f.points.iter().map(|p| p[2]))
        .fold(f64::INFINITY, f64::min);
    assert!(
        lowest.abs() < 1e-3,
        "lowest landmark at {lowest} m in place"
    );
    for frame in &still.frames {
        let p = pelvis(frame);
        assert!(
            p[0].abs() < 1e-6 && p[1].abs() < 1e-6 && p[2] > 0.5,
            "{p:?}"
        );
    }
}

/// A `camloc-keypoints` file in `dir` of [`walk_document`]`(numbers)`.
fn walk_across(dir: &TempDir, numbers: impl Iterator<Item = usize>) -> String {
    dir.file("walk.json", &walk_document(numbers).to_string())
}

/// Frames the detector missed (no record of the person) keep the video's timing in a
/// sequence's BVH: they take the person from the frame before the gap to the one after it,
/// and the person is where the camera saw them after the gap (a trial's walk with 28 frames missing had played 0.93 s early after them).
#[test]
fn frames_the_person_is_missing_from_keep_the_timing_of_the_bvh() {
    let dir = TempDir::new("bvh-gap");
    let input = walk_across(&dir, (0..8).chain(12..20));
    let bvh = dir.0.join("gap.bvh");
    let run = |bvh: &Path, input: &str| {
        let args = [
            "reconstruct",
            "--input",
            input,
            "--json",
            "--sequence",
            "--quiet",
        ];
        let mut args = args.to_vec();
        args.extend(["--bvh", bvh.to_str().unwrap()]);
        success(&camloc(&args))
    };
    let objects = run(&bvh, &input);
    assert_eq!(objects.len(), 16);
    let clip = read_bvh_with_unit(&bvh, BVH_CENTIMETRE).unwrap();
    assert_eq!(clip.frames.len(), 20);
    // The missing frames move the person from frame 7 to frame 12 in equal steps.
    let pelvis = |t: usize| clip.frames[t].get(Landmark::Pelvis);
    let whole_step = (pelvis(12)[0] - pelvis(7)[0]) / 5.0;
    for t in 8..12 {
        let step = pelvis(t)[0] - pelvis(t - 1)[0];
        assert!(
            (step - whole_step).abs() < 1e-6 && whole_step.abs() > 1e-3,
            "frame {t}: {step} m against {whole_step} m"
        );
    }
    // After the gap the person is as far across as the image says: the distance in pixels
    // over the weak-perspective scale (pixels per metre at the pelvis).
    let scale: f64 = objects
        .iter()
        .map(|o| o["camera"]["scale"].as_f64().unwrap())
        .sum::<f64>()
        / objects.len() as f64;
    let start = clip.frames[0].get(Landmark::Pelvis);
    for t in [12, 19] {
        let p = clip.frames[t].get(Landmark::Pelvis);
        let across = (p[0] - start[0]).hypot(p[1] - start[1]);
        let expected = WALK_STEP_PX * t as f64 / scale;
        assert!(
            (across / expected - 1.0).abs() < 0.1,
            "frame {t}: {across} m across, expected {expected} m"
        );
    }
    // The frames it made up are said.
    let stderr_of_bvh = |input: &str, bvh: &Path| {
        let bvh = bvh.to_str().unwrap();
        let args = [
            "reconstruct",
            "--input",
            input,
            "--sequence",
            "--quiet",
            "--bvh",
            bvh,
        ];
        let out = camloc(&args);
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(out.status.success(), "{stderr}");
        stderr
    };
    let stderr = stderr_of_bvh(&input, &dir.0.join("gap2.bvh"));
    assert!(
        stderr.contains("the BVH of person 0 fills 4 of its 20 frames from the frames around"),
        "{stderr}"
    );
    // Frames far apart are not filled by the thousand: 8 frames spanning 2,004 play one after
    // another (beyond 100 frames filled for each, plus 1,000), and a message says so.
    let sparse = walk_across(&dir, (0..4).chain(2000..2004));
    let far = dir.0.join("far.bvh");
    let stderr = stderr_of_bvh(&sparse, &far);
    assert!(
        stderr.contains("plays its 8 frames one after another"),
        "{stderr}"
    );
    assert_eq!(
        read_bvh_with_unit(&far, BVH_CENTIMETRE)
            .unwrap()
            .frames
            .len(),
        8
    );
}

/// `camloc reconstruct --sequence --json --bvh` of `document` written to `NAME.json` in
/// `dir`: the run's output and the BVH's path (`NAME.bvh`).
fn sequence_with_bvh(dir: &TempDir, name: &str, document: &Value) -> (Output, PathBuf) {
    let file = dir.file(&format!("{name}.json"), &document.to_string());
    let bvh = dir.0.join(format!("{name}.bvh"));
    let out = camloc(&[
        "reconstruct",
        "--input",
        &file,
        "--json",
        "--sequence",
        "--quiet",
        "--bvh",
        bvh.to_str().unwrap(),
    ]);
    (out, bvh)
}

/// A second pose of a frame (a tracker's duplicate) and a frame holding another person's
/// pose (two people's ids swapped for one frame) are left out of the sequence, with warnings
/// naming the person and the frames: the BVH keeps the video's timing (the duplicate had made
/// it play every frame one after another) and fills the swapped frame from its neighbours
/// (the other person's pose had pulled the root 0.5 m away in a trial).
#[test]
fn a_duplicate_and_a_swapped_frame_are_left_out_of_the_sequence() {
    let dir = TempDir::new("bvh-left-out");
    let mut document = walk_document(0..20);
    let poses = document["poses"].as_array_mut().unwrap();
    let moved = |pose: &Value, dx: f64, id: &str| {
        let mut pose = pose.clone();
        for p in pose["landmarks"].as_object_mut().unwrap().values_mut() {
            p[0] = (p[0].as_f64().unwrap() + dx).into();
        }
        pose["id"] = id.into();
        pose
    };
    let duplicate = moved(&poses[5], 3.0, "dup5");
    poses.insert(6, duplicate);
    // Frames 13 to 15 (now at positions 14 to 16) hold someone 900 px away.
    for (frame, pose) in (13..16).zip(&mut poses[14..17]) {
        *pose = moved(pose, 900.0, &format!("other{frame}"));
    }
    let (out, bvh) = sequence_with_bvh(&dir, "left-out", &document);
    let objects = success(&out);
    assert_eq!(objects.len(), 21);
    let stderr = String::from_utf8_lossy(&out.stderr);
    for expected in [
        "person 0: 1 pose shares a frame with another pose (first at frame 5)",
        "person 0: the poses of 3 frames lie apart from the frames before and after them \
         (first at frame 13",
    ] {
        assert!(stderr.contains(expected), "{stderr}");
    }
    // The jumps into and out of the other person's frames are those frames, not a change of
    // person.
    assert!(!stderr.contains("jumps across the image"), "{stderr}");
    // `localize --sequence` leaves the same poses out of its smoothing and says so per pose.
    let file = dir.0.join("left-out.json");
    let localized = success(&camloc(&[
        "localize",
        "--input",
        file.to_str().unwrap(),
        "--json",
        "--sequence",
        "-q",
    ]));
    let left: Vec<&str> = localized
        .iter()
        .filter(|o| o["left_out_of_sequence"] == true)
        .map(|o| o["id"].as_str().unwrap())
        .collect();
    assert_eq!(left, ["dup5", "other13", "other14", "other15"]);
    let clip = read_bvh_with_unit(&bvh, BVH_CENTIMETRE).unwrap();
    assert_eq!(clip.frames.len(), 20);
    // Frames 13 to 15 are filled in even steps between their neighbours, which the walk
    // keeps one step apart on each side.
    let pelvis = |t: usize| clip.frames[t].get(Landmark::Pelvis);
    let steps: Vec<f64> = (13..17).map(|t| pelvis(t)[0] - pelvis(t - 1)[0]).collect();
    assert!(
        steps
            .iter()
            .all(|s| (s - steps[0]).abs() < 1e-6 && s.abs() < 0.1),
        "steps {steps:?} m"
    );
}

/// A tracker's swap for the last frames of a track (numbered frames, so the jump happens
/// from one frame to the next) is left out as well: the BVH holds the person's last frame
/// instead of carrying the root to the other person (1.4-7.3 m in a trial).
#[test]
fn a_swap_at_the_end_of_a_track_is_left_out() {
    let dir = TempDir::new("bvh-end-swap");
    let mut document = walk_document(0..20);
    for pose in &mut document["poses"].as_array_mut().unwrap()[16..] {
        for p in pose["landmarks"].as_object_mut().unwrap().values_mut() {
            p[0] = (p[0].as_f64().unwrap() + 900.0).into();
        }
    }
    let (out, bvh) = sequence_with_bvh(&dir, "end-swap", &document);
    let objects = success(&out);
    assert_eq!(objects.len(), 20);
    for (t, object) in objects.iter().enumerate() {
        let marked = object.get("left_out_of_sequence") == Some(&Value::Bool(true));
        assert_eq!(marked, t >= 16, "frame {t}: {object}");
    }
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains(
            "the poses of 4 frames lie apart from the frames before and after them (first at frame 16"
        ),
        "{stderr}"
    );
    assert!(!stderr.contains("jumps across the image"), "{stderr}");
    let clip = read_bvh_with_unit(&bvh, BVH_CENTIMETRE).unwrap();
    assert_eq!(clip.frames.len(), 20);
    let pelvis = |t: usize| clip.frames[t].get(Landmark::Pelvis);
    let walked = (pelvis(15)[0] - pelvis(0)[0]).abs();
    for t in 16..20 {
        let past = (pelvis(t)[0] - pelvis(15)[0]).abs();
        assert!(
            past < 0.1 * walked.max(0.1),
            "frame {t}: {past} m past frame 15"
        );
    }
}

/// Frames whose left and right legs a detector swapped are swapped back before the
/// sequence is solved, with a warning: their 3D is the clean walk's, and so are their cameras
/// in `localize --sequence`.
#[test]
fn legs_a_detector_swapped_for_two_frames_are_swapped_back() {
    let dir = TempDir::new("sides-swapped");
    let clean = walk_across(&dir, 0..20);
    let mut document = walk_document(0..20);
    for pose in &mut document["poses"].as_array_mut().unwrap()[5..7] {
        let landmarks = pose["landmarks"].as_object_mut().unwrap();
        for side in ["hip", "knee", "ankle"] {
            let left = landmarks[&format!("left_{side}")].clone();
            let right = landmarks[&format!("right_{side}")].clone();
            landmarks.insert(format!("left_{side}"), right);
            landmarks.insert(format!("right_{side}"), left);
        }
    }
    let swapped = dir.file("swapped.json", &document.to_string());
    let run = |input: &str| {
        camloc(&[
            "reconstruct",
            "--input",
            input,
            "--json",
            "--sequence",
            "-q",
        ])
    };
    let (clean_out, swapped_out) = (run(&clean), run(&swapped));
    let stderr = String::from_utf8_lossy(&swapped_out.stderr);
    assert!(
        stderr.contains(
            "person 0: the left and right legs of 2 frames are swapped against the frames around \
             them (first at frame 5"
        ),
        "{stderr}"
    );
    assert!(!String::from_utf8_lossy(&clean_out.stderr).contains("swapped"));
    for (t, (a, b)) in success(&clean_out)
        .iter()
        .zip(success(&swapped_out))
        .enumerate()
    {
        // The camera heights are estimated from the rows as given (two of them swapped), so
        // the middle cameras' elevation, hence the 3D, may differ a little (about 1 mm here).
        let (clean_m, swapped_m) = (
            a["landmarks_m"].as_object().unwrap(),
            b["landmarks_m"].as_object().unwrap(),
        );
        for (name, point) in clean_m {
            for (x, y) in point
                .as_array()
                .unwrap()
                .iter()
                .zip(swapped_m[name].as_array().unwrap())
            {
                let (x, y) = (x.as_f64().unwrap(), y.as_f64().unwrap());
                assert!((x - y).abs() < 5e-3, "frame {t} {name}: {x} against {y}");
            }
        }
        let marked = b.get("swapped_sides").cloned();
        let expected = (5..7).contains(&t).then(|| serde_json::json!(["legs"]));
        assert_eq!(marked, expected, "frame {t}");
    }
    // `localize --sequence` localizes them again, swapped back.
    let localize =
        |input: &str| camloc(&["localize", "--input", input, "--json", "--sequence", "-q"]);
    let (clean_view, swapped_view) = (localize(&clean), localize(&swapped));
    assert!(String::from_utf8_lossy(&swapped_view.stderr).contains("legs of 2 frames"));
    for (t, (a, b)) in success(&clean_view)
        .iter()
        .zip(success(&swapped_view))
        .enumerate()
    {
        for key in ["label", "smoothed_label"] {
            assert_eq!(a[key], b[key], "frame {t}: {key}");
        }
        // (The pose localized again was kept in single precision, and the input's camera
        // heights are estimated from its poses as given, two of them swapped.)
        for (key, tolerance) in [("probability", 1e-3), ("azimuth_deg", 0.1)] {
            let (x, y) = (a[key].as_f64().unwrap(), b[key].as_f64().unwrap());
            assert!((x - y).abs() < tolerance, "frame {t}: {key} {x} vs {y}");
        }
        let expected = (5..7).contains(&t).then(|| serde_json::json!(["legs"]));
        assert_eq!(b.get("swapped_sides").cloned(), expected, "frame {t}");
    }
}

/// Chromium's command, when installed.
fn chromium() -> Option<&'static str> {
    ["chromium", "chromium-browser"].into_iter().find(|name| {
        Command::new(name)
            .arg("--version")
            .output()
            .is_ok_and(|o| o.status.success())
    })
}

/// The page's `<body ...>` tag after its script ran in headless Chromium.
fn body_after_load(browser: &str, page: &Path, dir: &TempDir) -> String {
    let out = Command::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            &format!("--user-data-dir={}", dir.0.join("profile").display()),
            "--dump-dom",
            &format!("file://{}", page.display()),
        ])
        .output()
        .unwrap();
    let dom = String::from_utf8_lossy(&out.stdout).into_owned();
    let start = dom.find("<body").unwrap_or(0);
    let end = start + dom[start..].find('>').unwrap_or(0);
    let errors = dom
        .split("<pre id=\"errors\">")
        .nth(1)
        .and_then(|rest| rest.split("</pre>").next())
        .unwrap_or("");
    assert!(errors.is_empty(), "script errors: {errors}");
    dom[start..=end].to_owned()
}

#[test]
fn the_pages_load_in_a_browser_and_draw_the_skeleton() {
    let dir = TempDir::new("html");
    let folder = video(&dir, 6);
    let pages = [
        ("reconstruct", vec!["--sequence"], "sequence.html"),
        ("localize", vec!["--sequence"], "localize-sequence.html"),
        ("localize", vec![], "localize.html"),
        ("reconstruct", vec![], "reconstruct.html"),
    ];
    let mut poses = Vec::new();
    for (command, extra, name) in &pages {
        let page = dir.0.join(name);
        let mut args = vec![*command, "--input", &folder, "--quiet", "--html"];
        let page_arg = page.to_string_lossy().into_owned();
        args.push(&page_arg);
        args.extend(extra.iter().copied());
        let out = camloc(&args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let html = std::fs::read_to_string(&page).unwrap();
        // Self-contained: no address to fetch anything from.
        assert!(
            !html.contains("http://") && !html.contains("https://"),
            "{name}"
        );
        let start = html.find(r#"id="data">"#).unwrap() + 10;
        let end = start + html[start..].find("</script>").unwrap();
        let data: Value = serde_json::from_str(&html[start..end]).unwrap();
        assert_eq!(data["frames"].as_array().unwrap().len(), 12, "{name}");
        let groups = data["groups"].as_array().unwrap().len();
        assert_eq!(groups, if extra.is_empty() { 1 } else { 2 }, "{name}");
        let frame = &data["frames"][0];
        assert!(
            frame["pose"].is_array() && frame["probabilities"].is_array(),
            "{name}"
        );
        assert!(frame["direction"].is_array(), "{name}");
        if extra.is_empty() {
            poses.push(data["frames"].clone());
        }
    }
    // localize's page shows the skeletons `camloc reconstruct` gives.
    for (l, r) in poses[0]
        .as_array()
        .unwrap()
        .iter()
        .zip(poses[1].as_array().unwrap())
    {
        assert_eq!(l["pose"], r["pose"]);
    }
    let Some(browser) = chromium() else {
        let _ = std::io::stderr().lock().write_all(
            b"\nSKIPPED: the --html browser test: chromium not found (apt-get install chromium)\n",
        );
        return;
    };
    // Every page runs the same script on data of the same shape (checked above for each): one
    // load (a browser start takes seconds) of the page that uses the most of it (two persons,
    // smoothed cameras).
    let name = "localize-sequence.html";
    let body = body_after_load(browser, &dir.0.join(name), &dir);
    assert!(body.contains(r#"data-status="ready""#), "{name}: {body}");
    let pixels: u64 = body
        .split("data-skeleton-pixels=\"")
        .nth(1)
        .and_then(|rest| rest.split('"').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or(0);
    // A skeleton of 4-pixel lines some 300 pixels tall: well over 500 limb pixels.
    assert!(pixels > 500, "{name}: {pixels} skeleton pixels");
}
