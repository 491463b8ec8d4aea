//! `.npy` keypoint arrays in every dtype the reader takes (`float64` and `float32`, little- or
//! big-endian) give the same records, and a truncated stream fails at the same pose in each.

use std::io::Cursor;

use camloc_keypoints::{KeypointRecord, ReadOptions, open_keypoints_reader};

/// Two poses of 15 joints (x, y), numbers a `float32` holds exactly, joint 3 of pose 1 missing
/// (NaN, NaN).
fn values() -> Vec<f64> {
    let mut values: Vec<f64> = (0..60).map(|k| 100.0 + k as f64 * 2.5).collect();
    values[30 + 6] = f64::NAN;
    values[30 + 7] = f64::NAN;
    values
}

/// An array of shape (N, 15, 2) with `descr`, its numbers written by `bytes`.
fn npy(descr: &str, values: &[f64], bytes: impl Fn(f64) -> Vec<u8>) -> Vec<u8> {
    let n = values.len() / 30;
    let mut header =
        format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': ({n}, 15, 2), }}");
    while !(10 + header.len() + 1).is_multiple_of(64) {
        header.push(' ');
    }
    header.push('\n');
    let mut out = b"\x93NUMPY\x01\x00".to_vec();
    out.extend_from_slice(&(header.len() as u16).to_le_bytes());
    out.extend_from_slice(header.as_bytes());
    for &v in values {
        out.extend_from_slice(&bytes(v));
    }
    out
}

/// Every dtype the reader takes, as (descr, the array of `values`).
fn arrays(values: &[f64]) -> Vec<(&'static str, Vec<u8>)> {
    let f32 = |v: f64| v as f32;
    vec![
        ("<f8", npy("<f8", values, |v| v.to_le_bytes().to_vec())),
        (">f8", npy(">f8", values, |v| v.to_be_bytes().to_vec())),
        ("<f4", npy("<f4", values, |v| f32(v).to_le_bytes().to_vec())),
        (">f4", npy(">f4", values, |v| f32(v).to_be_bytes().to_vec())),
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
    let values = values();
    let reference = read(&arrays(&values)[0].1).unwrap();
    assert_eq!(reference.len(), 2);
    assert_eq!(reference[0].pose.points[1], Some([105.0, 107.5]));
    assert_eq!(reference[1].pose.points[3], None);
    for (descr, bytes) in arrays(&values) {
        assert_eq!(read(&bytes).unwrap(), reference, "{descr}");
    }
}

#[test]
fn a_truncated_stream_fails_at_the_same_pose_in_every_dtype() {
    for (descr, bytes) in arrays(&values()) {
        // The second pose loses its last number but one byte.
        let cut = &bytes[..bytes.len() - 1];
        let e = read(cut).unwrap_err();
        assert_eq!(
            e, "a.npy: [1]: the data end inside pose 1 of 2 (truncated?)",
            "{descr}"
        );
    }
}
