//! An image size given the wrong way round ([`ImageSizeCheck`]): coordinates normalised by the
//! image's sides (MediaPipe, YOLO) scaled by a portrait video's size given as landscape come
//! out stretched across, and every pose is solved as a strange body without a word (a
//! simulated user's phone video: PA-MPJPE 25 -> 173 mm).

use std::path::Path;

use camloc_keypoints::{ImageSize, KeypointFormat, ReadOptions, sample_records};
use camloc_reconstruct::median;
use camloc_skeleton::PartialPose2;

use crate::PoseReconstructor;

/// Poses of an input that [`ImageSizeCheck::measure`] solves (twice each).
pub const IMAGE_SIZE_CHECK_POSES: usize = 60;

/// Fewest poses solved both ways for [`ImageSizeCheck::measure`] to tell.
pub const IMAGE_SIZE_CHECK_MIN_POSES: usize = 10;

/// [`ImageSizeCheck::swapped_fits_better`] when the other order reads the poses narrower
/// (a landscape size given: the other is portrait) and its median reprojection error is below
/// this share of the given order's, over the poses seen from a side ([`SIDE_VIEW_MIN_SINE`]).
/// Both orders scale the normalised coordinates by the same area (width x height), so their
/// pixel errors compare as they are. Measured with [`WIDER_READING_RATIO`]: over 29 CMU clips
/// seen by Table 1's 12 cameras (4 m, 1000 px, 1.5 px noise, the person at the centre of a
/// portrait and of a landscape image), 1 of 696 right-way inputs warned and 295 of 696
/// wrong-way ones (3 and 342 with 0.8 both ways); over a reviewer's random real-world cameras
/// (`/tmp/trial131`: 2-15 m, -60 to +70 deg, 400-3000 px, the person anywhere in the image,
/// 16:9 and 4:3 sizes, noise 0.25-3% of the person's height), 3 of 700 right-way inputs
/// warned and 265 of 700 wrong-way ones (16 and 357 with 0.8 both ways).
pub const IMAGE_SIZE_SWAP_RATIO: f64 = 0.8;

/// As [`IMAGE_SIZE_SWAP_RATIO`] when the other reading is the wider one (a portrait size
/// given): a wider body fits too easily (people seen from below or above, small noisy people),
/// and 15 of the reviewer's 16 false warnings at 0.8 were such readings.
pub const WIDER_READING_RATIO: f64 = 0.6;

/// The sine of the least angle from the front or back (azimuth 180 or 0 deg) of the poses
/// [`ImageSizeCheck::measure`] compares, read both ways: a person seen from the front or back
/// fits a wider or narrower image about as well (twice as wide shoulders and hips), and such
/// views made most of the check's false alarms (sin 30 deg).
pub const SIDE_VIEW_MIN_SINE: f64 = 0.5;

/// How well the first poses of an input fit a body (the median over the poses of the
/// reconstruction's reprojection error, pixels) with the image size as given and with its
/// sides swapped.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImageSizeCheck {
    /// The image size as given (pixels).
    pub size: ImageSize,
    /// Poses solved both ways and seen from a side both ways.
    pub poses: usize,
    /// Median reprojection error with the size as given (pixels).
    pub given: f64,
    /// Median reprojection error with width and height swapped (pixels).
    pub swapped: f64,
}

impl ImageSizeCheck {
    /// Solves the first [`IMAGE_SIZE_CHECK_POSES`] of `normalised` (poses in coordinates
    /// divided by the image's width and height) scaled by `size` and by `size` swapped with
    /// `reconstructor`, and compares the fits of those seen from a side both ways (a
    /// localized azimuth 30 deg or more from the front and the back). `None` for a square
    /// size, or when fewer than [`IMAGE_SIZE_CHECK_MIN_POSES`] poses could be so compared.
    pub fn measure(
        reconstructor: &PoseReconstructor,
        normalised: &[PartialPose2],
        size: ImageSize,
    ) -> Option<ImageSizeCheck> {
        let (w, h) = (size.width, size.height);
        if !(w.is_finite() && h.is_finite()) || w == h {
            return None;
        }
        let fit =
            |pose: &PartialPose2, sx: f64, sy: f64| side_view_error(reconstructor, pose, sx, sy);
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
    /// ([`IMAGE_SIZE_SWAP_RATIO`], or [`WIDER_READING_RATIO`] when the swapped order reads
    /// them wider: a portrait size given).
    pub fn swapped_fits_better(&self) -> bool {
        let ratio = if self.size.width < self.size.height {
            WIDER_READING_RATIO
        } else {
            IMAGE_SIZE_SWAP_RATIO
        };
        self.swapped < ratio * self.given
    }
}

/// The reprojection error (in the scaled pose's units) of `pose` with its x scaled by `sx` and
/// its y by `sy`, as `reconstructor` solves it, when it is seen from a side
/// ([`SIDE_VIEW_MIN_SINE`]); `None` otherwise or when it cannot be solved.
pub(crate) fn side_view_error(
    reconstructor: &PoseReconstructor,
    pose: &PartialPose2,
    sx: f64,
    sy: f64,
) -> Option<f64> {
    let mut scaled = *pose;
    for p in scaled.points.iter_mut().flatten() {
        *p = [p[0] * sx, p[1] * sy];
    }
    let solved = reconstructor.reconstruct(&scaled).ok()?;
    let azimuth = solved.localization?.azimuth_deg?.to_radians();
    let error = solved.reconstruction.projection_error;
    (error.is_finite() && azimuth.sin().abs() >= SIDE_VIEW_MIN_SINE).then_some(error)
}

/// What was measured, for a warning: `of the first 60 poses, the 41 seen from a side fit a
/// body better with the image 1080x1920 than 1920x1080 (median reprojection error 4.1 against
/// 12.6 px)`.
impl std::fmt::Display for ImageSizeCheck {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (w, h) = (self.size.width, self.size.height);
        write!(
            f,
            "of the first {IMAGE_SIZE_CHECK_POSES} poses, the {} seen from a side fit a body \
             better with the image {h}x{w} than {w}x{h} (median reprojection error {:.1} \
             against {:.1} px)",
            self.poses, self.swapped, self.given
        )
    }
}
