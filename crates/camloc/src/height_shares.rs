//! [`HeightShares`]: how an input's cameras divide among Table 1's three heights, and their
//! estimate from the input's own poses ([`CameraLocalizer::estimate_height_shares`]).

use camloc_dataset::Dataset;
use camloc_geometry::{CameraSet, Level};
use camloc_skeleton::PartialPose2;
use rayon::prelude::*;

use crate::rows::sample_pose;
use crate::view_weights::view_weights;
use crate::{CameraLocalizer, CamlocError, EYE_LEVEL_WEIGHT};

/// Views of a camera at eye level added to an input's views when its camera heights are
/// estimated ([`CameraLocalizer::estimate_height_shares`]; shares [`eye_level_shares`]): an
/// input worth a few views (a photo, a short clip) moves the estimate little from eye level,
/// one worth thousands settles it.
pub const HEIGHT_SHARE_PSEUDO_VIEWS: f64 = 5.0;

/// The estimate reads at most this many poses: the first ones of an input (three shares: a
/// few thousand poses settle them). Reading the first ones, not a spread, lets a stream be
/// localized once they are read, and gives the same answer whatever the input's source.
pub const HEIGHT_SHARE_MAX_POSES: usize = 20_000;

/// What [`CameraLocalizer::estimate_height_shares`] found in an input.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeightEstimate {
    /// The shares of the heights, or `None` when none of the poses read could be localized.
    pub shares: Option<HeightShares>,
    /// The poses read: the first ones, at most [`HEIGHT_SHARE_MAX_POSES`].
    pub read: usize,
    /// Of those, the poses that could be localized (the others are left out of the estimate).
    pub localized: usize,
    /// The independent views the localized poses are worth (a video's frames are nearly the
    /// same view again and again): the weight of the input's evidence against
    /// [`HEIGHT_SHARE_PSEUDO_VIEWS`].
    pub views: f64,
}

impl HeightEstimate {
    /// The prior the estimate gives: [`CameraHeight::Shares`](crate::CameraHeight::Shares),
    /// or [`CameraHeight::Any`](crate::CameraHeight::Any) without shares.
    pub fn camera_height(&self) -> crate::CameraHeight {
        self.shares
            .map_or(crate::CameraHeight::Any, crate::CameraHeight::Shares)
    }

    /// [`views`](Self::views) when the estimate gave shares, NaN when it gave none (no pose
    /// could be localized): what `camloc localize --npz` and Python's `camera_height_views`
    /// report, NaN beside the NaN shares.
    pub fn reported_views(&self) -> f64 {
        if self.shares.is_some() {
            self.views
        } else {
            f64::NAN
        }
    }
}

/// At most this many rounds of the estimate (it usually settles in a few dozen).
const MAX_ROUNDS: usize = 500;

/// The estimate has settled when no share moves by more than this in a round.
const SETTLED: f64 = 1e-9;

/// The shares of Table 1's three camera heights among the cameras of some footage
/// ([`Level`]: below the body, at body height within 22.5 deg, above it): non-negative, summing
/// to 1, and, when estimated from the footage, the mean elevation of its middle cameras. As a
/// prior ([`CameraHeight::Shares`](crate::CameraHeight::Shares)) they replace the model's own
/// priors over the heights, keeping its priors within each height.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeightShares {
    /// Share of cameras in the lower ring (looking up at the body).
    pub lower: f64,
    /// Share of cameras in the middle ring (at body height).
    pub middle: f64,
    /// Share of cameras in the upper ring (looking down on the body).
    pub upper: f64,
    /// Per height (lower, middle, upper), the mean elevation above the pelvis (degrees) of
    /// the input's cameras of that height, as the viewpoint heads read its views with their
    /// regression toward the training's elevations undone
    /// ([`ElevationFit`](camloc_learning::ElevationFit)); `None`: not estimated (the lower
    /// and upper heights always). Under these shares each continuous viewpoint of a height
    /// with one is moved by its head's
    /// [`ElevationFit::shift_deg`](camloc_learning::ElevationFit::shift_deg) of it: it
    /// regresses toward that elevation instead of the training's mean.
    elevations_deg: [Option<f64>; 3],
}

impl HeightShares {
    /// The shares `lower`, `middle` and `upper`, normalised to sum to 1.
    ///
    /// # Errors
    /// [`CamlocError::InvalidOption`] when one is negative or not finite, or all are 0.
    pub fn new(lower: f64, middle: f64, upper: f64) -> Result<Self, CamlocError> {
        let total = lower + middle + upper;
        let valid = [lower, middle, upper]
            .iter()
            .all(|s| s.is_finite() && *s >= 0.0);
        if !(valid && total > 0.0 && total.is_finite()) {
            return Err(CamlocError::InvalidOption {
                name: "camera height shares",
                detail: format!(
                    "expected three non-negative finite shares, not all 0; got {lower:?}, {middle:?}, \
                     {upper:?}"
                ),
            });
        }
        Ok(HeightShares {
            lower: lower / total,
            middle: middle / total,
            upper: upper / total,
            elevations_deg: [None; 3],
        })
    }

    /// These shares with the input's mean camera elevation per height (lower, middle, upper;
    /// degrees above the pelvis, `None` for a height without one), as
    /// [`CameraLocalizer::estimate_height_shares`] estimates them: the middle height's alone
    /// (the upper heads do not regress as their fits say, docs/conventions.md section 5).
    ///
    /// # Errors
    /// [`CamlocError::InvalidOption`] for an elevation outside `[-90, 90]` or not finite, and
    /// for one given for the lower or upper height.
    pub fn with_elevations(
        mut self,
        elevations_deg: [Option<f64>; 3],
    ) -> Result<Self, CamlocError> {
        if let [Some(_), _, _] | [_, _, Some(_)] = elevations_deg {
            return Err(CamlocError::InvalidOption {
                name: "camera height elevations",
                detail: "only the middle height's is used: give none (NaN) for the lower and \
                         upper ones"
                    .into(),
            });
        }
        if let Some(e) = elevations_deg
            .iter()
            .flatten()
            .find(|e| !(-90.0..=90.0).contains(*e))
        {
            return Err(CamlocError::InvalidOption {
                name: "camera height elevations",
                detail: format!("expected degrees in [-90, 90], got {e:?}"),
            });
        }
        self.elevations_deg = elevations_deg;
        Ok(self)
    }

    /// The input's mean camera elevation per height (lower, middle, upper; degrees above
    /// the pelvis), `None` where not estimated ([`with_elevations`](Self::with_elevations)).
    pub fn elevations_deg(&self) -> [Option<f64>; 3] {
        self.elevations_deg
    }

    /// The shares in the order lower, middle, upper.
    pub fn to_array(self) -> [f64; 3] {
        [self.lower, self.middle, self.upper]
    }

    /// Shares given in the order lower, middle, upper (as they are, not checked).
    fn from_array([lower, middle, upper]: [f64; 3]) -> Self {
        HeightShares {
            lower,
            middle,
            upper,
            elevations_deg: [None; 3],
        }
    }

    /// The share of `level`.
    pub fn of(&self, level: Level) -> f64 {
        self.to_array()[level.index()]
    }

    /// The shares of the heights under the per-camera priors `priors` (one per camera of
    /// `cameras`, summing to 1).
    pub(crate) fn of_priors(cameras: &CameraSet, priors: &[f64]) -> Self {
        let mut shares = [0.0; 3];
        for (p, view) in priors.iter().zip(cameras.viewpoints()) {
            shares[view.level.index()] += p;
        }
        HeightShares::from_array(shares)
    }

    /// Per level (lower, middle, upper), how many times as likely a camera of that height is
    /// under these shares as under `model` (1 for a height the model gives no share).
    pub(crate) fn weights_against(&self, model: &HeightShares) -> [f64; 3] {
        let (own, model) = (self.to_array(), model.to_array());
        [0, 1, 2].map(|l| {
            if model[l] > 0.0 {
                own[l] / model[l]
            } else {
                1.0
            }
        })
    }
}

/// The shares in per cent, e.g. `lower 0.3%, middle 99.5%, upper 0.2%`.
impl std::fmt::Display for HeightShares {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "lower {:.1}%, middle {:.1}%, upper {:.1}%",
            100.0 * self.lower,
            100.0 * self.middle,
            100.0 * self.upper
        )
    }
}

/// The shares of a camera at eye level: the model's own shares of the heights (`model`) with
/// the middle ring [`EYE_LEVEL_WEIGHT`] times as likely, as
/// [`CameraHeight::EyeLevel`](crate::CameraHeight::EyeLevel) weighs it.
pub fn eye_level_shares(model: &HeightShares) -> HeightShares {
    let [lower, middle, upper] = model.to_array();
    let total = lower + EYE_LEVEL_WEIGHT * middle + upper;
    HeightShares::from_array([lower, EYE_LEVEL_WEIGHT * middle, upper].map(|s| s / total))
}

/// The shares of the heights that best explain `probabilities` (rows of one probability per
/// camera of `cameras`, under the model's own per-camera `priors`), each row weighing as
/// much as its entry of `weights` (the share of an independent view it is worth):
/// expectation-maximisation of the heights' shares with the classifier's probabilities held
/// fixed (Saerens, Latinne and Decaestecker 2002, "Adjusting the outputs of a classifier to
/// new a priori probabilities"), with [`HEIGHT_SHARE_PSEUDO_VIEWS`] views of a camera at eye
/// level ([`eye_level_shares`]) added: real footage is mostly filmed from about eye level, and
/// the model's own shares (its training views, from every height alike) are no prior for it.
pub(crate) fn estimate(
    cameras: &CameraSet,
    priors: &[f64],
    probabilities: &[f64],
    weights: &[f64],
) -> HeightShares {
    let model = HeightShares::of_priors(cameras, priors);
    let centre = eye_level_shares(&model);
    let levels: Vec<usize> = cameras
        .viewpoints()
        .iter()
        .map(|v| v.level.index())
        .collect();
    let k = levels.len();
    let views: f64 = weights.iter().sum();
    let mut shares = centre;
    for _ in 0..MAX_ROUNDS {
        let by_level = shares.weights_against(&model);
        let mut sums = [0.0; 3];
        for (row, weight) in probabilities.chunks_exact(k).zip(weights) {
            let total: f64 = row.iter().zip(&levels).map(|(p, &l)| p * by_level[l]).sum();
            if total > 0.0 {
                for (p, &l) in row.iter().zip(&levels) {
                    sums[l] += weight * p * by_level[l] / total;
                }
            }
        }
        let (before, prior) = (shares.to_array(), centre.to_array());
        let next = [0, 1, 2].map(|l| {
            (sums[l] + HEIGHT_SHARE_PSEUDO_VIEWS * prior[l]) / (views + HEIGHT_SHARE_PSEUDO_VIEWS)
        });
        let moved = (0..3)
            .map(|l| (next[l] - before[l]).abs())
            .fold(0.0, f64::max);
        shares = HeightShares::from_array(next);
        if moved < SETTLED {
            break;
        }
    }
    shares
}

impl CameraLocalizer {
    /// The shares of the camera heights among the first [`HEIGHT_SHARE_MAX_POSES`] of `poses`,
    /// as the model reads them: the classifier's probabilities of every pose under its own
    /// priors, each pose weighing the share of an independent view it is worth (the frames
    /// of a video little each: [`NEW_VIEW_SIZES`](crate::NEW_VIEW_SIZES)), then the shares
    /// that best explain them all (expectation-maximisation with the probabilities held
    /// fixed, Saerens, Latinne and Decaestecker 2002, with [`HEIGHT_SHARE_PSEUDO_VIEWS`] views
    /// of a camera at eye level added: an input worth a few views is read about as
    /// [`CameraHeight::EyeLevel`](crate::CameraHeight::EyeLevel) reads it), and with them
    /// the middle cameras' mean elevation ([`HeightShares::elevations_deg`]: every pose
    /// localized again under the shares). Poses that cannot be localized (no pelvis or neck, non-finite or degenerate landmarks) are left
    /// out; with none left there are no shares. Give the estimate's
    /// [`camera_height`](HeightEstimate::camera_height) to
    /// [`CameraLocalizer::with_camera_height`] to localize the input under it: then each
    /// pose's answer depends on the others. Runs in parallel.
    pub fn estimate_height_shares(&self, poses: &[PartialPose2]) -> HeightEstimate {
        let read = &poses[..poses.len().min(HEIGHT_SHARE_MAX_POSES)];
        let k = self.cameras.len();
        let rows: Vec<(&PartialPose2, Vec<f64>)> = read
            .par_iter()
            .filter_map(|pose| {
                self.with_pose_rows(pose, String::new, |rows| {
                    let mut p = vec![0.0; k];
                    self.model_camera_probabilities_into(rows.classifier, rows.classes, &mut p)?;
                    Ok((pose, p))
                })
                .ok()
            })
            .collect();
        let (kept, probabilities): (Vec<&PartialPose2>, Vec<Vec<f64>>) = rows.into_iter().unzip();
        let weights = view_weights(&kept);
        let shares = (!kept.is_empty()).then(|| {
            let shares = estimate(
                &self.cameras,
                &self.info.camera_priors,
                &probabilities.concat(),
                &weights,
            );
            let elevations = self.input_elevations(&kept, &weights, shares);
            // (Means of clamped degrees: always valid.)
            shares.with_elevations(elevations).unwrap_or(shares)
        });
        HeightEstimate {
            shares,
            read: read.len(),
            localized: kept.len(),
            // (From 0.0: a float sum of nothing is -0.0, which Python printed for no poses.)
            views: weights.iter().fold(0.0, |sum, w| sum + w),
        }
    }

    /// The shares of the heights under the model's own priors (its training views').
    pub fn model_height_shares(&self) -> HeightShares {
        HeightShares::of_priors(&self.cameras, &self.info.camera_priors)
    }

    /// [`estimate_height_shares`](Self::estimate_height_shares) of the samples of `dataset`
    /// (with their missing landmarks).
    pub fn estimate_height_shares_of(&self, dataset: &Dataset) -> HeightEstimate {
        let poses: Vec<PartialPose2> = dataset
            .samples
            .iter()
            .take(HEIGHT_SHARE_MAX_POSES)
            .map(sample_pose)
            .collect();
        self.estimate_height_shares(&poses)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Camera probabilities of a classifier that is right with probability `sure` and spreads
    /// the rest evenly, for a view of camera `truth`.
    fn row(truth: usize, sure: f64) -> Vec<f64> {
        let mut p = vec![(1.0 - sure) / 11.0; 12];
        p[truth] = sure;
        p
    }

    #[test]
    fn the_estimate_finds_an_input_of_one_height_and_keeps_an_even_one() {
        let cameras = CameraSet::table1();
        let priors = vec![1.0 / 12.0; 12];
        // A classifier that sees the right camera 60% of the time and each other one 40/11%
        // (its answer's probabilities are `row`): `views` views of camera `truth` give these
        // answers in these numbers.
        let answers = |truth: usize, views: usize| {
            (0..12).flat_map(move |seen| {
                let n = if seen == truth {
                    views * 6 / 10
                } else {
                    views * 4 / 110
                };
                std::iter::repeat_n(row(seen, 0.6), n).flatten()
            })
        };
        // 1,100 views of each middle camera (Table 1's 5-8), 110 of each lower one.
        let mut rows = Vec::new();
        for truth in 0..8 {
            rows.extend(answers(truth, if truth < 4 { 110 } else { 1100 }));
        }
        let ones = vec![1.0; rows.len() / 12];
        let shares = estimate(&cameras, &priors, &rows, &ones);
        assert!((shares.lower + shares.middle + shares.upper - 1.0).abs() < 1e-12);
        // Within 2 points: the rounds settle slowly towards a share of 0 (upper).
        assert!((shares.middle - 10.0 / 11.0).abs() < 0.02, "{shares:?}");
        assert!((shares.lower - 1.0 / 11.0).abs() < 0.02, "{shares:?}");
        // An even input stays about even (5 views at eye level against its 1,200).
        let even: Vec<f64> = (0..1200).flat_map(|i| row(i % 12, 0.6)).collect();
        let shares = estimate(&cameras, &priors, &even, &[1.0; 1200]);
        for s in [shares.lower, shares.middle, shares.upper] {
            assert!((s - 1.0 / 3.0).abs() < 0.02, "{shares:?}");
        }
        // The same 1,200 rows worth 12 views (a video's frames): eye level holds more.
        let shares_of_video = estimate(&cameras, &priors, &even, &[0.01; 1200]);
        assert!(shares_of_video.middle > 0.5, "{shares_of_video:?}");
    }

    #[test]
    fn few_views_move_the_estimate_little_from_eye_level() {
        let cameras = CameraSet::table1();
        // A model that saw the middle ring twice as often: at eye level, the middle ring is 16
        // times as likely as each other one.
        let mut priors = vec![1.0 / 16.0; 12];
        priors[4..8].iter_mut().for_each(|p| *p = 1.0 / 8.0);
        let centre = eye_level_shares(&HeightShares::of_priors(&cameras, &priors));
        assert!((centre.middle - 16.0 / 18.0).abs() < 1e-12, "{centre:?}");
        let none = estimate(&cameras, &priors, &[], &[]).to_array();
        for (a, b) in none.iter().zip(centre.to_array()) {
            assert!((a - b).abs() < 1e-12, "{none:?}");
        }
        // One view against the pseudo-views moves a share by at most its weight in them.
        let one = estimate(&cameras, &priors, &row(0, 0.9), &[1.0]);
        let most = 1.0 / (1.0 + HEIGHT_SHARE_PSEUDO_VIEWS);
        assert!(
            one.lower > centre.lower && one.lower < centre.lower + most,
            "{one:?}"
        );
    }

    #[test]
    fn shares_are_normalised_and_bad_ones_refused() {
        let s = HeightShares::new(1.0, 2.0, 1.0).unwrap();
        assert_eq!((s.lower, s.middle, s.upper), (0.25, 0.5, 0.25));
        for bad in [(0.0, 0.0, 0.0), (-1.0, 1.0, 1.0), (f64::NAN, 1.0, 1.0)] {
            assert!(HeightShares::new(bad.0, bad.1, bad.2).is_err());
        }
        let model = HeightShares::new(0.25, 0.5, 0.25).unwrap();
        let input = HeightShares::new(0.0, 1.0, 0.0).unwrap();
        assert_eq!(input.weights_against(&model), [0.0, 2.0, 0.0]);
    }
}
