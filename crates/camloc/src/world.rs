//! One person's reconstructed frames placed where a camera standing still saw them
//! ([`PoseReconstructor::place_in_world`]), upright as their localizations saw them.

use camloc_reconstruct::world_poses;
use camloc_skeleton::Pose3;

use crate::{PoseReconstruction, PoseReconstructor, timeline_slots};

impl PoseReconstructor {
    /// The frames of one person filmed by one camera standing still, in time order (`None`:
    /// a frame without a reconstruction), placed in one z-up world of that camera, metres
    /// (`camloc::reconstruct::world_poses`, which says how): upright as each frame's
    /// localization saw the body (its continuous viewpoint), and, with the reconstructor's
    /// intrinsics when its principal point is given, placed by them. What
    /// `camloc reconstruct --sequence --bvh` animates.
    pub fn place_in_world(&self, frames: &[Option<&PoseReconstruction>]) -> Vec<Option<Pose3>> {
        let reconstructions: Vec<_> = frames
            .iter()
            .map(|f| f.map(|r| &r.reconstruction))
            .collect();
        let verticals: Vec<Option<[f64; 3]>> = frames
            .iter()
            .map(|f| {
                let rotation = (*f)?.localization.as_ref()?.viewpoint_rotation();
                Some(rotation.column(2).into_owned().into())
            })
            .collect();
        let fixed = self
            .given()
            .intrinsics
            .as_ref()
            .and_then(|i| i.principal_point.map(|c| (i.focal_px, c)));
        world_poses(&reconstructions, &verticals, fixed, self.frame_rate())
    }

    /// [`place_in_world`](Self::place_in_world) of one person's frames at their video frame
    /// `numbers` (in time order; see [`timeline_slots`]): the frame numbers the person is
    /// missing from count as time passing for the placement's windows (its smoothing, planted
    /// feet), as `camloc reconstruct --sequence --bvh` places a video's frames; of several
    /// frames at one number only the first reconstructed one is placed. Without numbers for
    /// every frame, in order, within `max_slots` frame numbers, the frames are placed as
    /// consecutive ones.
    pub fn place_on_timeline(
        &self,
        numbers: &[Option<u64>],
        frames: &[Option<&PoseReconstruction>],
        max_slots: usize,
    ) -> Vec<Option<Pose3>> {
        let Some(slots) = timeline_slots(numbers, max_slots, |m| {
            frames.get(m).is_some_and(Option::is_some)
        }) else {
            return self.place_in_world(frames);
        };
        let on_timeline: Vec<_> = slots
            .iter()
            .map(|s| s.and_then(|m| frames.get(m).copied().flatten()))
            .collect();
        let mut placed = vec![None; frames.len()];
        for (slot, pose) in slots.iter().zip(self.place_in_world(&on_timeline)) {
            if let Some(m) = slot {
                placed[*m] = pose;
            }
        }
        placed
    }
}
