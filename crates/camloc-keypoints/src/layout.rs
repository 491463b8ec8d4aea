//! Joint layouts of keypoint arrays and detector outputs, and their mapping to camloc's 15
//! landmarks (docs/keypoints.md lists every table).

use std::fmt;
use std::str::FromStr;

use camloc_skeleton::{Landmark, PartialPose2};

use crate::ReadOptions;

/// What one joint of a layout becomes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Role {
    /// Read as this landmark.
    To(Landmark),
    /// A face point (nose, eyes, ears): the head is the mean of the present ones (derived).
    Face,
    /// Not used by camloc (toes, hands, spine, the crown when a better head point exists...).
    Unused,
}

/// One joint of a layout: its name and what it becomes.
pub(crate) type Joint = (&'static str, Role);

use Landmark as L;
use Role::{Face, To, Unused};

/// COCO-17 (COCO keypoints, MMPose's default): face points give the head.
pub(crate) const COCO17: [Joint; 17] = [
    ("nose", Face),
    ("left_eye", Face),
    ("right_eye", Face),
    ("left_ear", Face),
    ("right_ear", Face),
    ("left_shoulder", To(L::LeftShoulder)),
    ("right_shoulder", To(L::RightShoulder)),
    ("left_elbow", To(L::LeftElbow)),
    ("right_elbow", To(L::RightElbow)),
    ("left_wrist", To(L::LeftWrist)),
    ("right_wrist", To(L::RightWrist)),
    ("left_hip", To(L::LeftHip)),
    ("right_hip", To(L::RightHip)),
    ("left_knee", To(L::LeftKnee)),
    ("right_knee", To(L::RightKnee)),
    ("left_ankle", To(L::LeftAnkle)),
    ("right_ankle", To(L::RightAnkle)),
];

/// Human3.6M's 17 joints (the order of VideoPose3D and most 2D-to-3D lifting code).
const H36M17: [Joint; 17] = [
    ("pelvis", To(L::Pelvis)),
    ("right_hip", To(L::RightHip)),
    ("right_knee", To(L::RightKnee)),
    ("right_ankle", To(L::RightAnkle)),
    ("left_hip", To(L::LeftHip)),
    ("left_knee", To(L::LeftKnee)),
    ("left_ankle", To(L::LeftAnkle)),
    ("spine", Unused),
    ("thorax", To(L::Neck)),
    ("neck_nose", To(L::Head)),
    ("head_top", Unused),
    ("left_shoulder", To(L::LeftShoulder)),
    ("left_elbow", To(L::LeftElbow)),
    ("left_wrist", To(L::LeftWrist)),
    ("right_shoulder", To(L::RightShoulder)),
    ("right_elbow", To(L::RightElbow)),
    ("right_wrist", To(L::RightWrist)),
];

/// OpenPose BODY_25.
const BODY25: [Joint; 25] = [
    ("nose", Face),
    ("neck", To(L::Neck)),
    ("right_shoulder", To(L::RightShoulder)),
    ("right_elbow", To(L::RightElbow)),
    ("right_wrist", To(L::RightWrist)),
    ("left_shoulder", To(L::LeftShoulder)),
    ("left_elbow", To(L::LeftElbow)),
    ("left_wrist", To(L::LeftWrist)),
    ("mid_hip", To(L::Pelvis)),
    ("right_hip", To(L::RightHip)),
    ("right_knee", To(L::RightKnee)),
    ("right_ankle", To(L::RightAnkle)),
    ("left_hip", To(L::LeftHip)),
    ("left_knee", To(L::LeftKnee)),
    ("left_ankle", To(L::LeftAnkle)),
    ("right_eye", Face),
    ("left_eye", Face),
    ("right_ear", Face),
    ("left_ear", Face),
    ("left_big_toe", Unused),
    ("left_small_toe", Unused),
    ("left_heel", Unused),
    ("right_big_toe", Unused),
    ("right_small_toe", Unused),
    ("right_heel", Unused),
];

/// OpenPose's COCO-18 model (not an array layout: OpenPose JSON only).
pub(crate) const COCO18: [Joint; 18] = [
    ("nose", Face),
    ("neck", To(L::Neck)),
    ("right_shoulder", To(L::RightShoulder)),
    ("right_elbow", To(L::RightElbow)),
    ("right_wrist", To(L::RightWrist)),
    ("left_shoulder", To(L::LeftShoulder)),
    ("left_elbow", To(L::LeftElbow)),
    ("left_wrist", To(L::LeftWrist)),
    ("right_hip", To(L::RightHip)),
    ("right_knee", To(L::RightKnee)),
    ("right_ankle", To(L::RightAnkle)),
    ("left_hip", To(L::LeftHip)),
    ("left_knee", To(L::LeftKnee)),
    ("left_ankle", To(L::LeftAnkle)),
    ("right_eye", Face),
    ("left_eye", Face),
    ("right_ear", Face),
    ("left_ear", Face),
];

/// MPII's 16 joints: `upper_neck` is camloc's head (the upper end of the neck), `thorax` its neck.
pub(crate) const MPII16: [Joint; 16] = [
    ("right_ankle", To(L::RightAnkle)),
    ("right_knee", To(L::RightKnee)),
    ("right_hip", To(L::RightHip)),
    ("left_hip", To(L::LeftHip)),
    ("left_knee", To(L::LeftKnee)),
    ("left_ankle", To(L::LeftAnkle)),
    ("pelvis", To(L::Pelvis)),
    ("thorax", To(L::Neck)),
    ("upper_neck", To(L::Head)),
    ("head_top", Unused),
    ("right_wrist", To(L::RightWrist)),
    ("right_elbow", To(L::RightElbow)),
    ("right_shoulder", To(L::RightShoulder)),
    ("left_shoulder", To(L::LeftShoulder)),
    ("left_elbow", To(L::LeftElbow)),
    ("left_wrist", To(L::LeftWrist)),
];

/// LSP's 14 joints in the order of the dataset's `joints.mat` (`head_top` is the head, as in the
/// LSP CSV reader).
const LSP14: [Joint; 14] = [
    ("right_ankle", To(L::RightAnkle)),
    ("right_knee", To(L::RightKnee)),
    ("right_hip", To(L::RightHip)),
    ("left_hip", To(L::LeftHip)),
    ("left_knee", To(L::LeftKnee)),
    ("left_ankle", To(L::LeftAnkle)),
    ("right_wrist", To(L::RightWrist)),
    ("right_elbow", To(L::RightElbow)),
    ("right_shoulder", To(L::RightShoulder)),
    ("left_shoulder", To(L::LeftShoulder)),
    ("left_elbow", To(L::LeftElbow)),
    ("left_wrist", To(L::LeftWrist)),
    ("neck", To(L::Neck)),
    ("head_top", To(L::Head)),
];

/// camloc's own 15 landmarks, in [`Landmark::ALL`] order.
const CAMLOC15: [Joint; 15] = {
    let mut table = [("", Unused); 15];
    let mut i = 0;
    while i < 15 {
        table[i] = (Landmark::ALL[i].name(), To(Landmark::ALL[i]));
        i += 1;
    }
    table
};

/// MediaPipe Pose's 33 landmarks (MediaPipe JSON, and arrays as [`Layout::Mediapipe33`]). The
/// head is the mean of the same face points as COCO's (nose, eyes, ears).
pub(crate) const MEDIAPIPE33: [Joint; 33] = [
    ("nose", Face),
    ("left_eye_inner", Unused),
    ("left_eye", Face),
    ("left_eye_outer", Unused),
    ("right_eye_inner", Unused),
    ("right_eye", Face),
    ("right_eye_outer", Unused),
    ("left_ear", Face),
    ("right_ear", Face),
    ("mouth_left", Unused),
    ("mouth_right", Unused),
    ("left_shoulder", To(L::LeftShoulder)),
    ("right_shoulder", To(L::RightShoulder)),
    ("left_elbow", To(L::LeftElbow)),
    ("right_elbow", To(L::RightElbow)),
    ("left_wrist", To(L::LeftWrist)),
    ("right_wrist", To(L::RightWrist)),
    ("left_pinky", Unused),
    ("right_pinky", Unused),
    ("left_index", Unused),
    ("right_index", Unused),
    ("left_thumb", Unused),
    ("right_thumb", Unused),
    ("left_hip", To(L::LeftHip)),
    ("right_hip", To(L::RightHip)),
    ("left_knee", To(L::LeftKnee)),
    ("right_knee", To(L::RightKnee)),
    ("left_ankle", To(L::LeftAnkle)),
    ("right_ankle", To(L::RightAnkle)),
    ("left_heel", Unused),
    ("right_heel", Unused),
    ("left_foot_index", Unused),
    ("right_foot_index", Unused),
];

/// The joint order of a keypoint array: which joint each row of a (J, 2) pose is. Used by the
/// `.npy` reader, by MMPose predictions, and by callers that hold raw arrays (a Python binding).
///
/// Each layout maps to the 15 landmarks as listed in docs/keypoints.md: joints with a camloc
/// landmark of the same meaning are read as it; face points (COCO-17, BODY_25) are averaged into
/// the head, which is then *derived*; the pelvis and neck, when the layout has none, are derived
/// from the hips and shoulders ([`derive_torso`](crate::derive_torso)).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Layout {
    /// COCO-17: nose, eyes, ears, then shoulders, elbows, wrists, hips, knees, ankles (left
    /// before right). Head = mean of the face points; pelvis and neck derived.
    Coco17,
    /// Human3.6M 17 joints: pelvis, right leg, left leg, spine, thorax, neck/nose, head top, left
    /// arm, right arm. Thorax = neck, neck/nose = head; spine and head top unused.
    H36m17,
    /// OpenPose BODY_25: neck and mid-hip are read as neck and pelvis; head = mean of nose, eyes
    /// and ears; feet unused.
    Body25,
    /// MPII 16 joints: right leg (ankle first), left leg (hip first), pelvis, thorax, upper neck,
    /// head top, right arm (wrist first), left arm (shoulder first). Thorax = neck, upper neck =
    /// head; head top unused.
    Mpii16,
    /// LSP 14 joints (the dataset's `joints.mat` order): right leg, left leg, right arm, left arm,
    /// neck, head top (= head); pelvis derived.
    Lsp14,
    /// camloc's 15 landmarks in [`Landmark::ALL`] order (pelvis first).
    Camloc15,
    /// MediaPipe Pose's 33 landmarks (nose, eyes and ears with their inner and outer corners,
    /// mouth, shoulders, elbows, wrists, hand points, hips, knees, ankles, heels, foot points):
    /// head = mean of nose, eyes and ears; pelvis and neck derived; hands, feet, eye corners
    /// and mouth unused. In pixels: MediaPipe's coordinates times the image's width and height.
    Mediapipe33,
}

impl Layout {
    /// All layouts.
    pub const ALL: [Layout; 7] = [
        Layout::Coco17,
        Layout::H36m17,
        Layout::Body25,
        Layout::Mpii16,
        Layout::Lsp14,
        Layout::Camloc15,
        Layout::Mediapipe33,
    ];

    /// The names of [`Layout::ALL`], comma-separated (for messages and help texts).
    pub const NAMES: &'static str = "coco17, h36m17, body25, mpii16, lsp14, camloc15, mediapipe33";

    /// Short lower-case name (`coco17`, `h36m17`, `body25`, `mpii16`, `lsp14`, `camloc15`,
    /// `mediapipe33`), as accepted by [`str::parse`].
    pub const fn name(self) -> &'static str {
        match self {
            Layout::Coco17 => "coco17",
            Layout::H36m17 => "h36m17",
            Layout::Body25 => "body25",
            Layout::Mpii16 => "mpii16",
            Layout::Lsp14 => "lsp14",
            Layout::Camloc15 => "camloc15",
            Layout::Mediapipe33 => "mediapipe33",
        }
    }

    /// The joint table.
    pub(crate) const fn joints(self) -> &'static [Joint] {
        match self {
            Layout::Coco17 => &COCO17,
            Layout::H36m17 => &H36M17,
            Layout::Body25 => &BODY25,
            Layout::Mpii16 => &MPII16,
            Layout::Lsp14 => &LSP14,
            Layout::Camloc15 => &CAMLOC15,
            Layout::Mediapipe33 => &MEDIAPIPE33,
        }
    }

    /// Number of joints J of one pose in this layout.
    pub const fn joint_count(self) -> usize {
        self.joints().len()
    }

    /// The name of joint `joint` (0-based), e.g. `Layout::Mpii16.joint_name(7) == Some("thorax")`.
    pub fn joint_name(self, joint: usize) -> Option<&'static str> {
        self.joints().get(joint).map(|(name, _)| *name)
    }

    /// The landmark joint `joint` is read as, or `None` for a face point (averaged into the
    /// derived head) or a joint camloc does not use.
    pub fn joint_landmark(self, joint: usize) -> Option<Landmark> {
        match self.joints().get(joint)?.1 {
            To(landmark) => Some(landmark),
            Face | Unused => None,
        }
    }

    /// The layouts with `joints` joints per pose (two for 17: COCO-17 and Human3.6M).
    pub fn with_joint_count(joints: usize) -> Vec<Layout> {
        Layout::ALL
            .into_iter()
            .filter(|l| l.joint_count() == joints)
            .collect()
    }
}

impl fmt::Display for Layout {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A layout name that is not one of [`Layout::NAMES`].
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "unknown layout \"{}\" (expected one of: {})",
    crate::error::clip(.0),
    Layout::NAMES
)]
pub struct UnknownLayoutName(pub String);

impl FromStr for Layout {
    type Err = UnknownLayoutName;

    /// Parses a name of [`Layout::name`], ignoring ASCII case.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Layout::ALL
            .into_iter()
            .find(|l| l.name().eq_ignore_ascii_case(s.trim()))
            .ok_or_else(|| UnknownLayoutName(s.to_owned()))
    }
}

/// The layout of poses with `joints` joints: `given` when set (the count must match), else
/// `default_17` for 17 joints, else the one layout with that count. The error says what was
/// expected.
pub(crate) fn resolve_layout(
    given: Option<Layout>,
    joints: usize,
    default_17: Option<Layout>,
) -> Result<Layout, String> {
    if let Some(layout) = given {
        return if layout.joint_count() == joints {
            Ok(layout)
        } else {
            Err(format!("layout {layout} has {}", layout.joint_count()))
        };
    }
    let candidates = Layout::with_joint_count(joints);
    match (candidates.as_slice(), default_17) {
        ([layout], _) => Ok(*layout),
        ([_, _], Some(layout)) => Ok(layout),
        ([_, _], None) => Err(
            "that can be coco17 or h36m17: name the layout (--layout; Python layout=; Rust ReadOptions::layout)"
                .to_owned(),
        ),
        _ => Err(format!(
            "no layout has {joints} (layouts: {})",
            Layout::ALL
                .map(|l| format!("{l} {}", l.joint_count()))
                .join(", ")
        )),
    }
}

/// `true` when a joint with this score is kept: scores of 0 (or below) mean "not detected" or
/// "not labelled" in every format, and [`ReadOptions::min_score`] drops weaker ones.
pub(crate) fn keeps(score: f64, options: &ReadOptions) -> bool {
    score > 0.0 && score >= options.min_score
}

/// Maps the joints of one pose, in `table` order (`None` where missing), to the landmarks.
/// Returns the pose and the landmarks computed from several joints (the head from face points).
/// Extra joints beyond the table are ignored; callers check the count.
pub(crate) fn map_joints(
    table: &[Joint],
    joints: impl IntoIterator<Item = Option<[f64; 2]>>,
) -> (PartialPose2, Vec<Landmark>) {
    let mut pose = PartialPose2::empty();
    let mut face = [[0.0; 2]; 5];
    let mut faces = 0;
    for ((_, role), point) in table.iter().zip(joints) {
        let Some(point) = point else { continue };
        match role {
            To(landmark) => pose.points[landmark.index()] = Some(point),
            Face if faces < face.len() => {
                face[faces] = point;
                faces += 1;
            }
            Face | Unused => {}
        }
    }
    let mut derived = Vec::new();
    if faces > 0 {
        // Mean of the present face points; dividing first keeps the sum finite.
        let n = faces as f64;
        let head = face[..faces]
            .iter()
            .fold([0.0, 0.0], |m, p| [m[0] + p[0] / n, m[1] + p[1] / n]);
        pose.points[Landmark::Head.index()] = Some(head);
        derived.push(Landmark::Head);
    }
    (pose, derived)
}

/// A pose mapped to the 15 landmarks, with what was derived rather than read.
#[derive(Clone, Debug, PartialEq)]
pub struct MappedPose {
    /// The landmarks, in the array's units; `None` where missing.
    pub pose: PartialPose2,
    /// Landmarks computed from other joints (head from face points, pelvis and neck from hips
    /// and shoulders when [`ReadOptions::derive_torso`]), in landmark order.
    pub derived: Vec<Landmark>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_layout_maps_each_landmark_at_most_once_and_names_are_unique() {
        for layout in Layout::ALL.iter().map(|l| l.joints()).chain([&COCO18[..]]) {
            for l in Landmark::ALL {
                let n = layout.iter().filter(|(_, r)| *r == To(l)).count();
                assert!(n <= 1, "{l:?}");
            }
            for (i, (name, _)) in layout.iter().enumerate() {
                assert!(!layout[..i].iter().any(|(n, _)| n == name), "{name}");
            }
            assert!(layout.len() <= 33);
        }
        // A named joint that is a camloc landmark maps to it (no left/right swaps).
        for layout in Layout::ALL {
            for j in 0..layout.joint_count() {
                let name = layout.joint_name(j).unwrap();
                if let (Some(named), Some(l)) =
                    (Landmark::from_name(name), layout.joint_landmark(j))
                {
                    assert_eq!(named, l, "{layout} {name}");
                }
            }
        }
    }

    #[test]
    fn names_round_trip_and_joint_counts_identify_all_but_17() {
        for l in Layout::ALL {
            assert_eq!(l.name().to_uppercase().parse::<Layout>(), Ok(l));
            let same = Layout::with_joint_count(l.joint_count());
            assert_eq!(same.len(), if l.joint_count() == 17 { 2 } else { 1 });
        }
        let e = "openpose".parse::<Layout>().unwrap_err();
        assert!(e.to_string().contains("coco17, h36m17"), "{e}");
    }
}
