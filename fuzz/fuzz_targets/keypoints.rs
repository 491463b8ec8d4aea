//! The 2D keypoint readers never panic: the first byte picks the format (camloc JSON, LSP CSV,
//! COCO JSON or auto-detection), the rest is the file.
#![no_main]
use camloc_keypoints::{KeypointFormat, ReadOptions, parse_keypoints_bytes};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((&selector, rest)) = data.split_first() else {
        return;
    };
    let format = match selector % 4 {
        0 => Some(KeypointFormat::Camloc),
        1 => Some(KeypointFormat::Lsp),
        2 => Some(KeypointFormat::Coco),
        _ => None,
    };
    if let Ok(records) = parse_keypoints_bytes(rest, "fuzz", format, &ReadOptions::default()) {
        for r in &records {
            let _ = r.require_torso();
        }
    }
});
