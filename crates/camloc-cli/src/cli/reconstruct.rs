//! `camloc reconstruct` and `camloc evaluate-reconstruction`.

use std::fmt::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use camloc::dataset::Dataset;
use camloc::reconstruct::PoseBasis;
use camloc::store::Persist;
use camloc::{CamlocError, Landmark, ModeKind, Pose2, PoseReconstructor, default_basis};
use clap::builder::{PossibleValue, TypedValueParser};
use serde_json::json;

use crate::svg;

use super::{InputArgs, load_model, numbered_path};

/// The camera modes `reconstruct` offers (the library's [`ModeKind`] without `oracle`, which
/// needs the true camera), with their help.
fn camera_modes() -> [PossibleValue; 3] {
    [
        PossibleValue::new("opt").help(
            "Procrustes camera re-estimated at every step (Ramakrishna et al.); default: lowest \
             3D error when cameras stand anywhere (jittered protocol, docs/RESULTS.md)",
        ),
        PossibleValue::new("classified").help(
            "Rotation fixed to the classified Table-1 camera (the paper's section 8.2); best \
             when the camera is one of the 12 viewpoints",
        ),
        PossibleValue::new("hybrid")
            .help("Classified rotation as the start, refined by Procrustes"),
    ]
}

/// Parses `--camera` (clap has already checked the name against [`camera_modes`]).
fn parse_camera(text: &str) -> Result<ModeKind, String> {
    ModeKind::ALL
        .into_iter()
        .find(|m| m.name() == text && *m != ModeKind::Oracle)
        .ok_or_else(|| format!("unknown camera mode {text:?}"))
}

/// Arguments of `camloc reconstruct`.
#[derive(clap::Args)]
pub struct Args {
    /// Model file for the classified camera [default: the embedded model].
    #[arg(long, value_name = "MODEL")]
    pub model: Option<PathBuf>,
    /// Pose basis file [default: the embedded basis].
    #[arg(long, value_name = "BASIS")]
    pub basis: Option<PathBuf>,
    #[command(flatten)]
    pub input: InputArgs,
    /// Which camera to reconstruct with.
    #[arg(long, default_value = "opt", value_name = "MODE",
          value_parser = clap::builder::PossibleValuesParser::new(camera_modes())
              .try_map(|s| parse_camera(&s)))]
    pub camera: ModeKind,
    /// Print one JSON array with one object per pose.
    #[arg(long)]
    pub json: bool,
    /// Draw input, reprojection and three views of the 3D pose as SVG to this file (several
    /// poses: FILE-001.svg, ...).
    #[arg(long, value_name = "OUT")]
    pub svg: Option<PathBuf>,
    /// Replace existing output files. A symbolic link at an output path is replaced by the new
    /// file (never written through; its target is untouched); a directory, device or FIFO is
    /// refused even with --force.
    #[arg(long)]
    pub force: bool,
}

/// Arguments of `camloc evaluate-reconstruction`.
#[derive(clap::Args)]
pub struct EvalArgs {
    /// Labelled dataset with 3D poses (from `cargo xtask gen-dataset`).
    #[arg(long, value_name = "FILE")]
    pub dataset: PathBuf,
    /// Model file for the classified camera [default: the embedded model].
    #[arg(long, value_name = "MODEL")]
    pub model: Option<PathBuf>,
    /// Pose basis file [default: the embedded basis].
    #[arg(long, value_name = "BASIS")]
    pub basis: Option<PathBuf>,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
}

fn load_basis(path: Option<&std::path::Path>) -> Result<PoseBasis, CamlocError> {
    match path {
        Some(p) => Ok(PoseBasis::load(p)?),
        None => default_basis(),
    }
}

fn to_json<T: serde::Serialize>(value: &T) -> Result<String, CamlocError> {
    serde_json::to_string_pretty(value).map_err(|e| CamlocError::InvalidOption {
        name: "json",
        detail: e.to_string(),
    })
}

/// Runs `camloc reconstruct`.
pub fn run(args: &Args, out: &mut String) -> Result<ExitCode, CamlocError> {
    let choice = args.camera;
    let mut reconstructor = PoseReconstructor::new(load_basis(args.basis.as_deref())?)?;
    if choice != ModeKind::Opt || args.model.is_some() {
        reconstructor = reconstructor.with_localizer(load_model(args.model.as_deref())?);
    }
    let reconstructor = reconstructor.with_mode(choice)?;
    let records = args.input.read()?;
    let mut failures = 0;
    let mut json_out = Vec::new();
    for (i, record) in records.iter().enumerate() {
        let result = match reconstructor.reconstruct(&record.pose) {
            Ok(r) => r,
            Err(e) => {
                failures += 1;
                eprintln!("camloc: error: {} ({}): {e}", record.id, record.source);
                json_out.push(
                    json!({"id": record.id, "source": record.source, "error": e.to_string()}),
                );
                continue;
            }
        };
        let r = &result.reconstruction;
        let camera_text = match &result.localization {
            Some(l) => format!(
                "{} (classified camera {}, {} {}, p = {:.3})",
                choice.name(),
                l.label,
                l.level.name(),
                l.side.name(),
                l.probability
            ),
            None => choice.name().to_string(),
        };
        let rot = &r.camera.rotation;
        let rotation: Vec<[f64; 3]> = (0..3)
            .map(|i| [rot[(i, 0)], rot[(i, 1)], rot[(i, 2)]])
            .collect();
        if args.json {
            let landmarks: serde_json::Map<String, serde_json::Value> = Landmark::ALL
                .iter()
                .map(|l| (l.name().to_string(), json!(r.pose.points[l.index()])))
                .collect();
            json_out.push(json!({
                "id": record.id,
                "source": record.source,
                "camera_mode": choice.name(),
                "classified_label": result.localization.as_ref().map(|l| l.label),
                "camera": {"rotation": rotation, "scale": r.camera.scale, "translation": r.camera.translation},
                "projection_error": r.projection_error,
                "landmarks_m": landmarks,
            }));
        } else {
            let _ = writeln!(
                out,
                "{}: camera {camera_text}; reprojection error {:.3} (image units, eq. 6)",
                record.id, r.projection_error
            );
            for row in &rotation {
                let _ = writeln!(
                    out,
                    "  R = [{:>7.4} {:>7.4} {:>7.4}]",
                    row[0], row[1], row[2]
                );
            }
            let _ = writeln!(
                out,
                "  3D landmarks (metres, canonical frame: facing -x, z up):"
            );
            for l in Landmark::ALL {
                let p = r.pose.points[l.index()];
                let _ = writeln!(
                    out,
                    "    {:<15} {:>8.4} {:>8.4} {:>8.4}",
                    l.name(),
                    p[0],
                    p[1],
                    p[2]
                );
            }
        }
        if let (Some(svg_out), Some(input)) = (&args.svg, record.pose.complete()) {
            let reprojection = Pose2::new(r.camera.project(&r.pose.points));
            let caption = format!("{}: camera {camera_text}", record.id);
            let drawing = svg::reconstruction_svg(&input, &reprojection, &r.pose, &caption);
            let path = numbered_path(svg_out, i, records.len());
            camloc::store::write_new(&path, drawing.as_bytes(), args.force)?;
        }
    }
    if args.json {
        let _ = writeln!(out, "{}", to_json(&json_out)?);
    }
    if failures > 0 {
        eprintln!(
            "camloc: {failures} of {} poses could not be reconstructed",
            records.len()
        );
        return Ok(ExitCode::from(super::EXIT_ERROR));
    }
    Ok(ExitCode::SUCCESS)
}

/// Runs `camloc evaluate-reconstruction`.
pub fn run_evaluation(args: &EvalArgs, out: &mut String) -> Result<ExitCode, CamlocError> {
    let reconstructor = PoseReconstructor::new(load_basis(args.basis.as_deref())?)?
        .with_localizer(load_model(args.model.as_deref())?);
    let dataset = Dataset::load(&args.dataset)?;
    let report = reconstructor.evaluate(&dataset)?;
    if args.json {
        let _ = writeln!(out, "{}", to_json(&report)?);
    } else {
        let _ = write!(out, "{report}");
    }
    Ok(ExitCode::SUCCESS)
}
