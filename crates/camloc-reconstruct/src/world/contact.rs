//! The floor as a second measure of depth ([`onto_floor`]): a camera looking down sees a
//! person's depth error as a height error, and a person standing, walking or sitting has a
//! landmark on the floor, so where that landmark's height leaves the floor the depth from the
//! frame's scale was off.

use camloc_geometry::{Matrix3, Vector3};

use super::floor::Plane;
use crate::{FrameRate, Reconstruction};

/// How far a frame's depth from its scale may be off, as a share of the depth (a simulated
/// user's child filmed from 3 m up: measured over true depth 0.93-1.01, 5th to 95th
/// percentile, with the true bone lengths and focal length).
const DEPTH_DEVIATION: f64 = 0.03;
/// How far the lowest landmark of a person on the floor is from the floor's plane, metres
/// (an ankle lifts by a few centimetres in a step).
const CONTACT_DEVIATION_M: f64 = 0.03;
/// A frame whose lowest landmark is further from the floor than this many deviations of the
/// two measures together is off the floor (a jump) and keeps its depth.
const OFF_FLOOR_DEVIATIONS: f64 = 3.0;
/// The floor's plane is fitted again without the frames further from it than this many
/// median distances.
const OUTLIER_MEDIANS: f64 = 3.0;
/// The floor's plane is fitted to each frame's contact averaged over the frames within this
/// many frames of it.
const PLANE_FRAMES: usize = 15;
/// A frame's distance from the floor is taken as the depth's error in two parts: its
/// mean over the frames within this many frames of it (its slow part), and the rest.
const SLOW_FRAMES: usize = 8;
/// The slow part of a frame's distance from the floor is the depth's error up to this many
/// metres and the person's own motion (a jump, kept) from twice as many, in proportion
/// between. (On a simulated user's jumps of 28-49 cm filmed from 1.5-6 m up, the flight's
/// height, mean absolute error: 10.2 cm with every part taken for the depth's error, the
/// jumps flattened under the steep cameras; 8.7 cm so; 6.7 cm with no slow part taken,
/// which left the child of [`onto_floor`] 4.7 cm above the floor against 1.2 cm so.)
const SLOW_ERROR_M: f64 = 0.05;
/// [`depth_factor`] needs the frames' depths to spread over more than this many times what
/// their scale errors ([`DEPTH_DEVIATION`]) alone would spread them (a walk across the view
/// fitted its scale errors as a factor of 0.04).
const DEPTH_CHANGE_DEVIATIONS: f64 = 1.0;
/// How far the vertical the localizer saw may tilt towards or away from the camera, radians
/// (7 deg: a simulated user's walks under a camera 3 m up sloped by 6.5-7.4 deg with the
/// focal length given).
const VERTICAL_DEVIATION_RAD: f64 = 0.12;
/// How far an estimated focal length may be off, in natural logarithms (a factor of 2; a
/// simulated user's estimates were 0.49-19 times the true one).
const ESTIMATED_FOCAL_LOG_DEVIATION: f64 = std::f64::consts::LN_2;
/// The fewest frames that place a floor.
const MIN_FRAMES: usize = 10;

/// Moves each frame's pelvis (`seen`: body -> camera rotation and pelvis, camera frame,
/// metres; the camera at the origin; `horizontal`: two axes across the floor, orthonormal
/// with `up`) along its ray from the camera, weighing the depth from
/// its scale ([`DEPTH_DEVIATION`]) against the depth that puts its lowest landmark along `up`
/// (the world's vertical in camera coordinates) on the floor ([`CONTACT_DEVIATION_M`]). The
/// floor is the plane fitted to the frames' lowest landmarks (its slope is the floor
/// levelling's to take out), fitted again without outliers; a frame further from it than
/// [`OFF_FLOOR_DEVIATIONS`] keeps its depth. The floor weighs the more the steeper the camera
/// looks down: from 3 m up at a child 5 m away, a height error of 3 cm is a depth error of 1.2%;
/// from eye level at a pelvis 0.5 m below, 6%. Nothing moves with fewer than [`MIN_FRAMES`]
/// frames. The windows ([`PLANE_FRAMES`], [`SLOW_FRAMES`]) are at 30 frames a second,
/// `rate.step()` times as many at `rate`'s faster ones ([`FrameRate`]).
pub(super) fn onto_floor(
    frames: &[Option<&Reconstruction>],
    seen: &mut [Option<(Matrix3, Vector3)>],
    up: &Vector3,
    horizontal: [Vector3; 2],
    rate: FrameRate,
) {
    // Per frame: the pelvis, its height along `up` and its place across the floor (along the
    // two horizontal axes), and the height of its lowest landmark.
    let [across, along] = horizontal;
    let contacts: Vec<Contact> = frames
        .iter()
        .zip(seen.iter())
        .enumerate()
        .filter_map(|(frame, (f, s))| {
            let (r, (rotation, pelvis)) = ((*f)?, s.as_ref()?);
            let lowest = lowest_along(r, rotation, up);
            Some(Contact {
                frame,
                place: [across.dot(pelvis), along.dot(pelvis)],
                height: up.dot(pelvis) + lowest,
                pelvis: *pelvis,
            })
        })
        .collect();
    if contacts.len() < MIN_FRAMES {
        return;
    }
    // The plane is fitted to the contacts averaged over a second or so: a frame's depth error
    // moves its place and its height together along its ray, which a plane fitted to single
    // frames takes for a slope.
    let numbers: Vec<usize> = contacts.iter().map(|c| c.frame).collect();
    let points: Vec<[f64; 3]> = contacts
        .iter()
        .map(|c| [c.place[0], c.place[1], c.height])
        .collect();
    let averaged = window_means(&numbers, &points, PLANE_FRAMES * rate.step());
    let fit = |kept: &dyn Fn(&Contact) -> bool| {
        Plane::fit(
            contacts
                .iter()
                .zip(&averaged)
                .filter(|(c, _)| kept(c))
                .map(|(_, a)| *a),
        )
    };
    let distance = |c: &Contact, plane: &Plane| c.height - plane.height_at(c.place[0], c.place[1]);
    let mut plane = fit(&|_| true);
    let bound = outlier_bound(contacts.iter().map(|c| distance(c, &plane)));
    let near = |c: &Contact| distance(c, &plane).abs() <= bound;
    if contacts.iter().filter(|c| near(c)).count() >= MIN_FRAMES {
        plane = fit(&near);
    }
    let offs: Vec<[f64; 1]> = contacts.iter().map(|c| [distance(c, &plane)]).collect();
    // The distance's slow part, its mean over the frames near: a depth error while small, a
    // jump (kept) from twice that.
    let slow_parts = window_means(&numbers, &offs, SLOW_FRAMES * rate.step());
    for ((c, [own]), [slow]) in contacts.iter().zip(&offs).zip(&slow_parts) {
        let kept = ((slow.abs() - SLOW_ERROR_M) / SLOW_ERROR_M).clamp(0.0, 1.0);
        let off = own - kept * slow;
        // The distance's change per unit of depth factor: the pelvis moves along its ray,
        // and so does its place under the plane.
        let gain = up.dot(&c.pelvis) - (plane.slope[0] * c.place[0] + plane.slope[1] * c.place[1]);
        let spread = CONTACT_DEVIATION_M.hypot(gain * DEPTH_DEVIATION);
        if !(off.abs() <= OFF_FLOOR_DEVIATIONS * spread) {
            continue;
        }
        let (depth_weight, floor_weight) = (
            DEPTH_DEVIATION.powi(-2),
            (gain / CONTACT_DEVIATION_M).powi(2),
        );
        let factor = 1.0 - off * gain / CONTACT_DEVIATION_M.powi(2) / (depth_weight + floor_weight);
        if let Some((_, p)) = &mut seen[c.frame] {
            *p *= factor;
        }
    }
}

/// The factor of every depth (an estimated focal length's error) that puts the frames' lowest
/// landmarks (`seen`, `up` as [`onto_floor`] takes them) at one height: with the depths scaled
/// by `k`, a frame's height is `a + k b` (`b` the depth's part along `up`), and `k` is the
/// least-squares one, fitted again without the frames off by more than [`OUTLIER_MEDIANS`]
/// median residuals, then weighed in logarithms against 1 (the estimate) by its errors
/// ([`VERTICAL_DEVIATION_RAD`], [`ESTIMATED_FOCAL_LOG_DEVIATION`]): a person who kept their
/// distance says little. `None` with fewer than [`MIN_FRAMES`] frames or no depth change. A
/// floor that really slopes towards the camera (stairs, a ramp) is taken for a focal
/// length's error. `rate` as [`onto_floor`] takes it.
pub(super) fn depth_factor(
    frames: &[Option<&Reconstruction>],
    seen: &[Option<(Matrix3, Vector3)>],
    up: &Vector3,
    rate: FrameRate,
) -> Option<f64> {
    let (numbers, lines): (Vec<usize>, Vec<[f64; 2]>) = frames
        .iter()
        .zip(seen)
        .enumerate()
        .filter_map(|(t, (f, s))| {
            let (r, (rotation, pelvis)) = ((*f)?, s.as_ref()?);
            let lowest = lowest_along(r, rotation, up);
            let depth = up.z * pelvis.z;
            Some((t, [up.dot(pelvis) - depth + lowest, depth]))
        })
        .unzip();
    if lines.len() < MIN_FRAMES {
        return None;
    }
    // Fitted to the lines averaged over a second or so: a frame's scale error moves its
    // pelvis along its ray, which changes `a` and `b` together (a factor of its own).
    let averaged = window_means(&numbers, &lines, PLANE_FRAMES * rate.step());
    let fit = |kept: &dyn Fn(usize) -> bool| -> Option<(f64, [f64; 2], f64)> {
        let chosen: Vec<[f64; 2]> = (0..lines.len())
            .filter(|&i| kept(i))
            .map(|i| averaged[i])
            .collect();
        let n = chosen.len() as f64;
        let mean = chosen
            .iter()
            .fold([0.0; 2], |m, l| [m[0] + l[0] / n, m[1] + l[1] / n]);
        let (sab, sbb) = chosen.iter().fold((0.0, 0.0), |(x, y), l| {
            (
                x + (l[0] - mean[0]) * (l[1] - mean[1]),
                y + (l[1] - mean[1]).powi(2),
            )
        });
        (sbb > 0.0).then(|| (-sab / sbb, mean, sbb))
    };
    // The frames' own residuals under the fit.
    let residuals = |k: f64, mean: [f64; 2]| -> Vec<f64> {
        lines
            .iter()
            .map(|l| (l[0] - mean[0]) + k * (l[1] - mean[1]))
            .collect()
    };
    let (k, mean, _) = fit(&|_| true)?;
    let first = residuals(k, mean);
    let bound = outlier_bound(first.iter().copied());
    let kept = |i: usize| first[i].abs() <= bound;
    let (k, mean, _) = fit(&kept)?;
    if !(k.is_finite() && k > 0.0) {
        return None;
    }
    // The frames' own spread: the larger of the residuals' and the one their contact and
    // scale deviations give (a frame's scale error moves its height by its share of the
    // pelvis's height along `up`); over the spread of the frames' own depths (a person who
    // kept their distance has only their scale errors'), in logarithms.
    let inliers: Vec<usize> = (0..lines.len()).filter(|&i| kept(i)).collect();
    let n = inliers.len() as f64;
    let mean_b = inliers.iter().map(|&i| lines[i][1]).sum::<f64>() / n;
    let sbb_own: f64 = inliers
        .iter()
        .map(|&i| (lines[i][1] - mean_b).powi(2))
        .sum();
    let own = residuals(k, mean);
    let spread = (inliers.iter().map(|&i| own[i].powi(2)).sum::<f64>() / n).sqrt();
    let expected = (inliers
        .iter()
        .map(|&i| {
            CONTACT_DEVIATION_M.powi(2)
                + (DEPTH_DEVIATION * (lines[i][0] + k * lines[i][1])).powi(2)
        })
        .sum::<f64>()
        / n)
        .sqrt();
    // A person whose depth changed no more than their scale errors would change it says
    // nothing of the factor.
    let mean_depth = inliers.iter().map(|&i| lines[i][1].abs()).sum::<f64>() / n;
    if sbb_own / n < (DEPTH_CHANGE_DEVIATIONS * DEPTH_DEVIATION * mean_depth).powi(2) {
        return None;
    }
    // And the vertical's error (a tilt of the vertical towards the camera raises the floor
    // with the depth as a factor does, by the tilt over `up.z`), weighed against the estimate.
    let error =
        (spread.max(expected) / sbb_own.sqrt() / k).hypot(VERTICAL_DEVIATION_RAD / up.z.abs());
    let (fit_weight, prior_weight) = (error.powi(-2), ESTIMATED_FOCAL_LOG_DEVIATION.powi(-2));
    let log = k.ln() * fit_weight / (fit_weight + prior_weight);
    log.is_finite().then(|| log.exp())
}

/// The mean of `values` (of frames `numbers`, ascending) over the frames within `half` frames
/// of each.
fn window_means<const N: usize>(
    numbers: &[usize],
    values: &[[f64; N]],
    half: usize,
) -> Vec<[f64; N]> {
    // (Sums over the values before each: a window's mean in O(1).)
    let mut sums = vec![[0.0; N]];
    for v in values {
        let last = sums[sums.len() - 1];
        sums.push(std::array::from_fn(|k| last[k] + v[k]));
    }
    numbers
        .iter()
        .map(|&t| {
            let from = numbers.partition_point(|&u| u + half < t);
            let to = numbers.partition_point(|&u| u <= t + half);
            let n = (to - from) as f64;
            std::array::from_fn(|k| (sums[to][k] - sums[from][k]) / n)
        })
        .collect()
}

/// [`OUTLIER_MEDIANS`] times the median of the sizes of `residuals` (at least one): a
/// residual beyond it is left out of the second fit.
fn outlier_bound(residuals: impl Iterator<Item = f64>) -> f64 {
    let mut sizes: Vec<f64> = residuals.map(f64::abs).collect();
    sizes.sort_by(f64::total_cmp);
    OUTLIER_MEDIANS * sizes[sizes.len() / 2]
}

/// The height along `up` of the lowest landmark of `r` turned by `rotation` (from its pelvis).
fn lowest_along(r: &Reconstruction, rotation: &Matrix3, up: &Vector3) -> f64 {
    r.pose
        .points
        .iter()
        .map(|x| up.dot(&(rotation * Vector3::from(*x))))
        .fold(f64::INFINITY, f64::min)
}

/// A frame's pelvis and its lowest landmark, in the camera frame.
struct Contact {
    /// The frame's index.
    frame: usize,
    /// The pelvis's place across the floor (two horizontal axes), metres.
    place: [f64; 2],
    /// The height along the vertical of the frame's lowest landmark, metres.
    height: f64,
    /// The pelvis, metres.
    pelvis: Vector3,
}

#[cfg(test)]
mod tests {
    use super::super::horizontal_axes;
    use super::*;
    use camloc_geometry::WeakPerspective;
    use camloc_skeleton::{NUM_LANDMARKS, Pose3};

    /// A walk across the floor under a camera 3 m up looking down by 26 deg, 5 m away: the
    /// frames, each frame's body -> camera rotation and pelvis (its depth off by `noise[t]`,
    /// a share), and the world's vertical in camera coordinates.
    fn walk(noise: &[f64]) -> (Vec<Reconstruction>, Vec<Seen>, Vector3) {
        walk_along(noise, [0.05, 0.0])
    }

    /// [`walk`] stepping by `step` (metres across the view and away from the camera) a frame.
    fn walk_along(noise: &[f64], step: [f64; 2]) -> (Vec<Reconstruction>, Vec<Seen>, Vector3) {
        let pitch = 26f64.to_radians();
        let (right, forward) = (Vector3::x(), Vector3::new(0.0, pitch.cos(), -pitch.sin()));
        let down = forward.cross(&right);
        // Rows: the camera's axes in world coordinates (world -> camera).
        let to_camera =
            Matrix3::from_rows(&[right.transpose(), down.transpose(), forward.transpose()]);
        let up = to_camera * Vector3::z();
        // The body frame is the world's, turned so that the person walks across the view.
        let mut points = [[0.0, 0.0, -0.5]; NUM_LANDMARKS];
        points[3] = [0.0, 0.1, -0.85];
        points[6] = [0.0, -0.1, -0.9];
        let frames = noise
            .iter()
            .map(|_| {
                let camera = WeakPerspective {
                    scale: 100.0,
                    rotation: Matrix3::identity(),
                    translation: [0.0; 2],
                };
                Reconstruction::seen_by(Pose3 { points }, camera)
            })
            .collect();
        let seen = noise
            .iter()
            .enumerate()
            .map(|(t, k)| {
                // The pelvis 0.9 m above the floor, the camera 3 m above it.
                let (x, y) = (step[0] * t as f64, step[1] * t as f64);
                let world = Vector3::new(-1.0 + x, 5.0 + y, 0.9 - 3.0);
                Some((to_camera, (1.0 + k) * (to_camera * world)))
            })
            .collect();
        (frames, seen, up)
    }

    /// A frame's body -> camera rotation and pelvis.
    type Seen = Option<(Matrix3, Vector3)>;

    /// The height along `up` of each frame's lowest landmark.
    fn lowest(
        frames: &[Reconstruction],
        seen: &[Option<(Matrix3, Vector3)>],
        up: &Vector3,
    ) -> Vec<f64> {
        frames
            .iter()
            .zip(seen)
            .map(|(r, s)| {
                let (rotation, pelvis) = s.unwrap();
                r.pose
                    .points
                    .iter()
                    .map(|x| up.dot(&(rotation * Vector3::from(*x) + pelvis)))
                    .fold(f64::INFINITY, f64::min)
            })
            .collect()
    }

    #[test]
    fn a_depth_error_seen_as_a_height_error_is_taken_out_and_a_jump_is_kept() {
        let noise: Vec<f64> = (0..40)
            .map(|t| 0.04 * ((t * 7 % 5) as f64 - 2.0) / 2.0)
            .collect();
        let (frames, mut seen, up) = walk(&noise);
        let refs: Vec<Option<&Reconstruction>> = frames.iter().map(Some).collect();
        let spread = |h: &[f64]| {
            h.iter().copied().fold(f64::NEG_INFINITY, f64::max)
                - h.iter().copied().fold(f64::INFINITY, f64::min)
        };
        let before = spread(&lowest(&frames, &seen, &up));
        // A jump: frame 20 half a metre up (along the vertical, not the ray).
        let jump = seen[20].unwrap().1 + 0.5 * up;
        seen[20] = Some((seen[20].unwrap().0, jump));
        onto_floor(
            &refs,
            &mut seen,
            &up,
            horizontal_axes(&up),
            FrameRate::default(),
        );
        assert_eq!(seen[20].unwrap().1, jump);
        let mut after = lowest(&frames, &seen, &up);
        after.remove(20);
        assert!(before > 0.1, "{before}");
        assert!(
            spread(&after) < 0.4 * before,
            "{} against {before}",
            spread(&after)
        );
        // Too few frames: nothing moves.
        let (frames, mut few, up) = walk(&noise[..MIN_FRAMES - 1]);
        let refs: Vec<Option<&Reconstruction>> = frames.iter().map(Some).collect();
        let unchanged = few.clone();
        onto_floor(
            &refs,
            &mut few,
            &up,
            horizontal_axes(&up),
            FrameRate::default(),
        );
        assert_eq!(few, unchanged);
    }

    /// A walk away from the camera whose depths are all 3 times too large (an estimated focal
    /// length's error) is told so; a walk across the view says nothing.
    #[test]
    fn an_estimated_focal_length_is_corrected_by_the_floor() {
        let noise: Vec<f64> = (0..40)
            .map(|t| 0.02 * ((t * 7 % 5) as f64 - 2.0) / 2.0)
            .collect();
        let tripled = |(frames, seen, up): (Vec<Reconstruction>, Vec<Seen>, Vector3)| {
            let seen: Vec<Seen> = seen
                .into_iter()
                .map(|s| s.map(|(r, p)| (r, Vector3::new(p.x, p.y, 3.0 * p.z))))
                .collect();
            (frames, seen, up)
        };
        let (frames, seen, up) = tripled(walk_along(&noise, [0.0, 0.08]));
        let refs: Vec<Option<&Reconstruction>> = frames.iter().map(Some).collect();
        let factor = depth_factor(&refs, &seen, &up, FrameRate::default()).unwrap();
        // Most of the way to 1/3 in logarithms (the rest is the vertical's possible tilt).
        let share = factor.ln() / (1.0f64 / 3.0).ln();
        assert!((0.8..=1.0).contains(&share), "{factor}");
        let (frames, seen, up) = tripled(walk(&noise));
        let refs: Vec<Option<&Reconstruction>> = frames.iter().map(Some).collect();
        assert_eq!(depth_factor(&refs, &seen, &up, FrameRate::default()), None);
    }
}
