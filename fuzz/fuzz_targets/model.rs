//! Model files (`camloc::CameraLocalizer`) never panic when decoded. The first byte picks what
//! the rest is: an arbitrary file (header, kind, version, length and checksum checks), or a
//! payload wrapped in a valid envelope (so that mutations reach the bincode decoder and the
//! validation behind the checksum). A model that decodes is used once.
#![no_main]
use camloc::store::{MODEL_KIND, Persist};
use camloc::{CameraLocalizer, Pose2};
use libfuzzer_sys::fuzz_target;

mod common;

fuzz_target!(|data: &[u8]| {
    let Some(bytes) = common::decoder_input(data, MODEL_KIND) else {
        return;
    };
    if let Ok(localizer) = CameraLocalizer::from_bytes(&bytes) {
        let mut points = [[0.0; 2]; 15];
        for (i, p) in points.iter_mut().enumerate() {
            *p = [i as f64 * 7.0 % 13.0, i as f64 * 11.0];
        }
        let _ = localizer.localize(&Pose2::new(points));
    }
});
