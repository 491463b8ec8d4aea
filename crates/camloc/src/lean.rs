//! Whether the camera of an input was rolled about its optical axis (a handheld phone held
//! askew, a portrait video read as landscape): the poses' torsos lean alike in the image. camloc
//! takes images upright, and a simulated user's views lost 6 points of 12-class accuracy at
//! 20 deg of roll, 59 points at 45 deg and 70 at 90 deg, with confident answers.

use camloc_keypoints::derive_torso;
use camloc_skeleton::{Landmark, PartialPose2};

/// The smallest lean of an input's torsos, degrees, that [`orientation_warning`]
/// warns of (at 20 deg of roll a simulated user's views lost 6 points of accuracy; upright
/// walking and sitting people lean a few degrees).
pub const TILT_WARNING_DEG: f64 = 20.0;

/// The fewest poses with a torso for [`orientation_warning`] to judge a roll: one person
/// bending over is not a rolled camera.
pub const TILT_MIN_POSES: u64 = 5;

/// How far the torso of `pose` leans from the image's vertical, degrees in (-180, 180]: 0
/// when the neck is straight above the pelvis (`v` down), positive when it is to the right of
/// the pelvis (the person turned clockwise as the image is shown), ±180 upside down. The
/// pelvis stands in for the hips' midpoint and the neck for the shoulders' where missing;
/// `None` without them (or with a point at exactly `(0, 0)`, a detector's placeholder, or
/// one not finite).
pub fn torso_lean_deg(pose: &PartialPose2) -> Option<f64> {
    // The torso rule of docs/conventions.md section 3, placeholders left out.
    let mut torso = *pose;
    for point in &mut torso.points {
        *point = point.filter(|p| *p != [0.0, 0.0]);
    }
    derive_torso(&mut torso);
    let pelvis = torso.points[Landmark::Pelvis.index()]?;
    let neck = torso.points[Landmark::Neck.index()]?;
    let (dx, dy) = (neck[0] - pelvis[0], neck[1] - pelvis[1]);
    ((dx != 0.0 || dy != 0.0) && dx.is_finite() && dy.is_finite())
        .then(|| dx.atan2(-dy).to_degrees())
}

/// How far each shin of `pose` leans from the image's vertical, degrees in (-180, 180] as
/// [`torso_lean_deg`] measures it (0 when the knee is straight above the ankle); `None` for
/// a leg without knee or ankle (or with one at exactly `(0, 0)`, or not finite).
pub fn shin_leans_deg(pose: &PartialPose2) -> [Option<f64>; 2] {
    let lean = |knee: Landmark, ankle: Landmark| {
        let present = |l: Landmark| pose.points[l.index()].filter(|p| *p != [0.0, 0.0]);
        let (knee, ankle) = (present(knee)?, present(ankle)?);
        let (dx, dy) = (knee[0] - ankle[0], knee[1] - ankle[1]);
        ((dx != 0.0 || dy != 0.0) && dx.is_finite() && dy.is_finite())
            .then(|| dx.atan2(-dy).to_degrees())
    };
    [
        lean(Landmark::LeftKnee, Landmark::LeftAnkle),
        lean(Landmark::RightKnee, Landmark::RightAnkle),
    ]
}

/// Leans of an input's poses (torsos, [`torso_lean_deg`], or shins, [`shin_leans_deg`])
/// counted in 1-degree bins: the memory of a million poses is that of one.
#[derive(Clone, Debug)]
pub struct LeanHistogram {
    /// Poses per degree, bin `k` holding the leans in `[k - 180, k - 179)`.
    bins: Box<[u64; 360]>,
    /// Poses counted.
    count: u64,
}

impl Default for LeanHistogram {
    fn default() -> Self {
        LeanHistogram {
            bins: Box::new([0; 360]),
            count: 0,
        }
    }
}

impl LeanHistogram {
    /// Counts the torso lean of `pose`, if it has one.
    pub fn add(&mut self, pose: &PartialPose2) {
        if let Some(lean) = torso_lean_deg(pose) {
            self.add_deg(lean);
        }
    }

    /// Counts the shin leans of `pose` (one for each leg that has one).
    pub fn add_shins(&mut self, pose: &PartialPose2) {
        for lean in shin_leans_deg(pose).into_iter().flatten() {
            self.add_deg(lean);
        }
    }

    /// Counts a lean, degrees (a finite one; others are not counted).
    fn add_deg(&mut self, lean: f64) {
        if lean.is_finite() {
            let bin = ((lean + 180.0).floor() as usize).min(359);
            self.bins[bin] += 1;
            self.count += 1;
        }
    }

    /// Poses counted.
    pub fn count(&self) -> u64 {
        self.count
    }

    /// The input's lean, degrees in (-180, 180]: the circular median of the leans (the
    /// 1-degree bin whose summed angular distance to all of them is least, refined to the
    /// mean direction of the leans within [`TILT_NEAR_DEG`] of it),
    /// which neither wraps at ±180 deg as a median of numbers does nor follows a minority of
    /// people lying down as a mean does; `None` before any pose or when the leans spread too
    /// evenly to have a direction (the mean of their unit vectors shorter than
    /// [`TILT_MIN_AGREEMENT`]).
    pub fn typical_deg(&self) -> Option<f64> {
        if self.count == 0 {
            return None;
        }
        let centre = |k: usize| (k as f64 - 179.5).to_radians();
        let (mut x, mut y) = (0.0, 0.0);
        for (k, &n) in self.bins.iter().enumerate() {
            x += n as f64 * centre(k).cos();
            y += n as f64 * centre(k).sin();
        }
        let n = self.count as f64;
        if (x / n).hypot(y / n) < TILT_MIN_AGREEMENT {
            return None;
        }
        // Angular distance between bins, in bins (degrees).
        let apart = |a: usize, b: usize| {
            let d = a.abs_diff(b);
            d.min(360 - d) as f64
        };
        // The summed distance is least at a bin that holds leans (a circular median lies on
        // a datum), and only those bins add to it: a call of one pose costs one bin, not
        // 360 x 360 (a simulated user's per-pose calls spent 79% of their time here).
        let held: Vec<(usize, f64)> = (self.bins.iter().enumerate())
            .filter(|(_, n)| **n > 0)
            .map(|(k, &n)| (k, n as f64))
            .collect();
        let cost = |c: usize| -> f64 { held.iter().map(|&(k, n)| n * apart(c, k)).sum() };
        let best = (held.iter().map(|&(k, _)| k)).min_by(|&a, &b| cost(a).total_cmp(&cost(b)))?;
        // The mean direction of the leans within TILT_NEAR_DEG of that bin: its degree, not
        // the bin's middle.
        let (mut x, mut y) = (0.0, 0.0);
        for (k, &n) in self.bins.iter().enumerate() {
            if apart(best, k) <= TILT_NEAR_DEG {
                x += n as f64 * centre(k).cos();
                y += n as f64 * centre(k).sin();
            }
        }
        Some(y.atan2(x).to_degrees())
    }

    /// The share of the poses whose lean is within [`TILT_NEAR_DEG`] of `lean_deg`.
    pub fn share_near(&self, lean_deg: f64) -> f64 {
        if self.count == 0 {
            return 0.0;
        }
        let near: u64 = (self.bins.iter().enumerate())
            .filter(|(k, _)| {
                let d = (*k as f64 - 179.5 - lean_deg).rem_euclid(360.0);
                d.min(360.0 - d) <= TILT_NEAR_DEG + 0.5
            })
            .map(|(_, &n)| n)
            .sum();
        near as f64 / self.count as f64
    }
}

/// The least lean of the input's shins ([`LeanHistogram::add_shins`]), degrees the same way
/// as its torsos', for [`orientation_warning`] to take leaning torsos for a rolled camera:
/// the shins of people standing, walking and sitting are near upright, and rolled with the
/// camera. A simulated lab's studio cameras (level, 60 views of 15 clips, 25-160 frames
/// each) had two seated people leaning forward warned of as rolled, torsos 20 and 21 deg,
/// shins 3-5 deg; turned by 20, 25 and 30 deg, 26 of 28, 40 of 46 and 53 of 54 views whose
/// torsos lean 20 deg or more have their shins lean 10 deg or more the same way.
pub const TILT_SHIN_DEG: f64 = 10.0;

/// Whether the shins counted in `shins` leave torsos leaning `torso_deg` (degrees) to a
/// rolled camera ([`TILT_SHIN_DEG`]): too few shins or no direction of theirs, or their lean
/// that far the same way.
fn shins_lean_too(shins: &LeanHistogram, torso_deg: f64) -> bool {
    if shins.count() < TILT_MIN_POSES {
        return true;
    }
    shins
        .typical_deg()
        .is_none_or(|s| s.abs() >= TILT_SHIN_DEG && s.signum() == torso_deg.signum())
}

/// How near a pose's lean must be to the input's, degrees, to count as leaning alike
/// ([`LeanHistogram::share_near`]; upright walking and sitting people lean within about 10).
pub const TILT_NEAR_DEG: f64 = 15.0;

/// How much the torsos of an input must agree for [`LeanHistogram::typical_deg`] to give
/// their lean: the length of the mean of their unit vectors (1 when all lean alike, 0.7 for
/// leans spread evenly over ±80 deg).
pub const TILT_MIN_AGREEMENT: f64 = 0.5;

/// The warning for an input whose poses are not upright in the image, `None` otherwise:
/// - when most of the `checked` poses that have a head and both ankles have the head below
///   both (`upside_down` of them, [`head_below_ankles`](crate::head_below_ankles)): points
///   given with `v` up (to be flipped), or a camera upside down (to be turned by the
///   input's lean, [`LeanHistogram::typical_deg`]; flipping would mirror the people, front
///   for back);
/// - else when the input's lean is [`TILT_WARNING_DEG`] or more from upright over at least
///   [`TILT_MIN_POSES`] poses, more than half of them within [`TILT_NEAR_DEG`] of it, and the
///   shins (`shins`, [`LeanHistogram::add_shins`]) lean [`TILT_SHIN_DEG`] or more the same way
///   (or fewer than [`TILT_MIN_POSES`] of them, or too spread to have a direction): a camera
///   rolled about its axis.
pub fn orientation_warning(
    checked: u64,
    upside_down: u64,
    leans: &LeanHistogram,
    shins: &LeanHistogram,
) -> Option<String> {
    let lean = leans.typical_deg();
    let turn = |lean: f64| {
        let way = if lean > 0.0 {
            "counterclockwise"
        } else {
            "clockwise"
        };
        format!(
            "{:.0} deg {way} (as the image is shown) about the image centre",
            lean.abs()
        )
    };
    if 2 * upside_down > checked {
        let by = lean
            .filter(|l| l.abs() >= 90.0)
            .map_or_else(|| "180 deg about the image centre".to_owned(), turn);
        return Some(format!(
            "{upside_down} of {checked} poses have the head below both ankles: camloc takes \
             image coordinates with v down (image rows); flip v if the input's v points up, \
             but if the camera was upside down (the image turned, v down) turn the keypoints \
             {by} instead: flipping would mirror the people, front for back (people on their \
             hands are seen as they are)"
        ));
    }
    // Most poses must lean alike: a large minority lying down moves the median of the rest.
    let lean = lean.filter(|&l| {
        leans.count() >= TILT_MIN_POSES
            && l.abs() >= TILT_WARNING_DEG
            && 2.0 * leans.share_near(l) > 1.0
            && shins_lean_too(shins, l)
    })?;
    Some(format!(
        "the poses' torsos lean {:.0} deg from the image's vertical (of {} poses): was the \
         camera rolled (a phone held askew, a portrait video read as landscape)? camloc takes \
         the image upright; turn the keypoints {}. People lying, crawling, sitting on the \
         floor or bent over lean too, as do people walking seen from a camera looking steeply \
         down: then ignore this; and so do keypoints read in a joint order other than theirs \
         (check --layout, Python's layout=: COCO-17 read as h36m17 leaned 177 deg)",
        lean.abs(),
        leans.count(),
        turn(lean)
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn torso(neck: [f64; 2]) -> PartialPose2 {
        let mut pose = PartialPose2::empty();
        pose.points[Landmark::Pelvis.index()] = Some([100.0, 200.0]);
        pose.points[Landmark::Neck.index()] = Some([100.0 + neck[0], 200.0 + neck[1]]);
        pose
    }

    #[test]
    fn leaning_torsos_are_measured_and_a_rolled_input_warned_of() {
        let close = |a: Option<f64>, b: f64| assert!((a.unwrap() - b).abs() < 1e-9, "{a:?}");
        close(torso_lean_deg(&torso([0.0, -50.0])), 0.0);
        close(torso_lean_deg(&torso([50.0, -50.0])), 45.0);
        close(torso_lean_deg(&torso([-50.0, 0.0])), -90.0);
        close(torso_lean_deg(&torso([0.0, 50.0])), 180.0);
        assert_eq!(torso_lean_deg(&PartialPose2::empty()), None);
        // Upright people: no warning (without shins to tell).
        let none = LeanHistogram::default();
        let mut leans = LeanHistogram::default();
        for _ in 0..10 {
            leans.add(&torso([3.0, -50.0]));
        }
        assert!(orientation_warning(0, 0, &leans, &none).is_none());
        // Torsos leaning about 30 deg to the right: turn the keypoints back counterclockwise.
        let at = |deg: f64| {
            let a = deg.to_radians();
            torso([a.sin() * 50.0, -a.cos() * 50.0])
        };
        let mut rolled = LeanHistogram::default();
        for k in 0..10 {
            rolled.add(&at(25.0 + k as f64));
        }
        let warning = orientation_warning(0, 0, &rolled, &none).unwrap();
        assert!(warning.contains("lean 30 deg") && warning.contains("30 deg counterclockwise"));
        // A joint order other than the layout's leans too, and the warning says so.
        assert!(warning.contains("a joint order other than theirs (check --layout"));
        // Shins upright or leaning the other way: people leaning, not a rolled camera; shins
        // leaning the same way: rolled.
        let shins_at = |deg: f64| {
            let mut shins = LeanHistogram::default();
            for _ in 0..10 {
                let a = deg.to_radians();
                let mut pose = PartialPose2::empty();
                pose.points[Landmark::LeftAnkle.index()] = Some([50.0, 400.0]);
                pose.points[Landmark::LeftKnee.index()] =
                    Some([50.0 + a.sin() * 40.0, 400.0 - a.cos() * 40.0]);
                shins.add_shins(&pose);
            }
            shins
        };
        assert_eq!(shin_leans_deg(&PartialPose2::empty()), [None, None]);
        assert!((shins_at(30.0).typical_deg().unwrap() - 30.0).abs() <= 0.5);
        assert!(orientation_warning(0, 0, &rolled, &shins_at(4.0)).is_none());
        assert!(orientation_warning(0, 0, &rolled, &shins_at(-25.0)).is_none());
        assert!(orientation_warning(0, 0, &rolled, &shins_at(25.0)).is_some());
        // Too few poses: none.
        let mut few = LeanHistogram::default();
        few.add(&at(30.0));
        assert!(orientation_warning(0, 0, &few, &none).is_none());
        // Leans spread evenly all round have no direction.
        let mut spread = LeanHistogram::default();
        for k in 0..36 {
            spread.add(&at(10.0 * k as f64));
        }
        assert_eq!(spread.typical_deg(), None);
        // A third of the people lying down does not make upright ones rolled (a mean of
        // directions had said 22-39 deg).
        let mut lying = LeanHistogram::default();
        for k in 0..10 {
            lying.add(&at(if k < 7 { 2.0 } else { 90.0 }));
        }
        assert!(lying.typical_deg().unwrap().abs() < 3.0);
        assert!(orientation_warning(0, 0, &lying, &none).is_none());
        // A camera upside down, about ±180 (which a median of numbers put near 0 and called
        // a roll of 72 deg), or at 150: the upside-down warning, with the turn that helps.
        let mut turned = LeanHistogram::default();
        for k in 0..10 {
            turned.add(&at(if k % 2 == 0 { 178.0 } else { -178.0 }));
        }
        assert!(turned.typical_deg().unwrap().abs() > 178.0);
        let warning = orientation_warning(10, 10, &turned, &none).unwrap();
        assert!(warning.contains("head below") && warning.contains("turn the keypoints 18"));
        let mut tilted = LeanHistogram::default();
        for _ in 0..10 {
            tilted.add(&at(150.0));
        }
        let warning = orientation_warning(10, 10, &tilted, &none).unwrap();
        assert!(
            warning.contains("turn the keypoints 150 deg counterclockwise"),
            "{warning}"
        );
        assert!(orientation_warning(10, 5, &leans, &none).is_none());
    }
}
