//! Comparing camera modes on samples with known 3D truth.

use std::fmt;

use camloc_geometry::Matrix3;
use camloc_skeleton::{Pose2, Pose3};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::{
    CameraMode, ModeKind, ReconstructError, Reconstructor, mpjpe_after_similarity,
    projection_error_eq12_bbox, rms_error_in_torsos,
};

/// One evaluation sample: 2D landmarks with their 3D truth and cameras.
#[derive(Clone, Debug, PartialEq)]
pub struct EvalSample {
    /// The 2D landmarks (any image units).
    pub pose2: Pose2,
    /// The true 3D pose, metres (any frame: MPJPE aligns by a similarity).
    pub truth: Pose3,
    /// The true camera rotation relative to the basis's canonical frame (for `oracle`).
    pub true_rotation: Matrix3,
    /// The classified viewpoint's rotation (for `classified` and `hybrid`), if any.
    pub classified_rotation: Option<Matrix3>,
}

impl ModeKind {
    /// The camera mode for `sample`; `None` when the sample has no classified rotation and
    /// the mode needs one.
    pub fn camera_mode(self, sample: &EvalSample) -> Option<CameraMode> {
        match self {
            ModeKind::Opt => Some(CameraMode::Opt),
            ModeKind::Oracle => Some(CameraMode::Oracle(sample.true_rotation)),
            ModeKind::Classified => sample.classified_rotation.map(CameraMode::Classified),
            ModeKind::Hybrid => sample.classified_rotation.map(CameraMode::Hybrid),
        }
    }
}

/// Results of one mode over a sample set.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ModeReport {
    /// The mode.
    pub mode: ModeKind,
    /// Samples reconstructed successfully.
    pub evaluated: usize,
    /// Samples whose reconstruction (or metric) returned an error.
    pub failures: usize,
    /// Samples skipped because they have no classified rotation (classified and hybrid).
    pub unavailable: usize,
    /// Mean PA-MPJPE (the mean per-landmark error after similarity alignment), millimetres
    /// (`None` without evaluated samples).
    pub mean_pa_mpjpe_mm: Option<f64>,
    /// Median PA-MPJPE, millimetres.
    pub median_pa_mpjpe_mm: Option<f64>,
    /// Mean eq. 12 projection error with each pose's bounding box as `w x h`
    /// ([`crate::projection_error_eq12_bbox`]), 1 / image unit.
    pub mean_projection_error_eq12: Option<f64>,
    /// Mean RMS reprojection error per landmark in 2D torso lengths
    /// ([`crate::rms_error_in_torsos`]).
    pub mean_rms_error_torsos: Option<f64>,
    /// Share (0..=1) of the samples reconstructed by both this mode and `opt` where this mode's
    /// PA-MPJPE is strictly lower; `None` for `opt` itself or when no sample qualifies.
    pub beats_opt_share: Option<f64>,
    /// Share (0..=1) of evaluated samples where the depth-reflected hypothesis won.
    pub reflected_share: Option<f64>,
}

/// Results of [`evaluate`]: one [`ModeReport`] per requested mode, in request order.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EvalReport {
    /// Number of samples.
    pub samples: usize,
    /// Per-mode results.
    pub modes: Vec<ModeReport>,
}

/// Metrics of one successful reconstruction.
#[derive(Clone, Copy, Debug)]
struct Scores {
    pa_mpjpe_mm: f64,
    eq12: f64,
    rms_torsos: f64,
    reflected: bool,
}

/// What happened to one sample under one mode.
#[derive(Clone, Copy, Debug)]
enum Outcome {
    Unavailable,
    Failed,
    Done(Scores),
}

impl Outcome {
    fn scores(&self) -> Option<&Scores> {
        match self {
            Outcome::Done(s) => Some(s),
            _ => None,
        }
    }
}

/// Reconstructs every sample under every mode in `modes` (duplicates ignored) and summarises
/// each mode. `opt` is always run, as the reference of [`ModeReport::beats_opt_share`], but
/// reported only if requested. Samples are processed in parallel (rayon); the report does not
/// depend on the number of threads.
pub fn evaluate(
    samples: &[EvalSample],
    reconstructor: &Reconstructor,
    modes: &[ModeKind],
) -> EvalReport {
    let mut requested: Vec<ModeKind> = Vec::new();
    for &m in modes {
        if !requested.contains(&m) {
            requested.push(m);
        }
    }
    let mut run = requested.clone();
    if !run.contains(&ModeKind::Opt) {
        run.push(ModeKind::Opt);
    }
    let outcomes: Vec<Vec<Outcome>> = samples
        .par_iter()
        .map(|sample| {
            run.iter()
                .map(|&kind| match kind.camera_mode(sample) {
                    None => Outcome::Unavailable,
                    Some(mode) => match score(sample, reconstructor, &mode) {
                        Ok(s) => Outcome::Done(s),
                        Err(_) => Outcome::Failed,
                    },
                })
                .collect()
        })
        .collect();
    let opt_column = run.iter().position(|&m| m == ModeKind::Opt);
    let reports = requested
        .iter()
        .enumerate()
        .map(|(column, &mode)| {
            let results: Vec<&Outcome> = outcomes.iter().map(|row| &row[column]).collect();
            let done: Vec<&Scores> = results.iter().filter_map(|o| o.scores()).collect();
            let mean = |f: fn(&Scores) -> f64| {
                (!done.is_empty())
                    .then(|| done.iter().map(|s| f(s)).sum::<f64>() / done.len() as f64)
            };
            let mut mpjpe: Vec<f64> = done.iter().map(|s| s.pa_mpjpe_mm).collect();
            mpjpe.sort_by(f64::total_cmp);
            let median = (!mpjpe.is_empty()).then(|| {
                let mid = mpjpe.len() / 2;
                if mpjpe.len() % 2 == 1 {
                    mpjpe[mid]
                } else {
                    0.5 * (mpjpe[mid - 1] + mpjpe[mid])
                }
            });
            let beats_opt_share = match opt_column {
                Some(opt) if mode != ModeKind::Opt => {
                    let pairs: Vec<(f64, f64)> = outcomes
                        .iter()
                        .filter_map(|row| {
                            Some((
                                row[column].scores()?.pa_mpjpe_mm,
                                row[opt].scores()?.pa_mpjpe_mm,
                            ))
                        })
                        .collect();
                    (!pairs.is_empty()).then(|| {
                        pairs.iter().filter(|(m, o)| m < o).count() as f64 / pairs.len() as f64
                    })
                }
                _ => None,
            };
            ModeReport {
                mode,
                evaluated: done.len(),
                failures: results
                    .iter()
                    .filter(|o| matches!(o, Outcome::Failed))
                    .count(),
                unavailable: results
                    .iter()
                    .filter(|o| matches!(o, Outcome::Unavailable))
                    .count(),
                mean_pa_mpjpe_mm: mean(|s| s.pa_mpjpe_mm),
                median_pa_mpjpe_mm: median,
                mean_projection_error_eq12: mean(|s| s.eq12),
                mean_rms_error_torsos: mean(|s| s.rms_torsos),
                beats_opt_share,
                reflected_share: mean(|s| if s.reflected { 1.0 } else { 0.0 }),
            }
        })
        .collect();
    EvalReport {
        samples: samples.len(),
        modes: reports,
    }
}

/// Reconstructs one sample under one mode and scores it.
fn score(
    sample: &EvalSample,
    reconstructor: &Reconstructor,
    mode: &CameraMode,
) -> Result<Scores, ReconstructError> {
    let recon = reconstructor.reconstruct(&sample.pose2, mode)?;
    let pa_mpjpe_mm = mpjpe_after_similarity(&recon.pose, &sample.truth);
    if !pa_mpjpe_mm.is_finite() {
        return Err(ReconstructError::Numerical("non-finite MPJPE"));
    }
    Ok(Scores {
        pa_mpjpe_mm,
        eq12: projection_error_eq12_bbox(&sample.pose2, &recon)?,
        rms_torsos: rms_error_in_torsos(&sample.pose2, &recon)?,
        reflected: recon.reflected,
    })
}

impl fmt::Display for EvalReport {
    /// A plain-text table, one line per mode.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let opt = |v: Option<f64>, scale: f64, digits: usize| match v {
            Some(x) => format!("{:.*}", digits, x * scale),
            None => "-".into(),
        };
        writeln!(
            f,
            "{} samples\n{:<11} {:>6} {:>6} {:>6} {:>11} {:>10} {:>12} {:>10} {:>9} {:>9}",
            self.samples,
            "mode",
            "ok",
            "failed",
            "n/a",
            "PA-MPJPE mm",
            "median mm",
            "eq12 (bbox)",
            "rms/torso",
            "beat opt",
            "reflected"
        )?;
        for m in &self.modes {
            writeln!(
                f,
                "{:<11} {:>6} {:>6} {:>6} {:>11} {:>10} {:>12} {:>10} {:>8}% {:>8}%",
                m.mode.name(),
                m.evaluated,
                m.failures,
                m.unavailable,
                opt(m.mean_pa_mpjpe_mm, 1.0, 1),
                opt(m.median_pa_mpjpe_mm, 1.0, 1),
                opt(m.mean_projection_error_eq12, 1.0, 5),
                opt(m.mean_rms_error_torsos, 1.0, 4),
                opt(m.beats_opt_share, 100.0, 1),
                opt(m.reflected_share, 100.0, 1),
            )?;
        }
        Ok(())
    }
}
