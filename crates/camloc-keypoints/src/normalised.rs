//! Coordinates normalised to [0, 1] by the image's sides (MediaPipe, YOLO), told from
//! coordinates in pixels given as such ([`check_normalised`]).

use crate::ImageSize;
use crate::error::{KeypointError, Location};

/// Farthest the middle of a pose's normalised coordinates may lie outside the image (in image
/// sides): MediaPipe places landmarks it guesses beyond the image's edges a little outside
/// [0, 1] (a close-up's ankles 6.5 sides below), and pixel coordinates lie hundreds of sides
/// away.
const NORMALISED_REACH: f64 = 5.0;

/// [`KeypointError::InvalidValue`] for the pose at `at` whose `points`' median x or y
/// coordinate (normalised) lies over [`NORMALISED_REACH`] image sides outside [0, 1]: pixels,
/// not normalised coordinates. `size` (1, 1) says that they are pixels; no point (a pose
/// without any keypoint kept) passes.
pub(crate) fn check_normalised(
    points: &[[f64; 2]],
    size: ImageSize,
    file: &str,
    at: Location,
) -> Result<(), KeypointError> {
    if (size.width == 1.0 && size.height == 1.0) || points.is_empty() {
        return Ok(());
    }
    for (c, key) in ["x", "y"].into_iter().enumerate() {
        let mut coordinates: Vec<f64> = points.iter().map(|p| p[c]).collect();
        coordinates.sort_by(f64::total_cmp);
        let median = coordinates[coordinates.len() / 2];
        if !(-NORMALISED_REACH..=1.0 + NORMALISED_REACH).contains(&median) {
            return Err(KeypointError::InvalidValue {
                file: file.to_owned(),
                at,
                field: key,
                text: format!("{median} (the frame's median)"),
                expected: "a normalised coordinate (MediaPipe's and YOLO's lie near [0, 1], a \
                           fraction of the image's side; coordinates already in pixels: \
                           --image-size 1,1, Python image_size=(1, 1))",
            });
        }
    }
    Ok(())
}
