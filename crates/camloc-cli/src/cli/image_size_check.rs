//! The warning that `--image-size` may be the wrong way round ([`ImageSizeCheck`]): for
//! coordinates normalised by the image's sides (MediaPipe, YOLO), the input's first poses
//! solved with the size as given and swapped.

use camloc::{ImageSizeCheck, PoseReconstructor};

use super::InputArgs;

/// Says on standard error when the first
/// [`IMAGE_SIZE_CHECK_POSES`](camloc::IMAGE_SIZE_CHECK_POSES) poses of `input` (a
/// regular file or folder of coordinates normalised by the image's sides, read with
/// `--image-size`) fit a body clearly better with the image's width and height swapped, as
/// `reconstructor` (by default the embedded models' `hybrid`) solves them.
pub fn warn_of_swapped_image_size(input: &InputArgs, reconstructor: Option<&PoseReconstructor>) {
    let Some(size) = input.image_size.filter(|_| !input.is_standard_input()) else {
        return;
    };
    let poses = ImageSizeCheck::normalised_poses(
        input.path(),
        input.format,
        &input.options(),
        input.recursive,
    );
    // The embedded models are loaded only for an input the size scales.
    let Some(poses) = poses else {
        return;
    };
    let check = match reconstructor {
        Some(given) => ImageSizeCheck::measure(given, &poses, size),
        None => PoseReconstructor::default_reconstructor()
            .ok()
            .and_then(|made| ImageSizeCheck::measure(&made, &poses, size)),
    };
    if let Some(check) = check.filter(ImageSizeCheck::swapped_fits_better) {
        stderr_line!(
            "camloc: warning: {check}: --image-size is width first (a portrait phone video is \
             1080,1920)"
        );
    }
}
