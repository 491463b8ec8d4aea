//! `camloc localize`.

use std::fmt::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use camloc::keypoints::KeypointRecord;
use camloc::{CameraLocalizer, CamlocError, Localization};
use serde_json::json;

use crate::svg;

use super::{InputArgs, load_model, numbered_path};

/// Arguments of `camloc localize`.
#[derive(clap::Args)]
pub struct Args {
    /// Model file [default: the model embedded in this binary].
    #[arg(long, value_name = "MODEL")]
    pub model: Option<PathBuf>,
    #[command(flatten)]
    pub input: InputArgs,
    /// Print one JSON array with one object per pose.
    #[arg(long)]
    pub json: bool,
    /// Draw each pose and its predicted viewpoint as SVG to this file (several poses:
    /// FILE-001.svg, FILE-002.svg, ...).
    #[arg(long, value_name = "OUT")]
    pub svg: Option<PathBuf>,
    /// Replace existing output files. A symbolic link at an output path is replaced by the new
    /// file (never written through; its target is untouched); a directory, device or FIFO is
    /// refused even with --force.
    #[arg(long)]
    pub force: bool,
}

/// Runs `camloc localize`.
pub fn run(args: &Args, out: &mut String) -> Result<ExitCode, CamlocError> {
    let localizer = load_model(args.model.as_deref())?;
    let records = args.input.read()?;
    let results = localizer.localize_batch(&records.iter().map(|r| r.pose).collect::<Vec<_>>());
    let mut failures = 0usize;
    let mut json_out = Vec::new();
    for (i, (record, result)) in records.iter().zip(&results).enumerate() {
        match result {
            Ok(loc) => {
                if args.json {
                    json_out.push(localization_json(&localizer, record, loc));
                } else {
                    print_localization(out, &localizer, record, loc);
                }
                if let Some(out) = &args.svg {
                    let path = numbered_path(out, i, records.len());
                    let caption = format!(
                        "{}: camera {} ({} {}), p = {:.2}",
                        record.id,
                        loc.label,
                        loc.level.name(),
                        loc.side.name(),
                        loc.probability
                    );
                    let drawing = svg::localization_svg(
                        &record.pose,
                        localizer.cameras(),
                        loc.label,
                        &caption,
                    );
                    camloc::store::write_new(&path, drawing.as_bytes(), args.force)?;
                }
            }
            Err(e) => {
                failures += 1;
                eprintln!("camloc: error: {} ({}): {e}", record.id, record.source);
                if args.json {
                    json_out.push(
                        json!({"id": record.id, "source": record.source, "error": e.to_string()}),
                    );
                }
            }
        }
    }
    if args.json {
        let _ = writeln!(out, "{}", serde_json::Value::Array(json_out));
    }
    if failures > 0 {
        eprintln!(
            "camloc: {failures} of {} poses could not be localized",
            records.len()
        );
        return Ok(ExitCode::from(super::EXIT_ERROR));
    }
    Ok(ExitCode::SUCCESS)
}

fn rotation_rows(loc: &Localization) -> [[f64; 3]; 3] {
    let r = &loc.rotation;
    [
        [r[(0, 0)], r[(0, 1)], r[(0, 2)]],
        [r[(1, 0)], r[(1, 1)], r[(1, 2)]],
        [r[(2, 0)], r[(2, 1)], r[(2, 2)]],
    ]
}

fn localization_json(
    localizer: &CameraLocalizer,
    record: &KeypointRecord,
    loc: &Localization,
) -> serde_json::Value {
    let probabilities: serde_json::Map<String, serde_json::Value> = localizer
        .cameras()
        .viewpoints()
        .iter()
        .zip(&loc.probabilities)
        .map(|(v, p)| (v.label_text(), json!(p)))
        .collect();
    json!({
        "id": record.id,
        "source": record.source,
        "label": loc.label,
        "level": loc.level.name(),
        "side": loc.side.name(),
        "probability": loc.probability,
        "folded_label": loc.folded_label,
        "azimuth_deg": loc.azimuth_deg,
        "elevation_deg": loc.elevation_deg,
        "uncertainty_deg": loc.uncertainty_deg,
        "rotation": rotation_rows(loc),
        "probabilities": probabilities,
        "missing": loc.missing.iter().map(|l| l.name()).collect::<Vec<_>>(),
        "derived": record.derived.iter().map(|l| l.name()).collect::<Vec<_>>(),
    })
}

fn print_localization(
    out: &mut String,
    localizer: &CameraLocalizer,
    record: &KeypointRecord,
    loc: &Localization,
) {
    let view = localizer.cameras().get(loc.label.get());
    let where_ = view.map_or_else(String::new, |v| {
        format!(
            " (azimuth {:.0} deg, elevation {:.0} deg)",
            v.azimuth_deg, v.elevation_deg
        )
    });
    let _ = writeln!(
        out,
        "{}: camera {}, {} level, {} side{where_}, probability {:.3}",
        record.id,
        loc.label,
        loc.level.name(),
        loc.side.name(),
        loc.probability
    );
    if loc.folded_label != loc.label {
        let _ = writeln!(out, "  mirror-folded camera: {}", loc.folded_label);
    }
    if let (Some(a), Some(e), Some(u)) = (loc.azimuth_deg, loc.elevation_deg, loc.uncertainty_deg) {
        let _ = writeln!(
            out,
            "  viewpoint: azimuth {a:.1} deg, elevation {e:.1} deg, +- {u:.1} deg"
        );
    }
    for row in rotation_rows(loc) {
        let _ = writeln!(
            out,
            "  R = [{:>7.4} {:>7.4} {:>7.4}]",
            row[0], row[1], row[2]
        );
    }
    if !record.derived.is_empty() {
        let names: Vec<&str> = record.derived.iter().map(|l| l.name()).collect();
        let _ = writeln!(out, "  derived: {}", names.join(", "));
    }
    if !loc.missing.is_empty() {
        let names: Vec<&str> = loc.missing.iter().map(|l| l.name()).collect();
        let _ = writeln!(out, "  missing (imputed): {}", names.join(", "));
    }
}
