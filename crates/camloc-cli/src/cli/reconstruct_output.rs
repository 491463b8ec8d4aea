//! What `camloc reconstruct` writes for one pose (its JSON object or text, and its drawing) and
//! says of a whole run (poses past the joint limits).

use std::fmt::Write;

use camloc::reconstruct::{BONE_KEYS, BoneLengths, PerspectiveCamera, Reconstruction};
use camloc::store::escaped;
use camloc::{CameraLabel, Landmark, ModeKind, PartialPose2, Pose2, Pose3, PoseReconstruction};
use serde::ser::SerializeMap;
use serde::{Serialize, Serializer};

use crate::svg;

use super::stream::{self, Format};

/// Where a pose came from: the fields of its record that the output repeats.
pub struct PoseMeta<'a> {
    /// The pose's id.
    pub id: &'a str,
    /// Its place in the input.
    pub source: &'a str,
    /// Its frame, if the input has frames.
    pub frame: Option<u64>,
    /// Its person, if the input has persons.
    pub person: Option<u64>,
    /// Left out of its person's sequence (`reconstruct --sequence`: a second pose of a frame,
    /// or a pose apart from the frames around it) and reconstructed on its own.
    pub left_out: bool,
    /// The limb chains (`legs`, `arms`) whose left and right sides were swapped back before
    /// the sequence was solved ([`camloc::swapped_sides`]).
    pub swapped_sides: &'a [&'static str],
}

/// The camera of one pose of `reconstruct --json`.
#[derive(Serialize)]
struct CameraJson {
    rotation: [[f64; 3]; 3],
    scale: f64,
    translation: [f64; 2],
}

/// The perspective camera of one pose of `reconstruct --json` (with `--focal-px`, or at the
/// estimated distance without it).
#[derive(Serialize)]
struct PerspectiveJson {
    rotation: [[f64; 3]; 3],
    translation_m: [f64; 3],
    focal_px: f64,
    principal_point: [f64; 2],
}

impl PerspectiveJson {
    fn new(p: &PerspectiveCamera) -> Self {
        PerspectiveJson {
            rotation: rows(&p.rotation),
            translation_m: p.translation,
            focal_px: p.focal_px,
            principal_point: p.principal_point,
        }
    }
}

/// The rows of a rotation.
fn rows(rot: &camloc::geometry::Matrix3) -> [[f64; 3]; 3] {
    std::array::from_fn(|i| [rot[(i, 0)], rot[(i, 1)], rot[(i, 2)]])
}

/// One hypothesis of `reconstruct --json`: camera, scores, bone lengths and 3D landmarks.
#[derive(Serialize)]
struct HypothesisJson<'a> {
    camera: CameraJson,
    #[serde(skip_serializing_if = "Option::is_none")]
    perspective: Option<PerspectiveJson>,
    projection_error: f64,
    reflected: bool,
    limit_violation_rad: f64,
    outside_limits_rad: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    bone_lengths_m: Option<BoneLengths>,
    landmarks_m: Landmarks<'a>,
}

impl<'a> HypothesisJson<'a> {
    fn new(r: &'a Reconstruction) -> Self {
        HypothesisJson {
            camera: CameraJson {
                rotation: rows(&r.camera.rotation),
                scale: r.camera.scale,
                translation: r.camera.translation,
            },
            perspective: r.perspective.as_ref().map(PerspectiveJson::new),
            projection_error: r.projection_error,
            reflected: r.reflected,
            limit_violation_rad: r.limit_violation_rad,
            outside_limits_rad: r.outside_limits_rad,
            bone_lengths_m: BoneLengths::of_pose(&r.pose).ok(),
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
    /// Left out of the person's sequence (`PoseMeta::left_out`); absent when not.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    left_out_of_sequence: bool,
    /// `PoseMeta::swapped_sides`; absent when none.
    #[serde(skip_serializing_if = "<[_]>::is_empty")]
    swapped_sides: &'a [&'static str],
    camera_mode: &'static str,
    classified_label: Option<CameraLabel>,
    /// The localization's probability of `classified_label` and its continuous viewpoint
    /// (degrees, as `localize` writes them); absent without a localization.
    #[serde(skip_serializing_if = "Option::is_none")]
    probability: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    azimuth_deg: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    elevation_deg: Option<f64>,
    #[serde(flatten)]
    best: HypothesisJson<'a>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    alternatives: Vec<HypothesisJson<'a>>,
    /// The landmarks missing in the input, filled in before the reconstruction.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    imputed: Vec<&'static str>,
}

/// How the camera of `result` was chosen, for text and captions.
fn camera_text(choice: ModeKind, result: &PoseReconstruction) -> String {
    match &result.localization {
        Some(l) => format!(
            "{} (classified camera {}, {} {}, p = {:.3})",
            choice.name(),
            l.label,
            l.level.name(),
            l.side.name(),
            l.probability
        ),
        None => choice.name().to_string(),
    }
}

/// The names of the landmarks of `result` that were filled in.
fn imputed_names(result: &PoseReconstruction) -> Vec<&'static str> {
    result.imputed.iter().map(|l| l.name()).collect()
}

/// `title`, how the camera of `result` was chosen and the landmarks filled in: the heading of
/// its text and the caption of its drawing.
fn heading(title: &str, choice: ModeKind, result: &PoseReconstruction) -> String {
    let mut heading = format!("{title}: camera {}", camera_text(choice, result));
    let imputed = imputed_names(result);
    if !imputed.is_empty() {
        let _ = write!(heading, "; filled in: {}", imputed.join(", "));
    }
    heading
}

/// The output of one reconstructed pose: one JSON object (no newline) or lines of text.
pub fn pose_output(
    format: Format,
    meta: &PoseMeta,
    choice: ModeKind,
    result: &PoseReconstruction,
) -> String {
    let r = &result.reconstruction;
    if format.is_json() {
        return stream::json_line(&ReconstructionJson {
            id: meta.id,
            source: meta.source,
            frame: meta.frame,
            person: meta.person,
            left_out_of_sequence: meta.left_out,
            swapped_sides: meta.swapped_sides,
            camera_mode: choice.name(),
            classified_label: result.localization.as_ref().map(|l| l.label),
            probability: result.localization.as_ref().map(|l| l.probability),
            azimuth_deg: result.localization.as_ref().and_then(|l| l.azimuth_deg),
            elevation_deg: result.localization.as_ref().and_then(|l| l.elevation_deg),
            best: HypothesisJson::new(r),
            alternatives: result
                .alternatives
                .iter()
                .map(HypothesisJson::new)
                .collect(),
            imputed: imputed_names(result),
        });
    }
    let id = escaped(meta.id);
    let mut title = format!("{id}");
    if let Some(f) = meta.frame {
        let _ = write!(title, " frame {f}");
    }
    if let Some(p) = meta.person {
        let _ = write!(title, " person {p}");
    }
    if meta.left_out {
        title.push_str(" (left out of the sequence)");
    }
    if !meta.swapped_sides.is_empty() {
        let _ = write!(title, " ({} swapped back)", meta.swapped_sides.join(", "));
    }
    let mut text = reconstruction_text(&heading(&title, choice, result), r);
    for (k, alternative) in result.alternatives.iter().enumerate() {
        text.push_str(&reconstruction_text(
            &format!("  alternative {}", k + 1),
            alternative,
        ));
    }
    text
}

/// The drawing of one reconstructed pose (input, reprojection, three views); the caption
/// names the landmarks that were filled in, and the drawing rings them (a landmark far off
/// the others too: read as missing, it was filled in, and is left out of the input drawn).
pub fn pose_svg(
    input: &PartialPose2,
    id: &str,
    choice: ModeKind,
    result: &PoseReconstruction,
) -> String {
    let r = &result.reconstruction;
    let projected = r.reprojection();
    let caption = heading(id, choice, result);
    let (read, _) = camloc::without_far_off_landmarks(input);
    svg::reconstruction_svg(&read, &Pose2::new(projected), &r.pose, &caption)
}

/// Bone lengths as one line of text: `KEY LENGTH` pairs, metres.
pub fn lengths_text(lengths: &BoneLengths) -> String {
    BONE_KEYS
        .iter()
        .zip(lengths.as_array())
        .map(|(k, l)| format!("{k} {l:.3}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// One hypothesis as text: `heading` with its scores, the camera rotation (and perspective
/// camera), the bone lengths, the 3D landmarks.
fn reconstruction_text(heading: &str, r: &Reconstruction) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{heading}; reprojection error {:.3} (image units, eq. 6); joint-limit violation \
         {:.3} rad before the limits, the pose {:.3} rad outside them{}",
        r.projection_error,
        r.limit_violation_rad,
        r.outside_limits_rad,
        if r.reflected {
            " (depth-reflected)"
        } else {
            ""
        }
    );
    for row in rows(&r.camera.rotation) {
        let _ = writeln!(
            out,
            "  R = [{:>7.4} {:>7.4} {:>7.4}]",
            row[0], row[1], row[2]
        );
    }
    if let Some(p) = &r.perspective {
        let t = p.translation;
        let _ = writeln!(
            out,
            "  perspective: T = [{:.3} {:.3} {:.3}] m, f = {:.1} px, principal point ({:.1}, {:.1})",
            t[0], t[1], t[2], p.focal_px, p.principal_point[0], p.principal_point[1]
        );
    }
    if let Ok(lengths) = BoneLengths::of_pose(&r.pose) {
        let _ = writeln!(out, "  bone lengths (m): {}", lengths_text(&lengths));
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

/// Warns on standard error when most poses of a run were reconstructed past the joint
/// limits ([`camloc::LimitCount::summary`]): landmarks in another order than the layout's.
pub fn warn_of_limits(limits: camloc::LimitCount) {
    if let Some(said) = limits.summary() {
        stderr_line!(
            "camloc: warning: {said} (`outside_limits_rad` in JSON; --layout names the layout, \
             docs/keypoints.md its joint order)"
        );
    }
}
