//! [`pose_from_array`]: one pose given as raw numbers in a [`Layout`], mapped to the 15
//! landmarks, and [`ArrayPoseError`], why it cannot be.

use crate::ReadOptions;
use crate::layout::{Layout, MappedPose, keeps, map_joints};
use crate::layout_check::contradicted;
use crate::torso::derive_torso;

/// Why one pose of a raw array cannot be mapped ([`pose_from_array`]). Joints and channels are
/// 0-based; the `.npy` reader turns these into [`KeypointError`](crate::KeypointError)s that name
/// the file and the element.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ArrayPoseError {
    /// The slice does not hold `J × C` numbers, or C is not 2 or 3.
    #[error(
        "expected {joints} joints × 2 or 3 channels for layout {layout}, got {values} numbers with {channels} channels"
    )]
    Shape {
        /// The layout.
        layout: Layout,
        /// Its joint count.
        joints: usize,
        /// Channels given.
        channels: usize,
        /// Numbers given.
        values: usize,
    },
    /// A coordinate or score is infinite, or a score is NaN.
    #[error("joint {joint}'s {}: {value} is not a finite number", ["x", "y", "score"][(*.channel).min(2)])]
    NonFinite {
        /// Joint index.
        joint: usize,
        /// Channel (0 = x, 1 = y, 2 = score).
        channel: usize,
        /// The value.
        value: f64,
    },
    /// One coordinate is NaN and the other is not.
    #[error(
        "joint {joint}: one coordinate is NaN and the other is not (NaN, NaN marks a missing joint)"
    )]
    HalfMissing {
        /// Joint index.
        joint: usize,
    },
    /// A score outside [0, 1].
    #[error("joint {joint}: score {score} is outside [0, 1]{}", score_hint(*.score, *.separate))]
    ScoreOutOfRange {
        /// Joint index.
        joint: usize,
        /// The score.
        score: f64,
        /// Whether the score came from an array of scores of its own (Python's `scores`), not
        /// from the third channel of the points ([`pose_from_array`] sets `false`).
        separate: bool,
    },
    /// The first five joints of a 17-joint pose contradict the layout
    /// ([`contradicted`](crate::contradicted)).
    #[error("{}", crate::layout_check::mismatch(*.layout, *.likely, *.spread))]
    LayoutMismatch {
        /// The layout given.
        layout: Layout,
        /// The layout the joints look like.
        likely: Layout,
        /// The spread of the first five joints relative to the pose's.
        spread: f64,
    },
}

/// What a score outside [0, 1] most likely is, as a hint starting with `; `: COCO's
/// visibility flags (0, 1, 2), a percentage (2 to 100), else, for the third channel of an
/// `(N, J, 3)` array (not `separate` scores), a third coordinate; or nothing.
pub(crate) fn score_hint(score: f64, separate: bool) -> &'static str {
    if score == 2.0 {
        "; COCO visibility flags (0, 1, 2)? give (v > 0) as the score, or x and y alone"
    } else if (2.0..=100.0).contains(&score) {
        "; scores in percent? divide them by 100"
    } else if separate {
        ""
    } else {
        "; (N, J, 3) keypoint arrays hold x, y, score, not 3D points"
    }
}

/// Maps one pose given as raw numbers to the 15 landmarks: `values` holds J × C numbers in row
/// order (joint by joint), J = `layout.joint_count()`, C = 2 (`x, y`) or 3 (`x, y, score`).
///
/// A joint is missing when both coordinates are NaN (whatever its score: an export that fills
/// an undetected joint with NaN in every channel), or (C = 3) when its score is 0 or below
/// [`ReadOptions::min_score`]. Scores must lie in [0, 1]; infinities, a present joint's NaN
/// score or a single NaN coordinate are errors. The head of COCO-17 and BODY_25 is the mean of the present face
/// points, and pelvis and neck are derived per [`ReadOptions::derive_torso`].
pub fn pose_from_array(
    layout: Layout,
    values: &[f64],
    channels: usize,
    options: &ReadOptions,
) -> Result<MappedPose, ArrayPoseError> {
    let joints = layout.joint_count();
    if !(channels == 2 || channels == 3) || values.len() != joints * channels {
        return Err(ArrayPoseError::Shape {
            layout,
            joints,
            channels,
            values: values.len(),
        });
    }
    // Every joint is checked first, so that mapping (which reads the rows again) cannot fail.
    for (joint, row) in values.chunks_exact(channels).enumerate() {
        if row[0].is_nan() && row[1].is_nan() {
            continue;
        }
        for (channel, &value) in row.iter().enumerate() {
            if value.is_infinite() || (channel == 2 && value.is_nan()) {
                return Err(ArrayPoseError::NonFinite {
                    joint,
                    channel,
                    value,
                });
            }
        }
        match row.get(2) {
            Some(&score) if !(0.0..=1.0).contains(&score) => {
                return Err(ArrayPoseError::ScoreOutOfRange {
                    joint,
                    score,
                    separate: false,
                });
            }
            _ => {}
        }
        if row[0].is_nan() != row[1].is_nan() {
            return Err(ArrayPoseError::HalfMissing { joint });
        }
    }
    let point = |row: &[f64]| {
        let kept = !row[0].is_nan() && row.get(2).is_none_or(|&score| keeps(score, options));
        kept.then_some([row[0], row[1]])
    };
    // Only the 17-joint layouts are checked (on the stack: this runs for every pose), and
    // their points are mapped as checked.
    let (mut pose, mut derived) = if joints == 17 {
        let mut points = [None; 17];
        let mut scores = [1.0; 17];
        for (j, row) in values.chunks_exact(channels).enumerate() {
            points[j] = point(row);
            // (A joint missing by its NaN coordinates may have a NaN score: read as 0.)
            scores[j] = row
                .get(2)
                .map_or(1.0, |&s| if s.is_nan() { 0.0 } else { s });
        }
        let scored = (channels == 3).then_some(&scores[..]);
        if let Some((likely, spread)) = contradicted(layout, &points, scored) {
            return Err(ArrayPoseError::LayoutMismatch {
                layout,
                likely,
                spread,
            });
        }
        map_joints(layout.joints(), points)
    } else {
        map_joints(layout.joints(), values.chunks_exact(channels).map(point))
    };
    if options.derive_torso {
        derived.extend(derive_torso(&mut pose));
        derived.sort_unstable();
    }
    Ok(MappedPose { pose, derived })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_layout_gives_all_15_landmarks_from_a_full_pose() {
        for layout in Layout::ALL {
            // Joints along a line; Human3.6M's first five (pelvis, right leg, left hip) spread
            // as a body's, not clustered as COCO-17's face points.
            let values: Vec<f64> = (0..layout.joint_count())
                .flat_map(|j| {
                    let at = if layout == Layout::H36m17 && j < 5 {
                        4.0 * j as f64
                    } else {
                        j as f64
                    };
                    [at, 2.0 * at]
                })
                .collect();
            let mapped = pose_from_array(layout, &values, 2, &ReadOptions::default()).unwrap();
            assert!(mapped.pose.complete().is_some(), "{layout}");
        }
    }

    #[test]
    fn a_17_joint_pose_whose_first_five_joints_contradict_its_layout_is_refused() {
        let coco: Vec<f64> = (0..17)
            .flat_map(|j| {
                let at = if j < 5 { 0.2 * j as f64 } else { j as f64 };
                [at, 2.0 * at]
            })
            .collect();
        let options = ReadOptions::default();
        assert!(pose_from_array(Layout::Coco17, &coco, 2, &options).is_ok());
        let e = pose_from_array(Layout::H36m17, &coco, 2, &options).unwrap_err();
        assert!(
            matches!(
                e,
                ArrayPoseError::LayoutMismatch {
                    layout: Layout::H36m17,
                    likely: Layout::Coco17,
                    ..
                }
            ),
            "{e:?}"
        );
        assert!(
            e.to_string()
                .contains("the layout is likely coco17, not h36m17"),
            "{e}"
        );
    }

    /// A joint NaN in all three channels (an export's undetected joint) is missing, as NaN, NaN
    /// is, whatever its score; a present joint's NaN score is still an error.
    #[test]
    fn a_joint_nan_in_every_channel_is_missing() {
        let options = ReadOptions::default();
        // The left wrist of each.
        for (layout, wrist) in [(Layout::Camloc15, 11), (Layout::Coco17, 9)] {
            let mut values: Vec<f64> = (0..layout.joint_count())
                .flat_map(|j| [j as f64, 2.0 * j as f64 + 0.3 * (j % 3) as f64, 0.9])
                .collect();
            values[3 * wrist..3 * wrist + 3].fill(f64::NAN);
            let mapped = pose_from_array(layout, &values, 3, &options).unwrap();
            assert_eq!(mapped.pose.points.iter().flatten().count(), 14, "{layout}");
            values[3 * wrist..3 * wrist + 3].copy_from_slice(&[1.0, 2.0, f64::NAN]);
            let e = pose_from_array(layout, &values, 3, &options).unwrap_err();
            assert!(
                matches!(e, ArrayPoseError::NonFinite { joint, channel: 2, .. } if joint == wrist),
                "{e:?}"
            );
        }
    }

    /// A score out of range names its likely cause: COCO's visibility flag 2, a percentage,
    /// else a third coordinate.
    #[test]
    fn a_score_out_of_range_says_what_it_likely_is() {
        let options = ReadOptions::default();
        for (score, cause) in [
            (2.0, "COCO visibility flags (0, 1, 2)?"),
            (90.0, "scores in percent?"),
            (1.5, "not 3D points"),
            (-3.0, "not 3D points"),
            (250.0, "not 3D points"),
        ] {
            let values: Vec<f64> = (0..15)
                .flat_map(|j| [j as f64, 2.0 * j as f64, score])
                .collect();
            let e = pose_from_array(Layout::Camloc15, &values, 3, &options).unwrap_err();
            let message = e.to_string();
            assert!(message.starts_with("joint 0: score "), "{message}");
            assert!(message.contains(cause), "{score}: {message}");
        }
    }
}
