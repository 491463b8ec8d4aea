//! A few frames of one person for the sequence tests, and the reconstructor they use (included
//! by the tests that need them: `#[path = "common/moving.rs"] mod moving;`).

use camloc::skeleton::Pose2;
use camloc::{
    CameraLocalizer, DepthLifter, ModeKind, PartialPose2, PoseReconstructor, default_basis,
};

/// `count` frames: the example's first pose, moved and bent a little more in each.
pub fn frames(count: usize) -> Vec<PartialPose2> {
    let pose = crate::common::example_records()[0].pose.complete().unwrap();
    (0..count)
        .map(|t| {
            let f = t as f64;
            let mut points = pose.points;
            for (j, p) in points.iter_mut().enumerate() {
                p[0] += 4.0 * f + 3.0 * (0.7 * f + j as f64).sin();
                p[1] += 2.0 * (1.3 * f + 2.0 * j as f64).cos();
            }
            PartialPose2::from(Pose2::new(points))
        })
        .collect()
}

/// The embedded basis, model and lifter, `hybrid` (the command line's default).
pub fn hybrid_reconstructor() -> PoseReconstructor {
    PoseReconstructor::new(default_basis().unwrap())
        .unwrap()
        .with_localizer(CameraLocalizer::default_model().unwrap())
        .with_lifter(DepthLifter::default_lifter().unwrap())
        .with_mode(ModeKind::Hybrid)
        .unwrap()
}
