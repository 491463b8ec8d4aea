//! A few frames of one person for the sequence tests (included by the tests that need them:
//! `#[path = "common/moving.rs"] mod moving;`; the reconstructor they use is
//! `common/hybrid.rs`'s).

use camloc::PartialPose2;
use camloc::skeleton::Pose2;

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
