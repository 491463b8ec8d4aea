//! The sample files of the detector formats (fixtures/keypoints/samples/) are made here from the
//! poses of `example.json`, and each reads back to the same landmarks, up to what its format
//! derives. The committed files must equal what this generator writes; run
//! `CAMLOC_WRITE_SAMPLES=1 cargo test -p camloc-keypoints --test samples` to rewrite them (and
//! the malformed `.npy` files of fixtures/keypoints/bad/, made here too).

mod common;

use camloc_keypoints::{
    ImageSize, KeypointFormat, KeypointRecord, Landmark, Layout, PartialPose2, ReadOptions,
    read_folder, read_keypoints, write_npy,
};
use common::{SAMPLE_IMAGE as IMAGE, fixture, mid, read};
use serde_json::{Value, json};

use Landmark as L;

/// The complete poses of example.json (its missing pelvis derived), as read.
fn poses() -> Vec<[[f64; 2]; 15]> {
    read("example.json")
        .iter()
        .map(|r| {
            r.pose
                .complete()
                .expect("example poses are complete")
                .points
        })
        .collect()
}

fn at(pose: &[[f64; 2]; 15], l: Landmark) -> [f64; 2] {
    pose[l.index()]
}

fn add(p: [f64; 2], dx: f64, dy: f64) -> [f64; 2] {
    [p[0] + dx, p[1] + dy]
}

/// A detector-like confidence, varying by pose and joint, in [0.6, 0.95].
fn confidence(pose: usize, joint: usize) -> f64 {
    0.6 + 0.05 * ((3 * pose + 5 * joint) % 8) as f64
}

/// The joint of pose 1 given a low confidence, to show `min_score`.
const WEAK_JOINT: Landmark = L::RightWrist;
const WEAK_SCORE: f64 = 0.05;

/// Face points around the head: nose, left eye, right eye, left ear, right ear (person's
/// sides; the example poses face the camera or its left, so the offsets are symmetric).
fn face(pose: &[[f64; 2]; 15]) -> [[f64; 2]; 5] {
    let h = at(pose, L::Head);
    [
        h,
        add(h, 4.0, -2.0),
        add(h, -4.0, -2.0),
        add(h, 9.0, 2.0),
        add(h, -9.0, 2.0),
    ]
}

/// The position of `name` (a joint of some format) in a pose: landmarks by name, face points,
/// and the points camloc does not use placed plausibly.
fn joint(pose: &[[f64; 2]; 15], name: &str) -> [f64; 2] {
    let f = face(pose);
    let neck = at(pose, L::Neck);
    let pelvis = at(pose, L::Pelvis);
    let head = at(pose, L::Head);
    match name {
        "nose" => f[0],
        "left_eye" | "left_eye_inner" | "left_eye_outer" => f[1],
        "right_eye" | "right_eye_inner" | "right_eye_outer" => f[2],
        "left_ear" => f[3],
        "right_ear" => f[4],
        "mouth_left" => add(head, 3.0, 6.0),
        "mouth_right" => add(head, -3.0, 6.0),
        "mid_hip" => pelvis,
        "thorax" => neck,
        "upper_neck" | "neck_nose" => head,
        "head_top" => add(head, 0.5 * (head[0] - neck[0]), 0.5 * (head[1] - neck[1])),
        "spine" => mid(pelvis, neck),
        _ => {
            if let Some(l) = Landmark::from_name(name) {
                return at(pose, l);
            }
            // Hands and feet near the wrists and ankles.
            let (side, rest) = name.split_once('_').unwrap();
            let base = |l: &str| at(pose, Landmark::from_name(&format!("{side}_{l}")).unwrap());
            match rest {
                "pinky" | "index" | "thumb" => add(base("wrist"), 0.0, 8.0),
                "heel" => add(base("ankle"), -3.0, 4.0),
                _ => add(base("ankle"), 8.0, 5.0),
            }
        }
    }
}

/// x, y, c triples of `names` for pose `p` (the weak joint of pose 1 gets [`WEAK_SCORE`]).
fn triples(pose: &[[f64; 2]; 15], p: usize, names: &[&str]) -> Vec<f64> {
    names
        .iter()
        .enumerate()
        .flat_map(|(k, name)| {
            let [x, y] = joint(pose, name);
            let c = if p == 1 && *name == WEAK_JOINT.name() {
                WEAK_SCORE
            } else {
                confidence(p, k)
            };
            [x, y, c]
        })
        .collect()
}

fn layout_names(layout: Layout) -> Vec<&'static str> {
    (0..layout.joint_count())
        .map(|j| layout.joint_name(j).unwrap())
        .collect()
}

const COCO18: [&str; 18] = [
    "nose",
    "neck",
    "right_shoulder",
    "right_elbow",
    "right_wrist",
    "left_shoulder",
    "left_elbow",
    "left_wrist",
    "right_hip",
    "right_knee",
    "right_ankle",
    "left_hip",
    "left_knee",
    "left_ankle",
    "right_eye",
    "left_eye",
    "right_ear",
    "left_ear",
];

const MEDIAPIPE33: [&str; 33] = [
    "nose",
    "left_eye_inner",
    "left_eye",
    "left_eye_outer",
    "right_eye_inner",
    "right_eye",
    "right_eye_outer",
    "left_ear",
    "right_ear",
    "mouth_left",
    "mouth_right",
    "left_shoulder",
    "right_shoulder",
    "left_elbow",
    "right_elbow",
    "left_wrist",
    "right_wrist",
    "left_pinky",
    "right_pinky",
    "left_index",
    "right_index",
    "left_thumb",
    "right_thumb",
    "left_hip",
    "right_hip",
    "left_knee",
    "right_knee",
    "left_ankle",
    "right_ankle",
    "left_heel",
    "right_heel",
    "left_foot_index",
    "right_foot_index",
];

fn openpose_frame(people: Vec<Vec<f64>>) -> String {
    let people: Vec<Value> = people
        .into_iter()
        .map(|kp| {
            json!({"person_id": [-1], "pose_keypoints_2d": kp, "face_keypoints_2d": [],
                   "hand_left_keypoints_2d": [], "hand_right_keypoints_2d": []})
        })
        .collect();
    serde_json::to_string(&json!({"version": 1.3, "people": people})).unwrap() + "\n"
}

fn npy_bytes<P: camloc_keypoints::NpyPose>(poses: &[P]) -> Vec<u8> {
    let mut out = Vec::new();
    write_npy(&mut out, poses).unwrap();
    out
}

/// An `.npy` file of `float64` values with the given header dict text (padded as NumPy does).
fn raw_npy(dict: &str, values: &[f64]) -> Vec<u8> {
    let mut header = dict.to_owned();
    while !(10 + header.len() + 1).is_multiple_of(64) {
        header.push(' ');
    }
    header.push('\n');
    let mut out = b"\x93NUMPY\x01\x00".to_vec();
    out.extend_from_slice(&(header.len() as u16).to_le_bytes());
    out.extend_from_slice(header.as_bytes());
    for v in values {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out
}

/// Every generated file: (path under fixtures/keypoints, content).
fn generated() -> Vec<(String, Vec<u8>)> {
    let poses = poses();
    let mut files = Vec::new();
    let mut add_text = |name: &str, text: String| files.push((name.to_owned(), text.into_bytes()));

    // OpenPose BODY_25, a folder of frames: pose 0; poses 1 and 2 (two people); nobody.
    let body25 = layout_names(Layout::Body25);
    let person = |p: usize| triples(&poses[p], p, &body25);
    for (frame, people) in [vec![person(0)], vec![person(1), person(2)], vec![]]
        .into_iter()
        .enumerate()
    {
        add_text(
            &format!("samples/openpose/clip_{frame:012}_keypoints.json"),
            openpose_frame(people),
        );
    }
    // OpenPose COCO-18, one frame of three people.
    add_text(
        "samples/openpose_coco18_000000000007_keypoints.json",
        openpose_frame((0..3).map(|p| triples(&poses[p], p, &COCO18)).collect()),
    );

    // MMPose video predictions, COCO-17, one instance per frame.
    let coco17 = layout_names(Layout::Coco17);
    let frames: Vec<Value> = poses
        .iter()
        .enumerate()
        .map(|(p, pose)| {
            let t = triples(pose, p, &coco17);
            let keypoints: Vec<[f64; 2]> = t.chunks(3).map(|c| [c[0], c[1]]).collect();
            let scores: Vec<f64> = t.chunks(3).map(|c| c[2]).collect();
            json!({"frame_id": p, "instances": [{"keypoints": keypoints, "keypoint_scores": scores,
                   "bbox": [[200.0, 100.0, 400.0, 430.0]], "bbox_score": 0.98}]})
        })
        .collect();
    add_text(
        "samples/mmpose.json",
        serde_json::to_string_pretty(
            &json!({"meta_info": {"dataset_name": "coco"}, "instance_info": frames}),
        )
        .unwrap()
            + "\n",
    );

    // MediaPipe Pose, normalised by a 640 x 480 image; a frame without a person (null).
    let mut frames: Vec<Value> = poses
        .iter()
        .enumerate()
        .map(|(p, pose)| {
            let t = triples(pose, p, &MEDIAPIPE33);
            let landmarks: Vec<Value> = t
                .chunks(3)
                .enumerate()
                .map(|(k, c)| {
                    json!({"x": c[0] / IMAGE.width, "y": c[1] / IMAGE.height,
                           "z": -0.01 * k as f64, "visibility": c[2]})
                })
                .collect();
            Value::Array(landmarks)
        })
        .collect();
    frames.insert(2, Value::Null);
    add_text(
        "samples/mediapipe.json",
        serde_json::to_string_pretty(&frames).unwrap() + "\n",
    );

    // Ultralytics YOLO pose text normalised by the 640 x 480 image, a folder of frames: pose
    // 0; poses 1 and 2 with the box's confidence and a tracker's ids 7 and 9; nobody.
    let line = |p: usize, extra: &str| {
        let [x, y] = at(&poses[p], L::Pelvis);
        let mut words = vec![format!(
            "0 {} {} 0.25 0.75",
            x / IMAGE.width,
            y / IMAGE.height
        )];
        for c in triples(&poses[p], p, &coco17).chunks(3) {
            words.push(format!(
                "{} {} {}",
                c[0] / IMAGE.width,
                c[1] / IMAGE.height,
                c[2]
            ));
        }
        words.push(extra.to_owned());
        words.join(" ").trim_end().to_owned() + "\n"
    };
    for (frame, text) in [
        line(0, ""),
        line(1, "0.93 7") + &line(2, "0.88 9"),
        String::new(),
    ]
    .into_iter()
    .enumerate()
    {
        add_text(&format!("samples/yolo/clip_{frame}.txt"), text);
    }

    // MPII JSON annotations.
    let mpii16 = layout_names(Layout::Mpii16);
    let entries: Vec<Value> = poses
        .iter()
        .enumerate()
        .map(|(p, pose)| {
            let joints: Vec<[f64; 2]> = mpii16.iter().map(|n| joint(pose, n)).collect();
            json!({"image": format!("example_{p}.jpg"), "joints": joints,
                   "joints_vis": vec![1; 16], "center": at(pose, L::Pelvis), "scale": 1.5})
        })
        .collect();
    add_text(
        "samples/mpii.json",
        serde_json::to_string_pretty(&entries).unwrap() + "\n",
    );

    // NumPy: camloc15 (N, 15, 2) by the crate's writer; h36m17 with scores (N, 17, 3).
    let partial: Vec<PartialPose2> = poses
        .iter()
        .map(|p| PartialPose2 {
            points: p.map(Some),
        })
        .collect();
    files.push(("samples/camloc15.npy".to_owned(), npy_bytes(&partial)));
    let h36m = layout_names(Layout::H36m17);
    let values: Vec<f64> = poses
        .iter()
        .enumerate()
        .flat_map(|(p, pose)| triples(pose, p, &h36m))
        .collect();
    files.push((
        "samples/h36m17_scores.npy".to_owned(),
        raw_npy(
            "{'descr': '<f8', 'fortran_order': False, 'shape': (3, 17, 3), }",
            &values,
        ),
    ));

    // Malformed arrays (fixtures/keypoints/bad/).
    let good = npy_bytes(&partial);
    let c15: Vec<f64> = partial
        .iter()
        .flat_map(|p| p.points.iter().flat_map(|q| q.unwrap()))
        .collect();
    let header =
        |shape: &str| format!("{{'descr': '<f8', 'fortran_order': False, 'shape': {shape}, }}");
    let mut nan = c15[..30].to_vec();
    nan[2 * 3] = f64::NAN; // x of joint 3, y stays
    let mut inf = c15[..30].to_vec();
    inf[2 * 5 + 1] = f64::INFINITY;
    let score: Vec<f64> = c15[..30]
        .chunks(2)
        .enumerate()
        .flat_map(|(k, p)| [p[0], p[1], if k == 4 { 1.5 } else { 0.9 }])
        .collect();
    let mut long_header = b"\x93NUMPY\x02\x00".to_vec();
    long_header.extend_from_slice(&u32::MAX.to_le_bytes());
    long_header.extend_from_slice(b"{'descr': '<f8'");
    let bad = [
        ("npy_truncated.npy", good[..good.len() - 20].to_vec()),
        ("npy_nan.npy", raw_npy(&header("(1, 15, 2)"), &nan)),
        ("npy_inf.npy", raw_npy(&header("(1, 15, 2)"), &inf)),
        (
            "npy_score_out_of_range.npy",
            raw_npy(&header("(1, 15, 3)"), &score),
        ),
        ("npy_shape_2d.npy", raw_npy(&header("(1, 30)"), &c15[..30])),
        (
            "npy_13_joints.npy",
            raw_npy(&header("(1, 13, 2)"), &c15[..26]),
        ),
        (
            "npy_17_joints.npy",
            raw_npy(&header("(1, 17, 2)"), &[0.0; 34]),
        ),
        (
            "npy_int32.npy",
            raw_npy(
                "{'descr': '<i4', 'fortran_order': False, 'shape': (1, 15, 4), }",
                &c15[..30],
            ),
        ),
        (
            "npy_shape_overflow.npy",
            raw_npy(&header("(4294967296, 4294967296, 2)"), &[]),
        ),
        ("npy_header_length.npy", long_header),
    ];
    for (name, bytes) in bad {
        files.push((format!("bad/{name}"), bytes));
    }
    files
}

#[test]
fn committed_samples_are_what_the_generator_writes() {
    let write = std::env::var_os("CAMLOC_WRITE_SAMPLES").is_some();
    for (name, bytes) in generated() {
        let path = fixture(&name);
        if write {
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
            std::fs::write(&path, &bytes).unwrap();
        }
        let committed = std::fs::read(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(
            committed == bytes,
            "{name} differs from the generator's output"
        );
        assert!(bytes.len() < 64 << 10, "{name} is small");
    }
}

/// Checks that `records` hold the example poses (`which[i]` is the pose of record i): every
/// landmark equal (within `tol` pixels), except those in `derived_by_format`, which must be
/// derived and equal to their rule (head: the face mean; pelvis, neck: midpoints).
fn same_as_example(
    records: &[KeypointRecord],
    which: &[usize],
    tol: f64,
    derived_by_format: &[Landmark],
) {
    let poses = poses();
    assert_eq!(records.len(), which.len());
    for (record, &p) in records.iter().zip(which) {
        let pose = &poses[p];
        let got = record
            .pose
            .complete()
            .unwrap_or_else(|| panic!("{}", record.id))
            .points;
        for l in Landmark::ALL {
            let expected = if derived_by_format.contains(&l) {
                assert!(record.is_derived(l), "{} {l:?}", record.id);
                match l {
                    L::Pelvis => mid(at(pose, L::LeftHip), at(pose, L::RightHip)),
                    L::Neck => mid(at(pose, L::LeftShoulder), at(pose, L::RightShoulder)),
                    _ => at(pose, l),
                }
            } else {
                assert!(!record.is_derived(l), "{} {l:?}", record.id);
                at(pose, l)
            };
            let d = (got[l.index()][0] - expected[0]).hypot(got[l.index()][1] - expected[1]);
            assert!(
                d <= tol,
                "{} {l:?}: {:?} vs {expected:?}",
                record.id,
                got[l.index()]
            );
        }
    }
}

/// The id, frame and person of each record.
fn ids_frames_persons(records: &[KeypointRecord]) -> Vec<(&str, Option<u64>, Option<u64>)> {
    records
        .iter()
        .map(|r| (r.id.as_str(), r.frame, r.person))
        .collect()
}

/// The face mean is the head up to rounding.
const FACE_TOL: f64 = 1e-9;

#[test]
fn openpose_body25_folder_reads_the_example_poses() {
    let dir = fixture("samples/openpose");
    let mut records = Vec::new();
    let mut frames = Vec::new();
    for (path, result) in read_folder(&dir, None, &ReadOptions::default(), false).unwrap() {
        let file_records = result.unwrap_or_else(|e| panic!("{e}"));
        frames.push((path.file_name().unwrap().to_owned(), file_records.len()));
        records.extend(file_records);
    }
    assert_eq!(frames.len(), 3, "{frames:?}");
    assert_eq!(frames.iter().map(|f| f.1).collect::<Vec<_>>(), [1, 2, 0]);
    same_as_example(&records, &[0, 1, 2], FACE_TOL, &[L::Head]);
    assert_eq!(
        ids_frames_persons(&records),
        [
            ("0/0", Some(0), Some(0)),
            ("1/0", Some(1), Some(0)),
            ("1/1", Some(1), Some(1))
        ]
    );
    assert!(
        records[2]
            .source
            .ends_with("clip_000000000001_keypoints.json: people[1]"),
        "{}",
        records[2].source
    );
}

#[test]
fn openpose_coco18_reads_the_example_poses_with_derived_pelvis() {
    let records = read("samples/openpose_coco18_000000000007_keypoints.json");
    same_as_example(&records, &[0, 1, 2], FACE_TOL, &[L::Pelvis, L::Head]);
    assert!(records.iter().all(|r| r.frame == Some(7)));
    assert_eq!(records[2].id, "7/2");
}

#[test]
fn min_score_drops_weak_joints_in_every_format_with_scores() {
    let options = ReadOptions {
        min_score: 0.1,
        image_size: Some(IMAGE),
        ..ReadOptions::default()
    };
    let weak_pose = |name: &str, index: usize| {
        let options = ReadOptions {
            layout: name.contains("h36m").then_some(Layout::H36m17),
            ..options
        };
        let all = read_keypoints(fixture(name), None, &options).unwrap();
        let default = read_keypoints(
            fixture(name),
            None,
            &ReadOptions {
                min_score: 0.0,
                ..options
            },
        )
        .unwrap();
        assert!(
            default[index].pose.points[WEAK_JOINT.index()].is_some(),
            "{name}"
        );
        all[index].pose.points[WEAK_JOINT.index()]
    };
    for (name, index) in [
        ("samples/openpose_coco18_000000000007_keypoints.json", 1),
        ("samples/mmpose.json", 1),
        ("samples/mediapipe.json", 1),
        ("samples/h36m17_scores.npy", 1),
        ("samples/yolo/clip_1.txt", 0),
    ] {
        assert_eq!(weak_pose(name, index), None, "{name}");
    }
    // A score equal to min_score is kept.
    let at_threshold = ReadOptions {
        min_score: WEAK_SCORE,
        ..options
    };
    let records = read_keypoints(fixture("samples/mmpose.json"), None, &at_threshold).unwrap();
    assert!(records[1].pose.points[WEAK_JOINT.index()].is_some());
}

#[test]
fn mmpose_reads_the_example_poses() {
    let records = read("samples/mmpose.json");
    same_as_example(
        &records,
        &[0, 1, 2],
        FACE_TOL,
        &[L::Pelvis, L::Neck, L::Head],
    );
    assert_eq!(records[1].id, "1/0");
    assert_eq!((records[1].frame, records[1].person), (Some(1), Some(0)));
}

#[test]
fn mediapipe_reads_the_example_poses_given_the_image_size() {
    let options = ReadOptions {
        image_size: Some(IMAGE),
        ..ReadOptions::default()
    };
    let records = read_keypoints(fixture("samples/mediapipe.json"), None, &options).unwrap();
    // Normalising and scaling back costs at most an ulp or two.
    same_as_example(&records, &[0, 1, 2], 1e-9, &[L::Pelvis, L::Neck, L::Head]);
    // The null frame has no pose; frames keep their positions.
    let frames: Vec<_> = records.iter().map(|r| r.frame).collect();
    assert_eq!(frames, [Some(0), Some(1), Some(3)]);
    // Without the image size: a clear error naming the file.
    let e = read_keypoints(
        fixture("samples/mediapipe.json"),
        None,
        &ReadOptions::default(),
    )
    .unwrap_err();
    let message = e.to_string();
    assert!(
        message.contains("mediapipe.json: MediaPipe coordinates are normalised"),
        "{message}"
    );
    assert!(message.contains("--image-size W,H"), "{message}");
}

#[test]
fn yolo_folder_reads_the_example_poses_given_the_image_size() {
    let options = ReadOptions {
        image_size: Some(IMAGE),
        ..ReadOptions::default()
    };
    let mut records = Vec::new();
    for (_, result) in read_folder(fixture("samples/yolo"), None, &options, false).unwrap() {
        records.extend(result.unwrap_or_else(|e| panic!("{e}")));
    }
    same_as_example(&records, &[0, 1, 2], 1e-9, &[L::Pelvis, L::Neck, L::Head]);
    assert_eq!(
        ids_frames_persons(&records),
        [
            ("0/0", Some(0), Some(0)),
            ("1/0", Some(1), Some(7)),
            ("1/1", Some(1), Some(9))
        ]
    );
    assert!(
        records[2].source.ends_with("clip_1.txt: line 2"),
        "{}",
        records[2].source
    );
    let e = read_keypoints(
        fixture("samples/yolo/clip_0.txt"),
        None,
        &ReadOptions::default(),
    );
    let message = e.unwrap_err().to_string();
    assert!(
        message.contains("YOLO coordinates are normalised"),
        "{message}"
    );
}

#[test]
fn mpii_reads_the_example_poses() {
    let records = read("samples/mpii.json");
    same_as_example(&records, &[0, 1, 2], 0.0, &[]);
    assert_eq!(records[0].id, "example_0.jpg/0");
}

#[test]
fn npy_samples_read_the_example_poses() {
    let camloc15 = read("samples/camloc15.npy");
    same_as_example(&camloc15, &[0, 1, 2], 0.0, &[]);
    assert_eq!(camloc15[2].id, "2");
    assert!(camloc15[2].source.ends_with("camloc15.npy: [2]"));
    // 17 joints need the layout named.
    let options = ReadOptions {
        layout: Some(Layout::H36m17),
        ..ReadOptions::default()
    };
    let h36m = read_keypoints(fixture("samples/h36m17_scores.npy"), None, &options).unwrap();
    same_as_example(&h36m, &[0, 1, 2], 0.0, &[]);
}

#[test]
fn detection_recognises_every_sample() {
    let options = ReadOptions {
        image_size: Some(IMAGE),
        layout: Some(Layout::H36m17),
        ..ReadOptions::default()
    };
    for (name, format) in [
        (
            "samples/openpose/clip_000000000000_keypoints.json",
            KeypointFormat::OpenPose,
        ),
        (
            "samples/openpose_coco18_000000000007_keypoints.json",
            KeypointFormat::OpenPose,
        ),
        ("samples/mmpose.json", KeypointFormat::MmPose),
        ("samples/mediapipe.json", KeypointFormat::MediaPipe),
        ("samples/mpii.json", KeypointFormat::Mpii),
        ("samples/camloc15.npy", KeypointFormat::Npy),
        ("samples/h36m17_scores.npy", KeypointFormat::Npy),
        ("samples/yolo/clip_0.txt", KeypointFormat::Yolo),
    ] {
        let bytes = std::fs::read(fixture(name)).unwrap();
        let text = String::from_utf8_lossy(&bytes);
        let ext = name.rsplit('.').next();
        assert_eq!(
            KeypointFormat::from_extension_and_content(ext, &text),
            Some(format),
            "{name}"
        );
        let options = ReadOptions {
            layout: (name.contains("h36m")).then_some(Layout::H36m17),
            ..options
        };
        let detected = read_keypoints(fixture(name), None, &options).unwrap();
        let explicit = read_keypoints(fixture(name), Some(format), &options).unwrap();
        assert_eq!(detected, explicit, "{name}");
        // From a stream without a name or size (standard input), the content alone decides.
        let stream = camloc_keypoints::open_keypoints_reader(
            std::io::Cursor::new(bytes),
            "-",
            None,
            None,
            &options,
        )
        .unwrap()
        .collect::<Result<Vec<_>, _>>()
        .unwrap();
        assert_eq!(stream.len(), explicit.len(), "{name}");
        assert_eq!(stream[0].pose, explicit[0].pose, "{name}");
    }
}

#[test]
fn options_parse_from_the_text_a_command_line_gives() {
    let size = |w, h| ImageSize {
        width: w,
        height: h,
    };
    assert_eq!("1920,1080".parse::<ImageSize>(), Ok(size(1920.0, 1080.0)));
    assert_eq!(" 640 x 480 ".parse::<ImageSize>(), Ok(size(640.0, 480.0)));
    assert_eq!(
        size(640.0, 480.5).to_string().parse(),
        Ok(size(640.0, 480.5))
    );
    for bad in ["", "1920", "0,10", "-5,5", "nan,1", "inf,2", "1,2,3", "a,b"] {
        let e = bad.parse::<ImageSize>().unwrap_err();
        assert!(e.to_string().contains("W,H"), "{bad}: {e}");
    }
    for format in KeypointFormat::ALL {
        assert_eq!(format.name().parse(), Ok(format));
        assert!(KeypointFormat::NAMES.contains(format.name()));
    }
    for layout in Layout::ALL {
        assert!(Layout::NAMES.contains(layout.name()));
    }
}

#[test]
fn streams_and_records_can_move_to_worker_threads() {
    fn send<T: Send>() {}
    send::<camloc_keypoints::KeypointStream>();
    send::<camloc_keypoints::FolderRecords>();
    send::<KeypointRecord>();
    send::<camloc_keypoints::KeypointError>();
}
