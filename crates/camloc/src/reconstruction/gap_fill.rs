//! Landmarks missing for a moment in a sequence, filled in from the frames around them
//! ([`fill_short_gaps`]): a detector drops a knee or a wrist for a few frames when it passes
//! behind the body; the frames on each side saw it, where a single frame's fill from the pose
//! basis can only guess (a simulated user's walker: the far arm swung 86 deg where the truth's
//! swung 26, an ankle popped 15 cm where it was seen again).

use camloc_reconstruct::FrameRate;
use camloc_skeleton::{LIMBS, PartialPose2};

use crate::sequence::{frame_time, run_ids};

/// Longest time, in seconds, a landmark may be missing in a row (between two frames of its
/// run that have it) to be filled in from those two frames (0.7: 21 frames at 30 frames a
/// second, at most; docs/RESULTS.md). Longer gaps are left to each frame's fill from the
/// pose basis.
pub const GAP_FILL_S: f64 = 0.7;

/// `poses` (one person's frames in time order, as [`smooth_landmarks`](crate::smooth_landmarks)
/// takes them: `frames[t]` frame `t`'s number in the video, else consecutive; `breaks[t]`:
/// frame `t` starts a new run) with each landmark that is missing for at most `longest_s`
/// seconds between two frames of the same run where it is present filled in: its offset from
/// its parent in the skeleton ([`LIMBS`]: the knee's from the hip, the wrist's from the elbow)
/// interpolated linearly in time between those two frames and added to the parent where it is
/// in each missing frame (the parent present, or filled in first). The pelvis (the root), a
/// landmark whose parent is missing in the gap, and a gap at either end of a run are left
/// missing; so is every landmark for a non-positive or non-finite `longest_s`. A non-finite
/// landmark counts as missing.
pub fn fill_short_gaps(
    poses: &[PartialPose2],
    frames: Option<&[u64]>,
    breaks: &[bool],
    rate: FrameRate,
    longest_s: f64,
) -> Vec<PartialPose2> {
    let mut filled: Vec<PartialPose2> = poses.to_vec();
    if !(longest_s.is_finite() && longest_s > 0.0) {
        return filled;
    }
    let time = |t: usize| frame_time(frames, t);
    let longest_frames = longest_s * rate.hz();
    let run = run_ids(poses.len(), breaks);
    let finite = |p: Option<[f64; 2]>| p.filter(|p| p.iter().all(|c| c.is_finite()));
    // Parents before children: `LIMBS` lists each limb after the one that reaches its parent.
    for (parent, child) in LIMBS {
        let (p, c) = (parent.index(), child.index());
        // The last frame of the run so far where both were there, with the child's offset.
        let mut last: Option<(usize, [f64; 2])> = None;
        for t in 0..filled.len() {
            if t > 0 && run[t] != run[t - 1] {
                last = None;
            }
            let (Some(at), Some(from)) = (finite(filled[t].points[c]), finite(filled[t].points[p]))
            else {
                continue;
            };
            let offset = [at[0] - from[0], at[1] - from[1]];
            if let Some((k, before)) = last.filter(|&(k, _)| k + 1 < t) {
                let span = time(t) - time(k);
                let gap = (k + 1..t).all(|g| finite(filled[g].points[p]).is_some());
                if gap && span - 1.0 <= longest_frames && span > 0.0 {
                    for (g, pose) in (k + 1..t).zip(&mut filled[k + 1..t]) {
                        let s = (time(g) - time(k)) / span;
                        let Some(base) = finite(pose.points[p]) else {
                            continue;
                        };
                        let at: [f64; 2] = std::array::from_fn(|a| {
                            base[a] + before[a] + s * (offset[a] - before[a])
                        });
                        // (Coordinates near the largest floats can overflow: left missing.)
                        pose.points[c] = finite(Some(at));
                    }
                }
            }
            last = Some((t, offset));
        }
    }
    filled
}

#[cfg(test)]
mod tests {
    use super::*;
    use camloc_skeleton::Landmark;

    /// A pose with the pelvis at `pelvis` and the left hip and knee `hip` and `knee` from it.
    fn leg(pelvis: [f64; 2], knee: Option<[f64; 2]>) -> PartialPose2 {
        let mut pose = PartialPose2::empty();
        pose.points[Landmark::Pelvis.index()] = Some(pelvis);
        pose.points[Landmark::LeftHip.index()] = Some([pelvis[0] + 10.0, pelvis[1]]);
        pose.points[Landmark::LeftKnee.index()] =
            knee.map(|k| [pelvis[0] + 10.0 + k[0], pelvis[1] + k[1]]);
        pose
    }

    fn knee(pose: &PartialPose2) -> Option<[f64; 2]> {
        pose.points[Landmark::LeftKnee.index()]
    }

    #[test]
    fn a_short_gap_follows_the_parent_and_interpolates_the_offset() {
        let rate = FrameRate::default();
        // The person walks right 5 px a frame; the knee's offset from the hip goes from
        // (0, 40) to (8, 40) over frames 0 to 4, missing in 1 to 3.
        let poses: Vec<PartialPose2> = (0..5)
            .map(|t| {
                let seen = t == 0 || t == 4;
                leg(
                    [5.0 * t as f64, 0.0],
                    seen.then_some([2.0 * t as f64, 40.0]),
                )
            })
            .collect();
        let filled = fill_short_gaps(&poses, None, &[], rate, GAP_FILL_S);
        for (t, pose) in filled.iter().enumerate() {
            let [x, y] = knee(pose).unwrap();
            let want = [5.0 * t as f64 + 10.0 + 2.0 * t as f64, 40.0];
            assert!((x - want[0]).abs() < 1e-12 && (y - want[1]).abs() < 1e-12);
        }
        // The frames given: the same gap over frames 0, 10, 20, 30, 40 of a 30 fps video is
        // 40 frames long, beyond 0.7 s: left missing, as across a break.
        let numbers: Vec<u64> = (0..5).map(|t| 10 * t).collect();
        let far = fill_short_gaps(&poses, Some(&numbers), &[], rate, GAP_FILL_S);
        assert!((1..4).all(|t| knee(&far[t]).is_none()));
        let broken = fill_short_gaps(&poses, None, &[false, false, true], rate, GAP_FILL_S);
        assert!((1..4).all(|t| knee(&broken[t]).is_none()));
        let off = fill_short_gaps(&poses, None, &[], rate, 0.0);
        assert!((1..4).all(|t| knee(&off[t]).is_none()));
    }

    #[test]
    fn gaps_at_the_ends_or_without_the_parent_stay_missing() {
        let rate = FrameRate::default();
        let mut poses: Vec<PartialPose2> = (0..6)
            .map(|t| leg([0.0, 0.0], (t != 0 && t != 5).then_some([0.0, 40.0])))
            .collect();
        // Frame 2 without its knee, hip and pelvis: the hip cannot follow the pelvis (the
        // root is not filled in), nor the knee its hip.
        for l in [Landmark::LeftKnee, Landmark::LeftHip, Landmark::Pelvis] {
            poses[2].points[l.index()] = None;
        }
        let filled = fill_short_gaps(&poses, None, &[], rate, GAP_FILL_S);
        for t in [0, 2, 5] {
            assert_eq!(knee(&filled[t]), None, "frame {t}");
        }
        assert_eq!(filled[2].points[Landmark::LeftHip.index()], None);
        // A NaN knee counts as missing and is filled in.
        let mut poses: Vec<PartialPose2> =
            (0..3).map(|_| leg([0.0, 0.0], Some([0.0, 40.0]))).collect();
        poses[1].points[Landmark::LeftKnee.index()] = Some([f64::NAN, 0.0]);
        let filled = fill_short_gaps(&poses, None, &[], rate, GAP_FILL_S);
        assert_eq!(knee(&filled[1]), Some([10.0, 40.0]));
    }
}
