//! The descriptors and their extraction.

use camloc_skeleton::{LIMBS, Landmark, NUM_LANDMARKS, NUM_LIMBS, PartialPose2, Pose2};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::{FeatureError, ShapeContextBins};

mod frame;

use frame::TorsoFrame;

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

/// A 2D pose descriptor, chosen by name: `joints` (the default), `landmarks` or `paper`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum Descriptor {
    /// Landmark-aware descriptor: torso-normalised coordinates of the 14 non-pelvis
    /// landmarks (28 values), the unit direction of every limb (28), and the 13 non-torso limb
    /// lengths relative to the torso (13): 69 values.
    Landmarks,
    /// The paper's Algorithm 1: 13 Gaussian-smoothed relative lengths, then the shape-context
    /// histogram (counts of the 14 non-pelvis landmarks per cell).
    Paper(PaperConfig),
    /// Convention-robust descriptor: like [`Descriptor::Landmarks`] but built only on the 12
    /// limb joints (hips, knees, ankles, shoulders, elbows, wrists), which every keypoint
    /// convention places alike. The frame is the mid-hip point (origin) and the mid-shoulder
    /// point (unit length) instead of the pelvis and neck, whose placement differs between
    /// mocap skeletons and photo annotations. Values: 12 joint coordinates (24), directions
    /// (20) and relative lengths (10) of the 10 segments hip-hip, shoulder-shoulder and the
    /// 8 limb bones: 54 values. Falls back to the pelvis (neck) when a hip (shoulder) is
    /// missing.
    Joints,
}

impl Default for Descriptor {
    /// [`Descriptor::Joints`]: as accurate as [`Descriptor::Landmarks`] on held-out mocap
    /// subjects and robust to how photo annotations place the neck and pelvis
    /// (docs/RESULTS.md).
    fn default() -> Self {
        Descriptor::Joints
    }
}

/// Offsets of the landmark-aware descriptor's parts.
const COORDS: usize = 2 * (NUM_LANDMARKS - 1);
const DIRECTIONS: usize = 2 * NUM_LIMBS;
const LENGTHS: usize = NUM_LIMBS - 1;
/// The 12 limb joints of [`Descriptor::Joints`].
const JOINTS: [Landmark; 12] = {
    // Every landmark but the pelvis, neck and head, in index order.
    let mut joints = [Landmark::Pelvis; 12];
    let (mut i, mut n) = (0, 0);
    while i < NUM_LANDMARKS {
        let l = Landmark::ALL[i];
        if !matches!(l, Landmark::Pelvis | Landmark::Neck | Landmark::Head) {
            joints[n] = l;
            n += 1;
        }
        i += 1;
    }
    joints
};
/// The 10 segments of [`Descriptor::Joints`].
const SEGMENTS: [(Landmark, Landmark); 10] = [
    (Landmark::LeftHip, Landmark::RightHip),
    (Landmark::LeftHip, Landmark::LeftKnee),
    (Landmark::LeftKnee, Landmark::LeftAnkle),
    (Landmark::RightHip, Landmark::RightKnee),
    (Landmark::RightKnee, Landmark::RightAnkle),
    (Landmark::LeftShoulder, Landmark::RightShoulder),
    (Landmark::LeftShoulder, Landmark::LeftElbow),
    (Landmark::LeftElbow, Landmark::LeftWrist),
    (Landmark::RightShoulder, Landmark::RightElbow),
    (Landmark::RightElbow, Landmark::RightWrist),
];
/// Length of [`Descriptor::Joints`].
const JOINTS_LEN: usize = 2 * JOINTS.len() + 3 * SEGMENTS.len();
/// Mask with every landmark present.
const ALL_PRESENT: u16 = (1 << NUM_LANDMARKS) - 1;
/// Values that can be flagged undefined: the landmark-aware descriptor's length bounds every
/// descriptor's defined-by-landmark part (the histogram is never flagged).
const MAX_LEN: usize = COORDS + DIRECTIONS + LENGTHS;
const _: () = assert!(2 * JOINTS.len() + 3 * SEGMENTS.len() <= MAX_LEN);

impl Descriptor {
    /// Checks that this descriptor can be computed for the complete pose `pose`: finite
    /// coordinates and a torso (pelvis to neck, or for [`Descriptor::Joints`] hip midpoint to
    /// shoulder midpoint) longer than a billionth of the pose's extent. The same check the
    /// localizer makes, for callers that use the pose otherwise (3D reconstruction).
    ///
    /// # Errors
    /// [`FeatureError::NonFinite`] or [`FeatureError::DegenerateTorso`].
    pub fn check_scale(&self, pose: &Pose2) -> Result<(), FeatureError> {
        let (scaled, _) = pose.within_safe_range();
        self.frame(&scaled, &|_| true).map(|_| ())
    }

    /// Whether every descriptor can describe the complete pose `pose` ([`check_scale`] of the
    /// joints' hip-to-shoulder torso and of the pelvis-to-neck torso the others use): the
    /// rule by which dataset generation leaves out views no model could train on.
    ///
    /// [`check_scale`]: Self::check_scale
    pub fn describable_by_all(pose: &Pose2) -> bool {
        [Descriptor::Joints, Descriptor::Landmarks]
            .iter()
            .all(|d| d.check_scale(pose).is_ok())
    }

    /// The 2D frame of `pose` (within the safe range) with the landmarks `is_present` has.
    fn frame(
        &self,
        pose: &Pose2,
        is_present: &dyn Fn(Landmark) -> bool,
    ) -> Result<TorsoFrame, FeatureError> {
        match self {
            Descriptor::Joints => TorsoFrame::from_joints(pose, is_present),
            _ => TorsoFrame::new(pose),
        }
    }

    /// The descriptor called `name`: `landmarks`, `joints` or `paper`
    /// (with default settings).
    ///
    /// # Errors
    /// [`FeatureError::UnknownName`].
    pub fn from_name(name: &str) -> Result<Descriptor, FeatureError> {
        match name {
            "landmarks" => Ok(Descriptor::Landmarks),
            "joints" => Ok(Descriptor::Joints),
            "paper" => Ok(Descriptor::Paper(PaperConfig::default())),
            other => Err(FeatureError::UnknownName(other.to_string())),
        }
    }

    /// Short name (`"landmarks"`, `"joints"`, `"paper"`).
    pub fn name(&self) -> &'static str {
        match self {
            Descriptor::Landmarks => "landmarks",
            Descriptor::Joints => "joints",
            Descriptor::Paper(_) => "paper",
        }
    }

    /// Number of values in the descriptor.
    pub fn len(&self) -> usize {
        match self {
            Descriptor::Landmarks => COORDS + DIRECTIONS + LENGTHS,
            Descriptor::Joints => JOINTS_LEN,
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
                    "shape-context bins need radial, angular >= 1, at most {} cells and 0 < inner < outer radius, got {:?}",
                    crate::shape_context::MAX_SHAPE_CONTEXT_CELLS,
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
    /// [`FeatureError::MissingTorso`] when the pelvis or neck is missing (for
    /// [`Descriptor::Joints`]: when it is missing and so is a hip or shoulder), then as
    /// [`Descriptor::extract_into`] (also for a wrong `undefined` length).
    pub fn extract_partial_into(
        &self,
        pose: &PartialPose2,
        out: &mut [f64],
        undefined: &mut [bool],
    ) -> Result<(), FeatureError> {
        let has = |l: Landmark| pose.points[l.index()].is_some();
        for (torso, left, right) in [
            (Landmark::Pelvis, Landmark::LeftHip, Landmark::RightHip),
            (
                Landmark::Neck,
                Landmark::LeftShoulder,
                Landmark::RightShoulder,
            ),
        ] {
            let replaceable = matches!(self, Descriptor::Joints) && has(left) && has(right);
            if !has(torso) && !replaceable {
                return Err(FeatureError::MissingTorso {
                    landmark: torso.name(),
                });
            }
        }
        // Missing landmarks sit at the first present one: every value they touch is
        // overwritten below.
        let anchor = pose
            .points
            .iter()
            .flatten()
            .next()
            .copied()
            .unwrap_or([0.0, 0.0]);
        let filled = Pose2::new(pose.points.map(|p| p.unwrap_or(anchor)));
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
        // Descriptors are scale invariant: extreme magnitudes are brought into range first
        // (exactly, by a power of two).
        let (scaled, _) = pose.within_safe_range();
        let pose = &scaled;
        let frame = self.frame(pose, &is_present)?;
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
                    let [du, dv] = frame.direction(pose.get(a), pose.get(b));
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
            Descriptor::Joints => {
                let (coords, rest) = out.split_at_mut(2 * JOINTS.len());
                let (directions, lengths) = rest.split_at_mut(2 * SEGMENTS.len());
                for (k, (c, joint)) in coords.chunks_exact_mut(2).zip(JOINTS).enumerate() {
                    let [du, dv] = frame.offset(pose, joint.index());
                    c[0] = du;
                    c[1] = dv;
                    if !is_present(joint) {
                        flags[2 * k] = true;
                        flags[2 * k + 1] = true;
                    }
                }
                let base = 2 * JOINTS.len();
                for (k, ((d, length), (a, b))) in directions
                    .chunks_exact_mut(2)
                    .zip(lengths.iter_mut())
                    .zip(SEGMENTS)
                    .enumerate()
                {
                    let [du, dv] = frame.direction(pose.get(a), pose.get(b));
                    d[0] = du;
                    d[1] = dv;
                    *length = frame.relative(pose.get(a), pose.get(b));
                    if !(is_present(a) && is_present(b)) {
                        flags[base + 2 * k] = true;
                        flags[base + 2 * k + 1] = true;
                        flags[base + 2 * SEGMENTS.len() + k] = true;
                    }
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

    fn all() -> [Descriptor; 3] {
        [
            Descriptor::Landmarks,
            Descriptor::Joints,
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

    /// `pose()` with every coordinate multiplied by `k`.
    fn scaled(k: f64) -> Pose2 {
        Pose2::new(pose().points.map(|p| [p[0] * k, p[1] * k]))
    }

    #[test]
    fn shoulders_on_the_hips_name_the_segment_that_collapsed() {
        let mut p = scaled(2.5);
        let (pelvis, neck) = (p.get(Landmark::Pelvis), p.get(Landmark::Neck));
        assert_eq!((pelvis[1] - neck[1]).abs(), 150.0);
        for (shoulder, hip) in [
            (Landmark::LeftShoulder, Landmark::LeftHip),
            (Landmark::RightShoulder, Landmark::RightHip),
        ] {
            p.points[shoulder.index()] = p.get(hip);
        }
        let err = Descriptor::Joints.extract(&p).unwrap_err();
        assert_eq!(
            err.to_string(),
            "degenerate torso: the shoulder midpoint and the hip midpoint are 0 apart (relative to the pose size), so the pose has no scale"
        );
        // The descriptors built on pelvis and neck are well defined for this pose.
        assert!(Descriptor::Landmarks.extract(&p).is_ok());
        let mut q = pose();
        q.points[Landmark::Neck.index()] = q.get(Landmark::Pelvis);
        let err = Descriptor::Landmarks.extract(&q).unwrap_err();
        assert!(
            err.to_string()
                .starts_with("degenerate torso: the neck and the pelvis are 0 apart"),
            "{err}"
        );
    }

    #[test]
    fn extreme_coordinates_neither_overflow_nor_underflow() {
        for d in all() {
            let reference = d.extract(&pose()).unwrap();
            for k in [1e154, 1e305 / 322.0, 1e-200, 1e-300] {
                let v = d.extract(&scaled(k)).unwrap();
                for (a, b) in v.iter().zip(&reference) {
                    assert!((a - b).abs() < 1e-9, "{} x {k:e}: {a} vs {b}", d.name());
                }
            }
        }
        // +-1e308 corners: finite, and a collapsed torso is "0 apart", never "NaN apart".
        let mut p = Pose2::new([[1e308, -1e308]; 15]);
        p.points[Landmark::Neck.index()] = [-1e308, 1e308];
        for d in [
            Descriptor::Landmarks,
            Descriptor::Paper(PaperConfig::default()),
        ] {
            let v = d.extract(&p).unwrap();
            assert!(v.iter().all(|x| x.is_finite()), "{}: {v:?}", d.name());
        }
        let flat = Pose2::new([[1e308, -1e308]; 15]);
        for d in all() {
            let err = d.extract(&flat).unwrap_err().to_string();
            assert!(err.contains(" are 0 apart"), "{}: {err}", d.name());
        }
        let mut signs = Pose2::new([[1e308, 1e308]; 15]);
        signs.points[Landmark::LeftHip.index()] = [-1e308, -1e308];
        signs.points[Landmark::LeftShoulder.index()] = [-1e308, -1e308];
        let err = Descriptor::Joints.extract(&signs).unwrap_err().to_string();
        assert!(!err.contains("NaN"), "{err}");
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
                Descriptor::Landmarks | Descriptor::Joints => assert_eq!(flagged, 4 + 6 + 3),
                // 3 lengths; the histogram counts the 12 present non-pelvis landmarks.
                Descriptor::Paper(_) => {
                    assert_eq!(flagged, 3);
                    assert!((out[13..].iter().sum::<f64>() - 12.0).abs() < 1e-12);
                }
            }
            for (k, (a, b)) in complete.iter().zip(&out).enumerate() {
                if undefined[k] {
                    assert_eq!(*b, 0.0);
                } else if k < 13 || !matches!(d, Descriptor::Paper(_)) {
                    assert!((a - b).abs() < 1e-12, "{} value {k}", d.name());
                }
            }
            partial.points[Landmark::Neck.index()] = None;
            if matches!(d, Descriptor::Joints) {
                // The shoulders stand in for the neck: nothing changes.
                d.extract_partial_into(&partial, &mut out, &mut undefined)
                    .unwrap();
                partial.points[Landmark::LeftShoulder.index()] = None;
            }
            assert_eq!(
                d.extract_partial_into(&partial, &mut out, &mut undefined),
                Err(FeatureError::MissingTorso { landmark: "neck" })
            );
        }
    }

    #[test]
    fn bad_input_is_an_error_not_nan() {
        // Neck on the pelvis, and the shoulders on the hips (the joints descriptor's frame).
        let mut p = pose();
        p.points[7] = p.points[0];
        p.points[9] = p.points[1];
        p.points[12] = p.points[4];
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
