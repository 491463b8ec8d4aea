//! One person's reconstructed frames placed where a camera standing still saw them
//! ([`PoseReconstructor::place_in_world`]), upright as their localizations saw them.

use camloc_reconstruct::world_poses;
use camloc_skeleton::Pose3;

use crate::{PoseReconstruction, PoseReconstructor};

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
}
