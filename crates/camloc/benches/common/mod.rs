//! The 2D poses the benches run on.

use camloc::Pose2;

/// A plausible standing pose in pixels, varied by `k` so that batches are not one pose.
pub fn pose(k: usize) -> Pose2 {
    let t = k as f64 * 0.001;
    Pose2::new([
        [320.0, 250.0],
        [338.0, 260.0],
        [339.0 + 5.0 * t.sin(), 337.0],
        [338.0, 411.0],
        [301.0, 260.0],
        [300.0 - 5.0 * t.cos(), 336.0],
        [300.0, 412.0],
        [319.0, 162.0],
        [320.0, 128.0],
        [353.0, 169.0],
        [361.0, 219.0 + 10.0 * t.sin()],
        [365.0, 263.0],
        [286.0, 169.0],
        [279.0, 221.0],
        [275.0 + 10.0 * t.cos(), 264.0],
    ])
}
