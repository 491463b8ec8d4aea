//! `.npy` keypoint arrays in every dtype the reader takes (`float64` and `float32`, little- or
//! big-endian or this machine's order, with or without `=`) give the same records, and a truncated stream fails at the same pose in each;
//! a row with a value no pose holds is that row's error, the rows after it read.

use std::io::Cursor;

use camloc_keypoints::{
    KeypointRecord, PartialPose2, ReadOptions, open_keypoints_reader, write_npy,
};

/// Two poses with numbers a `float32` holds exactly, joint 3 of the second one missing.
fn poses() -> Vec<PartialPose2> {
    let pose = |first: f64| PartialPose2 {
        points: std::array::from_fn(|j| {
            Some([first + j as f64 * 5.0, first + 2.5 + j as f64 * 5.0])
        }),
    };
    let mut second = pose(250.0);
    second.points[3] = None;
    vec![pose(100.0), second]
}

/// Every dtype the reader takes, as (descr, the array of [`poses`]): the crate's own `<f8`
/// array, its header given another descr of the same length and its numbers re-encoded.
fn arrays() -> Vec<(&'static str, Vec<u8>)> {
    let mut le = Vec::new();
    write_npy(&mut le, &poses()).unwrap();
    let body_at = 10 + usize::from(u16::from_le_bytes([le[8], le[9]]));
    let (head, body) = le.split_at(body_at);
    let numbers: Vec<f64> = body
        .chunks_exact(8)
        .map(|b| f64::from_le_bytes(b.try_into().unwrap()))
        .collect();
    let array = |descr: &'static str, encode: fn(f64) -> Vec<u8>| {
        let mut bytes = head.to_vec();
        let at = head.windows(5).position(|w| w == b"'<f8'").unwrap();
        bytes[at + 1..at + 4].copy_from_slice(descr.as_bytes());
        bytes.extend(numbers.iter().flat_map(|&v| encode(v)));
        (descr, bytes)
    };
    vec![
        array("<f8", |v| v.to_le_bytes().to_vec()),
        array(">f8", |v| v.to_be_bytes().to_vec()),
        array("<f4", |v| (v as f32).to_le_bytes().to_vec()),
        array(">f4", |v| (v as f32).to_be_bytes().to_vec()),
        // This machine's order, as NumPy reads `=` (hand-made headers).
        array("=f8", |v| v.to_ne_bytes().to_vec()),
        array("=f4", |v| (v as f32).to_ne_bytes().to_vec()),
    ]
}

/// The records read from `bytes` as a stream of unknown size (a pipe), or the first error.
fn read(bytes: &[u8]) -> Result<Vec<KeypointRecord>, String> {
    let options = ReadOptions::default();
    open_keypoints_reader(Cursor::new(bytes.to_vec()), "a.npy", None, None, &options)
        .map_err(|e| e.to_string())?
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| e.to_string())
}

#[test]
fn every_float_dtype_and_byte_order_gives_the_same_records() {
    let arrays = arrays();
    let reference = read(&arrays[0].1).unwrap();
    let poses: Vec<PartialPose2> = reference.iter().map(|r| r.pose).collect();
    assert_eq!(poses, self::poses());
    for (descr, bytes) in arrays {
        assert_eq!(read(&bytes).unwrap(), reference, "{descr}");
    }
}

/// A descr without a byte order (`'f8'`, one character shorter than `'<f8'`, its header
/// padded by one space to keep the data where it was), as NumPy reads it, also from a file
/// whose size is known.
#[test]
fn a_descr_without_a_byte_order_is_read_in_this_machine_s() {
    let (_, mut bytes) = arrays().remove(0);
    let at = bytes.windows(5).position(|w| w == b"'<f8'").unwrap();
    bytes.splice(at..at + 5, *b"'f8'");
    let newline = bytes.iter().position(|&b| b == b'\n').unwrap();
    bytes.insert(newline, b' ');
    if cfg!(target_endian = "little") {
        let reference = read(&arrays()[0].1).unwrap();
        assert_eq!(read(&bytes).unwrap(), reference);
        let size = Some(bytes.len() as u64);
        let options = ReadOptions::default();
        let sized: Vec<KeypointRecord> =
            open_keypoints_reader(Cursor::new(bytes), "a.npy", size, None, &options)
                .unwrap()
                .collect::<Result<_, _>>()
                .unwrap();
        assert_eq!(sized, reference);
    }
}

#[test]
fn a_truncated_stream_fails_at_the_same_pose_in_every_dtype() {
    for (descr, bytes) in arrays() {
        // The second pose loses one byte of its last number.
        let e = read(&bytes[..bytes.len() - 1]).unwrap_err();
        assert_eq!(
            e, "a.npy: [1]: the data end inside pose 1 of 2 (truncated?)",
            "{descr}"
        );
    }
}

#[test]
fn a_row_with_a_value_no_pose_holds_is_its_own_error_and_the_rows_after_it_are_read() {
    let (_, bytes) = &arrays()[0];
    let body_at = bytes.len() - 2 * 15 * 2 * 8;
    // Row 0, joint 3: x NaN, y not; row 1, joint 5: y infinite. Then a clean copy of row 0.
    let mut numbers: Vec<f64> = bytes[body_at..]
        .chunks_exact(8)
        .map(|b| f64::from_le_bytes(b.try_into().unwrap()))
        .collect();
    let clean_first: Vec<f64> = numbers[..30].to_vec();
    numbers[3 * 2] = f64::NAN;
    numbers[30 + 5 * 2 + 1] = f64::INFINITY;
    numbers.extend(clean_first);
    let mut array = bytes[..body_at].to_vec();
    let shape = array.windows(4).position(|w| w == b"(2, ").unwrap();
    array[shape + 1] = b'3';
    array.extend(numbers.iter().flat_map(|v| v.to_le_bytes()));
    let options = ReadOptions::default();
    let items: Vec<_> = open_keypoints_reader(Cursor::new(array), "a.npy", None, None, &options)
        .unwrap()
        .collect();
    assert_eq!(items.len(), 3);
    let refused: Vec<(String, String)> = items[..2]
        .iter()
        .map(|item| {
            let e = item.as_ref().unwrap_err();
            assert!(e.is_pose_error(), "{e}");
            let (place, why) = e.refused_pose().unwrap();
            (format!("{}: {why}", place.source), e.to_string())
        })
        .collect();
    assert_eq!(
        refused[0].0,
        "a.npy: [0]: joint 3: one coordinate is NaN and the other is not (NaN, NaN marks a missing joint)"
    );
    assert!(
        refused[0].1.starts_with("a.npy: [0, 3]: "),
        "{}",
        refused[0].1
    );
    assert_eq!(
        refused[1].0,
        "a.npy: [1]: joint 5's y: inf is not a finite number"
    );
    assert_eq!(items[2].as_ref().unwrap().pose, poses()[0]);
}
