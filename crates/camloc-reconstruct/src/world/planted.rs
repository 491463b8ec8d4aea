//! Planted feet: the pelvis's path of a placed sequence moved so that a foot on the floor
//! stays where it stands ([`plant_feet`]). The path from one camera's scale jitters in depth
//! by centimetres from frame to frame, and the feet slide with it.

use camloc_skeleton::{Landmark, NUM_LANDMARKS, Pose3};

use super::centred::{centred_lines, centred_means};
use super::image_ankles::ImageAnkles;
use crate::FrameRate;

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
/// Frames on each side over which each ankle seen from the pelvis is averaged for a step's
/// test of which foot is planted and for the planted foot's step: a detector's noise moved a
/// planted ankle by centimetres a frame, more than a walker's pelvis step, so that neither
/// foot passed and the feet slid (a simulated user's walk with 5.4 px of noise: 4.6 cm a
/// frame; 2.1 cm averaged so).
const STEP_FRAMES: usize = 3;
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
/// A foot of a person standing, sitting or kneeling still keeps its place when its place
/// averaged over [`COARSE_FRAMES`] on each side moves by less than this share of the legs'
/// length (thigh plus shin) from one frame to the next (0.4 cm for an adult), in the world
/// or in the image (where a depth the scale got wrong does not move it): its frames jitter
/// by a centimetre or more with 2 px of detector noise.
const KEPT_SHARE: f64 = 0.005;
/// A foot kept in place on average stays so only while its averaged place stays within this
/// share of the legs' length of where it was when the stretch began (in the image where
/// known, else in the world: 2 cm for an adult), and only for stretches of at least twice
/// [`COARSE_FRAMES`] and one steps: a foot moving slowly (a slow walk, a walk filmed at 120
/// frames a second) passes the step bound frame by frame, and
/// locked at its stretch's mean it had jumped by 17 cm at the stretch's end (a simulated
/// user's quarter-speed walk).
const KEPT_SPAN_SHARE: f64 = 0.025;
/// A foot still in the image is kept in place when its averaged place in the world moves by
/// less than this many times the [`KEPT_SHARE`] step (a depth the scale got wrong moves it
/// by centimetres; a foot running towards the camera, still in the image, by a decimetre).
const IMAGE_KEPT_SLACK: f64 = 4.0;
/// Frames on each side whose lowest ankle is the floor near a frame.
const FLOOR_FRAMES: usize = 15;

/// Moves the frames of `placed` (z-up world, metres, in time order; `None`: a frame the
/// person is missing from, which keeps time) so that the pelvis's path keeps planted feet in
/// place: per axis, the path nearest the frames' own pelvis places (weighted by
/// [`CAMERA_DEVIATION_M`]) whose steps are those of the planted ankle seen from the pelvis
/// (weighted by [`PLANTED_DEVIATION_M`]) and which bends little from frame to frame (weighted
/// by [`ACCELERATION_DEVIATION_M`]; across missing frames the path only bends). In each step
/// between two frames the planted foot is the one that moves less on a coarse path (the
/// pelvis's averaged over [`COARSE_FRAMES`] on each side, each ankle seen from it over
/// [`STEP_FRAMES`]), unless it moves with the pelvis
/// ([`GLIDE_SHARE`]), counted as much as it is near the floor. The poses themselves are
/// kept; fewer than 3 frames are left as they are.
///
/// A foot that moves with the pelvis on the coarse path but keeps its place on average
/// ([`KEPT_SHARE`]) in the world or in `images` (each frame's landmarks as its camera sees
/// them, image units; `None` where unknown) is planted too, its steps averaged alike; both
/// feet may be.
///
/// The windows and per-frame bounds above are at 30 frames a second; at `rate`'s faster
/// ones they are kept in time ([`FrameRate`]: windows `step()` times longer, steps `step()`
/// times shorter, the path's bend deviation times `deviation_factor()`).
///
/// Returns the planted ankles counted at least half.
pub(super) fn plant_feet(
    placed: &mut [Option<Pose3>],
    images: &[Option<[[f64; 2]; NUM_LANDMARKS]>],
    rate: FrameRate,
) -> PlantedAnkles {
    if placed.iter().flatten().count() < 3 {
        return PlantedAnkles::default();
    }
    let (shifts, planted) = pelvis_shifts(placed, images, rate);
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

/// The planted ankles of [`plant_feet`], (frame, landmark) pairs.
#[derive(Debug, Default)]
pub(super) struct PlantedAnkles {
    /// Every planted ankle: the feet to lock.
    pub(super) all: Vec<(usize, Landmark)>,
    /// The ankles planted by the step test alone (the foot that moves less, not with the
    /// pelvis), without those only kept in place on average: the floor's. With the kept ones
    /// too, a simulated user's run seen from 2.5 m had its floor rise 38 cm (5 cm before) and
    /// climbing steps seen from 6 m up their pelvis 22 cm off (12 cm).
    pub(super) stepping: Vec<(usize, Landmark)>,
}

/// The shift of each frame of `frames` (at least 3 of them present) that plants its feet,
/// and the planted ankles counted at least half.
fn pelvis_shifts(
    frames: &[Option<Pose3>],
    images: &[Option<[[f64; 2]; NUM_LANDMARKS]>],
    rate: FrameRate,
) -> (Vec<[f64; 3]>, PlantedAnkles) {
    let n = frames.len();
    // The windows below are counted at 30 frames a second and kept in time at faster rates.
    let coarse_frames = COARSE_FRAMES * rate.step();
    // Steps from frame to frame shorten as the frames come faster.
    let per_frame = rate.step() as f64;
    let floor_frames = FLOOR_FRAMES * rate.step();
    let pelvis: Vec<Option<[f64; 3]>> = frames
        .iter()
        .map(|p| p.map(|p| p.get(Landmark::Pelvis)))
        .collect();
    // The mean of the frames present within as many frames on both sides.
    let coarse = centred_means(&pelvis, coarse_frames);
    let ankles = [Landmark::LeftAnkle, Landmark::RightAnkle];
    // Each ankle seen from the pelvis.
    let offset = |t: usize, f: usize| -> [f64; 3] {
        let (a, p) = (
            frames[t].map_or([0.0; 3], |p| p.get(ankles[f])),
            pelvis[t].unwrap_or([0.0; 3]),
        );
        std::array::from_fn(|k| a[k] - p[k])
    };
    // An ankle's offset from the pelvis placed on the coarse path at frame `t`.
    let on_coarse = |t: usize, o: [f64; 3]| -> [f64; 3] {
        let c = coarse[t].unwrap_or([0.0; 3]);
        std::array::from_fn(|k| c[k] + o[k])
    };
    let coarse_ankle = |t: usize, f: usize| on_coarse(t, offset(t, f));
    // Each ankle seen from the pelvis (frames present), once per foot for the two averages
    // below.
    let offsets: [Vec<Option<[f64; 3]>>; 2] =
        std::array::from_fn(|f| (0..n).map(|t| frames[t].map(|_| offset(t, f))).collect());
    // Each ankle seen from the pelvis averaged over the frames present within
    // [`COARSE_FRAMES`] on each side, and its place on the coarse path so: the jitter of a
    // still foot's frames (the detector's pixels, the depth from the scale) averages out,
    // a step does not.
    let smooth_offsets = offsets.each_ref().map(|o| centred_means(o, coarse_frames));
    let smooth_offset = |t: usize, f: usize| smooth_offsets[f][t].unwrap_or([0.0; 3]);
    let smooth_ankle = |t: usize, f: usize| on_coarse(t, smooth_offset(t, f));
    // The same over [`STEP_FRAMES`], a straight line: which foot is planted, and its step.
    let step_offsets = offsets
        .each_ref()
        .map(|o| centred_lines(o, STEP_FRAMES * rate.step()));
    let step_offset = |t: usize, f: usize| step_offsets[f][t].unwrap_or([0.0; 3]);
    let step_ankle = |t: usize, f: usize| on_coarse(t, step_offset(t, f));
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
                t.saturating_sub(floor_frames),
                (t + floor_frames).min(n - 1),
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
    let still = STILL_SHARE * legs[legs.len() / 2].max(0.0) / per_frame;
    // The legs' length, thigh plus shin (the median of the frames' left legs), metres.
    let mut leg_lengths: Vec<f64> = frames
        .iter()
        .flatten()
        .map(|p| {
            let [hip, knee, ankle] =
                [Landmark::LeftHip, Landmark::LeftKnee, Landmark::LeftAnkle].map(|l| p.get(l));
            distance(hip, knee) + distance(knee, ankle)
        })
        .collect();
    leg_lengths.sort_by(f64::total_cmp);
    let leg = leg_lengths[leg_lengths.len() / 2];
    let kept_step = KEPT_SHARE * leg / per_frame;
    let image = ImageAnkles::of(images, n, coarse_frames);
    // Per step between two frames present: the weight (1 / m^2) of the planted foot and the
    // pelvis's step it makes.
    let mut weight = vec![0.0; n + 1];
    let mut step = vec![[0.0; 3]; n + 1];
    let mut planted = PlantedAnkles::default();
    // Per step, the feet that keep their place on average while the person stands, sits or
    // kneels still: its frames' jitter (a centimetre or more a frame from 2 px of noise) is
    // larger than a still foot's step test allows.
    let mut kept: Vec<[bool; 2]> = (0..n)
        .map(|t| {
            std::array::from_fn(|f| {
                let present = t > 0 && coarse[t].is_some() && coarse[t - 1].is_some();
                let step = || distance(smooth_ankle(t, f), smooth_ankle(t - 1, f));
                let still_in_image = || {
                    image
                        .apart(t - 1, t, f)
                        .is_some_and(|d| d <= KEPT_SHARE / per_frame)
                };
                present
                    && (step() <= kept_step
                        || (still_in_image() && step() <= IMAGE_KEPT_SLACK * kept_step))
            })
        })
        .collect();
    for f in 0..2 {
        // In the image where known (the depth of a still foot's frames jitters by
        // centimetres), else in the world.
        let left_span = |origin: usize, t: usize| match image.apart(origin, t, f) {
            Some(d) => d > KEPT_SPAN_SHARE,
            None => distance(smooth_ankle(origin, f), smooth_ankle(t, f)) > KEPT_SPAN_SHARE * leg,
        };
        keep_still_stretches(&mut kept, f, left_span, 2 * coarse_frames + 1);
    }
    for t in 1..n {
        let (Some(now), Some(before)) = (coarse[t], coarse[t - 1]) else {
            continue;
        };
        let moved: [f64; 2] =
            std::array::from_fn(|f| distance(step_ankle(t, f), step_ankle(t - 1, f)));
        let kept = kept[t];
        let on_floor = |f: usize| {
            let height = coarse_ankle(t, f)[2].max(coarse_ankle(t - 1, f)[2]) - floor[t];
            (-(height - ON_FLOOR_M).max(0.0) / LIFTED_M).exp()
        };
        let mut f = usize::from(moved[1] < moved[0]);
        // A foot that moves with the pelvis (a person gliding, or carried) is not planted.
        let stepping = moved[f] <= GLIDE_SHARE * distance(now, before) + still;
        let (from, to) = if stepping {
            (step_offset(t - 1, f), step_offset(t, f))
        } else if kept[f] || kept[1 - f] {
            f = if kept[f] { f } else { 1 - f };
            (smooth_offset(t - 1, f), smooth_offset(t, f))
        } else {
            continue;
        };
        weight[t] = on_floor(f) / PLANTED_DEVIATION_M.powi(2);
        if on_floor(f) >= 0.5 {
            planted.all.push((t, ankles[f]));
            if stepping {
                planted.stepping.push((t, ankles[f]));
            }
        }
        // The other foot, still too, is planted as well (a person standing or sitting still).
        if kept[1 - f] && on_floor(1 - f) >= 0.5 {
            planted.all.push((t, ankles[1 - f]));
        }
        step[t] = std::array::from_fn(|k| from[k] - to[k]);
    }
    // Per axis, the banded normal equations of sum_t a_t (r_t - c_t)^2 (a_t = 0 for a missing
    // frame) + sum_t W_t (r_t - r_{t-1} - s_t)^2 + b sum_t (r_{t+1} - 2 r_t + r_{t-1})^2;
    // row t holds the entries (t, t-2), (t, t-1), (t, t).
    let b = (ACCELERATION_DEVIATION_M * rate.deviation_factor()).powi(-2);
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

/// Clears `kept[t][foot]` (per step, whether the foot keeps its place) outside stretches of
/// consecutive kept steps in which the foot stays near where the stretch began
/// (`left_span(start, t)`: whether step `t` has left the place of step `start`) and which last
/// `min_steps` steps or more: each run of kept steps is cut where the foot leaves, and
/// the pieces too short are cleared.
fn keep_still_stretches(
    kept: &mut [[bool; 2]],
    foot: usize,
    left_span: impl Fn(usize, usize) -> bool,
    min_steps: usize,
) {
    let n = kept.len();
    let mut t = 0;
    while t < n {
        if !kept[t][foot] {
            t += 1;
            continue;
        }
        let start = t;
        let mut end = t + 1;
        while end < n && kept[end][foot] && !left_span(start, end) {
            end += 1;
        }
        if end - start < min_steps {
            for k in &mut kept[start..end] {
                k[foot] = false;
            }
        }
        // The step that left the place starts the next stretch.
        t = end;
    }
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
    fn both_feet_of_a_person_standing_still_are_planted_through_their_jitter() {
        // 90 frames of a person standing still, each landmark jittering by up to 1.5 cm a
        // frame on each axis (2 px of detector noise), legs 0.85 m (knees halfway).
        let mut seed = 11u64;
        let mut jitter = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            0.03 * ((seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5)
        };
        let mut placed: Vec<Option<Pose3>> = (0..90)
            .map(|_| {
                let mut points = [[0.0, 0.0, 0.9]; NUM_LANDMARKS];
                for (l, y) in [(Landmark::LeftAnkle, 0.1), (Landmark::RightAnkle, -0.1)] {
                    points[l.index()] = [0.0, y, 0.05];
                }
                for (l, y) in [(Landmark::LeftKnee, 0.1), (Landmark::RightKnee, -0.1)] {
                    points[l.index()] = [0.0, y, 0.475];
                }
                for p in &mut points {
                    *p = p.map(|v| v + jitter());
                }
                Some(Pose3 { points })
            })
            .collect();
        let contacts = plant_feet(&mut placed, &[], FrameRate::default()).all;
        for ankle in [Landmark::LeftAnkle, Landmark::RightAnkle] {
            let planted = contacts.iter().filter(|(_, a)| *a == ankle).count();
            assert!(planted > 80, "{ankle:?}: {planted} of 89 steps");
        }
    }

    #[test]
    fn a_foot_moving_slowly_is_not_kept_in_place() {
        // 90 frames: the left foot still, the right one sliding 0.3 cm a frame (under the
        // still step's bound frame by frame, 27 cm in all), legs 0.85 m.
        let mut placed: Vec<Option<Pose3>> = (0..90)
            .map(|t| {
                let mut points = [[0.0, 0.0, 0.9]; NUM_LANDMARKS];
                points[Landmark::LeftAnkle.index()] = [0.0, 0.1, 0.05];
                points[Landmark::RightAnkle.index()] = [0.003 * t as f64, -0.1, 0.05];
                points[Landmark::LeftKnee.index()] = [0.0, 0.1, 0.475];
                points[Landmark::RightKnee.index()] = [0.0015 * t as f64, -0.1, 0.475];
                Some(Pose3 { points })
            })
            .collect();
        let planted = plant_feet(&mut placed, &[], FrameRate::default()).all;
        let count = |ankle| planted.iter().filter(|(_, a)| *a == ankle).count();
        assert!(
            count(Landmark::LeftAnkle) > 80,
            "{}",
            count(Landmark::LeftAnkle)
        );
        assert_eq!(count(Landmark::RightAnkle), 0);
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
        let contacts = plant_feet(&mut placed, &[], FrameRate::default()).stepping;
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
        assert!(
            plant_feet(&mut placed, &[], FrameRate::default())
                .all
                .is_empty()
        );
        assert_eq!(placed, before);
    }
}
