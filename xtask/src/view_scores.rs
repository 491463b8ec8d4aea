//! Per-view outcomes of a localizer on a test set, and their summaries by motion category and
//! posture: 12-class and level accuracy, the continuous viewpoint's median error and its mean
//! signed elevation error (issue 21), and the level accuracy by the true camera elevation.

use std::fmt::Write;

use camloc::dataset::{
    Dataset, MotionCategory, Sample, camera_direction_deg, direction_vector, is_low_posture,
};
use camloc::geometry::procrustes_camera;
use camloc::learning::angle_deg;
use camloc::{CameraLocalizer, CameraSet, Level, PartialPose2};

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
    /// Whether the error lies within the uncertainty the localizer reported (`None` for an
    /// answer without one).
    pub within_uncertainty: Option<bool>,
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
            let mut o = outcome(cameras, data, s, l.label.get(), l.level, (az, el));
            o.within_uncertainty = l.uncertainty_deg.map(|u| o.angle_deg <= u);
            Ok(o)
        })
        .collect()
}

/// What a localizer that knew each view's true 3D pose would answer: the direction of the
/// weak-perspective camera that maps the true canonical pose onto the view's 2D landmarks
/// (Procrustes, eq. 3, every landmark), the class that of its ring and side
/// ([`CameraSet::by_ring_and_side`]). Its errors come from the protocol alone (2D noise,
/// perspective, lens distortion, boundaries between classes): a reference for any localizer
/// that reads the 2D pose, not a strict bound (one that learnt the protocol's perspective
/// and noise could do better).
///
/// # Errors
/// A message naming the view whose camera cannot be fitted.
pub fn known_pose_outcomes(
    cameras: &CameraSet,
    data: &Dataset,
) -> Result<Vec<ViewOutcome>, String> {
    data.samples
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let camera = procrustes_camera(&s.pose3.points, &s.landmarks.points)
                .map_err(|e| format!("view {i}: {e}"))?;
            let direction = camera_direction_deg(&camera.rotation);
            let view = cameras.by_ring_and_side(direction.0, direction.1);
            Ok(outcome(cameras, data, s, view.label, view.level, direction))
        })
        .collect()
}

/// The outcome of answering camera `label` at `level` and the viewpoint
/// `(azimuth, elevation)` (degrees) for the view `sample` of `data`.
fn outcome(
    cameras: &CameraSet,
    data: &Dataset,
    sample: &Sample,
    label: u16,
    level: Level,
    (azimuth_deg, elevation_deg): (f64, f64),
) -> ViewOutcome {
    let (true_az, true_el) = camera_direction_deg(&sample.rotation);
    let truth_level = cameras.get(sample.label).map(|v| v.level);
    let level_offset = truth_level.map_or(0, |t| level.index() as i32 - t.index() as i32);
    ViewOutcome {
        category: data.category_of(sample),
        low: is_low_posture(&sample.pose3),
        inside: sample.in_class_box,
        correct: label == sample.label,
        level_correct: Some(level) == truth_level,
        angle_deg: angle_deg(
            &direction_vector(azimuth_deg, elevation_deg),
            &direction_vector(true_az, true_el),
        ),
        elevation_error_deg: elevation_deg - true_el,
        true_elevation_deg: true_el,
        level_offset,
        within_uncertainty: None,
    }
}

/// Bands of the true camera elevation above the pelvis, degrees (`[lo, hi)`), for
/// [`elevation_bands`]: the middle ring's upper half in 4-degree steps up to its boundary at
/// 22.5 deg, then the upper ring's first bands.
pub const ELEVATION_BANDS: [(f64, f64); 10] = [
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
/// per band and row (a recipe's, or the true-pose reference's) the level accuracy, the shares
/// of views placed a level too high and too low, the mean signed elevation error and the
/// number of views.
pub fn elevation_bands(md: &mut String, title: &str, results: &[(&str, Vec<ViewOutcome>)]) {
    let _ = writeln!(md, "\n{title}\n");
    let mut header = "| true elevation above the pelvis |".to_string();
    for (name, _) in results {
        let _ = write!(header, " {name} |");
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
    /// Views whose error lies within their reported uncertainty (calibrated to hold about 68%),
    /// percent; `None` when the answers have no uncertainty.
    pub within_uncertainty: Option<f64>,
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
        Summary {
            views: kept.len(),
            accuracy: share(|o| o.correct),
            level_accuracy: share(|o| o.level_correct),
            level_too_high: share(|o| o.level_offset > 0),
            level_too_low: share(|o| o.level_offset < 0),
            median_deg: camloc::reconstruct::median(&mut angles).unwrap_or(f64::NAN),
            elevation_bias_deg: kept.iter().map(|o| o.elevation_error_deg).sum::<f64>() / n,
            within_uncertainty: kept
                .iter()
                .all(|o| o.within_uncertainty.is_some())
                .then(|| share(|o| o.within_uncertainty == Some(true))),
        }
    }

    /// `accuracy% (level%, median deg, bias deg[, within%], n)` for a table cell; `-`
    /// without views.
    pub fn cell(&self) -> String {
        if self.views == 0 {
            return "-".into();
        }
        let within = self
            .within_uncertainty
            .map_or_else(String::new, |w| format!("{w:.0}% within uncertainty, "));
        format!(
            "{:.2}% (level {:.1}%, {:.1} deg, bias {:+.1} deg, {within}{})",
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
            within_uncertainty: None,
        }
    }

    #[test]
    fn the_true_pose_locates_noiseless_views_exactly() {
        // The embedded basis's mean pose (canonical: facing -x, z up, metres).
        let pose = camloc::default_basis().unwrap().mean();
        let clip = camloc::dataset::PoseSequence {
            clip: camloc::dataset::ClipInfo::new("01", "01_01"),
            frames: vec![(0, pose)],
        };
        let config = camloc::dataset::GenerateConfig::new(camloc::dataset::Protocol::Canonical);
        let data = camloc::dataset::generate(&[clip], &config, &|_, _| {}).unwrap();
        assert_eq!(data.samples.len(), 12);
        let out = known_pose_outcomes(&CameraSet::table1(), &data).unwrap();
        for o in &out {
            assert!(o.correct && o.level_correct, "{o:?}");
            assert!(
                o.angle_deg < 1e-6 && o.elevation_error_deg.abs() < 1e-6,
                "{o:?}"
            );
        }
    }

    #[test]
    fn elevation_bands_count_each_view_once_in_its_band() {
        let out = vec![
            outcome(-3.0, 0),
            outcome(5.0, 0),
            outcome(6.0, 1),
            outcome(21.0, -1),
            outcome(22.5, 0),
            outcome(40.0, -1),
        ];
        let mut md = String::new();
        elevation_bands(&mut md, "bands", &[("recipe", out)]);
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
