//! Regression tests of a third round of hostile inputs (a simulated reviewer's): each failed
//! before its fix, by memory or time out of proportion with the input.

use camloc_keypoints::{
    KeypointError, KeypointFormat, KeypointStream, ReadOptions, open_keypoints_reader,
    parse_keypoints,
};

/// The records of `text` named `name`, as `open_keypoints_reader` streams them.
fn open_text(text: String, name: &str) -> KeypointStream {
    let reader = std::io::Cursor::new(text.into_bytes());
    open_keypoints_reader(reader, name, None, None, &ReadOptions::default()).unwrap()
}

/// A CSV header or row of a million fields is refused with a count of them, not a list (it
/// had kept one string per field: 3 GB for a 100 MB header of commas).
#[test]
fn a_csv_line_of_a_million_fields_is_counted_not_kept() {
    let commas = ",".repeat(1_000_000);
    let e = parse_keypoints(
        &commas,
        "wide.csv",
        Some(KeypointFormat::Lsp),
        &ReadOptions::default(),
    )
    .unwrap_err();
    let message = e.to_string();
    assert!(matches!(e, KeypointError::CsvHeader { .. }), "{e:?}");
    assert!(message.contains("… and 999993 more"), "{message}");
    assert!(message.len() < 1_000, "{}", message.len());
    let text = format!("image,joint,x,y,visible\n{commas}\n");
    let e = parse_keypoints(
        &text,
        "wide.csv",
        Some(KeypointFormat::Lsp),
        &ReadOptions::default(),
    )
    .unwrap_err();
    assert!(
        matches!(
            e,
            KeypointError::CsvFieldCount {
                expected: 5,
                found: 1_000_001,
                ..
            }
        ),
        "{e:?}"
    );
}

/// A camloc document of 200,000 unknown top-level keys is refused naming a few and counting
/// the rest (its keys were compared pair by pair: 38 s).
#[test]
fn a_document_of_many_unknown_keys_is_refused_with_their_count() {
    let keys: String = (0..200_000).map(|i| format!("\"k{i:x}\": 0, ")).collect();
    let text = format!(r#"{{{keys}"poses": []}}"#);
    let e = parse_keypoints(&text, "keys.json", None, &ReadOptions::default()).unwrap_err();
    assert!(matches!(e, KeypointError::UnknownKeys { .. }), "{e:?}");
    assert!(e.to_string().contains("more"), "{e}");
    // The same key 200,000 times is one repeated key.
    let repeated: String = (0..200_000).map(|_| "\"version\": 1, ").collect();
    let text = format!(r#"{{{repeated}"poses": []}}"#);
    let e = parse_keypoints(&text, "twice.json", None, &ReadOptions::default()).unwrap_err();
    assert!(matches!(e, KeypointError::DuplicateKey { .. }), "{e:?}");
}

/// A short document after a long blank lead is streamed (read whole, its lead had been held:
/// 886 MB for 900 MB of spaces), and its errors keep their line.
#[test]
fn a_short_document_after_a_long_blank_lead_is_streamed() {
    let pose = r#"{"landmarks": {"pelvis": [1, 2], "neck": [1, 1]}}"#;
    let lead = " ".repeat(100_000) + "\n";
    let stream = open_text(format!(r#"{lead}{{"poses": [{pose}]}}"#), "padded.json");
    assert_eq!(stream.size_hint(), (0, None));
    assert_eq!(stream.count(), 1);
    let stream = open_text(format!(r#"{lead}{{"poses": [{pose},]}}"#), "padded.json");
    let e = stream.last().unwrap().unwrap_err();
    assert!(matches!(e, KeypointError::Json { line: 2, .. }), "{e:?}");
}

/// An `.npz` archive and UTF-16 or UTF-32 text say what they are (they had been "not valid
/// UTF-8").
#[test]
fn an_archive_and_text_in_utf16_say_what_they_are() {
    let cases: [(&[u8], &str); 6] = [
        (b"PK\x03\x04\x14\x00", "a ZIP archive"),
        (b"\xFF\xFE{\x00}\x00", "UTF-16 text"),
        (b"\xFE\xFF\x00{\x00}", "UTF-16 text"),
        (b"\xFF\xFE\x00\x00{\x00\x00\x00", "UTF-32 text"),
        (b"{\x00\"\x00p\x00", "UTF-16 text"),
        (b"\x00{\x00\"\x00p", "UTF-16 text"),
    ];
    for (bytes, what) in cases {
        let reader = std::io::Cursor::new(bytes.to_vec());
        let e = open_keypoints_reader(reader, "in.json", None, None, &ReadOptions::default())
            .err()
            .unwrap();
        assert!(matches!(e, KeypointError::NotKeypoints { .. }), "{e:?}");
        assert!(e.to_string().contains(what), "{e}");
    }
}

/// A long text where a camloc JSON document names its format or version is quoted short in
/// the message (it was copied whole: a megabyte of message), and a long id is the pose's.
#[test]
fn long_texts_of_a_camloc_document_are_quoted_short_and_a_long_id_is_kept() {
    let long = "x".repeat(1_000_000);
    for document in [
        format!(r#"{{"format": "{long}", "version": 1, "poses": []}}"#),
        format!(r#"{{"format": "camloc-keypoints", "version": "{long}", "poses": []}}"#),
    ] {
        let e = parse_keypoints(
            &document,
            "long.json",
            Some(KeypointFormat::Camloc),
            &ReadOptions::default(),
        )
        .unwrap_err();
        let message = e.to_string();
        assert!(message.len() < 1_000, "{}", message.len());
    }
    let pose = format!(
        r#"{{"format": "camloc-keypoints", "version": 1, "poses": [{{"id": "{long}", "landmarks": {{"pelvis": [1, 2]}}}}]}}"#
    );
    let records = parse_keypoints(
        &pose,
        "id.json",
        Some(KeypointFormat::Camloc),
        &ReadOptions::default(),
    )
    .unwrap();
    assert_eq!(records[0].id, long);
}
