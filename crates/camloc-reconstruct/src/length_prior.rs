//! [`LengthPrior`]: a Gaussian on the 14 log limb lengths learned from motion capture
//! skeletons, and [`LengthWidening`], how much wider the reconstruction makes it for the
//! conventions of other skeletons and detectors.

use camloc_skeleton::{NUM_LIMBS, Pose3};
use nalgebra::{SMatrix, SVector};
use serde::{Deserialize, Serialize};

use crate::{BoneLengths, ReconstructError};

/// A 14 x 14 matrix over the limbs.
pub(crate) type LimbMatrix = SMatrix<f64, NUM_LIMBS, NUM_LIMBS>;

/// A value per limb.
pub(crate) type LimbVector = SVector<f64, NUM_LIMBS>;

/// The squared Mahalanobis distance of a single pose's estimated log limb lengths from the
/// widened [`LengthPrior`] beyond which a reconstruction started from lifted depths is solved
/// again from the pursuit's pose (36.12: 99.9% of the draws of the prior itself lie within, the
/// chi-squared quantile of 14 degrees of freedom). Over the held-out subjects' 2,577 single
/// poses of `xtask reconstruction --proportions-only` it was passed twice; over LSP's 400
/// photos 14 times (docs/RESULTS.md).
pub const IMPLAUSIBLE_LENGTHS_D2: f64 = 36.12;

/// A Gaussian on the logarithms of the 14 limb lengths (metres, [`camloc_skeleton::LIMBS`]
/// order) of the people in motion capture: mean and covariance of the log lengths of the
/// training poses ([`LengthPrior::fit`]). Motion capture skeletons are rigid, so every pose of
/// a clip has its skeleton's lengths and the statistics are those of the skeletons, weighted
/// by their poses. Stored in the [`PoseBasis`](crate::PoseBasis).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LengthPrior {
    /// Mean log length of each limb (log metres).
    mean_log: [f64; NUM_LIMBS],
    /// Covariance of the log lengths, row-major.
    covariance: [[f64; NUM_LIMBS]; NUM_LIMBS],
}

/// How much wider than the motion capture skeletons' spread the length prior is made at
/// reconstruction, as standard deviations of log length (a deviation of 0.1 is about 10%):
/// other skeletons, annotations and detectors put the head, neck, pelvis and hips elsewhere
/// (docs/keypoints.md, docs/conventions.md section 6), and people differ more than ~30
/// captured subjects. Each limb type's deviation is shared by its left and right limbs (a
/// convention moves both); `asymmetry` is added to each limb on its own.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct LengthWidening {
    /// Pelvis to hip (half the hip width): skeletons put the hip joints 0.5-2 times as far
    /// apart as CMU's ASF skeletons; the pelvis of annotations is the mid-hip point.
    pub hip_width: f64,
    /// Thighs and shins: detectors' and annotators' hip, knee and ankle points sit off the
    /// mocap joint centres (the hip points of COCO-like detectors are higher and wider).
    pub legs: f64,
    /// Pelvis to neck: the CMU BVH skeletons' is 0.12 m (about a quarter) shorter than the
    /// ASF ones'; the neck of annotations is the mid-shoulder point, their pelvis the mid-hip
    /// point.
    pub torso: f64,
    /// Neck to head: the head point of COCO-like detectors (the face) is lower than CMU's,
    /// that of LSP and MPII (the head top) higher.
    pub head: f64,
    /// Neck to shoulder (half the shoulder width).
    pub shoulder_width: f64,
    /// Upper arms and forearms: the wrist and elbow points of detectors and annotations sit
    /// off the mocap joint centres.
    pub arms: f64,
    /// Left and right limbs of a type apart.
    pub asymmetry: f64,
}

impl Default for LengthWidening {
    /// Hip width 0.35 (the hip joints 0.5-2 times as far apart within two deviations),
    /// legs 0.08, torso 0.22 (the BVH and ASF torsos within two deviations), head 0.35,
    /// shoulder width 0.15, arms 0.10, asymmetry 0.03 (log standard deviations, chosen from
    /// the convention differences listed on each field; legs, arms and torso were then
    /// compared at a few widths on rescaled held-out people, docs/RESULTS.md).
    fn default() -> Self {
        LengthWidening {
            hip_width: 0.35,
            legs: 0.08,
            torso: 0.22,
            head: 0.35,
            shoulder_width: 0.15,
            arms: 0.10,
            asymmetry: 0.03,
        }
    }
}

impl LengthWidening {
    /// The limb groups (by [`camloc_skeleton::LIMBS`] index) and their shared deviation.
    fn groups(&self) -> [(&'static [usize], f64); 8] {
        [
            (&[0, 3], self.hip_width),
            (&[1, 4], self.legs),
            (&[2, 5], self.legs),
            (&[6], self.torso),
            (&[7], self.head),
            (&[8, 11], self.shoulder_width),
            (&[9, 12], self.arms),
            (&[10, 13], self.arms),
        ]
    }

    /// An error for a deviation that is negative, not finite or above 2.
    pub(crate) fn check(&self) -> Result<(), ReconstructError> {
        let values = [
            self.hip_width,
            self.legs,
            self.torso,
            self.head,
            self.shoulder_width,
            self.arms,
            self.asymmetry,
        ];
        match values.iter().find(|v| !(0.0..=2.0).contains(*v)) {
            Some(v) => Err(ReconstructError::InvalidConfig {
                field: "LengthWidening",
                value: format!("{v:?}"),
                reason: "every deviation must lie in [0, 2]",
            }),
            None => Ok(()),
        }
    }
}

/// The smallest variance added to the diagonal so that the covariance has an inverse.
const VARIANCE_FLOOR: f64 = 1e-6;

impl LengthPrior {
    /// The mean and covariance of the log limb lengths of `poses` (metres); poses with a limb
    /// of zero length are left out.
    ///
    /// # Errors
    /// [`ReconstructError::EmptyTrainingSet`] when no pose has 14 limbs of positive length.
    pub fn fit(poses: &[Pose3]) -> Result<LengthPrior, ReconstructError> {
        let logs: Vec<[f64; NUM_LIMBS]> = poses
            .iter()
            .map(|p| std::array::from_fn(|b| p.limb_length(b).ln()))
            .filter(|l: &[f64; NUM_LIMBS]| l.iter().all(|v| v.is_finite()))
            .collect();
        if logs.is_empty() {
            return Err(ReconstructError::EmptyTrainingSet);
        }
        let n = logs.len() as f64;
        let mean_log: [f64; NUM_LIMBS] =
            std::array::from_fn(|b| logs.iter().map(|l| l[b]).sum::<f64>() / n);
        let mut covariance = [[0.0; NUM_LIMBS]; NUM_LIMBS];
        for l in &logs {
            for (a, row) in covariance.iter_mut().enumerate() {
                for (b, c) in row.iter_mut().enumerate() {
                    *c += (l[a] - mean_log[a]) * (l[b] - mean_log[b]) / n;
                }
            }
        }
        Ok(LengthPrior {
            mean_log,
            covariance,
        })
    }

    /// The mean log length of each limb (log metres).
    pub fn mean_log(&self) -> [f64; NUM_LIMBS] {
        self.mean_log
    }

    /// The covariance of the log lengths (row-major).
    pub fn covariance(&self) -> [[f64; NUM_LIMBS]; NUM_LIMBS] {
        self.covariance
    }

    /// The template: `exp` of the mean log lengths (the geometric mean skeleton, metres).
    ///
    /// # Errors
    /// As [`BoneLengths::from_array`] (a prior learned from implausible skeletons).
    pub fn template(&self) -> Result<BoneLengths, ReconstructError> {
        Ok(BoneLengths::from_array(self.mean_log.map(f64::exp))?)
    }

    /// The whitening matrix `W` of the widened prior: with `Sigma = C + widening + floor` and
    /// `Sigma = L L^T`, `W = L^-1`, so that `|W (l - mean)|^2` is the prior's squared
    /// Mahalanobis distance of the log lengths `l`.
    pub(crate) fn whitening(
        &self,
        widening: &LengthWidening,
    ) -> Result<LimbMatrix, ReconstructError> {
        let mut sigma = LimbMatrix::from_fn(|a, b| self.covariance[a][b]);
        for (limbs, deviation) in widening.groups() {
            for &a in limbs {
                for &b in limbs {
                    sigma[(a, b)] += deviation * deviation;
                }
            }
        }
        for a in 0..NUM_LIMBS {
            sigma[(a, a)] += widening.asymmetry * widening.asymmetry + VARIANCE_FLOOR;
        }
        let cholesky = sigma.cholesky().ok_or(ReconstructError::Numerical(
            "the length prior's covariance is not positive definite",
        ))?;
        let l = cholesky.l();
        l.solve_lower_triangular(&LimbMatrix::identity())
            .ok_or(ReconstructError::Numerical(
                "the length prior's factor cannot be inverted",
            ))
    }

    /// Checks a decoded prior: finite numbers, plausible mean lengths, a symmetric covariance
    /// with a non-negative diagonal.
    pub(crate) fn check(&self) -> Result<(), String> {
        let numbers = self.mean_log.iter().chain(self.covariance.iter().flatten());
        if !numbers.clone().all(|v| v.is_finite()) {
            return Err("length prior: non-finite number".into());
        }
        BoneLengths::from_array(self.mean_log.map(f64::exp))
            .map_err(|e| format!("length prior mean: {e}"))?;
        for a in 0..NUM_LIMBS {
            if self.covariance[a][a] < 0.0 {
                return Err(format!("length prior: negative variance of limb {a}"));
            }
            for b in 0..a {
                if (self.covariance[a][b] - self.covariance[b][a]).abs() > 1e-12 {
                    return Err("length prior: covariance is not symmetric".into());
                }
            }
        }
        Ok(())
    }
}
