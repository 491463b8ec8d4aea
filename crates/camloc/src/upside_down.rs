//! Whether the poses of an input stand on their heads in the image: points given with `v` up
//! (a plot's convention) rather than down (image rows), which camloc reads as people upside
//! down and answers for confidently ([`orientation_warning`](crate::orientation_warning) warns).

use camloc_skeleton::{Landmark, PartialPose2};

/// Whether `pose` stands on its head in the image: the head below both ankles (`v` larger),
/// by at least half its distance from the ankles' midpoint (the body within 60 deg of upside
/// down; a person lying across the image, head a little lower than the feet, is not: a
/// simulated user's person lying on their back had been warned of in every frame). `None`
/// when its head or an ankle is missing or at exactly `(0, 0)` (a detector's placeholder for
/// a joint it did not find: [`has_origin_placeholders`](crate::has_origin_placeholders)).
pub fn head_below_ankles(pose: &PartialPose2) -> Option<bool> {
    let point = |l: Landmark| pose.points[l.index()].filter(|p| *p != [0.0, 0.0]);
    let v = |l: Landmark| point(l).map(|p| p[1]);
    let x = |l: Landmark| point(l).map(|p| p[0]);
    let (head, left, right) = (
        v(Landmark::Head)?,
        v(Landmark::LeftAnkle)?,
        v(Landmark::RightAnkle)?,
    );
    let head_x = x(Landmark::Head)?;
    let (left_x, right_x) = (x(Landmark::LeftAnkle)?, x(Landmark::RightAnkle)?);
    let ankles = [(left_x + right_x) / 2.0, (left + right) / 2.0];
    let reach = (head_x - ankles[0]).hypot(head - ankles[1]);
    Some(head - left.max(right) >= 0.5 * reach && reach > 0.0)
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
        // Lying across the image, the head a little lower than the feet: not upside down.
        pose.points[Landmark::Head.index()] = Some([300.0, 230.0]);
        assert_eq!(head_below_ankles(&pose), Some(false));
    }
}
