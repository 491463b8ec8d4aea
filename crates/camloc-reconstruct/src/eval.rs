//! Comparing camera modes on samples with known 3D truth.

use std::fmt;

use camloc_geometry::Matrix3;
use camloc_skeleton::{Pose2, Pose3};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::{
    CameraMode, ModeKind, ReconstructError, Reconstruction, Reconstructor, mpjpe_after_similarity,
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

/// A whole reconstruction pipeline measured beside the camera modes
/// ([`evaluate_with_pipeline`]): for instance the facade's `reconstruct`, with lifted depths
/// and estimated bone lengths, which no single [`CameraMode`] of the pursuit is.
pub struct Pipeline<'a> {
    /// What it is, as the report names it (e.g. `"hybrid + lifter"`).
    pub name: String,
    /// The camera mode it reconstructs with.
    pub mode: ModeKind,
    /// Reconstructs one sample's 2D landmarks; `None` when the pipeline fails on them.
    pub run: &'a (dyn Fn(&Pose2) -> Option<Reconstruction> + Sync),
}

/// Results of a [`Pipeline`] over a sample set, measured as the modes are (its `unavailable`
/// is 0: a pipeline needs no classified rotation).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PipelineReport {
    /// The pipeline's [`Pipeline::name`].
    pub name: String,
    /// Its results, under its camera mode ([`Pipeline::mode`]).
    #[serde(flatten)]
    pub report: ModeReport,
}

/// Results of [`evaluate`]: one [`ModeReport`] per requested mode, in request order, and the
/// [`Pipeline`]'s if one was measured.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EvalReport {
    /// Number of samples.
    pub samples: usize,
    /// Per-mode results.
    pub modes: Vec<ModeReport>,
    /// The pipeline's results ([`evaluate_with_pipeline`]); absent from the JSON when none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pipeline: Option<PipelineReport>,
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

/// Summarises column `column` of `outcomes` (one row per sample) as `mode`'s; `opt` is
/// `opt`'s column, the reference of [`ModeReport::beats_opt_share`] (`None` for `opt`
/// itself).
fn summarise(
    outcomes: &[Vec<Outcome>],
    column: usize,
    mode: ModeKind,
    opt: Option<usize>,
) -> ModeReport {
    let results: Vec<&Outcome> = outcomes.iter().map(|row| &row[column]).collect();
    let done: Vec<&Scores> = results.iter().filter_map(|o| o.scores()).collect();
    let mean = |f: fn(&Scores) -> f64| {
        (!done.is_empty()).then(|| done.iter().map(|s| f(s)).sum::<f64>() / done.len() as f64)
    };
    let mut mpjpe: Vec<f64> = done.iter().map(|s| s.pa_mpjpe_mm).collect();
    let median = crate::median(&mut mpjpe);
    let beats_opt_share = opt.and_then(|opt| {
        let pairs: Vec<(f64, f64)> = outcomes
            .iter()
            .filter_map(|row| {
                Some((
                    row[column].scores()?.pa_mpjpe_mm,
                    row[opt].scores()?.pa_mpjpe_mm,
                ))
            })
            .collect();
        (!pairs.is_empty())
            .then(|| pairs.iter().filter(|(m, o)| m < o).count() as f64 / pairs.len() as f64)
    });
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
    evaluate_with_pipeline(samples, reconstructor, modes, None)
}

/// [`evaluate`], and `pipeline` (if any) run on every sample and measured as the modes are
/// ([`EvalReport::pipeline`]).
pub fn evaluate_with_pipeline(
    samples: &[EvalSample],
    reconstructor: &Reconstructor,
    modes: &[ModeKind],
    pipeline: Option<&Pipeline<'_>>,
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
            let mut row: Vec<Outcome> = run
                .iter()
                .map(|&kind| match kind.camera_mode(sample) {
                    None => Outcome::Unavailable,
                    Some(mode) => {
                        outcome(sample, reconstructor.reconstruct(&sample.pose2, &mode).ok())
                    }
                })
                .collect();
            if let Some(p) = pipeline {
                row.push(outcome(sample, (p.run)(&sample.pose2)));
            }
            row
        })
        .collect();
    let opt_column = run.iter().position(|&m| m == ModeKind::Opt);
    let modes = requested
        .iter()
        .enumerate()
        .map(|(column, &mode)| {
            summarise(
                &outcomes,
                column,
                mode,
                opt_column.filter(|_| mode != ModeKind::Opt),
            )
        })
        .collect();
    let pipeline = pipeline.map(|p| PipelineReport {
        name: p.name.clone(),
        report: summarise(&outcomes, run.len(), p.mode, opt_column),
    });
    EvalReport {
        samples: samples.len(),
        modes,
        pipeline,
    }
}

/// The outcome of one sample's reconstruction (`None`: it failed).
fn outcome(sample: &EvalSample, recon: Option<Reconstruction>) -> Outcome {
    match recon.map(|r| score(sample, &r)) {
        Some(Ok(s)) => Outcome::Done(s),
        _ => Outcome::Failed,
    }
}

/// Scores one sample's reconstruction. A true pose whose limbs all have no length (a forged
/// dataset's all-zero poses, which scored 0.0 mm) cannot be aligned to and is not measured.
fn score(sample: &EvalSample, recon: &Reconstruction) -> Result<Scores, ReconstructError> {
    if sample.truth.limb_lengths().iter().all(|&l| !(l > 0.0)) {
        return Err(ReconstructError::Numerical("a true pose of no extent"));
    }
    let pa_mpjpe_mm = mpjpe_after_similarity(&recon.pose, &sample.truth);
    if !pa_mpjpe_mm.is_finite() {
        return Err(ReconstructError::Numerical("non-finite MPJPE"));
    }
    Ok(Scores {
        pa_mpjpe_mm,
        eq12: projection_error_eq12_bbox(&sample.pose2, recon)?,
        rms_torsos: rms_error_in_torsos(&sample.pose2, recon)?,
        reflected: recon.reflected,
    })
}

impl fmt::Display for EvalReport {
    /// A plain-text table, one line per mode, then the pipeline's.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let opt = |v: Option<f64>, scale: f64, digits: usize| match v {
            Some(x) => format!("{:.*}", digits, x * scale),
            None => "-".into(),
        };
        let cells = |m: &ModeReport| -> [String; 10] {
            [
                m.mode.name().to_string(),
                m.evaluated.to_string(),
                m.failures.to_string(),
                m.unavailable.to_string(),
                opt(m.mean_pa_mpjpe_mm, 1.0, 1),
                opt(m.median_pa_mpjpe_mm, 1.0, 1),
                opt(m.mean_projection_error_eq12, 1.0, 5),
                opt(m.mean_rms_error_torsos, 1.0, 4),
                opt(m.beats_opt_share, 100.0, 1) + "%",
                opt(m.reflected_share, 100.0, 1) + "%",
            ]
        };
        let mut rows: Vec<[String; 10]> = self.modes.iter().map(cells).collect();
        if let Some(p) = &self.pipeline {
            let mut row = cells(&p.report);
            row[0].clone_from(&p.name);
            rows.push(row);
        }
        let width = rows.iter().map(|r| r[0].len()).max().unwrap_or(0).max(11);
        let line = |f: &mut fmt::Formatter<'_>, r: &[String; 10]| {
            writeln!(
                f,
                "{:<width$} {:>6} {:>6} {:>6} {:>11} {:>10} {:>12} {:>10} {:>9} {:>9}",
                r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8], r[9]
            )
        };
        writeln!(f, "{} samples", self.samples)?;
        let header = [
            "mode",
            "ok",
            "failed",
            "n/a",
            "PA-MPJPE mm",
            "median mm",
            "eq12 (bbox)",
            "rms/torso",
            "beat opt",
            "reflected",
        ]
        .map(String::from);
        line(f, &header)?;
        for r in &rows {
            line(f, r)?;
        }
        Ok(())
    }
}
