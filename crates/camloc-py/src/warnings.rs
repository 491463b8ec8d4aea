//! The warnings the Python functions give (`camloc.CamlocWarning`, a `UserWarning`), as the
//! command line gives them on standard error: points with v up, a rolled camera or joints at
//! the image origin, weakly scored landmarks used as detected, an image size that looks the
//! wrong way round, pixels that look stretched across or squeezed, legs or arms swapped back,
//! rows of a sequence that jump between people, and a call whose every pose failed.

use camloc::keypoints::WeakScores;
use camloc::reconstruct::{FrameRate, Intrinsics};
use camloc::{
    HEIGHT_SHARE_MAX_POSES, InputConventions, PartialPose2, TorsoAnchor, identity_jumps,
    left_out_of_sequence, swap_sides_back,
};
use camloc::{ImageSizeCheck, StretchCheck};
use pyo3::prelude::*;

/// Gives `message` as a [`CamlocWarning`](crate::CamlocWarning), which callers can filter
/// by its class instead of its text.
pub(crate) fn warn(py: Python<'_>, message: String) -> PyResult<()> {
    let message = std::ffi::CString::new(message).unwrap_or_default();
    PyErr::warn(py, &py.get_type::<crate::CamlocWarning>(), &message, 1)
}

/// Warns (`UserWarning`) when most of the first [`HEIGHT_SHARE_MAX_POSES`] poses of a call
/// (`leading`, [`PoseBatch::leading_poses`](crate::arrays::PoseBatch::leading_poses)) have the
/// head below both ankles or their torsos lean alike (points with v up, a camera upside down
/// or rolled) and when any has joints at the image origin, as the command line warns
/// (`camloc::InputConventions`, with the camera's intrinsics `aim` when given).
pub(crate) fn warn_of_input_conventions(
    py: Python<'_>,
    leading: &[Option<PartialPose2>],
    aim: Option<Intrinsics>,
) -> PyResult<()> {
    let mut conventions = InputConventions::aimed(aim);
    for pose in leading.iter().take(HEIGHT_SHARE_MAX_POSES).flatten() {
        conventions.add(pose);
    }
    for warning in conventions.warnings() {
        warn(py, warning)?;
    }
    Ok(())
}

/// Warns (`UserWarning`) when `counts` (the first poses of a call read at `min_score` 0) has
/// many weakly scored landmarks ([`WeakScores::worth_saying`]), as the command line warns at
/// `--min-score 0`: a detector writes coordinates for joints it cannot see.
pub(crate) fn warn_of_weak_scores(py: Python<'_>, counts: Option<WeakScores>) -> PyResult<()> {
    match counts {
        Some(counts) if counts.worth_saying() => warn(
            py,
            format!(
                "{counts} (min_score=0, the default): a detector writes coordinates for joints \
                 it cannot see; try min_score={}, which fills them in instead (with \
                 sequence=True from the frames around; a seated frame's hidden legs can come \
                 out standing)",
                counts.threshold()
            ),
        ),
        _ => Ok(()),
    }
}

/// Warns (`UserWarning`) when `check` (the first poses of a `read_keypoints` of coordinates
/// normalised by the image's sides) fits a body clearly better with the image size swapped
/// ([`ImageSizeCheck::swapped_fits_better`]), as `camloc localize` and `camloc reconstruct`
/// warn.
pub(crate) fn warn_of_swapped_image_size(
    py: Python<'_>,
    check: Option<ImageSizeCheck>,
) -> PyResult<()> {
    match check {
        Some(check) if check.swapped_fits_better() => warn(
            py,
            format!(
                "{check}: image_size is (width, height); a portrait phone video is (1080, 1920)"
            ),
        ),
        _ => Ok(()),
    }
}

/// Warns (`UserWarning`) when the first poses of a call (`leading`, 100 or more) fit a body
/// clearly better narrower or wider ([`StretchCheck`], solved with the defaults'
/// reconstructor), as `camloc localize` and `camloc reconstruct` warn: coordinates normalised
/// by the image's sides multiplied by its width and height swapped. Returns whether the check
/// could compare them (enough poses seen from a side), warned or not.
pub(crate) fn warn_of_stretch(py: Python<'_>, leading: &[Option<PartialPose2>]) -> PyResult<bool> {
    if leading.len() < camloc::STRETCH_CHECK_MIN_POSES {
        return Ok(false);
    }
    let poses: Vec<PartialPose2> = leading.iter().flatten().copied().collect();
    let reconstructor = crate::defaults::default_reconstructor()?;
    let check = py.detach(|| crate::pool::run(|| StretchCheck::measure(reconstructor, &poses)));
    let Some(check) = check else {
        return Ok(false);
    };
    if let Some(warning) = check.warning() {
        warn(
            py,
            format!("{warning}; NumPy's image.shape is (height, width)"),
        )?;
    }
    Ok(true)
}

/// Warns (`UserWarning`) when every one of `poses` (two or more) failed (`errors`: the
/// failures, by pose): with the first failure that is not "nothing detected" (an input
/// mistake, a layout that is not the array's, otherwise shows only in `error`), or, when no
/// pose had a landmark, as the command line says it (asking, with a `min_score` above 0,
/// whether it is above the scores' scale).
pub(crate) fn warn_if_every_pose_failed(
    py: Python<'_>,
    poses: usize,
    errors: &[(usize, String)],
    min_score: f64,
) -> PyResult<()> {
    if poses < 2 || errors.len() != poses {
        return Ok(());
    }
    // The library's own message for a pose without landmarks (a frame the person is missing
    // from, not a mistake on its own).
    let undetected = camloc::CamlocError::NothingDetected.to_string();
    let message = match errors.iter().find(|(_, e)| !e.ends_with(&undetected)) {
        Some((_, first)) => {
            format!("every one of the {poses} poses failed (see \"error\"); the first: {first}")
        }
        None if min_score > 0.0 => format!(
            "none of the {poses} poses has a landmark (nothing detected) at min_score \
             {min_score}: is it on the scale of the scores, or above all of them?"
        ),
        None => format!("none of the {poses} poses has a landmark (nothing detected)"),
    };
    warn(py, message)
}

/// The rows of a sequence (in time order, at frame numbers `rows`; those `left_out` of it
/// aside) with the limbs a detector swapped for a few frames swapped back
/// (`camloc::swap_sides_back`, as `camloc reconstruct --sequence` does), with a `UserWarning`
/// per chain, and per row whether its legs and its arms were swapped back (`[legs, arms]`,
/// the order of `camloc::SideChain::ALL`).
pub(crate) fn warn_of_swapped_sides(
    py: Python<'_>,
    mut poses: Vec<PartialPose2>,
    rows: &[Option<u64>],
    left_out: &[bool],
    rate: FrameRate,
) -> PyResult<(Vec<PartialPose2>, Vec<[bool; 2]>)> {
    let mut marks = vec![[false; 2]; poses.len()];
    for (c, (chain, swapped)) in swap_sides_back(rows, &mut poses, left_out, rate)
        .into_iter()
        .enumerate()
    {
        let Some(&first) = swapped.first() else {
            continue;
        };
        for &m in &swapped {
            marks[m][c] = true;
        }
        let message = format!(
            "the left and right {} of {} row(s) are swapped against the rows around them \
             (first at {}: a detector's confusion?): they are swapped back, as the \
             command line does (the result's swapped_sides)",
            chain.name(),
            swapped.len(),
            row_name(rows, first)
        );
        warn(py, message)?;
    }
    Ok((poses, marks))
}

/// Warns (`UserWarning`) when the rows of a sequence jump across the image or change size as
/// one person cannot (`camloc::identity_jumps`, as `camloc reconstruct --sequence` warns):
/// rows of several people, or a detector's order of people that changed. `poses` are the
/// rows in time order at frame numbers `rows`, `None` for one that could not be mapped; the
/// rows of a frame other than the person's (`camloc::left_out_of_sequence`: the pose nearest
/// the person's track is the person's) and those that lie apart from the rows around them
/// (another person's detection, a misplaced one) are warned of as `treated`, and the jumps
/// are looked for among the others. Returns, per row, whether it is left out so, as the
/// command line leaves it out.
pub(crate) fn warn_of_identity_jumps<'a>(
    py: Python<'_>,
    poses: impl Iterator<Item = Option<&'a PartialPose2>>,
    rows: &[Option<u64>],
    rate: FrameRate,
    treated: &str,
) -> PyResult<Vec<bool>> {
    let anchors: Vec<Option<TorsoAnchor>> = poses.map(|p| p.and_then(TorsoAnchor::of)).collect();
    let left_out = left_out_of_sequence(rows, &anchors, rate);
    if let Some(first) = left_out.second_poses.first() {
        let message = format!(
            "{} row(s) share their frame number with another row (first at {}): of a \
             frame's rows the one nearest where the person is expected is the person's, the \
             others are {treated} when untracked; for several tracked people give one person's \
             rows per call (read_keypoints gives each pose's person), with the \
             camera_height_shares and camera_height_elevations_deg of a call on all rows",
            left_out.second_poses.len(),
            row_name(rows, *first)
        );
        warn(py, message)?;
    }
    if let Some(first) = left_out.outliers.first() {
        let message = format!(
            "{} row(s) lie apart from the rows before and after them while those agree (first \
             at {}): another person's detection, or a misplaced one? They are {treated}",
            left_out.outliers.len(),
            row_name(rows, *first)
        );
        warn(py, message)?;
    }
    if let Some(first) = identity_jumps(rows, &left_out.kept_anchors(&anchors)).first() {
        let message = format!(
            "the pose jumps across the image or changes size from one row to the next (first \
             at {}): these may be several people, or not consecutive frames of a video; give \
             one person's rows per call (read_keypoints gives each pose's person)",
            row_name(rows, *first)
        );
        warn(py, message)?;
    }
    Ok(left_out.mask(anchors.len()))
}

/// How a warning names row `m` of a sequence whose rows are at frame numbers `rows`: `row 7`,
/// or `row 7 (frame 12)` when its frame number is not its row's (the command line names the
/// frame).
pub(crate) fn row_name(rows: &[Option<u64>], m: usize) -> String {
    match rows.get(m).copied().flatten() {
        Some(frame) if frame != m as u64 => format!("row {m} (frame {frame})"),
        _ => format!("row {m}"),
    }
}
