//! Whether the poses of an input stand on their heads in the image: points given with `v` up
//! (a plot's convention) rather than down (image rows), which camloc reads as people upside
//! down and answers for confidently.

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

/// The warning for an input of which `upside_down` of the `checked` poses that have a head
/// and both ankles have the head below both ([`head_below_ankles`]), when that is most of
/// them; `None` otherwise.
pub fn upside_down_warning(checked: u64, upside_down: u64) -> Option<String> {
    (2 * upside_down > checked).then(|| {
        format!(
            "{upside_down} of {checked} poses have the head below both ankles: camloc takes \
             image coordinates with v down (image rows); flip v if the input's v points up, \
             but if the camera was upside down (the image turned, v down) turn the keypoints \
             180 deg about the image centre instead: flipping would mirror the people, front \
             for back (people on their hands are seen as they are)"
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pose_upside_down_is_told_and_most_of_an_input_warned_of() {
        let mut pose = PartialPose2::empty();
        pose.points[Landmark::Head.index()] = Some([0.0, 10.0]);
        assert_eq!(head_below_ankles(&pose), None);
        pose.points[Landmark::LeftAnkle.index()] = Some([0.0, 200.0]);
        pose.points[Landmark::RightAnkle.index()] = Some([5.0, 190.0]);
        assert_eq!(head_below_ankles(&pose), Some(false));
        pose.points[Landmark::Head.index()] = Some([0.0, 250.0]);
        assert_eq!(head_below_ankles(&pose), Some(true));
        assert!(upside_down_warning(10, 5).is_none());
        assert!(
            upside_down_warning(10, 6)
                .unwrap()
                .starts_with("6 of 10 poses")
        );
    }
}
