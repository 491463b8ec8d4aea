//! What an input's poses say of how they were given, counted pose by pose as they are read
//! ([`InputConventions`]), for the warnings `camloc localize`, `camloc reconstruct` and Python
//! give alike: points with `v` up, a camera upside down or rolled
//! ([`orientation_warning`]), and detectors' placeholders at the image origin
//! ([`origin_placeholder_warning`]).

use camloc_reconstruct::Intrinsics;
use camloc_skeleton::PartialPose2;

use crate::{
    LeanHistogram, aimed_at_pelvis, has_origin_placeholders, head_below_ankles,
    orientation_warning, origin_placeholder_warning,
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
    /// The poses' torso leans.
    leans: LeanHistogram,
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
        let aimed = self.aim.and_then(|k| aimed_at_pelvis(pose, &k).ok());
        self.leans.add(aimed.as_ref().unwrap_or(pose));
        if let Some(below) = head_below_ankles(pose) {
            self.upside_down.0 += 1;
            self.upside_down.1 += u64::from(below);
        }
    }

    /// The warnings of the poses counted: [`orientation_warning`], then
    /// [`origin_placeholder_warning`].
    pub fn warnings(&self) -> impl Iterator<Item = String> {
        let (checked, upside_down) = self.upside_down;
        orientation_warning(checked, upside_down, &self.leans)
            .into_iter()
            .chain(origin_placeholder_warning(
                self.poses,
                self.origin_placeholders,
            ))
    }
}
