//! [`ElevationFit`]: how the elevations a direction head predicts follow the true ones, so
//! that an input's own cameras can move the head's answers from the elevations it was trained
//! on to the input's.

use serde::{Deserialize, Serialize};

use crate::LearningError;

/// A fit needs at least this many samples; with fewer it is [`ElevationFit::IDENTITY`].
pub const ELEVATION_FIT_MIN_SAMPLES: usize = 50;

/// The slope is held at least this (a flatter fit would multiply the noise of an input's
/// mean by more than 10).
pub const ELEVATION_FIT_MIN_SLOPE: f64 = 0.1;

/// Samples whose predicted elevation is farther than this from the true one (degrees; a view
/// put in the wrong camera class) are left out of the fit.
pub const ELEVATION_FIT_MAX_ERROR_DEG: f64 = 30.0;

/// How the elevations a direction head predicts follow the true ones on its calibration
/// samples: the least-squares line of the predicted elevation on the true one, through their
/// means (degrees above the horizontal). A regression answers near the elevations it was
/// trained on: its slope is below 1, so a camera higher than the training's average is read
/// lower and a lower one higher. Over many views of one input that shrinkage can be undone
/// ([`unbiased_deg`](Self::unbiased_deg)) to estimate the input's own mean elevation, and each
/// answer moved to shrink toward that mean instead ([`shift_deg`](Self::shift_deg)).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ElevationFit {
    /// Mean true elevation of the samples, degrees.
    pub true_mean_deg: f64,
    /// Mean predicted elevation of the samples, degrees.
    pub predicted_mean_deg: f64,
    /// Slope of the predicted on the true elevation, in `[ELEVATION_FIT_MIN_SLOPE, 1]`.
    pub slope: f64,
}

impl ElevationFit {
    /// The fit that changes nothing (slope 1): [`shift_deg`](Self::shift_deg) is always 0.
    pub const IDENTITY: ElevationFit = ElevationFit {
        true_mean_deg: 0.0,
        predicted_mean_deg: 0.0,
        slope: 1.0,
    };

    /// The fit of `(true, predicted)` elevation pairs (degrees): the pairs farther apart than
    /// [`ELEVATION_FIT_MAX_ERROR_DEG`] and non-finite ones are left out; fewer than
    /// [`ELEVATION_FIT_MIN_SAMPLES`] left, or no spread in the true elevations, give
    /// [`IDENTITY`](Self::IDENTITY); the slope is clamped to `[ELEVATION_FIT_MIN_SLOPE, 1]`.
    pub fn of(pairs: impl IntoIterator<Item = (f64, f64)>) -> ElevationFit {
        let kept: Vec<(f64, f64)> = pairs
            .into_iter()
            .filter(|(t, p)| (t - p).abs() <= ELEVATION_FIT_MAX_ERROR_DEG)
            .collect();
        if kept.len() < ELEVATION_FIT_MIN_SAMPLES {
            return ElevationFit::IDENTITY;
        }
        let n = kept.len() as f64;
        let true_mean = kept.iter().map(|(t, _)| t).sum::<f64>() / n;
        let predicted_mean = kept.iter().map(|(_, p)| p).sum::<f64>() / n;
        let (mut covariance, mut variance) = (0.0, 0.0);
        for (t, p) in &kept {
            covariance += (t - true_mean) * (p - predicted_mean);
            variance += (t - true_mean) * (t - true_mean);
        }
        if variance <= 0.0 {
            return ElevationFit::IDENTITY;
        }
        ElevationFit {
            true_mean_deg: true_mean,
            predicted_mean_deg: predicted_mean,
            slope: (covariance / variance).clamp(ELEVATION_FIT_MIN_SLOPE, 1.0),
        }
    }

    /// The elevation (degrees) that the predicted `predicted_deg` stands for with the fit's
    /// shrinkage undone: an unbiased but noisier reading of one view, whose mean over many
    /// views of an input estimates the input's mean elevation.
    pub fn unbiased_deg(&self, predicted_deg: f64) -> f64 {
        self.true_mean_deg + (predicted_deg - self.predicted_mean_deg) / self.slope
    }

    /// Degrees to add to a predicted elevation so that it shrinks toward `input_mean_deg`
    /// (an input's own mean elevation) instead of the training's mean: `(1 - slope)` times
    /// their difference.
    pub fn shift_deg(&self, input_mean_deg: f64) -> f64 {
        (1.0 - self.slope) * (input_mean_deg - self.true_mean_deg)
    }

    /// Checks a decoded fit: finite means within `[-90, 90]` degrees and a slope in
    /// `[ELEVATION_FIT_MIN_SLOPE, 1]`.
    ///
    /// # Errors
    /// [`LearningError::InvalidParameter`] naming the value.
    pub fn validate(&self) -> Result<(), LearningError> {
        let means = [self.true_mean_deg, self.predicted_mean_deg];
        if let Some(m) = means.iter().find(|m| !(-90.0..=90.0).contains(*m)) {
            return Err(LearningError::InvalidParameter {
                name: "elevation fit mean",
                value: format!("{m:?}"),
                reason: "must be finite, in [-90, 90] degrees",
            });
        }
        if !(ELEVATION_FIT_MIN_SLOPE..=1.0).contains(&self.slope) {
            return Err(LearningError::InvalidParameter {
                name: "elevation fit slope",
                value: format!("{:?}", self.slope),
                reason: "must be in [0.1, 1]",
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_shrunk_line_is_found_and_undone() {
        // Predictions shrink halfway toward the mean true elevation, 8 degrees; one outlier
        // 40 degrees off.
        let mut pairs: Vec<(f64, f64)> = (0..=100)
            .map(|i| {
                let t = -4.0 + 0.24 * i as f64;
                (t, 8.0 + 0.5 * (t - 8.0))
            })
            .collect();
        pairs.push((0.0, 40.0));
        let fit = ElevationFit::of(pairs.iter().copied());
        assert!(
            (fit.slope - 0.5).abs() < 1e-9 && (fit.true_mean_deg - 8.0).abs() < 1e-9,
            "{fit:?}"
        );
        fit.validate().unwrap();
        assert!((fit.unbiased_deg(8.0 + 0.5 * 12.0) - 20.0).abs() < 1e-9);
        // An input whose cameras average 20 degrees: a view read 14 moves to 20.
        assert!((14.0 + fit.shift_deg(20.0) - 20.0).abs() < 1e-9);
        assert_eq!(fit.shift_deg(fit.true_mean_deg), 0.0);
    }

    #[test]
    fn too_few_or_flat_samples_change_nothing_and_bad_fits_are_refused() {
        let few = ElevationFit::of((0..10).map(|i| (i as f64, i as f64 / 2.0)));
        assert_eq!(few, ElevationFit::IDENTITY);
        let flat = ElevationFit::of((0..100).map(|_| (5.0, 3.0)));
        assert_eq!(flat, ElevationFit::IDENTITY);
        assert_eq!(ElevationFit::IDENTITY.shift_deg(40.0), 0.0);
        let steep = ElevationFit::of((0..100).map(|i| (i as f64 / 10.0, i as f64 / 5.0)));
        assert_eq!(steep.slope, 1.0);
        for bad in [
            ElevationFit {
                slope: 0.0,
                ..ElevationFit::IDENTITY
            },
            ElevationFit {
                true_mean_deg: f64::NAN,
                ..ElevationFit::IDENTITY
            },
            ElevationFit {
                predicted_mean_deg: 91.0,
                ..ElevationFit::IDENTITY
            },
        ] {
            assert!(bad.validate().is_err(), "{bad:?}");
        }
    }
}
