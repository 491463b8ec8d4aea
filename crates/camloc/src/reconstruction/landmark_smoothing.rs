//! A person's 2D landmarks smoothed over the frames of a sequence before it is reconstructed
//! ([`smooth_landmarks`]): a detector's noise, independent from frame to frame, had passed
//! into the 3D and the animation as limb jitter (a simulated user's walk with 3 px of noise:
//! joints accelerating 20.6 m/s^2 on average where the motion's own were 2.6).

use camloc_reconstruct::FrameRate;
use camloc_skeleton::{NUM_LANDMARKS, PartialPose2};

use crate::sequence::{frame_time, run_ids, window_around};
use crate::spread::centroid_and_spread;

/// Half the time window each landmark is smoothed over, in seconds (1/15 s: 2 frames on each
/// side at 30 frames a second, 4 at 60, 1 at 15 and below, which leaves the landmark as it
/// is). Over a simulated user's takes (3 px of noise, 24-60 fps) it halved the joints' mean
/// acceleration or better and left the PA-MPJPE and bone lengths within 1 mm.
pub const LANDMARK_SMOOTHING_S: f64 = 1.0 / 15.0;

/// Most frames on each side of the window (at rates beyond any camera's).
const MOST_HALF_WINDOW: usize = 64;

/// How far (in the pose's size: the root mean square distance of its landmarks from their
/// centroid) a landmark may lie from the quadratic through its neighbours in the window to be
/// smoothed and to smooth them (0.3): a detector's few pixels of noise are a few hundredths
/// of it, a misplaced landmark or another person's pose far more; such a landmark is kept as
/// it is and left out of its neighbours' fits, so that the steps after (landmarks far off the
/// others, landmarks behind the fitted camera) still find it.
const OUTLIER_SIZES: f64 = 0.3;

/// Landmarks of one frame far from their neighbours' fits ([`OUTLIER_SIZES`]) that make the
/// whole frame an outlier (3).
const OUTLIER_FRAME_LANDMARKS: usize = 3;

/// `poses` (one person's frames in time order; `breaks[t]`: frame `t` starts a new run after
/// a gap, as
/// [`reconstruct_sequence_with_breaks`](crate::PoseReconstructor::reconstruct_sequence_with_breaks)
/// takes them) with each landmark replaced by the value at its frame of the quadratic
/// fitted, by least squares, to that landmark in the frames of its run within
/// [`LANDMARK_SMOOTHING_S`] of it where it is present (a Savitzky-Golay filter that takes
/// missing frames): motion up to constant acceleration is kept, noise is damped. A landmark
/// missing stays missing; one farther than 0.3 of the pose's size from the fit of its
/// neighbours (found in two rounds, the second without the first's; all of a frame with 3
/// such landmarks), one with fewer than 3 frames to fit, or whose frames leave the fit
/// undetermined, is kept as it is. `frames[t]`, when given, is frame `t`'s number in the
/// video (frames the person is missing from count as time passing); else the frames are
/// consecutive.
pub fn smooth_landmarks(
    poses: &[PartialPose2],
    frames: Option<&[u64]>,
    breaks: &[bool],
    rate: FrameRate,
) -> Vec<PartialPose2> {
    let half = ((LANDMARK_SMOOTHING_S * rate.hz()).round() as usize).min(MOST_HALF_WINDOW);
    if half < 2 {
        return poses.to_vec();
    }
    let time = |t: usize| frame_time(frames, t);
    let run = run_ids(poses.len(), breaks);
    let sizes: Vec<Option<f64>> = poses.iter().map(size).collect();
    // Each frame's window: the frames of its run within `half` frames of it.
    let windows: Vec<_> = (0..poses.len())
        .map(|t| {
            window_around(poses.len(), t, |k| {
                run[k] == run[t] && (time(k) - time(t)).abs() <= half as f64
            })
        })
        .collect();
    let point = |k: usize, l: usize| poses[k].points[l].filter(|p| p.iter().all(|c| c.is_finite()));
    // The fit at frame `t` of landmark `l` from the frames of its window that `usable`
    // allows.
    let fit = |t: usize, l: usize, usable: &dyn Fn(usize) -> bool| {
        quadratic_at_zero(
            windows[t]
                .clone()
                .filter(|&k| usable(k))
                .filter_map(|k| Some((time(k) - time(t), point(k, l)?))),
        )
    };
    let far = |t: usize, l: usize, fitted: [f64; 2]| match (point(t, l), sizes[t]) {
        (Some(p), Some(size)) => (p[0] - fitted[0]).hypot(p[1] - fitted[1]) > OUTLIER_SIZES * size,
        _ => false,
    };
    let mut outlier = vec![[false; NUM_LANDMARKS]; poses.len()];
    for _ in 0..2 {
        let previous = outlier.clone();
        for (t, flags) in outlier.iter_mut().enumerate() {
            for (l, flag) in flags.iter_mut().enumerate() {
                // Without enough of the others left, the first round's answer stands.
                *flag = match fit(t, l, &|k| k != t && !previous[k][l]) {
                    Some(fitted) => far(t, l, fitted),
                    None => previous[t][l],
                };
            }
            // A frame of several such landmarks is another pose (another person's, a
            // misdetection): all of it is kept as it is.
            if flags.iter().filter(|&&f| f).count() >= OUTLIER_FRAME_LANDMARKS {
                *flags = [true; NUM_LANDMARKS];
            }
        }
    }
    (0..poses.len())
        .map(|t| {
            let mut pose = poses[t];
            for (l, p) in pose.points.iter_mut().enumerate() {
                if point(t, l).is_none() || outlier[t][l] {
                    continue;
                }
                if let Some(fitted) = fit(t, l, &|k| !outlier[k][l]) {
                    *p = Some(fitted);
                }
            }
            pose
        })
        .collect()
}

/// The root mean square distance of the finite landmarks of `pose` from their centroid;
/// `None` without two of them or when they coincide.
fn size(pose: &PartialPose2) -> Option<f64> {
    let points: Vec<[f64; 2]> = pose
        .points
        .iter()
        .flatten()
        .filter(|p| p.iter().all(|c| c.is_finite()))
        .copied()
        .collect();
    centroid_and_spread(&points).map(|(_, spread)| spread)
}

/// The value at 0 of the quadratic in `dt` fitted by least squares to each coordinate of the
/// `(dt, point)` samples; `None` with fewer than 3 samples, a singular fit or a value that is
/// not finite. The points are fitted as offsets from the first (coordinates near the largest
/// floats had overflowed in the sums and been reported as non-finite input).
fn quadratic_at_zero(samples: impl Iterator<Item = (f64, [f64; 2])>) -> Option<[f64; 2]> {
    let mut samples = samples.peekable();
    let origin = samples.peek()?.1;
    // Sums of dt^0..dt^4, and of dt^0..dt^2 times each coordinate.
    let (mut s, mut b, mut n) = ([0.0; 5], [[0.0; 2]; 3], 0);
    for (dt, p) in samples {
        let p = [p[0] - origin[0], p[1] - origin[1]];
        let powers = [1.0, dt, dt * dt, dt * dt * dt, dt * dt * dt * dt];
        for (sum, power) in s.iter_mut().zip(powers) {
            *sum += power;
        }
        for (row, power) in b.iter_mut().zip(powers) {
            for (c, value) in row.iter_mut().zip(p) {
                *c += power * value;
            }
        }
        n += 1;
    }
    // The normal equations [s0 s1 s2; s1 s2 s3; s2 s3 s4] x = b, x[0] by Cramer's rule.
    let det3 = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let normal = [[s[0], s[1], s[2]], [s[1], s[2], s[3]], [s[2], s[3], s[4]]];
    let det = det3(normal);
    if n < 3 || det.abs() <= 1e-9 * s[0] * s[4] * s[2] {
        return None;
    }
    let at = |c: usize| {
        let mut m = normal;
        for (row, rhs) in m.iter_mut().zip(&b) {
            row[0] = rhs[c];
        }
        det3(m) / det
    };
    let fitted = [origin[0] + at(0), origin[1] + at(1)];
    fitted.iter().all(|c| c.is_finite()).then_some(fitted)
}

#[cfg(test)]
mod tests {
    use super::*;
    use camloc_skeleton::Landmark;

    /// A pose with only the head, at `p`.
    fn head_at(p: [f64; 2]) -> PartialPose2 {
        let mut pose = PartialPose2::empty();
        pose.points[Landmark::Head.index()] = Some(p);
        pose
    }

    fn head(pose: &PartialPose2) -> Option<[f64; 2]> {
        pose.points[Landmark::Head.index()]
    }

    #[test]
    fn coordinates_near_the_largest_floats_are_smoothed_as_small_ones() {
        // (Their sums had overflowed: the landmarks came out non-finite.)
        let rate = FrameRate::default();
        let poses: Vec<_> = (0..9)
            .map(|t| head_at([4e307 + 1e305 * f64::from(t), -3e307]))
            .collect();
        for (t, pose) in smooth_landmarks(&poses, None, &[], rate).iter().enumerate() {
            let [x, y] = head(pose).unwrap();
            assert!((x - (4e307 + 1e305 * t as f64)).abs() < 1e292, "{x}");
            assert_eq!(y, -3e307);
        }
    }

    #[test]
    fn accelerating_motion_is_kept_and_noise_damped() {
        let rate = FrameRate::default();
        // Constant acceleration: kept exactly, to the edges.
        let motion = |t: f64| [3.0 + 2.0 * t + 0.5 * t * t, 100.0 - 4.0 * t];
        let poses: Vec<_> = (0..20).map(|t| head_at(motion(f64::from(t)))).collect();
        for (t, pose) in smooth_landmarks(&poses, None, &[], rate).iter().enumerate() {
            let [x, y] = head(pose).unwrap();
            let want = motion(t as f64);
            assert!(
                (x - want[0]).abs() < 1e-6 && (y - want[1]).abs() < 1e-6,
                "{t}"
            );
        }
        // Alternating noise of +-1 px about a still point: damped inside the sequence.
        let noisy: Vec<_> = (0..20)
            .map(|t| head_at([50.0 + if t % 2 == 0 { 1.0 } else { -1.0 }, 50.0]))
            .collect();
        let smoothed = smooth_landmarks(&noisy, None, &[], rate);
        for pose in &smoothed[2..18] {
            assert!(
                (head(pose).unwrap()[0] - 50.0).abs() < 0.5,
                "{:?}",
                head(pose)
            );
        }
    }

    #[test]
    fn frames_the_person_is_missing_from_count_as_time() {
        // Accelerating motion seen at frames 0, 1, 2, 5, 6, 7, 9, 10 (missed in between).
        let numbers: [u64; 8] = [0, 1, 2, 5, 6, 7, 9, 10];
        let motion = |t: f64| [t * t, 3.0 * t];
        let poses: Vec<_> = numbers.iter().map(|&n| head_at(motion(n as f64))).collect();
        let rate = FrameRate::default();
        for (pose, &n) in smooth_landmarks(&poses, Some(&numbers), &[], rate)
            .iter()
            .zip(&numbers)
        {
            let [x, y] = head(pose).unwrap();
            let want = motion(n as f64);
            assert!(
                (x - want[0]).abs() < 1e-6 && (y - want[1]).abs() < 1e-6,
                "{n}"
            );
        }
        // Read as consecutive frames, the same points are bent.
        let consecutive = smooth_landmarks(&poses, None, &[], rate);
        assert!((head(&consecutive[3]).unwrap()[0] - 25.0).abs() > 0.1);
    }

    #[test]
    fn another_pose_is_kept_as_it_is_and_left_out_of_its_neighbours() {
        // A still pose with +-1 px of noise on every landmark, 200 px from its centroid.
        let still = |t: usize| {
            let mut pose = PartialPose2::empty();
            for (l, p) in pose.points.iter_mut().enumerate() {
                let angle = l as f64 * 0.4;
                let noise = if (t + l).is_multiple_of(2) { 1.0 } else { -1.0 };
                *p = Some([
                    500.0 + 200.0 * angle.cos() + noise,
                    500.0 + 200.0 * angle.sin(),
                ]);
            }
            pose
        };
        let mut poses: Vec<_> = (0..15).map(still).collect();
        // Frame 7 another person's pose, 300 px to the side.
        for p in poses[7].points.iter_mut().flatten() {
            p[0] += 300.0;
        }
        let smoothed = smooth_landmarks(&poses, None, &[], FrameRate::default());
        assert_eq!(smoothed[7], poses[7]);
        for t in (0..15).filter(|&t| t != 7) {
            for (a, b) in smoothed[t].points.iter().zip(still(t).points) {
                let (a, b) = (a.unwrap(), b.unwrap());
                // Within the noise of the still pose, never pulled towards frame 7.
                assert!(
                    (a[0] - b[0]).abs() < 2.0 && (a[1] - b[1]).abs() < 1e-9,
                    "{t}: {a:?} {b:?}"
                );
            }
        }
    }

    #[test]
    fn runs_missing_landmarks_and_slow_rates_are_respected() {
        let rate = FrameRate::default();
        // A jump at a break is not smoothed across.
        let mut poses: Vec<_> = (0..10).map(|_| head_at([0.0, 0.0])).collect();
        poses.extend((0..10).map(|_| head_at([100.0, 0.0])));
        let mut breaks = vec![false; 20];
        breaks[10] = true;
        let smoothed = smooth_landmarks(&poses, None, &breaks, rate);
        assert_eq!(head(&smoothed[9]), Some([0.0, 0.0]));
        assert_eq!(head(&smoothed[10]), Some([100.0, 0.0]));
        // A missing landmark stays missing, and the frames around it use the others.
        poses[5] = PartialPose2::empty();
        let smoothed = smooth_landmarks(&poses, None, &breaks, rate);
        assert_eq!(head(&smoothed[5]), None);
        assert_eq!(head(&smoothed[4]), Some([0.0, 0.0]));
        // At 15 frames a second and below the window is one frame a side: nothing changes.
        let noisy: Vec<_> = (0..9).map(|t| head_at([f64::from(t % 2), 0.0])).collect();
        let slow = FrameRate::new(15.0).unwrap();
        assert_eq!(smooth_landmarks(&noisy, None, &[], slow), noisy);
    }
}
