//! Held-out CMU walks filmed by a tripod camera and reconstructed as `camloc reconstruct
//! --sequence` does, for the tests of sequences that need 2D keypoints of real motion seen as
//! a camera standing still sees it.

#[path = "../held_out/mod.rs"]
mod held_out;
#[path = "../common/hybrid.rs"]
mod hybrid;

use std::path::Path;

use camloc::Pose3;
use camloc::mocap::{MocapIndex, MocapSource, MotionCategory, discover};
use camloc::skeleton::{Landmark, Pose2};
use held_out::HELD_OUT;
pub use hybrid::hybrid_reconstructor;

/// The walks of the held-out subjects in the CMU folder `cmu` (by the CMU index's
/// descriptions, not by folder), in clip order.
pub fn held_out_walks(cmu: &Path) -> Vec<MocapSource> {
    let index = MocapIndex::load(&cmu.join("cmu-mocap-index-text.txt")).unwrap();
    let mut walks: Vec<_> = discover(cmu)
        .unwrap()
        .into_iter()
        .filter(|s| {
            HELD_OUT.contains(&s.subject().as_str())
                && index.category(&s.subject(), &s.clip()).0 == MotionCategory::Walk
        })
        .collect();
    walks.sort_by_key(|s| s.clip());
    walks
}

/// Focal length of the tripod camera, pixels.
pub const FOCAL_PX: f64 = 1000.0;
/// Principal point of the tripod camera, pixels.
pub const PRINCIPAL: [f64; 2] = [960.0, 540.0];

/// The 2D keypoints of `poses` (metres, z-up world) seen by a camera standing still 1.5 m above
/// the floor (the lowest ankle of the clip) and 5 m across the floor from the clip's mean
/// pelvis, aimed at that pelvis.
pub fn tripod(poses: &[Pose3]) -> Vec<Pose2> {
    let n = poses.len() as f64;
    let mean: [f64; 3] =
        std::array::from_fn(|k| poses.iter().map(|p| p.points[0][k]).sum::<f64>() / n);
    let floor = poses
        .iter()
        .flat_map(|p| {
            [
                p.get(Landmark::LeftAnkle)[2],
                p.get(Landmark::RightAnkle)[2],
            ]
        })
        .fold(f64::INFINITY, f64::min);
    let eye = [mean[0] + 5.0, mean[1] + 1.0, floor + 1.5];
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let unit = |a: [f64; 3]| {
        let n = dot(a, a).sqrt();
        a.map(|c| c / n)
    };
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let z = unit(sub(mean, eye));
    let x = unit(cross(z, [0.0, 0.0, 1.0]));
    let y = cross(z, x);
    poses
        .iter()
        .map(|p| {
            Pose2::new(p.points.map(|q| {
                let d = sub(q, eye);
                let depth = dot(d, z);
                [
                    PRINCIPAL[0] + FOCAL_PX * dot(d, x) / depth,
                    PRINCIPAL[1] + FOCAL_PX * dot(d, y) / depth,
                ]
            }))
        })
        .collect()
}
