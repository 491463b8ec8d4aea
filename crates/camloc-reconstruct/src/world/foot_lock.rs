//! Locked feet: within each run of frames where an ankle is planted, the ankle is put at one
//! place (the run's mean) by turning the thigh and shin about the hip ([`lock_feet`]), the
//! knee kept in its plane; the pelvis's path moved by `planted` leaves the feet sliding by a
//! centimetre or two a frame (the legs' steps and the path from the scale disagree), which an
//! animation shows as skating.

use camloc_geometry::Vector3;
use camloc_skeleton::{Landmark, Pose3};

use crate::FrameRate;

/// Frames after (before) a locked run over which the lock's correction fades out (in), so
/// that the foot does not jump when it leaves (lands on) the floor, where no other run of the
/// same foot is within [`BLEND_FRAMES`].
const FADE_FRAMES: usize = 2;
/// The most frames between two locked runs of one foot across which the correction goes
/// from the one run's to the other's in even steps (a step's swing takes 10-15 frames at 30
/// frames a second).
const BLEND_FRAMES: usize = 30;

/// The straightest a lock makes a knee (the angle between thigh and shin, degrees) unless it
/// was straighter: where the foot's place needs more, the foot is left short of it.
const MAX_KNEE_DEG: f64 = 165.0;
/// The most a lock straightens a knee, degrees.
const MAX_KNEE_STRAIGHTEN_DEG: f64 = 5.0;

/// The legs: hip, knee and ankle.
const LEGS: [[Landmark; 3]; 2] = [
    [Landmark::LeftHip, Landmark::LeftKnee, Landmark::LeftAnkle],
    [
        Landmark::RightHip,
        Landmark::RightKnee,
        Landmark::RightAnkle,
    ],
];

/// Moves each planted ankle of `placed` (z-up world, metres, in time order; `None`: a missing
/// frame) to the mean place of its run of consecutive planted frames (`contacts`: the planted
/// ankles, frame and landmark); between two runs the correction goes from the one's to the
/// other's in even steps, and it fades over [`FADE_FRAMES`] frames before the first run,
/// after the last and across gaps longer than [`BLEND_FRAMES`]; the knee is placed so that
/// the thigh and shin keep their lengths, in the plane of the hip, the new ankle and the old
/// knee (an ankle the leg cannot reach, or only by straightening the knee more than
/// [`MAX_KNEE_STRAIGHTEN_DEG`] or beyond [`MAX_KNEE_DEG`], goes as far as it may). The hips
/// and every other landmark stay.
///
/// [`FADE_FRAMES`] and [`BLEND_FRAMES`] are at 30 frames a second, `rate.step()` times as many
/// at `rate`'s faster ones ([`FrameRate`]).
pub(super) fn lock_feet(
    placed: &mut [Option<Pose3>],
    contacts: &[(usize, Landmark)],
    rate: FrameRate,
) {
    let n = placed.len();
    // Counted at 30 frames a second, kept in time at faster rates.
    let (fade_frames, blend_frames) = (FADE_FRAMES * rate.step(), BLEND_FRAMES * rate.step());
    for leg in LEGS {
        let ankle = leg[2];
        let mut planted = vec![false; n];
        for &(t, a) in contacts {
            if a == ankle && t < n && placed[t].is_some() {
                planted[t] = true;
            }
        }
        // The correction of each locked frame, and the runs (first, last frame).
        let mut shift: Vec<Option<[f64; 3]>> = vec![None; n];
        let mut runs: Vec<(usize, usize)> = Vec::new();
        let mut t = 0;
        while t < n {
            if !planted[t] {
                t += 1;
                continue;
            }
            let start = t;
            while t < n && planted[t] {
                t += 1;
            }
            if t - start < 2 {
                continue;
            }
            let places: Vec<[f64; 3]> = (start..t)
                .filter_map(|u| placed[u].map(|p| p.get(ankle)))
                .collect();
            let m = places.len() as f64;
            let target: [f64; 3] =
                std::array::from_fn(|k| places.iter().map(|p| p[k]).sum::<f64>() / m);
            for u in start..t {
                shift[u] = placed[u].map(|p| {
                    let a = p.get(ankle);
                    std::array::from_fn(|k| target[k] - a[k])
                });
            }
            runs.push((start, t - 1));
        }
        // Between two runs at most BLEND_FRAMES apart the correction goes from the one's to
        // the other's in even steps; before the first and after the last, and across longer
        // gaps, it fades out over FADE_FRAMES.
        let fade = |from: usize, to: usize| -> Option<[f64; 3]> {
            let steps = from.abs_diff(to);
            let edge = shift[from]?;
            let weight = 1.0 - steps as f64 / (fade_frames + 1) as f64;
            (weight > 0.0).then(|| edge.map(|c| c * weight))
        };
        let mut between: Vec<Option<[f64; 3]>> = vec![None; n];
        // Each gap: before the first run, between two runs, after the last.
        for w in 0..=runs.len() {
            let before = w.checked_sub(1).map(|v| runs[v].1);
            let after = runs.get(w).map(|r| r.0);
            for u in before.map_or(0, |e| e + 1)..after.unwrap_or(n) {
                if placed[u].is_none() {
                    continue;
                }
                between[u] = match (before, after) {
                    (Some(e), Some(s)) if s - e <= blend_frames => {
                        let (Some(a), Some(b)) = (shift[e], shift[s]) else {
                            continue;
                        };
                        let w = (u - e) as f64 / (s - e) as f64;
                        Some(std::array::from_fn(|k| a[k] + (b[k] - a[k]) * w))
                    }
                    (before, after) => {
                        let (x, y) = (
                            before.and_then(|e| fade(e, u)),
                            after.and_then(|s| fade(s, u)),
                        );
                        match (x, y) {
                            (Some(x), Some(y)) => Some(std::array::from_fn(|k| x[k] + y[k])),
                            (x, y) => x.or(y),
                        }
                    }
                };
            }
        }
        for (s, b) in shift.iter_mut().zip(between) {
            if s.is_none() {
                *s = b;
            }
        }
        for (pose, shift) in placed.iter_mut().zip(&shift) {
            if let (Some(pose), Some(shift)) = (pose.as_mut(), shift) {
                move_ankle(pose, leg, *shift);
            }
        }
    }
}

/// Moves the ankle of `leg` in `pose` by `shift` (metres), the knee following so that the
/// thigh and shin keep their lengths (two-bone inverse kinematics about the fixed hip).
fn move_ankle(pose: &mut Pose3, leg: [Landmark; 3], shift: [f64; 3]) {
    let [hip, knee, ankle] = leg.map(|l| Vector3::from(pose.get(l)));
    let (thigh, shin) = ((knee - hip).norm(), (ankle - knee).norm());
    let wanted = ankle + Vector3::from(shift) - hip;
    let reach = wanted.norm();
    if !(thigh > 0.0 && shin > 0.0 && reach > 0.0) {
        return;
    }
    // Within the leg's reach, and straightened by at most MAX_KNEE_STRAIGHTEN_DEG, to at
    // most MAX_KNEE_DEG (a trailing leg pulled back to its footprint went to the limit, then
    // bent 27 deg in two frames; a cap at 165 deg alone raised knees bent to 139-155 deg).
    let reach_at = |angle_deg: f64| {
        (thigh * thigh + shin * shin - 2.0 * thigh * shin * angle_deg.to_radians().cos()).sqrt()
    };
    let own_deg = {
        let cos =
            (thigh * thigh + shin * shin - (ankle - hip).norm_squared()) / (2.0 * thigh * shin);
        cos.clamp(-1.0, 1.0).acos().to_degrees()
    };
    let straightest = own_deg.max((own_deg + MAX_KNEE_STRAIGHTEN_DEG).min(MAX_KNEE_DEG));
    let d = reach
        .min(reach_at(straightest))
        .clamp((thigh - shin).abs() * 1.001, (thigh + shin) * 0.999);
    let axis = wanted / reach;
    // The knee's side: the old knee's offset across the new hip-ankle line.
    let old = knee - hip;
    let across = old - axis * old.dot(&axis);
    let across_norm = across.norm();
    if across_norm < 1e-9 {
        return;
    }
    let side = across / across_norm;
    let a = (thigh * thigh - shin * shin + d * d) / (2.0 * d);
    let h = (thigh * thigh - a * a).max(0.0).sqrt();
    pose.points[leg[1].index()] = (hip + axis * a + side * h).into();
    pose.points[leg[2].index()] = (hip + axis * d).into();
}

#[cfg(test)]
mod tests {
    use super::*;
    use camloc_skeleton::NUM_LANDMARKS;

    /// A standing leg whose ankle slides 1 cm a frame along x: hip at 0.8 m, knee bent
    /// forward (the ankle within the leg's reach), ankle on the floor.
    fn sliding(frames: usize) -> Vec<Option<Pose3>> {
        (0..frames)
            .map(|t| {
                let x = 0.01 * t as f64;
                let mut points = [[0.0, 0.0, 0.9]; NUM_LANDMARKS];
                points[Landmark::LeftHip.index()] = [0.0, 0.1, 0.8];
                points[Landmark::LeftKnee.index()] = [0.2, 0.1, 0.45];
                points[Landmark::LeftAnkle.index()] = [x, 0.1, 0.05];
                Some(Pose3 { points })
            })
            .collect()
    }

    fn length(p: &Pose3, a: Landmark, b: Landmark) -> f64 {
        let (a, b) = (p.get(a), p.get(b));
        ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
    }

    #[test]
    fn a_planted_ankle_stays_at_its_runs_mean_and_the_leg_keeps_its_lengths() {
        let before = sliding(20);
        let mut placed = before.clone();
        // Planted in frames 3 to 8.
        let contacts: Vec<(usize, Landmark)> = (3..9).map(|t| (t, Landmark::LeftAnkle)).collect();
        lock_feet(&mut placed, &contacts, FrameRate::default());
        let ankle = |t: usize| placed[t].unwrap().get(Landmark::LeftAnkle);
        // The mean of frames 3-8 along x is 0.055 m; every planted frame is there.
        for t in 3..9 {
            assert!(
                (ankle(t)[0] - 0.055).abs() < 1e-9,
                "frame {t}: {:?}",
                ankle(t)
            );
        }
        // The fades: two frames on each side, corrected by 2/3 and 1/3 of the edge's.
        let moved = |t: usize| ankle(t)[0] - before[t].unwrap().get(Landmark::LeftAnkle)[0];
        assert!((moved(9) - 2.0 / 3.0 * moved(8)).abs() < 1e-9);
        assert!((moved(10) - 1.0 / 3.0 * moved(8)).abs() < 1e-9);
        assert!((moved(2) - 2.0 / 3.0 * moved(3)).abs() < 1e-9);
        assert_eq!(placed[11..], before[11..]);
        assert_eq!(placed[0], before[0]);
        // A second run, frames 13 to 16: between the two the correction goes from the first
        // run's last to the second's first in even steps.
        let mut two = before.clone();
        let mut contacts = contacts;
        contacts.extend((13..17).map(|t| (t, Landmark::LeftAnkle)));
        lock_feet(&mut two, &contacts, FrameRate::default());
        let moved = |t: usize| {
            two[t].unwrap().get(Landmark::LeftAnkle)[0]
                - before[t].unwrap().get(Landmark::LeftAnkle)[0]
        };
        for t in 9..13 {
            let w = (t - 8) as f64 / 5.0;
            assert!((moved(t) - (moved(8) + (moved(13) - moved(8)) * w)).abs() < 1e-9);
        }
        for (p, q) in placed.iter().flatten().zip(before.iter().flatten()) {
            // The hip and the other landmarks stay; the thigh and shin keep their lengths.
            assert_eq!(p.get(Landmark::LeftHip), q.get(Landmark::LeftHip));
            assert_eq!(p.get(Landmark::RightAnkle), q.get(Landmark::RightAnkle));
            for (a, b) in [
                (Landmark::LeftHip, Landmark::LeftKnee),
                (Landmark::LeftKnee, Landmark::LeftAnkle),
            ] {
                assert!((length(p, a, b) - length(q, a, b)).abs() < 1e-9);
            }
        }
    }
}
