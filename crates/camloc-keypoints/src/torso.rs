//! The torso derivation rule of docs/conventions.md section 3: a missing pelvis or neck is the
//! midpoint of the hips or shoulders.

use camloc_skeleton::{Landmark, PartialPose2};

/// The derivation rule: (derived landmark, its two sources whose midpoint it becomes).
const TORSO_RULES: [(Landmark, Landmark, Landmark); 2] = [
    (Landmark::Pelvis, Landmark::LeftHip, Landmark::RightHip),
    (
        Landmark::Neck,
        Landmark::LeftShoulder,
        Landmark::RightShoulder,
    ),
];

/// Fills a missing pelvis with the midpoint of the hips, and a missing neck with the midpoint of
/// the shoulders, when both are present (docs/conventions.md section 3). Returns the landmarks it
/// filled.
///
/// Landmarks already present are never changed.
pub fn derive_torso(pose: &mut PartialPose2) -> Vec<Landmark> {
    let mut filled = Vec::new();
    for (target, a, b) in TORSO_RULES {
        if pose.points[target.index()].is_some() {
            continue;
        }
        if let (Some(p), Some(q)) = (pose.points[a.index()], pose.points[b.index()]) {
            // Halve first: the midpoint of two finite coordinates stays finite.
            pose.points[target.index()] = Some([0.5 * p[0] + 0.5 * q[0], 0.5 * p[1] + 0.5 * q[1]]);
            filled.push(target);
        }
    }
    filled
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A pose with only `points`.
    pub(crate) fn with(points: &[(Landmark, [f64; 2])]) -> PartialPose2 {
        let mut pose = PartialPose2::empty();
        for &(l, p) in points {
            pose.points[l.index()] = Some(p);
        }
        pose
    }

    #[test]
    fn derives_pelvis_and_neck_as_midpoints_only_when_missing() {
        let mut pose = with(&[
            (Landmark::LeftHip, [10.0, 100.0]),
            (Landmark::RightHip, [30.0, 104.0]),
            (Landmark::LeftShoulder, [0.0, 20.0]),
            (Landmark::RightShoulder, [40.0, 24.0]),
        ]);
        assert_eq!(
            derive_torso(&mut pose),
            vec![Landmark::Pelvis, Landmark::Neck]
        );
        assert_eq!(pose.points[Landmark::Pelvis.index()], Some([20.0, 102.0]));
        assert_eq!(pose.points[Landmark::Neck.index()], Some([20.0, 22.0]));
        // A second pass has nothing left to do and changes nothing.
        let before = pose;
        assert!(derive_torso(&mut pose).is_empty());
        assert_eq!(pose, before);
    }

    #[test]
    fn does_not_derive_from_one_side_or_overwrite() {
        let mut pose = with(&[
            (Landmark::LeftHip, [10.0, 100.0]),
            (Landmark::Neck, [5.0, 5.0]),
            (Landmark::LeftShoulder, [0.0, 20.0]),
            (Landmark::RightShoulder, [40.0, 24.0]),
        ]);
        assert!(derive_torso(&mut pose).is_empty());
        assert_eq!(pose.points[Landmark::Pelvis.index()], None);
        assert_eq!(pose.points[Landmark::Neck.index()], Some([5.0, 5.0]));
    }

    #[test]
    fn midpoint_of_huge_coordinates_stays_finite() {
        let mut pose = with(&[
            (Landmark::LeftHip, [f64::MAX, -f64::MAX]),
            (Landmark::RightHip, [f64::MAX, -f64::MAX]),
        ]);
        derive_torso(&mut pose);
        assert_eq!(pose.points[0], Some([f64::MAX, -f64::MAX]));
    }
}
