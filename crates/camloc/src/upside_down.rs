//! Whether the poses of an input stand on their heads in the image: points given with `v` up
//! (a plot's convention) rather than down (image rows), which camloc reads as people upside
//! down and answers for confidently ([`orientation_warning`](crate::orientation_warning) warns).

use camloc_skeleton::{Landmark, PartialPose2};

/// Whether `pose` has its head below both ankles in the image (`v` larger), `None` when its
/// head or an ankle is missing or at exactly `(0, 0)` (a detector's placeholder for a joint it
/// did not find: [`has_origin_placeholders`](crate::has_origin_placeholders)).
pub fn head_below_ankles(pose: &PartialPose2) -> Option<bool> {
    let v = |l: Landmark| {
        pose.points[l.index()]
            .filter(|p| *p != [0.0, 0.0])
            .map(|p| p[1])
    };
    let (head, left, right) = (
        v(Landmark::Head)?,
        v(Landmark::LeftAnkle)?,
        v(Landmark::RightAnkle)?,
    );
    Some(head > left && head > right)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pose_upside_down_is_told() {
        let mut pose = PartialPose2::empty();
        pose.points[Landmark::Head.index()] = Some([0.0, 10.0]);
        assert_eq!(head_below_ankles(&pose), None);
        pose.points[Landmark::LeftAnkle.index()] = Some([0.0, 200.0]);
        pose.points[Landmark::RightAnkle.index()] = Some([5.0, 190.0]);
        assert_eq!(head_below_ankles(&pose), Some(false));
        pose.points[Landmark::Head.index()] = Some([0.0, 250.0]);
        assert_eq!(head_below_ankles(&pose), Some(true));
    }
}
