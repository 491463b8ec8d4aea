//! Planted feet: the pelvis's path of a placed sequence moved so that a foot on the floor
//! stays where it stands ([`plant_feet`]). The path from one camera's scale jitters in depth
//! by centimetres from frame to frame, and the feet slide with it.

use camloc_skeleton::{Landmark, Pose3};

/// How far the camera's place of the pelvis may be off, metres, along the world's x (across
/// the camera's view), y (away from it, the depth from the scale) and z (up).
/// (Chosen on tripod views of eight CMU walks of training subjects, before the glide test and
/// [`ACCELERATION_DEVIATION_M`] were added: at 0.1 m in depth the feet slid less, 0.70
/// against 0.81 cm a frame, but the path strayed further from the true one, 6.4 against 5.9
/// cm; without planting, 1.80 cm and 6.3 cm.)
const CAMERA_DEVIATION_M: [f64; 3] = [0.03, 0.05, 0.03];
/// How far the pelvis's path may bend from one frame to the next (its second difference),
/// metres. Without it the path takes up the planted ankle's jitter. (Chosen on the walks of
/// [`CAMERA_DEVIATION_M`] and on a simulated user's tripod views of five CMU walks, which
/// found the pelvis shaking with 1 cm: there the pelvis's mean second difference across /
/// in depth / up was 0.71 / 0.78 / 0.31 cm with 1 cm, 0.35 / 0.38 / 0.16 cm with 0.5 cm,
/// 0.18 / 0.20 / 0.09 cm with 0.3 cm (the truth's 0.29 across the floor, 0.20 up), and the
/// planted feet slid 1.43 / 1.70 / 1.86 cm a frame (2.12 without planting).)
const ACCELERATION_DEVIATION_M: f64 = 0.005;
/// How far a planted foot's ankle may move from one frame to the next, metres.
const PLANTED_DEVIATION_M: f64 = 0.005;
/// Frames on each side over which the pelvis's path is averaged to tell which foot moves.
const COARSE_FRAMES: usize = 5;
/// An ankle this far above the lowest ankle of the frames near it can still be planted,
/// metres; above it its weight falls off over [`LIFTED_M`].
const ON_FLOOR_M: f64 = 0.05;
/// See [`ON_FLOOR_M`], metres.
const LIFTED_M: f64 = 0.03;
/// A planted foot moves on the coarse path by less than this share of the pelvis's step
/// (plus [`STILL_SHARE`]); the other foot, or both when the person glides, moves more.
const GLIDE_SHARE: f64 = 0.8;
/// A planted foot of a person standing still moves on the coarse path by less than this
/// share of the pelvis's height above the lower ankle in a frame (0.5 cm for a standing
/// adult).
const STILL_SHARE: f64 = 0.005;
/// Frames on each side whose lowest ankle is the floor near a frame.
const FLOOR_FRAMES: usize = 15;

/// Moves the frames of `placed` (z-up world, metres, in time order; `None`: a frame the
/// person is missing from, which keeps time) so that the pelvis's path keeps planted feet in
/// place: per axis, the path nearest the frames' own pelvis places (weighted by
/// [`CAMERA_DEVIATION_M`]) whose steps are those of the planted ankle seen from the pelvis
/// (weighted by [`PLANTED_DEVIATION_M`]) and which bends little from frame to frame (weighted
/// by [`ACCELERATION_DEVIATION_M`]; across missing frames the path only bends). In each step
/// between two frames the planted foot is the one that moves less on a coarse path (the
/// pelvis's averaged over [`COARSE_FRAMES`] on each side), unless it moves with the pelvis
/// ([`GLIDE_SHARE`]), counted as much as it is near the floor. The poses themselves are
/// kept; fewer than 3 frames are left as they are.
///
/// Returns the planted ankles (frame, landmark) counted at least half.
pub(super) fn plant_feet(placed: &mut [Option<Pose3>]) -> Vec<(usize, Landmark)> {
    if placed.iter().flatten().count() < 3 {
        return Vec::new();
    }
    let (shifts, planted) = pelvis_shifts(placed);
    for (p, d) in placed.iter_mut().zip(shifts) {
        if let Some(p) = p {
            for q in &mut p.points {
                for k in 0..3 {
                    q[k] += d[k];
                }
            }
        }
    }
    planted
}

/// The shift of each frame of `frames` (at least 3 of them present) that plants its feet,
/// and the planted ankles (frame, landmark) counted at least half.
fn pelvis_shifts(frames: &[Option<Pose3>]) -> (Vec<[f64; 3]>, Vec<(usize, Landmark)>) {
    let n = frames.len();
    let pelvis: Vec<Option<[f64; 3]>> = frames
        .iter()
        .map(|p| p.map(|p| p.get(Landmark::Pelvis)))
        .collect();
    // The mean of the frames present within as many frames on both sides.
    let coarse: Vec<Option<[f64; 3]>> = (0..n)
        .map(|t| {
            pelvis[t]?;
            let half = COARSE_FRAMES.min(t).min(n - 1 - t);
            let near: Vec<[f64; 3]> = pelvis[t - half..=t + half]
                .iter()
                .flatten()
                .copied()
                .collect();
            let m = near.len() as f64;
            Some(std::array::from_fn(|k| {
                near.iter().map(|p| p[k]).sum::<f64>() / m
            }))
        })
        .collect();
    let ankles = [Landmark::LeftAnkle, Landmark::RightAnkle];
    // Each ankle seen from the pelvis, and its place on the coarse path (frames present).
    let offset = |t: usize, f: usize| -> [f64; 3] {
        let (a, p) = (
            frames[t].map_or([0.0; 3], |p| p.get(ankles[f])),
            pelvis[t].unwrap_or([0.0; 3]),
        );
        std::array::from_fn(|k| a[k] - p[k])
    };
    let coarse_ankle = |t: usize, f: usize| -> [f64; 3] {
        let (o, c) = (offset(t, f), coarse[t].unwrap_or([0.0; 3]));
        std::array::from_fn(|k| c[k] + o[k])
    };
    let lowest: Vec<f64> = (0..n)
        .map(|t| {
            if frames[t].is_none() {
                return f64::INFINITY;
            }
            (0..2)
                .map(|f| coarse_ankle(t, f)[2])
                .fold(f64::INFINITY, f64::min)
        })
        .collect();
    let floor: Vec<f64> = (0..n)
        .map(|t| {
            let (lo, hi) = (
                t.saturating_sub(FLOOR_FRAMES),
                (t + FLOOR_FRAMES).min(n - 1),
            );
            lowest[lo..=hi]
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min)
        })
        .collect();
    let distance = |a: [f64; 3], b: [f64; 3]| {
        ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
    };
    // The pelvis's typical height above the lower ankle, metres.
    let mut legs: Vec<f64> = frames
        .iter()
        .flatten()
        .map(|p| {
            let low = p.get(ankles[0])[2].min(p.get(ankles[1])[2]);
            p.get(Landmark::Pelvis)[2] - low
        })
        .collect();
    legs.sort_by(f64::total_cmp);
    let still = STILL_SHARE * legs[legs.len() / 2].max(0.0);
    // Per step between two frames present: the weight (1 / m^2) of the planted foot and the
    // pelvis's step it makes.
    let mut weight = vec![0.0; n + 1];
    let mut step = vec![[0.0; 3]; n + 1];
    let mut planted = Vec::new();
    for t in 1..n {
        let (Some(now), Some(before)) = (coarse[t], coarse[t - 1]) else {
            continue;
        };
        let moved: [f64; 2] =
            std::array::from_fn(|f| distance(coarse_ankle(t, f), coarse_ankle(t - 1, f)));
        let f = usize::from(moved[1] < moved[0]);
        // A foot that moves with the pelvis (a person gliding, or carried) is not planted.
        if moved[f] > GLIDE_SHARE * distance(now, before) + still {
            continue;
        }
        let height = coarse_ankle(t, f)[2].max(coarse_ankle(t - 1, f)[2]) - floor[t];
        let on_floor = (-(height - ON_FLOOR_M).max(0.0) / LIFTED_M).exp();
        weight[t] = on_floor / PLANTED_DEVIATION_M.powi(2);
        if on_floor >= 0.5 {
            planted.push((t, ankles[f]));
        }
        let (from, to) = (offset(t - 1, f), offset(t, f));
        step[t] = std::array::from_fn(|k| from[k] - to[k]);
    }
    // Per axis, the banded normal equations of sum_t a_t (r_t - c_t)^2 (a_t = 0 for a missing
    // frame) + sum_t W_t (r_t - r_{t-1} - s_t)^2 + b sum_t (r_{t+1} - 2 r_t + r_{t-1})^2;
    // row t holds the entries (t, t-2), (t, t-1), (t, t).
    let b = ACCELERATION_DEVIATION_M.powi(-2);
    let mut shifts = vec![[0.0; 3]; n];
    for k in 0..3 {
        let a = CAMERA_DEVIATION_M[k].powi(-2);
        let mut rows: Vec<[f64; 3]> = pelvis
            .iter()
            .map(|p| [0.0, 0.0, if p.is_some() { a } else { 0.0 }])
            .collect();
        let mut right: Vec<f64> = pelvis.iter().map(|p| p.map_or(0.0, |p| a * p[k])).collect();
        for t in 1..n {
            let w = weight[t];
            rows[t][2] += w;
            rows[t - 1][2] += w;
            rows[t][1] -= w;
            right[t] += w * step[t][k];
            right[t - 1] -= w * step[t][k];
        }
        for t in 1..n - 1 {
            rows[t - 1][2] += b;
            rows[t][2] += 4.0 * b;
            rows[t + 1][2] += b;
            rows[t][1] -= 2.0 * b;
            rows[t + 1][1] -= 2.0 * b;
            rows[t + 1][0] += b;
        }
        let path = solve_banded(&rows, &right);
        for t in 0..n {
            if let Some(p) = pelvis[t] {
                shifts[t][k] = path[t] - p[k];
            }
        }
    }
    (shifts, planted)
}

/// The solution of the symmetric positive definite system whose row `t` has the entries
/// `rows[t] = [A(t, t-2), A(t, t-1), A(t, t)]` (the rest 0) and right-hand side `right`
/// (banded Cholesky factorisation).
fn solve_banded(rows: &[[f64; 3]], right: &[f64]) -> Vec<f64> {
    let n = rows.len();
    // The factor's rows: [L(t, t-2), L(t, t-1), L(t, t)].
    let mut factor = vec![[0.0; 3]; n];
    for t in 0..n {
        let far = if t >= 2 {
            rows[t][0] / factor[t - 2][2]
        } else {
            0.0
        };
        let near = if t >= 1 {
            (rows[t][1] - far * factor[t - 1][1]) / factor[t - 1][2]
        } else {
            0.0
        };
        factor[t] = [far, near, (rows[t][2] - far * far - near * near).sqrt()];
    }
    let mut y = vec![0.0; n];
    for t in 0..n {
        let mut v = right[t];
        if t >= 1 {
            v -= factor[t][1] * y[t - 1];
        }
        if t >= 2 {
            v -= factor[t][0] * y[t - 2];
        }
        y[t] = v / factor[t][2];
    }
    let mut x = vec![0.0; n];
    for t in (0..n).rev() {
        let mut v = y[t];
        if t + 1 < n {
            v -= factor[t + 1][1] * x[t + 1];
        }
        if t + 2 < n {
            v -= factor[t + 2][0] * x[t + 2];
        }
        x[t] = v / factor[t][2];
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;
    use camloc_skeleton::NUM_LANDMARKS;

    /// A walk along x, 3 cm a frame, a step every 20 frames: the stance ankle stays on its
    /// footprint while the other swings 10 cm above the floor to the next one. Returns the
    /// poses (pelvis 0.9 m up, the other landmarks at the pelvis) and each frame's planted
    /// ankle.
    fn walk(frames: usize) -> (Vec<Pose3>, Vec<Landmark>) {
        let (mut poses, mut planted) = (Vec::new(), Vec::new());
        for t in 0..frames {
            let x = 0.03 * t as f64;
            let step = t / 20;
            let phase = (t % 20) as f64 / 20.0;
            // A step is 0.6 m: the stance foot was put 0.3 m ahead of the pelvis at the
            // step's start; the swing foot goes from 0.6 m behind that footprint to 0.6 m
            // ahead of it.
            let stance_at = 0.6 * step as f64 + 0.3;
            let swing_x = stance_at - 0.6 + 1.2 * phase;
            let lift = 0.1 * (std::f64::consts::PI * phase).sin();
            let (stance, swing) = if step % 2 == 0 {
                (Landmark::LeftAnkle, Landmark::RightAnkle)
            } else {
                (Landmark::RightAnkle, Landmark::LeftAnkle)
            };
            let mut points = [[x, 0.0, 0.9]; NUM_LANDMARKS];
            points[stance.index()] = [stance_at, 0.0, 0.0];
            points[swing.index()] = [swing_x, 0.0, lift];
            poses.push(Pose3 { points });
            planted.push(stance);
        }
        (poses, planted)
    }

    #[test]
    fn a_walk_whose_depth_jitters_keeps_its_planted_feet_and_its_path_across_missing_frames() {
        let (truth, planted) = walk(120);
        // The camera's depth (y) jitters by up to 5 cm from frame to frame.
        let mut seed = 7u64;
        let mut placed: Vec<Option<Pose3>> = truth
            .iter()
            .map(|p| {
                seed = seed
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let dy = 0.1 * ((seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5);
                Some(Pose3 {
                    points: p.points.map(|q| [q[0], q[1] + dy, q[2]]),
                })
            })
            .collect();
        // Every 4th frame missing (a detector that missed the person), and four in a row.
        for (t, p) in placed.iter_mut().enumerate() {
            if t % 4 == 3 || (60..64).contains(&t) {
                *p = None;
            }
        }
        let slide_and_path = |poses: &[Option<Pose3>]| {
            let (mut slide, mut path) = (0.0, 0.0);
            for t in 1..poses.len() {
                let (Some(a), Some(b)) = (poses[t - 1], poses[t]) else {
                    continue;
                };
                if planted[t] == planted[t - 1] {
                    let (p, q) = (a.get(planted[t]), b.get(planted[t]));
                    slide += ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt();
                }
                let (p, q) = (b.get(Landmark::Pelvis), truth[t].get(Landmark::Pelvis));
                path += ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt();
            }
            (slide / poses.len() as f64, path / poses.len() as f64)
        };
        let (slide_before, path_before) = slide_and_path(&placed);
        let contacts = plant_feet(&mut placed);
        assert!(contacts.len() > 40, "{}", contacts.len());
        let (slide_after, path_after) = slide_and_path(&placed);
        assert!(
            slide_after < 0.2 * slide_before,
            "{slide_before} -> {slide_after}"
        );
        assert!(path_after < path_before, "{path_before} -> {path_after}");
        // The poses are moved, not changed.
        for (p, q) in placed
            .iter()
            .zip(&truth)
            .filter_map(|(p, q)| Some((p.as_ref()?, q)))
        {
            let d = |r: &Pose3| -> [f64; 3] {
                let (a, b) = (r.get(Landmark::LeftAnkle), r.get(Landmark::Pelvis));
                std::array::from_fn(|k| a[k] - b[k])
            };
            let (a, b) = (d(p), d(q));
            assert!((0..3).all(|k| (a[k] - b[k]).abs() < 1e-12));
        }
    }

    #[test]
    fn fewer_than_three_frames_are_left_as_they_are() {
        let (truth, _) = walk(5);
        let mut placed: Vec<Option<Pose3>> = vec![Some(truth[0]), None, None, Some(truth[3])];
        let before = placed.clone();
        assert!(plant_feet(&mut placed).is_empty());
        assert_eq!(placed, before);
    }
}
