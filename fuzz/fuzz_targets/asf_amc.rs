//! The ASF and AMC readers never panic: the input is split at the first NUL byte into an ASF
//! skeleton and an AMC motion; when the skeleton parses, the motion is read against it.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let (asf, amc) = match data.iter().position(|&b| b == 0) {
        Some(i) => (&data[..i], &data[i + 1..]),
        None => (data, &data[..0]),
    };
    if let Ok(skeleton) = camloc_mocap::parse_asf(asf, "fuzz.asf") {
        let _ = camloc_mocap::parse_amc(amc, "fuzz.amc", &skeleton);
    }
});
