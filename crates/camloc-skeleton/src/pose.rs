//! Landmarks, limbs and the 2D/3D pose containers.

use serde::{Deserialize, Serialize};

/// Number of landmarks in a camloc pose.
pub const NUM_LANDMARKS: usize = 15;
/// Number of limbs (landmark pairs) in a camloc pose.
pub const NUM_LIMBS: usize = 14;

/// The 15 landmarks, in the fixed order of docs/conventions.md section 3 (the discriminant is the
/// index).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[repr(u8)]
pub enum Landmark {
    /// Pelvis (root); the origin of the canonical 3D frame and the 2D shape-context centre.
    Pelvis = 0,
    /// Left hip joint.
    LeftHip = 1,
    /// Left knee.
    LeftKnee = 2,
    /// Left ankle.
    LeftAnkle = 3,
    /// Right hip joint.
    RightHip = 4,
    /// Right knee.
    RightKnee = 5,
    /// Right ankle.
    RightAnkle = 6,
    /// Neck (lower neck / thorax end).
    Neck = 7,
    /// Head (upper neck end).
    Head = 8,
    /// Left shoulder.
    LeftShoulder = 9,
    /// Left elbow.
    LeftElbow = 10,
    /// Left wrist.
    LeftWrist = 11,
    /// Right shoulder.
    RightShoulder = 12,
    /// Right elbow.
    RightElbow = 13,
    /// Right wrist.
    RightWrist = 14,
}

impl Landmark {
    /// All landmarks in index order.
    pub const ALL: [Landmark; NUM_LANDMARKS] = [
        Landmark::Pelvis,
        Landmark::LeftHip,
        Landmark::LeftKnee,
        Landmark::LeftAnkle,
        Landmark::RightHip,
        Landmark::RightKnee,
        Landmark::RightAnkle,
        Landmark::Neck,
        Landmark::Head,
        Landmark::LeftShoulder,
        Landmark::LeftElbow,
        Landmark::LeftWrist,
        Landmark::RightShoulder,
        Landmark::RightElbow,
        Landmark::RightWrist,
    ];

    /// Index of the landmark in a pose (0..15).
    pub const fn index(self) -> usize {
        self as usize
    }

    /// The landmark at `index`, or `None` when `index >= 15`.
    pub fn from_index(index: usize) -> Option<Landmark> {
        Landmark::ALL.get(index).copied()
    }

    /// Snake-case name as used in the project's JSON keypoint format (`left_hip`, ...).
    pub const fn name(self) -> &'static str {
        match self {
            Landmark::Pelvis => "pelvis",
            Landmark::LeftHip => "left_hip",
            Landmark::LeftKnee => "left_knee",
            Landmark::LeftAnkle => "left_ankle",
            Landmark::RightHip => "right_hip",
            Landmark::RightKnee => "right_knee",
            Landmark::RightAnkle => "right_ankle",
            Landmark::Neck => "neck",
            Landmark::Head => "head",
            Landmark::LeftShoulder => "left_shoulder",
            Landmark::LeftElbow => "left_elbow",
            Landmark::LeftWrist => "left_wrist",
            Landmark::RightShoulder => "right_shoulder",
            Landmark::RightElbow => "right_elbow",
            Landmark::RightWrist => "right_wrist",
        }
    }

    /// The landmark with snake-case `name`, or `None`.
    pub fn from_name(name: &str) -> Option<Landmark> {
        Landmark::ALL.iter().copied().find(|l| l.name() == name)
    }

    /// The same landmark on the other side of the body (left <-> right); central ones map to
    /// themselves.
    pub const fn mirrored(self) -> Landmark {
        match self {
            Landmark::LeftHip => Landmark::RightHip,
            Landmark::LeftKnee => Landmark::RightKnee,
            Landmark::LeftAnkle => Landmark::RightAnkle,
            Landmark::RightHip => Landmark::LeftHip,
            Landmark::RightKnee => Landmark::LeftKnee,
            Landmark::RightAnkle => Landmark::LeftAnkle,
            Landmark::LeftShoulder => Landmark::RightShoulder,
            Landmark::LeftElbow => Landmark::RightElbow,
            Landmark::LeftWrist => Landmark::RightWrist,
            Landmark::RightShoulder => Landmark::LeftShoulder,
            Landmark::RightElbow => Landmark::LeftElbow,
            Landmark::RightWrist => Landmark::LeftWrist,
            other => other,
        }
    }
}

impl Landmark {
    /// The parent of this landmark in the kinematic tree of [`LIMBS`] (rooted at the
    /// pelvis); `None` for the pelvis.
    pub fn parent(self) -> Option<Landmark> {
        LIMBS
            .iter()
            .find(|(_, child)| *child == self)
            .map(|(parent, _)| *parent)
    }

    /// This landmark and every landmark below it in the kinematic tree of [`LIMBS`], in
    /// index order (the pelvis: all 15).
    pub fn subtree(self) -> impl Iterator<Item = Landmark> {
        // LIMBS lists every parent before its children, so one pass finds them all.
        let mut inside = [false; NUM_LANDMARKS];
        inside[self.index()] = true;
        for (parent, child) in LIMBS {
            if inside[parent.index()] {
                inside[child.index()] = true;
            }
        }
        Landmark::ALL.into_iter().filter(move |l| inside[l.index()])
    }

    /// The mask of `landmarks`: bit `i` set for landmark index `i` (as
    /// [`PartialPose2::missing_mask`]).
    pub fn mask_of<'a>(landmarks: impl IntoIterator<Item = &'a Landmark>) -> u16 {
        landmarks.into_iter().fold(0, |m, l| m | 1 << l.index())
    }

    /// The landmarks whose bits are set in `mask`, in index order (the inverse of
    /// [`mask_of`](Self::mask_of)).
    pub fn in_mask(mask: u16) -> impl Iterator<Item = Landmark> {
        Landmark::ALL
            .into_iter()
            .filter(move |l| mask & (1 << l.index()) != 0)
    }
}

/// Index of the left/right counterpart of landmark `index` (see [`Landmark::mirrored`]).
///
/// Returns `index` itself for the central landmarks and for out-of-range indices.
pub fn mirror_landmark_index(index: usize) -> usize {
    Landmark::from_index(index).map_or(index, |l| l.mirrored().index())
}

/// The 14 limbs as (parent, child) landmark pairs, in the order of docs/conventions.md section 3.
pub const LIMBS: [(Landmark, Landmark); NUM_LIMBS] = [
    (Landmark::Pelvis, Landmark::LeftHip),
    (Landmark::LeftHip, Landmark::LeftKnee),
    (Landmark::LeftKnee, Landmark::LeftAnkle),
    (Landmark::Pelvis, Landmark::RightHip),
    (Landmark::RightHip, Landmark::RightKnee),
    (Landmark::RightKnee, Landmark::RightAnkle),
    (Landmark::Pelvis, Landmark::Neck),
    (Landmark::Neck, Landmark::Head),
    (Landmark::Neck, Landmark::LeftShoulder),
    (Landmark::LeftShoulder, Landmark::LeftElbow),
    (Landmark::LeftElbow, Landmark::LeftWrist),
    (Landmark::Neck, Landmark::RightShoulder),
    (Landmark::RightShoulder, Landmark::RightElbow),
    (Landmark::RightElbow, Landmark::RightWrist),
];

/// Position of the torso (pelvis to neck) in [`LIMBS`]; the reference length in 2D.
pub const TORSO_LIMB: usize = 6;

/// Position of the neck-to-head bone in [`LIMBS`].
pub const NECK_HEAD_LIMB: usize = 7;

/// Human-readable limb names, parallel to [`LIMBS`].
pub const LIMB_NAMES: [&str; NUM_LIMBS] = [
    "left pelvis-hip",
    "left thigh",
    "left shin",
    "right pelvis-hip",
    "right thigh",
    "right shin",
    "torso",
    "neck-head",
    "left collar",
    "left upper arm",
    "left forearm",
    "right collar",
    "right upper arm",
    "right forearm",
];

/// Largest coordinate magnitude, as a power of two, that [`Pose2::within_safe_range`] leaves
/// as it is. At 250, squares of coordinate differences stay normal numbers down to
/// differences of 2^-510 (2^-260 of the smallest extent left as it is), far below any
/// difference a descriptor still resolves.
pub const SAFE_EXPONENT: i32 = 250;

/// A 2D pose: the 15 landmarks in image coordinates `(u, v)`, `v` growing downwards.
///
/// Units are whatever the caller uses (pixels for photos, metres for orthographic
/// projections); every camloc descriptor is invariant to 2D translation and scale.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pose2 {
    /// Landmark positions, indexed by [`Landmark::index`].
    pub points: [[f64; 2]; NUM_LANDMARKS],
}

impl Pose2 {
    /// Wraps 15 image points.
    pub const fn new(points: [[f64; 2]; NUM_LANDMARKS]) -> Self {
        Pose2 { points }
    }

    /// Position of one landmark.
    pub fn get(&self, landmark: Landmark) -> [f64; 2] {
        self.points[landmark.index()]
    }

    /// Euclidean length of limb `limb` (an index into [`LIMBS`]), in the pose's units.
    ///
    /// # Panics
    /// When `limb` is not below [`NUM_LIMBS`].
    pub fn limb_length(&self, limb: usize) -> f64 {
        let (a, b) = LIMBS[limb];
        let (p, q) = (self.get(a), self.get(b));
        (p[0] - q[0]).hypot(p[1] - q[1])
    }

    /// Length of the torso (pelvis to neck), the 2D unit of scale.
    pub fn torso_length(&self) -> f64 {
        self.limb_length(TORSO_LIMB)
    }

    /// The pose multiplied by an exact power of two `f` that brings its largest coordinate
    /// magnitude into `[1, 2)`, and `f`, when that magnitude lies outside
    /// `2^-SAFE_EXPONENT..=2^SAFE_EXPONENT` (e.g. coordinates of 1e308 or 1e-100); otherwise,
    /// and for non-finite or all-zero poses, the pose unchanged and `f = 1`.
    ///
    /// Within the safe range, differences, midpoints and squares of coordinates and of their
    /// differences neither overflow nor underflow (see [`SAFE_EXPONENT`]). Multiplying by a
    /// power of two is exact (barring subnormal results), so scale-invariant computations give
    /// the same bits on the rescaled pose; poses already in range are not touched at all.
    pub fn within_safe_range(&self) -> (Pose2, f64) {
        let extent = self
            .points
            .iter()
            .map(|p| p[0].abs().max(p[1].abs()))
            .fold(0.0, f64::max);
        if !extent.is_finite() || extent == 0.0 {
            return (*self, 1.0);
        }
        // In range: 2^-SAFE <= extent < 2^(SAFE + 1), i.e. |floor(log2 extent)| <= SAFE,
        // checked without a logarithm.
        let (low, high) = (2f64.powi(-SAFE_EXPONENT), 2f64.powi(SAFE_EXPONENT + 1));
        if (low..high).contains(&extent) {
            return (*self, 1.0);
        }
        let exponent = extent.log2().floor() as i32;
        // 2^-exponent in two exact factors (one could overflow for tiny poses).
        let (a, b) = (
            2f64.powi(-exponent / 2),
            2f64.powi(-exponent - (-exponent / 2)),
        );
        let scaled = self.points.map(|p| [p[0] * a * b, p[1] * a * b]);
        (Pose2::new(scaled), a * b)
    }

    /// `true` when every coordinate is finite.
    pub fn is_finite(&self) -> bool {
        self.points.iter().flatten().all(|c| c.is_finite())
    }

    /// The image mirrored horizontally (`u -> -u`) with left and right labels swapped, i.e. the
    /// pose a camera at the mirrored viewpoint would see.
    pub fn mirrored(&self) -> Pose2 {
        let mut points = [[0.0; 2]; NUM_LANDMARKS];
        for (i, p) in self.points.iter().enumerate() {
            points[mirror_landmark_index(i)] = [-p[0], p[1]];
        }
        Pose2 { points }
    }
}

/// A 3D pose: the 15 landmarks in metres, in the right-handed z-up world frame of
/// docs/conventions.md section 1 (canonical poses have the pelvis at the origin and face -x, right
/// side towards +y).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pose3 {
    /// Landmark positions in metres, indexed by [`Landmark::index`].
    pub points: [[f64; 3]; NUM_LANDMARKS],
}

impl Pose3 {
    /// Wraps 15 points in metres.
    pub const fn new(points: [[f64; 3]; NUM_LANDMARKS]) -> Self {
        Pose3 { points }
    }

    /// Position of one landmark, in metres.
    pub fn get(&self, landmark: Landmark) -> [f64; 3] {
        self.points[landmark.index()]
    }

    /// Euclidean length of limb `limb` (an index into [`LIMBS`]), in metres.
    ///
    /// # Panics
    /// When `limb` is not below [`NUM_LIMBS`].
    pub fn limb_length(&self, limb: usize) -> f64 {
        let (a, b) = LIMBS[limb];
        let (p, q) = (self.get(a), self.get(b));
        ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
    }

    /// `true` when every coordinate is finite.
    pub fn is_finite(&self) -> bool {
        self.points.iter().flatten().all(|c| c.is_finite())
    }

    /// The lengths of the 14 limbs, in metres, in [`LIMBS`] order.
    pub fn limb_lengths(&self) -> [f64; NUM_LIMBS] {
        std::array::from_fn(|limb| self.limb_length(limb))
    }

    /// This pose with each limb brought to `lengths[limb]` (metres, [`LIMBS`] order) along its
    /// own direction: the pelvis stays, and each landmark is placed from its parent's new
    /// position, so every limb keeps its direction and the landmarks below it follow.
    ///
    /// `None` when a limb of this pose has no direction (zero or non-finite length) or a
    /// length is not finite.
    pub fn with_limb_lengths(&self, lengths: &[f64; NUM_LIMBS]) -> Option<Pose3> {
        let mut out = *self;
        // LIMBS lists every parent before its children: each parent is already in place.
        for ((parent, child), &length) in LIMBS.iter().zip(lengths) {
            let (p, c) = (self.get(*parent), self.get(*child));
            let d = [c[0] - p[0], c[1] - p[1], c[2] - p[2]];
            let norm = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            if !(norm > 0.0 && norm.is_finite() && length.is_finite()) {
                return None;
            }
            let base = out.get(*parent);
            out.points[child.index()] = std::array::from_fn(|k| base[k] + d[k] * (length / norm));
        }
        Some(out)
    }
}

/// The mean length of each limb over `poses` (metres, [`LIMBS`] order); `None` for no poses.
pub fn mean_limb_lengths(poses: &[Pose3]) -> Option<[f64; NUM_LIMBS]> {
    if poses.is_empty() {
        return None;
    }
    let n = poses.len() as f64;
    let mut mean = [0.0; NUM_LIMBS];
    for pose in poses {
        for (m, length) in mean.iter_mut().zip(pose.limb_lengths()) {
            *m += length / n;
        }
    }
    Some(mean)
}

/// A 2D pose whose landmarks may be missing (`None`): what keypoint files and detectors give.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PartialPose2 {
    /// Landmark positions in image coordinates, `None` where the landmark is missing.
    pub points: [Option<[f64; 2]>; NUM_LANDMARKS],
}

impl PartialPose2 {
    /// A pose with every landmark missing.
    pub const fn empty() -> Self {
        PartialPose2 {
            points: [None; NUM_LANDMARKS],
        }
    }

    /// The complete pose, or `None` if any landmark is missing.
    pub fn complete(&self) -> Option<Pose2> {
        let mut points = [[0.0; 2]; NUM_LANDMARKS];
        for (o, p) in points.iter_mut().zip(&self.points) {
            *o = (*p)?;
        }
        Some(Pose2 { points })
    }

    /// Landmarks that are missing, in index order.
    pub fn missing(&self) -> impl Iterator<Item = Landmark> + '_ {
        Landmark::ALL
            .into_iter()
            .filter(|l| self.points[l.index()].is_none())
    }

    /// The image mirrored horizontally (`u -> -u`) with left and right labels swapped (see
    /// [`Pose2::mirrored`]); missing landmarks stay missing.
    pub fn mirrored(&self) -> PartialPose2 {
        let mut points = [None; NUM_LANDMARKS];
        for (i, p) in self.points.iter().enumerate() {
            points[mirror_landmark_index(i)] = p.map(|q| [-q[0], q[1]]);
        }
        PartialPose2 { points }
    }

    /// Bit `i` set when landmark `i` is present.
    pub fn present_mask(&self) -> u16 {
        self.points
            .iter()
            .enumerate()
            .fold(0, |m, (i, p)| if p.is_some() { m | (1 << i) } else { m })
    }

    /// Bit `i` set when landmark `i` is missing (the complement of
    /// [`present_mask`](Self::present_mask) over the 15 landmarks).
    pub fn missing_mask(&self) -> u16 {
        !self.present_mask() & ((1 << NUM_LANDMARKS) - 1)
    }
}

impl From<Pose2> for PartialPose2 {
    fn from(pose: Pose2) -> Self {
        PartialPose2 {
            points: pose.points.map(Some),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pose whose every landmark is somewhere different (no zero-length limb).
    fn spread_pose() -> Pose3 {
        Pose3::new(std::array::from_fn(|i| {
            let t = i as f64;
            [0.1 * t.sin() + 0.01 * t, 0.2 * t.cos(), 0.05 * t * t - 0.3]
        }))
    }

    /// The missing mask is the present mask's complement over the 15 landmarks.
    #[test]
    fn missing_and_present_masks_split_the_landmarks() {
        let mut pose = PartialPose2 {
            points: [Some([1.0, 2.0]); NUM_LANDMARKS],
        };
        assert_eq!(pose.missing_mask(), 0);
        pose.points[Landmark::RightWrist.index()] = None;
        pose.points[Landmark::Pelvis.index()] = None;
        let expected = 1 << Landmark::RightWrist.index() | 1 << Landmark::Pelvis.index();
        assert_eq!(pose.missing_mask(), expected);
        assert_eq!(
            pose.missing_mask() | pose.present_mask(),
            (1 << NUM_LANDMARKS) - 1
        );
        assert_eq!(
            PartialPose2::empty().missing_mask(),
            (1 << NUM_LANDMARKS) - 1
        );
    }

    #[test]
    fn with_limb_lengths_sets_lengths_and_keeps_directions() {
        let pose = spread_pose();
        let lengths: [f64; NUM_LIMBS] = std::array::from_fn(|k| 0.1 + 0.03 * k as f64);
        let out = pose.with_limb_lengths(&lengths).unwrap();
        assert_eq!(out.get(Landmark::Pelvis), pose.get(Landmark::Pelvis));
        for (k, (a, b)) in LIMBS.iter().enumerate() {
            assert!((out.limb_length(k) - lengths[k]).abs() < 1e-12);
            let (u, v) = (pose.get(*b), out.get(*b));
            let (pu, pv) = (pose.get(*a), out.get(*a));
            let du: Vec<f64> = (0..3)
                .map(|i| (u[i] - pu[i]) / pose.limb_length(k))
                .collect();
            let dv: Vec<f64> = (0..3).map(|i| (v[i] - pv[i]) / lengths[k]).collect();
            for i in 0..3 {
                assert!((du[i] - dv[i]).abs() < 1e-12, "limb {k} turned");
            }
        }
        // Its own lengths give the pose back; a zero-length limb has no direction.
        let same = pose.with_limb_lengths(&pose.limb_lengths()).unwrap();
        for (p, q) in same
            .points
            .iter()
            .flatten()
            .zip(pose.points.iter().flatten())
        {
            assert!((p - q).abs() < 1e-12);
        }
        let mut flat = pose;
        flat.points[Landmark::Head.index()] = flat.get(Landmark::Neck);
        assert_eq!(flat.with_limb_lengths(&lengths), None);
        let mut bad = lengths;
        bad[3] = f64::NAN;
        assert_eq!(pose.with_limb_lengths(&bad), None);
    }

    #[test]
    fn mean_limb_lengths_averages_each_limb() {
        let pose = spread_pose();
        let twice = Pose3::new(pose.points.map(|p| p.map(|c| 2.0 * c)));
        let mean = mean_limb_lengths(&[pose, twice]).unwrap();
        for (k, m) in mean.iter().enumerate() {
            assert!((m - 1.5 * pose.limb_length(k)).abs() < 1e-12);
        }
        assert_eq!(mean_limb_lengths(&[]), None);
    }

    #[test]
    fn within_safe_range_rescales_only_extreme_poses_and_exactly() {
        let pose = Pose2::new(std::array::from_fn(|i| {
            [i as f64 * 3.5 - 20.0, 7.25 * i as f64]
        }));
        assert_eq!(pose.within_safe_range(), (pose, 1.0));
        for k in [1e154, 1e-200, 1e300] {
            let big = Pose2::new(pose.points.map(|p| [p[0] * k, p[1] * k]));
            let (scaled, f) = big.within_safe_range();
            assert_eq!(f.log2().fract(), 0.0, "{k:e}: a power of two");
            let extent = scaled
                .points
                .iter()
                .flatten()
                .fold(0.0_f64, |m, c| m.max(c.abs()));
            assert!((1.0..2.0).contains(&extent), "{k:e}: extent {extent}");
            for (a, b) in scaled
                .points
                .iter()
                .flatten()
                .zip(big.points.iter().flatten())
            {
                assert_eq!(*a, b * f, "exact");
            }
        }
        let zero = Pose2::new([[0.0; 2]; NUM_LANDMARKS]);
        assert_eq!(zero.within_safe_range().1, 1.0);
        let nan = Pose2::new([[f64::NAN; 2]; NUM_LANDMARKS]);
        assert_eq!(nan.within_safe_range().1, 1.0);
    }

    #[test]
    fn landmark_order_and_names_round_trip() {
        for (i, l) in Landmark::ALL.iter().enumerate() {
            assert_eq!(l.index(), i);
            assert_eq!(Landmark::from_name(l.name()), Some(*l));
            assert_eq!(l.mirrored().mirrored(), *l);
        }
        assert_eq!(Landmark::from_index(15), None);
    }

    #[test]
    fn limbs_form_a_tree_rooted_at_the_pelvis() {
        // Every landmark except the pelvis is the child of exactly one limb.
        let mut parents = [0usize; NUM_LANDMARKS];
        for (_, child) in LIMBS {
            parents[child.index()] += 1;
        }
        assert_eq!(parents[0], 0);
        assert!(parents[1..].iter().all(|&n| n == 1));
        assert_eq!(LIMBS[TORSO_LIMB], (Landmark::Pelvis, Landmark::Neck));
        assert_eq!(LIMBS[NECK_HEAD_LIMB], (Landmark::Neck, Landmark::Head));
        // Parents come before their children (what Landmark::subtree relies on).
        for (k, (parent, _)) in LIMBS.iter().enumerate() {
            assert!(
                *parent == Landmark::Pelvis || LIMBS[..k].iter().any(|(_, c)| c == parent),
                "limb {k}"
            );
        }
    }

    #[test]
    fn parents_and_subtrees_follow_the_limbs() {
        assert_eq!(Landmark::Pelvis.parent(), None);
        for (parent, child) in LIMBS {
            assert_eq!(child.parent(), Some(parent));
        }
        assert_eq!(Landmark::Pelvis.subtree().count(), NUM_LANDMARKS);
        assert_eq!(
            Landmark::LeftHip.subtree().collect::<Vec<_>>(),
            [Landmark::LeftHip, Landmark::LeftKnee, Landmark::LeftAnkle]
        );
        assert_eq!(
            Landmark::RightElbow.subtree().collect::<Vec<_>>(),
            [Landmark::RightElbow, Landmark::RightWrist]
        );
        assert_eq!(Landmark::Neck.subtree().count(), 8);
        assert_eq!(
            Landmark::Head.subtree().collect::<Vec<_>>(),
            [Landmark::Head]
        );
        // Every landmark is in the subtree of each of its ancestors.
        for l in Landmark::ALL {
            let mut a = Some(l);
            while let Some(ancestor) = a {
                assert!(
                    ancestor.subtree().any(|m| m == l),
                    "{l:?} under {ancestor:?}"
                );
                a = ancestor.parent();
            }
        }
    }

    #[test]
    fn mirroring_twice_is_identity_and_keeps_limb_lengths() {
        let mut points = [[0.0; 2]; NUM_LANDMARKS];
        for (i, p) in points.iter_mut().enumerate() {
            *p = [i as f64 * 1.5 - 3.0, (i * i) as f64 * 0.25];
        }
        let pose = Pose2::new(points);
        assert_eq!(pose.mirrored().mirrored(), pose);
        let m = pose.mirrored();
        // The left thigh of the mirror is the right thigh of the original.
        assert!((m.limb_length(1) - pose.limb_length(4)).abs() < 1e-12);
        assert!((m.torso_length() - pose.torso_length()).abs() < 1e-12);
    }
}
