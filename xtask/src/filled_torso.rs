//! The report's rows for poses with missing landmarks (docs/conventions.md section 6): the
//! held-out views with the pelvis and a hip, the neck and a shoulder, or all four missing,
//! localized with the torso filled in from a basis of the training subjects
//! (`CameraLocalizer::localize_filled`); and with k random landmarks of the limbs and head
//! missing, localized from their descriptor values' training means
//! (`CameraLocalizer::localize_partial`) and filled in.

use std::fmt::Write;
use std::time::Instant;

use camloc::dataset::{Dataset, Sample};
use camloc::reconstruct::PoseBasis;
use camloc::{CameraLocalizer, CameraSet, Landmark, Localization, PartialPose2, PoseReconstructor};
use rand::SeedableRng;
use rand::seq::IndexedRandom;
use rayon::prelude::*;

/// How many random landmarks of the limbs and head the random rows take away.
const RANDOM_MISSING: [usize; 4] = [1, 2, 4, 6];

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
/// `basis`, and the milliseconds per pose; then the random rows ([`random_rows`]).
pub fn rows(
    localizer: &CameraLocalizer,
    basis: PoseBasis,
    test: &Dataset,
) -> Result<String, String> {
    let filler = PoseReconstructor::new(basis).map_err(|e| e.to_string())?;
    let mut md = torso_rows(localizer, &filler, test)?;
    md.push_str(&random_rows(localizer, &filler, test)?);
    Ok(md)
}

/// A way of localizing a pose (the error as text).
type Localize<'a> = &'a (dyn Fn(&PartialPose2) -> Result<Localization, String> + Sync);

/// How one way of localizing did on views with landmarks taken away ([`score`]).
struct Scores {
    /// Views localized.
    views: usize,
    /// The share of them whose camera is right, and right folded (back onto front), percent.
    right: [f64; 2],
    /// The mean probability of the answers.
    mean_probability: f64,
    /// Milliseconds of wall time per view, localized in parallel.
    ms: f64,
}

/// `localize` of each of `poses` (the landmarks of `views` with some taken away), scored
/// against the views' cameras (`cameras`).
fn score(
    cameras: &CameraSet,
    poses: &[PartialPose2],
    views: &[&Sample],
    localize: Localize,
) -> Result<Scores, String> {
    let start = Instant::now();
    let found: Vec<(bool, bool, f64)> = (poses.par_iter().zip(views))
        .map(|(pose, sample)| {
            let found = localize(pose)?;
            let folded = cameras.fold_back_to_front(sample.label);
            Ok((
                found.label.get() == sample.label,
                found.folded_label.get() == folded,
                found.probability,
            ))
        })
        .collect::<Result<_, String>>()?;
    let n = found.len().max(1) as f64;
    let share = |f: fn(&(bool, bool, f64)) -> bool| {
        100.0 * found.iter().filter(|h| f(h)).count() as f64 / n
    };
    Ok(Scores {
        views: found.len(),
        right: [share(|h| h.0), share(|h| h.1)],
        mean_probability: found.iter().map(|h| h.2).sum::<f64>() / n,
        ms: 1e3 * start.elapsed().as_secs_f64() / n,
    })
}

/// The views of `test` with every landmark present.
fn complete_views(test: &Dataset) -> Vec<&Sample> {
    (test.samples.iter())
        .filter(|s| s.missing_mask == 0)
        .collect()
}

/// The rows of the torso cases ([`CASES`]).
fn torso_rows(
    localizer: &CameraLocalizer,
    filler: &PoseReconstructor,
    test: &Dataset,
) -> Result<String, String> {
    let views = complete_views(test);
    let filled = |p: &PartialPose2| {
        (localizer.localize_filled(p, filler.reconstructor())).map_err(|e| e.to_string())
    };
    let mut md = String::new();
    for (what, parts) in CASES {
        let poses: Vec<PartialPose2> = (views.iter().enumerate())
            .map(|(i, sample)| {
                let mut pose = PartialPose2::from(sample.landmarks);
                for part in parts {
                    pose.points[part.landmark(i).index()] = None;
                }
                pose
            })
            .collect();
        let s = score(localizer.cameras(), &poses, &views, &filled)?;
        let _ = writeln!(
            md,
            "| joints + mirror + dropout (default settings), {what} missing: torso filled in \
             ({} views, {:.2} ms of wall time per pose, in parallel) | {:.2}% | {:.2}% |",
            s.views, s.ms, s.right[0], s.right[1]
        );
    }
    Ok(md)
}

/// Rows of the complete views of `test` with k random landmarks other than the pelvis and the
/// neck taken away ([`RANDOM_MISSING`]; one draw per view and k, the same for both ways),
/// localized by `localizer` from their descriptor values' training means (`localize_partial`)
/// and with them filled in from `filler`'s basis (`localize_filled`, what `camloc localize`
/// does); the mean probability of the answers and the milliseconds per pose.
fn random_rows(
    localizer: &CameraLocalizer,
    filler: &PoseReconstructor,
    test: &Dataset,
) -> Result<String, String> {
    let limbs: Vec<Landmark> = Landmark::ALL
        .into_iter()
        .filter(|l| !matches!(l, Landmark::Pelvis | Landmark::Neck))
        .collect();
    let views = complete_views(test);
    let means = |p: &PartialPose2| localizer.localize_partial(p).map_err(|e| e.to_string());
    let filled = |p: &PartialPose2| {
        (localizer.localize_filled(p, filler.reconstructor())).map_err(|e| e.to_string())
    };
    let ways: [(&str, Localize); 2] = [
        ("descriptor values at their training means", &means),
        ("filled in", &filled),
    ];
    let mut md = String::new();
    for k in RANDOM_MISSING {
        let poses: Vec<PartialPose2> = (views.iter().enumerate())
            .map(|(i, sample)| {
                let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64((i * 16 + k) as u64);
                let mut pose = PartialPose2::from(sample.landmarks);
                for l in limbs.choose_multiple(&mut rng, k) {
                    pose.points[l.index()] = None;
                }
                pose
            })
            .collect();
        for (way, localize) in ways {
            let s = score(localizer.cameras(), &poses, &views, localize)?;
            let _ = writeln!(
                md,
                "| joints + mirror + dropout (default settings), {k} random landmark{} of the \
                 limbs and head missing, {way} ({} views, mean probability of the answer \
                 {:.2}, {:.3} ms of wall time per pose, in parallel) | {:.2}% | {:.2}% |",
                if k == 1 { "" } else { "s" },
                s.views,
                s.mean_probability,
                s.ms,
                s.right[0],
                s.right[1]
            );
        }
    }
    Ok(md)
}
