//! The floor of a placed sequence, from its planted ankles ([`level`]): heights that climb
//! along the path where the floor is level (from the camera's depth, whose error grows with
//! the distance) are taken out, and the floor is put under the planted feet rather than under
//! the one lowest landmark of the clip.

use camloc_skeleton::{Landmark, Pose3};

/// The steepest slope of the planted ankles' heights along the path that is taken out,
/// degrees; steeper, the person climbed (stairs) and the heights are kept. (It was 6 deg; a
/// simulated user's child filmed from 3 m up walked on a floor sloping 12 deg, from the
/// localizer's elevation for a body of a child's proportions.)
const MAX_SLOPE_DEG: f64 = 20.0;
/// The planted ankles set the slope only when they spread over at least this share of the
/// path (the extent of the frames' lowest landmarks); else the frames' lowest landmarks do (a
/// simulated user's diagonal walk under a camera 4 m up had 12 planted ankles in one place
/// and kept a floor sloping 10 deg).
const CONTACTS_EXTENT_SHARE: f64 = 0.5;
/// The fewest planted ankles that place the floor.
const MIN_CONTACTS: usize = 10;
/// The share of the planted ankles put below the floor: the floor is at this quantile of
/// their heights.
const BELOW_SHARE: f64 = 0.1;
/// Ridge weight on the slope, square metres per ankle (a spread of 10 cm): planted ankles
/// along a straight line leave the slope across it at 0.
const SLOPE_RIDGE_M2: f64 = 0.01;

/// Takes a slope gentler than [`MAX_SLOPE_DEG`] out of the heights of `placed` (z-up world,
/// metres): the plane fitted to the `contacts` (frame, planted ankle) is made level by
/// moving each frame up or down by the plane's height under its pelvis (the bodies keep
/// their orientation). With fewer than [`MIN_CONTACTS`] contacts, or contacts over less than
/// [`CONTACTS_EXTENT_SHARE`] of the path, the plane is fitted to each frame's lowest landmark (a simulated user's walks under a camera 3 m up found no planted
/// foot and kept floors sloping 5-7 deg; nothing moves with fewer such frames). Returns the
/// floor's height, the [`BELOW_SHARE`] quantile of the contacts' heights; `None` with fewer
/// than [`MIN_CONTACTS`] contacts.
pub(super) fn level(placed: &mut [Option<Pose3>], contacts: &[(usize, Landmark)]) -> Option<f64> {
    let planted: Vec<[f64; 3]> = contacts
        .iter()
        .filter_map(|&(t, l)| placed.get(t).copied().flatten().map(|p| p.get(l)))
        .collect();
    let lowest: Vec<[f64; 3]> = placed
        .iter()
        .flatten()
        .filter_map(|p| {
            p.points
                .iter()
                .copied()
                .min_by(|a, b| a[2].total_cmp(&b[2]))
        })
        .collect();
    // Planted ankles gathered in a part of the path tell nothing of the slope along the rest.
    let points = if planted.len() >= MIN_CONTACTS
        && extent(&planted) >= CONTACTS_EXTENT_SHARE * extent(&lowest)
    {
        planted
    } else {
        lowest
    };
    if points.len() < MIN_CONTACTS {
        return None;
    }
    let plane = Plane::fit(points.iter().copied());
    let [a, b] = plane.slope;
    let slope = a.hypot(b).atan().to_degrees();
    if slope.is_finite() && slope < MAX_SLOPE_DEG {
        for p in placed.iter_mut().flatten() {
            let pelvis = p.get(Landmark::Pelvis);
            let rise = plane.height_at(pelvis[0], pelvis[1]) - plane.mean[2];
            for q in &mut p.points {
                q[2] -= rise;
            }
        }
    }
    let mut heights: Vec<f64> = contacts
        .iter()
        .filter_map(|&(t, l)| placed.get(t).copied().flatten().map(|p| p.get(l)[2]))
        .collect();
    if heights.len() < MIN_CONTACTS {
        return None;
    }
    heights.sort_by(f64::total_cmp);
    Some(heights[((heights.len() - 1) as f64 * BELOW_SHARE).round() as usize])
}

/// The diagonal of the box of `points` across the floor (x, y), metres.
fn extent(points: &[[f64; 3]]) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in points {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (hi[0] - lo[0]).hypot(hi[1] - lo[1])
}

/// A plane `z = mean_z + a (x - mean_x) + b (y - mean_y)` fitted to points by least squares,
/// its slope ridged by [`SLOPE_RIDGE_M2`] per point.
pub(super) struct Plane {
    /// `[a, b]`: the rise per metre along x and y.
    pub(super) slope: [f64; 2],
    /// The points' mean.
    pub(super) mean: [f64; 3],
}

impl Plane {
    /// The plane of `points` (at least one; x, y across the floor and z up, metres).
    pub(super) fn fit(points: impl Iterator<Item = [f64; 3]> + Clone) -> Plane {
        let n = points.clone().count() as f64;
        let mean = points
            .clone()
            .fold([0.0; 3], |m, p| std::array::from_fn(|k| m[k] + p[k] / n));
        let (mut sxx, mut sxy, mut syy, mut sxz, mut syz) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for p in points {
            let (x, y, z) = (p[0] - mean[0], p[1] - mean[1], p[2] - mean[2]);
            sxx += x * x;
            sxy += x * y;
            syy += y * y;
            sxz += x * z;
            syz += y * z;
        }
        let ridge = SLOPE_RIDGE_M2 * n;
        let (sxx, syy) = (sxx + ridge, syy + ridge);
        let det = sxx * syy - sxy * sxy;
        Plane {
            slope: [(syy * sxz - sxy * syz) / det, (sxx * syz - sxy * sxz) / det],
            mean,
        }
    }

    /// The plane's height at `(x, y)`.
    pub(super) fn height_at(&self, x: f64, y: f64) -> f64 {
        self.mean[2] + self.slope[0] * (x - self.mean[0]) + self.slope[1] * (y - self.mean[1])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use camloc_skeleton::NUM_LANDMARKS;

    /// Frames of a walk along x, 2 m, whose heights climb by `slope` (metres per metre), the
    /// left ankle planted in each, the pelvis 0.9 m above it; and the contacts.
    fn climbing(slope: f64) -> (Vec<Option<Pose3>>, Vec<(usize, Landmark)>) {
        let placed = (0..40)
            .map(|t| {
                let x = 0.05 * t as f64;
                let mut points = [[x, 0.0, 0.9 + slope * x]; NUM_LANDMARKS];
                points[Landmark::LeftAnkle.index()] = [x, 0.0, slope * x];
                Some(Pose3 { points })
            })
            .collect();
        let contacts = (0..40).map(|t| (t, Landmark::LeftAnkle)).collect();
        (placed, contacts)
    }

    #[test]
    fn a_gentle_slope_is_levelled_and_the_floor_is_under_the_planted_feet() {
        let (mut placed, contacts) = climbing(0.05);
        let floor = level(&mut placed, &contacts).unwrap();
        for p in placed.iter().flatten() {
            assert!(
                (p.get(Landmark::LeftAnkle)[2] - floor).abs() < 0.01,
                "{p:?}"
            );
            assert!(
                (p.get(Landmark::Pelvis)[2] - p.get(Landmark::LeftAnkle)[2] - 0.9).abs() < 1e-12
            );
        }
    }

    /// Without planted ankles, or with planted ankles in one part of the path, the slope is
    /// fitted to each frame's lowest landmark: a gentle one is still levelled.
    #[test]
    fn a_gentle_slope_without_planted_feet_is_levelled_by_the_lowest_landmarks() {
        let spread = |placed: &[Option<Pose3>]| {
            let heights: Vec<f64> = placed
                .iter()
                .flatten()
                .map(|p| p.get(Landmark::LeftAnkle)[2])
                .collect();
            heights.iter().copied().fold(f64::NEG_INFINITY, f64::max)
                - heights.iter().copied().fold(f64::INFINITY, f64::min)
        };
        let (mut placed, _) = climbing(0.1);
        assert_eq!(level(&mut placed, &[]), None);
        assert!(spread(&placed) < 0.01, "{}", spread(&placed));
        // Planted ankles in the first quarter of the path only: the lowest landmarks decide.
        let (mut placed, contacts) = climbing(0.1);
        assert!(level(&mut placed, &contacts[..12]).is_some());
        assert!(spread(&placed) < 0.01, "{}", spread(&placed));
    }

    #[test]
    fn stairs_keep_their_climb_and_few_contacts_place_no_floor() {
        let (mut placed, contacts) = climbing(0.5);
        let before = placed.clone();
        let floor = level(&mut placed, &contacts).unwrap();
        assert_eq!(placed, before);
        assert!((floor - 0.1 * 0.5 * 0.05 * 39.0).abs() < 0.01, "{floor}");
        assert_eq!(level(&mut placed, &contacts[..MIN_CONTACTS - 1]), None);
    }
}
