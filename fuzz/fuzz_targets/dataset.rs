//! Dataset files (`camloc_dataset::Dataset`) never panic when decoded: the first byte picks an
//! arbitrary file or a payload in a valid envelope (see the `model` target). A dataset that
//! decodes has its per-camera and per-subject summaries computed.
#![no_main]
use camloc_dataset::Dataset;
use camloc_store::{DATASET_KIND, Persist};
use libfuzzer_sys::fuzz_target;

mod common;

fuzz_target!(|data: &[u8]| {
    let Some(bytes) = common::decoder_input(data, DATASET_KIND) else {
        return;
    };
    if let Ok(dataset) = Dataset::from_bytes(&bytes) {
        let _ = dataset.samples_per_camera();
        let _ = dataset.subjects();
        for s in dataset.samples.iter().take(16) {
            let _ = dataset.header.cameras.fold_back_to_front(s.label);
            let _ = dataset.header.cameras.mirror_left_right(s.label);
        }
    }
});
