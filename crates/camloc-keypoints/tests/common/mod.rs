//! Helpers shared by the integration tests.

#![allow(dead_code)] // each test crate uses a different subset

use std::path::PathBuf;

use camloc_keypoints::{ImageSize, KeypointRecord, Landmark, ReadOptions, read_keypoints};

/// The image size of the MediaPipe and YOLO samples (pixels).
pub const SAMPLE_IMAGE: ImageSize = ImageSize {
    width: 640.0,
    height: 480.0,
};

/// `fixtures/keypoints/<name>` in the repository.
pub fn fixture(name: &str) -> PathBuf {
    PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../fixtures/keypoints"
    ))
    .join(name)
}

/// The text of a fixture.
pub fn fixture_text(name: &str) -> String {
    std::fs::read_to_string(fixture(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Reads a fixture with default options and format detection, panicking on error.
pub fn read(name: &str) -> Vec<KeypointRecord> {
    read_keypoints(fixture(name), None, &ReadOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

/// A landmark's point, panicking with the record id when it is missing.
pub fn point(record: &KeypointRecord, landmark: Landmark) -> [f64; 2] {
    record.pose.points[landmark.index()]
        .unwrap_or_else(|| panic!("{}: {} missing", record.id, landmark.name()))
}

/// Midpoint of two points.
pub fn mid(p: [f64; 2], q: [f64; 2]) -> [f64; 2] {
    [0.5 * p[0] + 0.5 * q[0], 0.5 * p[1] + 0.5 * q[1]]
}
