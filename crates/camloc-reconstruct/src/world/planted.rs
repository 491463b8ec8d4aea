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

/// Moves each run of consecutive frames of `placed` (z-up world, metres; `None` ends a run)
/// so that the pelvis's path keeps planted feet in place: per axis, the path nearest the
/// frames' own pelvis places (weighted by [`CAMERA_DEVIATION_M`]) whose steps are those of the
/// planted ankle seen from the pelvis (weighted by [`PLANTED_DEVIATION_M`]) and which bends
/// little from frame to frame (weighted by [`ACCELERATION_DEVIATION_M`]). In each step the
/// planted foot is the one that moves less on a coarse path (the pelvis's averaged over
/// [`COARSE_FRAMES`] on each side), unless it moves with the pelvis ([`GLIDE_SHARE`]),
/// counted as much as it is near the floor. The poses themselves are kept; runs of fewer
/// than 3 frames are left as they are.
///
/// Returns the planted ankles (frame, landmark) counted at least half.
pub(super) fn plant_feet(placed: &mut [Option<Pose3>]) -> Vec<(usize, Landmark)> {
    let mut contacts = Vec::new();
    let mut start = 0;
    while start < placed.len() {
        let len = placed[start..].iter().take_while(|p| p.is_some()).count();
        if len >= 3 {
            let run: Vec<Pose3> = placed[start..start + len]
                .iter()
                .flatten()
                .copied()
                .collect();
            let (shifts, planted) = pelvis_shifts(&run);
            contacts.extend(planted.into_iter().map(|(t, l)| (start + t, l)));
            for (p, d) in placed[start..start + len].iter_mut().flatten().zip(shifts) {
                for q in &mut p.points {
                    for k in 0..3 {
                        q[k] += d[k];
                    }
                }
            }
        }
        start += len.max(1);
    }
    contacts
}

/// The shift of each pose of `run` (at least 3 frames) that plants its feet, and the planted
/// ankles (frame, landmark) counted at least half.
fn pelvis_shifts(run: &[Pose3]) -> (Vec<[f64; 3]>, Vec<(usize, Landmark)>) {
    let n = run.len();
    let pelvis: Vec<[f64; 3]> = run.iter().map(|p| p.get(Landmark::Pelvis)).collect();
    // As wide on both sides, so that the steps near the ends keep their size.
    let coarse: Vec<[f64; 3]> = (0..n)
        .map(|t| {
            let half = COARSE_FRAMES.min(t).min(n - 1 - t);
            let (lo, hi) = (t - half, t + half);
            let m = (hi - lo + 1) as f64;
            std::array::from_fn(|k| pelvis[lo..=hi].iter().map(|p| p[k]).sum::<f64>() / m)
        })
        .collect();
    let ankles = [Landmark::LeftAnkle, Landmark::RightAnkle];
    // Each ankle seen from the pelvis, and its place on the coarse path.
    let offset = |t: usize, f: usize| -> [f64; 3] {
        let a = run[t].get(ankles[f]);
        std::array::from_fn(|k| a[k] - pelvis[t][k])
    };
    let coarse_ankle = |t: usize, f: usize| -> [f64; 3] {
        let o = offset(t, f);
        std::array::from_fn(|k| coarse[t][k] + o[k])
    };
    let lowest_seen = |t: usize| {
        (0..2)
            .map(|f| run[t].get(ankles[f])[2])
            .fold(f64::INFINITY, f64::min)
    };
    let lowest: Vec<f64> = (0..n)
        .map(|t| {
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
    // Per step t-1 -> t: each ankle's coarse displacement.
    let moved: Vec<[f64; 2]> = (1..n)
        .map(|t| std::array::from_fn(|f| distance(coarse_ankle(t, f), coarse_ankle(t - 1, f))))
        .collect();
    // The pelvis's typical height above the lower ankle, metres.
    let mut legs: Vec<f64> = (0..n).map(|t| pelvis[t][2] - lowest_seen(t)).collect();
    legs.sort_by(f64::total_cmp);
    let still = STILL_SHARE * legs[n / 2].max(0.0);
    // Per step: the weight (1 / m^2) of the planted foot and the pelvis's step it makes.
    let mut weight = vec![0.0; n + 1];
    let mut step = vec![[0.0; 3]; n + 1];
    let mut planted = Vec::new();
    for t in 1..n {
        let d = moved[t - 1];
        let f = usize::from(d[1] < d[0]);
        // A foot that moves with the pelvis (a person gliding, or carried) is not planted.
        if d[f] > GLIDE_SHARE * distance(coarse[t], coarse[t - 1]) + still {
            continue;
        }
        let height = coarse_ankle(t, f)[2].max(coarse_ankle(t - 1, f)[2]) - floor[t];
        let on_floor = (-(height - ON_FLOOR_M).max(0.0) / LIFTED_M).exp();
        weight[t] = on_floor / PLANTED_DEVIATION_M.powi(2);
        if on_floor >= 0.5 {
            planted.push((t, ankles[f]));
        }
        let (before, after) = (offset(t - 1, f), offset(t, f));
        step[t] = std::array::from_fn(|k| before[k] - after[k]);
    }
    // Per axis, the banded normal equations of sum_t a (r_t - c_t)^2
    // + sum_t W_t (r_t - r_{t-1} - s_t)^2 + b sum_t (r_{t+1} - 2 r_t + r_{t-1})^2; row t holds
    // the entries (t, t-2), (t, t-1), (t, t).
    let b = ACCELERATION_DEVIATION_M.powi(-2);
    let mut shifts = vec![[0.0; 3]; n];
    for k in 0..3 {
        let a = CAMERA_DEVIATION_M[k].powi(-2);
        let mut rows = vec![[0.0, 0.0, a]; n];
        let mut right: Vec<f64> = (0..n).map(|t| a * pelvis[t][k]).collect();
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
            shifts[t][k] = path[t] - pelvis[t][k];
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
    fn a_walk_whose_depth_jitters_keeps_its_planted_feet_and_its_path() {
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
        let slide_and_path = |poses: &[Option<Pose3>]| {
            let (mut slide, mut path) = (0.0, 0.0);
            for t in 1..poses.len() {
                let (a, b) = (poses[t - 1].unwrap(), poses[t].unwrap());
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
        assert!(contacts.len() > 100, "{}", contacts.len());
        let (slide_after, path_after) = slide_and_path(&placed);
        assert!(
            slide_after < 0.2 * slide_before,
            "{slide_before} -> {slide_after}"
        );
        assert!(path_after < path_before, "{path_before} -> {path_after}");
        // The poses are moved, not changed.
        for (p, q) in placed.iter().flatten().zip(&truth) {
            let d = |r: &Pose3| -> [f64; 3] {
                let (a, b) = (r.get(Landmark::LeftAnkle), r.get(Landmark::Pelvis));
                std::array::from_fn(|k| a[k] - b[k])
            };
            let (a, b) = (d(p), d(q));
            assert!((0..3).all(|k| (a[k] - b[k]).abs() < 1e-12));
        }
    }

    #[test]
    fn short_runs_and_gaps_are_left_as_they_are() {
        let (truth, _) = walk(5);
        let mut placed: Vec<Option<Pose3>> =
            vec![Some(truth[0]), Some(truth[1]), None, Some(truth[3])];
        let before = placed.clone();
        assert!(plant_feet(&mut placed).is_empty());
        assert_eq!(placed, before);
    }
}
