//! The BVH reader never panics, whatever the bytes.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = camloc_mocap::parse_bvh(data, "fuzz.bvh");
});
