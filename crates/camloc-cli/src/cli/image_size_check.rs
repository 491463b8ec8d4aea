//! The warning that `--image-size` may be the wrong way round ([`ImageSizeCheck`]): for
//! coordinates normalised by the image's sides (MediaPipe, YOLO), the input's first poses
//! solved with the size as given and swapped.

use std::path::Path;

use camloc::keypoints::{ImageSize, ReadOptions, sample_records};
use camloc::skeleton::PartialPose2;
use camloc::{IMAGE_SIZE_CHECK_POSES, ImageSizeCheck, PoseReconstructor};

use super::InputArgs;

/// Says on standard error when the first [`IMAGE_SIZE_CHECK_POSES`] poses of `input` (a
/// regular file or folder read with `--image-size`) fit a body clearly better, as
/// `reconstructor` solves them, with the image's width and height swapped. Inputs whose
/// coordinates the size does not scale (pixels) are not looked at, nor standard input.
pub fn warn_of_swapped_image_size(input: &InputArgs, reconstructor: &PoseReconstructor) {
    let Some(size) = input.image_size else {
        return;
    };
    if input.path() == Path::new("-") {
        return;
    }
    let options = input.options();
    let unit = ReadOptions {
        image_size: Some(ImageSize {
            width: 1.0,
            height: 1.0,
        }),
        ..options
    };
    let sample = |options: &ReadOptions| {
        sample_records(
            input.path(),
            input.format,
            options,
            input.recursive,
            IMAGE_SIZE_CHECK_POSES,
        )
    };
    let (Some(normalised), Some(given)) = (sample(&unit), sample(&options)) else {
        return;
    };
    // Only coordinates that the size scales: the same poses read in pixels are the same.
    let scaled = normalised.iter().zip(&given).any(|(a, b)| {
        a.pose
            .points
            .iter()
            .zip(&b.pose.points)
            .any(|(p, q)| matches!((p, q), (Some(p), Some(q)) if p != q))
    });
    if !scaled {
        return;
    }
    let poses: Vec<PartialPose2> = normalised.iter().map(|r| r.pose).collect();
    let Some(check) = ImageSizeCheck::measure(reconstructor, &poses, size) else {
        return;
    };
    if check.swapped_fits_better() {
        stderr_line!(
            "camloc: warning: the first {} poses fit a body much better with the image {}x{} \
             than {}x{} (median reprojection error {:.3} against {:.3} of a pose's size): \
             --image-size is width first (a portrait phone video is 1080,1920)",
            check.poses,
            size.height,
            size.width,
            size.width,
            size.height,
            check.swapped,
            check.given
        );
    }
}
