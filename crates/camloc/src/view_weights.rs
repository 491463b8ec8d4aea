//! How much new evidence of its camera each pose of an input brings ([`view_weights`]), for
//! the estimate of the input's camera heights: the frames of a video are nearly the same view
//! again and again, and counted as independent views they had turned a model's slight lean on
//! one clip into certainty (a simulated lab's walk filmed from behind at eye level: 117 frames
//! each 47% upper back under the model's priors made the estimate 83% upper cameras, and every
//! frame came out upper back).

use camloc_skeleton::{Landmark, NUM_LANDMARKS, PartialPose2};

use crate::spread::centroid_and_spread;

/// How far (in pose sizes: the root mean square distance of the torso's landmarks, pelvis,
/// neck, hips and shoulders, from their centroid) the landmarks of two smoothed poses of a
/// track must have moved on average, per pose of the track between them, for the later to
/// count as a whole new view: a walker's limbs move about that far in a quarter of a second.
pub const NEW_VIEW_SIZES: f64 = 0.5;

/// Poses averaged, centred on each, before poses are compared (9): a detector's noise of a few
/// pixels moves a landmark of a 30 fps video farther a frame than its motion does, and
/// averaging keeps the motion while it damps the noise.
const SMOOTHED_POSES: usize = 9;

/// Frames back (10, fewer at the input's start) that a pose is compared with: over a third of
/// a second a motion moves the landmarks well beyond what the averaged noise does.
const COMPARED_BACK: usize = 10;

/// Two consecutive poses are of one video (one person, one camera) when their centroids are
/// less than this many pose sizes apart (0.5) and their sizes within [`SAME_VIDEO_SIZE_RATIO`]
/// of each other; otherwise (unrelated photos, another person) the later is a whole new view.
const SAME_VIDEO_MOVE_SIZES: f64 = 0.5;

/// See [`SAME_VIDEO_MOVE_SIZES`] (1.25).
const SAME_VIDEO_SIZE_RATIO: f64 = 1.25;

/// A pose's landmarks, each present or not.
type Landmarks = [Option<[f64; 2]>; NUM_LANDMARKS];

/// The landmarks a pose is framed by when at least [`FRAMING_MIN`] of them are present: the
/// torso's, which a person half out of the picture or behind a desk keeps (framed by every
/// landmark present, a frame without its legs had changed size by more than a quarter and
/// counted as a new view, and a simulated user's walk with legs missing in 5-15% of its frames
/// was read from the wrong height again).
const FRAMING: [Landmark; 6] = crate::torso_placement::TORSO;

/// See [`FRAMING`] (4).
const FRAMING_MIN: usize = 4;

/// A pose's landmarks relative to the centroid of its framing landmarks ([`FRAMING`], or all
/// present with fewer than [`FRAMING_MIN`] of them), in their size (the root mean square
/// distance of those landmarks from the centroid), with the centroid and the size in the
/// image's units; `None` without two distinct finite framing landmarks.
fn size_frame(pose: &PartialPose2) -> Option<(Landmarks, [f64; 2], f64)> {
    let finite = |p: &&[f64; 2]| p.iter().all(|c| c.is_finite());
    let torso: Vec<[f64; 2]> = FRAMING
        .iter()
        .filter_map(|l| pose.points[l.index()].as_ref())
        .filter(finite)
        .copied()
        .collect();
    let points: Vec<[f64; 2]> = if torso.len() >= FRAMING_MIN {
        torso
    } else {
        pose.points
            .iter()
            .flatten()
            .filter(finite)
            .copied()
            .collect()
    };
    let (centre, size) = centroid_and_spread(&points)?;
    let framed = pose.points.map(|point| {
        point
            .filter(|p| p.iter().all(|c| c.is_finite()))
            .map(|[x, y]| [(x - centre[0]) / size, (y - centre[1]) / size])
    });
    Some((framed, centre, size))
}

/// Per pose of `poses` (in the input's order), the share of a new view it is worth, in
/// [0, 1]. The poses are first followed into tracks (one person in one video): a pose joins
/// the track, of those whose last pose is among the [`TRACK_LOOKBACK`] poses before it, whose
/// last pose is of the same video as it (centroids less than [`SAME_VIDEO_MOVE_SIZES`] apart,
/// sizes within [`SAME_VIDEO_SIZE_RATIO`]; unless it is the pose just before, landmarks less
/// than [`SAME_POSE_SIZES`] apart) and nearest; else (unrelated photos, another
/// person) it starts a track and is worth a whole view, as is a pose that cannot be framed
/// ([`size_frame`]). A track's later pose is worth `min(1, d / (k NEW_VIEW_SIZES))` with `d`
/// the mean move of the landmarks present in both between it and the track's pose `k` =
/// [`COMPARED_BACK`] before it (fewer at the track's start), each averaged with its
/// neighbours in the track ([`SMOOTHED_POSES`]: a video's noise). The weights sum to the
/// input's number of independent views: a few for every second of a video, also when the
/// rows of several people alternate (more when the detector's noise is large against a small
/// torso), and one a pose for unrelated photos.
pub(crate) fn view_weights(poses: &[&PartialPose2]) -> Vec<f64> {
    let framed: Vec<_> = poses.iter().map(|p| size_frame(p)).collect();
    let mut weights = vec![1.0; poses.len()];
    for track in tracks(&framed) {
        let half = SMOOTHED_POSES / 2;
        let smoothed: Vec<Landmarks> = (0..track.len())
            .map(|j| {
                let window = &track[j.saturating_sub(half)..(j + half + 1).min(track.len())];
                std::array::from_fn(|l| {
                    let (mut sum, mut n) = ([0.0, 0.0], 0.0);
                    for point in window.iter().filter_map(|&t| framed[t].as_ref()?.0[l]) {
                        sum = [sum[0] + point[0], sum[1] + point[1]];
                        n += 1.0;
                    }
                    (n > 0.0).then(|| [sum[0] / n, sum[1] / n])
                })
            })
            .collect();
        for (j, &t) in track.iter().enumerate().skip(1) {
            let back = COMPARED_BACK.min(j);
            weights[t] = mean_move(&smoothed[j], &smoothed[j - back])
                .map_or(1.0, |d| (d / (back as f64 * NEW_VIEW_SIZES)).min(1.0));
        }
    }
    weights
}

/// Poses back (16) in which a track's last pose is looked for: the rows of several people
/// written frame by frame alternate, and a detector misses a person in some frames.
const TRACK_LOOKBACK: usize = 16;

/// How far (in pose sizes, the mean move of the framed landmarks) a pose may be from the last
/// pose of a track that is not the pose just before it to join that track (0.5): a few frames
/// of a person's motion, and a detector's noise on a person 135 px tall, are within it; two
/// unrelated photos framed alike seldom are (without it, 50 unrelated photos were worth 13
/// views instead of 38; with 0.3, a far person's noisy rows alternating with another's were
/// worth 3 times as many views as the same rows ordered by person).
const SAME_POSE_SIZES: f64 = 0.5;

/// The tracks of [`view_weights`]: the positions of the framed poses of each, in the input's
/// order; poses that cannot be framed are in none.
fn tracks(framed: &[Option<(Landmarks, [f64; 2], f64)>]) -> Vec<Vec<usize>> {
    let mut tracks: Vec<Vec<usize>> = Vec::new();
    // The tracks whose last pose is among the last TRACK_LOOKBACK.
    let mut open: Vec<usize> = Vec::new();
    for (t, frame) in framed.iter().enumerate() {
        let Some((landmarks, centre, size)) = frame else {
            continue;
        };
        open.retain(|&k| {
            tracks[k]
                .last()
                .is_some_and(|&last| t - last <= TRACK_LOOKBACK)
        });
        let nearest = open
            .iter()
            .filter_map(|&k| {
                let last = *tracks[k].last()?;
                let (landmarks_before, centre_before, size_before) = framed[last].as_ref()?;
                let apart = (centre[0] - centre_before[0]).hypot(centre[1] - centre_before[1])
                    / size.max(*size_before);
                let ratio = size / size_before;
                let same_video = apart < SAME_VIDEO_MOVE_SIZES
                    && (1.0 / SAME_VIDEO_SIZE_RATIO..SAME_VIDEO_SIZE_RATIO).contains(&ratio);
                let joins = same_video
                    && (last + 1 == t
                        || mean_move(landmarks, landmarks_before)
                            .is_some_and(|d| d < SAME_POSE_SIZES));
                joins.then_some((apart, k))
            })
            .min_by(|a, b| a.0.total_cmp(&b.0));
        match nearest {
            Some((_, k)) => tracks[k].push(t),
            None => {
                open.push(tracks.len());
                tracks.push(vec![t]);
            }
        }
    }
    tracks
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
        // the image: a few views a second, not 30, and as few with a detector's noise (up to
        // 8 px on a person 100 px from pelvis to neck).
        let walk: Vec<PartialPose2> = (0..120)
            .map(|t| {
                let s = t as f64 / 30.0;
                pose(0.3 * (std::f64::consts::TAU * s).sin(), 10.0 * t as f64)
            })
            .collect();
        let weights = view_weights(&walk.iter().collect::<Vec<_>>());
        let views: f64 = weights.iter().sum();
        assert!((2.0..30.0).contains(&views), "{views}");
        // Up to 8 px of noise, uncorrelated from frame to frame (a fixed irrational pattern).
        let noise = |t: usize, k: usize| 8.0 * ((t * 15 + k) as f64 * 2.399_963).sin();
        let noisy: Vec<PartialPose2> = walk
            .iter()
            .enumerate()
            .map(|(t, p)| {
                let mut points = p.points;
                for (l, point) in points.iter_mut().enumerate() {
                    *point = point.map(|[x, y]| [x + noise(t, 2 * l), y + noise(t, 2 * l + 1)]);
                }
                PartialPose2 { points }
            })
            .collect();
        let noisy_views: f64 = view_weights(&noisy.iter().collect::<Vec<_>>()).iter().sum();
        assert!(noisy_views < 2.0 * views, "{noisy_views} against {views}");
        // Its legs missing in every tenth frame (behind a desk): about as few views.
        let legless: Vec<PartialPose2> = walk
            .iter()
            .enumerate()
            .map(|(t, p)| {
                let mut p = *p;
                if t % 10 == 5 {
                    for l in [
                        Landmark::LeftKnee,
                        Landmark::RightKnee,
                        Landmark::LeftAnkle,
                        Landmark::RightAnkle,
                    ] {
                        p.points[l.index()] = None;
                    }
                }
                p
            })
            .collect();
        let legless_views: f64 = view_weights(&legless.iter().collect::<Vec<_>>())
            .iter()
            .sum();
        assert!(
            legless_views < 2.0 * views,
            "{legless_views} against {views}"
        );
        // The same walk with a second walker 4 torsos to its right, their rows alternating
        // as a detector writes a video's frames: about as few views as each walk alone, and
        // unchanged with a frame of the second walker missing now and then.
        let second: Vec<PartialPose2> = walk
            .iter()
            .map(|p| PartialPose2 {
                points: p.points.map(|point| point.map(|[x, y]| [x + 400.0, y])),
            })
            .collect();
        let both: Vec<&PartialPose2> = walk
            .iter()
            .zip(&second)
            .enumerate()
            .flat_map(|(t, (a, b))| std::iter::once(a).chain((t % 7 != 3).then_some(b)))
            .collect();
        let both_views: f64 = view_weights(&both).iter().sum();
        assert!(both_views < 3.0 * views, "{both_views} against {views}");
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
        // The same pose again and again is one view, also after a pose without a torso, which
        // is a whole one.
        let still = pose(0.1, 0.0);
        let nobody = PartialPose2::empty();
        let weights = view_weights(&[&still, &still, &still, &nobody, &still]);
        for (w, expected) in weights.iter().zip([1.0, 0.0, 0.0, 1.0, 0.0]) {
            assert!((w - expected).abs() < 1e-12, "{weights:?}");
        }
    }
}
