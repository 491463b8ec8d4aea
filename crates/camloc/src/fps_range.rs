//! The frame rates a sequence may be given ([`frame_rate_problem`]): the command line's
//! `--fps` and Python's `fps` take the same ones.

use camloc_mocap::BVH_FRAME_TIME_RANGE_S;

/// Why `fps` (frames a second) is not a frame rate camloc takes, or `None`: one a BVH file can
/// hold, from one frame an hour to a million a second ([`BVH_FRAME_TIME_RANGE_S`]). The
/// message does not repeat the value (the caller names it as the user wrote it).
pub fn frame_rate_problem(fps: f64) -> Option<&'static str> {
    let (shortest, longest) = BVH_FRAME_TIME_RANGE_S;
    (!(1.0 / longest..=1.0 / shortest).contains(&fps)).then_some(
        "not a frame rate: a number of frames a second from 0.000278 (one an hour) to 1000000",
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rates_from_one_an_hour_to_a_million_a_second() {
        for good in [1.0 / 3600.0, 25.0, 29.97, 1e6] {
            assert_eq!(frame_rate_problem(good), None, "{good}");
        }
        for bad in [0.0, -5.0, 1e7, 1e-4, f64::NAN, f64::INFINITY] {
            assert!(frame_rate_problem(bad).is_some(), "{bad}");
        }
    }
}
