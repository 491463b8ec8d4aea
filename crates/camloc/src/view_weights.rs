//! How much new evidence of its camera each pose of an input brings ([`view_weights`]), for
//! the estimate of the input's camera heights: the frames of a video are nearly the same view
//! again and again, and counted as independent views they had turned a model's slight lean on
//! one clip into certainty (a simulated lab's walk filmed from behind at eye level: 117 frames
//! each 47% upper back under the model's priors made the estimate 83% upper cameras, and every
//! frame came out upper back).

use camloc_keypoints::derive_torso;
use camloc_skeleton::{Landmark, NUM_LANDMARKS, PartialPose2};

/// How far (torso lengths, the landmarks' mean move) a pose must differ from the one before it
/// to count as a new view: a walker's limbs move about that far in a quarter of a second;
/// unrelated photos (other people, poses and sides) differ by about as much or more.
pub const NEW_VIEW_TORSOS: f64 = 0.5;

/// Poses averaged, centred on each, before poses are compared (5): a detector's noise of a few
/// pixels moves a landmark of a 30 fps video about as far a frame as its motion does, and
/// averaging keeps the motion while it damps the noise.
const SMOOTHED_POSES: usize = 5;

/// A pose's landmarks, each present or not.
type Landmarks = [Option<[f64; 2]>; NUM_LANDMARKS];

/// A pose's landmarks relative to its pelvis, in torso lengths (the pelvis and neck derived
/// from the hips and shoulders where missing); `None` without a torso of finite, non-zero
/// length.
fn torso_frame(pose: &PartialPose2) -> Option<Landmarks> {
    let mut pose = *pose;
    derive_torso(&mut pose);
    let pelvis = pose.points[Landmark::Pelvis.index()]?;
    let neck = pose.points[Landmark::Neck.index()]?;
    let torso = (neck[0] - pelvis[0]).hypot(neck[1] - pelvis[1]);
    (torso.is_finite() && torso > 0.0).then(|| {
        pose.points.map(|point| {
            point
                .map(|[x, y]| [(x - pelvis[0]) / torso, (y - pelvis[1]) / torso])
                .filter(|p| p.iter().all(|c| c.is_finite()))
        })
    })
}

/// Per pose of `poses` (in the input's order), the share of a new view it is worth, in
/// [0, 1]: the first 1; each other 1 when the mean move of the landmarks present in both
/// between it and the pose before is [`NEW_VIEW_TORSOS`] or more, else
/// `min(1, d / NEW_VIEW_TORSOS)` with `d` the same move between the two poses each averaged
/// with its neighbours ([`SMOOTHED_POSES`]: a video's noise). A pose without a torso, or
/// sharing no landmark with the one before, is worth a whole view. The weights sum to the
/// input's number of independent views: a few for every second of a video, about one a pose
/// for unrelated photos.
pub(crate) fn view_weights(poses: &[&PartialPose2]) -> Vec<f64> {
    let framed: Vec<_> = poses.iter().map(|p| torso_frame(p)).collect();
    let half = SMOOTHED_POSES / 2;
    let smoothed: Vec<Option<Landmarks>> = (0..framed.len())
        .map(|t| {
            framed[t]?;
            let window = &framed[t.saturating_sub(half)..(t + half + 1).min(framed.len())];
            Some(std::array::from_fn(|l| {
                let (mut sum, mut n) = ([0.0, 0.0], 0.0);
                for point in window.iter().flatten().filter_map(|f| f[l]) {
                    sum = [sum[0] + point[0], sum[1] + point[1]];
                    n += 1.0;
                }
                (n > 0.0).then(|| [sum[0] / n, sum[1] / n])
            }))
        })
        .collect();
    (0..framed.len())
        .map(|t| {
            let Some(before) = t.checked_sub(1) else {
                return 1.0;
            };
            let moved = |now: &Option<Landmarks>, before: &Option<Landmarks>| {
                mean_move(now.as_ref()?, before.as_ref()?)
            };
            match moved(&framed[t], &framed[before]) {
                Some(raw) if raw < NEW_VIEW_TORSOS => moved(&smoothed[t], &smoothed[before])
                    .map_or(1.0, |d| (d / NEW_VIEW_TORSOS).min(1.0)),
                _ => 1.0,
            }
        })
        .collect()
}

/// The mean distance between the landmarks present in both `a` and `b`; `None` without any.
fn mean_move(a: &Landmarks, b: &Landmarks) -> Option<f64> {
    let (mut sum, mut n) = (0.0, 0usize);
    for (a, b) in a.iter().zip(b) {
        if let (Some(a), Some(b)) = (a, b) {
            sum += (a[0] - b[0]).hypot(a[1] - b[1]);
            n += 1;
        }
    }
    (n > 0).then(|| sum / n as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A standing pose (pixels, y down) with its legs swung by `swing` torso lengths.
    fn pose(swing: f64, x0: f64) -> PartialPose2 {
        let mut pose = PartialPose2::empty();
        let at = |l: Landmark, x: f64, y: f64| (l.index(), [x0 + 100.0 * x, 500.0 + 100.0 * y]);
        for (i, p) in [
            at(Landmark::Pelvis, 0.0, 0.0),
            at(Landmark::Neck, 0.0, -1.0),
            at(Landmark::Head, 0.0, -1.3),
            at(Landmark::LeftHip, 0.2, 0.0),
            at(Landmark::RightHip, -0.2, 0.0),
            at(Landmark::LeftKnee, 0.2 + swing, 0.9),
            at(Landmark::RightKnee, -0.2 - swing, 0.9),
            at(Landmark::LeftAnkle, 0.2 + 2.0 * swing, 1.8),
            at(Landmark::RightAnkle, -0.2 - 2.0 * swing, 1.8),
            at(Landmark::LeftShoulder, 0.3, -1.0),
            at(Landmark::RightShoulder, -0.3, -1.0),
        ] {
            pose.points[i] = Some(p);
        }
        pose
    }

    #[test]
    fn a_video_counts_as_few_views_and_unrelated_poses_as_one_each() {
        // Four seconds of a walk at 30 fps (legs swinging 0.3 torsos at 1 Hz), walking across
        // the image: a few views a second, not 30.
        let walk: Vec<PartialPose2> = (0..120)
            .map(|t| {
                let s = t as f64 / 30.0;
                pose(0.3 * (std::f64::consts::TAU * s).sin(), 40.0 * t as f64)
            })
            .collect();
        let weights = view_weights(&walk.iter().collect::<Vec<_>>());
        let views: f64 = weights.iter().sum();
        assert!((2.0..30.0).contains(&views), "{views}");
        // Unrelated photos: people seen from other sides (hips and shoulders 0.1 to 0.5 torsos
        // wide), legs and arms elsewhere: nearly a view each.
        let photos: Vec<PartialPose2> = (0..120)
            .map(|k| {
                let u = |m: usize| ((k * m) % 17) as f64 / 16.0;
                let mut p = pose(0.8 * u(7) - 0.4, 1000.0 * u(3));
                let width = 0.1 + 0.4 * u(5);
                for (l, side) in [
                    (Landmark::LeftHip, 1.0),
                    (Landmark::RightHip, -1.0),
                    (Landmark::LeftShoulder, 1.0),
                    (Landmark::RightShoulder, -1.0),
                ] {
                    if let Some(point) = &mut p.points[l.index()] {
                        point[0] = 1000.0 * u(3) + 100.0 * side * width;
                    }
                }
                p.points[Landmark::LeftWrist.index()] = Some([100.0 * u(11), 400.0 * u(13)]);
                p.points[Landmark::RightWrist.index()] = Some([100.0 * u(13), 400.0 * u(11)]);
                p
            })
            .collect();
        let views: f64 = view_weights(&photos.iter().collect::<Vec<_>>())
            .iter()
            .sum();
        assert!(views > 90.0, "{views}");
        // The same pose again and again is one view; a pose without a torso is a whole one.
        let still = pose(0.1, 0.0);
        let nobody = PartialPose2::empty();
        let weights = view_weights(&[&still, &still, &still, &nobody, &still]);
        for (w, expected) in weights.iter().zip([1.0, 0.0, 0.0, 1.0, 1.0]) {
            assert!((w - expected).abs() < 1e-12, "{weights:?}");
        }
    }
}
