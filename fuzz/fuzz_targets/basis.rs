//! Pose basis files (`camloc_reconstruct::PoseBasis`) never panic when decoded: the first byte
//! picks an arbitrary file or a payload in a valid envelope (see the `model` target). A basis
//! that decodes is used once to build a pose.
#![no_main]
use camloc_reconstruct::PoseBasis;
use camloc_store::{POSE_BASIS_KIND, Persist};
use libfuzzer_sys::fuzz_target;

mod common;

fuzz_target!(|data: &[u8]| {
    let Some(bytes) = common::decoder_input(data, POSE_BASIS_KIND) else {
        return;
    };
    if let Ok(basis) = PoseBasis::from_bytes(&bytes) {
        let _ = basis.pose(&vec![0.5; basis.n_components()]);
    }
});
