//! Pixel coordinates stretched across or squeezed ([`StretchCheck`]): coordinates normalised
//! by the image's sides (MediaPipe, YOLO) multiplied by hand by the image's width and height
//! swapped come out (16/9)^2 times too wide or too narrow for their height, and every pose is
//! solved as a strange body without a word (a simulated user's phone video as arrays:
//! 12-class accuracy 95.8 -> 12.8%). [`ImageSizeCheck`](crate::ImageSizeCheck) checks an image
//! size camloc is given; this checks pixels it is not told how they were made.

use camloc_reconstruct::median;
use camloc_skeleton::PartialPose2;
use rayon::prelude::*;

use crate::conventions::within_unit_square;
use crate::image_size_check::{
    IMAGE_SIZE_CHECK_MIN_POSES, IMAGE_SIZE_CHECK_POSES, IMAGE_SIZE_SWAP_RATIO, WIDER_READING_RATIO,
    side_view_error,
};
use crate::{MIN_PRESENT_FOR_FILL, PoseReconstructor};

/// Fewest poses of an input for [`StretchCheck::measure`] to run, as for the camera-height
/// estimate: a call or run of fewer poses (a frame-by-frame loop) does not pay for it.
pub const STRETCH_CHECK_MIN_POSES: usize = 100;

/// The stretch across (x against y) of a 16:9 video's normalised coordinates multiplied by
/// its width and height swapped: (16/9)^2.
pub const VIDEO_STRETCH: f64 = (16.0 / 9.0) * (16.0 / 9.0);

/// How well the first poses of an input of pixel coordinates fit a body, over those seen from
/// a side in all three readings (a localized azimuth 30 deg or more from the front and the
/// back: a person seen from the front or back fits one twice as wide about as well): the
/// median reprojection error as given, narrower (x divided and y multiplied by the square root
/// of [`VIDEO_STRETCH`]: the same area, so that the pixel errors compare) and wider.
///
/// Measured (`/tmp/s71/st2/proto.py`, not in the repository: 29 CMU clips seen by Table 1's
/// 12 cameras, 4 m, 1000 px, 1.5 px noise; both readings below 0.8): none of 348 right-way
/// inputs warned, 160 of 348 stretched across by [`VIDEO_STRETCH`] and 196 of 348 squeezed,
/// each the right way (side views 23-29 of 29; front and back views 1-5 of 29: mostly not
/// compared). A reviewer's random real-world cameras (`/tmp/trial131`: 2-15 m, -60 to +70
/// deg, 400-3000 px, 16:9 and 4:3 sizes, noise up to 10 px or 3% of the person's height,
/// 1,600 inputs each way): 42 false warnings at 0.8, 41 of them "squeezed"; with the wider
/// reading below [`WIDER_READING_RATIO`], 1 false warning, and 403 of 1,600 swapped inputs
/// caught (157 portrait videos read as landscape, 246 the other way; (4/3)^2 swaps mostly
/// not).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StretchCheck {
    /// Poses compared (of the first [`IMAGE_SIZE_CHECK_POSES`]).
    pub poses: usize,
    /// Median reprojection error as given (pixels).
    pub given: f64,
    /// Median reprojection error narrower (the given pixels' units).
    pub narrower: f64,
    /// Median reprojection error wider (the given pixels' units).
    pub wider: f64,
}

impl StretchCheck {
    /// Solves the first [`IMAGE_SIZE_CHECK_POSES`] of `poses` (pixels) with
    /// [`MIN_PRESENT_FOR_FILL`] landmarks or more as given, narrower and wider with
    /// `reconstructor`, in parallel, and compares the fits of those seen from a side in all
    /// three. `None` for fewer than [`STRETCH_CHECK_MIN_POSES`] poses, for poses that
    /// all lie within the unit square (normalised coordinates, of which camloc warns on their
    /// own), or when fewer than [`IMAGE_SIZE_CHECK_MIN_POSES`] could be so compared.
    pub fn measure(reconstructor: &PoseReconstructor, poses: &[PartialPose2]) -> Option<Self> {
        if poses.len() < STRETCH_CHECK_MIN_POSES {
            return None;
        }
        // (Rows of nobody before a person comes into view are no poses to compare.)
        let first: Vec<&PartialPose2> = poses
            .iter()
            .filter(|p| p.points.iter().flatten().count() >= MIN_PRESENT_FOR_FILL)
            .take(IMAGE_SIZE_CHECK_POSES)
            .collect();
        if first.iter().all(|p| within_unit_square(p)) {
            return None;
        }
        let root = VIDEO_STRETCH.sqrt();
        let fits: Vec<[f64; 3]> = first
            .par_iter()
            .filter_map(|pose| {
                let fit = |sx: f64, sy: f64| side_view_error(reconstructor, pose, sx, sy);
                Some([
                    fit(1.0, 1.0)?,
                    fit(1.0 / root, root)?,
                    fit(root, 1.0 / root)?,
                ])
            })
            .collect();
        if fits.len() < IMAGE_SIZE_CHECK_MIN_POSES {
            return None;
        }
        let column = |k: usize| median(&mut fits.iter().map(|f| f[k]).collect::<Vec<_>>());
        Some(StretchCheck {
            poses: fits.len(),
            given: column(0)?,
            narrower: column(1)?,
            wider: column(2)?,
        })
    }

    /// Whether the poses fit a body clearly better narrower (`Some(true)`: stretched across;
    /// below [`IMAGE_SIZE_SWAP_RATIO`] of the given error) or wider (`Some(false)`: squeezed;
    /// below [`WIDER_READING_RATIO`]) than as given; the better of the two when both do;
    /// `None`: as given.
    pub fn stretched_across(&self) -> Option<bool> {
        let narrower = self.narrower < IMAGE_SIZE_SWAP_RATIO * self.given;
        let wider = self.wider < WIDER_READING_RATIO * self.given;
        match (narrower, wider) {
            (false, false) => None,
            (true, false) => Some(true),
            (false, true) => Some(false),
            (true, true) => Some(self.narrower <= self.wider),
        }
    }

    /// The warning, when the poses fit clearly better narrower or wider
    /// ([`stretched_across`](Self::stretched_across)), with the likely mistake and the
    /// video of that shape: `of the first 60 poses, the 41 seen from a side fit a body better
    /// with x divided by 3.16 against y than as given (median reprojection error 4.1 against
    /// 12.6 px): the coordinates look stretched across: were coordinates normalised by the
    /// image's sides multiplied by its width and height swapped? x = nx * width, y = ny *
    /// height (a portrait video is 1080 wide and 1920 high)`.
    pub fn warning(&self) -> Option<String> {
        let across = self.stretched_across()?;
        let (how, fit, what, video) = match across {
            true => (
                "divided",
                self.narrower,
                "stretched across",
                "a portrait video is 1080 wide and 1920 high",
            ),
            false => (
                "multiplied",
                self.wider,
                "squeezed",
                "a landscape video is 1920 wide and 1080 high",
            ),
        };
        Some(format!(
            "of the first {IMAGE_SIZE_CHECK_POSES} poses, the {} seen from a side fit a body \
             better with x {how} by {VIDEO_STRETCH:.2} against y than as given (median \
             reprojection error {fit:.1} against {:.1} px): the coordinates look {what}: were \
             coordinates normalised by the image's sides multiplied by its width and height \
             swapped? x = nx * width, y = ny * height ({video})",
            self.poses, self.given
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A standing figure (pixels, y down) shifted by `k` pixels.
    fn figure(k: usize) -> PartialPose2 {
        let base: [[f64; 2]; 15] = [
            [500.0, 500.0],
            [480.0, 500.0],
            [478.0, 600.0],
            [476.0, 700.0],
            [520.0, 500.0],
            [522.0, 600.0],
            [524.0, 700.0],
            [500.0, 350.0],
            [500.0, 300.0],
            [470.0, 360.0],
            [460.0, 430.0],
            [455.0, 500.0],
            [530.0, 360.0],
            [540.0, 430.0],
            [545.0, 500.0],
        ];
        PartialPose2 {
            points: base.map(|p| Some([p[0] + k as f64, p[1]])),
        }
    }

    #[test]
    fn too_few_poses_normalised_ones_and_front_views_are_not_measured() {
        let reconstructor = PoseReconstructor::default_reconstructor().unwrap();
        let few: Vec<PartialPose2> = (0..STRETCH_CHECK_MIN_POSES - 1).map(figure).collect();
        assert_eq!(StretchCheck::measure(&reconstructor, &few), None);
        let normalised: Vec<PartialPose2> = (0..STRETCH_CHECK_MIN_POSES)
            .map(|k| {
                let mut pose = figure(k);
                for p in pose.points.iter_mut().flatten() {
                    *p = [p[0] / 1080.0, p[1] / 1920.0];
                }
                pose
            })
            .collect();
        assert_eq!(StretchCheck::measure(&reconstructor, &normalised), None);
        // A figure facing the camera is not compared: it fits one twice as wide as well.
        let facing: Vec<PartialPose2> = (0..STRETCH_CHECK_MIN_POSES).map(figure).collect();
        assert_eq!(StretchCheck::measure(&reconstructor, &facing), None);
    }
}
