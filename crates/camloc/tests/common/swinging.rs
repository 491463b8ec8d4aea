//! A synthetic person whose arms and legs swing (included by the tests that need it:
//! `#[path = "common/swinging.rs"] mod swinging;`).

use camloc::Pose3;

/// A canonical pose (metres, facing -x, right side on +y) with arms and legs moved by `t`:
/// not a pose of the basis.
pub fn pose(t: f64) -> Pose3 {
    let (s, c) = (t.sin(), t.cos());
    Pose3::new([
        [0.0, 0.0, 0.0],
        [0.0, -0.1, -0.05],
        [-0.25 * s, -0.11, -0.46],
        [0.1 * c, -0.11, -0.88],
        [0.0, 0.1, -0.05],
        [0.2 * s, 0.12, -0.47],
        [-0.05 * c, 0.12, -0.9],
        [0.02, 0.0, 0.5],
        [-0.04, 0.0, 0.72],
        [0.02, -0.18, 0.46],
        [-0.2 + 0.1 * s, -0.25, 0.3],
        [-0.35 * c, -0.2, 0.3],
        [0.02, 0.18, 0.46],
        [0.1 - 0.1 * s, 0.25, 0.22],
        [-0.05, 0.3 * c, 0.05],
    ])
}
