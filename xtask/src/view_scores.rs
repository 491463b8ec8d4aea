//! Per-view outcomes of a localizer on a test set, and their summaries by motion category and
//! posture: 12-class and level accuracy, the continuous viewpoint's median error and its mean
//! signed elevation error (issue 21), and the level accuracy by the true camera elevation.

use std::fmt::Write;

use camloc::dataset::{
    Dataset, MotionCategory, camera_direction_deg, direction_vector, is_low_posture,
};
use camloc::learning::angle_deg;
use camloc::{CameraLocalizer, Level, PartialPose2};

use crate::recipe::Recipe;

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
    /// The true camera's elevation above the pelvis, degrees.
    pub true_elevation_deg: f64,
    /// Predicted level minus true level, in levels (lower, middle, upper): +1 a level too high.
    pub level_offset: i32,
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
            let level_offset = truth_level.map_or(0, |t| level_rank(l.level) - level_rank(t));
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
                true_elevation_deg: true_el,
                level_offset,
            })
        })
        .collect()
}

/// 0, 1, 2 for the lower, middle and upper level.
fn level_rank(level: Level) -> i32 {
    match level {
        Level::Lower => 0,
        Level::Middle => 1,
        Level::Upper => 2,
    }
}

/// Bands of the true camera elevation above the pelvis, degrees (`[lo, hi)`), for
/// [`elevation_bands`]: the middle ring's upper half in 4-degree steps up to its boundary at
/// 22.5 deg, then the upper ring's first bands.
const ELEVATION_BANDS: [(f64, f64); 10] = [
    (f64::NEG_INFINITY, 0.0),
    (0.0, 4.0),
    (4.0, 8.0),
    (8.0, 12.0),
    (12.0, 16.0),
    (16.0, 20.0),
    (20.0, 22.5),
    (22.5, 26.0),
    (26.0, 30.0),
    (30.0, f64::INFINITY),
];

/// A table of `results` by the true camera elevation above the pelvis ([`ELEVATION_BANDS`]):
/// per band and recipe the level accuracy, the shares of views placed a level too high and
/// too low, the mean signed elevation error and the number of views.
pub fn elevation_bands(md: &mut String, title: &str, results: &[(&Recipe, Vec<ViewOutcome>)]) {
    let _ = writeln!(md, "\n{title}\n");
    let mut header = "| true elevation above the pelvis |".to_string();
    for (recipe, _) in results {
        let _ = write!(header, " {} |", recipe.name);
    }
    let _ = writeln!(md, "{header}\n|{}", "---|".repeat(1 + results.len()));
    for (lo, hi) in ELEVATION_BANDS {
        let band = match (lo.is_finite(), hi.is_finite()) {
            (false, _) => format!("below {hi} deg"),
            (_, false) => format!("{lo} deg and above"),
            _ => format!("{lo} to {hi} deg"),
        };
        let mut line = format!("| {band} |");
        for (_, out) in results {
            let s = Summary::of(out, |o| (lo..hi).contains(&o.true_elevation_deg));
            if s.views == 0 {
                line.push_str(" - |");
                continue;
            }
            let _ = write!(
                line,
                " level {:.1}% ({:.1}% too high, {:.1}% too low, bias {:+.1} deg, {}) |",
                s.level_accuracy, s.level_too_high, s.level_too_low, s.elevation_bias_deg, s.views
            );
        }
        let _ = writeln!(md, "{line}");
    }
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
    /// Views placed a level (or two) too high, percent.
    pub level_too_high: f64,
    /// Views placed a level (or two) too low, percent.
    pub level_too_low: f64,
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
            level_too_high: share(|o| o.level_offset > 0),
            level_too_low: share(|o| o.level_offset < 0),
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

#[cfg(test)]
mod tests {
    use super::*;

    /// An outcome at `true_elevation_deg` whose level is `level_offset` off.
    fn outcome(true_elevation_deg: f64, level_offset: i32) -> ViewOutcome {
        ViewOutcome {
            category: MotionCategory::Walk,
            low: false,
            inside: true,
            correct: level_offset == 0,
            level_correct: level_offset == 0,
            angle_deg: 5.0,
            elevation_error_deg: -2.0,
            true_elevation_deg,
            level_offset,
        }
    }

    #[test]
    fn elevation_bands_count_each_view_once_in_its_band() {
        let recipe = Recipe::default_model();
        let out = vec![
            outcome(-3.0, 0),
            outcome(5.0, 0),
            outcome(6.0, 1),
            outcome(21.0, -1),
            outcome(22.5, 0),
            outcome(40.0, -1),
        ];
        let mut md = String::new();
        elevation_bands(&mut md, "bands", &[(&recipe, out)]);
        let line = |band: &str| {
            md.lines()
                .find(|l| l.starts_with(&format!("| {band} |")))
                .unwrap_or_else(|| panic!("no row {band} in\n{md}"))
                .to_string()
        };
        assert!(line("below 0 deg").contains("level 100.0% (0.0% too high, 0.0% too low"));
        assert!(line("4 to 8 deg").contains("level 50.0% (50.0% too high, 0.0% too low"));
        assert!(line("4 to 8 deg").ends_with("bias -2.0 deg, 2) |"));
        assert!(line("20 to 22.5 deg").contains("(0.0% too high, 100.0% too low"));
        assert!(line("22.5 to 26 deg").contains("level 100.0%"));
        assert!(line("30 deg and above").ends_with(", 1) |"));
        assert_eq!(line("0 to 4 deg"), "| 0 to 4 deg | - |");
    }
}
