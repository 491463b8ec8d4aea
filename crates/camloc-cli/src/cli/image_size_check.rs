//! The warnings that `--image-size` may be the wrong way round ([`ImageSizeCheck`]: for
//! coordinates normalised by the image's sides, MediaPipe's or YOLO's, the input's first poses
//! solved with the size as given and swapped) and, for pixels, that they look stretched across
//! or squeezed ([`StretchCheck`]: normalised coordinates multiplied by hand by the image's
//! width and height swapped).

use camloc::keypoints::sample_records;
use camloc::{ImageSizeCheck, PoseReconstructor, STRETCH_CHECK_MIN_POSES, StretchCheck};

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

/// Says on standard error when the first poses of `input` (a regular file or folder of pixel
/// coordinates, of [`STRETCH_CHECK_MIN_POSES`] poses or more; not coordinates `--image-size`
/// scales, which [`warn_of_swapped_image_size`] checks) fit a body clearly better narrower or
/// wider ([`StretchCheck`]), as the embedded models' `hybrid` solves them.
pub fn warn_of_stretch(input: &InputArgs) {
    if input.is_standard_input() {
        return;
    }
    let options = input.options();
    let scaled = input.image_size.is_some()
        && ImageSizeCheck::normalised_poses(input.path(), input.format, &options, input.recursive)
            .is_some();
    if scaled {
        return;
    }
    let records = sample_records(
        input.path(),
        input.format,
        &options,
        input.recursive,
        STRETCH_CHECK_MIN_POSES,
    );
    let Some(records) = records.filter(|r| r.len() >= STRETCH_CHECK_MIN_POSES) else {
        return;
    };
    let poses: Vec<_> = records.iter().map(|r| r.pose).collect();
    let warning = PoseReconstructor::default_reconstructor()
        .ok()
        .and_then(|made| StretchCheck::measure(&made, &poses))
        .and_then(|check| Some((check.warning()?, check.stretched_across()?)));
    if let Some((warning, across)) = warning {
        let size = if across {
            "1080 wide, 1920 high"
        } else {
            "1920 wide, 1080 high"
        };
        stderr_line!(
            "camloc: warning: {warning}: were coordinates normalised by the image's sides \
             multiplied by its width and height swapped? x = nx * width, y = ny * height (a \
             {} video is {size})",
            if across { "portrait" } else { "landscape" }
        );
    }
}
