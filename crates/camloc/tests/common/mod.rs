//! What several of this crate's tests read.

use camloc::keypoints::{KeypointRecord, ReadOptions, read_keypoints};

/// The example poses of fixtures/keypoints/example.json (image coordinates; each id names the
/// camera the pose was drawn for), read with the default options.
pub fn example_records() -> Vec<KeypointRecord> {
    let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/keypoints/example.json");
    read_keypoints(&file, None, &ReadOptions::default()).unwrap()
}
