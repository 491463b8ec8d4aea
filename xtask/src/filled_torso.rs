//! The report's rows for poses whose torso is incomplete (docs/conventions.md section 6): the
//! held-out views with the pelvis and a hip, the neck and a shoulder, or all four missing,
//! localized with the torso filled in from a basis of the training subjects
//! (`CameraLocalizer::localize_filled`).

use std::fmt::Write;
use std::time::Instant;

use camloc::dataset::Dataset;
use camloc::reconstruct::PoseBasis;
use camloc::{CameraLocalizer, Landmark, PartialPose2, PoseReconstructor};
use rayon::prelude::*;

/// What is taken away; `Hip`/`Shoulder` alternate left and right from one view to the next.
const CASES: [(&str, &[Part]); 3] = [
    ("the pelvis and one hip", &[Part::Pelvis, Part::Hip]),
    ("the neck and one shoulder", &[Part::Neck, Part::Shoulder]),
    (
        "the pelvis, one hip, the neck and one shoulder",
        &[Part::Pelvis, Part::Hip, Part::Neck, Part::Shoulder],
    ),
];

#[derive(Clone, Copy)]
enum Part {
    Pelvis,
    Hip,
    Neck,
    Shoulder,
}

impl Part {
    /// The landmark taken away from view `i`.
    fn landmark(self, i: usize) -> Landmark {
        let left = i.is_multiple_of(2);
        match self {
            Part::Pelvis => Landmark::Pelvis,
            Part::Neck => Landmark::Neck,
            Part::Hip if left => Landmark::LeftHip,
            Part::Hip => Landmark::RightHip,
            Part::Shoulder if left => Landmark::LeftShoulder,
            Part::Shoulder => Landmark::RightShoulder,
        }
    }
}

/// Markdown rows `| what | accuracy | folded |` of the complete views of `test` with each
/// case's landmarks taken away, localized by `localizer` with the torso filled in from
/// `basis`, and the milliseconds per pose.
pub fn rows(
    localizer: &CameraLocalizer,
    basis: PoseBasis,
    test: &Dataset,
) -> Result<String, String> {
    let filler = PoseReconstructor::new(basis).map_err(|e| e.to_string())?;
    let cameras = localizer.cameras();
    let views: Vec<_> = test
        .samples
        .iter()
        .filter(|s| s.missing_mask == 0)
        .collect();
    let mut md = String::new();
    for (what, parts) in CASES {
        let start = Instant::now();
        let hits: Result<Vec<(bool, bool)>, String> = views
            .par_iter()
            .enumerate()
            .map(|(i, sample)| {
                let mut pose = PartialPose2::from(sample.landmarks);
                for part in parts {
                    pose.points[part.landmark(i).index()] = None;
                }
                let found = localizer
                    .localize_filled(&pose, filler.reconstructor())
                    .map_err(|e| e.to_string())?;
                let folded = cameras.fold_back_to_front(sample.label);
                Ok((
                    found.label.get() == sample.label,
                    found.folded_label.get() == folded,
                ))
            })
            .collect();
        let hits = hits?;
        let ms = 1e3 * start.elapsed().as_secs_f64() / views.len().max(1) as f64;
        let share = |f: fn(&(bool, bool)) -> bool| {
            100.0 * hits.iter().filter(|h| f(h)).count() as f64 / hits.len().max(1) as f64
        };
        let _ = writeln!(
            md,
            "| joints + mirror + dropout (default settings), {what} missing: torso filled in \
             ({} views, {ms:.2} ms of wall time per pose, in parallel) | {:.2}% | {:.2}% |",
            hits.len(),
            share(|h| h.0),
            share(|h| h.1)
        );
    }
    Ok(md)
}
