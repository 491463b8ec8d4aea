//! The input's own camera elevation: the viewpoint heads regress toward the elevations they
//! were trained on, so a camera higher than those is read lower; over an input's many views
//! that regression is undone to estimate its middle cameras' mean elevation, and each
//! middle-ring viewpoint is then moved to regress toward it instead
//! ([`HeightShares::elevations_deg`]; docs/conventions.md section 5).

use camloc_geometry::Level;
use camloc_skeleton::PartialPose2;
use rayon::prelude::*;

use crate::height_shares::HeightShares;
use crate::{CameraHeight, CameraLocalizer};

/// Views at the training's mean elevation added to an input's own when its middle cameras'
/// mean elevation is estimated ([`HeightShares::elevations_deg`]): one person's short clip
/// errs alike in most of its frames (the same build and posture read in each), so it moves
/// the estimate little. Chosen among 5, 10, 20 and 40 on two simulated labs: clips of
/// one person and one action per input, level cameras (1-17 views each), median viewpoint
/// error 4.5, 4.3, 4.3, 4.2 deg (4.2 without the move); an office's eight cameras, one file
/// each (300-500 views), 6.8, 6.8, 6.8, 6.7 deg (7.6 without it; docs/measured.md).
pub const ELEVATION_PSEUDO_VIEWS: f64 = 40.0;

impl CameraLocalizer {
    /// The mean camera elevation per height (lower, middle, upper; degrees above the pelvis)
    /// of the input whose localizable poses are `poses` (each weighing its entry of
    /// `weights`, the share of an independent view it is worth): every pose localized under
    /// `shares`, and for those put at the middle height, their elevations read without their
    /// head's shrinkage ([`ElevationFit::unbiased_deg`]) averaged, each weighing its weight
    /// times the square of its head's slope (the inverse of the unshrunk reading's variance
    /// when the heads' errors are alike: a front view's head, which regresses most, counts
    /// least), with [`ELEVATION_PSEUDO_VIEWS`] views at the training's mean elevation added
    /// (a few views move it little). Only the middle height's is estimated: at the lower edge
    /// of the upper ring, where high room cameras stand, the upper heads do not regress as
    /// their fits say (`rig` views 26 deg and more above the pelvis, read as one input per
    /// band of elevation: 1.6 and -1.4 deg mean error without the shift, -4.9 and -7.0 with
    /// it; docs/measured.md). `None` for the other heights, for a middle height no pose was
    /// put at, without viewpoint heads, and for a camera set with more than one ring in the
    /// middle band (a custom sphere's rings at -20, 0 and 20 deg: one mean moved the 20 deg
    /// ring's views 15 deg down, a simulated user's finding).
    pub(crate) fn input_elevations(
        &self,
        poses: &[&PartialPose2],
        weights: &[f64],
        shares: HeightShares,
    ) -> [Option<f64>; 3] {
        let Some(heads) = &self.viewpoint else {
            return [None; 3];
        };
        if self.several_middle_rings() {
            return [None; 3];
        }
        let under = self
            .clone()
            .with_camera_height(CameraHeight::Shares(shares));
        let answers: Vec<Option<(usize, f64)>> = poses
            .par_iter()
            .map(|pose| {
                let l = under.localize_partial(pose).ok()?;
                Some((l.label.index(), l.elevation_deg?))
            })
            .collect();
        let middle = |class: usize| self.cameras.viewpoints()[class].level == Level::Middle;
        let (mut sum, mut total) = (0.0, 0.0);
        for (answer, weight) in answers.iter().zip(weights) {
            if let Some((class, elevation)) = *answer
                && middle(class)
            {
                let fit = heads.elevation_fit(class);
                let w = weight * fit.slope * fit.slope;
                sum += w * fit.unbiased_deg(elevation);
                total += w;
            }
        }
        let classes: Vec<usize> = (0..self.cameras.len()).filter(|&c| middle(c)).collect();
        if total <= 0.0 || classes.is_empty() {
            return [None; 3];
        }
        // The pseudo-views weigh as views of the level's mean slope.
        let (mut prior, mut slope) = (0.0, 0.0);
        for &c in &classes {
            let fit = heads.elevation_fit(c);
            prior += fit.true_mean_deg / classes.len() as f64;
            slope += fit.slope / classes.len() as f64;
        }
        let pseudo = ELEVATION_PSEUDO_VIEWS * slope * slope;
        let mean = ((sum + pseudo * prior) / (total + pseudo)).clamp(-90.0, 90.0);
        let mut elevations = [None; 3];
        elevations[Level::Middle.index()] = Some(mean);
        elevations
    }

    /// Degrees to add to the elevation that the head of camera class `class` (0-based)
    /// predicts, under this localizer's [`CameraHeight`]: the head's
    /// [`ElevationFit::shift_deg`](camloc_learning::ElevationFit::shift_deg) of the input's
    /// mean elevation of that class's height, when the prior is [`CameraHeight::Shares`] with
    /// one; else 0, also for a camera set of several middle-band rings (as
    /// [`input_elevations`](Self::input_elevations) estimates none for it, elevations given by
    /// hand move none of them).
    pub(crate) fn input_elevation_shift_deg(&self, class: usize) -> f64 {
        let (CameraHeight::Shares(shares), Some(heads)) = (self.camera_height, &self.viewpoint)
        else {
            return 0.0;
        };
        if self.several_middle_rings() {
            return 0.0;
        }
        let Some(view) = self.cameras.viewpoints().get(class) else {
            return 0.0;
        };
        shares.elevations_deg()[view.level.index()]
            .map_or(0.0, |mean| heads.elevation_fit(class).shift_deg(mean))
    }

    /// Whether this localizer's cameras have more than one elevation ring in the middle band
    /// (within 22.5 deg of level): one mean elevation cannot stand for them.
    fn several_middle_rings(&self) -> bool {
        self.cameras
            .elevations_deg()
            .iter()
            .filter(|&&e| Level::nearest(e) == Level::Middle)
            .count()
            > 1
    }
}
