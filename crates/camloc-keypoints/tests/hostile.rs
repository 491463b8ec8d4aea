//! Regression tests of issue 22 ("hostile inputs round 2"): each failed before its fix.

mod common;

use std::io::Read;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use camloc_keypoints::{
    KeypointError, KeypointFormat, KeypointStream, Layout, ReadOptions, open_keypoints_reader,
    parse_keypoints,
};

/// Parses `text` as `format` with default options.
fn parse(text: &str, format: KeypointFormat) -> Result<usize, KeypointError> {
    parse_keypoints(text, "t.json", Some(format), &ReadOptions::default()).map(|r| r.len())
}

/// A COCO-17-sized MMPose keypoint list and its scores.
fn mmpose_instance(extra: &str) -> String {
    let points = vec!["[1.0, 2.0]"; 17].join(", ");
    let scores = vec!["0.9"; 17].join(", ");
    format!(r#"{{"keypoints": [{points}], "keypoint_scores": [{scores}]{extra}}}"#)
}

#[test]
fn openpose_and_mmpose_refuse_repeated_keys() {
    let keypoints = vec!["1.0"; 75].join(", ");
    let person = format!(r#"{{"pose_keypoints_2d": [{keypoints}]}}"#);
    let twice_in_person = format!(
        r#"{{"people": [{{"pose_keypoints_2d": [{keypoints}], "pose_keypoints_2d": []}}]}}"#
    );
    let people_twice = format!(r#"{{"people": [{person}], "people": []}}"#);
    for text in [twice_in_person, people_twice] {
        let e = parse(&text, KeypointFormat::OpenPose).unwrap_err();
        assert!(matches!(e, KeypointError::DuplicateKey { .. }), "{e:?}");
    }
    let instance = mmpose_instance(r#", "keypoints": []"#);
    let frames = format!(
        r#"[{{"frame_id": 1, "frame_id": 2, "instances": [{}]}}]"#,
        mmpose_instance("")
    );
    let info = format!(
        r#"{{"instance_info": [{}], "instance_info": []}}"#,
        mmpose_instance("")
    );
    for text in [format!("[{instance}]"), frames, info] {
        let e = parse(&text, KeypointFormat::MmPose).unwrap_err();
        assert!(
            matches!(e, KeypointError::DuplicateKey { .. }),
            "{text}: {e:?}"
        );
    }
    // Other keys (bbox, meta_info) may still appear once each.
    let fine = format!(
        r#"{{"meta_info": {{}}, "instance_info": [{}]}}"#,
        mmpose_instance(r#", "bbox": [[1, 2, 3, 4]]"#)
    );
    assert_eq!(parse(&fine, KeypointFormat::MmPose).unwrap(), 1);
}

#[test]
fn a_long_lsp_input_with_a_wrong_header_is_refused_before_it_is_read_whole() {
    let options = ReadOptions {
        max_bytes: 64 << 20,
        ..ReadOptions::default()
    };
    let (reader, given) = endless(b"\nimage,joint,x,y\n", b"im1,head,1,2\n");
    let e = open_keypoints_reader(reader, "s.csv", None, Some(KeypointFormat::Lsp), &options)
        .err()
        .unwrap();
    assert!(
        matches!(&e, KeypointError::CsvHeader { line: 2, missing, .. } if missing == &["visible"]),
        "{e:?}"
    );
    let given = given.load(Ordering::Relaxed);
    assert!(given < 1 << 20, "{given} bytes read");
}

#[test]
fn a_minimum_score_that_no_joint_can_pass_is_refused() {
    let text = format!("[{}]", mmpose_instance(""));
    for value in [f64::NAN, f64::INFINITY, -0.5] {
        let options = ReadOptions {
            min_score: value,
            ..ReadOptions::default()
        };
        let e =
            parse_keypoints(&text, "t.json", Some(KeypointFormat::MmPose), &options).unwrap_err();
        assert!(matches!(e, KeypointError::InvalidMinScore { .. }), "{e:?}");
        assert!(e.to_string().contains("not a finite number >= 0"), "{e}");
        let reader = std::io::Cursor::new(text.clone().into_bytes());
        let e = open_keypoints_reader(reader, "t.json", None, None, &options)
            .err()
            .unwrap();
        assert!(matches!(e, KeypointError::InvalidMinScore { .. }), "{e:?}");
    }
    let options = ReadOptions {
        min_score: 0.3,
        ..ReadOptions::default()
    };
    assert_eq!(
        parse_keypoints(&text, "t.json", Some(KeypointFormat::MmPose), &options)
            .unwrap()
            .len(),
        1
    );
}

#[test]
fn a_version_given_as_text_says_so() {
    let e = parse(r#"{"version": "1", "poses": []}"#, KeypointFormat::Camloc).unwrap_err();
    let message = e.to_string();
    assert!(
        matches!(e, KeypointError::UnsupportedVersion { .. }),
        "{e:?}"
    );
    assert!(message.contains("\"1\" (a string)"), "{message}");
    let e = parse(r#"{"version": 2, "poses": []}"#, KeypointFormat::Camloc).unwrap_err();
    assert!(e.to_string().contains("version 2 "), "{e}");
}

/// A reader that gives `head` and then `unit` over and over, counting the bytes it gave.
struct Endless {
    head: Vec<u8>,
    unit: Vec<u8>,
    at: usize,
    given: Arc<AtomicU64>,
}

impl Read for Endless {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let mut n = 0;
        while n < buf.len() {
            let source = if self.at < self.head.len() {
                &self.head[self.at..]
            } else {
                let k = (self.at - self.head.len()) % self.unit.len();
                &self.unit[k..]
            };
            let m = source.len().min(buf.len() - n);
            buf[n..n + m].copy_from_slice(&source[..m]);
            n += m;
            self.at += m;
        }
        self.given.fetch_add(n as u64, Ordering::Relaxed);
        Ok(n)
    }
}

#[test]
fn one_endless_keypoint_list_is_refused_after_a_bounded_read() {
    let options = ReadOptions {
        image_size: Some("640,480".parse().unwrap()),
        // Far more than the readers may take before refusing one entry.
        max_bytes: 64 << 20,
        ..ReadOptions::default()
    };
    for (format, head, unit) in [
        (KeypointFormat::MmPose, r#"[{"keypoints": ["#, "[1, 2],"),
        (
            KeypointFormat::Mpii,
            r#"[{"image": "a", "joints": ["#,
            "[1, 2],",
        ),
        (
            KeypointFormat::Coco,
            r#"[{"image_id": 1, "keypoints": ["#,
            "1,",
        ),
        (KeypointFormat::MediaPipe, "[[", r#"{"x": 0.5, "y": 0.5},"#),
        (
            KeypointFormat::OpenPose,
            r#"{"people": [{"pose_keypoints_2d": ["#,
            "1,",
        ),
        (
            KeypointFormat::Camloc,
            r#"{"poses": [{"landmarks": {"neck": ["#,
            "1,",
        ),
    ] {
        let (reader, given) = endless(head.as_bytes(), unit.as_bytes());
        let result = open_keypoints_reader(reader, "endless", None, Some(format), &options)
            .and_then(|stream| stream.collect::<Result<Vec<_>, _>>());
        let e = result.unwrap_err();
        assert!(e.to_string().contains("MAX_ENTRY_VALUES"), "{format}: {e}");
        let given = given.load(Ordering::Relaxed);
        assert!(given < 4 << 20, "{format}: {given} bytes read");
    }
}

#[test]
fn an_mmpose_frame_id_must_be_a_frame_number() {
    for frame_id in ["-1", "1.5", "1e30"] {
        let text = format!(
            r#"[{{"frame_id": {frame_id}, "instances": [{}]}}]"#,
            mmpose_instance("")
        );
        let e = parse(&text, KeypointFormat::MmPose).unwrap_err();
        assert!(
            matches!(
                &e,
                KeypointError::InvalidValue {
                    field: "frame_id",
                    ..
                }
            ),
            "{frame_id}: {e:?}"
        );
    }
    let text = format!(
        r#"[{{"frame_id": 7, "instances": [{}]}}]"#,
        mmpose_instance("")
    );
    let records = parse_keypoints(&text, "t.json", None, &ReadOptions::default()).unwrap();
    assert_eq!((records[0].frame, records[0].id.as_str()), (Some(7), "7/0"));
}

/// The records of `text` named `name`, as `open_keypoints_reader` streams them.
fn open_text(text: String, name: &str, format: Option<KeypointFormat>) -> KeypointStream {
    let reader = std::io::Cursor::new(text.into_bytes());
    open_keypoints_reader(reader, name, None, format, &ReadOptions::default()).unwrap()
}

/// An [`Endless`] reader of `head` then `unit`, and its count of bytes given.
fn endless(head: &[u8], unit: &[u8]) -> (Endless, Arc<AtomicU64>) {
    let given = Arc::new(AtomicU64::new(0));
    let reader = Endless {
        head: head.to_vec(),
        unit: unit.to_vec(),
        at: 0,
        given: Arc::clone(&given),
    };
    (reader, given)
}

#[test]
fn input_that_is_not_text_or_no_format_is_refused_from_its_start() {
    let options = ReadOptions {
        max_bytes: 64 << 20,
        ..ReadOptions::default()
    };
    // Random bytes on standard input, and endless text that no format matches.
    for (unit, format) in [
        (&b"\xff\xfe\x00\x93"[..], None),
        (b"\xff", Some(KeypointFormat::Camloc)),
        (b"abc ", None),
    ] {
        let (reader, given) = endless(b"", unit);
        let e = open_keypoints_reader(reader, "-", None, format, &options)
            .err()
            .unwrap();
        assert!(
            matches!(
                e,
                KeypointError::NotUtf8 {
                    line: 1,
                    offset: 0,
                    ..
                } | KeypointError::UnknownFormat { .. }
                    | KeypointError::NotKeypoints { .. }
            ),
            "{e:?}"
        );
        let given = given.load(Ordering::Relaxed);
        assert!(given < 1 << 20, "{given} bytes read");
    }
}

#[test]
fn a_blank_lead_does_not_stop_a_document_from_streaming() {
    let pose = r#"{"landmarks": {"pelvis": [1, 2], "neck": [1, 1]}}"#;
    let poses = vec![pose; 2_000].join(", ");
    let lead = "\n".repeat(70_000) + &" ".repeat(10_000);
    for format in [None, Some(KeypointFormat::Camloc)] {
        let text = format!(r#"{lead}{{"poses": [{poses}]}}"#);
        let stream = open_text(text, "padded.json", format);
        // Streamed records have no known count.
        assert_eq!(stream.size_hint(), (0, None), "{format:?}");
        assert_eq!(stream.count(), 2_000);
    }
    // Errors after the lead keep their line and column.
    let text = format!("{lead}{{\"poses\": [{poses},]}}");
    let stream = open_text(text, "padded.json", None);
    let e = stream.last().unwrap().unwrap_err();
    assert!(
        matches!(e, KeypointError::Json { line: 70_001, .. }),
        "{e:?}"
    );
}

#[test]
fn a_long_lsp_file_gives_its_records_one_at_a_time() {
    let mut text = String::from("image,joint,x,y,visible\n");
    for i in 0..10_000 {
        text.push_str(&format!("im{i},neck,{i},1,1\n"));
    }
    // An image whose rows are apart still comes at the place of its first row.
    text.push_str("im0,head_top,5,6,1\n");
    let stream = open_text(text, "long.csv", None);
    assert_eq!(stream.size_hint(), (0, None));
    let records: Vec<_> = stream.collect::<Result<_, _>>().unwrap();
    assert_eq!(records.len(), 10_000);
    assert_eq!(records[0].id, "im0");
    assert_eq!(records[0].source, "long.csv: line 2");
    assert!(records[0].pose.points[camloc_keypoints::Landmark::Head.index()].is_some());
    assert_eq!(records[9_999].id, "im9999");
}

#[test]
fn an_npy_header_with_another_key_is_refused() {
    let header = "{'descr': '<f8', 'fortran_order': False, 'shape': (0, 15, 2), 'extra': 1, }";
    let mut npy = b"\x93NUMPY\x01\x00".to_vec();
    let padded = format!("{header:<117}\n");
    npy.extend_from_slice(&(padded.len() as u16).to_le_bytes());
    npy.extend_from_slice(padded.as_bytes());
    let e = camloc_keypoints::parse_keypoints_bytes(&npy, "x.npy", None, &ReadOptions::default())
        .unwrap_err();
    assert!(e.to_string().contains("no other key"), "{e}");
}

#[test]
fn a_document_whose_format_comes_late_is_still_given_one_record_at_a_time() {
    let pose = r#"{"landmarks": {"pelvis": [1, 2], "neck": [1, 1]}}"#;
    let poses = vec![pose; 100].join(", ");
    let padding = " ".repeat(70_000);
    let text = format!(r#"{{"format": "camloc-keypoints",{padding}"poses": [{poses}]}}"#);
    let stream = open_text(text, "late.json", None);
    assert_eq!(stream.size_hint(), (0, None));
    assert_eq!(stream.count(), 100);
}

/// A file camloc wrote (here the default model) given as keypoints is named for what it is,
/// not reported as text that is not UTF-8.
#[test]
fn a_camloc_file_given_as_keypoints_says_what_it_is() {
    let model = std::fs::read(common::fixture("../default-model.bin")).unwrap();
    let err =
        camloc_keypoints::parse_keypoints_bytes(&model, "m.bin", None, &ReadOptions::default())
            .unwrap_err();
    assert!(
        matches!(err, KeypointError::CamlocFile { what: "model", .. }),
        "{err}"
    );
    assert!(
        err.to_string().contains("camloc model file, not keypoints"),
        "{err}"
    );
}

/// A pose tracker's `track_id` is the person; one that is not a person number (`-1`,
/// untracked) leaves the instance's position in its frame.
#[test]
fn an_mmpose_track_id_is_the_person() {
    let text = format!(
        r#"[{{"frame_id": 3, "instances": [{}, {}, {}]}}]"#,
        mmpose_instance(r#", "track_id": 12"#),
        mmpose_instance(r#", "track_id": -1"#),
        mmpose_instance("")
    );
    let records = parse_keypoints(&text, "t.json", None, &ReadOptions::default()).unwrap();
    let persons: Vec<_> = records.iter().map(|r| r.person).collect();
    assert_eq!(persons, [Some(12), Some(1), Some(2)]);
}

/// MMPose's 17 keypoints are COCO-17 unless a layout is named: keypoints in Human3.6M order
/// (pelvis and legs first) are refused with the likely layout, and read with it.
#[test]
fn mmpose_keypoints_of_the_other_17_joint_layout_are_refused() {
    // A body along a line whose first five joints spread as Human3.6M's do.
    let points: Vec<String> = (0..17)
        .map(|j| format!("[{}, {}]", 3.0 * f64::from(j), 10.0 * f64::from(j % 7)))
        .collect();
    let text = format!(r#"[{{"keypoints": [{}]}}]"#, points.join(", "));
    let e = parse(&text, KeypointFormat::MmPose).unwrap_err();
    assert!(matches!(e, KeypointError::LayoutMismatch { .. }), "{e:?}");
    assert!(
        e.to_string()
            .contains("the layout is likely h36m17, not coco17 (if the layout is right"),
        "{e}"
    );
    let options = ReadOptions {
        layout: Some(Layout::H36m17),
        ..ReadOptions::default()
    };
    let records = parse_keypoints(&text, "t.json", Some(KeypointFormat::MmPose), &options);
    assert_eq!(records.unwrap().len(), 1);
}

/// COCO and MMPose scores are not range-checked, but a minimum score on a 0-1 scale with
/// scores on a 0-100 one would keep every joint: refused, naming the score; a minimum on the
/// scores' scale reads them.
#[test]
fn scores_on_another_scale_than_the_minimum_are_refused() {
    let coco_keypoints: Vec<String> = (0..17)
        .map(|j| format!("{}, {}, 73.5", 10 * j, 20 * j))
        .collect();
    let coco = format!(
        r#"[{{"image_id": 1, "keypoints": [{}]}}]"#,
        coco_keypoints.join(", ")
    );
    let points = vec!["[1.0, 2.0]"; 17].join(", ");
    let scores = vec!["73.5"; 17].join(", ");
    let mmpose = format!(r#"[{{"keypoints": [{points}], "keypoint_scores": [{scores}]}}]"#);
    for (text, format, at) in [
        (&coco, KeypointFormat::Coco, "[0].keypoints[2]"),
        (&mmpose, KeypointFormat::MmPose, "[0].keypoint_scores[0]"),
    ] {
        let on = |min_score| ReadOptions {
            min_score,
            ..ReadOptions::default()
        };
        let e = parse_keypoints(text, "t.json", Some(format), &on(0.3)).unwrap_err();
        assert!(matches!(e, KeypointError::ScoreScale { .. }), "{e:?}");
        assert!(
            e.to_string()
                .starts_with(&format!("t.json: {at}: score 73.5 is on another scale")),
            "{e}"
        );
        for min_score in [0.0, 30.0] {
            assert_eq!(
                parse_keypoints(text, "t.json", Some(format), &on(min_score))
                    .unwrap()
                    .len(),
                1
            );
        }
    }
}

/// A layout given for a format that names or fixes its joints is refused rather than ignored,
/// unless it is the format's own.
#[test]
fn a_layout_for_a_format_that_does_not_take_one_is_refused() {
    let camloc = r#"{"poses": [{"landmarks": {"neck": [1.0, 2.0]}}]}"#;
    let with = |layout| ReadOptions {
        layout: Some(layout),
        ..ReadOptions::default()
    };
    let e = parse_keypoints(camloc, "p.json", None, &with(Layout::H36m17)).unwrap_err();
    assert!(matches!(e, KeypointError::LayoutNotUsed { .. }), "{e:?}");
    assert!(
        e.to_string()
            .starts_with("p.json: a layout (h36m17) was given, but camloc input"),
        "{e}"
    );
    assert!(parse_keypoints(camloc, "p.json", None, &with(Layout::Camloc15)).is_ok());
    let csv = "image,joint,x,y,visible\nim1,neck,1,2,1\n";
    let e = parse_keypoints(csv, "l.csv", None, &with(Layout::Coco17)).unwrap_err();
    assert!(matches!(e, KeypointError::LayoutNotUsed { .. }), "{e:?}");
}

/// An input of nothing but white space, longer than the peek, is empty (a YOLO frame without
/// people) after its blanks are counted, not held (a simulated user's 1 GB of spaces had been
/// read into memory whole to say so).
#[test]
fn a_long_blank_input_is_empty() {
    let blanks = || std::io::Read::take(std::io::repeat(b' '), 8 << 20);
    let e = open_keypoints_reader(blanks(), "b.json", None, None, &ReadOptions::default())
        .err()
        .unwrap();
    assert!(matches!(e, KeypointError::Empty { .. }), "{e:?}");
    let options = ReadOptions {
        image_size: Some(camloc_keypoints::ImageSize {
            width: 100.0,
            height: 100.0,
        }),
        ..ReadOptions::default()
    };
    let frame = open_keypoints_reader(blanks(), "f_1.txt", None, None, &options).unwrap();
    assert_eq!(frame.count(), 0);
}
