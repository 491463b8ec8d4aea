//! [`CameraHeight`]: what the caller knows of the camera's height before seeing a pose, as a
//! prior over the cameras that reweighs the classifier's probabilities.

use std::fmt;
use std::str::FromStr;

use camloc_geometry::CameraSet;

use crate::CamlocError;
use crate::height_shares::HeightShares;

/// How many times as likely a camera of the middle ring is, a priori, under
/// [`CameraHeight::EyeLevel`] as under the model's own priors. Chosen on the validation
/// subjects 07, 13, 14, 75 and 114 among 2, 4, 8 and 16: `rig` views 90.8% without a prior,
/// then 92.0, 92.7, 92.9 and 93.1%; `jittered` views (every height alike) 94.1%, then 92.3,
/// 89.8, 86.9 and 83.6% (docs/measured.md).
pub const EYE_LEVEL_WEIGHT: f64 = 8.0;

/// Where the camera may stand, as the caller knows before seeing the pose: a prior over the
/// cameras multiplied into the classifier's probabilities (then normalised to sum to 1), so
/// that the most probable camera, its probability and the continuous viewpoint of its head
/// follow it. Not stored in a model file: a property of the footage, set per use
/// ([`CameraLocalizer::with_camera_height`](crate::CameraLocalizer::with_camera_height)).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum CameraHeight {
    /// Nothing known: the model's own priors (Table 1's heights as its training balanced
    /// them, docs/conventions.md section 5). The default.
    #[default]
    Any,
    /// A camera at about a standing person's eye level or a little above, a few metres away,
    /// as tripods, handheld phones and studio rigs are (the `rig` protocol: 1.0-2.2 m high,
    /// 2.5-7 m from the centre of the room): every camera of the middle ring (elevation within
    /// 22.5 deg of level, [`Level::Middle`](camloc_geometry::Level::Middle)) is [`EYE_LEVEL_WEIGHT`] times as likely a priori.
    /// A camera far above or below the person can still win, on stronger evidence.
    EyeLevel,
    /// The heights in these shares, as an input's own poses show them
    /// ([`CameraLocalizer::estimate_height_shares`](crate::CameraLocalizer::estimate_height_shares);
    /// `camloc localize`'s default `--camera-height from-input`): each height's cameras are
    /// weighed by its share over the model's own share of it.
    Shares(HeightShares),
}

impl CameraHeight {
    /// The name of [`CameraHeight::Shares`] estimated from the input (the command line's and
    /// Python's default).
    pub const FROM_INPUT: &'static str = "from-input";

    /// The name used on the command line and in Python (`"any"`, `"eye-level"`, and
    /// `"from-input"` for shares, which the command line and Python estimate from the input).
    pub const fn name(self) -> &'static str {
        match self {
            CameraHeight::Any => "any",
            CameraHeight::EyeLevel => "eye-level",
            CameraHeight::Shares(_) => CameraHeight::FROM_INPUT,
        }
    }

    /// The heights' shares and the middle cameras' mean elevation (lower, middle, upper;
    /// degrees above the pelvis) this prior localizes under, as the outputs report them
    /// (`camloc localize --npz`, Python's `camera_height_shares` and
    /// `camera_height_elevations_deg`): NaN for what it holds none of (all of them but under
    /// [`CameraHeight::Shares`], the elevations of the heights without one).
    pub fn reported(self) -> ([f64; 3], [f64; 3]) {
        match self {
            CameraHeight::Shares(shares) => (
                shares.to_array(),
                shares.elevations_deg().map(|e| e.unwrap_or(f64::NAN)),
            ),
            _ => ([f64::NAN; 3], [f64::NAN; 3]),
        }
    }

    /// Multiplies each camera's probability in `probabilities` (one per camera of
    /// `cameras`, summing to 1) by this prior's weight for it and normalises them again;
    /// `priors` are the model's own priors over the cameras (one per camera).
    pub(crate) fn reweigh(self, cameras: &CameraSet, priors: &[f64], probabilities: &mut [f64]) {
        let weights = match self {
            CameraHeight::Any => return,
            CameraHeight::EyeLevel => [1.0, EYE_LEVEL_WEIGHT, 1.0],
            CameraHeight::Shares(shares) => {
                shares.weights_against(&HeightShares::of_priors(cameras, priors))
            }
        };
        let mut total = 0.0;
        for (p, camera) in probabilities.iter_mut().zip(cameras.viewpoints()) {
            *p *= weights[camera.level.index()];
            total += *p;
        }
        if total > 0.0 {
            probabilities.iter_mut().for_each(|p| *p /= total);
        }
    }
}

impl fmt::Display for CameraHeight {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for CameraHeight {
    type Err = CamlocError;

    /// Reads `"any"` or `"eye-level"`.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "any" => Ok(CameraHeight::Any),
            "eye-level" => Ok(CameraHeight::EyeLevel),
            other => Err(CamlocError::InvalidOption {
                name: "camera height",
                detail: format!("expected \"any\" or \"eye-level\", got {other:?}"),
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eye_level_favours_the_middle_ring_and_keeps_a_distribution() {
        let cameras = CameraSet::table1();
        // Upper front twice as likely as middle front, the rest even.
        let mut p = vec![0.05; 12];
        p[4] = 0.1;
        p[8] = 0.2;
        let total: f64 = p.iter().sum();
        p.iter_mut().for_each(|v| *v /= total);
        let before = p.clone();
        let priors = vec![1.0 / 12.0; 12];
        CameraHeight::Any.reweigh(&cameras, &priors, &mut p);
        assert_eq!(p, before);
        CameraHeight::EyeLevel.reweigh(&cameras, &priors, &mut p);
        assert!((p.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        // Middle front now beats upper front: 0.1 x 8 against 0.2.
        assert!(p[4] > p[8]);
        assert!((p[4] / p[8] - EYE_LEVEL_WEIGHT / 2.0).abs() < 1e-12);
        // Cameras of one ring keep their ratios.
        assert!((p[8] / p[9] - before[8] / before[9]).abs() < 1e-12);
    }

    #[test]
    fn shares_weigh_each_height_by_its_share_over_the_models() {
        let cameras = CameraSet::table1();
        // The model saw the middle ring twice as often; the input is all middle and upper.
        let mut priors = vec![1.0 / 16.0; 12];
        priors[4..8].iter_mut().for_each(|p| *p = 1.0 / 8.0);
        let shares = HeightShares::new(0.0, 0.5, 0.5).unwrap();
        let mut p = vec![1.0 / 12.0; 12];
        CameraHeight::Shares(shares).reweigh(&cameras, &priors, &mut p);
        // Weights 0, 1 and 2 over the rings: lower 0, middle 1/12 x 1, upper 1/12 x 2.
        assert!(p[..4].iter().all(|&v| v == 0.0));
        assert!((p[8] / p[4] - 2.0).abs() < 1e-12);
        assert!((p.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        // The model's own shares change nothing.
        let own = HeightShares::new(0.25, 0.5, 0.25).unwrap();
        let mut q = vec![0.01; 12];
        q[3] = 0.89;
        let before = q.clone();
        CameraHeight::Shares(own).reweigh(&cameras, &priors, &mut q);
        for (a, b) in q.iter().zip(&before) {
            assert!((a - b).abs() < 1e-12);
        }
    }

    #[test]
    fn names_read_back_and_others_are_refused() {
        for h in [CameraHeight::Any, CameraHeight::EyeLevel] {
            assert_eq!(h.name().parse::<CameraHeight>().unwrap(), h);
        }
        let err = "tripod".parse::<CameraHeight>().unwrap_err().to_string();
        assert!(err.contains("eye-level") && err.contains("tripod"), "{err}");
    }
}
