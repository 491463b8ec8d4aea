//! Test views localized as inputs of one camera height, as a fixed camera's footage is: the
//! views of each band of true elevation above the pelvis ([`ELEVATION_BANDS`]) read as one
//! input under `--camera-height from-input`, with the input's estimated mean elevations or
//! with its heights' shares alone (issue 21: the elevation bias of high cameras).

use camloc::dataset::{Dataset, camera_direction_deg};
use camloc::{CameraHeight, CameraLocalizer, HeightEstimate, HeightShares};

use crate::view_scores::{ELEVATION_BANDS, ViewOutcome, outcomes};

/// The prior of `estimate` (`CameraHeight::Shares` with the input's mean elevations), or
/// with `shares_alone` the same shares without them (the prior before the mean elevations
/// were estimated).
pub fn prior(estimate: &HeightEstimate, shares_alone: bool) -> CameraHeight {
    match estimate.shares {
        Some(s) if shares_alone => {
            let [lower, middle, upper] = s.to_array();
            HeightShares::new(lower, middle, upper).map_or(CameraHeight::Any, CameraHeight::Shares)
        }
        _ => estimate.camera_height(),
    }
}

/// The outcomes of the views of `test`, each band of true elevation read as one input under
/// its own estimate ([`prior`]), in band order.
///
/// # Errors
/// As [`outcomes`].
pub fn band_outcomes(
    localizer: &CameraLocalizer,
    test: &Dataset,
    shares_alone: bool,
) -> Result<Vec<ViewOutcome>, String> {
    let mut all = Vec::with_capacity(test.samples.len());
    for (lo, hi) in ELEVATION_BANDS {
        let samples: Vec<_> = test
            .samples
            .iter()
            .filter(|s| (lo..hi).contains(&camera_direction_deg(&s.rotation).1))
            .cloned()
            .collect();
        if samples.is_empty() {
            continue;
        }
        let band = Dataset {
            header: test.header.clone(),
            samples,
        };
        let estimate = localizer.estimate_height_shares_of(&band);
        let under = localizer
            .clone()
            .with_camera_height(prior(&estimate, shares_alone));
        all.extend(outcomes(&under, &band)?);
    }
    Ok(all)
}
