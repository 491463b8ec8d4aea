//! camloc JSON documents longer than `STREAM_PEEK_BYTES` are streamed: the records, and the
//! errors, are those of the whole-text reader, and records come before the rest of the input is
//! read.

use std::io::{self, Read};
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use camloc_keypoints::{
    KeypointError, KeypointFormat, KeypointRecord, ReadOptions, STREAM_PEEK_BYTES,
    open_keypoints_reader, parse_keypoints,
};

/// One pose object with id `p{i}` and a full torso.
fn pose(i: usize) -> String {
    format!(
        r#"{{"id": "p{i}", "landmarks": {{"pelvis": [{i}, 250.5], "neck": [{i}.25, 161], "head": null}}}}"#
    )
}

/// `count` poses, comma-separated, with `bad` (if any) replacing pose `at`.
fn poses(count: usize, bad: Option<(usize, &str)>) -> String {
    (0..count)
        .map(|i| match bad {
            Some((at, text)) if at == i => text.to_owned(),
            _ => pose(i),
        })
        .collect::<Vec<_>>()
        .join(",\n")
}

/// The input read through the stream (size unknown, as a pipe), as a list of results.
fn streamed(text: &str, options: &ReadOptions) -> Result<Vec<KeypointRecord>, String> {
    let reader = io::Cursor::new(text.as_bytes().to_vec());
    open_keypoints_reader(reader, "doc.json", None, None, options)
        .map_err(|e| e.to_string())?
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| e.to_string())
}

/// The input read whole.
fn whole(text: &str, options: &ReadOptions) -> Result<Vec<KeypointRecord>, String> {
    parse_keypoints(text, "doc.json", None, options).map_err(|e| e.to_string())
}

#[test]
fn streamed_documents_give_the_records_and_errors_of_the_whole_text_reader() {
    let options = ReadOptions::default();
    let many = poses(1000, None);
    let long_id = "x".repeat(STREAM_PEEK_BYTES as usize);
    let cases = [
        format!(r#"{{"format": "camloc-keypoints", "version": 1, "poses": [{many}]}}"#),
        format!("\u{feff}\n{{\"poses\": [{many}]}}\n"),
        // A bare pose.
        format!(r#"{{"landmarks": {{"neck": [1, 2]}}, "id": "{long_id}"}}"#),
        // Document-level errors after the poses come after them ...
        format!(r#"{{"poses": [{many}], "version": 2}}"#),
        format!(r#"{{"poses": [{many}], "format": "other"}}"#),
        format!(r#"{{"poses": [{many}], "poses": []}}"#),
        // ... and before them, stop before any pose (all unknown keys named).
        format!(r#"{{"version": 3, "poses": [{many}]}}"#),
        format!(r#"{{"nose": 1, "poses": [{many}], "ears": 2}}"#),
        format!(r#"{{"poses": {{"a": "{long_id}"}}}}"#),
        format!(r#"{{"poses": "{long_id}"}}"#),
        // Pose errors, the first in input order.
        format!(
            r#"{{"poses": [{}]}}"#,
            poses(1000, Some((700, r#"{"landmarks": {"neck": [1, 2, 3]}}"#)))
        ),
        format!(
            r#"{{"poses": [{}]}}"#,
            poses(1000, Some((3, r#"{"landmarks": {"nose": [1, 2]}}"#)))
        ),
        format!(r#"{{"poses": [{}]}}"#, poses(1000, Some((999, "[]")))),
        // Syntax errors: line and column as in the whole text.
        format!("{{\"poses\": [{many}"),
        format!("{{\"poses\": [{many}]}} trailing"),
    ];
    for text in &cases {
        assert!(text.len() as u64 > STREAM_PEEK_BYTES, "{}", &text[..40]);
        let expected = whole(text, &options);
        assert_eq!(streamed(text, &options), expected, "{}", &text[..40]);
    }
    // A number out of range: the streaming parser reports it one column further on.
    for text in [
        format!(r#"{{"nose": 1, "poses": [{many}], "ears": [1e400]}}"#),
        format!("{{\"poses\": [{many}, {{\"landmarks\": {{\"neck\": [1e400, 0]}}}}]}}"),
    ] {
        let line = |message: String| message.split(", column").next().map(str::to_owned);
        let expected = whole(&text, &options).unwrap_err();
        assert!(expected.contains("number out of range"), "{expected}");
        assert_eq!(line(streamed(&text, &options).unwrap_err()), line(expected));
    }
    let records = whole(&cases[0], &options).unwrap();
    assert_eq!(records.len(), 1000);
    assert_eq!(records[999].source, "doc.json: poses[999]");
    for (text, expected) in [
        (&cases[3], "unsupported camloc-keypoints version 2"),
        (
            &cases[7],
            r#"unknown key(s) "nose" (did you mean "poses"?), "ears""#,
        ),
        (&cases[10], "poses[700].landmarks.neck"),
        (&cases[13], "line 1000"),
    ] {
        let message = whole(text, &options).unwrap_err();
        assert!(message.contains(expected), "{message}");
    }
}

#[test]
fn an_error_after_some_poses_ends_the_stream_after_them() {
    let text = format!(r#"{{"poses": [{}], "version": 2}}"#, poses(1000, None));
    let reader = io::Cursor::new(text.into_bytes());
    let items: Vec<_> =
        open_keypoints_reader(reader, "doc.json", None, None, &ReadOptions::default())
            .unwrap()
            .collect();
    assert_eq!(items.len(), 1001);
    assert!(items[..1000].iter().all(Result::is_ok));
    assert!(
        matches!(&items[1000], Err(KeypointError::UnsupportedVersion { .. })),
        "{:?}",
        items[1000]
    );
}

#[test]
fn an_unsized_stream_is_cut_at_the_size_limit() {
    let text = format!(r#"{{"poses": [{}]}}"#, poses(3000, None));
    let options = ReadOptions {
        max_bytes: 2 * STREAM_PEEK_BYTES,
        ..ReadOptions::default()
    };
    assert!(text.len() as u64 > options.max_bytes);
    let reader = io::Cursor::new(text.into_bytes());
    let items: Vec<_> = open_keypoints_reader(reader, "doc.json", None, None, &options)
        .unwrap()
        .collect();
    let (last, records) = items.split_last().unwrap();
    assert!(!records.is_empty() && records.iter().all(Result::is_ok));
    assert!(
        matches!(last, Err(KeypointError::TooLarge { bytes, limit, .. }) if *limit == options.max_bytes && bytes > limit),
        "{last:?}"
    );
}

/// An endless camloc JSON document (`{"poses": [pose, pose, ...`) that fails once `fail_at`
/// bytes have been read, counting the bytes read.
struct Endless {
    pending: Vec<u8>,
    next: usize,
    read: Arc<AtomicU64>,
    fail_at: u64,
}

impl Read for Endless {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        if self.read.load(Ordering::SeqCst) >= self.fail_at {
            return Err(io::Error::other("read past the end of the test input"));
        }
        while self.pending.len() < buf.len() {
            let separator = if self.next == 0 { "{\"poses\": [" } else { "," };
            self.pending
                .extend_from_slice(format!("{separator}{}", pose(self.next)).as_bytes());
            self.next += 1;
        }
        let n = buf.len();
        buf.copy_from_slice(&self.pending[..n]);
        self.pending.drain(..n);
        self.read.fetch_add(n as u64, Ordering::SeqCst);
        Ok(n)
    }
}

/// Memory does not grow with the input: the first records arrive while the reader is far from
/// its end, and the producer stops reading when the consumer does not take more (a reader
/// that is read whole would fail with its error before giving any record).
#[test]
fn the_first_records_come_before_the_rest_is_read() {
    let read = Arc::new(AtomicU64::new(0));
    let reader = Endless {
        pending: Vec::new(),
        next: 0,
        read: Arc::clone(&read),
        fail_at: 64 << 20,
    };
    let mut stream = open_keypoints_reader(
        reader,
        "endless.json",
        None,
        Some(KeypointFormat::Camloc),
        &ReadOptions::default(),
    )
    .unwrap();
    for i in 0..3000 {
        let record = stream.next().unwrap().unwrap();
        assert_eq!(record.id, format!("p{i}"));
    }
    // The producer waits on the bounded channel: ~1,500 records (~100 bytes each) in flight,
    // plus the peeked start and the read buffer.
    let bound = 3000 * 100 + 1500 * 100 + 4 * STREAM_PEEK_BYTES;
    let now = read.load(Ordering::SeqCst);
    assert!(now < bound, "{now} bytes read, bound {bound}");
    drop(stream);
}

/// A COCO-17 pose as MMPose keypoints: a face-sized cluster first, then the body.
fn coco_points(shift: f64) -> Vec<[f64; 2]> {
    let face = [
        [0.0, 0.0],
        [-3.0, -3.0],
        [3.0, -3.0],
        [-6.0, 0.0],
        [6.0, 0.0],
    ];
    let body = [
        [-20.0, 30.0],
        [20.0, 30.0],
        [-25.0, 60.0],
        [25.0, 60.0],
        [-27.0, 90.0],
        [27.0, 90.0],
        [-10.0, 100.0],
        [10.0, 100.0],
        [-10.0, 150.0],
        [10.0, 150.0],
        [-10.0, 200.0],
        [10.0, 200.0],
    ];
    face.iter()
        .chain(&body)
        .map(|p| [p[0] + shift, p[1]])
        .collect()
}

/// Human3.6M-ordered points (pelvis and legs first) that contradict COCO-17.
fn h36m_points() -> Vec<[f64; 2]> {
    (0..17)
        .map(|j| [3.0 * f64::from(j), 10.0 * f64::from(j % 7)])
        .collect()
}

/// An MMPose document of `frames` frames of two instances, instance `refused.1` of frame
/// `refused.0` in the other 17-joint layout.
fn mmpose_frames(frames: usize, refused: (usize, usize)) -> String {
    let instance = |points: Vec<[f64; 2]>| {
        let points: Vec<String> = points
            .iter()
            .map(|p| format!("[{}, {}]", p[0], p[1]))
            .collect();
        format!(r#"{{"keypoints": [{}]}}"#, points.join(", "))
    };
    let frames: Vec<String> = (0..frames)
        .map(|f| {
            let [first, second] = [f as f64 * 0.1, 100.0].map(coco_points);
            let mut pair = [first, second];
            if f == refused.0 {
                pair[refused.1] = h36m_points();
            }
            let [first, second] = pair;
            format!(
                r#"{{"frame_id": {f}, "instances": [{}, {}]}}"#,
                instance(first),
                instance(second)
            )
        })
        .collect();
    format!("[{}]", frames.join(",\n"))
}

/// A pose refused for its layout is an error in its place, and the frame's other instance and
/// the next frames are still read, whether the input is read whole or streamed, and whether it
/// is the input's first pose or not (a streamed file whose first pose was refused had been
/// refused whole; a simulated user); the whole-text parser still refuses the input with that
/// error.
#[test]
fn a_pose_refused_for_its_layout_does_not_end_the_input() {
    for (frames, refused, at) in [
        (4, (1, 1), 3),
        (2000, (1, 1), 3),
        (4, (0, 0), 0),
        (2000, (0, 0), 0),
    ] {
        let text = mmpose_frames(frames, refused);
        assert_eq!(
            text.len() as u64 > STREAM_PEEK_BYTES,
            frames > 4,
            "{}",
            text.len()
        );
        let reader = io::Cursor::new(text.as_bytes().to_vec());
        let items: Vec<_> = open_keypoints_reader(
            reader,
            "pred.json",
            None,
            Some(KeypointFormat::MmPose),
            &ReadOptions::default(),
        )
        .unwrap()
        .collect();
        assert_eq!(items.len(), 2 * frames, "{frames}");
        let failed: Vec<usize> = (0..items.len()).filter(|&i| items[i].is_err()).collect();
        assert_eq!(failed, [at], "{frames}");
        assert!(matches!(
            items[at],
            Err(KeypointError::LayoutMismatch { .. })
        ));
        let last = items.last().unwrap().as_ref().unwrap();
        assert_eq!(last.frame, Some(frames as u64 - 1));
        let e = parse_keypoints(
            &text,
            "pred.json",
            Some(KeypointFormat::MmPose),
            &ReadOptions::default(),
        )
        .unwrap_err();
        assert!(matches!(e, KeypointError::LayoutMismatch { .. }), "{e}");
    }
}
