//! What an input's poses say of how they were given, counted pose by pose as they are read
//! ([`InputConventions`]), for the warnings `camloc localize`, `camloc reconstruct` and Python
//! give alike: points with `v` up, a camera upside down or rolled
//! ([`orientation_warning`]), detectors' placeholders at the image origin
//! ([`origin_placeholder_warning`]), coordinates normalised by the image's sides, and poses
//! of too few landmarks to be more than guessed at.

use camloc_keypoints::derive_torso;
use camloc_reconstruct::Intrinsics;
use camloc_skeleton::{Landmark, PartialPose2};

use crate::{
    LeanHistogram, MIN_PRESENT_FOR_FILL, aimed_at_pelvis, has_origin_placeholders,
    head_below_ankles, orientation_warning, origin_placeholder_warning,
};

/// The counts behind an input's warnings (the memory of a million poses is that of one).
#[derive(Clone, Debug, Default)]
pub struct InputConventions {
    /// Poses counted.
    poses: u64,
    /// Poses with a head and both ankles, and of those the poses whose head is below both
    /// ([`head_below_ankles`]).
    upside_down: (u64, u64),
    /// Poses with landmarks at the image origin ([`has_origin_placeholders`]).
    origin_placeholders: u64,
    /// Poses whose landmarks all lie within the unit square ([`within_unit_square`]).
    unit_square: u64,
    /// Poses with a torso and fewer than [`MIN_PRESENT_FOR_FILL`] landmarks
    /// ([`localized_from_few`]).
    few_landmarks: u64,
    /// The poses' torso leans.
    leans: LeanHistogram,
    /// The poses' shin leans.
    shins: LeanHistogram,
    /// The camera's intrinsics, when given: the leans are those of the poses as the camera
    /// aimed at each would see them ([`aimed_at_pelvis`]), as they are localized (a person
    /// in a corner of a wide-angle image leans in the image without any roll).
    aim: Option<Intrinsics>,
}

impl InputConventions {
    /// Counts for the poses of a camera of known intrinsics (`None`: unknown).
    pub fn aimed(aim: Option<Intrinsics>) -> InputConventions {
        InputConventions {
            aim,
            ..InputConventions::default()
        }
    }

    /// Counts `pose`.
    pub fn add(&mut self, pose: &PartialPose2) {
        self.poses += 1;
        self.origin_placeholders += u64::from(has_origin_placeholders(pose));
        self.unit_square += u64::from(within_unit_square(pose));
        self.few_landmarks += u64::from(localized_from_few(pose));
        let aimed = self.aim.and_then(|k| aimed_at_pelvis(pose, &k).ok());
        self.leans.add(aimed.as_ref().unwrap_or(pose));
        self.shins.add_shins(aimed.as_ref().unwrap_or(pose));
        if let Some(below) = head_below_ankles(pose) {
            self.upside_down.0 += 1;
            self.upside_down.1 += u64::from(below);
        }
    }

    /// The warnings of the poses counted: [`orientation_warning`],
    /// [`origin_placeholder_warning`], the warning of an input whose every coordinate lies
    /// within [0, 1] (normalised by the image's sides), then that of poses with fewer than
    /// [`MIN_PRESENT_FOR_FILL`] landmarks.
    pub fn warnings(&self) -> impl Iterator<Item = String> {
        let (checked, upside_down) = self.upside_down;
        orientation_warning(checked, upside_down, &self.leans, &self.shins)
            .into_iter()
            .chain(origin_placeholder_warning(
                self.poses,
                self.origin_placeholders,
            ))
            .chain(normalised_coordinates_warning(self.poses, self.unit_square))
            .chain(few_landmarks_warning(self.poses, self.few_landmarks))
    }
}

/// How far outside [0, 1] a normalised landmark may lie (in image sides): people partly out of
/// the image have some a little outside it.
const UNIT_SQUARE_MARGIN: f64 = 0.5;

/// Whether every landmark of `pose` (two or more) lies within [0, 1] in both coordinates,
/// give or take [`UNIT_SQUARE_MARGIN`]: image coordinates divided by the image's sides (YOLO
/// pose labels, OpenPose's `--keypoint_scale 3`, MediaPipe's before `--image-size`), which no
/// pixel pose has.
pub(crate) fn within_unit_square(pose: &PartialPose2) -> bool {
    let mut present = 0;
    let within = pose.points.iter().flatten().all(|point| {
        present += 1;
        point
            .iter()
            .all(|c| (-UNIT_SQUARE_MARGIN..=1.0 + UNIT_SQUARE_MARGIN).contains(c))
    });
    within && present >= 2
}

/// The warning for an input of which every one of the `checked` poses lies within the unit
/// square ([`within_unit_square`]): only a scale shared by both axes leaves the answer
/// unchanged, and coordinates divided by an image's width and by its height squash the pose
/// (a simulated user's 16:9 views: diagonal and high cameras 22-36 deg off). `None`
/// otherwise.
fn normalised_coordinates_warning(checked: u64, within: u64) -> Option<String> {
    (checked > 0 && within == checked).then(|| {
        format!(
            "every coordinate of the {checked} pose(s) lies within about [0, 1]: normalised by \
             the image's width and height? That squashes the pose unless the image is \
             square (diagonal and high views of a 16:9 image came out 22-36 deg off): give \
             pixels (x times the width, y times the height); coordinates divided by one \
             number for both are right as they are"
        )
    })
}

/// Whether `pose` has a torso (its pelvis and neck, or the hips and shoulders they are
/// derived from) but fewer than [`MIN_PRESENT_FOR_FILL`] landmarks: `localize` reads its
/// camera from those few, the others at their training means (a pose without a torso and as
/// few landmarks fails with its own error instead, and `reconstruct` refuses both).
fn localized_from_few(pose: &PartialPose2) -> bool {
    let present = pose.points.iter().flatten().count();
    if present >= MIN_PRESENT_FOR_FILL {
        return false;
    }
    let mut torso = *pose;
    derive_torso(&mut torso);
    torso.points[Landmark::Pelvis.index()].is_some()
        && torso.points[Landmark::Neck.index()].is_some()
}

/// The warning for `few` of the `checked` poses being [`localized_from_few`]: a camera
/// localized from a pelvis and a neck (13 landmarks imputed) had been answered like any other,
/// 21% probable, without a word. `None` when no pose is.
fn few_landmarks_warning(checked: u64, few: u64) -> Option<String> {
    (few > 0).then(|| {
        format!(
            "{few} of the {checked} pose(s) have a torso but fewer than {MIN_PRESENT_FOR_FILL} \
             of the 15 landmarks: `localize` reads their camera from those few (the others \
             at their training means: a guess), `reconstruct` refuses them (in a sequence, \
             unless the frames around fill a short gap in)"
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coordinates_normalised_by_the_image_s_sides_are_warned_of() {
        let mut pose = PartialPose2::empty();
        for (k, p) in pose.points.iter_mut().enumerate() {
            *p = Some([0.4 + 0.01 * k as f64, 0.2 + 0.04 * k as f64]);
        }
        let mut normalised = InputConventions::default();
        normalised.add(&pose);
        let said: Vec<String> = normalised.warnings().collect();
        assert!(
            said.iter().any(|w| w.contains("lies within about [0, 1]")),
            "{said:?}"
        );
        // The same pose in pixels, or one pixel pose among them: no such warning.
        let pixels = PartialPose2 {
            points: pose
                .points
                .map(|p| p.map(|[x, y]| [1920.0 * x, 1080.0 * y])),
        };
        for poses in [vec![pixels], vec![pose, pixels]] {
            let mut counted = InputConventions::default();
            for p in &poses {
                counted.add(p);
            }
            assert!(counted.warnings().all(|w| !w.contains("[0, 1]")));
        }
    }

    #[test]
    fn poses_of_too_few_landmarks_are_warned_of() {
        let mut counted = InputConventions::default();
        let mut pose = PartialPose2::empty();
        counted.add(&pose);
        for k in 0..pose.points.len() {
            pose.points[k] = Some([100.0 + k as f64, 50.0 + 20.0 * k as f64]);
            counted.add(&pose);
        }
        // The poses of 1 to 7 landmarks here (the pelvis, then the legs, in `LANDMARKS` order)
        // have no neck and no shoulders to derive one from: no torso, not counted (they fail
        // with their own error).
        let said: Vec<String> = counted.warnings().collect();
        assert!(said.iter().all(|w| !w.contains("fewer than")), "{said:?}");
        // A pelvis and a neck, with up to 5 more: warned of.
        let mut sparse = PartialPose2::empty();
        sparse.points[Landmark::Pelvis.index()] = Some([100.0, 200.0]);
        sparse.points[Landmark::Neck.index()] = Some([100.0, 100.0]);
        counted.add(&sparse);
        let said: Vec<String> = counted.warnings().collect();
        assert!(
            said.iter()
                .any(|w| w.starts_with("1 of the 17 pose(s) have a torso but fewer than 8")),
            "{said:?}"
        );
        let mut full = InputConventions::default();
        full.add(&pose);
        assert!(full.warnings().all(|w| !w.contains("fewer than")));
    }
}
