//! `camloc evaluate`.

use std::fmt::Write;

use clap::ValueEnum;
use std::path::PathBuf;
use std::process::ExitCode;

use camloc::{CamlocError, ViewpointAccuracy, evaluate};

use super::heights;
use super::{CameraHeightArgs, CliError, Out, ProgressArgs, load_dataset, load_model, targets};
use camloc::store::StagedFiles;

/// Arguments of `camloc evaluate`.
#[derive(clap::Args)]
pub struct Args {
    /// Model file (from `camloc train`) [default: the model embedded in this binary].
    #[arg(long, value_name = "MODEL")]
    pub model: Option<PathBuf>,
    #[command(flatten)]
    pub height: CameraHeightArgs,
    /// Labelled dataset (from `cargo xtask gen-dataset`).
    #[arg(long, value_name = "FILE")]
    pub dataset: PathBuf,
    /// Print one JSON object (keys: camera_height, camera_height_shares, samples, accuracy,
    /// accuracy_folded, viewpoint, per_level, per_ring, per_elevation_band, per_camera,
    /// confusion; `viewpoint`: the continuous viewpoints' median_error_deg, beyond_45,
    /// mean_elevation_error_deg and within_uncertainty against the true directions, null for a
    /// model without viewpoint heads, as in each level, ring and camera; per_elevation_band:
    /// the bands of true elevation with samples, each with from_deg, to_deg, samples and its
    /// viewpoint).
    #[arg(long)]
    pub json: bool,
    /// Score samples with missing landmarks (or a landmark far off the others) with their
    /// descriptor's missing values at the training means: fast, but not what `camloc
    /// localize` answers for them (by default they are filled in from the
    /// embedded basis, as `localize` fills them: a few tenths of a millisecond each).
    #[arg(long)]
    pub no_fill: bool,
    /// Draw the confusion matrix (rows: true camera, columns: predicted, shaded by the share
    /// of the row) as SVG to this file, written only when the run succeeds.
    #[arg(long, value_name = "OUT")]
    pub svg: Option<PathBuf>,
    /// Replace an existing SVG file (see `camloc localize --help`).
    #[arg(long)]
    pub force: bool,
    #[command(flatten)]
    pub progress: ProgressArgs,
}

/// Runs `camloc evaluate`.
pub fn run(args: &Args, stdout: &mut Out) -> Result<ExitCode, CliError> {
    targets::check(
        [(args.svg.as_deref(), "--svg", None)],
        &[
            ("--dataset", Some(&args.dataset)),
            ("--model", args.model.as_deref()),
        ],
        args.force,
    )?;
    let localizer = load_model(args.model.as_deref(), &args.height)?;
    let dataset = load_dataset(&args.dataset)?;
    let localizer = heights::for_dataset(localizer, &args.height, &dataset, args.progress.quiet);
    // Samples with missing landmarks are localized as `localize` localizes such poses: filled
    // in from the embedded basis.
    let filled = (dataset.samples.iter())
        .filter(|s| s.missing_mask != 0)
        .count();
    let bar = super::progress::spinner(
        args.progress.quiet || filled == 0 || args.no_fill,
        &format!(
            "evaluating {} samples, {filled} of them with missing landmarks filled in \
             (--no-fill: faster, at the training means)",
            dataset.samples.len()
        ),
    );
    let evaluated = match super::embedded_basis().filter(|_| !args.no_fill) {
        Some(basis) => camloc::evaluate_filled(&localizer, &dataset, basis.reconstructor()),
        None => evaluate(&localizer, &dataset),
    };
    bar.finish_and_clear();
    let e = evaluated.map_err(|err| match err {
        // Say which file: the dataset's cameras are not the model's, say.
        CamlocError::Inconsistent { what, detail } => CamlocError::Inconsistent {
            what,
            detail: format!("{}: {detail}", camloc::store::quoted_path(&args.dataset)),
        },
        other => other,
    })?;
    // The prior the run localized under, as `localize --npz` reports it.
    let prior = args
        .height
        .camera_height
        .to_possible_value()
        .map_or_else(String::new, |v| v.get_name().to_string());
    let shares = match localizer.camera_height() {
        camloc::CameraHeight::Shares(shares) => Some(shares),
        _ => None,
    };
    let mut staged = StagedFiles::new(args.force);
    if let Some(svg) = &args.svg {
        let title = format!(
            "{}: {} samples, accuracy {:.2}%",
            args.dataset.display(),
            e.samples,
            100.0 * e.accuracy
        );
        let drawing = crate::svg::confusion_svg(localizer.cameras(), &e.confusion, &title);
        staged.add(svg, drawing.as_bytes())?;
    }
    let mut out = String::new();
    if args.json {
        let json = EvaluationJson {
            camera_height: &prior,
            camera_height_shares: shares.map(|s| s.to_array()),
            evaluation: &e,
        };
        let _ = writeln!(
            out,
            "{}",
            serde_json::to_string_pretty(&json).map_err(|err| CamlocError::InvalidOption {
                name: "json",
                detail: err.to_string(),
            })?
        );
        stdout.write(&out)?;
        stdout.flush()?;
        staged.commit()?;
        return Ok(ExitCode::SUCCESS);
    }
    let _ = writeln!(out, "samples:          {}", e.samples);
    let estimated = shares.map_or_else(String::new, |s| format!(" ({s} estimated)"));
    let _ = writeln!(out, "camera height:    {prior}{estimated}");
    let _ = writeln!(out, "accuracy:         {:.2}%", 100.0 * e.accuracy);
    let _ = writeln!(
        out,
        "accuracy folded:  {:.2}% (back cameras folded onto front)",
        100.0 * e.accuracy_folded
    );
    if let Some(v) = &e.viewpoint {
        let _ = writeln!(out, "viewpoint:        {}", viewpoint_text(v));
    }
    let _ = writeln!(out, "per level:");
    for l in &e.per_level {
        let _ = writeln!(
            out,
            "  {:<6} {:>8} samples  exact {:>6.2}%  right level {:>6.2}%{}",
            l.level.name(),
            l.samples,
            100.0 * l.accuracy,
            100.0 * l.level_accuracy,
            short_viewpoint_text(l.viewpoint.as_ref())
        );
    }
    // Table 1's rings are its levels; a sphere with several rings in a level gets them apart.
    if e.per_ring.len() != e.per_level.len() {
        let _ = writeln!(out, "per ring:");
        for r in &e.per_ring {
            let _ = writeln!(
                out,
                "  {:>+6.1} deg {:>8} samples  exact {:>6.2}%  right ring {:>6.2}%{}",
                r.elevation_deg,
                r.samples,
                100.0 * r.accuracy,
                100.0 * r.ring_accuracy,
                short_viewpoint_text(r.viewpoint.as_ref())
            );
        }
    }
    if !e.per_elevation_band.is_empty() {
        let _ = writeln!(out, "by true elevation:");
        for b in &e.per_elevation_band {
            let _ = writeln!(
                out,
                "  {:>+6.1} to {:>+5.1} deg {:>8} samples{}",
                b.from_deg,
                b.to_deg,
                b.samples,
                short_viewpoint_text(Some(&b.viewpoint))
            );
        }
    }
    // A finer sphere's cameras are told apart by their angles, as their names repeat.
    let cameras = localizer.cameras();
    let repeat = cameras.names_repeat();
    let names: Vec<String> = (e.per_camera.iter().zip(cameras.viewpoints()))
        .map(|(c, v)| {
            if repeat {
                format!("{} ({})", c.name, v.angles_text())
            } else {
                c.name.clone()
            }
        })
        .collect();
    let width = names.iter().map(String::len).max().unwrap_or(0).max(13);
    let _ = writeln!(out, "per camera:");
    for (c, name) in e.per_camera.iter().zip(&names) {
        let accuracy = c
            .accuracy
            .map_or_else(|| "-".to_string(), |a| format!("{:.2}%", 100.0 * a));
        let _ = writeln!(
            out,
            "  {} {name:<width$} {:>8} samples  {accuracy:>7}{}",
            c.label,
            c.samples,
            short_viewpoint_text(c.viewpoint.as_ref())
        );
    }
    let _ = writeln!(out, "confusion (rows: true camera, columns: predicted):");
    let _ = write!(out, "      ");
    for p in 1..=e.confusion.len() {
        let _ = write!(out, "{p:>7}");
    }
    let _ = writeln!(out);
    for (t, row) in e.confusion.iter().enumerate() {
        let _ = write!(out, "  {:02}  ", t + 1);
        for c in row {
            let _ = write!(out, "{c:>7}");
        }
        let _ = writeln!(out);
    }
    stdout.write(&out)?;
    stdout.flush()?;
    staged.commit()?;
    Ok(ExitCode::SUCCESS)
}

/// `camloc evaluate --json`: the prior the run localized under (`--camera-height`), the
/// shares of the heights `from-input` estimated (none for the other priors), and the
/// evaluation.
#[derive(serde::Serialize)]
struct EvaluationJson<'a> {
    camera_height: &'a str,
    camera_height_shares: Option<[f64; 3]>,
    #[serde(flatten)]
    evaluation: &'a camloc::Evaluation,
}

/// The whole line of the continuous viewpoints' errors.
fn viewpoint_text(v: &ViewpointAccuracy) -> String {
    format!(
        "median {:.1} deg off the true direction, {:.2}% beyond 45 deg, elevation {:+.1} deg \
         on average (+: read higher), {:.1}% within the stated uncertainty",
        v.median_error_deg,
        100.0 * v.beyond_45,
        v.mean_elevation_error_deg,
        100.0 * v.within_uncertainty
    )
}

/// A group's median viewpoint error and elevation bias, after its accuracy ("" without).
fn short_viewpoint_text(v: Option<&ViewpointAccuracy>) -> String {
    v.map_or_else(String::new, |v| {
        format!(
            "  median {:>5.1} deg  elevation {:>+5.1} deg",
            v.median_error_deg, v.mean_elevation_error_deg
        )
    })
}
