//! Frame selection by pose: keep a frame only when its canonical pose differs enough from
//! every frame already kept for its clip.
//!
//! Distance between two canonical poses (pelvis at the origin, facing -x, metres): the largest
//! distance between corresponding landmarks (the maximum per-joint distance), in millimetres.
//! A frame is kept when that distance to *every* kept frame of the clip exceeds the threshold,
//! so a clip that holds still or repeats a cycle (walking, running) contributes each distinct
//! pose once, whatever its length or frame rate.

use camloc_skeleton::Pose3;

/// Default threshold of [`select_by_pose`] and `cargo xtask gen-dataset`: 100 mm of maximum
/// per-joint distance. On the CMU data of `../shared/data` it keeps 14,087 of 134,709 frames
/// (50 mm keeps 32,312 and 150 mm 7,583; `cargo xtask gen-dataset --min-pose-distance MM`
/// prints the count), and the motion categories come out far more even than by stride, where
/// long walking clips at 120 fps dominated.
pub const DEFAULT_MIN_POSE_DISTANCE_MM: f64 = 100.0;

/// The maximum per-landmark Euclidean distance between `a` and `b`, in millimetres (poses in
/// metres).
pub fn max_joint_distance_mm(a: &Pose3, b: &Pose3) -> f64 {
    a.points
        .iter()
        .zip(&b.points)
        .map(|(p, q)| {
            let d2: f64 = (0..3).map(|k| (p[k] - q[k]).powi(2)).sum();
            d2.sqrt()
        })
        .fold(0.0, f64::max)
        * 1000.0
}

/// Whether some landmark of `a` and `b` lies more than `threshold_m` (metres) apart; stops at
/// the first such landmark.
fn differs(a: &Pose3, b: &Pose3, threshold_m2: f64) -> bool {
    a.points.iter().zip(&b.points).any(|(p, q)| {
        let d2: f64 = (0..3).map(|k| (p[k] - q[k]).powi(2)).sum();
        d2 > threshold_m2
    })
}

/// The indices (into `poses`, in order) of the frames kept when each is compared with the
/// frames kept before it: a frame is kept when its maximum per-joint distance to every kept
/// frame is more than `min_distance_mm`. The first frame is always kept (when there is one).
/// `min_distance_mm <= 0` keeps every frame.
///
/// Cost: at most one comparison per (frame, kept frame) pair, each stopping at the first
/// landmark that is farther than the threshold; kept frames are tried newest first, as the
/// newest is the likeliest near-duplicate.
pub fn select_by_pose(poses: &[&Pose3], min_distance_mm: f64) -> Vec<usize> {
    if !(min_distance_mm > 0.0) {
        return (0..poses.len()).collect();
    }
    let threshold_m2 = (min_distance_mm / 1000.0).powi(2);
    let mut kept: Vec<usize> = Vec::new();
    for (i, pose) in poses.iter().enumerate() {
        if kept
            .iter()
            .rev()
            .all(|&k| differs(pose, poses[k], threshold_m2))
        {
            kept.push(i);
        }
    }
    kept
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn pose(shift: f64) -> Pose3 {
        let mut p = Pose3::new([[0.0; 3]; 15]);
        for (i, q) in p.points.iter_mut().enumerate() {
            *q = [0.01 * i as f64, shift, 0.0];
        }
        p.points[11][0] += shift;
        p
    }

    #[test]
    fn repeats_are_dropped_and_far_poses_kept() {
        // A cycle 0, 10, ..., 90 mm repeated 3 times.
        let poses: Vec<Pose3> = (0..30).map(|i| pose(0.01 * (i % 10) as f64)).collect();
        let refs: Vec<&Pose3> = poses.iter().collect();
        // The wrist moves sqrt(2) * shift: 10 mm steps are 14.1 mm apart.
        let kept = select_by_pose(&refs, 20.0);
        assert_eq!(kept, vec![0, 2, 4, 6, 8]);
        assert_eq!(select_by_pose(&refs, 0.0).len(), 30);
        assert!(select_by_pose(&[], 20.0).is_empty());
        assert!(
            (max_joint_distance_mm(&pose(0.0), &pose(0.01)) - 1000.0 * 0.01 * 2f64.sqrt()).abs()
                < 1e-9
        );
    }

    proptest! {
        #[test]
        fn kept_frames_are_pairwise_far_and_dropped_ones_near(
            shifts in proptest::collection::vec(-0.5f64..0.5, 1..60),
            threshold in 1.0f64..200.0,
        ) {
            let poses: Vec<Pose3> = shifts.iter().map(|&s| pose(s)).collect();
            let refs: Vec<&Pose3> = poses.iter().collect();
            let kept = select_by_pose(&refs, threshold);
            prop_assert_eq!(kept[0], 0);
            for (a, &i) in kept.iter().enumerate() {
                for &j in &kept[..a] {
                    prop_assert!(max_joint_distance_mm(&poses[i], &poses[j]) > threshold);
                }
            }
            for i in (0..poses.len()).filter(|i| !kept.contains(i)) {
                prop_assert!(kept.iter().filter(|&&k| k < i)
                    .any(|&k| max_joint_distance_mm(&poses[i], &poses[k]) <= threshold));
            }
        }
    }
}
