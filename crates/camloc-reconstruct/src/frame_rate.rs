//! How a sequence's frame rate scales the settings that are counted in frames
//! ([`FrameRate`]): the smoothness of the refinement and the pelvis's path of
//! [`world_poses`](crate::world_poses) were measured at [`REFERENCE_FRAME_RATE_HZ`], and a
//! faster video keeps their meaning in time.

use serde::{Deserialize, Serialize};

use crate::ReconstructError;

/// Frames a second at which the per-frame settings of sequences were chosen (the held-out
/// CMU windows of docs/RESULTS.md are about this fast); they hold as they are at this rate
/// and below.
pub const REFERENCE_FRAME_RATE_HZ: f64 = 30.0;

/// The fastest rate whose windows [`FrameRate::step`] keeps as long in time as at
/// [`REFERENCE_FRAME_RATE_HZ`] (high-speed cameras); faster rates keep its windows in frames,
/// shorter in time: the windows' work and memory grow with their frames (a simulated user's
/// 100,000 frames at 30,000 frames a second took 2.1 GB and 28 s against 0.16 GB and 0.7 s at
/// 30). [`FrameRate::deviation_factor`] stops there too: at a million frames a second the
/// world placement's second differences were weighted 10^17 times the camera's and its
/// solve came out NaN (a simulated user's frames numbered 50 apart).
pub const MOST_WINDOW_RATE_HZ: f64 = 1000.0;

/// A sequence's frames a second, and what it makes of per-frame settings. At or below
/// [`REFERENCE_FRAME_RATE_HZ`] every setting is the reference's. Above it:
///
/// - a window of `w` frames becomes `w * step()` frames (the same time), where
///   [`step`](Self::step) is `round(hz / 30)`;
/// - a deviation of a frame's second difference from its neighbours' (the smoothness of
///   bone directions, the bend of the pelvis's path) is multiplied by
///   [`deviation_factor`](Self::deviation_factor), `(30 / hz)^1.5`: the sum over the frames
///   of the squared second differences over that deviation is then the same integral of the
///   squared second derivative over time (a cubic smoothing spline's penalty) at any rate.
///
/// Measured on a simulated user's CMU walk (136_24) filmed by a tripod with detector-like 2D
/// noise at 24, 30, 60 and 120 frames a second (docs/RESULTS.md): without it the same motion
/// came out with accelerations growing with the square of the rate (171 and 687 m/s^2 at 60
/// and 120, 42 at 30).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct FrameRate {
    hz: f64,
}

impl Default for FrameRate {
    /// [`REFERENCE_FRAME_RATE_HZ`].
    fn default() -> Self {
        FrameRate {
            hz: REFERENCE_FRAME_RATE_HZ,
        }
    }
}

impl FrameRate {
    /// `hz` frames a second.
    ///
    /// # Errors
    /// [`ReconstructError::InvalidConfig`] unless `hz` is finite and > 0.
    pub fn new(hz: f64) -> Result<FrameRate, ReconstructError> {
        if !(hz.is_finite() && hz > 0.0) {
            return Err(ReconstructError::InvalidConfig {
                field: "frame rate",
                value: format!("{hz:?}"),
                reason: "must be finite and > 0 frames a second",
            });
        }
        Ok(FrameRate { hz })
    }

    /// Frames a second.
    pub fn hz(self) -> f64 {
        self.hz
    }

    /// Frames in the time of one reference frame (1 / 30 s), at least 1, and at most that of
    /// [`MOST_WINDOW_RATE_HZ`].
    pub fn step(self) -> usize {
        (self.window_hz() / REFERENCE_FRAME_RATE_HZ)
            .round()
            .max(1.0) as usize
    }

    /// The factor of a per-frame deviation of second differences: `min(1, 30 / hz)^1.5`,
    /// with `hz` at most [`MOST_WINDOW_RATE_HZ`].
    pub fn deviation_factor(self) -> f64 {
        (REFERENCE_FRAME_RATE_HZ / self.window_hz())
            .min(1.0)
            .powf(1.5)
    }

    /// The rate the per-frame settings are scaled for: `hz`, at most [`MOST_WINDOW_RATE_HZ`].
    fn window_hz(self) -> f64 {
        self.hz.min(MOST_WINDOW_RATE_HZ)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_reference_rate_and_slower_ones_change_nothing() {
        for hz in [1.0, 7.5, 24.0, 30.0] {
            let rate = FrameRate::new(hz).unwrap();
            assert_eq!(rate.step(), 1);
            assert_eq!(rate.deviation_factor(), 1.0);
        }
        assert_eq!(FrameRate::default().hz(), REFERENCE_FRAME_RATE_HZ);
    }

    #[test]
    fn faster_rates_keep_windows_in_time() {
        let rate = FrameRate::new(120.0).unwrap();
        assert_eq!(rate.step(), 4);
        assert!((rate.deviation_factor() - 0.125).abs() < 1e-12);
        assert_eq!(FrameRate::new(60.0).unwrap().step(), 2);
        assert_eq!(FrameRate::new(1000.0).unwrap().step(), 33);
        assert_eq!(FrameRate::new(1e9).unwrap().step(), 33);
        let fastest = FrameRate::new(MOST_WINDOW_RATE_HZ)
            .unwrap()
            .deviation_factor();
        assert_eq!(FrameRate::new(1e6).unwrap().deviation_factor(), fastest);
        for bad in [0.0, -30.0, f64::NAN, f64::INFINITY] {
            assert!(FrameRate::new(bad).is_err(), "{bad}");
        }
    }
}
