//! `camloc reconstruct` and `camloc evaluate-reconstruction`.

use std::fmt::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use camloc::reconstruct::{PoseBasis, Reconstruction};
use camloc::store::{Persist, escaped};
use camloc::{
    CameraLabel, CamlocError, Landmark, ModeKind, Pose2, Pose3, PoseReconstructor, default_basis,
};
use clap::builder::{PossibleValue, TypedValueParser};
use serde::ser::SerializeMap;
use serde::{Serialize, Serializer};

use crate::svg;

use super::input::Inputs;
use super::output::NpyStage;
use super::stream::{self, Done, Files};
use super::{
    CliError, ForceArgs, FormatArgs, InputArgs, Out, ProgressArgs, load_dataset, load_model,
    progress, targets,
};

/// The camera modes `reconstruct` offers (the library's [`ModeKind`] without `oracle`, which
/// needs the true camera), with their help.
fn camera_modes() -> [PossibleValue; 3] {
    [
        PossibleValue::new("opt").help(
            "Procrustes camera re-estimated at every step (Ramakrishna et al.); default: the \
             fastest, under 1 ms per pose (docs/RESULTS.md)",
        ),
        PossibleValue::new("classified").help(
            "Rotation fixed to the classified Table-1 camera (the paper's section 8.2); best \
             when the camera is one of the 12 viewpoints",
        ),
        PossibleValue::new("hybrid").help(
            "Classified rotation as the start, refined by Procrustes: the lowest 3D error \
             measured (docs/RESULTS.md), about 3 times the time of opt",
        ),
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
    /// Keep up to N hypotheses per pose. Where the 2D fits two poses about equally (the
    /// mirror in depth), the one within the learned joint-angle limits comes first; the
    /// others follow in the text output and under "alternatives" in JSON, each with its
    /// reprojection error and limit violation. Each solve has 2 (as found and
    /// depth-reflected); hybrid runs 2 solves. The .npy and SVG outputs hold the first.
    #[arg(long, default_value_t = 1, value_name = "N",
          value_parser = clap::value_parser!(u8).range(1..=4))]
    pub hypotheses: u8,
    #[command(flatten)]
    pub format: FormatArgs,
    /// Write the 3D poses as a (N, 15, 3) float64 .npy array in metres (camloc15 layout, the
    /// canonical frame): row n is the n-th pose read, NaN where it could not be reconstructed.
    #[arg(long, value_name = "OUT")]
    pub npy: Option<PathBuf>,
    /// Draw input, reprojection and three views of the 3D pose as SVG to this file (several
    /// poses: FILE-001.svg, ...). All files are written at the end, or none.
    #[arg(long, value_name = "OUT")]
    pub svg: Option<PathBuf>,
    #[command(flatten)]
    pub force: ForceArgs,
    #[command(flatten)]
    pub progress: ProgressArgs,
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
    #[command(flatten)]
    pub progress: ProgressArgs,
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
pub fn run(args: &Args, out: &mut Out) -> Result<ExitCode, CliError> {
    let outputs = [
        (args.npy.as_deref(), "--npy", false),
        (args.svg.as_deref(), "--svg", true),
    ];
    targets::check_distinct(&targets::outputs(outputs))?;
    let choice = args.camera;
    let mut reconstructor = PoseReconstructor::new(load_basis(args.basis.as_deref())?)?;
    if choice != ModeKind::Opt || args.model.is_some() {
        reconstructor = reconstructor.with_localizer(load_model(args.model.as_deref())?);
    }
    let reconstructor = reconstructor.with_mode(choice)?;
    let inputs = Inputs::open(&args.input)?;
    let format = args.format.format();
    let files = Files::<Pose3> {
        svg: args.svg.clone(),
        rows: NpyStage::boxed(args.npy.as_deref())?,
        summary: None,
        force: args.force.force,
    };
    let bar = progress::counter(
        args.progress.quiet,
        inputs.len_hint(),
        "reconstruct",
        "poses",
    );
    let summary = stream::run(inputs, out, format, files, &bar, |record| {
        let result = reconstructor
            .reconstruct_hypotheses(&record.pose, usize::from(args.hypotheses))
            .map_err(|e| e.to_string())?;
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
        let text = if format.is_json() {
            stream::json_line(&ReconstructionJson {
                id: &record.id,
                source: &record.source,
                frame: record.frame,
                person: record.person,
                camera_mode: choice.name(),
                classified_label: result.localization.as_ref().map(|l| l.label),
                best: HypothesisJson::new(r),
                alternatives: result
                    .alternatives
                    .iter()
                    .map(HypothesisJson::new)
                    .collect(),
            })
        } else {
            let id = escaped(&record.id);
            let mut text = reconstruction_text(&format!("{id}: camera {camera_text}"), r);
            for (k, alternative) in result.alternatives.iter().enumerate() {
                text.push_str(&reconstruction_text(
                    &format!("  alternative {}", k + 1),
                    alternative,
                ));
            }
            text
        };
        let svg = match (&args.svg, record.pose.complete()) {
            (Some(_), Some(input)) => {
                let reprojection = Pose2::new(r.camera.project(&r.pose.points));
                let caption = format!("{}: camera {camera_text}", record.id);
                Some(svg::reconstruction_svg(
                    &input,
                    &reprojection,
                    &r.pose,
                    &caption,
                ))
            }
            _ => None,
        };
        Ok(Done {
            text,
            svg,
            row: args.npy.as_ref().map(|_| r.pose),
        })
    })?;
    Ok(summary.exit_code("reconstructed"))
}

/// The camera of one pose of `reconstruct --json`.
#[derive(Serialize)]
struct CameraJson {
    rotation: [[f64; 3]; 3],
    scale: f64,
    translation: [f64; 2],
}

/// The rotation of `r`'s camera as rows.
fn rotation_rows(r: &Reconstruction) -> [[f64; 3]; 3] {
    let rot = &r.camera.rotation;
    std::array::from_fn(|i| [rot[(i, 0)], rot[(i, 1)], rot[(i, 2)]])
}

/// One hypothesis of `reconstruct --json`: camera, scores and 3D landmarks.
#[derive(Serialize)]
struct HypothesisJson<'a> {
    camera: CameraJson,
    projection_error: f64,
    reflected: bool,
    limit_violation_rad: f64,
    landmarks_m: Landmarks<'a>,
}

impl<'a> HypothesisJson<'a> {
    fn new(r: &'a Reconstruction) -> Self {
        HypothesisJson {
            camera: CameraJson {
                rotation: rotation_rows(r),
                scale: r.camera.scale,
                translation: r.camera.translation,
            },
            projection_error: r.projection_error,
            reflected: r.reflected,
            limit_violation_rad: r.limit_violation_rad,
            landmarks_m: Landmarks(&r.pose),
        }
    }
}

/// The 3D landmarks as a map from landmark name to `[x, y, z]` in metres.
struct Landmarks<'a>(&'a Pose3);

impl Serialize for Landmarks<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut map = serializer.serialize_map(Some(Landmark::ALL.len()))?;
        for l in Landmark::ALL {
            map.serialize_entry(l.name(), &self.0.points[l.index()])?;
        }
        map.end()
    }
}

/// One pose of `reconstruct --json` / `--jsonl`.
#[derive(Serialize)]
struct ReconstructionJson<'a> {
    id: &'a str,
    source: &'a str,
    #[serde(skip_serializing_if = "Option::is_none")]
    frame: Option<u64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    person: Option<u64>,
    camera_mode: &'static str,
    classified_label: Option<CameraLabel>,
    #[serde(flatten)]
    best: HypothesisJson<'a>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    alternatives: Vec<HypothesisJson<'a>>,
}

/// One hypothesis as text: `heading` with its scores, the camera rotation, the 3D landmarks.
fn reconstruction_text(heading: &str, r: &Reconstruction) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{heading}; reprojection error {:.3} (image units, eq. 6); joint-limit violation \
         {:.3} rad{}",
        r.projection_error,
        r.limit_violation_rad,
        if r.reflected {
            " (depth-reflected)"
        } else {
            ""
        }
    );
    for row in rotation_rows(r) {
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
    out
}

/// Runs `camloc evaluate-reconstruction`.
pub fn run_evaluation(args: &EvalArgs, out: &mut Out) -> Result<ExitCode, CliError> {
    let reconstructor = PoseReconstructor::new(load_basis(args.basis.as_deref())?)?
        .with_localizer(load_model(args.model.as_deref())?);
    let dataset = load_dataset(&args.dataset)?;
    let bar = progress::spinner(
        args.progress.quiet,
        &format!(
            "reconstructing {} samples with every camera mode",
            dataset.samples.len()
        ),
    );
    let report = reconstructor.evaluate(&dataset);
    bar.finish_and_clear();
    let report = report?;
    if args.json {
        out.write(&format!("{}\n", to_json(&report)?))?;
    } else {
        out.write(&report.to_string())?;
    }
    out.flush()?;
    Ok(ExitCode::SUCCESS)
}
