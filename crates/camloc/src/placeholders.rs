//! Whether an input marks joints a detector did not find by putting them at the image origin
//! (OpenPose and many array exports write `0, 0` for them), which camloc would read as joints
//! seen in the image's corner unless scores or NaN say otherwise.

use camloc_skeleton::PartialPose2;

/// Whether `pose` has a landmark at exactly `(0, 0)` that lies outside the bounding box of its
/// other landmarks (grown by a tenth of its size on each side): a detector's placeholder, far
/// from the body in the image's corner. A pose centred on one of its joints (that joint at the
/// origin, inside the body) has none.
pub fn has_origin_placeholders(pose: &PartialPose2) -> bool {
    // Called for every pose read: no allocation, and one pass when none is at the origin.
    let at_origin = |p: &[f64; 2]| p[0] == 0.0 && p[1] == 0.0;
    if !pose.points.iter().flatten().any(at_origin) {
        return false;
    }
    let (mut lo, mut hi, mut others) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2], 0);
    for p in pose.points.iter().flatten().filter(|p| !at_origin(p)) {
        others += 1;
        for axis in 0..2 {
            lo[axis] = lo[axis].min(p[axis]);
            hi[axis] = hi[axis].max(p[axis]);
        }
    }
    // No other landmark: no body to be outside of.
    others > 0
        && (0..2).any(|axis| {
            let margin = 0.1 * (hi[axis] - lo[axis]);
            0.0 < lo[axis] - margin || 0.0 > hi[axis] + margin
        })
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
    fn joints_at_the_origin_away_from_the_body_are_placeholders() {
        // A body in the middle of an image, with one wrist at the origin.
        let mut pose = PartialPose2::empty();
        for (k, p) in pose.points.iter_mut().enumerate() {
            *p = Some([300.0 + 5.0 * k as f64, 200.0 + 20.0 * k as f64]);
        }
        assert!(!has_origin_placeholders(&pose));
        pose.points[Landmark::LeftWrist.index()] = Some([0.0, 0.0]);
        assert!(has_origin_placeholders(&pose));
        // A pose centred on its pelvis: the origin is inside the body.
        let mut centred = PartialPose2::empty();
        for (k, p) in centred.points.iter_mut().enumerate() {
            *p = Some([-40.0 + 6.0 * k as f64, -150.0 + 20.0 * k as f64]);
        }
        centred.points[Landmark::Pelvis.index()] = Some([0.0, 0.0]);
        assert!(!has_origin_placeholders(&centred));
        // Every landmark at the origin: no body to be outside of.
        let mut nowhere = PartialPose2::empty();
        nowhere.points[Landmark::Head.index()] = Some([0.0, 0.0]);
        nowhere.points[Landmark::Neck.index()] = Some([0.0, 0.0]);
        assert!(!has_origin_placeholders(&nowhere));
        assert!(origin_placeholder_warning(10, 0).is_none());
        assert!(
            origin_placeholder_warning(10, 3)
                .unwrap()
                .starts_with("3 of 10 poses have landmarks at exactly (0, 0)")
        );
    }
}
