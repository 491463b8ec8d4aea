//! Per-view outcomes of a localizer on a test set, and their summaries by motion category and
//! posture: 12-class and level accuracy, the continuous viewpoint's median error and its mean
//! signed elevation error (issue 21).

use camloc::dataset::{
    Dataset, MotionCategory, camera_direction_deg, direction_vector, is_low_posture,
};
use camloc::learning::angle_deg;
use camloc::{CameraLocalizer, PartialPose2};

/// What the localizer answered for one test view.
#[derive(Clone, Copy, Debug)]
pub struct ViewOutcome {
    /// The clip's motion category.
    pub category: MotionCategory,
    /// Whether the 3D pose is seated or low (a thigh more than 60 deg from the vertical).
    pub low: bool,
    /// Whether the camera direction lies in its class's box (always under `canonical` and
    /// `jittered`).
    pub inside: bool,
    /// Whether the camera class is right.
    pub correct: bool,
    /// Whether the level (lower, middle, upper) is right.
    pub level_correct: bool,
    /// Angle between the continuous viewpoint and the true direction, degrees.
    pub angle_deg: f64,
    /// Predicted minus true elevation, degrees.
    pub elevation_error_deg: f64,
}

/// The outcome of every view of `data` (poses with their dropped landmarks missing).
///
/// # Errors
/// A message when a pose cannot be localized or the localizer has no viewpoint heads.
pub fn outcomes(localizer: &CameraLocalizer, data: &Dataset) -> Result<Vec<ViewOutcome>, String> {
    let poses: Vec<PartialPose2> = data
        .samples
        .iter()
        .map(|s| PartialPose2::from(s.landmarks))
        .collect();
    let cameras = localizer.cameras();
    localizer
        .localize_batch(&poses)
        .into_iter()
        .zip(&data.samples)
        .map(|(result, s)| {
            let l = result.map_err(|e| e.to_string())?;
            let (Some(az), Some(el)) = (l.azimuth_deg, l.elevation_deg) else {
                return Err("the localizer has no viewpoint heads".to_string());
            };
            let (true_az, true_el) = camera_direction_deg(&s.rotation);
            let truth_level = cameras.get(s.label).map(|v| v.level);
            Ok(ViewOutcome {
                category: data.category_of(s),
                low: is_low_posture(&s.pose3),
                inside: s.in_class_box,
                correct: l.label.get() == s.label,
                level_correct: Some(l.level) == truth_level,
                angle_deg: angle_deg(
                    &direction_vector(az, el),
                    &direction_vector(true_az, true_el),
                ),
                elevation_error_deg: el - true_el,
            })
        })
        .collect()
}

/// A summary of some outcomes.
#[derive(Clone, Copy, Debug, Default)]
pub struct Summary {
    /// Number of views.
    pub views: usize,
    /// 12-class accuracy, percent.
    pub accuracy: f64,
    /// Level accuracy, percent.
    pub level_accuracy: f64,
    /// Median viewpoint error, degrees.
    pub median_deg: f64,
    /// Mean signed elevation error, degrees (negative: the camera is placed too low).
    pub elevation_bias_deg: f64,
}

impl Summary {
    /// The summary of the outcomes `keep` selects (all zero when it selects none).
    pub fn of(outcomes: &[ViewOutcome], keep: impl Fn(&ViewOutcome) -> bool) -> Summary {
        let kept: Vec<&ViewOutcome> = outcomes.iter().filter(|o| keep(o)).collect();
        if kept.is_empty() {
            return Summary::default();
        }
        let n = kept.len() as f64;
        let share =
            |f: fn(&ViewOutcome) -> bool| 100.0 * kept.iter().filter(|o| f(o)).count() as f64 / n;
        let mut angles: Vec<f64> = kept.iter().map(|o| o.angle_deg).collect();
        angles.sort_by(f64::total_cmp);
        Summary {
            views: kept.len(),
            accuracy: share(|o| o.correct),
            level_accuracy: share(|o| o.level_correct),
            median_deg: angles[angles.len() / 2],
            elevation_bias_deg: kept.iter().map(|o| o.elevation_error_deg).sum::<f64>() / n,
        }
    }

    /// `accuracy% (level%, median deg, bias deg, n)` for a table cell; `-` without views.
    pub fn cell(&self) -> String {
        if self.views == 0 {
            return "-".into();
        }
        format!(
            "{:.2}% (level {:.1}%, {:.1} deg, bias {:+.1} deg, {})",
            self.accuracy,
            self.level_accuracy,
            self.median_deg,
            self.elevation_bias_deg,
            self.views
        )
    }
}

/// The categories present in `outcomes`, in [`MotionCategory::ALL`] order.
pub fn categories_in(outcomes: &[ViewOutcome]) -> Vec<MotionCategory> {
    MotionCategory::ALL
        .into_iter()
        .filter(|c| outcomes.iter().any(|o| o.category == *c))
        .collect()
}
