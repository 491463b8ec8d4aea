//! The warnings that `--image-size` may be the wrong way round ([`ImageSizeCheck`]: for
//! coordinates normalised by the image's sides, MediaPipe's or YOLO's, the input's first poses
//! solved with the size as given and swapped) and, for pixels, that they look stretched across
//! or squeezed ([`StretchCheck`]: normalised coordinates multiplied by hand by the image's
//! width and height swapped).

use camloc::keypoints::{ImageSize, ReadOptions, sample_records};
use camloc::{
    ImageSizeCheck, PartialPose2, PoseReconstructor, STRETCH_CHECK_MIN_POSES, StretchCheck,
};

use super::InputArgs;

/// Says on standard error when `input` (a regular file or folder, not standard input) looks
/// scaled the wrong way: with `--image-size` scaling its coordinates (normalised by the
/// image's sides), when its first [`IMAGE_SIZE_CHECK_POSES`](camloc::IMAGE_SIZE_CHECK_POSES)
/// poses fit a body clearly better with the image's width and height swapped
/// ([`ImageSizeCheck`], as `reconstructor`, by default the embedded models' `hybrid`, solves
/// them); otherwise, for pixels of [`STRETCH_CHECK_MIN_POSES`] poses or more, when they fit a
/// body clearly better narrower or wider ([`StretchCheck`], as the embedded models' `hybrid`
/// solves them). Whether the size scales the input is read once, for both.
pub fn warn_of_image_scale(input: &InputArgs, reconstructor: Option<&PoseReconstructor>) {
    if input.is_standard_input() {
        return;
    }
    let options = input.options();
    let normalised = input.image_size.and_then(|size| {
        let poses =
            ImageSizeCheck::normalised_poses(input.path(), input.format, &options, input.recursive);
        poses.map(|poses| (poses, size))
    });
    // The embedded models are loaded only for an input one of the checks measures.
    let warning = match normalised {
        Some((poses, size)) => swapped_size_warning(&poses, size, reconstructor),
        None => stretch_warning(input, &options),
    };
    if let Some(warning) = warning {
        stderr_line!("camloc: warning: {warning}");
    }
}

/// The warning of an image size whose width and height `normalised` poses fit clearly better
/// swapped ([`ImageSizeCheck`]).
fn swapped_size_warning(
    normalised: &[PartialPose2],
    size: ImageSize,
    reconstructor: Option<&PoseReconstructor>,
) -> Option<String> {
    let check = match reconstructor {
        Some(given) => ImageSizeCheck::measure(given, normalised, size),
        None => PoseReconstructor::default_reconstructor()
            .ok()
            .and_then(|made| ImageSizeCheck::measure(&made, normalised, size)),
    };
    let check = check.filter(ImageSizeCheck::swapped_fits_better)?;
    Some(format!(
        "{check}: --image-size is width first (a portrait phone video is 1080,1920)"
    ))
}

/// The warning of pixels that fit a body clearly better narrower or wider ([`StretchCheck`]):
/// the first [`STRETCH_CHECK_MIN_POSES`] poses of `input` read with `options`, if it has so
/// many.
fn stretch_warning(input: &InputArgs, options: &ReadOptions) -> Option<String> {
    let records = sample_records(
        input.path(),
        input.format,
        options,
        input.recursive,
        STRETCH_CHECK_MIN_POSES,
    )
    .filter(|r| r.len() >= STRETCH_CHECK_MIN_POSES)?;
    let poses: Vec<PartialPose2> = records.iter().map(|r| r.pose).collect();
    let made = PoseReconstructor::default_reconstructor().ok()?;
    StretchCheck::measure(&made, &poses)?.warning()
}
