//! Canonical body frame (docs/conventions.md section 1).

use super::error::CanonicaliseError;
use camloc_skeleton::{Landmark, Pose3};

/// Moves and turns a pose into the canonical body frame: pelvis at the origin, right side
/// towards +y, facing -x (z up, metres).
///
/// The pose is translated by `-pelvis` and rotated about z so that the horizontal part of
/// `(right_hip - left_hip) + (right_shoulder - left_shoulder)` points along +y. A rigid motion:
/// limb lengths and heights above the pelvis are kept.
///
/// # Errors
///
/// [`CanonicaliseError::NotFinite`] when a coordinate is infinite or NaN;
/// [`CanonicaliseError::NoLateralDirection`] when that horizontal vector is shorter than `1e-9`
/// times the pose's size (the largest landmark distance from the pelvis), e.g. a body lying
/// flat on its side or a pose with every landmark at one point.
pub fn canonicalise(pose: &Pose3) -> Result<Pose3, CanonicaliseError> {
    if !pose.is_finite() {
        return Err(CanonicaliseError::NotFinite);
    }
    let pelvis = pose.get(Landmark::Pelvis);
    let lateral = |right: Landmark, left: Landmark| {
        let (r, l) = (pose.get(right), pose.get(left));
        [r[0] - l[0], r[1] - l[1]]
    };
    let hips = lateral(Landmark::RightHip, Landmark::LeftHip);
    let shoulders = lateral(Landmark::RightShoulder, Landmark::LeftShoulder);
    let (hx, hy) = (hips[0] + shoulders[0], hips[1] + shoulders[1]);
    let horizontal_m = hx.hypot(hy);
    let size = pose
        .points
        .iter()
        .map(|p| {
            (p[0] - pelvis[0])
                .hypot(p[1] - pelvis[1])
                .hypot(p[2] - pelvis[2])
        })
        .fold(0.0, f64::max);
    if horizontal_m <= 1e-9 * size {
        return Err(CanonicaliseError::NoLateralDirection { horizontal_m });
    }
    // The rotation taking the unit vector (hx, hy) / |h| to (0, 1).
    let (c, s) = (hy / horizontal_m, hx / horizontal_m);
    Ok(Pose3::new(pose.points.map(|p| {
        let (x, y) = (p[0] - pelvis[0], p[1] - pelvis[1]);
        [c * x - s * y, s * x + c * y, p[2] - pelvis[2]]
    })))
}
