//! The detector-format readers (OpenPose, MMPose, MediaPipe, MPII, `.npy`) and the raw-array
//! mapping never panic. Byte 0 picks the format (or detection), byte 1 the layout, `min_score`
//! and whether the input is read as bytes or as a stream without a known size; the rest is the
//! file.
#![no_main]
use camloc_keypoints::{
    ImageSize, KeypointFormat, Layout, ReadOptions, open_keypoints_reader, parse_keypoints_bytes,
    pose_from_array,
};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let [selector, knobs, rest @ ..] = data else {
        return;
    };
    let formats = [
        Some(KeypointFormat::OpenPose),
        Some(KeypointFormat::MmPose),
        Some(KeypointFormat::MediaPipe),
        Some(KeypointFormat::Mpii),
        Some(KeypointFormat::Npy),
        None,
    ];
    let format = formats[usize::from(*selector) % formats.len()];
    let layout = Layout::ALL.get(usize::from(knobs & 7)).copied();
    let options = ReadOptions {
        image_size: Some(ImageSize {
            width: 640.0,
            height: 480.0,
        }),
        layout,
        min_score: f64::from(knobs >> 4) / 15.0,
        ..ReadOptions::default()
    };
    if knobs & 8 == 0 {
        let _ = parse_keypoints_bytes(rest, "fuzz.json", format, &options);
    } else if let Ok(stream) =
        open_keypoints_reader(std::io::Cursor::new(rest.to_vec()), "-", None, format, &options)
    {
        for record in stream.flatten() {
            let _ = record.require_torso();
        }
    }
    // The same bytes as raw f64 values of one pose.
    if let Some(layout) = layout {
        let values: Vec<f64> = rest
            .chunks_exact(8)
            .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
            .collect();
        for channels in [2, 3] {
            let _ = pose_from_array(layout, &values, channels, &options);
        }
    }
});
