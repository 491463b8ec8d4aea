//! Whether an input marks joints a detector did not find by putting them at the image origin
//! (OpenPose and many array exports write `0, 0` for them), which camloc would read as joints
//! seen in the image's corner unless scores or NaN say otherwise.

use camloc_skeleton::PartialPose2;

/// Whether `pose` has at least two landmarks at exactly `(0, 0)`: one joint there may be real,
/// two are a detector's placeholders.
pub fn has_origin_placeholders(pose: &PartialPose2) -> bool {
    pose.points
        .iter()
        .flatten()
        .filter(|p| p[0] == 0.0 && p[1] == 0.0)
        .nth(1)
        .is_some()
}

/// The warning for an input of which `with_placeholders` of the `checked` poses have
/// landmarks at the image origin ([`has_origin_placeholders`]), when any has; `None`
/// otherwise.
pub fn origin_placeholder_warning(checked: u64, with_placeholders: u64) -> Option<String> {
    (with_placeholders > 0).then(|| {
        format!(
            "{with_placeholders} of {checked} poses have landmarks at exactly (0, 0), where \
             detectors put joints they did not find: they are read as points in the image's \
             corner; give the joints' scores (0 there) or NaN for them"
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use camloc_skeleton::Landmark;

    #[test]
    fn two_joints_at_the_origin_are_placeholders() {
        let mut pose = PartialPose2::empty();
        pose.points[Landmark::Head.index()] = Some([0.0, 0.0]);
        pose.points[Landmark::Neck.index()] = Some([0.0, 5.0]);
        assert!(!has_origin_placeholders(&pose));
        pose.points[Landmark::LeftWrist.index()] = Some([0.0, 0.0]);
        assert!(has_origin_placeholders(&pose));
        assert!(origin_placeholder_warning(10, 0).is_none());
        assert!(
            origin_placeholder_warning(10, 3)
                .unwrap()
                .starts_with("3 of 10 poses have landmarks at exactly (0, 0)")
        );
    }
}
