//! The descriptors and their extraction.

use camloc_skeleton::{LIMBS, Landmark, NUM_LANDMARKS, NUM_LIMBS, PartialPose2, Pose2, TORSO_LIMB};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::ShapeContextBins;

/// Why a descriptor could not be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FeatureError {
    /// A landmark coordinate is NaN or infinite.
    #[error("landmark {landmark} has a non-finite coordinate")]
    NonFinite {
        /// Name of the landmark.
        landmark: &'static str,
    },
    /// Pelvis and neck coincide (or nearly so): there is no unit of scale.
    #[error(
        "degenerate torso: pelvis and neck are {length:e} apart (relative to the pose size), so the pose has no scale"
    )]
    DegenerateTorso {
        /// Torso length relative to the pose's extent.
        length: f64,
    },
    /// The output buffer has the wrong length.
    #[error("descriptor buffer has length {got}, expected {expected}")]
    BufferSize {
        /// Required length.
        expected: usize,
        /// Given length.
        got: usize,
    },
    /// Invalid descriptor settings.
    #[error("invalid descriptor settings: {0}")]
    InvalidConfig(String),
    /// The pelvis or the neck is missing: without the torso there is no origin or scale.
    #[error("landmark {landmark} is missing; the torso (pelvis and neck) is required")]
    MissingTorso {
        /// Name of the missing landmark.
        landmark: &'static str,
    },
    /// Unknown descriptor name.
    #[error("unknown descriptor '{0}' (expected 'landmarks' or 'paper')")]
    UnknownName(String),
}

/// Settings of the paper's descriptor (Algorithm 1).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PaperConfig {
    /// Width of the Gaussian applied to relative lengths, `exp(-rl^2 / (2 sigma^2))`.
    pub sigma: f64,
    /// Shape-context bins.
    pub bins: ShapeContextBins,
}

impl Default for PaperConfig {
    /// sigma = 1 torso length, 5 x 12 shape-context bins.
    fn default() -> Self {
        PaperConfig {
            sigma: 1.0,
            bins: ShapeContextBins::default(),
        }
    }
}

/// A 2D pose descriptor, chosen by name (`landmarks`, the default, or `paper`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum Descriptor {
    /// Landmark-aware descriptor (default): torso-normalised coordinates of the 14 non-pelvis
    /// landmarks (28 values), the unit direction of every limb (28), and the 13 non-torso limb
    /// lengths relative to the torso (13): 69 values.
    Landmarks,
    /// The paper's Algorithm 1: 13 Gaussian-smoothed relative lengths, then the shape-context
    /// histogram (counts of the 14 non-pelvis landmarks per cell).
    Paper(PaperConfig),
}

impl Default for Descriptor {
    fn default() -> Self {
        Descriptor::Landmarks
    }
}

/// Offsets of the landmark-aware descriptor's parts.
const COORDS: usize = 2 * (NUM_LANDMARKS - 1);
const DIRECTIONS: usize = 2 * NUM_LIMBS;
const LENGTHS: usize = NUM_LIMBS - 1;
/// Mask with every landmark present.
const ALL_PRESENT: u16 = (1 << NUM_LANDMARKS) - 1;
/// Values that can be flagged undefined: the landmark-aware descriptor's length bounds every
/// descriptor's defined-by-landmark part (the histogram is never flagged).
const MAX_LEN: usize = COORDS + DIRECTIONS + LENGTHS;

impl Descriptor {
    /// The descriptor called `name`: `landmarks` or `paper` (with default settings).
    ///
    /// # Errors
    /// [`FeatureError::UnknownName`].
    pub fn from_name(name: &str) -> Result<Descriptor, FeatureError> {
        match name {
            "landmarks" => Ok(Descriptor::Landmarks),
            "paper" => Ok(Descriptor::Paper(PaperConfig::default())),
            other => Err(FeatureError::UnknownName(other.to_string())),
        }
    }

    /// Short name (`"landmarks"`, `"paper"`).
    pub fn name(&self) -> &'static str {
        match self {
            Descriptor::Landmarks => "landmarks",
            Descriptor::Paper(_) => "paper",
        }
    }

    /// Number of values in the descriptor.
    pub fn len(&self) -> usize {
        match self {
            Descriptor::Landmarks => COORDS + DIRECTIONS + LENGTHS,
            Descriptor::Paper(c) => LENGTHS + c.bins.len(),
        }
    }

    /// Always `false`: descriptors have at least one value.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Checks the settings (positive finite sigma, valid bins).
    ///
    /// # Errors
    /// [`FeatureError::InvalidConfig`].
    pub fn validate(&self) -> Result<(), FeatureError> {
        if let Descriptor::Paper(c) = self {
            if !(c.sigma > 0.0 && c.sigma.is_finite()) {
                return Err(FeatureError::InvalidConfig(format!(
                    "sigma must be positive and finite, got {}",
                    c.sigma
                )));
            }
            if !c.bins.is_valid() {
                return Err(FeatureError::InvalidConfig(format!(
                    "shape-context bins need radial, angular >= 1 and 0 < inner < outer radius, got {:?}",
                    c.bins
                )));
            }
        }
        Ok(())
    }

    /// Computes the descriptor of `pose` into `out` (length [`Descriptor::len`]) without
    /// allocating.
    ///
    /// # Errors
    /// [`FeatureError::BufferSize`], [`FeatureError::NonFinite`],
    /// [`FeatureError::DegenerateTorso`], [`FeatureError::InvalidConfig`].
    pub fn extract_into(&self, pose: &Pose2, out: &mut [f64]) -> Result<(), FeatureError> {
        self.extract_masked(pose, ALL_PRESENT, out, None)
    }

    /// Computes the descriptor of a pose with missing landmarks. Values that depend on a
    /// missing landmark (its coordinates, and the direction and length of the limbs it ends)
    /// are set to 0 and flagged `true` in `undefined` (length [`Descriptor::len`]), so that the
    /// caller can impute them; the shape-context histogram simply does not count missing
    /// landmarks.
    ///
    /// # Errors
    /// [`FeatureError::MissingTorso`] when the pelvis or neck is missing, then as
    /// [`Descriptor::extract_into`] (also for a wrong `undefined` length).
    pub fn extract_partial_into(
        &self,
        pose: &PartialPose2,
        out: &mut [f64],
        undefined: &mut [bool],
    ) -> Result<(), FeatureError> {
        for torso in [Landmark::Pelvis, Landmark::Neck] {
            if pose.points[torso.index()].is_none() {
                return Err(FeatureError::MissingTorso {
                    landmark: torso.name(),
                });
            }
        }
        // Missing landmarks sit at the pelvis: every value they touch is overwritten below.
        let pelvis = pose.points[0].unwrap_or([0.0, 0.0]);
        let filled = Pose2::new(pose.points.map(|p| p.unwrap_or(pelvis)));
        self.extract_masked(&filled, pose.present_mask(), out, Some(undefined))
    }

    /// The descriptor of `pose` where only landmarks whose bit is set in `present` count.
    fn extract_masked(
        &self,
        pose: &Pose2,
        present: u16,
        out: &mut [f64],
        mut undefined: Option<&mut [bool]>,
    ) -> Result<(), FeatureError> {
        if out.len() != self.len() {
            return Err(FeatureError::BufferSize {
                expected: self.len(),
                got: out.len(),
            });
        }
        if let Some(u) = undefined.as_deref_mut() {
            if u.len() != self.len() {
                return Err(FeatureError::BufferSize {
                    expected: self.len(),
                    got: u.len(),
                });
            }
            u.fill(false);
        }
        let is_present = |l: Landmark| present & (1 << l.index()) != 0;
        let limb_present = |limb: usize| {
            let (a, b) = LIMBS[limb];
            is_present(a) && is_present(b)
        };
        let frame = TorsoFrame::new(pose)?;
        // Indices of the values each part fills, to flag undefined ones.
        let mut flags: [bool; MAX_LEN] = [false; MAX_LEN];
        match self {
            Descriptor::Landmarks => {
                let (coords, rest) = out.split_at_mut(COORDS);
                let (directions, lengths) = rest.split_at_mut(DIRECTIONS);
                for (i, c) in coords.chunks_exact_mut(2).enumerate() {
                    let [du, dv] = frame.offset(pose, i + 1);
                    c[0] = du;
                    c[1] = dv;
                    if !is_present(Landmark::ALL[i + 1]) {
                        flags[2 * i] = true;
                        flags[2 * i + 1] = true;
                    }
                }
                for (limb, d) in directions.chunks_exact_mut(2).enumerate() {
                    let (a, b) = LIMBS[limb];
                    let (p, q) = (pose.get(a), pose.get(b));
                    let (du, dv) = (q[0] - p[0], q[1] - p[1]);
                    let n = du.hypot(dv);
                    // A zero-length limb has no direction: encode it as (0, 0).
                    let (du, dv) = if n > frame.torso * 1e-12 {
                        (du / n, dv / n)
                    } else {
                        (0.0, 0.0)
                    };
                    d[0] = du;
                    d[1] = dv;
                    if !limb_present(limb) {
                        flags[COORDS + 2 * limb] = true;
                        flags[COORDS + 2 * limb + 1] = true;
                    }
                }
                for (k, (o, (limb, rl))) in lengths
                    .iter_mut()
                    .zip(frame.relative_lengths(pose))
                    .enumerate()
                {
                    *o = rl;
                    flags[COORDS + DIRECTIONS + k] = !limb_present(limb);
                }
            }
            Descriptor::Paper(c) => {
                self.validate()?;
                let (lengths, histogram) = out.split_at_mut(LENGTHS);
                let two_sigma2 = 2.0 * c.sigma * c.sigma;
                for (k, (o, (limb, rl))) in lengths
                    .iter_mut()
                    .zip(frame.relative_lengths(pose))
                    .enumerate()
                {
                    *o = (-rl * rl / two_sigma2).exp();
                    flags[k] = !limb_present(limb);
                }
                histogram.fill(0.0);
                for i in 1..NUM_LANDMARKS {
                    if is_present(Landmark::ALL[i]) {
                        let [du, dv] = frame.offset(pose, i);
                        histogram[c.bins.cell(du, dv)] += 1.0;
                    }
                }
            }
        }
        if present != ALL_PRESENT {
            for (k, o) in out.iter_mut().enumerate() {
                if flags.get(k).copied().unwrap_or(false) {
                    *o = 0.0;
                }
            }
            if let Some(u) = undefined {
                for (k, u) in u.iter_mut().enumerate() {
                    *u = flags.get(k).copied().unwrap_or(false);
                }
            }
        }
        Ok(())
    }

    /// Computes the descriptor of `pose` into a new vector.
    ///
    /// # Errors
    /// As [`Descriptor::extract_into`].
    pub fn extract(&self, pose: &Pose2) -> Result<Vec<f64>, FeatureError> {
        let mut out = vec![0.0; self.len()];
        self.extract_into(pose, &mut out)?;
        Ok(out)
    }

    /// Descriptors of many poses, row-major (`poses.len() x len()`), computed in parallel.
    ///
    /// # Errors
    /// The error of the first pose (in order) that fails, with its index.
    pub fn extract_batch(&self, poses: &[Pose2]) -> Result<Vec<f64>, (usize, FeatureError)> {
        let d = self.len();
        let mut out = vec![0.0; poses.len() * d];
        out.par_chunks_mut(d.max(1))
            .zip(poses.par_iter())
            .enumerate()
            .try_for_each(|(i, (row, pose))| self.extract_into(pose, row).map_err(|e| (i, e)))?;
        Ok(out)
    }
}

/// The pelvis origin and torso unit of a pose.
struct TorsoFrame {
    origin: [f64; 2],
    torso: f64,
}

impl TorsoFrame {
    fn new(pose: &Pose2) -> Result<TorsoFrame, FeatureError> {
        for (i, p) in pose.points.iter().enumerate() {
            if !(p[0].is_finite() && p[1].is_finite()) {
                return Err(FeatureError::NonFinite {
                    landmark: camloc_skeleton::Landmark::ALL[i].name(),
                });
            }
        }
        let torso = pose.torso_length();
        let extent = pose
            .points
            .iter()
            .map(|p| p[0].abs().max(p[1].abs()))
            .fold(0.0, f64::max);
        if !(torso > 1e-9 * extent) || torso == 0.0 {
            return Err(FeatureError::DegenerateTorso {
                length: if extent > 0.0 { torso / extent } else { 0.0 },
            });
        }
        Ok(TorsoFrame {
            origin: pose.points[0],
            torso,
        })
    }

    /// Offset of landmark `i` from the pelvis, in torso lengths.
    fn offset(&self, pose: &Pose2, i: usize) -> [f64; 2] {
        let p = pose.points[i];
        [
            (p[0] - self.origin[0]) / self.torso,
            (p[1] - self.origin[1]) / self.torso,
        ]
    }

    /// The 13 non-torso limbs and their lengths divided by the torso length, in [`LIMBS`]
    /// order.
    fn relative_lengths<'a>(&'a self, pose: &'a Pose2) -> impl Iterator<Item = (usize, f64)> + 'a {
        (0..NUM_LIMBS)
            .filter(|&l| l != TORSO_LIMB)
            .map(move |l| (l, pose.limb_length(l) / self.torso))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn pose() -> Pose2 {
        Pose2::new([
            [100.0, 200.0],
            [90.0, 205.0],
            [92.0, 260.0],
            [95.0, 320.0],
            [110.0, 205.0],
            [108.0, 262.0],
            [106.0, 322.0],
            [100.0, 140.0],
            [101.0, 115.0],
            [82.0, 145.0],
            [75.0, 175.0],
            [70.0, 200.0],
            [118.0, 145.0],
            [125.0, 170.0],
            [140.0, 150.0],
        ])
    }

    fn all() -> [Descriptor; 2] {
        [
            Descriptor::Landmarks,
            Descriptor::Paper(PaperConfig::default()),
        ]
    }

    proptest! {
        #[test]
        fn invariant_to_translation_and_scale(tx in -1e4f64..1e4, ty in -1e4f64..1e4,
                                              log_s in -6.0f64..6.0) {
            let s = log_s.exp();
            let moved = Pose2::new(pose().points.map(|p| [s * p[0] + tx, s * p[1] + ty]));
            for d in all() {
                let a = d.extract(&pose()).unwrap();
                let b = d.extract(&moved).unwrap();
                for (x, y) in a.iter().zip(&b) {
                    prop_assert!((x - y).abs() < 1e-9, "{}: {x} vs {y}", d.name());
                }
            }
        }

        #[test]
        fn mirrored_landmarks_descriptor_is_the_reflection(tx in -50.0f64..50.0) {
            // Mirroring the image (u -> -u) and swapping left/right labels maps the landmark
            // descriptor's coordinates to their mirrored counterparts.
            let p = Pose2::new(pose().points.map(|q| [q[0] + tx, q[1]]));
            let m = p.mirrored();
            let a = Descriptor::Landmarks.extract(&p).unwrap();
            let b = Descriptor::Landmarks.extract(&m).unwrap();
            for i in 1..NUM_LANDMARKS {
                let j = camloc_skeleton::mirror_landmark_index(i);
                prop_assert!((a[2 * (i - 1)] + b[2 * (j - 1)]).abs() < 1e-9);
                prop_assert!((a[2 * (i - 1) + 1] - b[2 * (j - 1) + 1]).abs() < 1e-9);
            }
            // The paper's relative lengths of a limb equal those of its mirror limb.
            let pa = Descriptor::Paper(PaperConfig::default()).extract(&p).unwrap();
            let pb = Descriptor::Paper(PaperConfig::default()).extract(&m).unwrap();
            prop_assert!((pa[1] - pb[4]).abs() < 1e-12); // left thigh vs right thigh (index 1 vs 4)
        }
    }

    #[test]
    fn paper_descriptor_has_expected_shape() {
        let d = Descriptor::Paper(PaperConfig::default());
        let v = d.extract(&pose()).unwrap();
        assert_eq!(v.len(), 13 + 60);
        assert!((v[13..].iter().sum::<f64>() - 14.0).abs() < 1e-12);
        assert!(v[..13].iter().all(|&x| x > 0.0 && x <= 1.0));
        // Thigh relative length 55/60 through the Gaussian with sigma 1.
        let rl = pose().limb_length(1) / pose().torso_length();
        assert!((v[1] - (-rl * rl / 2.0).exp()).abs() < 1e-12);
    }

    #[test]
    fn partial_pose_flags_exactly_the_values_of_missing_landmarks() {
        let full = pose();
        for d in all() {
            let complete = d.extract(&full).unwrap();
            let mut partial = PartialPose2::from(full);
            partial.points[Landmark::LeftWrist.index()] = None;
            partial.points[Landmark::RightKnee.index()] = None;
            let mut out = vec![0.0; d.len()];
            let mut undefined = vec![false; d.len()];
            d.extract_partial_into(&partial, &mut out, &mut undefined)
                .unwrap();
            let flagged = undefined.iter().filter(|&&u| u).count();
            match d {
                // The wrist ends 1 limb (forearm), the knee 2 (thigh, shin): 2 landmarks x 2
                // coordinates, 3 limbs x 2 direction values, 3 lengths.
                Descriptor::Landmarks => assert_eq!(flagged, 4 + 6 + 3),
                // 3 lengths; the histogram counts the 12 present non-pelvis landmarks.
                Descriptor::Paper(_) => {
                    assert_eq!(flagged, 3);
                    assert!((out[13..].iter().sum::<f64>() - 12.0).abs() < 1e-12);
                }
            }
            for (k, (a, b)) in complete.iter().zip(&out).enumerate() {
                if undefined[k] {
                    assert_eq!(*b, 0.0);
                } else if k < 13 || matches!(d, Descriptor::Landmarks) {
                    assert!((a - b).abs() < 1e-12, "{} value {k}", d.name());
                }
            }
            partial.points[Landmark::Neck.index()] = None;
            assert_eq!(
                d.extract_partial_into(&partial, &mut out, &mut undefined),
                Err(FeatureError::MissingTorso { landmark: "neck" })
            );
        }
    }

    #[test]
    fn bad_input_is_an_error_not_nan() {
        let mut p = pose();
        p.points[7] = p.points[0];
        for d in all() {
            assert!(matches!(
                d.extract(&p),
                Err(FeatureError::DegenerateTorso { .. })
            ));
        }
        let mut p = pose();
        p.points[3][1] = f64::NAN;
        assert_eq!(
            Descriptor::Landmarks.extract(&p),
            Err(FeatureError::NonFinite {
                landmark: "left_ankle"
            })
        );
        let mut short = [0.0; 5];
        assert!(matches!(
            Descriptor::Landmarks.extract_into(&pose(), &mut short),
            Err(FeatureError::BufferSize { .. })
        ));
        let bad = Descriptor::Paper(PaperConfig {
            sigma: 0.0,
            ..PaperConfig::default()
        });
        assert!(matches!(
            bad.extract(&pose()),
            Err(FeatureError::InvalidConfig(_))
        ));
        assert!(Descriptor::from_name("nope").is_err());
        let batch = Descriptor::Landmarks
            .extract_batch(&[pose(), p])
            .unwrap_err();
        assert_eq!(batch.0, 1);
    }
}
