//! The warnings the Python functions give (`UserWarning`), as the command line gives them on
//! standard error: points with v up, and rows of a sequence that jump between people.

use camloc::{
    HEIGHT_SHARE_MAX_POSES, PartialPose2, TorsoAnchor, head_below_ankles, identity_jumps,
    upside_down_warning,
};
use pyo3::exceptions::PyUserWarning;
use pyo3::prelude::*;

/// Gives `message` as a `UserWarning`.
fn warn(py: Python<'_>, message: String) -> PyResult<()> {
    let message = std::ffi::CString::new(message).unwrap_or_default();
    PyErr::warn(py, &py.get_type::<PyUserWarning>(), &message, 1)
}

/// Warns (`UserWarning`) when most of the first [`HEIGHT_SHARE_MAX_POSES`] poses of a call
/// (`leading`, [`PoseBatch::leading_poses`](crate::arrays::PoseBatch::leading_poses)) have the head below both ankles
/// (`camloc::upside_down_warning`, as the command line warns).
pub(crate) fn warn_if_upside_down(
    py: Python<'_>,
    leading: &[Option<PartialPose2>],
) -> PyResult<()> {
    let (mut checked, mut below) = (0, 0);
    for pose in leading.iter().take(HEIGHT_SHARE_MAX_POSES).flatten() {
        if let Some(b) = head_below_ankles(pose) {
            checked += 1;
            below += u64::from(b);
        }
    }
    match upside_down_warning(checked, below) {
        Some(warning) => warn(py, warning),
        None => Ok(()),
    }
}

/// Warns (`UserWarning`) when the rows of a sequence jump across the image or change size as
/// one person cannot (`camloc::identity_jumps`, as `camloc reconstruct --sequence` warns):
/// rows of several people, or a detector's order of people that changed. `poses` are the
/// rows in order, `None` for one that could not be mapped.
pub(crate) fn warn_of_identity_jumps<'a>(
    py: Python<'_>,
    poses: impl Iterator<Item = Option<&'a PartialPose2>>,
) -> PyResult<()> {
    let anchors: Vec<Option<TorsoAnchor>> = poses.map(|p| p.and_then(TorsoAnchor::of)).collect();
    let jumps = identity_jumps(&[], &anchors);
    let Some(first) = jumps.first() else {
        return Ok(());
    };
    let message = format!(
        "the pose jumps across the image or changes size from one row to the next at {} row(s) \
         (first at row {first}): these may be several people, or not consecutive frames of a \
         video; give one person's rows per call (read_keypoints gives each pose's person)",
        jumps.len()
    );
    warn(py, message)
}
