//! Pixel coordinates stretched across or squeezed ([`StretchCheck`]): coordinates normalised
//! by the image's sides (MediaPipe, YOLO) multiplied by hand by a portrait video's width and
//! height swapped come out (16/9)^2 times too wide for their height, and every pose is solved
//! as a strange body without a word (a simulated user's phone video as arrays: 12-class
//! accuracy 95.8 -> 12.8%). [`ImageSizeCheck`](crate::ImageSizeCheck) checks an image size
//! camloc is given; this checks pixels it is not told how they were made.

use camloc_reconstruct::median;
use camloc_skeleton::PartialPose2;
use rayon::prelude::*;

use crate::PoseReconstructor;
use crate::conventions::within_unit_square;
use crate::image_size_check::{IMAGE_SIZE_CHECK_MIN_POSES, IMAGE_SIZE_CHECK_POSES, relative_fit};

/// Fewest poses of an input for [`StretchCheck::measure`] to run, as for the camera-height
/// estimate: a call or run of fewer poses (a frame-by-frame loop) does not pay for it.
pub const STRETCH_CHECK_MIN_POSES: usize = 100;

/// The stretch across (x against y) of a 16:9 video's normalised coordinates multiplied by
/// its width and height swapped: (16/9)^2.
pub const VIDEO_STRETCH: f64 = (16.0 / 9.0) * (16.0 / 9.0);

/// [`StretchCheck::stretched_across`] when the poses narrower or wider fit a body with a
/// median relative reprojection error below this share of theirs as given. Measured on 60
/// poses each: a simulated user's six phone clips (walk, run, jump, squats, a seated clip;
/// COCO-17 from MediaPipe-like normalised coordinates) and a held-out CMU walk seen by a
/// fixed camera, given the right way 0.93-2.95; LSP's 400 photos in groups of 60, 1.06-1.46;
/// stretched across by [`VIDEO_STRETCH`] (a portrait size given as landscape) 0.34-0.57 for
/// the clips and the walk and 0.69 for LSP's first 60 photos; squeezed as much, the walk 0.75.
pub const STRETCH_RATIO: f64 = 0.8;

/// How well the first poses of an input of pixel coordinates fit a body (the median over the
/// poses of the reconstruction's reprojection error over the 2D pose's spread) as given, with
/// x divided by [`VIDEO_STRETCH`] (unstretched) and with x multiplied by it (unsqueezed).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StretchCheck {
    /// Poses solved all three ways.
    pub poses: usize,
    /// Median relative reprojection error as given.
    pub given: f64,
    /// Median relative reprojection error with x divided by [`VIDEO_STRETCH`].
    pub narrower: f64,
    /// Median relative reprojection error with x multiplied by [`VIDEO_STRETCH`].
    pub wider: f64,
}

impl StretchCheck {
    /// Solves the first [`IMAGE_SIZE_CHECK_POSES`] of `poses` (pixels) as given, narrower
    /// and wider with `reconstructor`, in parallel, and compares the fits. `None` for fewer
    /// than [`STRETCH_CHECK_MIN_POSES`] poses, for poses that all lie within the unit square
    /// (normalised coordinates, of which camloc warns on their own), or when fewer than
    /// [`IMAGE_SIZE_CHECK_MIN_POSES`] of them could be solved all three ways.
    pub fn measure(reconstructor: &PoseReconstructor, poses: &[PartialPose2]) -> Option<Self> {
        let first = poses.get(..IMAGE_SIZE_CHECK_POSES)?;
        if poses.len() < STRETCH_CHECK_MIN_POSES || first.iter().all(within_unit_square) {
            return None;
        }
        let fits: Vec<[f64; 3]> = first
            .par_iter()
            .filter_map(|pose| {
                let fit = |sx| relative_fit(reconstructor, pose, sx, 1.0);
                Some([fit(1.0)?, fit(1.0 / VIDEO_STRETCH)?, fit(VIDEO_STRETCH)?])
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

    /// Whether the poses fit a body clearly better narrower (`Some(true)`: stretched across)
    /// or wider (`Some(false)`: squeezed) than as given ([`STRETCH_RATIO`]); `None`: as given.
    /// Narrower is taken whenever it fits better so: poses made much wider fit well as seen
    /// from high above (a walk towards the camera stretched across fitted 0.39 times as well
    /// widened again, at a median camera elevation of 81 deg, and 0.71 narrowed back), while
    /// squeezed poses narrowed further fitted no better (1.04-1.13).
    pub fn stretched_across(&self) -> Option<bool> {
        let better = |fit: f64| fit < STRETCH_RATIO * self.given;
        if better(self.narrower) {
            Some(true)
        } else if better(self.wider) {
            Some(false)
        } else {
            None
        }
    }
}

/// What was measured, for a warning: `the first 60 poses fit a body better with x divided
/// by 3.16 than as given (median reprojection error 0.040 against 0.101 of a pose's size):
/// stretched across`; empty when they fit as given.
impl std::fmt::Display for StretchCheck {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let Some(across) = self.stretched_across() else {
            return Ok(());
        };
        let (how, fit, what) = match across {
            true => ("divided", self.narrower, "stretched across"),
            false => ("multiplied", self.wider, "squeezed across"),
        };
        write!(
            f,
            "the first {} poses fit a body better with x {how} by {VIDEO_STRETCH:.2} than as \
             given (median reprojection error {fit:.3} against {:.3} of a pose's size): the \
             coordinates look {what}",
            self.poses, self.given
        )
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
    fn too_few_poses_and_normalised_ones_are_not_measured() {
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
        let enough: Vec<PartialPose2> = (0..STRETCH_CHECK_MIN_POSES).map(figure).collect();
        let check = StretchCheck::measure(&reconstructor, &enough).unwrap();
        assert_eq!(check.poses, IMAGE_SIZE_CHECK_POSES);
        assert!(check.given.is_finite() && check.narrower.is_finite() && check.wider.is_finite());
    }
}
