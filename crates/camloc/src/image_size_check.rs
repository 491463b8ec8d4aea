//! An image size given the wrong way round ([`ImageSizeCheck`]): coordinates normalised by the
//! image's sides (MediaPipe, YOLO) scaled by a portrait video's size given as landscape come
//! out stretched across, and every pose is solved as a strange body without a word (a
//! simulated user's phone video: PA-MPJPE 25 -> 173 mm).

use std::path::Path;

use camloc_keypoints::{ImageSize, KeypointFormat, ReadOptions, sample_records};
use camloc_reconstruct::median;
use camloc_skeleton::PartialPose2;

use crate::PoseReconstructor;
use crate::spread::centroid_and_spread;

/// Poses of an input that [`ImageSizeCheck::measure`] solves (twice each).
pub const IMAGE_SIZE_CHECK_POSES: usize = 60;

/// Fewest poses solved both ways for [`ImageSizeCheck::measure`] to tell.
pub const IMAGE_SIZE_CHECK_MIN_POSES: usize = 10;

/// [`ImageSizeCheck::swapped_fits_better`] when the other order's median relative
/// reprojection error is below this share of the given order's. Simulated users' videos (CMU
/// walks, runs, kicks and jumps as MediaPipe and YOLO files, 2-3 px of noise or 2% of the
/// height plus 1.5 px, `hybrid`): a portrait video given as landscape (stretched across)
/// 0.33-0.49, a landscape one given as portrait (squeezed: it looks like side views) 0.56-0.92;
/// given the right way, the other order 1.09-3.04 times worse. At 0.6 (before) a sports
/// user's landscape footage given as portrait went unsaid (12-class accuracy 89.6 -> 59.4%).
pub const IMAGE_SIZE_SWAP_RATIO: f64 = 0.95;

/// How well the first poses of an input fit a body (the median over the poses of the
/// reconstruction's reprojection error over the 2D pose's spread) with the image size as
/// given and with its sides swapped.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImageSizeCheck {
    /// The image size as given (pixels).
    pub size: ImageSize,
    /// Poses solved both ways.
    pub poses: usize,
    /// Median relative reprojection error with the size as given.
    pub given: f64,
    /// Median relative reprojection error with width and height swapped.
    pub swapped: f64,
}

impl ImageSizeCheck {
    /// Solves the first [`IMAGE_SIZE_CHECK_POSES`] of `normalised` (poses in coordinates
    /// divided by the image's width and height) scaled by `size` and by `size` swapped with
    /// `reconstructor`, and compares the fits. `None` for a square size, or when fewer than
    /// [`IMAGE_SIZE_CHECK_MIN_POSES`] poses could be solved both ways.
    pub fn measure(
        reconstructor: &PoseReconstructor,
        normalised: &[PartialPose2],
        size: ImageSize,
    ) -> Option<ImageSizeCheck> {
        let (w, h) = (size.width, size.height);
        if !(w.is_finite() && h.is_finite()) || w == h {
            return None;
        }
        let fit = |pose: &PartialPose2, sx: f64, sy: f64| -> Option<f64> {
            let mut scaled = *pose;
            for p in scaled.points.iter_mut().flatten() {
                *p = [p[0] * sx, p[1] * sy];
            }
            let points: Vec<[f64; 2]> = scaled.points.iter().flatten().copied().collect();
            let (_, spread) = centroid_and_spread(&points)?;
            let error = reconstructor
                .reconstruct(&scaled)
                .ok()?
                .reconstruction
                .projection_error;
            (error.is_finite()).then_some(error / spread)
        };
        let (mut given, mut swapped): (Vec<f64>, Vec<f64>) = normalised
            .iter()
            .take(IMAGE_SIZE_CHECK_POSES)
            .filter_map(|pose| Some((fit(pose, w, h)?, fit(pose, h, w)?)))
            .unzip();
        if given.len() < IMAGE_SIZE_CHECK_MIN_POSES {
            return None;
        }
        Some(ImageSizeCheck {
            size,
            poses: given.len(),
            given: median(&mut given)?,
            swapped: median(&mut swapped)?,
        })
    }

    /// The first [`IMAGE_SIZE_CHECK_POSES`] poses of the file or folder at `path` (read with
    /// `format`, `options` and `recursive`, as [`sample_records`] reads them) in coordinates
    /// divided by the image's sides, for [`ImageSizeCheck::measure`] at the size `options`
    /// gives. `None` without an image size, for standard input or a named pipe (not read
    /// again), and for inputs whose coordinates the size does not scale (pixels: the poses read
    /// at a size of 1 x 1 are the same).
    pub fn normalised_poses(
        path: &Path,
        format: Option<KeypointFormat>,
        options: &ReadOptions,
        recursive: bool,
    ) -> Option<Vec<PartialPose2>> {
        options.image_size?;
        let unit = ReadOptions {
            image_size: Some(ImageSize {
                width: 1.0,
                height: 1.0,
            }),
            ..*options
        };
        let sample = |options: &ReadOptions| {
            sample_records(path, format, options, recursive, IMAGE_SIZE_CHECK_POSES)
        };
        let (normalised, given) = (sample(&unit)?, sample(options)?);
        let scaled = normalised.iter().zip(&given).any(|(a, b)| {
            a.pose
                .points
                .iter()
                .zip(&b.pose.points)
                .any(|(p, q)| matches!((p, q), (Some(p), Some(q)) if p != q))
        });
        scaled.then(|| normalised.iter().map(|r| r.pose).collect())
    }

    /// Whether the poses fit a body clearly better with width and height swapped
    /// ([`IMAGE_SIZE_SWAP_RATIO`]).
    pub fn swapped_fits_better(&self) -> bool {
        self.swapped < IMAGE_SIZE_SWAP_RATIO * self.given
    }
}

/// What was measured, for a warning: `the first 60 poses fit a body better with the image
/// 1080x1920 than 1920x1080 (median reprojection error 0.048 against 0.147 of a pose's size)`.
impl std::fmt::Display for ImageSizeCheck {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (w, h) = (self.size.width, self.size.height);
        write!(
            f,
            "the first {} poses fit a body better with the image {h}x{w} than {w}x{h} \
             (median reprojection error {:.3} against {:.3} of a pose's size)",
            self.poses, self.swapped, self.given
        )
    }
}
